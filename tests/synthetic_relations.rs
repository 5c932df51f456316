//! Acceptance test of relation inference and the global solve on synthetic assemblies.
//!
//! For each kind of assembly (`support::assemblies`: coaxial stacks of cylinders and
//! cones, tables, balls with radial tubes, bricks with studs, boxes with orthogonal
//! pipes; mugs with a straight, L or U handle, pipes with T and L joints, plugs with
//! equal prongs on a face, trumpet-like rows of valves, menorahs, rows of equal boxes
//! touching face to face (drawers, books); and scenes of two or
//! three unrelated handles, tees, plugs, valve rows or menorahs side by side), random ground-truth
//! assemblies are drawn by the test renderer from random
//! designer's views with a random hand, and placed part by part by script steps with
//! perturbed poses (as in `synthetic_snap`: centre off by up to 15 % of the part's size,
//! axis by up to 15°, sizes by ±25 %) through [`run_steps`] with the default settings:
//! snap, infer relations on release, solve globally.
//!
//! # Matching the model to the truth
//!
//! An orthographic view does not show depth: the whole model may come out as the mirror
//! image of the truth in the view plane (the first part's mirror is a free choice; the
//! later ones follow it through their relations). The truth is mirrored (z ↦ −z) when
//! that matches the document's directions better, object by object in a scene (its
//! objects are unrelated, so each one's mirror is a free choice); a mirror leaves every
//! relation's ‖ψ‖ within an object unchanged. Each document part is then matched to its truth part (the step that
//! placed it), and each of its features to the truth feature whose normal is nearest (a
//! cylinder turned end for end swaps `top` and `bottom`; a box's faces are relabelled).
//!
//! # Measures
//!
//! - **Precision**: of the inferred relations in the final document whose mode is
//!   [`Mode::Hard`], the fraction that hold on the truth: ‖ψ‖ ≤ [`PRECISION_TOL`]
//!   evaluated with [`residuals`] on the matched truth parts and features.
//! - **Suggestions**: relations whose mode is neither hard nor off ([`is_suggestion`]:
//!   medium confidence, shown to the user, not enforced until accepted; today's soft
//!   mode and the suggested mode to come), counted apart from precision with how many
//!   of them hold on the truth (the same test).
//! - **Cross-object relations**: relations whose mode is not off between parts of
//!   different objects of a scene ([`Assembly::object`](support::assemblies::Assembly)):
//!   the objects are unrelated, so there must be none.
//! - **Recall**: of the designed relations, the fraction found directly or through an
//!   equivalent chain (legs 1 ∥ 2 and 2 ∥ 3 give 1 ∥ 3, coaxial gives parallel, …): the
//!   designed relation holds on the *solved* document (‖ψ‖ ≤ [`RECALL_TOL`], which only
//!   relations enforced by the solve reach; a snap alone is off by a degree or a percent)
//!   and every member takes part in some relation that is not off. A part whose step was
//!   skipped misses all its designed relations.
//! - **Recall with suggestions**: as the shared sketches count it (`tests/shared_intent.rs`:
//!   hard or an accepted suggestion), the fraction of the designed relations found, or
//!   missed with a suggestion of their kind between their parts that holds on the truth
//!   (one a user accepts with one click). Printed beside the recall, not asserted.
//! - **Improvement**: each part's errors against its truth after its own snap
//!   ([`StepOutcome::Placed`]`.snap`) and in the final document: the axis angle (up to
//!   the view's mirror and reversal; a box's worst axis), the mean relative error of its
//!   sizes (radii and length; a box's three sizes) and the projected centre distance
//!   relative to its size. The means and the improvement in % are printed.
//! - **Wrecked parts**: a fairly snapped part whose axis error grows by more than
//!   [`WRECK_AXIS`] or whose size error grows by more than [`WRECK_SIZE`] from its own
//!   snap to the final model.
//!
//! The steps run with a [`MonotonicClock`], as `geosnap run` does, so the global
//! solve's time cap (10 s per solve by default) holds.
//!
//! The test prints a table per kind and overall (hard relations and the ones that hold,
//! precision, designed and found, recall, suggestions and the ones that hold,
//! cross-object relations, conflicts, the errors), every wrong and missed relation,
//! wrong suggestion and cross-object relation with its case, kinds and features, and
//! asserts: overall precision ≥ [`REQUIRED_PRECISION`] (issue 17's), recall ≥
//! [`REQUIRED_RECALL`] (a floor under today's figure; issue 17's [`ISSUE_RECALL`] is
//! printed, met or not), no hard relation between objects (suggestions between them are
//! counted and printed) and no wrecked part. It is
//! deterministic: case `i` of a kind always draws the same assembly (the kinds added by
//! issue 17 come after the first five, whose cases are unchanged).
//!
//! The default run ([`DEFAULT_CASES`] per kind, one thread per kind) takes about as long
//! as the five kinds took at 12 cases each before issue 17 added six kinds; set
//! `GEOSNAP_SYNTH_ASSEMBLIES` for a run that judges inference on more cases.
//!
//! Environment (optional): `GEOSNAP_SYNTH_ASSEMBLIES` (cases per kind, default
//! [`DEFAULT_CASES`]), `GEOSNAP_SYNTH_ASSEMBLY_KINDS` (comma-separated kind names of
//! [`AssemblyKind::name`]: `stack`, `table`, `ball+tubes`, `brick+studs`, `box+pipes`,
//! `handle`, `tee`, `plug`, `valves`, `menorah`, `scene`, `drawers`; e.g. `handle,tee`),
//! `GEOSNAP_SYNTH_ASSEMBLY_SHOW`
//! (`name:case`, e.g. `table:3`: prints that case in detail: each part's truth, own snap
//! and final parameters and errors, the relations inferred on each release, the
//! conflicts), `GEOSNAP_SYNTH_ASSEMBLY_PNG` (a folder: the shown case's truth, own snaps
//! and final model drawn over its strokes, three PNGs), `GEOSNAP_SYNTH_ASSEMBLY_PROGRESS`
//! (prints each case's time to stderr as it ends).
//!
//! ```text
//! cargo test --no-default-features --release --test synthetic_relations -- --nocapture
//! ```

