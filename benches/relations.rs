//! Benchmarks of what happens on release: relation inference for the new part
//! ([`Document::infer_relations`]) plus the global solve that follows
//! ([`Document::solve`] with the new part as the changed one), against model size.
//!
//! # Models
//!
//! A model of N primitives is a grid of synthetic assemblies from the test renderer
//! (`tests/support/assemblies.rs`: tables, stacks, bricks with studs, boxes with pipes,
//! balls with tubes, in turn, ending with a table whose last leg is the part released),
//! all drawn in one sketch from one designer's view, each
//! 450–650 sketch units large in a 700-unit cell: one scene as a person draws it, so
//! parts of different assemblies are related too where they happen to agree (all the
//! tables' legs stand parallel). The first N parts of that sequence are placed by
//! perturbed steps as in the acceptance test: each is snapped on the whole sketch,
//! added, and its relations inferred on release; the N − 1 first are then solved
//! together once ([`Document::solve`] over every part), which gives the document a
//! release meets.
//!
//! # What is timed
//!
//! Each sample clones that document, adds the last part as snapped (untimed) and times
//! `infer_relations(last)` + `solve(Some(&[last]))` with the default settings and a
//! [`MonotonicClock`] (as `geosnap run`; it makes the 10 s time cap per solve hold): the
//! work of one release. The solve covers the connected component of the relation graph that
//! holds the new part (in one view, typically most of the model). Reported per size:
//! median, p95, min; the relations in the model after the release, the relations the
//! release inferred, the parts the solve covered, the conflicts it switched off, and the
//! exponent k of a power law t ∝ N^k between consecutive sizes (median times).
//!
//! Targets (issue 4): 10 primitives / about 20 relations ≤ 30 ms median; 50 / about 100
//! ≤ 300 ms.
//!
//! Run with `cargo bench --no-default-features --bench relations` (`GEOSNAP_BENCH_SAMPLES`,
//! `GEOSNAP_BENCH_SECONDS` as for every benchmark; a name filter such as `-- N=50`).
//! Without `--bench` (`cargo test --benches`) it runs in smoke mode on the smallest
//! size only.

#![expect(clippy::print_stdout, reason = "benchmark output")]

mod support;

#[path = "../tests/support/assemblies.rs"]
#[allow(dead_code, reason = "the benchmark uses a part of the test support")]
mod assemblies;
#[path = "../tests/support/synth.rs"]
#[allow(dead_code, reason = "the benchmark uses a part of the test support")]
mod synth;

use std::time::Instant;

use assemblies::{canonical, moved, placement, view, AssemblyKind};
use geosnap::clock::MonotonicClock;
use geosnap::core::model::{Companions, Document, GlobalSettings};
use geosnap::core::primitive::Primitive;
use geosnap::core::relation::InferenceSettings;
use geosnap::core::sketch::{Sketch, Stroke, StrokeId};
use geosnap::core::snap::{snap, SnapContext, SnapResult, SnapSettings};
use glam::{DQuat, DVec3};
use support::{fmt_ns, timed, Bench, Table};
use synth::{draw, Rng, Style};

/// Model sizes (primitives).
const SIZES: [usize; 5] = [10, 20, 50, 100, 200];
/// The sizes of a smoke run.
const SMOKE_SIZES: [usize; 1] = [10];
/// The assemblies, in turn.
const SEQUENCE: [AssemblyKind; 5] = [
    AssemblyKind::Table,
    AssemblyKind::Stack,
    AssemblyKind::BrickStuds,
    AssemblyKind::BoxPipes,
    AssemblyKind::SphereTubes,
];
/// The side of a grid cell in sketch units.
const CELL: f64 = 700.0;

