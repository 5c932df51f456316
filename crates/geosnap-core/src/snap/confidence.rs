//! How sure a snap is: a verdict built from the evidence of the drawing, not from the fit
//! RMS alone.
//!
//! A snap can fit its strokes closely and still be wrong: a tube laid on the wrong pair of
//! strokes fits them at 1 % RMS. What tells a wrong part from a right one is what the
//! rest of the drawing says about it. [`judge`] weighs eight pieces of evidence (ten for a bent tube), each
//! turned into a factor in [0, 1] (1: no doubt):
//!
//! - **fit**: the RMS distance of its strokes to its curves, relative to its size;
//! - **support**: how much of its visible curves has a stroke near it (a designer draws
//!   what is visible; a pose whose outline runs where nothing is drawn is doubtful);
//! - **ownership**: how much of the stroke length it takes already belongs to parts placed
//!   before it (a part dropped on a modelled part, or one that reaches across it);
//! - **a placed part held**: whether a placed part whose strokes it takes lies inside
//!   its outline and spans it, its outline on the snap's on opposite sides (a chest read
//!   whole round a drawer placed before; see the `holds` module);
//! - **the drop**: how far the snap moved from where it was dropped, and how much it
//!   changed size (a rough drop lands near its part: a hand misses a part's centre by a
//!   tenth of its size, so a snap that moved more than a third of it is doubted);
//! - **ambiguity**: the margin over the best *other* reading the snap found (a pose
//!   whose outline differs, explaining the drawing about as well);
//! - **depth**: how well the drawing shows the part's length at all ([`depth`]): a part
//!   seen almost along its axis shows its length only through the flatness of its end
//!   ellipses, and the strokes' own noise leaves it loose;
//! - **pinning**: how tightly its strokes pin each dimension ([`Spread`]): the spread of
//!   its position, direction, radii and lengths that the strokes' noise leaves, read from
//!   the fit's curvature, with how far its own strokes would still move it. This is the
//!   general form of the depth evidence: it also sees a box seen square-on, a tube that
//!   can turn in depth, an end that nothing drawn fixes. Depth and pinning weigh one
//!   doubt, so the weaker of the two counts, once;
//! - **a bent tube's run and width** (bent tubes only): how much longer its spine is than
//!   the spine's drawing (a tube that runs mostly in depth draws almost the same outlines
//!   over a range of tilts, told apart only by how round its end ellipses are drawn), and
//!   how much wider than dropped it grew (two neighbouring tubes read as one fat one).
//!
//! The confidence is the product of the factors; the weakest factor names the reason.
//! A snap is *good* at a confidence of at least 0.5, *refused* below 0.1 and *doubtful*
//! in between. Every ramp is relative to the part's size or to its own curves,
//! never to a number of pixels, so the verdict means the same at any scale.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::assign::{curve_distance, curve_length};
use super::{Alternative, Dimension, SnapResult, Spread};
use crate::primitive::{Curve2, CurveClass, Primitive, Shape};
use crate::sketch::StrokeId;

/// A confidence at or above this is a good snap.
pub(crate) const GOOD: f64 = 0.5;
/// A confidence below this is a refused snap.
pub(crate) const REFUSED: f64 = 0.1;

/// What a snap's confidence says.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// The evidence agrees: the part can be trusted.
    Good,
    /// Some evidence speaks against it; the reason says which, and the snap's
    /// alternatives are the other readings it found.
    Doubtful,
    /// The evidence speaks clearly against it: the part should not be placed as snapped.
    Refused,
}

impl Verdict {
    /// The verdict's name as the model file writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Good => "good",
            Self::Doubtful => "doubtful",
            Self::Refused => "refused",
        }
    }

    /// The verdict called `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::Good, Self::Doubtful, Self::Refused]
            .into_iter()
            .find(|v| v.name() == name)
    }
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The evidence a verdict rests on; every length is relative (see the fields).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Evidence {
    /// Fit RMS over the part's size.
    pub rms: f64,
    /// The fraction of the length of its visible curves that has a stroke within the
    /// gate.
    pub support: f64,
    /// The fraction of the stroke length it takes that belongs to parts placed before it.
    pub owned: f64,
    /// The part that owns most of that length, if any.
    pub owner: Option<u32>,
    /// How far its outline lies from that part's (the mean distance between their
    /// visible curves, relative to the larger size); `None` when no part owns its strokes
    /// or the owner's pose is unknown.
    pub apart_from_owner: Option<f64>,
    /// Projected distance of the snapped centre from the dropped one, over the dropped
    /// size.
    pub moved: f64,
    /// How much its size in the view changed, as a factor ≥ 1 either way.
    pub resized: f64,
    /// How much more of the drawing the snap explains than its best other reading, over
    /// the length of its visible curves; `None` when it found no other reading.
    pub margin: Option<f64>,
    /// How loosely the drawing pins the part's extent in depth: the relative error of its
    /// length along the axis nearest the view direction that the strokes' own noise
    /// leaves (the module docs say how); 0 for a sphere and for parts seen from the side.
    pub depth: f64,
    /// How tightly the drawing pins its dimensions ([`Spread`]); `None` when the fit's
    /// curvature could not be read.
    pub spread: Option<Spread>,
    /// A placed part whose strokes it takes and which lies inside its outline, spanning
    /// it (`holds` module): the snap reads that part and its neighbours as one.
    pub holds: Option<u32>,
}