#![expect(clippy::print_stdout, reason = "the test prints its tables")]

mod support;

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::time::{Duration, Instant};

use geosnap::clock::MonotonicClock;
use geosnap::core::model::{run_steps, Document, PrimitiveId, SessionSettings, StepOutcome};
use geosnap::core::primitive::{Feature, FeatureCurve, FeatureGeometry, Primitive};
use geosnap::core::relation::{residuals, Member, Mode, RelationKind};
use geosnap::core::solve::SolveContext;
use glam::DVec3;
use support::assemblies::{assembly, AssemblyKind, Designed, PERMUTATIONS};
use support::synth::Rng;

/// Cases per kind unless `GEOSNAP_SYNTH_ASSEMBLIES` says otherwise: eleven kinds at 4
/// cost about what five kinds at 12 did (the new kinds have more parts).
const DEFAULT_CASES: usize = 4;
/// Largest ‖ψ‖ on the truth of an inferred relation that counts as correct.
const PRECISION_TOL: f64 = 0.02;
/// Largest ‖ψ‖ on the solved document of a designed relation that counts as found.
const RECALL_TOL: f64 = 5e-3;
/// A part whose axis error grows by more than this (degrees) from its own snap to the
/// final model, or whose mean size error grows by more than [`WRECK_SIZE`], was wrecked
/// by the solve: relations and the fits of other parts may move a part, but not turn a
/// fair snap into nonsense. A snap is fair when its own errors are within these
/// measures; a snap already nonsense is not counted (its relations are the snapping's
/// failure, counted in the recall).
const WRECK_AXIS: f64 = 15.0;
/// See [`WRECK_AXIS`] (a fraction: 0.5 is 50 percentage points).
const WRECK_SIZE: f64 = 0.5;
/// A case slower than this is named in the report.
const SLOW_CASE: Duration = Duration::from_secs(10);
/// The precision issue 17 asks for (over hard relations).
const REQUIRED_PRECISION: f64 = 0.95;
/// The recall issue 17 asks for; not met yet (0.811 at 4 cases per kind over the first
/// eleven kinds, 0.777 with the rows of drawers added: mostly parts whose own snap is
/// off: drawers hidden in part by their neighbours, plugs' blades, menorahs' arms, tees'
/// branches), so it is
/// printed, and [`REQUIRED_RECALL`] guards what is reached against going back.
const ISSUE_RECALL: f64 = 0.9;
/// The recall asserted: what inference reaches today at the default case count, less a
/// little (a floor against regressions, not the goal: see [`ISSUE_RECALL`]).
const REQUIRED_RECALL: f64 = 0.76;

/// The seed of case `index` of `kind`.
fn seed(kind: AssemblyKind, index: usize) -> u64 {
    let k = AssemblyKind::ALL
        .iter()
        .position(|x| *x == kind)
        .unwrap_or(0) as u64;
    0xA55E_0000 + 1000 * (k + 1) + index as u64
}

/// The mirror image of a direction through the view plane.
fn mirror(v: DVec3) -> DVec3 {
    DVec3::new(v.x, v.y, -v.z)
}

/// A part mirrored through the view plane z = 0 (the whole truth is mirrored at once, so
/// the parts keep their relations).
fn mirrored(p: &Primitive) -> Primitive {
    p.mirrored_in_depth()
        .transformed(DVec3::new(0.0, 0.0, -2.0 * p.center().z), 1.0)
}

/// The angle (degrees) between two lines.
fn line_angle(a: DVec3, b: DVec3) -> f64 {
    a.normalize()
        .dot(b.normalize())
        .abs()
        .min(1.0)
        .acos()
        .to_degrees()
}

/// The directions of a part: an axis, a box's three axes, none for a ball.
fn directions(p: &Primitive) -> Vec<DVec3> {
    match p {
        Primitive::Cylinder(c) => vec![c.axis],
        Primitive::Cone(c) => vec![c.axis],
        Primitive::Cuboid(b) => b.axes().to_vec(),
        _ => Vec::new(),
    }
}

/// How far the directions of `fit` are from those of `truth` (degrees, summed).
fn direction_mismatch(truth: &Primitive, fit: &Primitive) -> f64 {
    let t = directions(truth);
    directions(fit)
        .iter()
        .map(|f| {
            t.iter()
                .map(|d| line_angle(*d, *f))
                .fold(f64::INFINITY, f64::min)
        })
        .filter(|a| a.is_finite())
        .sum()
}

/// The unit normal of a feature.
fn normal(f: &FeatureCurve<f64>) -> DVec3 {
    match &f.geometry {
        FeatureGeometry::Circle { normal, .. } | FeatureGeometry::Rectangle { normal, .. } => {
            normal.to_dvec3()
        }
    }
}

/// The feature of `to` whose normal is nearest that of `from`'s feature `name`.
fn matching_feature(
    from: &[FeatureCurve<f64>],
    to: &[FeatureCurve<f64>],
    name: &str,
) -> Option<&'static str> {
    let n = normal(from.iter().find(|f| f.feature.name() == name)?);
    to.iter()
        .max_by(|a, b| n.dot(normal(a)).total_cmp(&n.dot(normal(b))))
        .map(|f| f.feature.name())
}

