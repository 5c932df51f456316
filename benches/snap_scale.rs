//! Benchmarks of how snapping scales with the number of strokes in a drawing: a cold snap
//! of a bent tube (BGC) dropped on its drawing among 1k, 5k and 10k clutter strokes, the
//! cold snap of every other kind among 10k, and preparing those drawings (preprocessing
//! and classification, [`SnapContext::from_sketch`]).
//!
//! Each drawing is one of the project's sample drawings in the middle cell of a 3 × 3
//! grid of cells the size of its viewBox, and clutter in the eight cells around it:
//! short lines, arcs and small ellipses (closed), at random places, sizes and angles
//! (a fixed seed). Nothing of the clutter lies within 40 units of the middle cell, so
//! the snap's result is the sample's own: its cost should not grow with the clutter.
//! The BGC is also dropped with the clutter spread over all nine cells ('over it'),
//! its own among them: the strokes near the drop then grow in number with the clutter,
//! and so does the work of reading the tube among them.
//!
//! A last table times preparing the 10k-stroke drawings on their own and with the
//! bent tube's drop after it (opening the drawing cold).
//!
//! Run with `cargo bench --no-default-features --bench snap_scale`. In smoke mode (and
//! in a debug build) the drawings hold 100, 200 and 300 clutter strokes instead.

#![expect(clippy::print_stdout, reason = "benchmark output")]

mod support;

use std::f64::consts::TAU;
use std::path::Path;

use geosnap::core::model::Step;
use geosnap::core::primitive::{Placement, Primitive, PrimitiveKind, DEFAULT_SIZE_FRACTION};
use geosnap::core::sketch::{Sketch, Stroke, StrokeId};
use geosnap::core::snap::{snap, SnapContext, SnapSettings};
use geosnap::io::script::parse_script;
use geosnap::io::svg::{import_svg, SvgOptions};
use glam::DVec2;
use support::{fmt_ns, timed, Bench, Rng, Table};

/// The sample of each kind.
const SAMPLES: [(&str, PrimitiveKind); 6] = [
    ("pipe", PrimitiveKind::Bgc),
    ("cylinders", PrimitiveKind::Cylinder),
    ("cones", PrimitiveKind::Cone),
    ("sphere", PrimitiveKind::Sphere),
    ("box", PrimitiveKind::Cuboid),
    ("vase", PrimitiveKind::Sgc),
];
/// The size of a grid cell (the samples' viewBox).
const CELL: DVec2 = DVec2::new(1200.0, 900.0);
/// No clutter comes this close to the middle cell.
const MARGIN: f64 = 40.0;

/// The clutter counts: the BGC's sweep and the count for every kind.
fn counts(bench: &Bench) -> ([usize; 3], usize) {
    if bench.is_smoke() || cfg!(debug_assertions) {
        ([100, 200, 300], 300)
    } else {
        ([1000, 5000, 10_000], 10_000)
    }
}

/// The sample drawing `name` moved to the middle cell, and the placement of its script's
/// first step of `kind`, moved with it.
fn sample(name: &str, kind: PrimitiveKind) -> (Vec<Stroke>, Placement) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("sketches");
    let svg = std::fs::read(dir.join(format!("{name}.svg"))).expect("the samples are there");
    let import = import_svg(&svg, &SvgOptions::default()).expect("the samples import");
    let strokes = import
        .sketch
        .strokes
        .into_iter()
        .map(|s| Stroke {
            points: s.points.iter().map(|p| *p + CELL).collect(),
            ..s
        })
        .collect();
    let script = std::fs::read(dir.join(format!("{name}.script.json"))).expect("a script");
    let script = parse_script(&script, &dir).expect("the scripts parse");
    let placement = script
        .steps
        .iter()
        .find_map(|s| match s {
            Step::Place { kind: k, placement } if *k == kind => Some(placement.clone()),
            _ => None,
        })
        .expect("each sample places its kind");
    (
        strokes,
        Placement {
            at: placement.at + CELL,
            ..placement
        },
    )
}

/// One clutter stroke centred at `at`: a short line, an arc or a small closed ellipse.
fn clutter_stroke(rng: &mut Rng, at: DVec2) -> (Vec<DVec2>, bool) {
    let size = rng.uniform(15.0, 60.0);
    let angle = rng.uniform(0.0, TAU);
    let (u, v) = (DVec2::from_angle(angle), DVec2::from_angle(angle).perp());
    let kind = rng.uniform(0.0, 1.0);
    if kind < 0.4 {
        let points = (0..8)
            .map(|i| at + u * size * (f64::from(i) / 7.0 - 0.5))
            .collect();
        (points, false)
    } else if kind < 0.7 {
        let sweep = rng.uniform(1.0, 3.0);
        let points = (0..12)
            .map(|i| {
                let t = sweep * f64::from(i) / 11.0;
                at + (u * t.cos() + v * t.sin()) * (size / 2.0)
            })
            .collect();
        (points, false)
    } else {
        let ratio = rng.uniform(0.3, 1.0);
        let points = (0..16)
            .map(|i| {
                let t = TAU * f64::from(i) / 16.0;
                at + (u * t.cos() + v * (ratio * t.sin())) * (size / 2.0)
            })
            .collect();
        (points, true)
    }
}