/// A snap's confidence: the verdict, its value in [0, 1] and, when not good, why.
#[derive(Clone, Debug, PartialEq)]
pub struct Confidence {
    /// Good, doubtful or refused.
    pub verdict: Verdict,
    /// The product of the evidence factors, in [0, 1].
    pub value: f64,
    /// What speaks most against the snap, in words; `None` for a good snap.
    pub reason: Option<String>,
    /// The evidence.
    pub evidence: Evidence,
}

/// A linear ramp: 1 at or below `full`, 0 at or above `none`.
fn ramp(x: f64, full: f64, none: f64) -> f64 {
    if !x.is_finite() {
        return 0.0;
    }
    ((none - x) / (none - full)).clamp(0.0, 1.0)
}

/// The fraction of the length of `primitive`'s visible curves that has a point of the
/// assigned strokes within `gate`, and that length. Each curve counts only its own
/// strokes; an end ellipse is fully supported when half of it is drawn.
pub(crate) fn support(primitive: &Primitive, result: &SnapResult, gate: f64) -> (f64, f64) {
    let gate = gate.max(f64::MIN_POSITIVE);
    let shape = primitive.current_shape();
    let (mut covered, mut total) = (0.0, 0.0);
    for (curve, strokes) in shape.curves.iter().zip(&result.assignment.curves) {
        if !curve.visible {
            continue;
        }
        let length = curve_length(&curve.curve);
        let points = super::holds::curve_samples(&curve.curve, gate / 2.0);
        let near = points
            .iter()
            .filter(|p| {
                strokes
                    .iter()
                    .flat_map(|s| s.samples.windows(2))
                    .any(|w| crate::geom::segment_distance(w[0], w[1], **p) <= gate)
            })
            .count();
        // An end is drawn whole when it faces the viewer and as its front half when it
        // faces away: half an end ellipse is all a drawing owes it.
        let owed = match (curve.class, &curve.curve) {
            (CurveClass::Feature, Curve2::Ellipse { .. }) => 0.5,
            _ => 1.0,
        };
        let fraction = near as f64 / points.len().max(1) as f64;
        covered += length * (fraction / owed).min(1.0);
        total += length;
    }
    if total > 0.0 {
        (covered / total, total)
    } else {
        (0.0, 0.0)
    }
}

/// The fraction of the stroke length `result` takes that `owner` gives to another part,
/// and the parts that own some of it, the one that owns most first. A piece between two
/// samples is owned when both its ends are, by the owner of the first.
fn owned(result: &SnapResult, owner: &dyn Owner) -> (f64, Vec<u32>) {
    let mut total = 0.0;
    let mut by_owner: Vec<(u32, f64)> = Vec::new();
    for stroke in result.assignment.curves.iter().flatten() {
        let owners: Vec<Option<u32>> = stroke
            .samples
            .iter()
            .map(|p| owner.owner(stroke.stroke, *p))
            .collect();
        for (w, o) in stroke.samples.windows(2).zip(owners.windows(2)) {
            let length = w[0].distance(w[1]);
            total += length;
            if let (Some(part), Some(_)) = (o[0], o[1]) {
                match by_owner.iter_mut().find(|(p, _)| *p == part) {
                    Some(entry) => entry.1 += length,
                    None => by_owner.push((part, length)),
                }
            }
        }
    }
    if total <= 0.0 {
        return (0.0, Vec::new());
    }
    let owned: f64 = by_owner.iter().map(|(_, l)| l).sum();
    by_owner.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    (
        owned / total,
        by_owner.into_iter().map(|(p, _)| p).collect(),
    )
}

/// The mean distance from the visible curves of `a` to those of `b` (each sampled),
/// the larger of the two directions, over the larger size: 0 for two poses that look
/// the same (a pose and its mirror image in depth), about a tenth for a box read the
/// other way round.
pub(crate) fn outline_distance(a: &Primitive, b: &Primitive) -> f64 {
    let (sa, sb) = (a.current_shape(), b.current_shape());
    let visible = |s: &Shape<f64>| {
        s.curves
            .iter()
            .filter(|c| c.visible)
            .map(|c| c.curve.clone())
            .collect::<Vec<_>>()
    };
    let (ca, cb) = (visible(&sa), visible(&sb));
    let one_way = |from: &[Curve2<f64>], to: &[Curve2<f64>]| {
        let points: Vec<DVec2> = from.iter().flat_map(|c| c.points(24)).collect();
        if points.is_empty() || to.is_empty() {
            return f64::INFINITY;
        }
        points
            .iter()
            .map(|p| {
                to.iter()
                    .map(|c| curve_distance(c, *p))
                    .fold(f64::INFINITY, f64::min)
            })
            .sum::<f64>()
            / points.len() as f64
    };
    one_way(&ca, &cb).max(one_way(&cb, &ca)) / a.size().max(b.size()).max(f64::MIN_POSITIVE)
}