/// ‖ψ‖ of a relation over (features, feature name) members.
fn psi(kind: RelationKind, members: &[(&[FeatureCurve<f64>], Option<&str>)]) -> Option<f64> {
    let members: Vec<Member<'_, f64>> = members
        .iter()
        .map(|(features, feature)| Member {
            features,
            feature: feature.and_then(|name| {
                features
                    .iter()
                    .find(|f| f.feature.name() == name)
                    .map(|f| f.feature)
            }),
        })
        .collect();
    residuals(kind, &members)
        .ok()
        .map(|r| r.iter().map(|v| v * v).sum::<f64>().sqrt())
}

/// |fit − truth| / truth.
fn rel(fit: f64, truth: f64) -> f64 {
    (fit - truth).abs() / truth.abs()
}

/// A part's errors against its truth.
#[derive(Clone, Copy, Debug, Default)]
struct PartErrors {
    /// Axis angle in degrees (a box's worst axis; none for a ball).
    axis: Option<f64>,
    /// Mean relative error of the sizes.
    size: f64,
    /// Projected centre distance relative to the size.
    centre: f64,
}

/// The errors of `fit` against `truth`, up to the view's mirror and reversal.
fn part_errors(truth: &Primitive, fit: &Primitive) -> PartErrors {
    let centre = truth.center().truncate().distance(fit.center().truncate()) / truth.size();
    let mut e = PartErrors {
        centre,
        ..PartErrors::default()
    };
    // (angle, reversed) over the mirror and the two senses.
    let axis = support::judge::axis_error;
    match (truth, fit) {
        (Primitive::Cylinder(t), Primitive::Cylinder(f)) => {
            e.axis = Some(axis(t.axis, f.axis).0);
            e.size = f64::midpoint(rel(f.radius, t.radius), rel(f.length, t.length));
        }
        (Primitive::Cone(t), Primitive::Cone(f)) => {
            let (angle, reversed) = axis(t.axis, f.axis);
            let (rb, rt) = if reversed {
                (f.radius_top, f.radius_bottom)
            } else {
                (f.radius_bottom, f.radius_top)
            };
            e.axis = Some(angle);
            e.size =
                (rel(rb, t.radius_bottom) + rel(rt, t.radius_top) + rel(f.length, t.length)) / 3.0;
        }
        (Primitive::Sphere(t), Primitive::Sphere(f)) => e.size = rel(f.radius, t.radius),
        (Primitive::Cuboid(t), Primitive::Cuboid(f)) => {
            let (ta, fa) = (t.axes(), f.axes());
            let mut best = (f64::INFINITY, 0.0);
            for m in [false, true] {
                for p in PERMUTATIONS {
                    let fit_axis = |i: usize| if m { mirror(fa[i]) } else { fa[i] };
                    let angle = (0..3)
                        .map(|i| line_angle(fit_axis(i), ta[p[i]]))
                        .fold(0.0, f64::max);
                    if angle < best.0 {
                        let sizes = (0..3).map(|i| rel(f.size[i], t.size[p[i]])).sum::<f64>();
                        best = (angle, sizes / 3.0);
                    }
                }
            }
            e.axis = Some(best.0);
            e.size = best.1;
        }
        (t, f) => panic!("a {:?} snapped to a {:?}", t.kind(), f.kind()),
    }
    e
}

