//! Benchmarks of the two relation costs of issue 19 that a hostile model or script
//! makes explode:
//!
//! - **Dense relations:** `Document::solve` of every part (as `geosnap solve` does) in a
//!   model of 200 cylinders with every pair related, 19,900 hard relations: all
//!   parallel; all orthogonal; all coaxial; and a mix of parallel, orthogonal, coaxial,
//!   same radius and equal length. The cylinders stand at random places and directions
//!   (a fixed seed), so most of what the relations ask is far from where the parts are,
//!   and much of it contradicts itself. Target: every solve ends in ≤ 10 s with a clear
//!   report (it was 40–90 s, or a refusal after nine full solves). The table gives the
//!   relations the solve left out as implied by the others, the conflicts switched off,
//!   the solves run and whether the result was kept.
//! - **Identical placements:** the placement script of `sketches/box.svg` with its one
//!   box placed 40 times over (`run_steps`, as `geosnap run`). Target: ≤ 2 s (it was
//!   116 s: every copy related to every other, then conflicts re-solved one by one).
//!
//! Run with `cargo bench --no-default-features --bench dense` (`GEOSNAP_BENCH_SAMPLES`,
//! `GEOSNAP_BENCH_SECONDS` as for every benchmark; each case takes at least 10 samples).
//! Without `--bench` it runs in smoke mode on 20 cylinders and 5 copies.

#![expect(clippy::print_stdout, reason = "benchmark output")]

mod support;

use std::path::Path;

use geosnap::clock::MonotonicClock;
use geosnap::core::model::{
    run_steps, Companions, Document, Fit, GlobalSettings, Placed, Relation, SessionSettings,
};
use geosnap::core::primitive::{Cylinder, Feature, Primitive};
use geosnap::core::relation::{Mode, RelationKind};
use geosnap::io::script::load_script;
use geosnap::io::sketch_file::load_sketch;
use glam::DVec3;
use support::{timed, Bench, Rng, Table};

/// The relation kind of pair (i, j) in each model.
type Pattern = fn(usize, usize) -> RelationKind;

const MIXED: [RelationKind; 5] = [
    RelationKind::Parallel,
    RelationKind::Orthogonal,
    RelationKind::Coaxial,
    RelationKind::SameRadius,
    RelationKind::EqualLength,
];

const PATTERNS: [(&str, Pattern); 4] = [
    ("parallel", |_, _| RelationKind::Parallel),
    ("orthogonal", |_, _| RelationKind::Orthogonal),
    ("coaxial", |_, _| RelationKind::Coaxial),
    ("mixed", |i, j| MIXED[(i * 7 + j * 13) % MIXED.len()]),
];

/// `n` cylinders at random places and directions, every pair related as `pattern` says.
fn dense(n: usize, pattern: Pattern) -> Document {
    let mut rng = Rng::new(19);
    let mut doc = Document::new();
    let ids: Vec<_> = (0..n)
        .map(|_| {
            let axis = DVec3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            )
            .try_normalize()
            .unwrap_or(DVec3::Y);
            let center = DVec3::new(rng.uniform(0.0, 2000.0), rng.uniform(-2000.0, 0.0), 0.0);
            doc.add(Placed {
                primitive: Primitive::Cylinder(Cylinder {
                    center,
                    axis,
                    length: rng.uniform(50.0, 300.0),
                    radius: rng.uniform(10.0, 60.0),
                }),
                fit: Fit::default(),
            })
        })
        .collect();
    for i in 0..n {
        for j in i + 1..n {
            let kind = pattern(i, j);
            let features = if kind == RelationKind::EqualLength {
                vec![None, None]
            } else {
                vec![Some(Feature::Top), Some(Feature::Top)]
            };
            doc.add_relation(Relation {
                kind,
                members: vec![ids[i], ids[j]],
                features,
                mode: Mode::Hard,
                inferred: None,
            })
            .expect("the relation suits cylinders");
        }
    }
    doc
}

fn bench_dense(bench: &Bench) {
    let n = if bench.is_smoke() { 20 } else { 200 };
    let table = Table::new(
        &format!(
            "solve of {n} cylinders, all {} pairs related (every part free)",
            n * (n - 1) / 2
        ),
        12,
        &[
            ("implied", 8),
            ("conflicts", 9),
            ("solves", 6),
            ("result", 8),
        ],
    );
    for (name, pattern) in PATTERNS {
        if !bench.wants(name) {
            continue;
        }
        let model = dense(n, pattern);
        let mut last = None;
        let stats = bench.each(|_| {
            let mut doc = model.clone();
            let clock = MonotonicClock::start();
            let (outcome, time) = timed(|| {
                doc.solve(
                    None,
                    &GlobalSettings::default(),
                    Companions {
                        clock: Some(&clock),
                        ..Companions::default()
                    },
                )
            });
            last = Some(outcome);
            time
        });
        let outcome = last.expect("at least one sample");
        table.row(
            name,
            &stats,
            &[
                outcome.implied.to_string(),
                outcome.conflicts.len().to_string(),
                outcome.solves.to_string(),
                if outcome.reverted { "refused" } else { "kept" }.to_owned(),
            ],
        );
    }
}

fn bench_identical(bench: &Bench) {
    if !bench.wants("identical") {
        return;
    }
    let copies = if bench.is_smoke() { 5 } else { 40 };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("sketches");
    let script = load_script(root.join("box.script.json")).expect("the box script loads");
    let sketch = load_sketch(root.join("box.svg"))
        .expect("the box sketch loads")
        .sketch;
    let steps: Vec<_> = script.steps.iter().cycle().take(copies).cloned().collect();
    let table = Table::new(
        &format!("{copies} identical placements of sketches/box.svg (run_steps)"),
        12,
        &[("relations", 9)],
    );
    let mut relations = 0;
    let stats = bench.each(|_| {
        let clock = MonotonicClock::start();
        let ((doc, _), time) = timed(|| {
            run_steps(
                &sketch,
                &steps,
                &SessionSettings::default(),
                Companions {
                    clock: Some(&clock),
                    ..Companions::default()
                },
            )
        });
        relations = doc.relations().len();
        time
    });
    table.row("identical", &stats, &[relations.to_string()]);
}

fn main() {
    let bench = Bench::from_env();
    bench.print_intro("dense relations and identical placements (issue 19)");
    bench_dense(&bench);
    bench_identical(&bench);
}