/// The size of `primitive`'s image: twice the farthest any point of its projected
/// curves lies from their centroid.
fn image_size(primitive: &Primitive) -> f64 {
    let shape = primitive.current_shape();
    let points: Vec<DVec2> = shape
        .curves
        .iter()
        .flat_map(|c| c.curve.points(24))
        .collect();
    if points.is_empty() {
        return primitive.size();
    }
    let centroid = points.iter().copied().sum::<DVec2>() / points.len() as f64;
    2.0 * points
        .iter()
        .map(|p| p.distance(centroid))
        .fold(0.0, f64::max)
}

/// The least error of a drawn cross-section's aspect ratio (minor over major axis of an
/// end ellipse, or a face's foreshortening), whatever the fit RMS says: a hand that
/// draws a circle in perspective misjudges its flatness by a percent or more, and the fit
/// follows the ellipse drawn, so its RMS does not show it.
const HAND_ASPECT: f64 = 0.01;

/// How loosely a drawing pins `primitive`'s lengths in depth, as a relative error, given
/// the fit RMS `rms` (view units).
///
/// A drawing shows a length L along a unit axis a as its projection ℓ = L·√(1 − a_z²),
/// and it shows a_z only through the flatness of a cross-section at right angles to the
/// axis: an end circle's image has minor/major = |a_z|, a face's image is foreshortened
/// by |a_z|. An error σ of that ratio gives L an error dL/L = |a_z|·σ / (1 − a_z²):
/// nothing for a part seen from the side, a few percent at 45°, and without bound as the
/// axis turns towards the viewer, where the drawing shows the length of nothing. σ is the
/// strokes' RMS over the cross-section's radius, at least [`HAND_ASPECT`]. The drawn
/// length ℓ itself is known only to the strokes' RMS: a thin disc whose two ellipses lie
/// a hand's wobble apart shows its thickness barely at all (rms/ℓ). The two errors add in
/// quadrature. A box has a
/// length along each of its axes (its cross-section is the face across it); the largest
/// error counts. A sphere has no axis, and a bent tube's depth is read from its end
/// ellipses and its plane together: 0 for both.
pub(crate) fn depth(primitive: &Primitive, rms: f64) -> f64 {
    let along = |axis: DVec3, length: f64, radius: f64| {
        let az = axis.z.abs().min(1.0);
        let sin2 = (1.0 - az * az).max(1e-12);
        let sigma = (rms / radius.max(f64::MIN_POSITIVE)).max(HAND_ASPECT);
        let tilt = az * sigma / sin2;
        let drawn = rms / (length * sin2.sqrt()).max(f64::MIN_POSITIVE);
        tilt.hypot(drawn)
    };
    match primitive {
        Primitive::Cylinder(c) => along(c.axis, c.length, c.radius),
        Primitive::Cone(c) => along(c.axis, c.length, c.radius_bottom.max(c.radius_top)),
        Primitive::Sgc(s) => along(
            s.axis,
            s.length,
            s.radii.iter().copied().fold(0.0, f64::max),
        ),
        Primitive::Cuboid(b) => {
            let s = b.size;
            let axes = b.axes();
            [(0, s.y + s.z), (1, s.x + s.z), (2, s.x + s.y)]
                .into_iter()
                .map(|(i, across)| along(axes[i], s[i], across / 4.0))
                .fold(0.0, f64::max)
        }
        Primitive::Sphere(_) | Primitive::Bgc(_) => 0.0,
    }
}

/// Two readings whose outlines are farther apart than this (relative to the size) are
/// different readings of the drawing.
pub(crate) const DISTINCT: f64 = 0.04;

/// What the parts placed before a snap say about it: which of them, if any, owns a
/// sample (view-plane point) of a stroke, and where each of them lies.
///
/// Any `Fn(StrokeId, DVec2) -> Option<u32>` is an owner that knows no poses (such as
/// [`nobody`]); [`crate::model::Document::owner`] knows both.
pub trait Owner {
    /// The placed part that took `sample` of `stroke`, if any.
    fn owner(&self, stroke: StrokeId, sample: DVec2) -> Option<u32>;

    /// Placed part `part` as it lies now, if known.
    fn pose(&self, part: u32) -> Option<Primitive> {
        let _ = part;
        None
    }
}

impl<F: Fn(StrokeId, DVec2) -> Option<u32>> Owner for F {
    fn owner(&self, stroke: StrokeId, sample: DVec2) -> Option<u32> {
        self(stroke, sample)
    }
}

/// No part owns any stroke: the first part of a model.
pub fn nobody(_: StrokeId, _: DVec2) -> Option<u32> {
    None
}

