//! The frame-time floor of the platform: an eframe window of geosnap's size and renderer
//! (wgpu) that draws nothing but a moving dot, repainted continuously, with the frame
//! intervals timed as `geosnap --drag-benchmark` times them. What this window takes, no
//! application drawn in it can go under; `tools/headless.sh floor` runs it under Xvfb.
//!
//! ```text
//! cargo run --release --example frame_floor -- [FRAMES] [OUT.json]
//! ```

use std::io::Write;
use std::time::{Duration, Instant};

use eframe::egui;

/// Frames left out at the start (window mapping, shader compilation).
const WARM_UP: usize = 20;

struct Floor {
    frames: usize,
    out: Option<std::path::PathBuf>,
    last: Option<Instant>,
    seen: usize,
    intervals: Vec<Duration>,
}

fn percentile(sorted_ms: &[f64], q: f64) -> f64 {
    if sorted_ms.is_empty() {
        return f64::NAN;
    }
    sorted_ms[((sorted_ms.len() - 1) as f64 * q).round() as usize]
}

impl eframe::App for Floor {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let now = Instant::now();
        if let (Some(last), true) = (self.last, self.seen > WARM_UP) {
            self.intervals.push(now - last);
        }
        self.last = Some(now);
        self.seen += 1;
        let rect = ui.max_rect();
        let t = self.seen as f32 * 0.05;
        let at = rect.center() + egui::vec2(t.sin(), (2.0 * t).sin() * 0.5) * rect.size() * 0.3;
        ui.painter()
            .circle_filled(at, 6.0, egui::Color32::from_rgb(240, 130, 20));
        if self.intervals.len() == self.frames {
            let mut ms: Vec<f64> = self
                .intervals
                .iter()
                .map(|d| d.as_secs_f64() * 1e3)
                .collect();
            ms.sort_by(f64::total_cmp);
            let report = serde_json::json!({
                "frames": ms.len(),
                "frame_interval_ms": {
                    "median": percentile(&ms, 0.5),
                    "p95": percentile(&ms, 0.95),
                    "max": percentile(&ms, 1.0),
                },
            });
            let text = format!("{report:#}\n");
            let written = match &self.out {
                Some(path) => geosnap::io::write_atomic(path, text.as_bytes()),
                None => std::io::stdout().write_all(text.as_bytes()),
            };
            if let Err(error) = written {
                log::error!("cannot write the report: {error}");
            }
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
        ui.ctx().request_repaint();
    }
}

fn main() -> eframe::Result {
    let mut args = std::env::args().skip(1);
    let frames = args
        .next()
        .and_then(|a| a.parse().ok())
        .unwrap_or(600_usize)
        .max(10);
    let out = args.next().map(std::path::PathBuf::from);
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("frame floor")
            .with_inner_size([1280.0, 800.0]),
        renderer: eframe::Renderer::Wgpu,
        ..eframe::NativeOptions::default()
    };
    eframe::run_native(
        "frame floor",
        options,
        Box::new(move |_| {
            Ok(Box::new(Floor {
                frames,
                out,
                last: None,
                seen: 0,
                intervals: Vec::new(),
            }))
        }),
    )
}
