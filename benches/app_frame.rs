//! The application's frame on the CPU during a live drag: a cylinder dragged from the
//! palette over the 63-stroke sheet (`sketches/sheet.svg`), one pointer move per frame,
//! through egui_kittest (no window, no GPU). Each sample is one frame: the app's UI (the
//! canvas with strokes, outlines and the preview, the panels, the software-painted 3D
//! view) and egui's tessellation of it into triangles. The preview's snap runs on its own
//! thread, as in the app.
//!
//! What a software rasterizer then spends drawing those triangles is measured in the
//! real window by `tools/headless.sh frames` (see the README).
//!
//! `cargo bench --bench app_frame`

#![expect(clippy::print_stdout, reason = "benchmark output")]

mod support;

use std::path::Path;
use std::time::Duration;

use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use geosnap::app::{AppOptions, GeosnapApp};
use support::{timed, Bench, Table};

fn main() {
    let bench = Bench::from_env();
    bench.print_intro("application frame (CPU: UI and tessellation) during a live drag");
    let sheet = Path::new(env!("CARGO_MANIFEST_DIR")).join("sketches/sheet.svg");
    let dir = std::env::temp_dir().join(format!("geosnap-bench-app-{}", std::process::id()));
    let options = AppOptions {
        file: Some(sheet),
        autosave_dir: Some(dir.join("autosave")),
        ..AppOptions::default()
    };
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1280.0, 800.0))
        .build_eframe(move |cc| GeosnapApp::new(cc, options));
    harness.run_steps(5);
    let strokes = harness.state().editor().sketch().strokes.len();
    let (lo, hi) = harness
        .state()
        .editor()
        .sketch()
        .bounds()
        .expect("the sheet has strokes");
    let from = harness.get_by_label("Cylinder").rect().center();
    harness.drag_at(from);
    harness.step();
    let mut frame = 0usize;
    let mut previews = 0usize;
    let mut last_generation = 0;
    let ppp = harness.ctx.pixels_per_point();
    let table = Table::new(
        &format!("{strokes}-stroke sheet, 1280×800 points"),
        34,
        &[("triangles", 10), ("previews", 9)],
    );
    let mut triangles = 0usize;
    let stats = bench.each(|_| {
        frame += 1;
        let t = frame as f64 * 0.03;
        let c = (lo + hi) / 2.0;
        let r = (hi - lo) * 0.3;
        let at = c + glam::DVec2::new(r.x * t.sin(), r.y * (2.0 * t).sin() * 0.5);
        let pos = harness.state().canvas_view().to_screen(at);
        harness.hover_at(pos);
        let (count, time) = timed(|| {
            harness.step();
            let shapes = harness.output().shapes.clone();
            harness
                .ctx
                .tessellate(shapes, ppp)
                .iter()
                .map(|p| match &p.primitive {
                    egui::epaint::Primitive::Mesh(m) => m.indices.len() / 3,
                    egui::epaint::Primitive::Callback(_) => 0,
                })
                .sum::<usize>()
        });
        triangles = count;
        if let Some(drag) = harness.state().drag() {
            if drag.preview_generation() != last_generation {
                previews += 1;
                last_generation = drag.preview_generation();
            }
        }
        // The frame rate of a display: the preview thread gets its time between frames.
        std::thread::sleep(Duration::from_millis(2));
        time
    });
    assert!(
        harness.state().drag().is_some(),
        "the drag went on throughout"
    );
    table.row(
        "frame during a palette drag",
        &stats,
        &[triangles.to_string(), previews.to_string()],
    );
    let _ = std::fs::remove_dir_all(&dir);
}