/// How much longer a bent tube's spine is than its drawing (1 for every other kind).
fn depth_ratio(primitive: &Primitive) -> f64 {
    let Primitive::Bgc(b) = primitive else {
        return 1.0;
    };
    let drawn: f64 = b
        .projected_spine()
        .windows(2)
        .map(|w| w[0].distance(w[1]))
        .sum();
    b.spine_length() / drawn.max(f64::MIN_POSITIVE)
}

/// How many times wider than dropped a bent tube snapped (its widest radius over the
/// dropped one's; 1 for every other kind): a tube that grew far wider than the hand
/// showed took the outlines of something else (two neighbouring tubes as one).
fn widening(primitive: &Primitive, dropped: &Primitive) -> f64 {
    let (Primitive::Bgc(b), Primitive::Bgc(d)) = (primitive, dropped) else {
        return 1.0;
    };
    let widest = |r: &[f64]| r.iter().fold(0.0f64, |m, x| m.max(*x));
    widest(&b.radii) / widest(&d.radii).max(f64::MIN_POSITIVE)
}

/// The factors only a bent tube has: how far it runs in depth and how much wider than
/// dropped it grew (both 1 for every other kind).
fn tube_factors(primitive: &Primitive, dropped: &Primitive) -> [(f64, String); 2] {
    let depth = depth_ratio(primitive);
    let widened = widening(primitive, dropped);
    [
        (
            0.4 + 0.6 * ramp(depth, 1.3, 2.0),
            format!(
                "it runs mostly in depth (its spine is {depth:.1}× as long as drawn), which only its end ellipses tell"
            ),
        ),
        (
            ramp(widened, 2.0, 4.0),
            format!("it grew {widened:.1}× as wide as dropped: it is not the tube pointed at"),
        ),
    ]
}

/// Judges `result`, a snap of `dropped`; `owner` tells which placed part, if any, owns a
/// piece of stroke; `gate` is the distance (view units) within which a stroke supports a
/// curve.
pub fn judge(result: &SnapResult, dropped: &Primitive, owner: &dyn Owner, gate: f64) -> Confidence {
    let primitive = &result.primitive;
    let size = primitive.size().max(f64::MIN_POSITIVE);
    let rms = result.rms / size;
    let (support, visible_length) = support(primitive, result, gate);
    let (owned, owners) = owned(result, owner);
    let owner_id = owners.first().copied();
    let band = super::swallow_band(result);
    let holds = owners.iter().copied().find(|&part| {
        owner
            .pose(part)
            .is_some_and(|pose| super::holds::holds(primitive, &pose, band))
    });
    let apart_from_owner = owner_id
        .and_then(|id| owner.pose(id))
        .map(|pose| outline_distance(primitive, &pose));
    let moved = (primitive.center().truncate() - dropped.center().truncate()).length()
        / dropped.size().max(f64::MIN_POSITIVE);
    // Sizes as drawn: a drop lies in the view plane at its drawn length, and a part seen
    // along its axis rightly snaps far longer in 3D than it was dropped.
    let factor = image_size(primitive) / image_size(dropped).max(f64::MIN_POSITIVE);
    let resized = factor.max(1.0 / factor);
    let rival: Option<&Alternative> = result.alternatives.first();
    let margin = rival.map(|alt| {
        (result.explained.unwrap_or(0.0) - alt.explained) / visible_length.max(f64::MIN_POSITIVE)
    });
    let depth = depth(primitive, result.rms);
    let spread = super::spread::spread(primitive, &result.assignment, result.rms, result.profile);
    let evidence = Evidence {
        rms,
        support,
        owned,
        owner: owner_id,
        apart_from_owner,
        moved,
        resized,
        margin,
        depth,
        spread,
        holds,
    };
    let mut factors = weigh(&evidence, factor, rival).to_vec();
    factors.extend(tube_factors(primitive, dropped));
    let value = factors.iter().map(|(f, _)| f).product::<f64>();
    let value = if value.is_finite() {
        value.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let verdict = if value >= GOOD {
        Verdict::Good
    } else if value >= REFUSED {
        Verdict::Doubtful
    } else {
        Verdict::Refused
    };
    let reason = (verdict != Verdict::Good).then(|| {
        factors
            .iter()
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, why)| why.clone())
            .unwrap_or_default()
    });
    Confidence {
        verdict,
        value,
        reason,
        evidence,
    }
}

