//! Benchmarks of the overlay PNG (`geosnap run … --overlay`) of large drawings: one
//! stroke of 100k points zigzagging a hundredth of a pixel apart, one stroke of 100k
//! points thrown at random over the page (a scribble of long crossing segments), and
//! 1,000 strokes of 100 points; each with a cylinder drawn over it, and the cost of
//! encoding the PNG included.
//!
//! Run with `cargo bench --no-default-features --bench overlay`. In smoke mode (and in a
//! debug build) the drawings hold 10k points instead.

#![expect(clippy::print_stdout, reason = "benchmark output")]

mod support;

use geosnap::core::primitive::{Cylinder, Primitive};
use geosnap::core::sketch::{Sketch, Stroke, StrokeId};
use geosnap::io::overlay::{overlay_png, OverlayItem};
use glam::{DVec2, DVec3};
use support::{timed, Bench, Rng, Table};

/// The page: the samples' viewBox.
const PAGE: DVec2 = DVec2::new(1200.0, 900.0);

/// A sketch of `strokes` on the page.
fn sketch(strokes: Vec<(Vec<DVec2>, bool)>) -> Sketch {
    Sketch {
        strokes: strokes
            .into_iter()
            .enumerate()
            .map(|(i, (points, closed))| Stroke {
                id: StrokeId(i as u32),
                points,
                closed,
                class_override: None,
            })
            .collect(),
        view_box: Some((DVec2::ZERO, PAGE)),
    }
}

/// The drawings of `points` points in all: (name, sketch).
fn drawings(points: usize) -> Vec<(String, Sketch)> {
    let mut rng = Rng::new(19);
    let step = (PAGE.x - 100.0) / points as f64;
    let zigzag = (0..points)
        .map(|i| {
            DVec2::new(
                50.0 + step * i as f64,
                if i % 2 == 0 { 100.0 } else { 800.0 },
            )
        })
        .collect();
    let scribble = (0..points)
        .map(|_| DVec2::new(rng.uniform(50.0, 1150.0), rng.uniform(50.0, 850.0)))
        .collect();
    let many = (0..points / 100)
        .map(|_| {
            let at = DVec2::new(rng.uniform(80.0, 1120.0), rng.uniform(80.0, 820.0));
            let points = (0..100)
                .map(|_| at + DVec2::new(rng.uniform(-30.0, 30.0), rng.uniform(-30.0, 30.0)))
                .collect();
            (points, false)
        })
        .collect();
    vec![
        (
            format!("zigzag of {points} points"),
            sketch(vec![(zigzag, false)]),
        ),
        (
            format!("scribble of {points} points"),
            sketch(vec![(scribble, false)]),
        ),
        (
            format!("{} strokes of 100 points", points / 100),
            sketch(many),
        ),
    ]
}

fn main() {
    let bench = Bench::from_env();
    bench.print_intro("Overlay rendering");
    let points = if bench.is_smoke() || cfg!(debug_assertions) {
        10_000
    } else {
        100_000
    };
    let cylinder = Primitive::Cylinder(Cylinder {
        center: DVec3::new(600.0, -450.0, 0.0),
        axis: DVec3::Y,
        length: 300.0,
        radius: 100.0,
    });
    let table = Table::new(
        "overlay_png (strokes, a cylinder over them, PNG encoding)",
        30,
        &[("bytes", 9)],
    );
    for (name, sketch) in drawings(points) {
        if !bench.wants(&name) {
            continue;
        }
        let taken: Vec<StrokeId> = sketch.strokes.iter().take(3).map(|s| s.id).collect();
        let items = [OverlayItem {
            primitive: &cylinder,
            strokes: &taken,
        }];
        let mut bytes = 0;
        let stats = bench.each(|_| {
            let (png, time) = timed(|| overlay_png(&sketch, &items, &[]));
            bytes = png.map_or(0, |p| p.len());
            time
        });
        table.row(&name, &stats, &[bytes.to_string()]);
    }
}