/// The first `n` parts of the scene, their sketch, and the parts' perturbed snaps (in
/// placement order; parts whose snap fails are left out).
fn model(n: usize) -> (Sketch, Vec<SnapResult>) {
    let mut rng = Rng::new(0x5CA1_E000 + n as u64);
    let style = Style::random(&mut rng);
    let turn = view(&mut rng);
    let columns = ((n as f64 / 4.0).sqrt().ceil() as usize).max(1);
    // The last assembly is a table, released last: its last leg is related to its top
    // and to the other legs, so the release has a component to solve.
    let (table, _) = canonical(AssemblyKind::Table, &mut rng, turn);
    let body = n.saturating_sub(table.len());
    let mut parts: Vec<Primitive> = Vec::new();
    let mut cell = 0;
    let place = |canon: &[Primitive], r: DQuat, cell: usize, rng: &mut Rng| {
        let size = rng.range(450.0, 650.0);
        let centre = DVec3::new(
            CELL * ((cell % columns) as f64 + 0.5),
            -CELL * ((cell / columns) as f64 + 0.5),
            rng.range(-size, size),
        );
        canon
            .iter()
            .map(|p| moved(p, r, size, centre))
            .collect::<Vec<_>>()
    };
    while parts.len() < body {
        let kind = SEQUENCE[cell % SEQUENCE.len()];
        let r = if kind == AssemblyKind::SphereTubes {
            DQuat::IDENTITY
        } else {
            turn
        };
        let (canon, _) = canonical(kind, &mut rng, r);
        parts.extend(place(&canon, r, cell, &mut rng));
        cell += 1;
    }
    parts.truncate(body);
    parts.extend(place(&table, turn, cell, &mut rng));
    parts.truncate(n);
    let mut strokes = Vec::new();
    for p in &parts {
        for s in draw(p, style, &mut rng) {
            strokes.push(Stroke {
                id: StrokeId(strokes.len() as u32),
                points: s.points,
                closed: false,
                class_override: Some(s.class),
            });
        }
    }
    let sketch = Sketch {
        strokes,
        view_box: None,
    };
    let context = SnapContext::from_sketch(&sketch);
    let settings = SnapSettings::default();
    let snaps = parts
        .iter()
        .filter_map(|p| {
            let dropped = Primitive::from_placement(p.kind(), &placement(p, &mut rng), p.size());
            snap(&context, &dropped, &settings).ok()
        })
        .collect();
    (sketch, snaps)
}

/// The exponent k of t ∝ N^k between two sizes.
fn exponent(n0: usize, t0: f64, n1: usize, t1: f64) -> f64 {
    (t1 / t0).ln() / (n1 as f64 / n0 as f64).ln()
}

/// A document of the snapped parts `placed`, related on release one by one and then
/// solved together once.
fn solved(
    placed: &[SnapResult],
    inference: &InferenceSettings,
    global: &GlobalSettings,
) -> Document {
    let mut base = Document::new();
    for s in placed {
        let id = base.add_snapped(s);
        base.infer_relations(id, inference);
    }
    let clock = MonotonicClock::start();
    base.solve(
        None,
        global,
        Companions {
            clock: Some(&clock),
            ..Companions::default()
        },
    );
    base
}

fn main() {
    let bench = Bench::from_env();
    bench.print_intro("Relations on release: inference + global solve");
    let inference = InferenceSettings::default();
    let global = GlobalSettings::default();
    let sizes: &[usize] = if bench.is_smoke() {
        &SMOKE_SIZES
    } else {
        &SIZES
    };
    let table = Table::new(
        "Release of the last part of an N-part model: infer_relations + solve (component \
         of the new part)",
        8,
        &[
            ("parts", 5),
            ("strokes", 7),
            ("relations", 9),
            ("new", 3),
            ("solved", 6),
            ("confl", 5),
            ("setup", 8),
            ("k", 5),
        ],
    );
    let mut previous: Option<(usize, f64)> = None;
    for &n in sizes {
        let name = format!("N={n}");
        if !bench.wants(&name) {
            continue;
        }
        // The document a release meets: N − 1 parts snapped, related and solved.
        let setup = Instant::now();
        let (sketch, snaps) = model(n);
        let Some((last, placed)) = snaps.split_last() else {
            println!("{name}: no part snapped");
            continue;
        };
        let mut base = solved(placed, &inference, &global);
        let id = base.add_snapped(last);
        let setup = setup.elapsed();
        let mut after: Option<(usize, usize, usize, usize)> = None;
        let stats = bench.each(|_| {
            let mut doc = base.clone();
            let (outcome, time) = timed(|| {
                let new = doc.infer_relations(id, &inference);
                let clock = MonotonicClock::start();
                let solve = doc.solve(
                    Some(&[id]),
                    &global,
                    Companions {
                        clock: Some(&clock),
                        ..Companions::default()
                    },
                );
                (new.len(), solve)
            });
            after = Some((
                doc.relations().len(),
                outcome.0,
                outcome.1.solved.len(),
                outcome.1.conflicts.len(),
            ));
            time
        });
        let (relations, new, solved, conflicts) = after.unwrap_or_default();
        let k = previous.map_or_else(
            || "-".to_owned(),
            |(n0, t0)| format!("{:.2}", exponent(n0, t0, n, stats.median)),
        );
        previous = Some((n, stats.median));
        table.row(
            &name,
            &stats,
            &[
                snaps.len().to_string(),
                sketch.strokes.len().to_string(),
                relations.to_string(),
                new.to_string(),
                solved.to_string(),
                conflicts.to_string(),
                fmt_ns(setup.as_nanos() as f64),
                k,
            ],
        );
    }
    println!(
        "\nparts = parts snapped (of N); relations = relations in the model after the \
         release; new = inferred by the release; solved = parts in the solved component; \
         confl = relations the release's solve switched off; setup = building the model \
         (snaps, inference, one solve of N − 1 parts), untimed; k = exponent of t ∝ N^k \
         from the previous size (medians)."
    );
}