/// One assembly, run and judged.
#[derive(Debug, Default)]
struct CaseResult {
    /// Parts, and parts whose step was skipped.
    parts: usize,
    skipped: usize,
    /// Inferred hard relations, and those that hold on the truth.
    inferred: usize,
    correct: usize,
    /// Suggestions (relations neither hard nor off, see [`is_suggestion`]), and those
    /// that hold on the truth.
    suggested: usize,
    suggested_ok: usize,
    /// Hard (or soft) relations between parts of different objects of a scene, and
    /// suggestions between them.
    cross: usize,
    cross_suggested: usize,
    /// Designed relations, and those found.
    designed: usize,
    found: usize,
    /// Designed relations missed, with a suggestion of their kind between their parts
    /// that holds on the truth.
    suggested_instead: usize,
    /// The suggestions that hold on the truth, as (kind, sorted members).
    right_suggestions: BTreeSet<(&'static str, Vec<usize>)>,
    /// Relations switched off by the solve (conflicts), in words.
    conflicts: Vec<String>,
    /// Lines describing the wrong and the missed relations.
    report: Vec<String>,
    /// (own snap, final) errors per placed part.
    errors: Vec<(PartErrors, PartErrors)>,
    /// Parts the solve took far from the truth, away from their own snap (see
    /// [`WRECK_AXIS`]).
    wrecked: usize,
    /// Inferred hard relations by kind: (inferred, correct).
    by_kind: BTreeMap<&'static str, (usize, usize)>,
    /// As `by_kind`, for the suggestions.
    suggested_by_kind: BTreeMap<&'static str, (usize, usize)>,
    elapsed: Duration,
}

/// A relation's members as `part:feature` words.
fn members_text(members: &[usize], features: &[Option<&str>]) -> String {
    members
        .iter()
        .zip(features)
        .map(|(m, f)| format!("{m}:{}", f.unwrap_or("solid")))
        .collect::<Vec<_>>()
        .join(", ")
}

fn run_case(kind: AssemblyKind, index: usize, show: bool) -> CaseResult {
    let start = Instant::now();
    let seed = seed(kind, index);
    let a = assembly(kind, seed);
    let sketch = a.sketch();
    let steps = a.steps(&mut Rng::new(seed ^ 0xD80F_D80F));
    // A clock, as the command line gives one: the solver's time cap holds only with one.
    let clock = MonotonicClock::start();
    let (doc, outcomes) = run_steps(
        &sketch,
        &steps,
        &SessionSettings::default(),
        SolveContext::default().with_clock(&clock),
    );
    let mut out = CaseResult {
        parts: a.parts.len(),
        designed: a.designed.len(),
        ..CaseResult::default()
    };
    let tag = format!("{} #{index} (seed {seed:#x})", kind.name());
    // Part index ↔ document id, and the own snaps.
    let mut id_of: BTreeMap<usize, PrimitiveId> = BTreeMap::new();
    let mut snapped: BTreeMap<usize, Primitive> = BTreeMap::new();
    for (i, o) in outcomes.iter().enumerate() {
        match o {
            StepOutcome::Placed {
                id, snap, solve, ..
            } => {
                id_of.insert(i, *id);
                snapped.insert(i, snap.primitive.clone());
                out.conflicts.extend(
                    solve
                        .conflicts
                        .iter()
                        .map(|c| format!("{tag}: {}", c.message)),
                );
            }
            StepOutcome::Skipped(s) | StepOutcome::Refused { skipped: s, .. } => {
                out.skipped += 1;
                out.report
                    .push(format!("{tag}: step {i} skipped: {}", s.reason));
            }
        }
    }
    let index_of: BTreeMap<PrimitiveId, usize> = id_of.iter().map(|(i, id)| (*id, *i)).collect();
    if show {
        out.report
            .extend(explain(&a.parts, &doc, &outcomes, &index_of, &tag));
        out.report.extend(write_overlays(
            &sketch, &doc, &outcomes, &a.parts, kind, index,
        ));
    }
    let fitted = |i: usize| doc.get(id_of[&i]).map(|p| &p.primitive);
    let truth = matched_truth(&a.parts, &a.object, &|i| {
        id_of
            .get(&i)
            .and_then(|id| doc.get(*id))
            .map(|p| p.primitive.clone())
    });
    let truth_features: Vec<Vec<FeatureCurve<f64>>> =
        truth.iter().map(|p| p.current_shape().features).collect();
    let doc_features: BTreeMap<usize, Vec<FeatureCurve<f64>>> = id_of
        .keys()
        .filter_map(|&i| Some((i, fitted(i)?.current_shape().features)))
        .collect();
    precision(
        &doc,
        &index_of,
        &a.object,
        &truth_features,
        &doc_features,
        &tag,
        &mut out,
    );
    recall(
        &a.designed,
        &doc,
        &index_of,
        &truth_features,
        &doc_features,
        &tag,
        &mut out,
    );
    for (i, own) in &snapped {
        if let Some(fin) = fitted(*i) {
            judge_part(
                &a.parts[*i],
                own,
                fin,
                &format!("{tag}: part {i}"),
                &mut out,
            );
        }
    }
    out.elapsed = start.elapsed();
    out
}

/// The truth `parts`, each object (`object` per part) mirrored when the document shows
/// its mirror image (the objects of a scene are unrelated: each one's mirror is a free
/// choice). `fitted` gives the document's part of each placed truth part.
fn matched_truth(
    parts: &[Primitive],
    object: &[usize],
    fitted: &dyn Fn(usize) -> Option<Primitive>,
) -> Vec<Primitive> {
    let score = |truth: &[Primitive], o: usize| -> f64 {
        (0..parts.len())
            .filter(|&i| object[i] == o)
            .filter_map(|i| Some(direction_mismatch(&truth[i], &fitted(i)?)))
            .sum()
    };
    let mirror_truth: Vec<Primitive> = parts.iter().map(mirrored).collect();
    let flipped: BTreeSet<usize> = object
        .iter()
        .copied()
        .filter(|&o| score(&mirror_truth, o) < score(parts, o))
        .collect();
    parts
        .iter()
        .zip(&mirror_truth)
        .zip(object)
        .map(|((p, m), o)| if flipped.contains(o) { m } else { p }.clone())
        .collect()
}

/// Writes the overlays of a shown case into the folder `GEOSNAP_SYNTH_ASSEMBLY_PNG`
/// names, if it is set: the truth, the own snaps and the final model over the strokes.
/// Returns what went wrong, if anything.
fn write_overlays(
    sketch: &geosnap::core::sketch::Sketch,
    doc: &Document,
    outcomes: &[StepOutcome],
    truth: &[Primitive],
    kind: AssemblyKind,
    index: usize,
) -> Vec<String> {
    use geosnap::io::overlay::{overlay_png, OverlayItem, OverlayRelation};
    let Some(folder) = std::env::var_os("GEOSNAP_SYNTH_ASSEMBLY_PNG") else {
        return Vec::new();
    };
    let folder = std::path::PathBuf::from(folder);
    let snaps: Vec<(Primitive, Vec<geosnap::core::sketch::StrokeId>)> = outcomes
        .iter()
        .filter_map(|o| match o {
            StepOutcome::Placed { snap, .. } => {
                Some((snap.primitive.clone(), snap.assignment.stroke_ids()))
            }
            StepOutcome::Skipped(_) | StepOutcome::Refused { .. } => None,
        })
        .collect();
    let finals: Vec<(Primitive, Vec<geosnap::core::sketch::StrokeId>)> = doc
        .primitives()
        .map(|(_, p)| (p.primitive.clone(), p.fit.strokes.clone()))
        .collect();
    let truths: Vec<(Primitive, Vec<geosnap::core::sketch::StrokeId>)> =
        truth.iter().map(|p| (p.clone(), Vec::new())).collect();
    let mut problems = Vec::new();
    for (name, parts, relations) in [
        ("truth", &truths, Vec::new()),
        ("snap", &snaps, Vec::new()),
        ("final", &finals, OverlayRelation::of_document(doc)),
    ] {
        let items: Vec<OverlayItem<'_>> = parts
            .iter()
            .map(|(p, s)| OverlayItem {
                primitive: p,
                strokes: s,
            })
            .collect();
        let path = folder.join(format!("assembly_{}_{index}_{name}.png", kind.name()));
        match overlay_png(sketch, &items, &relations) {
            Ok(bytes) => {
                if let Err(e) = std::fs::write(&path, bytes) {
                    problems.push(format!("{}: {e}", path.display()));
                }
            }
            Err(e) => problems.push(format!("{}: {e}", path.display())),
        }
    }
    problems
}

/// Records a part's errors against its `truth` after its own snap and in the final
/// model, and whether the solve wrecked it (see [`WRECK_AXIS`]).
fn judge_part(
    truth: &Primitive,
    own: &Primitive,
    fin: &Primitive,
    tag: &str,
    out: &mut CaseResult,
) {
    let (own, fin) = (part_errors(truth, own), part_errors(truth, fin));
    // Only a fair snap can be wrecked: one already off by more than the wreck's own
    // measures (a part snapped across its neighbours, 4 times too big) is not.
    let fair = own.axis.unwrap_or(0.0) <= WRECK_AXIS && own.size <= WRECK_SIZE;
    let turned = fin.axis.unwrap_or(0.0) - own.axis.unwrap_or(0.0);
    if fair && (turned > WRECK_AXIS || fin.size - own.size > WRECK_SIZE) {
        out.wrecked += 1;
        out.report.push(format!(
            "{tag} WRECKED: axis error {:.1}° → {:.1}°, size error {:.1} % → {:.1} %",
            own.axis.unwrap_or(0.0),
            fin.axis.unwrap_or(0.0),
            100.0 * own.size,
            100.0 * fin.size
        ));
    }
    out.errors.push((own, fin));
}

/// A case in detail: each part's truth, own snap and final pose, the relations inferred
/// on each release and the conflicts.
fn explain(
    truth: &[Primitive],
    doc: &Document,
    outcomes: &[StepOutcome],
    index_of: &BTreeMap<PrimitiveId, usize>,
    tag: &str,
) -> Vec<String> {
    let mut lines = vec![format!("{tag}: in detail")];
    for (i, o) in outcomes.iter().enumerate() {
        let StepOutcome::Placed {
            id,
            snap,
            confidence,
            relations,
            solve,
            ..
        } = o
        else {
            continue;
        };
        let fin = doc.get(*id).map(|p| &p.primitive);
        let (own, end) = (
            part_errors(&truth[i], &snap.primitive),
            fin.map(|f| part_errors(&truth[i], f)).unwrap_or_default(),
        );
        lines.push(format!(
            "    part {i} {}: truth {:?}\n      snap (axis {:.1}°, size {:.1} %, centre {:.1} %; {} {:.2}{}) \
             {:?}\n      final (axis {:.1}°, size {:.1} %, centre {:.1} %) {:?}",
            truth[i].kind().name(),
            truth[i].params(),
            own.axis.unwrap_or(0.0),
            100.0 * own.size,
            100.0 * own.centre,
            confidence.verdict,
            confidence.value,
            confidence
                .reason
                .as_ref()
                .map_or_else(String::new, |r| format!(": {r}")),
            snap.primitive.params(),
            end.axis.unwrap_or(0.0),
            100.0 * end.size,
            100.0 * end.centre,
            fin.map(Primitive::params),
        ));
        for &r in relations {
            let r = doc.relation(r).expect("an inferred relation");
            let parts: Vec<usize> = r.members.iter().map(|m| index_of[m]).collect();
            let names: Vec<Option<&str>> =
                r.features.iter().map(|f| f.map(Feature::name)).collect();
            lines.push(format!(
                "      inferred {} [{}] ({:?})",
                r.kind.name(),
                members_text(&parts, &names),
                r.mode
            ));
        }
        for c in &solve.conflicts {
            lines.push(format!("      conflict: {}", c.message));
        }
        if let Some(r) = &solve.report {
            lines.push(format!(
                "      solve of {} parts: {:?}, {} evaluations, |c| {:.1e}{}",
                solve.solved.len(),
                r.termination,
                r.evaluations,
                r.max_violation,
                if solve.reverted { ", reverted" } else { "" }
            ));
        }
    }
    lines
}

/// Whether a relation in `mode` is a suggestion: shown to the user, not enforced until
/// accepted (any mode but hard and off; written so that modes added later count).
fn is_suggestion(mode: Mode) -> bool {
    mode != Mode::Hard && mode != Mode::Off
}

/// Judges every inferred relation that is not off on the matched truth: the hard ones
/// for precision, the suggestions apart, and counts those between parts of different
/// objects (`object` per part).
fn precision(
    doc: &Document,
    index_of: &BTreeMap<PrimitiveId, usize>,
    object: &[usize],
    truth_features: &[Vec<FeatureCurve<f64>>],
    doc_features: &BTreeMap<usize, Vec<FeatureCurve<f64>>>,
    tag: &str,
    out: &mut CaseResult,
) {
    for r in doc.relations().iter().filter(|r| r.mode != Mode::Off) {
        let parts: Vec<usize> = r.members.iter().map(|m| index_of[m]).collect();
        let doc_names: Vec<Option<&str>> = (0..parts.len())
            .map(|k| r.features.get(k).copied().flatten().map(Feature::name))
            .collect();
        let truth_names: Vec<Option<&str>> = parts
            .iter()
            .zip(&doc_names)
            .map(|(&i, name)| {
                name.and_then(|n| matching_feature(&doc_features[&i], &truth_features[i], n))
            })
            .collect();
        let members: Vec<(&[FeatureCurve<f64>], Option<&str>)> = parts
            .iter()
            .zip(&truth_names)
            .map(|(&i, n)| (truth_features[i].as_slice(), *n))
            .collect();
        let value = psi(r.kind, &members);
        let ok = value.is_some_and(|v| v <= PRECISION_TOL);
        let what = || {
            format!(
                "{} [{}] ({:?}; truth features [{}]): ‖ψ‖ on the truth {}",
                r.kind.name(),
                members_text(&parts, &doc_names),
                r.mode,
                members_text(&parts, &truth_names),
                value.map_or_else(|| "n/a".to_owned(), |v| format!("{v:.3}")),
            )
        };
        let objects: BTreeSet<usize> = parts.iter().map(|&i| object[i]).collect();
        if objects.len() > 1 {
            if is_suggestion(r.mode) {
                out.cross_suggested += 1;
            } else {
                out.cross += 1;
            }
            out.report.push(format!(
                "{tag}: CROSS-OBJECT (objects {objects:?}) {}",
                what()
            ));
        }
        if is_suggestion(r.mode) {
            out.suggested += 1;
            let entry = out.suggested_by_kind.entry(r.kind.name()).or_default();
            entry.0 += 1;
            if ok {
                out.suggested_ok += 1;
                entry.1 += 1;
                let mut members = parts.clone();
                members.sort_unstable();
                out.right_suggestions.insert((r.kind.name(), members));
            } else {
                out.report
                    .push(format!("{tag}: WRONG SUGGESTION {}", what()));
            }
            continue;
        }
        out.inferred += 1;
        let entry = out.by_kind.entry(r.kind.name()).or_default();
        entry.0 += 1;
        if ok {
            out.correct += 1;
            entry.1 += 1;
        } else {
            out.report.push(format!("{tag}: WRONG {}", what()));
        }
    }
}

/// Looks for every designed relation in the solved document.
fn recall(
    designed: &[Designed],
    doc: &Document,
    index_of: &BTreeMap<PrimitiveId, usize>,
    truth_features: &[Vec<FeatureCurve<f64>>],
    doc_features: &BTreeMap<usize, Vec<FeatureCurve<f64>>>,
    tag: &str,
    out: &mut CaseResult,
) {
    let related: BTreeSet<usize> = doc
        .relations()
        .iter()
        .filter(|r| r.mode != Mode::Off)
        .flat_map(|r| r.members.iter().map(|m| index_of[m]))
        .collect();
    for d in designed {
        let what = format!(
            "{} [{}]",
            d.kind.name(),
            members_text(&d.members, &d.features)
        );
        if let Some(missing) = d.members.iter().find(|m| !doc_features.contains_key(m)) {
            out.report.push(format!(
                "{tag}: MISSED {what}: part {missing} was not placed"
            ));
            continue;
        }
        let doc_names: Vec<Option<&str>> = d
            .members
            .iter()
            .zip(&d.features)
            .map(|(&i, name)| {
                name.and_then(|n| matching_feature(&truth_features[i], &doc_features[&i], n))
            })
            .collect();
        let members: Vec<(&[FeatureCurve<f64>], Option<&str>)> = d
            .members
            .iter()
            .zip(&doc_names)
            .map(|(i, n)| (doc_features[i].as_slice(), *n))
            .collect();
        let value = psi(d.kind, &members);
        let holds = value.is_some_and(|v| v <= RECALL_TOL);
        let unrelated: Vec<usize> = d
            .members
            .iter()
            .copied()
            .filter(|m| !related.contains(m))
            .collect();
        let mut members = d.members.clone();
        members.sort_unstable();
        if holds && unrelated.is_empty() {
            out.found += 1;
        } else {
            if out.right_suggestions.contains(&(d.kind.name(), members)) {
                out.suggested_instead += 1;
            }
            out.report.push(format!(
                "{tag}: MISSED {what} (document features [{}]): ‖ψ‖ on the solved model {}{}",
                members_text(&d.members, &doc_names),
                value.map_or_else(|| "n/a".to_owned(), |v| format!("{v:.4}")),
                if unrelated.is_empty() {
                    String::new()
                } else {
                    format!(", parts {unrelated:?} in no relation")
                }
            ));
        }
    }
}

/// Adds the counts by relation kind `from` into `into`.
fn add_counts(
    into: &mut BTreeMap<&'static str, (usize, usize)>,
    from: &BTreeMap<&'static str, (usize, usize)>,
) {
    for (k, (n, ok)) in from {
        let e = into.entry(k).or_default();
        e.0 += n;
        e.1 += ok;
    }
}

/// Counts by relation kind, (relations, right ones), as "parallel 12/13, …".
fn kinds_text(counts: &BTreeMap<&'static str, (usize, usize)>) -> String {
    counts
        .iter()
        .map(|(k, (n, ok))| format!("{k} {ok}/{n}"))
        .collect::<Vec<String>>()
        .join(", ")
}

/// Sums of a set of cases.
#[derive(Debug, Default)]
struct Totals {
    cases: usize,
    parts: usize,
    skipped: usize,
    inferred: usize,
    correct: usize,
    suggested: usize,
    suggested_ok: usize,
    cross: usize,
    cross_suggested: usize,
    designed: usize,
    found: usize,
    suggested_instead: usize,
    conflicts: usize,
    /// Sums over parts: (snap, final) axis (with its count), size, centre.
    axis: (f64, f64, usize),
    size: (f64, f64),
    centre: (f64, f64),
    errors: usize,
    wrecked: usize,
    by_kind: BTreeMap<&'static str, (usize, usize)>,
    /// As `by_kind`, for the suggestions.
    suggested_by_kind: BTreeMap<&'static str, (usize, usize)>,
    wall: Duration,
}

impl Totals {
    fn add(&mut self, c: &CaseResult) {
        self.cases += 1;
        self.parts += c.parts;
        self.skipped += c.skipped;
        self.inferred += c.inferred;
        self.correct += c.correct;
        self.suggested += c.suggested;
        self.suggested_ok += c.suggested_ok;
        self.cross += c.cross;
        self.cross_suggested += c.cross_suggested;
        self.designed += c.designed;
        self.found += c.found;
        self.suggested_instead += c.suggested_instead;
        self.conflicts += c.conflicts.len();
        self.wrecked += c.wrecked;
        for (own, fin) in &c.errors {
            if let (Some(a), Some(b)) = (own.axis, fin.axis) {
                self.axis.0 += a;
                self.axis.1 += b;
                self.axis.2 += 1;
            }
            self.size.0 += own.size;
            self.size.1 += fin.size;
            self.centre.0 += own.centre;
            self.centre.1 += fin.centre;
            self.errors += 1;
        }
        add_counts(&mut self.by_kind, &c.by_kind);
        add_counts(&mut self.suggested_by_kind, &c.suggested_by_kind);
    }

