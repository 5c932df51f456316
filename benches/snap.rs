//! Benchmarks of snapping: one drag-frame update (assignment + warm-started snap) per
//! kind on a 60-stroke sketch, a cold snap per kind, its confidence (computed once, at
//! release), preparing the sketch (preprocessing and classification), and the SVG import
//! of the largest shared sketch.
//!
//! The 60-stroke sketch is the project's six sample drawings laid out on a 3 × 2 grid
//! plus short distractor strokes; each kind is dragged over its own drawing along a small
//! circle (a new pose every frame), through [`SnapSession::update`]. A second table sweeps
//! each kind along a wider circle (a quarter of its size), so the strokes under the cursor
//! change now and then and those frames snap afresh ('fresh%' of the frames). A point
//! drop of each kind at its first step's point, with no size or direction, snaps every
//! guess the drawing suggests ([`snap_at`]).
//!
//! Run with `cargo bench --no-default-features --bench snap`. The SVG import case reads
//! `legobrick.svg` from `GEOSNAP_SHARED_SKETCHES` (or `../shared/sketches`) when present.

#![expect(clippy::print_stdout, reason = "benchmark output")]

mod support;

use std::path::{Path, PathBuf};

use geosnap::core::model::Step;
use geosnap::core::primitive::{Placement, Primitive, PrimitiveKind, DEFAULT_SIZE_FRACTION};
use geosnap::core::sketch::{Sketch, Stroke, StrokeId};
use geosnap::core::snap::{guesses, nobody, snap, snap_at, SnapContext, SnapSession, SnapSettings};
use geosnap::core::solve::SolveContext;
use geosnap::io::script::parse_script;
use geosnap::io::svg::{import_svg, SvgOptions};
use glam::DVec2;
use support::{timed, Bench, Rng, Table};

/// The sample of each kind and the grid cell it goes to.
const SAMPLES: [(&str, PrimitiveKind); 6] = [
    ("cylinders", PrimitiveKind::Cylinder),
    ("cones", PrimitiveKind::Cone),
    ("sphere", PrimitiveKind::Sphere),
    ("box", PrimitiveKind::Cuboid),
    ("vase", PrimitiveKind::Sgc),
    ("pipe", PrimitiveKind::Bgc),
];
/// The size of a grid cell (the samples' viewBox).
const CELL: DVec2 = DVec2::new(1200.0, 900.0);
/// The number of strokes of the scene.
const STROKES: usize = 60;

/// The scene: the strokes and, per kind, the placement of its first step.
fn scene() -> (Sketch, Vec<(PrimitiveKind, Placement)>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("sketches");
    let mut strokes = Vec::new();
    let mut placements = Vec::new();
    for (cell, (name, kind)) in SAMPLES.iter().enumerate() {
        let offset = CELL * DVec2::new((cell % 3) as f64, (cell / 3) as f64);
        let svg = std::fs::read(dir.join(format!("{name}.svg"))).expect("the samples are there");
        let import = import_svg(&svg, &SvgOptions::default()).expect("the samples import");
        for stroke in import.sketch.strokes {
            strokes.push(Stroke {
                id: StrokeId(strokes.len() as u32),
                points: stroke.points.iter().map(|p| *p + offset).collect(),
                closed: stroke.closed,
                class_override: None,
            });
        }
        let script = std::fs::read(dir.join(format!("{name}.script.json"))).expect("a script");
        let script = parse_script(&script, &dir).expect("the scripts parse");
        let placement = script
            .steps
            .iter()
            .find_map(|s| match s {
                Step::Place { kind: k, placement } if k == kind => Some(placement.clone()),
                _ => None,
            })
            .expect("each sample places its kind");
        placements.push((
            *kind,
            Placement {
                at: placement.at + offset,
                ..placement
            },
        ));
    }
    // Distractors: short strokes scattered over the cells' margins.
    let mut rng = Rng::new(60);
    while strokes.len() < STROKES {
        let cell = CELL * DVec2::new(rng.index(3) as f64, rng.index(2) as f64);
        let start = cell + DVec2::new(rng.uniform(20.0, 250.0), rng.uniform(20.0, 150.0));
        let dir = DVec2::from_angle(rng.uniform(0.0, std::f64::consts::TAU));
        let points = (0..12)
            .map(|k| start + dir * (6.0 * f64::from(k)))
            .collect();
        strokes.push(Stroke {
            id: StrokeId(strokes.len() as u32),
            points,
            closed: false,
            class_override: None,
        });
    }
    let sketch = Sketch {
        strokes,
        view_box: Some((DVec2::ZERO, CELL * DVec2::new(3.0, 2.0))),
    };
    (sketch, placements)
}

