//! Snapping under the drawing conditions of issue 16: other hands, other shapes, other
//! views, and the classes from the automatic classifier.
//!
//! `synthetic_snap` draws kind shapes from a designer's view and hands the snapper the
//! renderer's true stroke classes. Here every case is drawn by the conditioned renderer
//! (`support::synth::scene_with`, module docs "Conditions"): the wider variety of shapes
//! (cylinders of length over radius 0.1–20, thin discs to rods; boxes from cubes to 1:15
//! slabs and planks; C and S spined, flared bent tubes), under each [`Condition`] (plain;
//! near-axial and side-on views; 20–60 % of a silhouette missing; large overshoots and
//! gaps; sketchy doubled lines; U and L strokes joined across corners; lines in short
//! fragments; end ellipses slanted by the hand), with hidden lines in every odd case (half of the scenes). The strokes
//! become a [`Sketch`] without classes, and [`SnapContext::from_sketch`] preprocesses and
//! classifies them as the app does. Each primitive is then dropped off its truth by
//! [`Perturbation::ISSUE_16`] (centre by up to 10 % of its size, axis by up to 10°, each
//! size by ±25 %; `support::assemblies::perturbed_placement`) and snapped with
//! [`snap`] and the default settings.
//!
//! The assemblies section does the same for every part of each assembly kind
//! (`support::assemblies::assembly_with`: stacks, tables with thin disc or slab tops on
//! rod legs, balls with tubes, bricks with studs, boxes with pipes; in the acceptance
//! run also the objects of issue 17, [`ACCEPTANCE_KINDS`]: handles, tees, plugs, valve
//! rows, menorahs and rows of drawers or books, whose parts hide or share pieces of one
//! another), all parts drawn together
//! in one view under the same condition and snapped one by one among the clutter of the
//! others' strokes, the parts before each placed where they truly lie, as a designer who
//! drops the parts in order and puts each wrong snap right has them (the snap gives up a
//! reading that holds a placed part or reads one again, `SnapContext::with_placed`).
//! `GEOSNAP_SYNTH_CONDITION_PLACED=snapped` places the snaps as they came out instead,
//! wrong or not (but for refused ones), owning the strokes they took, as `geosnap run`
//! builds its model; `none` snaps each part with none placed;
//! `GEOSNAP_SYNTH_CONDITION_ORDER=shuffled` drops an assembly's parts in an order shuffled
//! by the drawing's seed (a designer who starts with a leg or a middle drawer).
//!
//! A case is judged as `synthetic_snap` judges it (`support::judge`: centre within 3 % of
//! the size, axis within 5°, radii and lengths within 7 %). For a failed case the snap is
//! also started from the truth itself: a failure that persists there is the drawing's or
//! the objective's, not the search's ("truth" column). A failed snap whose projected
//! curves lie within 1 % of the size of the truth's draws the same picture
//! (`support::judge::picture_difference`, "same" column): it reads the strokes right,
//! and what fails is what the drawing leaves open (the depth of a bent tube whose ends
//! are nearly edge-on). A snap from the truth can fail for that reason too, so "truth"
//! counts search failures among its drawing's limits; "same" tells them apart.
//!
//! The table has one row per kind, per condition, with and without hidden lines, per
//! assembly kind and per condition among the assemblies: cases, successes, rate, the
//! failures that persist from the truth, those that draw the truth's picture, the share of strokes the classifier gave
//! another class than the renderer drew them with (joined strokes have no single class
//! and are left out), and the most common failed criteria. A matrix of rates per kind
//! and condition follows.
//!
//! Two tests:
//! - [`conditions_meet_the_issue_targets`] (ignored: today's snapper does not meet them)
//!   asserts exactly the issue's targets: ≥ 95 % per kind and per assembly kind, ≥ 90 %
//!   per condition (single primitives and assemblies).
//! - [`conditions_stay_above_todays_floor`] runs [`FLOOR_CASES`] cases per kind and
//!   condition and [`FLOOR_ASSEMBLIES`] assemblies per kind and condition, and asserts
//!   the regression floors ([`KIND_FLOOR`], [`CONDITION_FLOOR`], [`ASSEMBLY_FLOOR`],
//!   [`ASSEMBLY_CONDITION_FLOOR`]): today's rates minus a few points.
//!
//! Both are deterministic.
//!
//! Environment (all optional): `GEOSNAP_SYNTH_CONDITION_CASES` (cases per kind and
//! condition of the acceptance run, default [`ACCEPTANCE_CASES`]);
//! `GEOSNAP_SYNTH_CONDITION_ASSEMBLIES` (assemblies per kind and condition of the
//! acceptance run, default [`ACCEPTANCE_ASSEMBLIES`]); `GEOSNAP_SYNTH_CONDITION_PNG` (a
//! folder: an overlay PNG of every failed case, strokes grey, truth green, dropped blue,
//! snapped red); `GEOSNAP_SYNTH_CONDITION_LIST` (set: prints one line per failed case,
//! with its snap's verdict, the reason when it is not good, the evidence, and its first
//! three other readings, each with its RMS, what it explains beside what the snap
//! explains, and whether it is the truth);
//! `GEOSNAP_SYNTH_CONDITION_ALL` (set, with `GEOSNAP_SYNTH_CONDITION_LIST`: lists every
//! case, recovered or not, each with its confidence and evidence, to weigh the
//! evidence against the outcomes); `GEOSNAP_SYNTH_CONDITION_PROGRESS` (set: prints each drawing to stderr as it starts
//! and ends); `GEOSNAP_SYNTH_CONDITION_ONLY` (comma-separated kind, assembly kind and
//! condition names: runs only those drawings, for example `sgc,table,near-axial`; the
//! floors and targets still apply to what ran);
//! `GEOSNAP_SYNTH_CONDITION_HAND` (a factor: every error of the hand that places a
//! point, its jitter, wobble, over- and undershoots, a closed stroke's miss and drift,
//! scaled by it; `0` draws the ideal curves under the same conditions, which tells the
//! failures the hand's noise causes from those the snapper causes; the same shapes,
//! views and drops);
//! `GEOSNAP_SYNTH_CONDITION_SHOW` (`kind:condition:case`, for example
//! `cylinder:joined:3` or `table:side-on:1`: runs only that case, prints its analysis,
//! every part of an assembly, with the strokes each projected curve took in the snap
//! from the drop and in the snap from the truth, and writes its PNGs, failed or not, to
//! the PNG folder or the temporary folder).
//!
//! ```text
//! GEOSNAP_SYNTH_CONDITION_PNG=/tmp/cond cargo test --release --no-default-features \
//!     --test synthetic_conditions -- --ignored --nocapture
//! ```

#![expect(clippy::print_stdout, reason = "the test prints its tables")]

mod support;

use std::collections::BTreeMap;
use std::f64::consts::TAU;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use geosnap::core::geom::projection::{sketch_from_view, view_from_sketch};
use geosnap::core::model::{Document, Fit};
use geosnap::core::primitive::{Placement, Primitive, PrimitiveKind};
use geosnap::core::sketch::{Sketch, Stroke, StrokeClass, StrokeId};
use geosnap::core::snap::{
    nobody, snap, snap_at, Owner, SnapContext, SnapResult, SnapSettings, Verdict,
};
use glam::DVec2;
use support::assemblies::{assembly_with_hand, perturbed_placement, AssemblyKind, Perturbation};
use support::judge::{describe, distance_to, evaluate, picture_difference, Errors, SAME_PICTURE};
use support::overlay::write_overlay;
use support::synth::{bgc_across_post, scene_with, scene_with_hand, Condition, Rng, SynthStroke};

/// Cases per kind and condition of the acceptance run unless
/// `GEOSNAP_SYNTH_CONDITION_CASES` says otherwise.
const ACCEPTANCE_CASES: usize = 24;
/// Assemblies per kind and condition of the acceptance run unless
/// `GEOSNAP_SYNTH_CONDITION_ASSEMBLIES` says otherwise.
const ACCEPTANCE_ASSEMBLIES: usize = 4;
/// The assembly kinds of the acceptance run: issue 16's five, then the objects issue 17
/// added (handles, tees, plugs, valve rows, menorahs), whose parts stand in front of one
/// another (a stem behind its arms, a branch across its main pipe), and rows of equal
/// boxes touching face to face (drawers, books), each box's outline shared with its
/// neighbours'. Their order sets the seeds: the first five draw what they drew before the
/// others joined.
const ACCEPTANCE_KINDS: [AssemblyKind; 11] = [
    AssemblyKind::Stack,
    AssemblyKind::Table,
    AssemblyKind::SphereTubes,
    AssemblyKind::BrickStuds,
    AssemblyKind::BoxPipes,
    AssemblyKind::Handle,
    AssemblyKind::Tee,
    AssemblyKind::Plug,
    AssemblyKind::Valves,
    AssemblyKind::Menorah,
    AssemblyKind::Drawers,
];
/// Cases per kind and condition of the floor test (fixed: the floors were measured with
/// it).
const FLOOR_CASES: usize = 4;
/// Assemblies per kind and condition of the floor test (fixed, as [`FLOOR_CASES`]).
const FLOOR_ASSEMBLIES: usize = 1;
/// The issue's target per kind (single primitives) and per assembly kind (its parts).
const REQUIRED_KIND_RATE: f64 = 0.95;
/// The issue's target per condition (single primitives, and parts of assemblies).
const REQUIRED_CONDITION_RATE: f64 = 0.90;