/// The evidence as factors in [0, 1], each with what it says against the snap in words;
/// `factor` is the image's size over the drop's, `rival` the best other reading.
fn weigh(evidence: &Evidence, factor: f64, rival: Option<&Alternative>) -> [(f64, String); 7] {
    let Evidence {
        rms,
        support,
        owned,
        owner: owner_id,
        apart_from_owner,
        moved,
        resized,
        margin,
        depth,
        spread,
        holds,
    } = *evidence;
    [
        (
            ramp(rms, 0.02, 0.08),
            format!(
                "its strokes fit it loosely (RMS {:.1} % of its size)",
                100.0 * rms
            ),
        ),
        (
            ramp(1.0 - support, 0.3, 0.7),
            format!(
                "only {:.0} % of its visible outline is drawn",
                100.0 * support
            ),
        ),
        ownership(owned, owner_id, apart_from_owner),
        holds.map_or((1.0, String::new()), |p| {
            (
                HOLDS,
                format!(
                    "part #{p} lies inside it with its outline on it: it reads that part and \
                     its neighbours as one"
                ),
            )
        }),
        (
            ramp(moved, 0.35, 1.0) * ramp(resized, 2.5, 4.5),
            format!(
                "it landed far from the drop (moved {:.0} % of the dropped size, size ×{:.1})",
                100.0 * moved,
                factor
            ),
        ),
        (
            margin.map_or(1.0, |m| 0.3 + 0.7 * ramp(-m, -0.15, 0.0)),
            match rival {
                Some(alt) => format!(
                    "another reading explains the drawing about as well (a {} {:.0} % of the size away)",
                    alt.primitive.kind().name(),
                    100.0 * alt.distance
                ),
                None => String::new(),
            },
        ),
        loosest(
            (
                ramp(depth, 0.12, 0.4).max(0.3),
                format!(
                    "it is seen almost along its axis, so the drawing barely shows its length \
                     (about ±{:.0} %)",
                    100.0 * depth
                ),
            ),
            pinned(spread.as_ref()),
        ),
    ]
}

/// The factor of a snap that holds a placed part (`holds` module): doubtful on its own,
/// refused with any other doubt beside it. A reading of several parts as one fits and
/// explains its strokes as well as the part meant, so nothing else speaks against it.
const HOLDS: f64 = 0.25;

/// A part whose strokes belong to placed parts at least this much has nothing drawn of
/// its own: a hand's stray fragment aside, every stroke it takes is already explained.
const ALL_OWNED: f64 = 0.95;

/// The factor of how much of its strokes placed parts own, with what it says. A part
/// dropped on a modelled part is doubted (it may be meant to replace it, or to double
/// it). A part that takes only strokes other parts explain, and is not one of them
/// (its outline `apart` from the main owner's by more than [`DISTINCT`]), explains
/// nothing in the drawing: a drop on empty paper that reached a neighbour's outline, or
/// a part bridging two placed ones. It is refused.
fn ownership(owned: f64, owner: Option<u32>, apart: Option<f64>) -> (f64, String) {
    let Some(p) = owner else {
        return (1.0, String::new());
    };
    if owned >= ALL_OWNED && apart.is_some_and(|d| d > DISTINCT) {
        return (
            0.0,
            format!(
                "all its strokes belong to placed parts (most to part #{p}, which it does \
                 not match): nothing drawn there is its own"
            ),
        );
    }
    (
        ramp(owned, 0.7, 1.0).max(0.3),
        format!(
            "{:.0} % of its strokes belong to part #{p} already",
            100.0 * owned
        ),
    )
}

/// The weaker of two factors that weigh one doubt (how loosely the drawing holds the
/// part: along its axis, and in every dimension), so that it is not counted twice.
fn loosest(a: (f64, String), b: (f64, String)) -> (f64, String) {
    if b.0 < a.0 {
        b
    } else {
        a
    }
}

/// A part is pinned when each dimension's spread lies within these of a recovered part's
/// tolerances: the projected centre within 3 % of the size, the axis within 5°, radii and
/// lengths within 7 %.
const PINNED: (f64, f64, f64) = (0.03, 5.0 * std::f64::consts::PI / 180.0, 0.07);

