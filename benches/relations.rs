//! Benchmarks of what happens on release ([`Document::release`]): relation inference
//! for the new part plus the global solve that follows (with the new part as the changed
//! one), against model size.
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
//! perturbed steps as in the acceptance test: each is snapped on the whole sketch. The
//! N − 1 first are released one by one, as a user builds the model, which gives the
//! document the last release meets; each of those releases is timed once too.
//!
//! # What is timed
//!
//! Each sample clones that document, adds the last part as snapped (untimed) and times
//! `release(last)` with the default settings and a [`MonotonicClock`] (as `geosnap
//! run`; it makes the 10 s time cap per solve hold). The solve frees the new part and the
//! parts related to it and holds the rest of its component ([`GlobalSettings::reach`]).
//! Reported per size: median, p95, min; the relations in the model after the release,
//! the relations the release inferred, the parts the solve freed, the conflicts it
//! switched off, and the exponent k of a power law t ∝ N^k between consecutive sizes
//! (median times).
//!
//! A second table gives the N − 1 releases of the build-up, one timing each: the last
//! release alone may be a lucky or an unlucky one, while the build-up shows what a user
//! meets along the way (median, p95, the slowest, and the conflicts).
//!
//! Targets (issue 4): 10 primitives / about 20 relations ≤ 30 ms median; 50 / about 100
//! ≤ 300 ms.
//!
//! Run with `cargo bench --no-default-features --bench relations` (`GEOSNAP_BENCH_SAMPLES`,
//! `GEOSNAP_BENCH_SECONDS` as for every benchmark; a name filter such as `-- 'N=20$'`;
//! `GEOSNAP_BENCH_CONFLICTS=1` prints every relation the build-up switches off, and why;
//! `GEOSNAP_BENCH_CONFLICTS_DETAIL=1` adds its evidence and its members as solved).
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
use support::{fmt_ns, timed, Bench, Stats, Table};
use synth::{draw, Rng, Style};

/// Model sizes (primitives).
const SIZES: [usize; 6] = [10, 20, 50, 100, 200, 500];
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
    let table = canonical(AssemblyKind::Table, &mut rng, turn).parts;
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
        let canon = canonical(kind, &mut rng, r).parts;
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

/// What one release of the build-up did.
struct Release {
    /// Inference + solve, nanoseconds.
    time: f64,
    /// Parts solved.
    solved: usize,
    /// Relations switched off.
    conflicts: usize,
}

/// A document of the snapped parts `placed`, released one by one as a user would:
/// each is added, its relations inferred, and the parts it changed solved. With what
/// each release did.
fn released(
    placed: &[SnapResult],
    inference: &InferenceSettings,
    global: &GlobalSettings,
) -> (Document, Vec<Release>) {
    let mut base = Document::new();
    let mut releases = Vec::with_capacity(placed.len());
    for s in placed {
        let id = base.add_snapped(s);
        let start = Instant::now();
        let clock = MonotonicClock::start();
        let (_, outcome) = base.release(
            id,
            inference,
            global,
            Companions {
                clock: Some(&clock),
                ..Companions::default()
            },
        );
        if std::env::var_os("GEOSNAP_BENCH_CONFLICTS").is_some() {
            for c in &outcome.conflicts {
                println!("  N={} release of #{}: {}", placed.len(), id.0, c.message);
                if std::env::var_os("GEOSNAP_BENCH_CONFLICTS_DETAIL").is_some() {
                    if let Some(r) = base.relation(c.relation) {
                        println!("    {:?}", r.inferred);
                        for m in &r.members {
                            if let Some(p) = base.get(*m) {
                                println!("    #{}: {:?}", m.0, p.primitive);
                            }
                        }
                    }
                }
            }
        }
        releases.push(Release {
            time: start.elapsed().as_nanos() as f64,
            solved: outcome.solved.len(),
            conflicts: outcome.conflicts.len(),
        });
    }
    (base, releases)
}

/// The table of every release of each size's build-up.
fn print_build_up(build_up: Vec<(usize, Vec<Release>)>) {
    let table = Table::new(
        "Every release while the N-part model is built (the N − 1 releases of the setup, \
         one timing each)",
        8,
        &[("max", 8), ("solved", 6), ("confl", 5), ("w/confl", 7)],
    );
    for (n, releases) in build_up {
        if releases.is_empty() {
            continue;
        }
        let max = releases.iter().map(|r| r.time).fold(0.0, f64::max);
        let solved = releases.iter().map(|r| r.solved).max().unwrap_or(0);
        let conflicts: usize = releases.iter().map(|r| r.conflicts).sum();
        let with_conflicts = releases.iter().filter(|r| r.conflicts > 0).count();
        let stats = Stats::of(releases.iter().map(|r| r.time).collect());
        table.row(
            &format!("N={n}"),
            &stats,
            &[
                fmt_ns(max),
                solved.to_string(),
                conflicts.to_string(),
                with_conflicts.to_string(),
            ],
        );
    }
    println!(
        "\nmax = the slowest release; solved = most parts one release freed; confl = \
         relations switched off in all; w/confl = releases that switched one off."
    );
}

fn main() {
    env_logger::init();
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
        "Release of the last part of an N-part model: inference + solve of the parts it \
         changed",
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
    let mut build_up = Vec::new();
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
        let (mut base, releases) = released(placed, &inference, &global);
        build_up.push((n, releases));
        let id = base.add_snapped(last);
        let setup = setup.elapsed();
        let mut after: Option<(usize, usize, usize, usize)> = None;
        let stats = bench.each(|_| {
            let mut doc = base.clone();
            let (outcome, time) = timed(|| {
                let clock = MonotonicClock::start();
                let (new, solve) = doc.release(
                    id,
                    &inference,
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
         release; new = inferred by the release; solved = parts the solve freed; \
         confl = relations the release's solve switched off; setup = building the model \
         (snaps, N − 1 releases), untimed; k = exponent of t ∝ N^k \
         from the previous size (medians)."
    );
    print_build_up(build_up);
}