/// Today's floor per kind in the floor test ([`FLOOR_CASES`], 32 cases per kind): the
/// rate measured (cylinder 84.4 %, cone 93.8 %, sphere 100 %, box 75.0 % then, 87.5 %
/// since, SGC 87.5 %, BGC 40.6 % then, 50.0 % since a bent tube's profile is held as
/// drawn where its outlines show it, 62.5 % since it also starts from a spine through
/// its drawn ends, 50.0 % since the slanted condition turns ellipses by up to 20° and
/// the rough hand goes over its lines up to 8 % apart) minus about 5 points, rounded
/// down to 5 %. Raise these as snapping improves; the target is [`REQUIRED_KIND_RATE`].
const KIND_FLOOR: [(PrimitiveKind, f64); 6] = [
    (PrimitiveKind::Cylinder, 0.75),
    (PrimitiveKind::Cone, 0.85),
    (PrimitiveKind::Sphere, 0.95),
    (PrimitiveKind::Cuboid, 0.80),
    (PrimitiveKind::Sgc, 0.80),
    (PrimitiveKind::Bgc, 0.45),
];
/// Today's floor per condition in the floor test (24 cases per condition), as
/// [`KIND_FLOOR`]: measured plain 95.8 %, near-axial 62.5 %, side-on 79.2 %, missing
/// 91.7 %, overshoots 75.0 %, sketchy 83.3 %, joined 75.0 %, fragments 79.2 %; side-on
/// 100 % and fragments 95.8 % since a bent tube also starts from a spine through its
/// drawn ends (overshoots, sketchy and joined one case more each); slanted 87.5 % when
/// that condition joined, joined 79.2 % since a stroke drawn round a turn is read in its
/// pieces and a far end's arc in the shape of the near end; rough 79.2 % when that
/// condition joined, 87.5 % since its copies lie up to 8 % apart and a curve keeps a
/// line's copies, 79.2 % since half the later copies go over a stretch of the line only;
/// slanted 79.2 % since its ellipses turn by up to 20°. The target is
/// [`REQUIRED_CONDITION_RATE`].
const CONDITION_FLOOR: [(Condition, f64); 10] = [
    (Condition::Plain, 0.85),
    (Condition::NearAxial, 0.55),
    (Condition::SideOn, 0.90),
    (Condition::Missing, 0.85),
    (Condition::Overshoots, 0.70),
    (Condition::Sketchy, 0.75),
    (Condition::Joined, 0.70),
    (Condition::Fragments, 0.90),
    (Condition::Slanted, 0.70),
    (Condition::Rough, 0.70),
];
/// Today's floor per assembly kind (its parts; 23–39 per kind) in the floor test, as
/// [`KIND_FLOOR`]: measured stack 87.0 %, table 68.4 %, ball+tubes 93.3 %, brick+studs
/// 82.1 %, box+pipes 85.2 %. The target is [`REQUIRED_KIND_RATE`].
const ASSEMBLY_FLOOR: [(AssemblyKind, f64); 5] = [
    (AssemblyKind::Stack, 0.80),
    (AssemblyKind::Table, 0.60),
    (AssemblyKind::SphereTubes, 0.85),
    (AssemblyKind::BrickStuds, 0.75),
    (AssemblyKind::BoxPipes, 0.80),
];
/// Today's floor per condition among the assemblies' parts (18–23 per condition) in the
/// floor test, as [`KIND_FLOOR`]: measured plain 100 %, near-axial 82.6 %, side-on
/// 72.2 %, missing 90.0 %, overshoots 90.9 %, sketchy 88.9 %, joined 66.7 %, fragments
/// 94.7 %; slanted 100 % when that condition joined, joined 77.8 % since a stroke drawn
/// round a turn is read in its pieces and a far end's arc in the shape of the near end;
/// rough 91.3 % when that condition joined, 87.0 % since its copies lie up to 8 % apart
/// and a curve keeps a line's copies; slanted 81.0 % since its ellipses turn by up to
/// 20°; since half the later copies go over a stretch of the line only, sketchy 88.9 %
/// (94.4 % before) and rough 100 %; sketchy 83.3 % since a box's starts also stand where
/// its own edges lie on drawn lines (a brick read short in sketchy lines, whose new
/// start's fit leads narrowly; docs/decisions.md, "Where a box read off the drawing
/// stands"). The target is [`REQUIRED_CONDITION_RATE`].
const ASSEMBLY_CONDITION_FLOOR: [(Condition, f64); 10] = [
    (Condition::Plain, 0.85),
    (Condition::NearAxial, 0.70),
    (Condition::SideOn, 0.65),
    (Condition::Missing, 0.85),
    (Condition::Overshoots, 0.85),
    (Condition::Sketchy, 0.80),
    (Condition::Joined, 0.60),
    (Condition::Fragments, 0.85),
    (Condition::Slanted, 0.75),
    (Condition::Rough, 0.80),
];

/// The largest share of good parts whose snap may call itself doubtful or refused (the
/// issue's target, met today: 48 of 2605 at 40 cases per kind and condition).
const MAX_GOOD_FLAGGED: f64 = 0.05;
/// Today's floor for the share of wrong parts whose snap calls itself doubtful or refused
/// (22 of 58 in the floor test since a drop is also tried shrunk, which mends parts that
/// called themselves doubtful, so fewer of the wrong parts left do; 26 of 60 before, 14
/// of 60 before the snap weighed how tightly its strokes pin it; 47 % at 40 cases per
/// kind and condition either way; 20 of 60 once the slanted and rough hands were
/// widened, 18 of 52 since a curve keeps a line's copies, 42 % at 40 cases; 18 of 52,
/// 40 % at 40 cases, since the sketchy and rough hands go over stretches of lines); the
/// target is 90 %.
const WRONG_FLAGGED_FLOOR: f64 = 0.30;

/// How far (a fraction of the size) a perfect hand's stroke of an SGC or BGC may be from
/// the model's projected curve in the renderer check. Measured: SGCs up to 7.9 % in
/// near-axial views (an end ring's one-sided slope, whose error the contour's shift
/// along the axis magnifies by a_z²/ρ², see `synthetic_snap`'s renderer test), BGCs up to
/// 3.8 %.
const SMOOTH_TOL: f64 = 0.1;

/// What a case drew: a single primitive, or an assembly whose parts are judged one by one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Subject {
    /// A primitive of this kind alone.
    Single(PrimitiveKind),
    /// An assembly of this kind.
    Assembly(AssemblyKind),
}

impl Subject {
    fn name(self) -> &'static str {
        match self {
            Self::Single(k) => k.name(),
            Self::Assembly(k) => k.name(),
        }
    }

    /// The subject named `name` (a kind's or an assembly kind's name).
    fn from_name(name: &str) -> Option<Self> {
        PrimitiveKind::from_name(name)
            .map(Self::Single)
            .or_else(|| {
                ACCEPTANCE_KINDS
                    .into_iter()
                    .find(|k| k.name() == name)
                    .map(Self::Assembly)
            })
    }

    /// Its position in the seed.
    fn ordinal(self) -> u64 {
        match self {
            Self::Single(k) => PrimitiveKind::ALL.iter().position(|x| *x == k).unwrap_or(0) as u64,
            Self::Assembly(k) => {
                10 + ACCEPTANCE_KINDS.iter().position(|x| *x == k).unwrap_or(0) as u64
            }
        }
    }
}

/// One drawing to run: a subject under a condition, its index and whether it shows
/// hidden lines (odd indices).
#[derive(Clone, Copy, Debug)]
struct Job {
    subject: Subject,
    condition: Condition,
    index: usize,
}

impl Job {
    fn seed(self) -> u64 {
        let c = Condition::ALL
            .iter()
            .position(|x| *x == self.condition)
            .unwrap_or(0) as u64;
        0xC0_0000_0000 + 1_000_000 * (self.subject.ordinal() + 1) + 10_000 * c + self.index as u64
    }

    fn hidden_lines(self) -> bool {
        self.index % 2 == 1
    }

    fn name(self) -> String {
        format!(
            "{}:{}:{}",
            self.subject.name(),
            self.condition.name(),
            self.index
        )
    }
}

/// The judgement of one snapped primitive (a single one or one part of an assembly).
#[derive(Clone, Debug)]
struct Outcome {
    job: Job,
    /// The part's index in its assembly.
    part: Option<usize>,
    /// The failed criteria (`"error"` when the snap returned an error).
    failed: Vec<&'static str>,
    /// The shape's class among its kind's ([`shape_class`]).
    shape: Option<&'static str>,
    /// For a failure: whether it persists when the snap starts from the truth.
    at_truth: Option<bool>,
    /// For a failure: whether the snap draws the truth's picture (within
    /// [`SAME_PICTURE`]).
    same_picture: bool,
    /// The part's strokes (or the scene's) that the classifier gave another class than
    /// the renderer, and those compared (joined strokes are left out).
    misclassified: (usize, usize),
    elapsed: Duration,
    /// Whether the snap called itself doubtful or refused (a snap error counts as
    /// refused), and its confidence's evidence in words.
    flagged: bool,
    evidence: String,
}

impl Outcome {
    fn ok(&self) -> bool {
        self.failed.is_empty()
    }
}

/// The extremes of the wider variety, reported apart: thin discs (length under 0.25 ×
/// the radius) and rods (over 8 ×) among cylinders, flat boxes (a side under 1/4 of the
/// largest: slabs and planks) among boxes, S and C spines among bent tubes.
fn shape_class(truth: &Primitive) -> Option<&'static str> {
    match truth {
        Primitive::Cylinder(c) if c.length < 0.25 * c.radius => Some("thin discs"),
        Primitive::Cylinder(c) if c.length > 8.0 * c.radius => Some("rods"),
        Primitive::Cuboid(b) if b.size.min_element() < 0.25 * b.size.max_element() => {
            Some("flat boxes")
        }
        Primitive::Bgc(b) => {
            // The signed turns of the spine about its plane's normal: an S turns both ways.
            let turns: Vec<f64> = b
                .spine
                .windows(3)
                .map(|w| (w[1] - w[0]).cross(w[2] - w[1]).dot(b.plane_normal))
                .collect();
            let both = turns.iter().any(|t| *t > 0.0) && turns.iter().any(|t| *t < 0.0);
            Some(if both { "S tubes" } else { "C tubes" })
        }
        _ => None,
    }
}

/// The criteria `e` fails, as short keys.
fn failed_criteria(e: &Errors) -> Vec<&'static str> {
    let mut out = Vec::new();
    for f in e.failures() {
        for key in ["centre", "axis", "radius", "length"] {
            if f.starts_with(key) {
                out.push(key);
            }
        }
    }
    out
}

/// The strokes as a sketch without classes, as a drawing arrives in the app.
fn sketch_of(strokes: &[SynthStroke]) -> Sketch {
    Sketch {
        strokes: strokes
            .iter()
            .enumerate()
            .map(|(i, s)| Stroke {
                id: StrokeId(i as u32),
                points: s.points.clone(),
                closed: false,
                class_override: None,
            })
            .collect(),
        view_box: None,
    }
}