/// The dropped primitive of frame `frame`: the placement moved along a circle of 6 units.
fn dragged(
    kind: PrimitiveKind,
    placement: &Placement,
    frame: usize,
    default_size: f64,
) -> Primitive {
    let angle = frame as f64 * 0.35;
    let moved = Placement {
        at: placement.at + DVec2::from_angle(angle) * 6.0,
        ..placement.clone()
    };
    Primitive::from_placement(kind, &moved, default_size)
}

/// The dropped primitive of frame `frame` of the wide sweep: the placement moved along a
/// circle of a quarter of its size, a little further each frame.
fn swept(kind: PrimitiveKind, placement: &Placement, frame: usize, default_size: f64) -> Primitive {
    let at_rest = Primitive::from_placement(kind, placement, default_size);
    let angle = frame as f64 * 0.05;
    let moved = Placement {
        at: placement.at + DVec2::from_angle(angle) * (0.25 * at_rest.size()),
        ..placement.clone()
    };
    Primitive::from_placement(kind, &moved, default_size)
}

/// A wider sweep: the cursor circles at a quarter of the size around the drawing, so the
/// strokes under it change now and then and those frames snap afresh ('fresh%').
fn sweep(
    bench: &Bench,
    context: &SnapContext,
    settings: &SnapSettings,
    placements: &[(PrimitiveKind, Placement)],
    default_size: f64,
) {
    let table = Table::new(
        "Drag frame sweeping over its drawing (radius 25 % of the size)",
        34,
        &[("strokes", 8), ("fresh%", 7)],
    );
    for (kind, placement) in placements {
        let mut session = SnapSession::new(context.clone(), settings.clone());
        let (mut frames, mut fresh, mut strokes) = (0usize, 0usize, 0usize);
        let stats = bench.each(|i| {
            let primitive = swept(*kind, placement, i, default_size);
            let (result, time) = timed(|| session.update(&primitive, SolveContext::default()));
            frames += 1;
            if let Ok(r) = result {
                strokes = r.assignment.stroke_ids().len();
                fresh += usize::from(r.evaluations > 5);
            }
            time
        });
        table.row(
            kind.name(),
            &stats,
            &[
                strokes.to_string(),
                format!("{:.0}", 100.0 * fresh as f64 / frames.max(1) as f64),
            ],
        );
    }
}

fn shared_legobrick() -> Option<PathBuf> {
    let dir = std::env::var_os("GEOSNAP_SHARED_SKETCHES").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/sketches"),
        PathBuf::from,
    );
    let path = dir.join("legobrick.svg");
    path.is_file().then_some(path)
}