/// The sample `name` in the middle cell with `clutter` clutter strokes around it, or
/// `over` all the cells (see the module docs), and the placement of its `kind`.
fn drawing(name: &str, kind: PrimitiveKind, clutter: usize, over: bool) -> (Sketch, Placement) {
    let (mut strokes, placement) = sample(name, kind);
    let mut rng = Rng::new(19);
    let (lo, hi) = (CELL - MARGIN, 2.0 * CELL + MARGIN);
    let mut added = 0;
    while added < clutter {
        let at = DVec2::new(
            rng.uniform(0.0, 3.0 * CELL.x),
            rng.uniform(0.0, 3.0 * CELL.y),
        );
        // Clutter strokes reach at most 30 units from their centre.
        if !over && at.cmpgt(lo - 30.0).all() && at.cmplt(hi + 30.0).all() {
            continue;
        }
        let (points, closed) = clutter_stroke(&mut rng, at);
        strokes.push(Stroke {
            id: StrokeId(strokes.len() as u32),
            points,
            closed,
            class_override: None,
        });
        added += 1;
    }
    let sketch = Sketch {
        strokes,
        view_box: Some((DVec2::ZERO, 3.0 * CELL)),
    };
    (sketch, placement)
}

/// Times the cold snap of the sample `name`'s `kind` among `clutter` strokes (a row of
/// `table`), and the preparation of its drawing once (the 'prepare' column).
fn cold(
    bench: &Bench,
    table: &Table,
    (name, kind): (&str, PrimitiveKind),
    (clutter, over): (usize, bool),
) {
    let case = format!(
        "{} among {clutter} strokes{}",
        kind.name(),
        if over { " over it" } else { "" }
    );
    if !bench.wants(&case) {
        return;
    }
    let (sketch, placement) = drawing(name, kind, clutter, over);
    // Preparing is timed once: it is not what this benchmark is about, and it takes
    // seconds for the largest drawings.
    let (context, prepare) = timed(|| SnapContext::from_sketch(&sketch));
    let default_size = 3.0 * CELL.max_element() * 2.0 * DEFAULT_SIZE_FRACTION;
    let primitive = Primitive::from_placement(kind, &placement, default_size);
    let settings = SnapSettings::default();
    let mut last = None;
    let stats = bench.each(|_| {
        let (result, time) = timed(|| snap(&context, &primitive, &settings));
        last = Some(result);
        time
    });
    let mut extras = vec![
        sketch.strokes.len().to_string(),
        fmt_ns(prepare.as_nanos() as f64),
    ];
    match last {
        Some(Ok(r)) => extras.extend([
            r.assignment.stroke_ids().len().to_string(),
            format!("{:.2}", 100.0 * r.rms / r.primitive.size()),
        ]),
        _ => extras.extend(["-".into(), "fail".into()]),
    }
    table.row(&case, &stats, &extras);
}

/// Times preparing the BGC's drawing among `clutter` strokes (around or `over` it), and
/// opening it cold: preparing it and then dropping the tube, as a user who opens the
/// drawing and drops a bent tube first meets it.
fn open_and_drop(bench: &Bench, table: &Table, clutter: usize, over: bool) {
    let (name, kind) = SAMPLES[0];
    let where_ = if over { " over it" } else { "" };
    let (sketch, placement) = drawing(name, kind, clutter, over);
    let default_size = 3.0 * CELL.max_element() * 2.0 * DEFAULT_SIZE_FRACTION;
    let primitive = Primitive::from_placement(kind, &placement, default_size);
    let settings = SnapSettings::default();
    let prepare = format!("prepare {clutter} strokes{where_}");
    if bench.wants(&prepare) {
        let stats = bench.each(|_| timed(|| SnapContext::from_sketch(&sketch)).1);
        table.row(&prepare, &stats, &[sketch.strokes.len().to_string()]);
    }
    let open = format!("prepare + BGC drop, {clutter}{where_}");
    if bench.wants(&open) {
        let stats = bench.each(|_| {
            timed(|| {
                let context = SnapContext::from_sketch(&sketch);
                snap(&context, &primitive, &settings).is_ok()
            })
            .1
        });
        table.row(&open, &stats, &[sketch.strokes.len().to_string()]);
    }
}

fn main() {
    let bench = Bench::from_env();
    bench.print_intro("Snapping among many strokes");
    let (sweep, every) = counts(&bench);
    let table = Table::new(
        "Cold snap (snap from the dropped pose, the drawing prepared beforehand; 'prepare': \
         one call of SnapContext::from_sketch, preprocessing and classification)",
        34,
        &[("strokes", 8), ("prepare", 9), ("taken", 6), ("rms%", 6)],
    );
    for over in [false, true] {
        for clutter in sweep {
            cold(&bench, &table, SAMPLES[0], (clutter, over));
        }
    }
    for sample in &SAMPLES[1..] {
        cold(&bench, &table, *sample, (every, false));
    }
    let table = Table::new(
        "Opening cold (SnapContext::from_sketch, then the BGC's cold snap; target ≤ 1 s)",
        34,
        &[("strokes", 8)],
    );
    for over in [false, true] {
        open_and_drop(&bench, &table, every, over);
    }
}