/// Strokes among `which` whose class in `context` is not the renderer's, and those
/// compared (joined strokes and strokes dropped by preprocessing are left out).
fn misclassified(
    context: &SnapContext,
    strokes: &[SynthStroke],
    which: &[usize],
) -> (usize, usize) {
    let (mut wrong, mut total) = (0, 0);
    for &i in which {
        let s = &strokes[i];
        if s.label.starts_with("U:") || s.label.starts_with("L:") {
            continue;
        }
        if let Some(c) = context.stroke(StrokeId(i as u32)) {
            total += 1;
            if c.class != s.class {
                wrong += 1;
            }
        }
    }
    (wrong, total)
}

/// The class of every stroke as the renderer drew it and as the classifier saw it.
fn class_lines(out: &mut String, context: &SnapContext, strokes: &[SynthStroke]) {
    let name = |c: StrokeClass| match c {
        StrokeClass::Feature => "feature",
        StrokeClass::Silhouette => "silhouette",
    };
    for (i, s) in strokes.iter().enumerate() {
        let seen = context
            .stroke(StrokeId(i as u32))
            .map_or("dropped", |c| name(c.class));
        let mark = if seen == name(s.class) { "" } else { "  ≠" };
        let ends = context
            .stroke(StrokeId(i as u32))
            .map_or_else(String::new, |c| where_drawn(&c.points));
        let _ = writeln!(
            out,
            "      {i:>3} {:<48} {:<10} → {seen}{mark} {ends}",
            s.label,
            name(s.class)
        );
    }
}

/// A stroke's first, middle and last points (view plane), for reading a shown case.
fn where_drawn(points: &[DVec2]) -> String {
    match (points.first(), points.get(points.len() / 2), points.last()) {
        (Some(a), Some(m), Some(b)) => format!(
            "({:.0},{:.0})..({:.0},{:.0})..({:.0},{:.0})",
            a.x, a.y, m.x, m.y, b.x, b.y
        ),
        _ => String::new(),
    }
}

/// The verdict of a snap of `dropped` (none: no snap), and its confidence's evidence in
/// words, with the snap's `errors` against the truth.
fn judged_confidence(
    truth: &Primitive,
    result: Option<&SnapResult>,
    dropped: &Primitive,
    errors: Option<&Errors>,
    placed: &dyn Owner,
) -> (Option<Verdict>, String) {
    let confidence = result.map(|r| r.confidence(dropped, placed, &SnapSettings::default()));
    let verdict = confidence.as_ref().map(|c| c.verdict);
    let evidence = confidence.as_ref().map_or_else(String::new, |c| {
        let e = &c.evidence;
        let s = e.spread.unwrap_or_default();
        let why = c
            .reason
            .as_ref()
            .map_or_else(String::new, |r| format!(" ({r})"));
        format!(
            "{} {:.2}{why}: rms {:.2} %, drawn {:.0} %, moved {:.0} %, size ×{:.2}, margin {}, depth {:.1} %, spread c {:.4} a {:.4} r {:.4} l {:.4}",
            c.verdict,
            c.value,
            100.0 * e.rms,
            100.0 * e.support,
            100.0 * e.moved,
            e.resized,
            e.margin.map_or("—".to_owned(), |m| format!("{m:.2}")),
            100.0 * e.depth,
            s.centre,
            s.axis,
            s.radius,
            s.length
        )
    });
    // The other readings: their RMS and what they explain (the snap's beside it), and
    // whether each recovers the truth.
    let mut rivals = String::new();
    for (a, r) in result
        .iter()
        .flat_map(|r| r.alternatives.iter().take(3).map(move |a| (a, r)))
    {
        let _ = write!(
            rivals,
            " | alt {}: rms {:.2} %, explains {:.0} (the snap {:.0}), {:.0} % of the size away{}",
            a.primitive.kind().name(),
            100.0 * a.rms / a.primitive.size(),
            a.explained,
            r.explained.unwrap_or(f64::NAN),
            100.0 * a.distance,
            if failed_criteria(&evaluate(truth, &a.primitive)).is_empty() {
                ", the truth"
            } else {
                ""
            }
        );
    }
    let evidence = format!("{evidence}{rivals}");
    // The errors in the spread's units (sizes, radians, relative), to calibrate it.
    let evidence = match errors {
        Some(e) => format!(
            "{evidence} errors c {:.4} a {:.4} r {:.4} l {:.4}",
            e.centre,
            e.axis.unwrap_or(0.0).to_radians(),
            e.radius.unwrap_or(0.0),
            e.length.unwrap_or(0.0)
        ),
        None => evidence,
    };
    (verdict, evidence)
}

/// Of a snap started from the truth (`at_truth`, with its `errors`): whether it fails
/// too, and that in words with, when it does not, how much more of the drawing it
/// explains than the snap from the drop (`dropped`; more: the search missed a better
/// reading).
fn from_the_truth(
    at_truth: &Result<SnapResult, String>,
    errors: Option<&Errors>,
    dropped: &Result<SnapResult, String>,
) -> (bool, String) {
    if at_truth.is_err() || errors.is_some_and(|e| !e.failures().is_empty()) {
        return (true, "; fails from the truth too".to_owned());
    }
    let gain = match (at_truth, dropped) {
        (Ok(t), Ok(d)) => t
            .explained
            .zip(d.explained)
            .map(|(t, d)| (t - d) / d.abs().max(f64::MIN_POSITIVE)),
        _ => None,
    };
    let words = match gain {
        Some(gain) => format!(
            "; recovered from the truth (it explains {:.0} % {} of the drawing)",
            100.0 * gain.abs(),
            if gain >= 0.0 { "more" } else { "less" }
        ),
        None => "; recovered from the truth".to_owned(),
    };
    (false, words)
}

/// A failed snap's [`picture_difference`] from the truth, in words.
fn in_words(picture: Option<f64>) -> String {
    match picture {
        Some(d) if d <= SAME_PICTURE => {
            format!("; draws the truth's picture ({:.2} %S apart)", 100.0 * d)
        }
        Some(d) => format!("; its picture {:.1} %S from the truth's", 100.0 * d),
        None => String::new(),
    }
}

/// `truth` dropped as `drops` says and snapped (`run` snaps a rough drop): the drop (for
/// a point drop, the guess its snap came from), the snap and its errors.
fn drop_and_snap(
    drops: Drops,
    truth: &Primitive,
    context: &SnapContext,
    rng: &mut Rng,
    run: impl Fn(&Primitive) -> (Result<SnapResult, String>, Option<Errors>),
) -> (Primitive, Result<SnapResult, String>, Option<Errors>) {
    match drops {
        Drops::Rough => {
            let place = perturbed_placement(truth, rng, Perturbation::ISSUE_16);
            let dropped = Primitive::from_placement(truth.kind(), &place, truth.size());
            let (result, errors) = run(&dropped);
            (dropped, result, errors)
        }
        Drops::Point => {
            let off = DVec2::from_angle(rng.range(0.0, TAU)) * (rng.range(0.0, 0.1) * truth.size());
            let at = sketch_from_view(truth.center().truncate() + off);
            match snap_at(context, truth.kind(), at, None, &SnapSettings::default()) {
                Ok(snapped) => {
                    let errors = Some(evaluate(truth, &snapped.result.primitive));
                    (snapped.guess, Ok(snapped.result), errors)
                }
                Err(e) => {
                    let dropped =
                        Primitive::from_placement(truth.kind(), &Placement::at(at), truth.size());
                    (dropped, Err(e.to_string()), None)
                }
            }
        }
    }
}

/// Snaps `truth` dropped as `drops` says and judges it; writes the
/// analysis into `report` when the case fails or is `shown`, and its overlay into `png`.
/// Returns the outcome and the snap unless its confidence refused it (what a model keeps).
#[expect(
    clippy::too_many_arguments,
    reason = "one case's inputs, passed straight on"
)]
fn judge_part(
    job: Job,
    drops: Drops,
    part: Option<usize>,
    truth: &Primitive,
    context: &SnapContext,
    strokes: &[SynthStroke],
    own: &[usize],
    placed: &dyn Owner,
    shown: bool,
    png: Option<&Path>,
    report: &mut String,
) -> (Outcome, Option<SnapResult>) {
    let mut rng = Rng::new(job.seed() ^ 0xD80F_D80F ^ (part.unwrap_or(0) as u64) << 32);
    let run = |start: &Primitive| -> (Result<SnapResult, String>, Option<Errors>) {
        let result = snap(context, start, &SnapSettings::default()).map_err(|e| e.to_string());
        let errors = result.as_ref().ok().map(|r| evaluate(truth, &r.primitive));
        (result, errors)
    };
    let start = Instant::now();
    let (dropped, result, errors) = drop_and_snap(drops, truth, context, &mut rng, run);
    let elapsed = start.elapsed();
    let failed = errors
        .as_ref()
        .map_or_else(|| vec!["error"], failed_criteria);
    let mut truth_snap = None;
    let from_truth = (!failed.is_empty() || shown).then(|| {
        let (r, e) = run(truth);
        let words = from_the_truth(&r, e.as_ref(), &result);
        truth_snap = r.ok();
        words
    });
    let from_truth = from_truth.filter(|_| !failed.is_empty());
    let at_truth = from_truth.as_ref().map(|(fails, _)| *fails);
    let snapped = result.as_ref().ok();
    let (verdict, evidence) = judged_confidence(truth, snapped, &dropped, errors.as_ref(), placed);
    let flagged = verdict != Some(Verdict::Good);
    let kept = snapped
        .filter(|_| verdict.is_some_and(|v| v != Verdict::Refused))
        .cloned();
    let picture = (!failed.is_empty())
        .then(|| result.as_ref().ok())
        .flatten()
        .map(|r| picture_difference(truth, &r.primitive));
    let same_picture = picture.is_some_and(|d| d <= SAME_PICTURE);
    let outcome = Outcome {
        flagged,
        evidence,
        job,
        part,
        shape: shape_class(truth),
        failed,
        at_truth,
        same_picture,
        misclassified: misclassified(context, strokes, own),
        elapsed,
    };
    if outcome.ok() && !shown && std::env::var_os("GEOSNAP_SYNTH_CONDITION_ALL").is_none() {
        return (outcome, kept);
    }
    let part_name = part.map_or_else(String::new, |p| {
        format!(" part {p} ({})", truth.kind().name())
    });
    let verdict = match (&result, &errors) {
        (Err(e), _) => format!("snap failed: {e}"),
        (Ok(_), Some(e)) if !e.failures().is_empty() => e.failures().join(", "),
        _ => "recovered".to_owned(),
    };
    let persists = from_truth.map_or_else(String::new, |(_, words)| words) + &in_words(picture);
    let _ = writeln!(
        report,
        "  {}{part_name} (seed {:#x}{}): {verdict}{persists}{}; classes wrong {}/{}; {}",
        job.name(),
        job.seed(),
        [", hidden lines", ""][usize::from(!job.hidden_lines())],
        others_strokes(result.as_ref().ok(), own),
        outcome.misclassified.0,
        outcome.misclassified.1,
        if outcome.evidence.is_empty() {
            "refused"
        } else {
            &outcome.evidence
        }
    );
    if shown {
        shown_lines(
            report,
            truth,
            &dropped,
            result.as_ref().ok(),
            truth_snap.as_ref(),
        );
    }
    if let Some(folder) = png {
        let suffix = part.map_or_else(String::new, |p| format!("_part{p}"));
        let path = folder.join(format!(
            "cond_{}_{}_{:03}{suffix}.png",
            job.subject.name().replace('+', "_"),
            job.condition.name(),
            job.index
        ));
        let points: Vec<&[DVec2]> = strokes.iter().map(|s| s.points.as_slice()).collect();
        let snapped = result.as_ref().ok().map(|r| &r.primitive);
        match write_overlay(&path, &points, truth, &dropped, snapped) {
            Ok(()) => {
                let _ = writeln!(report, "    overlay: {}", path.display());
            }
            Err(e) => {
                let _ = writeln!(report, "    overlay not written: {e}");
            }
        }
    }
    (outcome, kept)
}