    fn merge(&mut self, o: &Self) {
        self.cases += o.cases;
        self.parts += o.parts;
        self.skipped += o.skipped;
        self.inferred += o.inferred;
        self.correct += o.correct;
        self.suggested += o.suggested;
        self.suggested_ok += o.suggested_ok;
        self.cross += o.cross;
        self.cross_suggested += o.cross_suggested;
        self.designed += o.designed;
        self.found += o.found;
        self.suggested_instead += o.suggested_instead;
        self.conflicts += o.conflicts;
        self.wrecked += o.wrecked;
        self.axis.0 += o.axis.0;
        self.axis.1 += o.axis.1;
        self.axis.2 += o.axis.2;
        self.size.0 += o.size.0;
        self.size.1 += o.size.1;
        self.centre.0 += o.centre.0;
        self.centre.1 += o.centre.1;
        self.errors += o.errors;
        add_counts(&mut self.by_kind, &o.by_kind);
        add_counts(&mut self.suggested_by_kind, &o.suggested_by_kind);
        self.wall = self.wall.max(o.wall);
    }

    fn precision(&self) -> f64 {
        if self.inferred == 0 {
            1.0
        } else {
            self.correct as f64 / self.inferred as f64
        }
    }

    fn recall(&self) -> f64 {
        if self.designed == 0 {
            1.0
        } else {
            self.found as f64 / self.designed as f64
        }
    }

