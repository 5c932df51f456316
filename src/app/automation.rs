//! Scripted runs of the app, for demos, screenshots and measurements: playing a
//! placement script as drags (`--play`), saving a screenshot once the work has settled
//! (`--screenshot`), and the simulated drag of the frame-time measurement
//! (`--drag-benchmark`).

use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::anyhow;
use glam::DVec2;

use super::GeosnapApp;
use crate::core::model::Step;
use crate::core::primitive::PrimitiveKind;

/// What the app does by itself: the placements still to play, the screenshot to take,
/// the drag benchmark to run.
#[derive(Debug, Default)]
pub(crate) struct Automation {
    /// Placements still to play (`--play`).
    play: VecDeque<Step>,
    screenshot: Option<Screenshot>,
    benchmark: Option<DragBenchmark>,
}

impl Automation {
    /// The runs `options` ask for (the script's steps are added by [`Self::play`]).
    pub(crate) fn new(options: &super::AppOptions) -> Self {
        Self {
            play: VecDeque::new(),
            screenshot: options.screenshot.clone().map(Screenshot::new),
            benchmark: options
                .drag_benchmark
                .clone()
                .map(|(frames, out)| DragBenchmark::new(frames, out)),
        }
    }

    /// Plays `steps` as drags, one after the other's solve.
    pub(crate) fn play(&mut self, steps: Vec<Step>) {
        self.play = steps.into();
    }
}

/// The simulated drag of the frame-time measurement.
#[derive(Debug)]
pub(crate) struct DragBenchmark {
    frames: usize,
    out: PathBuf,
    frame: usize,
    intervals: Vec<Duration>,
    cpu: Vec<Duration>,
    snaps: Vec<Duration>,
    last: Option<Instant>,
    last_generation: u64,
}

impl DragBenchmark {
    pub(crate) fn new(frames: usize, out: PathBuf) -> Self {
        Self {
            frames: frames.max(10),
            out,
            frame: 0,
            intervals: Vec::new(),
            cpu: Vec::new(),
            snaps: Vec::new(),
            last: None,
            last_generation: 0,
        }
    }
}

fn percentile(values: &[Duration], q: f64) -> f64 {
    let mut ms: Vec<f64> = values.iter().map(|d| d.as_secs_f64() * 1e3).collect();
    if ms.is_empty() {
        return f64::NAN;
    }
    ms.sort_by(f64::total_cmp);
    let k = ((ms.len() - 1) as f64 * q).round() as usize;
    ms[k]
}

impl GeosnapApp {
    /// Drops the next scripted placement once the previous one has been solved.
    pub(crate) fn play_step(&mut self) {
        if self.busy() || self.drag.is_some() || self.loading.is_some() {
            return;
        }
        let Some(step) = self.automation.play.pop_front() else {
            return;
        };
        if let Step::Place { kind, placement } = step {
            self.begin_drag(kind);
            self.place_drag(placement);
            self.end_drag();
        }
    }

    /// The frame-time measurement: a cylinder dragged over the drawing along a slow
    /// figure-eight, one step per frame, then the figures written and the app closed.
    pub(crate) fn benchmark_step(&mut self, ctx: &egui::Context) {
        if self.loading.is_some() {
            // The drawing is still being read: the measurement starts on it.
            return;
        }
        let Some(mut bench) = self.automation.benchmark.take() else {
            return;
        };
        let now = Instant::now();
        if let Some(last) = bench.last {
            if bench.frame > 20 {
                bench.intervals.push(now - last);
                bench
                    .cpu
                    .push(self.status.timer().last_cpu().unwrap_or_default());
            }
        }
        bench.last = Some(now);
        bench.frame += 1;
        if bench.frame == 10 {
            self.begin_drag(PrimitiveKind::Cylinder);
        }
        if let (Some((lo, hi)), true) = (self.editor.sketch().bounds(), bench.frame >= 10) {
            let t = bench.frame as f64 * 0.03;
            let c = (lo + hi) / 2.0;
            let r = (hi - lo) * 0.3;
            let at = c + DVec2::new(r.x * t.sin(), r.y * (2.0 * t).sin() * 0.5);
            self.drag_to(at, true);
            if let Some(drag) = &self.drag {
                if drag.generation() != bench.last_generation
                    && drag.preview_time() > Duration::ZERO
                {
                    bench.snaps.push(drag.preview_time());
                }
                bench.last_generation = drag.generation();
            }
        }
        if bench.frame >= bench.frames + 20 {
            self.cancel_drag();
            let report = serde_json::json!({
                "frames": bench.intervals.len(),
                "strokes": self.editor.sketch().strokes.len(),
                "frame_interval_ms": {
                    "median": percentile(&bench.intervals, 0.5),
                    "p95": percentile(&bench.intervals, 0.95),
                    "max": percentile(&bench.intervals, 1.0),
                },
                "ui_cpu_ms": {
                    "median": percentile(&bench.cpu, 0.5),
                    "p95": percentile(&bench.cpu, 0.95),
                },
                "preview_snap_ms": {
                    "median": percentile(&bench.snaps, 0.5),
                    "p95": percentile(&bench.snaps, 0.95),
                },
            });
            let text = serde_json::to_string_pretty(&report).unwrap_or_default();
            if let Err(error) = crate::io::write_atomic(&bench.out, text.as_bytes()) {
                log::error!("cannot write {}: {error}", bench.out.display());
            }
            self.files.quit(ctx);
            return;
        }
        ctx.request_repaint();
        self.automation.benchmark = Some(bench);
    }

    pub(crate) fn screenshot_step(&mut self, ctx: &egui::Context) {
        let Some(mut shot) = self.automation.screenshot.take() else {
            return;
        };
        if shot.done.load(Ordering::Acquire) {
            self.files.quit(ctx);
            return;
        }
        // Wait until the work has settled (no drag, no job, nothing left to play) and a
        // few frames have shown it.
        let settled = !self.busy()
            && self.drag.is_none()
            && self.loading.is_none()
            && self.automation.play.is_empty();
        shot.settled = if settled { shot.settled + 1 } else { 0 };
        if shot.settled == 30 {
            if self.selection.is_none() {
                self.selection = self.editor.document().primitives().last().map(|(id, _)| id);
            }
            let (path, done, repaint) = (shot.path.clone(), shot.done.clone(), ctx.clone());
            ctx.request_screenshot(move |image| {
                let [w, h] = image.size;
                let bytes: Vec<u8> = image
                    .pixels
                    .iter()
                    .flat_map(egui::Color32::to_array)
                    .collect();
                let saved = image::RgbaImage::from_raw(w as u32, h as u32, bytes)
                    .ok_or_else(|| anyhow!("bad screenshot size"))
                    .and_then(|img| img.save(&path).map_err(anyhow::Error::from));
                if let Err(error) = saved {
                    log::error!("cannot save the screenshot {}: {error:#}", path.display());
                }
                done.store(true, Ordering::Release);
                repaint.request_repaint();
            });
        }
        ctx.request_repaint_after(Duration::from_millis(30));
        self.automation.screenshot = Some(shot);
    }
}

/// A screenshot to take once the work has settled (`--screenshot`).
#[derive(Debug)]
pub(crate) struct Screenshot {
    pub(crate) path: PathBuf,
    settled: u32,
    done: Arc<AtomicBool>,
}

impl Screenshot {
    pub(crate) fn new(path: PathBuf) -> Self {
        Self {
            path,
            settled: 0,
            done: Arc::default(),
        }
    }
}