fn main() {
    let bench = Bench::from_env();
    bench.print_intro("Snapping benchmarks");
    let (sketch, placements) = scene();
    let default_size = CELL.max_element() * 2.0 * DEFAULT_SIZE_FRACTION;
    let settings = SnapSettings::default();

    let table = Table::new(
        &format!("Preparing the {}-stroke sketch", sketch.strokes.len()),
        34,
        &[],
    );
    let prepare = bench.each(|_| timed(|| SnapContext::from_sketch(&sketch)).1);
    table.row("SnapContext::from_sketch", &prepare, &[]);
    let context = SnapContext::from_sketch(&sketch);

    let table = Table::new(
        "Drag frame: assignment + warm-started snap (SnapSession::update)",
        34,
        &[("strokes", 8), ("evals", 6), ("rms%", 6)],
    );
    for (kind, placement) in &placements {
        let mut session = SnapSession::new(context.clone(), settings.clone());
        let mut last = None;
        let stats = bench.each(|i| {
            let primitive = dragged(*kind, placement, i, default_size);
            let (result, time) = timed(|| session.update(&primitive, SolveContext::default()));
            last = result.ok();
            time
        });
        let extras = last.map_or_else(
            || vec!["-".into(), "-".into(), "fail".into()],
            |r| {
                vec![
                    r.assignment.stroke_ids().len().to_string(),
                    r.evaluations.to_string(),
                    format!("{:.2}", 100.0 * r.rms / r.primitive.size()),
                ]
            },
        );
        table.row(kind.name(), &stats, &extras);
    }

    sweep(&bench, &context, &settings, &placements, default_size);

    let table = Table::new(
        "Cold snap (assignment + snap from the dropped pose)",
        34,
        &[("strokes", 8), ("evals", 6)],
    );
    for (kind, placement) in &placements {
        let primitive = dragged(*kind, placement, 0, default_size);
        let mut last = None;
        let stats = bench.each(|_| {
            let (result, time) = timed(|| snap(&context, &primitive, &settings));
            last = result.ok();
            time
        });
        let extras = last.map_or_else(
            || vec!["-".into(), "fail".into()],
            |r| {
                vec![
                    r.assignment.stroke_ids().len().to_string(),
                    r.evaluations.to_string(),
                ]
            },
        );
        table.row(kind.name(), &stats, &extras);
    }
    point_drops(&bench, &context, &settings, &placements);
    let table = Table::new(
        "Confidence of a cold snap, at release (SnapResult::confidence: evidence + spread)",
        34,
        &[("verdict", 9)],
    );
    for (kind, placement) in &placements {
        let primitive = dragged(*kind, placement, 0, default_size);
        let Ok(result) = snap(&context, &primitive, &settings) else {
            println!("{}: the cold snap failed, nothing to judge", kind.name());
            continue;
        };
        let mut verdict = String::new();
        let stats = bench.each(|_| {
            let (confidence, time) = timed(|| result.confidence(&primitive, &nobody, &settings));
            confidence.verdict.name().clone_into(&mut verdict);
            time
        });
        table.row(kind.name(), &stats, &[verdict]);
    }

    svg_import(&bench);
}

/// The point drop of each kind at its first step's point: no size, no direction, every
/// guess the drawing suggests snapped ([`snap_at`]).
fn point_drops(
    bench: &Bench,
    context: &SnapContext,
    settings: &SnapSettings,
    placements: &[(PrimitiveKind, Placement)],
) {
    let table = Table::new(
        "Point drop (snap_at: no size, no direction; every guess the drawing suggests)",
        34,
        &[("guesses", 8), ("strokes", 8)],
    );
    for (kind, placement) in placements {
        let guesses = guesses(context, *kind, placement.at, None).len();
        let mut last = None;
        let stats = bench.each(|_| {
            let (result, time) = timed(|| snap_at(context, *kind, placement.at, None, settings));
            last = result.ok();
            time
        });
        let strokes = last.map_or_else(
            || "fail".to_owned(),
            |p| p.result.assignment.stroke_ids().len().to_string(),
        );
        table.row(kind.name(), &stats, &[guesses.to_string(), strokes]);
    }
}

/// The SVG import of the largest shared sketch, when it is found.
fn svg_import(bench: &Bench) {
    let table = Table::new("SVG import", 34, &[("strokes", 8)]);
    if let Some(path) = shared_legobrick() {
        let data = std::fs::read(&path).expect("readable");
        let mut strokes = 0;
        let stats = bench.each(|_| {
            let (import, time) = timed(|| import_svg(&data, &SvgOptions::default()));
            strokes = import.map_or(0, |i| i.sketch.strokes.len());
            time
        });
        table.row(
            "legobrick.svg (largest shared)",
            &stats,
            &[strokes.to_string()],
        );
    } else {
        println!("legobrick.svg not found (set GEOSNAP_SHARED_SKETCHES): SVG import skipped");
    }
}