    /// The recall with the right suggestions accepted (module docs).
    fn recall_with_suggestions(&self) -> f64 {
        if self.designed == 0 {
            1.0
        } else {
            (self.found + self.suggested_instead) as f64 / self.designed as f64
        }
    }

    /// "snap → final (improvement %)" of a pair of error sums over `n` parts.
    fn improvement(snap: f64, fin: f64, n: usize, scale: f64, unit: &str) -> String {
        let n = n.max(1) as f64;
        let (s, f) = (scale * snap / n, scale * fin / n);
        let gain = if s > 0.0 { 100.0 * (s - f) / s } else { 0.0 };
        format!("{s:5.2}{unit} → {f:5.2}{unit} ({gain:+4.0} %)")
    }

    fn row(&self, name: &str) -> String {
        format!(
            "{name:<12}{:>6}{:>7}{:>5}{:>6}{:>6}{:>8.3}{:>6}{:>6}{:>8.3}{:>6}{:>6}{:>6}{:>6}  {}  {}  {}  {:>6.1} s",
            self.cases,
            self.parts,
            self.skipped,
            self.inferred,
            self.correct,
            self.precision(),
            self.designed,
            self.found,
            self.recall(),
            self.suggested,
            self.suggested_ok,
            self.cross,
            self.conflicts,
            Self::improvement(self.axis.0, self.axis.1, self.axis.2, 1.0, "°"),
            Self::improvement(self.size.0, self.size.1, self.errors, 100.0, "%"),
            Self::improvement(self.centre.0, self.centre.1, self.errors, 100.0, "%"),
            self.wall.as_secs_f64(),
        )
    }
}

/// Runs `cases` assemblies of `kind`: their totals and the lines about what went wrong.
fn run_kind(kind: AssemblyKind, cases: usize, show: Option<usize>) -> (Totals, Vec<String>) {
    let start = Instant::now();
    let mut totals = Totals::default();
    let mut lines = Vec::new();
    for index in 0..cases {
        let c = run_case(kind, index, show == Some(index));
        if c.elapsed > SLOW_CASE {
            lines.push(format!(
                "{} #{index} (seed {:#x}): SLOW, {:.1} s",
                kind.name(),
                seed(kind, index),
                c.elapsed.as_secs_f64()
            ));
        }
        if std::env::var_os("GEOSNAP_SYNTH_ASSEMBLY_PROGRESS").is_some() {
            eprintln!("{} #{index}: {:.1} s", kind.name(), c.elapsed.as_secs_f64());
        }
        totals.add(&c);
        lines.extend(c.report.iter().cloned());
        lines.extend(c.conflicts.iter().map(|m| format!("conflict: {m}")));
    }
    totals.wall = start.elapsed();
    (totals, lines)
}

/// The title and column header of the table.
fn header(cases: usize, wall: Duration) -> String {
    let mut table = String::new();
    let _ = writeln!(
        table,
        "synthetic assemblies: {cases} cases per kind, {:.1} s wall\n\
         infer = hard relations in the final model, ok = those holding on the truth\n\
         (‖ψ‖ ≤ {PRECISION_TOL}); sugg = suggestions (neither hard nor off), s-ok = those\n\
         holding on the truth; cross = relations not off between different objects of a\n\
         scene; designed = relations the assembly was built with, found =\n\
         holding on the solved model (‖ψ‖ ≤ {RECALL_TOL}) with every member related; skip =\n\
         steps skipped; confl = relations switched off by conflicts; errors per part as\n\
         own snap → final model (improvement): axis angle, mean relative size error,\n\
         projected centre error relative to the size",
        wall.as_secs_f64()
    );
    let _ = writeln!(
        table,
        "{:<12}{:>6}{:>7}{:>5}{:>6}{:>6}{:>8}{:>6}{:>6}{:>8}{:>6}{:>6}{:>6}{:>6}  {:<29}  {:<29}  {:<29}  {:>8}",
        "assembly",
        "cases",
        "parts",
        "skip",
        "infer",
        "ok",
        "prec",
        "dsgn",
        "found",
        "recall",
        "sugg",
        "s-ok",
        "cross",
        "confl",
        "axis",
        "size",
        "centre",
        "time"
    );
    table
}

/// The lines under the table: relations holding on the truth by kind, the recall with
/// the right suggestions accepted, cross-object suggestions and wrecked parts.
fn summary(all: &Totals) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "hard relations holding on the truth, by kind: {}",
        kinds_text(&all.by_kind)
    );
    let _ = writeln!(
        out,
        "suggestions holding on the truth, by kind: {}",
        kinds_text(&all.suggested_by_kind)
    );
    let _ = writeln!(
        out,
        "recall with the right suggestions accepted (hard, or a right suggestion of the \
         kind between the parts, as on the shared sketches): {:.3} ({} more)",
        all.recall_with_suggestions(),
        all.suggested_instead
    );
    let _ = writeln!(
        out,
        "suggestions between parts of different objects (not enforced): {}",
        all.cross_suggested
    );
    let _ = writeln!(
        out,
        "parts the solve took far from their own snap (axis +{WRECK_AXIS}°, sizes +{} %): {}",
        100.0 * WRECK_SIZE,
        all.wrecked
    );
    out
}