/// The parts of an assembly placed before a part is dropped, as a designer who puts each
/// snap right before dropping the next has them ([`Session::Truth`]): each where it truly
/// lies, owning the strokes drawn for it.
struct Placed<'a> {
    parts: &'a [Primitive],
    /// The part each stroke (by id) was drawn for.
    part_of: &'a [usize],
    /// Whether each part was dropped before.
    dropped: &'a [bool],
}

impl Placed<'_> {
    fn is_placed(&self, part: usize) -> bool {
        self.dropped.get(part).copied().unwrap_or(false)
    }
}

impl Owner for Placed<'_> {
    fn owner(&self, stroke: StrokeId, _: DVec2) -> Option<u32> {
        let part = *self.part_of.get(stroke.0 as usize)?;
        self.is_placed(part).then_some(part as u32)
    }

    fn pose(&self, part: u32) -> Option<Primitive> {
        let part = part as usize;
        self.is_placed(part).then(|| self.parts[part].clone())
    }
}

/// What an assembly's parts find placed when each is dropped
/// (`GEOSNAP_SYNTH_CONDITION_PLACED`), and in which order they are dropped
/// (`GEOSNAP_SYNTH_CONDITION_ORDER`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Session {
    /// The parts dropped before, each where it truly lies: a designer who puts every wrong
    /// snap right before the next drop (`truth`, the default).
    Truth,
    /// The snaps of the parts dropped before as they came out, wrong or not, but for the
    /// refused ones, owning the strokes they took: a designer who keeps what the snap
    /// gives, as `geosnap run` does (`snapped`).
    Snapped,
    /// No part placed: each part snapped as the first of a model (`none`).
    Nothing,
}

impl Session {
    /// The session the environment asks for.
    fn from_env() -> Self {
        match std::env::var("GEOSNAP_SYNTH_CONDITION_PLACED").as_deref() {
            Ok("snapped") => Self::Snapped,
            Ok("none") => Self::Nothing,
            Ok("truth") | Err(_) => Self::Truth,
            Ok(other) => panic!("GEOSNAP_SYNTH_CONDITION_PLACED={other}: truth, snapped or none"),
        }
    }
}

/// The order in which an assembly's `n` parts are dropped: the generator's (the object's
/// main part first), or with `GEOSNAP_SYNTH_CONDITION_ORDER=shuffled` a shuffle fixed by
/// the drawing's seed (a designer who starts with a leg or a drawer).
fn drop_order(n: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    match std::env::var("GEOSNAP_SYNTH_CONDITION_ORDER").as_deref() {
        Ok("shuffled") => {
            let mut rng = Rng::new(seed ^ 0x5E55_1011);
            for k in (1..n).rev() {
                let j = (rng.next_u64() % (k as u64 + 1)) as usize;
                order.swap(k, j);
            }
        }
        Ok("given") | Err(_) => {}
        Ok(other) => panic!("GEOSNAP_SYNTH_CONDITION_ORDER={other}: given or shuffled"),
    }
    order
}

/// How many of the strokes a snap took are other parts' (not in `own`), in words.
fn others_strokes(result: Option<&SnapResult>, own: &[usize]) -> String {
    result.map_or_else(String::new, |r| {
        let ids = r.assignment.stroke_ids();
        let theirs = ids
            .iter()
            .filter(|i| !own.contains(&(i.0 as usize)))
            .count();
        format!("; others' strokes {theirs}/{}", ids.len())
    })
}

/// A shown case's poses: the truth, the drop, the snap and the snap from the truth, each
/// snap with the strokes its curves took.
fn shown_lines(
    report: &mut String,
    truth: &Primitive,
    dropped: &Primitive,
    result: Option<&SnapResult>,
    truth_snap: Option<&SnapResult>,
) {
    let _ = writeln!(report, "    truth   {}", describe(truth));
    let _ = writeln!(report, "    dropped {}", describe(dropped));
    for (label, snap) in [("snapped", result), ("from the truth", truth_snap)] {
        if let Some(r) = snap {
            let _ = writeln!(
                report,
                "    {label} {} (rms {:.2} %S)",
                describe(&r.primitive),
                100.0 * r.rms / truth.size()
            );
            assignment_lines(report, label, r);
        }
    }
}

/// Which strokes (how many samples, how far on average) each projected curve of a shown
/// case's snap took.
fn assignment_lines(report: &mut String, label: &str, result: &SnapResult) {
    for (k, curve) in result.assignment.curves.iter().enumerate() {
        let taken: Vec<String> = curve
            .iter()
            .map(|a| {
                format!(
                    "{}{} ({} samples, {:.1})",
                    a.stroke.0,
                    if a.part.is_some() { " in part" } else { "" },
                    a.samples.len(),
                    a.mean_distance
                )
            })
            .collect();
        let _ = writeln!(report, "      {label} curve {k}: {}", taken.join(", "));
    }
}

/// Runs one job: its outcomes (one per part of an assembly) and its report.
fn run_job(
    job: Job,
    drops: Drops,
    hand: f64,
    shown: bool,
    png: Option<&Path>,
) -> (Vec<Outcome>, String) {
    let mut report = String::new();
    let hidden = job.hidden_lines();
    match job.subject {
        Subject::Single(kind) => {
            let scene = scene_with_hand(kind, job.seed(), job.condition, hidden, None, hand);
            let context = SnapContext::from_sketch(&sketch_of(&scene.strokes));
            if shown {
                let _ = writeln!(report, "  {} strokes (drawn as → classified):", job.name());
                class_lines(&mut report, &context, &scene.strokes);
            }
            let all: Vec<usize> = (0..scene.strokes.len()).collect();
            let (outcome, _) = judge_part(
                job,
                drops,
                None,
                &scene.truth,
                &context,
                &scene.strokes,
                &all,
                &nobody,
                shown,
                png,
                &mut report,
            );
            (vec![outcome], report)
        }
        Subject::Assembly(kind) => {
            let assembly = assembly_with_hand(kind, job.seed(), job.condition, hidden, hand);
            let context = SnapContext::from_sketch(&sketch_of(&assembly.strokes));
            if shown {
                let _ = writeln!(report, "  {} strokes (drawn as → classified):", job.name());
                class_lines(&mut report, &context, &assembly.strokes);
            }
            let session = Session::from_env();
            let n = assembly.parts.len();
            let mut dropped = vec![false; n];
            // The model the snaps build up ([`Session::Snapped`]).
            let mut document = Document::new();
            let mut outcomes: Vec<Option<Outcome>> = (0..n).map(|_| None).collect();
            for i in drop_order(n, job.seed()) {
                let truth = &assembly.parts[i];
                let mut context = context.clone();
                match session {
                    Session::Truth => context.set_placed(
                        (0..n)
                            .filter(|&p| dropped[p])
                            .map(|p| assembly.parts[p].clone()),
                    ),
                    Session::Snapped => {
                        context.set_placed(document.primitives().map(|(_, p)| p.primitive.clone()));
                    }
                    Session::Nothing => {}
                }
                let own: Vec<usize> = (0..assembly.strokes.len())
                    .filter(|k| assembly.part_of.get(*k) == Some(&i))
                    .collect();
                let truly_placed = Placed {
                    parts: &assembly.parts,
                    part_of: &assembly.part_of,
                    dropped: &dropped,
                };
                let snapped_placed = document.owner();
                let owner: &dyn Owner = match session {
                    Session::Truth => &truly_placed,
                    Session::Snapped => &snapped_placed,
                    Session::Nothing => &nobody,
                };
                let (outcome, kept) = judge_part(
                    job,
                    drops,
                    Some(i),
                    truth,
                    &context,
                    &assembly.strokes,
                    &own,
                    owner,
                    shown,
                    png,
                    &mut report,
                );
                if let Some(result) = kept {
                    document.add_fitted(&result, Fit::of(&result));
                }
                dropped[i] = true;
                outcomes[i] = Some(outcome);
            }
            (outcomes.into_iter().flatten().collect(), report)
        }
    }
}