/// The factor of how tightly the drawing pins the part ([`Spread`]), with what it says:
/// 1 while the worst dimension's spread is within 1.5 tolerances, falling to 0.3 at 5
/// (alone, a dimension the drawing leaves 4 tolerances loose makes the part doubtful:
/// at that spread most snaps miss it). No spread, no doubt.
fn pinned(spread: Option<&Spread>) -> (f64, String) {
    let Some(spread) = spread else {
        return (1.0, String::new());
    };
    let (worst, dimension) = spread.worst(PINNED.0, PINNED.1, PINNED.2);
    let value = spread.of(dimension);
    let how = match dimension {
        Dimension::Direction => format!("{:.0}°", value.to_degrees()),
        Dimension::Position => format!("{:.0} % of its size", 100.0 * value),
        Dimension::Radius | Dimension::Length => format!("{:.0} %", 100.0 * value),
    };
    let name = dimension.name();
    let why = if worst.is_finite() {
        format!("its strokes pin its {name} only to about ±{how}")
    } else {
        format!("its strokes do not pin its {name}")
    };
    (0.3 + 0.7 * ramp(worst, 1.5, 5.0), why)
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::{depth, nobody, Owner, Verdict};
    use crate::model::Document;
    use crate::primitive::{Cuboid, Cylinder, Primitive};
    use crate::sketch::{StrokeClass, StrokeId};
    use crate::snap::initial::tests::turned_box;
    use crate::snap::{snap, SnapContext, SnapSettings};

    /// A cylinder seen from the side and a little above (axis up the page): its two
    /// outlines, its top ellipse and the front arc of its bottom, in sketch space.
    fn drawn_cylinder() -> (SnapContext, Primitive) {
        let (x0, x1, top, bottom, b) = (40.0, 80.0, 100.0, 220.0, 6.0);
        let line = |x: f64| {
            (0..=30)
                .map(|i| DVec2::new(x, top + (bottom - top) * f64::from(i) / 30.0))
                .collect::<Vec<_>>()
        };
        let arc = |y: f64, from: f64, to: f64| {
            (0..=48)
                .map(|i| {
                    let t = from + (to - from) * f64::from(i) / 48.0;
                    DVec2::new(60.0 + 20.0 * t.cos(), y + b * t.sin())
                })
                .collect::<Vec<_>>()
        };
        let strokes = [
            (line(x0), StrokeClass::Silhouette),
            (line(x1), StrokeClass::Silhouette),
            (arc(top, 0.0, std::f64::consts::TAU), StrokeClass::Feature),
            (arc(bottom, 0.0, std::f64::consts::PI), StrokeClass::Feature),
        ];
        let context = SnapContext::new(
            strokes
                .iter()
                .enumerate()
                .map(|(i, (p, c))| (StrokeId(i as u32), p.as_slice(), *c)),
        );
        let dropped = Primitive::Cylinder(Cylinder {
            center: DVec3::new(63.0, -165.0, 0.0),
            axis: DVec3::new(0.05, 1.0, 0.2).normalize(),
            length: 105.0,
            radius: 17.0,
        });
        (context, dropped)
    }

    #[test]
    fn a_part_on_its_own_drawing_is_good() {
        let (context, dropped) = drawn_cylinder();
        let settings = SnapSettings::default();
        let result = snap(&context, &dropped, &settings).expect("it snaps");
        let confidence = result.confidence(&dropped, &nobody, &settings);
        assert_eq!(confidence.verdict, Verdict::Good, "{confidence:?}");
        assert!(confidence.reason.is_none(), "{confidence:?}");
        assert!(confidence.evidence.support > 0.7, "{confidence:?}");
    }

    #[test]
    fn a_pose_its_strokes_do_not_hold_is_doubtful_for_the_dimension_they_would_change() {
        let (context, dropped) = drawn_cylinder();
        let settings = SnapSettings::default();
        let mut result = snap(&context, &dropped, &settings).expect("it snaps");
        let Primitive::Cylinder(fitted) = &result.primitive else {
            unreachable!("a cylinder snaps to a cylinder")
        };
        result.primitive = Primitive::Cylinder(Cylinder {
            length: 1.4 * fitted.length,
            ..*fitted
        });
        let confidence = result.confidence(&dropped, &nobody, &settings);
        assert_ne!(confidence.verdict, Verdict::Good, "{confidence:?}");
        let spread = confidence.evidence.spread.expect("a spread");
        assert!(spread.length > 0.2, "{spread:?}");
    }

    #[test]
    fn a_part_made_only_of_another_parts_strokes_is_refused() {
        let (context, dropped) = drawn_cylinder();
        let settings = SnapSettings::default();
        let first = snap(&context, &dropped, &settings).expect("it snaps");
        let mut document = Document::new();
        let id = document.add_snapped(&first);
        // The same strokes read as a cylinder half as wide again: not the placed part,
        // and nothing in the drawing is its own.
        let mut wider = first.clone();
        let Primitive::Cylinder(c) = &mut wider.primitive else {
            panic!("a cylinder");
        };
        c.radius *= 1.5;
        let confidence = wider.confidence(&dropped, &document.owner(), &settings);
        assert_eq!(confidence.verdict, Verdict::Refused, "{confidence:?}");
        assert!(confidence.value < 1e-12, "{confidence:?}");
        assert!(confidence
            .evidence
            .apart_from_owner
            .is_some_and(|d| d > 0.04));
        let reason = confidence.reason.unwrap_or_default();
        assert!(reason.contains(&format!("part #{}", id.0)), "{reason}");
        assert!(
            reason.contains("nothing drawn there is its own"),
            "{reason}"
        );
        // An owner that knows no poses cannot tell it from the placed part.
        let owner = document.owner();
        let strokes_only = |stroke, sample| owner.owner(stroke, sample);
        let blind = wider.confidence(&dropped, &strokes_only, &settings);
        assert!(blind.value > 0.0, "{blind:?}");
        assert_eq!(blind.evidence.apart_from_owner, None);
    }

    #[test]
    fn a_part_dropped_on_a_modelled_part_is_doubtful_and_names_it() {
        let (context, dropped) = drawn_cylinder();
        let settings = SnapSettings::default();
        let first = snap(&context, &dropped, &settings).expect("it snaps");
        let mut document = Document::new();
        let id = document.add_snapped(&first);
        let again = snap(&context, &dropped, &settings).expect("it snaps again");
        let confidence = again.confidence(&dropped, &document.owner(), &settings);
        assert_eq!(confidence.verdict, Verdict::Doubtful, "{confidence:?}");
        assert_eq!(confidence.evidence.owner, Some(id.0));
        let reason = confidence.reason.unwrap_or_default();
        assert!(reason.contains(&format!("part #{}", id.0)), "{reason}");
    }

    #[test]
    fn a_box_with_most_of_its_edges_undrawn_is_doubtful() {
        let truth = turned_box();
        let full = crate::snap::initial::tests::drawn(&truth);
        let settings = SnapSettings::default();
        let dropped = Primitive::Cuboid(Cuboid {
            center: truth.center + DVec3::new(0.03, -0.02, 0.0) * truth.size.max_element(),
            ..truth.clone()
        });
        let good = snap(&full, &dropped, &settings).expect("it snaps");
        assert_eq!(
            good.confidence(&dropped, &nobody, &settings).verdict,
            Verdict::Good
        );
        // Three of its nine visible edges: enough to fit, not enough to trust.
        let sparse = SnapContext::of(full.strokes.iter().take(3).cloned().collect());
        let result = snap(&sparse, &dropped, &settings).expect("three edges fit a box");
        let confidence = result.confidence(&dropped, &nobody, &settings);
        assert_ne!(confidence.verdict, Verdict::Good, "{confidence:?}");
        assert!(confidence.evidence.support < 0.5, "{confidence:?}");
        // Three edges leave the box free to slide and stretch along the undrawn ones:
        // the fit is flat there, and the reason says so.
        let spread = confidence.evidence.spread.expect("a spread");
        assert!(spread.length.is_infinite(), "{spread:?}");
        let reason = confidence.reason.unwrap_or_default();
        assert!(reason.contains("do not pin"), "{reason}");
    }

    fn cylinder(axis: DVec3, length: f64, radius: f64) -> Primitive {
        Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: axis.normalize(),
            length,
            radius,
        })
    }

    #[test]
    fn the_length_is_loose_only_when_seen_along_the_axis() {
        let rms = 0.5;
        let at = |z: f64| depth(&cylinder(DVec3::new(1.0, 0.0, z), 100.0, 20.0), rms);
        // From the side the drawing shows the length as drawn; at 45° a few percent;
        // towards the view axis it grows without bound.
        assert!(at(0.0) < 0.01, "{}", at(0.0));
        assert!(at(1.0) < 0.05, "{}", at(1.0));
        assert!(at(6.0) > 0.1, "{}", at(6.0));
        let mut last = 0.0;
        for z in [0.0, 0.5, 1.0, 2.0, 4.0, 8.0] {
            assert!(at(z) >= last, "not monotonic at {z}");
            last = at(z);
        }
        // The same pose drawn more roughly pins it less.
        let rough = depth(&cylinder(DVec3::new(1.0, 0.0, 2.0), 100.0, 20.0), 3.0);
        assert!(rough > at(2.0), "{rough} vs {}", at(2.0));
    }

    #[test]
    fn a_disc_whose_ellipses_lie_a_wobble_apart_has_a_loose_thickness() {
        // A disc of radius 100 and thickness 10 seen at 60° from its axis: its two
        // ellipses lie under 9 units apart, and a hand that wobbles by 3 hardly shows it.
        let disc = cylinder(DVec3::new(0.0, 1.0, 0.5), 10.0, 100.0);
        assert!(depth(&disc, 3.0) > 0.3, "{}", depth(&disc, 3.0));
        // The same drawn cleanly, or a rod at the same angle, shows its length well.
        let rod = cylinder(DVec3::new(0.0, 1.0, 0.5), 200.0, 10.0);
        assert!(depth(&disc, 0.1) < 0.05, "{}", depth(&disc, 0.1));
        assert!(depth(&rod, 1.0) < 0.1, "{}", depth(&rod, 1.0));
    }

    #[test]
    fn a_box_seen_face_on_has_a_loose_depth_and_a_sphere_none() {
        let face_on = Primitive::Cuboid(Cuboid {
            center: DVec3::ZERO,
            rotation: glam::DQuat::from_rotation_x(0.1),
            size: DVec3::new(100.0, 80.0, 60.0),
        });
        assert!(depth(&face_on, 1.0) > 0.1, "{}", depth(&face_on, 1.0));
        assert!(depth(&Primitive::Cuboid(turned_box()), 1.0) < 0.1);
        let sphere = Primitive::Sphere(crate::primitive::Sphere {
            center: DVec3::ZERO,
            radius: 10.0,
        });
        assert!(depth(&sphere, 5.0).abs() < f64::EPSILON);
    }

    #[test]
    fn a_snap_that_wandered_from_its_drop_is_doubtful() {
        let (context, dropped) = drawn_cylinder();
        let settings = SnapSettings::default();
        let result = snap(&context, &dropped, &settings).expect("it snaps");
        // Judged against a drop far away and much smaller: the same snap did not land
        // where the user meant.
        let far = dropped.transformed(DVec3::new(150.0, 0.0, 0.0), 0.25);
        let confidence = result.confidence(&far, &nobody, &settings);
        assert_ne!(confidence.verdict, Verdict::Good, "{confidence:?}");
        let reason = confidence.reason.unwrap_or_default();
        assert!(reason.contains("far from the drop"), "{reason}");
    }

    /// A chest of two drawers, 90 wide, 30 high and 60 deep each, turned so that three
    /// faces face the viewer: the whole chest and its drawers (upper, lower), with the
    /// chest's visible edges drawn once each, a stroke per edge, and the line between
    /// the drawers across its two visible sides.
    fn drawn_chest() -> (SnapContext, Primitive, [Primitive; 2]) {
        let turn = glam::DQuat::from_rotation_x(0.5) * glam::DQuat::from_rotation_y(0.6);
        let up = turn * DVec3::Y;
        let cuboid = |center: DVec3, size: DVec3| {
            Primitive::Cuboid(Cuboid {
                center,
                rotation: turn,
                size,
            })
        };
        let size = DVec3::new(90.0, 30.0, 60.0);
        let whole = cuboid(DVec3::new(200.0, -200.0, 0.0), DVec3::new(90.0, 60.0, 60.0));
        let drawers = [
            cuboid(whole.center() + up * 15.0, size),
            cuboid(whole.center() - up * 15.0, size),
        ];
        // Each visible edge of the chest, and each visible edge of a drawer that no
        // edge of the chest covers (the line between them).
        let mut strokes: Vec<Vec<DVec2>> = Vec::new();
        let edges = |p: &Primitive| -> Vec<Vec<DVec2>> {
            p.current_shape()
                .curves
                .iter()
                .filter(|c| c.visible)
                .map(|c| c.curve.points(20))
                .collect()
        };
        let chest_edges = edges(&whole);
        strokes.extend(chest_edges.iter().cloned());
        let on_chest = |e: &[DVec2]| {
            e.iter().all(|p| {
                chest_edges
                    .iter()
                    .flat_map(|c| c.windows(2))
                    .any(|w| crate::geom::segment_distance(w[0], w[1], *p) < 0.5)
            })
        };
        for drawer in &drawers {
            for e in edges(drawer) {
                let seen = strokes
                    .iter()
                    .any(|s| e.iter().all(|p| s.iter().any(|q| q.distance(*p) < 0.5)));
                if !on_chest(&e) && !seen {
                    strokes.push(e);
                }
            }
        }
        let sketch: Vec<Vec<DVec2>> = strokes
            .iter()
            .map(|s| {
                s.iter()
                    .map(|p| crate::geom::projection::sketch_from_view(*p))
                    .collect()
            })
            .collect();
        let context = SnapContext::new(
            sketch
                .iter()
                .enumerate()
                .map(|(i, p)| (StrokeId(i as u32), p.as_slice(), StrokeClass::Silhouette)),
        );
        (context, whole, drawers)
    }

    #[test]
    fn a_snap_that_holds_a_placed_drawer_with_its_neighbour_is_doubted() {
        let (context, whole, [upper, lower]) = drawn_chest();
        let settings = SnapSettings::default();
        let placed = snap(&context, &upper, &settings).expect("the upper drawer snaps");
        let mut document = Document::new();
        let id = document.add_snapped(&placed);
        // The lower drawer dropped, read as the whole chest: it takes the upper drawer's
        // strokes and holds it.
        let mut read_whole = snap(&context, &lower, &settings).expect("the lower drawer snaps");
        read_whole.primitive = whole.clone();
        read_whole.assignment = crate::snap::assign(
            &context,
            &whole.current_shape().curves,
            settings.tight_gate * whole.size(),
        );
        read_whole.rms = crate::snap::fit_rms(&whole, &read_whole.assignment);
        read_whole.alternatives.clear();
        let blind = read_whole.confidence(&lower, &nobody, &settings);
        assert_eq!(
            blind.verdict,
            Verdict::Good,
            "with no part placed: {blind:?}"
        );
        let confidence = read_whole.confidence(&lower, &document.owner(), &settings);
        assert_eq!(confidence.evidence.holds, Some(id.0), "{confidence:?}");
        assert_ne!(confidence.verdict, Verdict::Good, "{confidence:?}");
        let reason = confidence.reason.unwrap_or_default();
        assert!(
            reason.contains(&format!("part #{} lies inside it", id.0)),
            "{reason}"
        );
        // The lower drawer read as itself shares an edge with the placed one and holds
        // nothing.
        let own = snap(&context, &lower, &settings).expect("the lower drawer snaps");
        let own = own.confidence(&lower, &document.owner(), &settings);
        assert_eq!(own.evidence.holds, None, "{own:?}");
    }
}