#[test]
fn relations_of_synthetic_assemblies_are_found_and_improve_the_fit() {
    let cases = std::env::var("GEOSNAP_SYNTH_ASSEMBLIES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    let only: Option<Vec<String>> = std::env::var("GEOSNAP_SYNTH_ASSEMBLY_KINDS")
        .ok()
        .map(|v| v.split(',').map(|k| k.trim().to_owned()).collect());
    let kinds: Vec<AssemblyKind> = AssemblyKind::ALL
        .into_iter()
        .filter(|k| {
            only.as_ref()
                .is_none_or(|o| o.iter().any(|n| n == k.name()))
        })
        .collect();
    let show: Option<(String, usize)> =
        std::env::var("GEOSNAP_SYNTH_ASSEMBLY_SHOW")
            .ok()
            .and_then(|v| {
                let (k, i) = v.rsplit_once(':')?;
                Some((k.to_owned(), i.parse().ok()?))
            });
    let start = Instant::now();
    // One thread per kind: the kinds are independent and each is deterministic.
    let results: Vec<(AssemblyKind, Totals, Vec<String>)> = std::thread::scope(|scope| {
        let handles: Vec<_> = kinds
            .iter()
            .map(|&kind| {
                let show = &show;
                std::thread::Builder::new()
                    .name(format!("assembly-{}", kind.name()))
                    .spawn_scoped(scope, move || {
                        let show = show.as_ref().filter(|(k, _)| k == kind.name());
                        let (t, lines) = run_kind(kind, cases, show.map(|(_, i)| *i));
                        (kind, t, lines)
                    })
                    .expect("a thread")
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a kind's thread does not panic"))
            .collect()
    });
    let mut table = header(cases, start.elapsed());
    let mut all = Totals::default();
    let mut details = String::new();
    for (kind, totals, lines) in &results {
        let _ = writeln!(table, "{}", totals.row(kind.name()));
        all.merge(totals);
        if !lines.is_empty() {
            let _ = writeln!(details, "{}:", kind.name());
            for l in lines {
                let _ = writeln!(details, "  {l}");
            }
        }
    }
    let _ = writeln!(table, "{}", all.row("overall"));
    table.push_str(&summary(&all));
    println!("{table}\nwrong, missed, skipped, cross-object and conflicts:\n{details}");
    assert_eq!(
        all.wrecked, 0,
        "the solve wrecked parts that snapped fairly (named WRECKED above)"
    );
    assert_eq!(
        all.cross, 0,
        "hard relations between parts of different objects of a scene (named CROSS-OBJECT above)"
    );
    let met = all.precision() >= REQUIRED_PRECISION && all.recall() >= ISSUE_RECALL;
    println!("issue 17's precision ≥ {REQUIRED_PRECISION} and recall ≥ {ISSUE_RECALL} met: {met}");
    assert!(
        all.precision() >= REQUIRED_PRECISION && all.recall() >= REQUIRED_RECALL,
        "overall precision {:.3} (required {REQUIRED_PRECISION}) and recall {:.3} (required \
         {REQUIRED_RECALL}); the table and the wrong and missed relations are printed above",
        all.precision(),
        all.recall()
    );
}