/// The settings of a run.
struct Run {
    cases: usize,
    assemblies: usize,
    /// The assembly kinds run.
    assembly_kinds: Vec<AssemblyKind>,
    /// Where the overlays of failed cases go.
    png: Option<PathBuf>,
    /// Where the overlays of the shown case go.
    show_png: PathBuf,
    show: Option<(Subject, Condition, usize)>,
    list: bool,
    /// Print each job's name to stderr as it starts and ends.
    progress: bool,
    /// Only these subjects (none: all) …
    only_subjects: Vec<Subject>,
    /// … and these conditions (none: all).
    only_conditions: Vec<Condition>,
    /// The hand's errors scaled by this (`Style::steadier`; 1: the generator's hand).
    hand: f64,
    /// How the parts are dropped.
    drops: Drops,
}

/// How a run drops each part.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Drops {
    /// As a hand that sizes and turns it: the issue's perturbation
    /// ([`Perturbation::ISSUE_16`]).
    Rough,
    /// As the palette drops it when the wheel has not sized or turned it, or a script step
    /// that gives only a point: at a point within 10 % of the part's size of its centre,
    /// with no size and no direction ([`snap_at`]).
    Point,
}

impl Run {
    /// A run of `cases` and `assemblies` (of `assembly_kinds`) per kind and condition,
    /// with the diagnostics the environment asks for.
    fn from_env(cases: usize, assemblies: usize, assembly_kinds: &[AssemblyKind]) -> Self {
        let show = std::env::var("GEOSNAP_SYNTH_CONDITION_SHOW")
            .ok()
            .and_then(|v| {
                let mut parts = v.split(':');
                let subject = Subject::from_name(parts.next()?.trim())?;
                let condition = Condition::from_name(parts.next()?.trim())?;
                let index = parts.next()?.trim().parse().ok()?;
                Some((subject, condition, index))
            });
        let png = std::env::var_os("GEOSNAP_SYNTH_CONDITION_PNG").map(PathBuf::from);
        let only: Vec<String> = std::env::var("GEOSNAP_SYNTH_CONDITION_ONLY")
            .map(|v| v.split(',').map(|n| n.trim().to_owned()).collect())
            .unwrap_or_default();
        Self {
            cases,
            assemblies,
            assembly_kinds: assembly_kinds.to_vec(),
            show_png: png.clone().unwrap_or_else(std::env::temp_dir),
            png,
            show,
            list: std::env::var_os("GEOSNAP_SYNTH_CONDITION_LIST").is_some(),
            progress: std::env::var_os("GEOSNAP_SYNTH_CONDITION_PROGRESS").is_some(),
            only_subjects: only.iter().filter_map(|n| Subject::from_name(n)).collect(),
            only_conditions: only
                .iter()
                .filter_map(|n| Condition::from_name(n))
                .collect(),
            hand: std::env::var("GEOSNAP_SYNTH_CONDITION_HAND")
                .ok()
                .and_then(|v| v.trim().parse::<f64>().ok())
                .filter(|h| h.is_finite() && *h >= 0.0)
                .unwrap_or(1.0),
            drops: Drops::Rough,
        }
    }
}

/// Every outcome of a run, in a deterministic order, and the reports of its failures.
fn run_all(run: &Run) -> (Vec<Outcome>, String) {
    let mut jobs = Vec::new();
    for kind in PrimitiveKind::ALL {
        for condition in Condition::ALL {
            for index in 0..run.cases {
                jobs.push(Job {
                    subject: Subject::Single(kind),
                    condition,
                    index,
                });
            }
        }
    }
    for &kind in &run.assembly_kinds {
        for condition in Condition::ALL {
            for index in 0..run.assemblies {
                jobs.push(Job {
                    subject: Subject::Assembly(kind),
                    condition,
                    index,
                });
            }
        }
    }
    jobs.retain(|j| {
        (run.only_subjects.is_empty() || run.only_subjects.contains(&j.subject))
            && (run.only_conditions.is_empty() || run.only_conditions.contains(&j.condition))
    });
    if let Some((subject, condition, index)) = run.show {
        jobs = vec![Job {
            subject,
            condition,
            index,
        }];
    }
    let next = AtomicUsize::new(0);
    let done: Mutex<Vec<(usize, Vec<Outcome>, String)>> = Mutex::new(Vec::new());
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get().min(4));
    std::thread::scope(|scope| {
        for t in 0..threads {
            let (next, done, jobs) = (&next, &done, &jobs);
            std::thread::Builder::new()
                .name(format!("conditions-{t}"))
                .spawn_scoped(scope, move || loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(job) = jobs.get(i) else { break };
                    let shown = run
                        .show
                        .is_some_and(|s| s == (job.subject, job.condition, job.index));
                    let png = if shown {
                        Some(run.show_png.as_path())
                    } else {
                        run.png.as_deref()
                    };
                    if run.progress {
                        eprintln!("start {}", job.name());
                    }
                    let (outcomes, report) = run_job(*job, run.drops, run.hand, shown, png);
                    if run.progress {
                        eprintln!("end {}", job.name());
                    }
                    done.lock()
                        .expect("no worker panicked")
                        .push((i, outcomes, report));
                })
                .expect("a thread");
        }
    });
    let mut done = done.into_inner().expect("no worker panicked");
    done.sort_by_key(|d| d.0);
    let mut outcomes = Vec::new();
    let mut report = String::new();
    for (i, o, r) in done {
        let job = jobs[i];
        let shown = run
            .show
            .is_some_and(|s| s == (job.subject, job.condition, job.index));
        if run.list || shown {
            report.push_str(&r);
        }
        outcomes.extend(o);
    }
    (outcomes, report)
}

/// Counts, rate and main failure reasons of a group of outcomes.
struct Tally {
    cases: usize,
    ok: usize,
    at_truth: usize,
    same_picture: usize,
    wrong_classes: (usize, usize),
    reasons: BTreeMap<&'static str, usize>,
    slowest: Duration,
}

impl Tally {
    fn of<'a>(outcomes: impl IntoIterator<Item = &'a Outcome>) -> Self {
        let mut t = Self {
            cases: 0,
            ok: 0,
            at_truth: 0,
            same_picture: 0,
            wrong_classes: (0, 0),
            reasons: BTreeMap::new(),
            slowest: Duration::ZERO,
        };
        for o in outcomes {
            t.cases += 1;
            t.ok += usize::from(o.ok());
            t.at_truth += usize::from(o.at_truth == Some(true));
            t.same_picture += usize::from(o.same_picture);
            t.wrong_classes.0 += o.misclassified.0;
            t.wrong_classes.1 += o.misclassified.1;
            for r in &o.failed {
                *t.reasons.entry(r).or_default() += 1;
            }
            t.slowest = t.slowest.max(o.elapsed);
        }
        t
    }

    fn rate(&self) -> f64 {
        self.ok as f64 / self.cases.max(1) as f64
    }

    fn row(&self, label: &str) -> String {
        let mut reasons: Vec<(&str, usize)> = self.reasons.iter().map(|(k, v)| (*k, *v)).collect();
        reasons.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
        let reasons: Vec<String> = reasons.iter().map(|(k, v)| format!("{k} {v}")).collect();
        format!(
            "{label:<16}{:>6}{:>6}{:>7.1}%{:>7}{:>6}{:>8.1}%{:>8.2}s  {}",
            self.cases,
            self.ok,
            100.0 * self.rate(),
            self.at_truth,
            self.same_picture,
            100.0 * self.wrong_classes.0 as f64 / self.wrong_classes.1.max(1) as f64,
            self.slowest.as_secs_f64(),
            reasons.join(", ")
        )
    }
}

/// The rates of a run, per group.
struct Rates {
    kinds: Vec<(PrimitiveKind, f64)>,
    conditions: Vec<(Condition, f64)>,
    assemblies: Vec<(AssemblyKind, f64)>,
    assembly_conditions: Vec<(Condition, f64)>,
    /// How the confidences sort good and wrong parts.
    flags: Flags,
}

/// Prints the tables of a run and returns its rates.
fn report(title: &str, run: &Run, outcomes: &[Outcome], failures: &str, wall: Duration) -> Rates {
    let mut table = String::new();
    let _ = writeln!(
        table,
        "{title}: {} cases per kind and condition, {} assemblies per kind and condition, \
         {:.1} s wall\n\
         drops: {}; classes from the classifier; hidden lines in odd cases\n\
         truth = failures that persist when the snap starts from the truth; same = \
         failures that draw the truth's picture (their curves within 1 % of the size of \
         its curves: what fails is what the drawing leaves open); cls = strokes \
         the classifier gave another class\n\
         (joined strokes left out); slowest = the slowest single snap; reasons = failed \
         criteria (error = the snap returned an error)",
        run.cases,
        run.assemblies,
        wall.as_secs_f64(),
        match run.drops {
            Drops::Rough => "centre ±10 % of the size, axis ±10°, sizes ±25 %",
            Drops::Point => "a point within 10 % of the size of the centre, no size, no direction",
        }
    );
    if (run.hand - 1.0).abs() > 1e-12 {
        let _ = writeln!(
            table,
            "hand: every error that places a point scaled by {} (GEOSNAP_SYNTH_CONDITION_HAND)",
            run.hand
        );
    }
    let header = format!(
        "{:<16}{:>6}{:>6}{:>8}{:>7}{:>6}{:>9}{:>9}  {}",
        "", "cases", "ok", "rate", "truth", "same", "cls", "slowest", "main failure reasons"
    );
    let mut rates = Rates {
        kinds: Vec::new(),
        conditions: Vec::new(),
        assemblies: Vec::new(),
        assembly_conditions: Vec::new(),
        flags: Flags::default(),
    };
    single_tables(&mut table, &header, outcomes, &mut rates);
    if run.assemblies > 0 {
        assembly_tables(&mut table, &header, outcomes, &mut rates);
    }
    rates.flags = confidence_table(&mut table, outcomes);
    if std::env::var_os("GEOSNAP_SYNTH_CONDITION_EVIDENCE").is_some() {
        for o in outcomes {
            let _ = writeln!(
                table,
                "evidence {} ok={} failed={} truth={} {}",
                o.job.name(),
                o.ok(),
                o.failed.join("+"),
                o.at_truth.unwrap_or(false),
                o.evidence
            );
        }
    }
    let failures = if failures.is_empty() {
        String::new()
    } else {
        format!("\ncases:\n{failures}")
    };
    println!("{table}{failures}");
    rates
}

/// How the snaps' confidences sort the parts, over everything run.
#[derive(Clone, Copy, Debug, Default)]
struct Flags {
    good: usize,
    good_flagged: usize,
    wrong: usize,
    wrong_flagged: usize,
}

/// The confidence rows: per group (single primitives, assemblies), good parts called
/// doubtful or refused and wrong parts called so.
fn confidence_table(table: &mut String, outcomes: &[Outcome]) -> Flags {
    let _ = writeln!(
        table,
        "\nconfidence: flagged = called doubtful or refused (a snap error counts as refused)"
    );
    let mut all = Flags::default();
    for (name, single) in [("single primitives", true), ("assembly parts", false)] {
        let mut f = Flags::default();
        for o in outcomes
            .iter()
            .filter(|o| matches!(o.job.subject, Subject::Single(_)) == single)
        {
            if o.ok() {
                f.good += 1;
                f.good_flagged += usize::from(o.flagged);
            } else {
                f.wrong += 1;
                f.wrong_flagged += usize::from(o.flagged);
            }
        }
        let _ = writeln!(
            table,
            "{name:<18} good flagged {:>4} of {:<5} wrong flagged {:>4} of {:<5}",
            f.good_flagged, f.good, f.wrong_flagged, f.wrong
        );
        all.good += f.good;
        all.good_flagged += f.good_flagged;
        all.wrong += f.wrong;
        all.wrong_flagged += f.wrong_flagged;
    }
    all
}

/// The single primitives' rows: per kind, per condition, with and without hidden lines,
/// and the matrix of rates.
fn single_tables(table: &mut String, header: &str, outcomes: &[Outcome], rates: &mut Rates) {
    let single = |o: &&Outcome| matches!(o.job.subject, Subject::Single(_));
    let _ = writeln!(table, "\nsingle primitives, per kind\n{header}");
    for kind in PrimitiveKind::ALL {
        let t = Tally::of(
            outcomes
                .iter()
                .filter(single)
                .filter(|o| o.job.subject == Subject::Single(kind)),
        );
        if t.cases > 0 {
            rates.kinds.push((kind, t.rate()));
        }
        let _ = writeln!(table, "{}", t.row(kind.name()));
    }
    for shape in ["thin discs", "rods", "flat boxes", "C tubes", "S tubes"] {
        let t = Tally::of(
            outcomes
                .iter()
                .filter(single)
                .filter(|o| o.shape == Some(shape)),
        );
        let _ = writeln!(table, "{}", t.row(&format!("  {shape}")));
    }
    let _ = writeln!(
        table,
        "{}",
        Tally::of(outcomes.iter().filter(single)).row("all")
    );
    let _ = writeln!(table, "\nsingle primitives, per condition\n{header}");
    for condition in Condition::ALL {
        let t = Tally::of(
            outcomes
                .iter()
                .filter(single)
                .filter(|o| o.job.condition == condition),
        );
        if t.cases > 0 {
            rates.conditions.push((condition, t.rate()));
        }
        let _ = writeln!(table, "{}", t.row(condition.name()));
    }
    for (hidden, name) in [(true, "hidden lines"), (false, "no hidden lines")] {
        let t = Tally::of(
            outcomes
                .iter()
                .filter(single)
                .filter(|o| o.job.hidden_lines() == hidden),
        );
        let _ = writeln!(table, "{}", t.row(name));
    }
    let _ = writeln!(
        table,
        "\nsingle primitives, rate per kind (rows) and condition (columns)"
    );
    let _ = write!(table, "{:<10}", "");
    for condition in Condition::ALL {
        let _ = write!(table, "{:>11}", condition.name());
    }
    let _ = writeln!(table);
    for kind in PrimitiveKind::ALL {
        let _ = write!(table, "{:<10}", kind.name());
        for condition in Condition::ALL {
            let t = Tally::of(outcomes.iter().filter(single).filter(|o| {
                o.job.subject == Subject::Single(kind) && o.job.condition == condition
            }));
            let _ = write!(table, "{:>10.0}%", 100.0 * t.rate());
        }
        let _ = writeln!(table);
    }
}

/// The assemblies' rows: per assembly kind (table tops and legs apart) and per
/// condition.
fn assembly_tables(table: &mut String, header: &str, outcomes: &[Outcome], rates: &mut Rates) {
    let part = |o: &&Outcome| matches!(o.job.subject, Subject::Assembly(_));
    let _ = writeln!(
        table,
        "\nassemblies, every part, per assembly kind\n{header}"
    );
    for kind in ACCEPTANCE_KINDS {
        let t = Tally::of(
            outcomes
                .iter()
                .filter(part)
                .filter(|o| o.job.subject == Subject::Assembly(kind)),
        );
        if t.cases > 0 {
            rates.assemblies.push((kind, t.rate()));
        }
        let _ = writeln!(table, "{}", t.row(kind.name()));
    }
    let tables = |top: bool| {
        move |o: &&Outcome| {
            o.job.subject == Subject::Assembly(AssemblyKind::Table) && (o.part == Some(0)) == top
        }
    };
    let _ = writeln!(
        table,
        "{}",
        Tally::of(outcomes.iter().filter(tables(true))).row("  table tops")
    );
    let _ = writeln!(
        table,
        "{}",
        Tally::of(outcomes.iter().filter(tables(false))).row("  table legs")
    );
    let _ = writeln!(
        table,
        "{}",
        Tally::of(outcomes.iter().filter(part)).row("all")
    );
    let _ = writeln!(table, "\nassemblies, every part, per condition\n{header}");
    for condition in Condition::ALL {
        let t = Tally::of(
            outcomes
                .iter()
                .filter(part)
                .filter(|o| o.job.condition == condition),
        );
        if t.cases > 0 {
            rates.assembly_conditions.push((condition, t.rate()));
        }
        let _ = writeln!(table, "{}", t.row(condition.name()));
    }
}

/// The groups of `rates` below `floor(group)`, in words.
fn below<T: Copy>(
    rates: &[(T, f64)],
    floor: impl Fn(T) -> f64,
    name: impl Fn(T) -> String,
) -> Vec<String> {
    rates
        .iter()
        .filter(|(g, r)| *r < floor(*g))
        .map(|(g, r)| {
            format!(
                "{} {:.1} % < {:.1} %",
                name(*g),
                100.0 * r,
                100.0 * floor(*g)
            )
        })
        .collect()
}

fn env_usize(name: &str) -> Option<usize> {
    std::env::var(name).ok().and_then(|v| v.trim().parse().ok())
}

/// The issue's acceptance: ≥ 95 % per kind and per assembly kind, ≥ 90 % per condition.
#[test]
#[ignore = "today's snapper misses the targets: 40 cases per kind and condition, 8 \
            assemblies per kind and condition (release): single primitives 82.5 % \
            (cylinder 82.0, cone 87.8, sphere 99.5, box 91.5, SGC 88.8, BGC 45.8); \
            conditions plain 92.5, near-axial 59.6, side-on 88.8, missing 92.1, overshoots \
            83.3, sketchy 89.2, joined 80.0, fragments 84.6, slanted 79.6, rough 75.8; \
            assembly parts 87.3 % (stack 91.4, table 82.7 with tops 68.8, ball+tubes 98.4, \
            brick+studs 92.6, box+pipes 96.4, handle 92.0, tee 86.5, plug 76.9, valves \
            88.1, menorah 79.6); assembly conditions from 64.0 (near-axial) to 95.0 \
            (plain), sketchy 94.2, rough 84.6; wrong parts called doubtful or refused 334 \
            of 839 (39.8 %), good ones 197 of 4879 (4.0 %)"]
fn conditions_meet_the_issue_targets() {
    meet_the_issue_targets(Drops::Rough, "drawing conditions (acceptance)");
}

/// The acceptance run of parts dropped as `drops` says: asserts the issue's targets.
fn meet_the_issue_targets(drops: Drops, title: &str) {
    let mut run = Run::from_env(
        env_usize("GEOSNAP_SYNTH_CONDITION_CASES").unwrap_or(ACCEPTANCE_CASES),
        env_usize("GEOSNAP_SYNTH_CONDITION_ASSEMBLIES").unwrap_or(ACCEPTANCE_ASSEMBLIES),
        &ACCEPTANCE_KINDS,
    );
    run.drops = drops;
    let start = Instant::now();
    let (outcomes, failures) = run_all(&run);
    let rates = report(title, &run, &outcomes, &failures, start.elapsed());
    if run.show.is_some() {
        // One case shown for a diagnosis: no rates to judge.
        return;
    }
    let mut missed = below(
        &rates.kinds,
        |_| REQUIRED_KIND_RATE,
        |k| k.name().to_owned(),
    );
    missed.extend(below(
        &rates.conditions,
        |_| REQUIRED_CONDITION_RATE,
        |c| c.name().to_owned(),
    ));
    missed.extend(below(
        &rates.assemblies,
        |_| REQUIRED_KIND_RATE,
        |k| k.name().to_owned(),
    ));
    missed.extend(below(
        &rates.assembly_conditions,
        |_| REQUIRED_CONDITION_RATE,
        |c| format!("assemblies {}", c.name()),
    ));
    missed.extend(confidence_misses(rates.flags, 0.90));
    assert!(
        missed.is_empty(),
        "below the issue's targets: {} (table above)",
        missed.join(", ")
    );
}

/// The point drops' acceptance run: as [`conditions_meet_the_issue_targets`], each part
/// dropped as the palette drops it, at a point, with no size and no direction
/// ([`Drops::Point`]). A user who lets go of a part without sizing it with the wheel
/// meets this, and so does a script step that gives only `at`.
#[test]
#[ignore = "today's snapper misses the targets from a point drop: 40 cases per kind and \
            condition, 8 assemblies per kind and condition (release): single primitives \
            81.5 % (cylinder 81.2, cone 85.8, sphere 99.2, box 91.0, SGC 83.2, BGC 48.2), \
            conditions from 60.4 (near-axial) to 92.1 (plain); assembly parts 66.7 % \
            (stack 80.3, table 50.3, ball+tubes 96.2, brick+studs 68.8, box+pipes 89.2, \
            handle 74.9, tee 64.0, plug 57.3, valves 51.9, menorah 56.7) before the \
            region's guesses; with them and one scale for a drop's readings, at 10 cases \
            and 2 assemblies: single 83.2 %, assembly parts 77.6 % (table 62.9, \
            brick+studs 89.3, plug 68.6, valves 73.8, menorah 65.3); with readings cut \
            at the lines they hold inside: single 83.2 %, assembly parts 79.4 % (table \
            71.1, brick+studs 90.3, plug 70.0, valves 76.2, menorah 67.6)"]
fn point_drops_meet_the_issue_targets() {
    meet_the_issue_targets(Drops::Point, "point drops (acceptance)");
}

/// Single cases per kind and condition of the point drops' floor test.
const POINT_FLOOR_CASES: usize = 2;

/// Today's floor of the point drops' floor test ([`POINT_FLOOR_CASES`], 20 cases per
/// kind): single parts found from a point drop, per kind, a few points under the rate
/// measured (cylinder 80 %, cone 100 %, sphere 95 %, box 100 %, SGC 85 %, BGC 55 %). Sized
/// by the palette's default instead (the strokes under the point), the acceptance set's
/// point drops found 7.8 % of the cylinders, none of the spheres, 3.8 % of the boxes.
const POINT_KIND_FLOOR: [(PrimitiveKind, f64); 6] = [
    (PrimitiveKind::Cylinder, 0.7),
    (PrimitiveKind::Cone, 0.9),
    (PrimitiveKind::Sphere, 0.9),
    (PrimitiveKind::Cuboid, 0.9),
    (PrimitiveKind::Sgc, 0.75),
    (PrimitiveKind::Bgc, 0.45),
];

/// The assembly kinds of the point drops' floor test, one per condition: those whose
/// thin parts (legs, prongs, planks) a guess in the palette's proportions misses, and
/// bricks, whose studs a reading spanning two of them took when each reading was
/// weighed at its own scale.
const POINT_FLOOR_ASSEMBLIES: [AssemblyKind; 4] = [
    AssemblyKind::Table,
    AssemblyKind::BrickStuds,
    AssemblyKind::Plug,
    AssemblyKind::Valves,
];

/// Today's floor of the point drops' floor test's assembly parts, a few points under
/// the rate measured (table 72.3 %, brick+studs 92.5 %, plug 74.3 %, valves 80.0 %).
/// Without a reading cut at the lines it holds inside (`snap/cut.rs`) they were 66.0,
/// 90.6, 74.3 and 77.5 %; with each reading of a drop weighed at its own guess's scale
/// instead of one, 68.1, 75.5, 62.9 and 75.0 %; guessed in the palette's proportions
/// alone, without the region round the point, table, plug and valves were 51.1, 57.1
/// and 60.0 %.
const POINT_ASSEMBLY_FLOOR: [(AssemblyKind, f64); 4] = [
    (AssemblyKind::Table, 0.68),
    (AssemblyKind::BrickStuds, 0.85),
    (AssemblyKind::Plug, 0.7),
    (AssemblyKind::Valves, 0.7),
];

/// The floor `floors` sets for `key`, 0 where it sets none.
fn floor_in<K: PartialEq + Copy>(floors: &[(K, f64)], key: K) -> f64 {
    floors
        .iter()
        .find(|(k, _)| *k == key)
        .map_or(0.0, |(_, f)| *f)
}

/// A part dropped at a point, with no size and no direction (as the palette drops it
/// unless the wheel sized it), lands on its part: the drawing sizes and turns the drop.
#[test]
fn point_drops_stay_above_todays_floor() {
    let mut run = Run::from_env(POINT_FLOOR_CASES, 1, &POINT_FLOOR_ASSEMBLIES);
    run.drops = Drops::Point;
    let start = Instant::now();
    let (outcomes, failures) = run_all(&run);
    let rates = report(
        "point drops (floor)",
        &run,
        &outcomes,
        &failures,
        start.elapsed(),
    );
    if run.show.is_some() {
        return;
    }
    let mut missed = below(
        &rates.kinds,
        |k| floor_in(&POINT_KIND_FLOOR, k),
        |k| k.name().to_owned(),
    );
    missed.extend(below(
        &rates.assemblies,
        |k| floor_in(&POINT_ASSEMBLY_FLOOR, k),
        |k| k.name().to_owned(),
    ));
    assert!(
        missed.is_empty(),
        "point drops below today's floor (a regression): {} (table above)",
        missed.join(", ")
    );
}

/// The Hausdorff distance between the projected spines of two bent tubes, as a fraction
/// of the first one's projected length (∞ for other kinds).
fn spine_apart(truth: &Primitive, fit: &Primitive) -> f64 {
    let (Primitive::Bgc(a), Primitive::Bgc(b)) = (truth, fit) else {
        return f64::INFINITY;
    };
    let dense = |line: Vec<DVec2>| -> Vec<DVec2> {
        line.windows(2)
            .flat_map(|w| (0..20).map(move |i| w[0].lerp(w[1], f64::from(i) / 20.0)))
            .chain(line.last().copied())
            .collect()
    };
    let (p, q) = (dense(a.projected_spine()), dense(b.projected_spine()));
    let one_way = |from: &[DVec2], to: &[DVec2]| {
        from.iter()
            .map(|x| {
                to.iter()
                    .map(|y| x.distance(*y))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    let length: f64 = a
        .projected_spine()
        .windows(2)
        .map(|w| w[0].distance(w[1]))
        .sum();
    one_way(&p, &q).max(one_way(&q, &p)) / length.max(f64::MIN_POSITIVE)
}

/// Bent tubes drawn across a post (see `bgc_across_post`) per run of the junction test.
const POST_CASES: u64 = 16;
/// Today's floor of that test (9 of 16; 13 of the same tubes drawn without the post):
/// tubes whose projected spine lands within 6 % of its length of the truth's.
const POST_FLOOR: usize = 9;

/// A bent tube whose outlines run on across a post drawn through its end (a candlestick's
/// arm meeting its stem) ends at the post: the post's outlines, crossing its own, tell
/// where the tube meets another part, and its fit does not run on along its outlines. The
/// end is judged in the drawing (the projected spine within 6 % of its length of the
/// truth's, as the shared sketches' tubes are): the hidden end shows no tilt.
#[test]
fn bent_tubes_end_where_a_post_crosses_their_outlines() {
    let mut good = 0;
    let mut failures = String::new();
    for i in 0..POST_CASES {
        let seed = 0x7057_0000 + i;
        let scene = bgc_across_post(seed);
        let context = SnapContext::from_sketch(&sketch_of(&scene.strokes));
        let mut rng = Rng::new(seed ^ 0xD80F_D80F);
        let place = perturbed_placement(&scene.truth, &mut rng, Perturbation::ISSUE_16);
        let dropped = Primitive::from_placement(PrimitiveKind::Bgc, &place, scene.truth.size());
        let result = snap(&context, &dropped, &SnapSettings::default());
        if let Some(folder) = std::env::var_os("GEOSNAP_SYNTH_CONDITION_PNG") {
            let path = PathBuf::from(folder).join(format!("post_{i:03}.png"));
            let points: Vec<&[DVec2]> = scene.strokes.iter().map(|s| s.points.as_slice()).collect();
            let snapped = result.as_ref().ok().map(|r| &r.primitive);
            let _ = write_overlay(&path, &points, &scene.truth, &dropped, snapped);
        }
        match result {
            Ok(r) => {
                let apart = spine_apart(&scene.truth, &r.primitive);
                if apart <= 0.06 {
                    good += 1;
                } else {
                    let _ = writeln!(
                        failures,
                        "  seed {seed:#x}: spine {:.0} % of its length away",
                        100.0 * apart
                    );
                }
            }
            Err(e) => {
                let _ = writeln!(failures, "  seed {seed:#x}: {e}");
            }
        }
    }
    println!("bent tubes across a post: {good} of {POST_CASES} good\n{failures}");
    assert!(
        good >= POST_FLOOR,
        "{good} of {POST_CASES} bent tubes across a post good, below today's floor {POST_FLOOR}:\n{failures}"
    );
}

/// Drawings where a drop a hand made a quarter too big, a little off its part, read
/// its neighbours' strokes and settled on the wrong reading (a table leg on the next
/// leg, a stacked tier over its neighbour, a box across its pipe), each with the part
/// concerned: the drop shrunk by a fifth is tried too, and each lands on its part. A
/// yardstick of that mechanism, not a target: every one of these failed before it.
/// (`table:plain:6` part 2 left the list when an end stopped taking a piece of a line
/// that runs on through it, see `snap::assign`: its shrunk drop now settles on a fit
/// three times worse than the one from the truth; the pieces it no longer takes had
/// steered it home.)
const SHRUNK_DROP_CASES: [(&str, usize); 7] = [
    ("table:plain:7", 3),
    ("table:missing:7", 2),
    ("table:overshoots:5", 1),
    ("stack:joined:0", 1),
    ("box+pipes:overshoots:5", 0),
    ("cuboid:fragments:6", 0),
    ("sgc:joined:10", 0),
];

#[test]
fn drops_made_too_big_among_neighbours_land_on_their_part() {
    let failures = cases_that_miss(&SHRUNK_DROP_CASES);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Drawings where the best snap of a drop had kept strokes it took within the wide gate,
/// or read a box as its mirror image in depth, each with the part concerned: the best
/// snap is read again at the tight gate from where it ended (and a box from its mirror
/// image too, see `snap::rereads`), and each lands on its part. A yardstick of that
/// mechanism, not a target: every one of these failed before it. (`plug:plain:2`'s body
/// was one; since a box's starts also stand where its own edges lie on drawn lines, a
/// start read with the wrong sizes leads its snap, and the body fails again.)
const REREAD_CASES: [(&str, usize); 9] = [
    ("cylinder:side-on:18", 0),
    ("cone:fragments:36", 0),
    ("cuboid:side-on:9", 0),
    ("cuboid:near-axial:38", 0),
    ("sgc:joined:14", 0),
    ("box+pipes:side-on:4", 0),
    ("table:missing:5", 0),
    ("menorah:side-on:0", 0),
    ("handle:joined:5", 1),
];

/// Blades of plugs and a plug's body, whose box starts read off the strokes near the
/// drop stood between two blades (the middle of the bounds of both blades' edges): a
/// start also stands where the box's own edges lie on drawn lines, the nearest the drop
/// (`snap/initial/aligned.rs`), and each lands on its part. A yardstick of that
/// mechanism, not a target: every one of these failed before it.
const ALIGNED_CASES: [(&str, usize); 6] = [
    ("plug:plain:3", 2),
    ("plug:slanted:3", 1),
    ("plug:joined:5", 1),
    ("plug:side-on:3", 2),
    ("plug:near-axial:7", 3),
    ("plug:slanted:7", 0),
];

#[test]
fn boxes_beside_twins_start_on_their_own_edges_and_land_on_their_part() {
    let failures = cases_that_miss(&ALIGNED_CASES);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Parts read as one part round themselves and a neighbour drawn alike (a plug's blades,
/// a table's legs, a menorah's candles), or round a line of their own drawing, where
/// the reading cut at the straight line it holds inside (`snap/cut.rs`) lands on the
/// part: from a hand's drop, then from a point. A yardstick of that mechanism, not a
/// target: every one of these failed before it.
const CUT_CASES: [(&str, usize); 4] = [
    ("cylinder:side-on:7", 0),
    ("plug:sketchy:0", 1),
    ("plug:slanted:0", 1),
    ("menorah:sketchy:0", 0),
];

/// As [`CUT_CASES`], dropped at a point (see `point_drops_meet_the_issue_targets`).
const CUT_POINT_CASES: [(&str, usize); 2] = [("table:plain:1", 4), ("table:fragments:1", 2)];

#[test]
fn readings_round_two_parts_are_cut_at_the_line_between_them() {
    let mut failures = cases_that_miss(&CUT_CASES);
    failures.extend(cases_that_miss_from(&CUT_POINT_CASES, Drops::Point));
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn snaps_read_again_from_where_they_ended_land_on_their_part() {
    let failures = cases_that_miss(&REREAD_CASES);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Cases of the rough hand (every line gone over 2–3 times, a few percent apart, half
/// the later times over a stretch of it only) that the snap misses while a curve keeps
/// only the closest of a line's copies, which holds the fit on one copy, off the line
/// meant; with the copies kept (`snap/copies.rs`) the fit settles in their middle. One
/// of each kind but the bent tube, and parts of assemblies.
const COPY_CASES: [(&str, usize); 10] = [
    ("sphere:rough:5", 0),
    ("cylinder:rough:2", 0),
    ("cone:rough:12", 0),
    ("cuboid:rough:5", 0),
    ("sgc:rough:0", 0),
    ("ball+tubes:rough:3", 0),
    ("brick+studs:rough:0", 1),
    ("table:rough:2", 4),
    ("menorah:rough:2", 3),
    ("valves:rough:1", 0),
];

#[test]
fn lines_gone_over_several_times_snap_to_the_middle_of_their_copies() {
    let failures = cases_that_miss(&COPY_CASES);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The cases (`subject:condition:index`, part) whose part is not recovered, each with
/// its report.
fn cases_that_miss(cases: &[(&str, usize)]) -> Vec<String> {
    cases_that_miss_from(cases, Drops::Rough)
}

/// [`cases_that_miss`] with the parts dropped as `drops` says.
fn cases_that_miss_from(cases: &[(&str, usize)], drops: Drops) -> Vec<String> {
    let mut failures = Vec::new();
    for (name, part) in cases {
        let mut fields = name.split(':');
        let job = (|| {
            Some(Job {
                subject: Subject::from_name(fields.next()?)?,
                condition: Condition::from_name(fields.next()?)?,
                index: fields.next()?.parse().ok()?,
            })
        })()
        .expect("a case name");
        let (outcomes, report) = run_job(job, drops, 1.0, false, None);
        let outcome = outcomes
            .iter()
            .find(|o| o.part.unwrap_or(0) == *part)
            .expect("the part's outcome");
        if !outcome.ok() {
            failures.push(format!("{name} part {part}: {report}"));
        }
    }
    failures
}

/// Where the confidences miss: more than [`MAX_GOOD_FLAGGED`] of the good parts called
/// doubtful or refused, or less than `wrong_floor` of the wrong parts.
fn confidence_misses(flags: Flags, wrong_floor: f64) -> Vec<String> {
    let mut missed = Vec::new();
    if flags.good_flagged as f64 > MAX_GOOD_FLAGGED * flags.good as f64 {
        missed.push(format!(
            "{} of {} good parts called doubtful or refused (at most {:.0} %)",
            flags.good_flagged,
            flags.good,
            100.0 * MAX_GOOD_FLAGGED
        ));
    }
    if (flags.wrong_flagged as f64) < wrong_floor * flags.wrong as f64 {
        missed.push(format!(
            "{} of {} wrong parts called doubtful or refused (at least {:.0} %)",
            flags.wrong_flagged,
            flags.wrong,
            100.0 * wrong_floor
        ));
    }
    missed
}

/// Today's rates, minus a few points, hold on a small fixed set of cases.
#[test]
fn conditions_stay_above_todays_floor() {
    let run = Run::from_env(FLOOR_CASES, FLOOR_ASSEMBLIES, &AssemblyKind::ISSUE_16);
    let start = Instant::now();
    let (outcomes, failures) = run_all(&run);
    let rates = report(
        "drawing conditions (floor)",
        &run,
        &outcomes,
        &failures,
        start.elapsed(),
    );
    if run.show.is_some() {
        // One case shown for a diagnosis: no rates to judge.
        return;
    }
    let lookup = |table: &[(PrimitiveKind, f64)], k: PrimitiveKind| {
        table.iter().find(|(x, _)| *x == k).map_or(0.0, |(_, f)| *f)
    };
    let mut missed = below(
        &rates.kinds,
        |k| lookup(&KIND_FLOOR, k),
        |k| k.name().to_owned(),
    );
    missed.extend(below(
        &rates.conditions,
        |c| {
            CONDITION_FLOOR
                .iter()
                .find(|(x, _)| *x == c)
                .map_or(0.0, |(_, f)| *f)
        },
        |c| c.name().to_owned(),
    ));
    missed.extend(below(
        &rates.assemblies,
        |k| {
            ASSEMBLY_FLOOR
                .iter()
                .find(|(x, _)| *x == k)
                .map_or(0.0, |(_, f)| *f)
        },
        |k| k.name().to_owned(),
    ));
    missed.extend(below(
        &rates.assembly_conditions,
        |c| {
            ASSEMBLY_CONDITION_FLOOR
                .iter()
                .find(|(x, _)| *x == c)
                .map_or(0.0, |(_, f)| *f)
        },
        |c| format!("assemblies {}", c.name()),
    ));
    missed.extend(confidence_misses(rates.flags, WRONG_FLAGGED_FLOOR));
    assert!(
        missed.is_empty(),
        "below today's floor (a regression): {} (table above)",
        missed.join(", ")
    );
}

/// Drawn with a perfect hand in the plain, near-axial and side-on views, every stroke of
/// the wider shapes lies on a visible projected curve of its truth, and every visible
/// curve is drawn (for an SGC or a BGC, whose short outlines in steep views may lie
/// nearer an end ellipse than their own contour, only the first): the conditioned
/// renderer draws what the primitives project to.
/// Cylinders, cones, spheres and boxes agree to 1e-5 of the size. An SGC's and a BGC's
/// smooth surfaces are approximated by the model from eight samples: their strokes are
/// allowed [`SMOOTH_TOL`] of the size (see `synthetic_snap`'s renderer test for where
/// the approximation is worst: the outlines' ends).
#[test]
fn the_conditioned_renderer_draws_the_projected_curves() {
    let perfect = support::synth::Style::perfect();
    let mut worst: BTreeMap<&'static str, f64> = BTreeMap::new();
    for kind in PrimitiveKind::ALL {
        for condition in [Condition::Plain, Condition::NearAxial, Condition::SideOn] {
            for index in 0..6 {
                let job = Job {
                    subject: Subject::Single(kind),
                    condition,
                    index,
                };
                let s = scene_with(kind, job.seed(), condition, false, Some(perfect));
                let size = s.truth.size();
                let smooth = matches!(kind, PrimitiveKind::Sgc | PrimitiveKind::Bgc);
                let tol = if smooth { SMOOTH_TOL } else { 1e-5 };
                let shape = s.truth.current_shape();
                let mut drawn = vec![false; shape.curves.len()];
                for stroke in &s.strokes {
                    let points: Vec<DVec2> =
                        stroke.points.iter().map(|p| view_from_sketch(*p)).collect();
                    let best = shape
                        .curves
                        .iter()
                        .enumerate()
                        .filter(|(_, c)| c.visible)
                        .map(|(k, c)| {
                            let off = points
                                .iter()
                                .step_by(3)
                                .map(|p| distance_to(&c.curve, *p) / size)
                                .fold(0.0, f64::max);
                            (off, k)
                        })
                        .min_by(|a, b| a.0.total_cmp(&b.0));
                    let Some((off, k)) = best else {
                        panic!("{}: no curve for {}", job.name(), stroke.label)
                    };
                    let w = worst.entry(kind.name()).or_default();
                    *w = w.max(off);
                    assert!(
                        off <= tol,
                        "{}: stroke {} is {:.4} of the size off its curve {}",
                        job.name(),
                        stroke.label,
                        off,
                        shape.curves[k].name
                    );
                    drawn[k] = true;
                }
                for (curve, drawn) in shape.curves.iter().zip(&drawn) {
                    // A smooth primitive's short outlines in steep views may lie nearer
                    // its end ellipses than its own (approximate) contours.
                    assert!(
                        !curve.visible || *drawn || smooth,
                        "{}: the visible curve {} is not drawn",
                        job.name(),
                        curve.name
                    );
                }
            }
        }
    }
    println!(
        "conditioned renderer, worst stroke offset per kind (fraction of the size): {worst:?}"
    );
}
