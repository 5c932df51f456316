//! Curve assignment: which strokes correspond to which projected curves of a primitive
//! at a given pose.
//!
//! Each stroke is tested against each visible projected curve whose class it suits
//! (feature strokes for end ellipses, silhouette strokes for outlines, straight strokes
//! of either class for box edges; a stroke of the other class is still accepted at a
//! threefold worse score, so a misclassified stroke is not lost); once the pose is
//! fitted, against the hidden ones too, which keep what they win from the visible ones
//! (a box's hidden edges, drawn by a designer who draws hidden lines). The distances of
//! the stroke's samples to the curve decide:
//! - a stroke whose samples lie within the *gate* (a distance relative to the
//!   primitive's size, never an absolute number of pixels; for an ellipse, at most its
//!   semi-major axis; once the pose is fitted, for an outline at most the distance to
//!   the part's own outline across from it, see `assign_within`) for at least 80 % is
//!   taken whole;
//! - a longer stroke that runs along the curve for at least half the curve's length is
//!   taken for that part only (one stroke may outline two stacked parts);
//! - among the curves a stroke qualifies for, the closest wins;
//! - within a curve, only strokes that fit about as well as its best one stay (twice the
//!   best score plus a tenth of the gate; once the pose is fitted, of the curve's own
//!   gate, so that an end ellipse judges by its radius, not by the part's length), so
//!   that a neighbouring part's stroke that merely passes the gate does not drag the fit
//!   (a cup's small bottom ellipse set on a long stem's end); once the pose is fitted, a
//!   stroke this drops stays when it is a hand's copy of one kept, the same line gone
//!   over again a little apart (`copies`), so that the fit settles in their middle.
//!
//! An end ellipse takes no straight piece of a stroke that runs on straight past the
//! piece (a neighbour's outline through the sliver of an end seen from the side).
//!
//! Straight strokes must also run within 35° of a straight curve's direction. Several
//! strokes may share a curve (a silhouette drawn in pieces, gaps are normal), and a stroke
//! may serve several primitives. One stroke may also serve several curves of one part, in
//! pieces (a U drawn down an outline, round an end and back up; an L round a box corner):
//! even a stroke that one outline's gate takes whole is split where other curves draw
//! runs of it several times more closely (a U round a thin tube's end lies within either
//! outline's gate). The result depends only on the inputs (no hashing, no
//! threads), so it is deterministic.

use glam::DVec2;

use super::context::{SnapContext, SnapStroke};
use crate::ad::ellipse_distance;
pub(crate) use crate::geom::segment_distance;
use crate::primitive::{Curve2, CurveClass, ProjectedCurve};
use crate::sketch::{StrokeClass, StrokeId};

/// Samples of one stroke that a curve takes.
#[derive(Clone, Debug, PartialEq)]
pub struct AssignedStroke {
    /// The stroke.
    pub stroke: StrokeId,
    /// The samples used, in view-plane coordinates (all of the stroke, or the part that
    /// runs along the curve).
    pub samples: Vec<DVec2>,
    /// Mean distance of the samples to the curve at assignment time.
    pub mean_distance: f64,
    /// When only part of the stroke runs along the curve, the indices of the samples
    /// taken among [`stroke_samples`] of the stroke, ascending; `None` when the whole
    /// stroke is taken. With the stroke id this is all a file needs to store to
    /// [`restore_assignment`].
    pub part: Option<Vec<usize>>,
}

/// The strokes assigned to each projected curve of one primitive.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Assignment {
    /// One entry per projected curve of the primitive's shape, in order.
    pub curves: Vec<Vec<AssignedStroke>>,
}

impl Assignment {
    /// The ids of all assigned strokes, sorted and without repeats.
    pub fn stroke_ids(&self) -> Vec<StrokeId> {
        let mut ids: Vec<StrokeId> = self.curves.iter().flatten().map(|a| a.stroke).collect();
        ids.sort_unstable();
        ids.dedup();
        ids
    }

    /// Whether curve `k` has at least one stroke.
    pub fn has(&self, k: usize) -> bool {
        self.curves.get(k).is_some_and(|c| !c.is_empty())
    }

    /// The same strokes per curve (ignoring samples), for telling whether a re-assignment
    /// changed anything.
    pub fn same_strokes(&self, other: &Self) -> bool {
        self.curves.len() == other.curves.len()
            && self
                .curves
                .iter()
                .zip(&other.curves)
                .all(|(a, b)| a.iter().map(|s| s.stroke).eq(b.iter().map(|s| s.stroke)))
    }
}

/// The distance from `p` to a numeric curve.
pub(crate) fn curve_distance(curve: &Curve2<f64>, p: DVec2) -> f64 {
    match curve {
        Curve2::Ellipse { center, a, b } => {
            ellipse_distance(center.to_dvec2(), a.to_dvec2(), b.to_dvec2(), p).0
        }
        Curve2::Polyline(points) => points
            .windows(2)
            .map(|w| segment_distance(w[0].to_dvec2(), w[1].to_dvec2(), p))
            .fold(f64::INFINITY, f64::min),
    }
}

/// The length of a numeric curve (an ellipse's by Ramanujan's approximation).
pub(crate) fn curve_length(curve: &Curve2<f64>) -> f64 {
    match curve {
        Curve2::Ellipse { a, b, .. } => {
            // Conjugate semi-diameters → semi-axes via the singular values of [a b].
            let m = glam::DMat2::from_cols(a.to_dvec2(), b.to_dvec2());
            let (p, q) = singular_values(m);
            let h = ((p - q) / (p + q + f64::MIN_POSITIVE)).powi(2);
            std::f64::consts::PI * (p + q) * (1.0 + 3.0 * h / (10.0 + (4.0 - 3.0 * h).sqrt()))
        }
        Curve2::Polyline(points) => points
            .windows(2)
            .map(|w| w[0].to_dvec2().distance(w[1].to_dvec2()))
            .sum(),
    }
}

/// The singular values (larger first) of a 2×2 matrix.
pub(crate) fn singular_values(m: glam::DMat2) -> (f64, f64) {
    let (a, b, c, d) = (m.x_axis.x, m.y_axis.x, m.x_axis.y, m.y_axis.y);
    let s1 = (a * a + b * b + c * c + d * d) / 2.0;
    let s2 = (((a * a + b * b - c * c - d * d) / 2.0).powi(2) + (a * c + b * d).powi(2)).sqrt();
    ((s1 + s2).max(0.0).sqrt(), (s1 - s2).max(0.0).sqrt())
}

/// Whether a stroke suits a curve, and the score factor if it does. A sphere's outline is
/// an ellipse like an end's, and a closed elliptical stroke is classified a feature
/// whichever it draws, so feature strokes suit it fully.
fn suitability(curve: &ProjectedCurve<f64>, stroke: &SnapStroke) -> Option<f64> {
    match (curve.class, stroke.class) {
        (CurveClass::Silhouette, StrokeClass::Feature)
            if matches!(curve.curve, Curve2::Ellipse { .. }) =>
        {
            Some(1.0)
        }
        (CurveClass::Edge, _) if stroke.straight => Some(1.0),
        (CurveClass::Edge, _) => (stroke.straightness <= ROUGHLY_STRAIGHT).then_some(1.5),
        (CurveClass::Feature, StrokeClass::Feature)
        | (CurveClass::Silhouette, StrokeClass::Silhouette) => Some(1.0),
        _ => Some(3.0),
    }
}

/// The straightness (see [`SnapStroke::straightness`]) up to which a stroke that is not
/// quite straight may still draw a box edge, at a worse score: a short edge drawn by a
/// shaky hand.
pub(crate) const ROUGHLY_STRAIGHT: f64 = 0.06;

/// At most this many samples of a stroke are tested and used per curve.
const MAX_SAMPLES: usize = 32;

/// The samples of a stroke that assignment tests and takes: at most 32, evenly chosen
/// along it, its end points included (view-plane coordinates).
pub fn stroke_samples(stroke: &SnapStroke) -> Vec<DVec2> {
    subsample(&stroke.points)
}

/// The samples taken of a stroke: all of `samples`, or those at the indices of `part`;
/// `None` when an index is out of range or the indices are not strictly ascending.
fn taken(samples: &[DVec2], part: Option<&[usize]>) -> Option<Vec<DVec2>> {
    let Some(part) = part else {
        return Some(samples.to_vec());
    };
    if part.windows(2).any(|w| w[0] >= w[1]) {
        return None;
    }
    part.iter().map(|i| samples.get(*i).copied()).collect()
}

/// Evenly chosen samples of a stroke (its end points included).
fn subsample(points: &[DVec2]) -> Vec<DVec2> {
    if points.len() <= MAX_SAMPLES {
        return points.to_vec();
    }
    (0..MAX_SAMPLES)
        .map(|i| points[i * (points.len() - 1) / (MAX_SAMPLES - 1)])
        .collect()
}

/// Assigns strokes to the curves of `curves` (a primitive's projected curves at its
/// current pose), with the gate distance `gate` in view-plane units.
pub fn assign(context: &SnapContext, curves: &[ProjectedCurve<f64>], gate: f64) -> Assignment {
    assign_within(context, curves, gate, false)
}

/// As [`assign`], and when `fitted` (the curves are those of a fitted pose, not of a
/// hand's drop) an outline's gate is also no wider than the part itself there: see
/// `outline_caps`.
pub(crate) fn assign_within(
    context: &SnapContext,
    curves: &[ProjectedCurve<f64>],
    gate: f64,
    fitted: bool,
) -> Assignment {
    let caps = if fitted {
        outline_caps(curves)
    } else {
        vec![f64::INFINITY; curves.len()]
    };
    let mut assignment = Assignment {
        curves: vec![Vec::new(); curves.len()],
    };
    // Bounds of the primitive's curves, grown by the gate, to skip far strokes quickly.
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for c in curves {
        let (clo, chi) = curve_bounds(&c.curve);
        lo = lo.min(clo);
        hi = hi.max(chi);
    }
    lo -= DVec2::splat(gate);
    hi += DVec2::splat(gate);
    let reaches: Vec<Reach> = curves
        .iter()
        .zip(&caps)
        .map(|(c, cap)| Reach {
            length: curve_length(&c.curve),
            gate: curve_gate(&c.curve, gate).min(*cap),
            bounds: curve_bounds(&c.curve),
        })
        .collect();
    let widths = if fitted {
        super::copies::widths(curves)
    } else {
        Vec::new()
    };
    let mut scored: Vec<Vec<(f64, AssignedStroke)>> = vec![Vec::new(); curves.len()];
    for stroke in &context.strokes {
        let (slo, shi) = stroke.bounds;
        if shi.x < lo.x || shi.y < lo.y || slo.x > hi.x || slo.y > hi.y {
            continue;
        }
        for (score, k, c) in pieces(stroke, curves, &reaches, fitted) {
            scored[k].push((score, c));
        }
    }
    // Competition within a curve: keep the strokes that fit about as well as its best one
    // (twice its score plus a tenth of the gate), so a neighbouring part's stroke that
    // merely passes the gate does not drag the fit. Once the pose is fitted, a tenth of
    // the curve's own gate: a long stem's gate, set by its length, is many times its
    // end's radius, and a cup's smaller ellipse set on that end passed it. At a hand's
    // drop the part's gate, as rough as the drop: its best stroke may be a neighbour's.
    for ((k, candidates), reach) in scored.into_iter().enumerate().zip(&reaches) {
        let best = candidates
            .iter()
            .map(|(s, _)| *s)
            .fold(f64::INFINITY, f64::min);
        let slack = if fitted { reach.gate } else { gate };
        let allowed = 2.0 * best + 0.1 * slack;
        let (kept, dropped): (Vec<_>, Vec<_>) =
            candidates.into_iter().partition(|(s, _)| *s <= allowed);
        let mut kept: Vec<AssignedStroke> = kept.into_iter().map(|(_, c)| c).collect();
        // Once the pose is fitted, a stroke that copies a kept one (a line gone over
        // again a little apart, nearer to it than to the part's next line) stays: the
        // line meant is the middle of its copies.
        let within = widths.get(k).map_or(0.0, |w| 0.5 * w);
        let copies: Vec<AssignedStroke> = dropped
            .into_iter()
            .filter(|(score, c)| {
                super::copies::is_copy(&curves[k].curve, c, *score, &kept, allowed, within)
            })
            .map(|(_, c)| c)
            .collect();
        kept.extend(copies);
        assignment.curves[k] = kept;
    }
    assignment
}

/// The curves one stroke is assigned to, with its score for each: the curve it fits best,
/// and, when that takes only a piece of it, the curves that other pieces of it fit (a
/// stroke drawn round a corner, or one that runs down an outline, round an end and back
/// up the other outline). Pieces may not share more than a sample.
///
/// At a `fitted` pose a hidden curve (a box's edge behind it) competes for the strokes
/// as well, and what it wins no visible curve takes: a hidden edge drawn by a designer
/// who draws hidden lines, or a neighbour's stroke lying along one, is not a visible
/// edge's stroke. Seen nearly along an axis a box's far edges run close beside its near
/// ones, and a visible edge that took a hidden one's stroke tilted the box off its
/// drawing. At a hand's drop hidden curves do not compete: placed that roughly, a hidden
/// edge can lie on the part's own visible stroke.
fn pieces(
    stroke: &SnapStroke,
    curves: &[ProjectedCurve<f64>],
    reaches: &[Reach],
    fitted: bool,
) -> Vec<(f64, usize, AssignedStroke)> {
    let samples = subsample(&stroke.points);
    let mut candidates: Vec<Piece> = Vec::new();
    for (k, (curve, reach)) in curves.iter().zip(reaches).enumerate() {
        if !(curve.visible || fitted) || reach.beyond(stroke.bounds) {
            continue;
        }
        if let Some(piece) = candidate(stroke, &samples, k, curve, reach) {
            candidates.push(piece);
        }
    }
    candidates.sort_by(|a, b| a.score().total_cmp(&b.score()).then(a.k.cmp(&b.k)));
    accepted_pieces(candidates, samples.len())
        .into_iter()
        .filter(|piece| curves[piece.k].visible)
        .filter_map(|piece| {
            let part = (!piece.whole).then(|| piece.indices.clone());
            let mean_distance = piece.mean_distance();
            Some((
                mean_distance * piece.factor,
                piece.k,
                AssignedStroke {
                    stroke: stroke.id,
                    samples: taken(&samples, part.as_deref())?,
                    mean_distance,
                    part,
                },
            ))
        })
        .collect()
}

/// The piece of a stroke that suits curve `k`, if any: the whole stroke when nearly all
/// of its samples lie within the curve's gate (`gate`, at most `cap`), else the samples
/// that do, when there are enough of them to draw at least half of the curve's length
/// (`length`); and it must suit the curve by class and direction.
fn candidate(
    stroke: &SnapStroke,
    samples: &[DVec2],
    k: usize,
    curve: &ProjectedCurve<f64>,
    reach: &Reach,
) -> Option<Piece> {
    let (gate, length) = (reach.gate, reach.length);
    let d: Vec<f64> = samples
        .iter()
        .map(|p| curve_distance(&curve.curve, *p))
        .collect();
    let near: Vec<usize> = (0..d.len()).filter(|i| d[*i] <= gate).collect();
    let part = if near.len() * 5 >= d.len() * 4 {
        None
    } else {
        let near_length = near.len() as f64 / d.len() as f64 * stroke.length;
        if near.len() < 4 || near_length < 0.5 * length {
            return None;
        }
        Some(near)
    };
    // A piece is judged by its own shape: the straight leg of a stroke drawn round a
    // box corner draws an edge, though the whole stroke is not straight.
    let piece;
    let judged = match &part {
        None => stroke,
        Some(near) => {
            let points: Vec<DVec2> = near.iter().map(|i| samples[*i]).collect();
            piece = super::context::prepare(stroke.id, points, stroke.class)?;
            &piece
        }
    };
    let factor = suitability(curve, judged)?;
    if !direction_ok(&curve.curve, judged) {
        return None;
    }
    if let (Some(near), Curve2::Ellipse { a, b, .. }) = (&part, &curve.curve) {
        let (reach, _) = singular_values(glam::DMat2::from_cols(a.to_dvec2(), b.to_dvec2()));
        if curve.class == CurveClass::Feature
            && judged.straightness <= ROUGHLY_STRAIGHT
            && runs_on_past(samples, near, reach)
        {
            return None;
        }
    }
    Some(Piece {
        factor,
        k,
        whole: part.is_none(),
        gate,
        outline: curve.class == CurveClass::Silhouette,
        reach: stroke.length / length.max(f64::MIN_POSITIVE),
        indices: part.unwrap_or_else(|| (0..samples.len()).collect()),
        distances: d,
    })
}

/// Whether a stroke whose samples `near` (ascending indices among `samples`) make a
/// straight piece runs on straight past that piece's either end by more than `reach`:
/// then the piece is part of a line passing by, not a curve of its own. Seen from the
/// side, an end ellipse is a sliver that a short straight stroke draws; but where a part
/// ends on another's outline (an arm on a stem, a branch on a main pipe), the other's
/// outline runs straight through that sliver and on, and a piece of it is not the end.
/// A U's arc is not such a piece: its outlines leave it at a right angle.
fn runs_on_past(samples: &[DVec2], near: &[usize], reach: f64) -> bool {
    let (Some(&first), Some(&last)) = (near.first(), near.last()) else {
        return false;
    };
    let (p, q) = (samples[first], samples[last]);
    let Some(u) = (q - p).try_normalize() else {
        return false;
    };
    // Along the piece's line from `from`, the stroke's samples in order: whether they
    // pass `reach` beyond it before leaving the line by half of `reach`.
    let on_past = |order: &mut dyn Iterator<Item = usize>, from: DVec2, sign: f64| {
        for k in order {
            let v = samples[k] - from;
            if v.perp_dot(u).abs() > 0.5 * reach {
                return false;
            }
            if sign * v.dot(u) > reach {
                return true;
            }
        }
        false
    };
    on_past(&mut (0..first).rev(), p, -1.0) || on_past(&mut (last + 1..samples.len()), q, 1.0)
}

/// How far a curve reaches for strokes: its gate (`curve_gate`, within its outline cap),
/// its length and its bounds.
struct Reach {
    length: f64,
    gate: f64,
    bounds: (DVec2, DVec2),
}

impl Reach {
    /// Whether every point within `bounds` (a stroke's) lies beyond the gate of the
    /// curve: the gap between the two boxes exceeds it, with a margin far above the
    /// rounding of a measured distance. No sample of such a stroke can be near the curve,
    /// so [`candidate`] would find nothing; measuring its distances (an ellipse's costs
    /// a search) is spared.
    fn beyond(&self, (lo, hi): (DVec2, DVec2)) -> bool {
        let (clo, chi) = self.bounds;
        let gap = (clo - hi).max(lo - chi).max(DVec2::ZERO);
        let scale = clo.abs().max(chi.abs()).max_element() + self.gate;
        gap.length() > self.gate + 1e-9 * scale
    }
}

/// The pieces accepted from candidates sorted best first. With a candidate that takes
/// the stroke whole: the pieces [`split_from_whole`] finds, if any; else that candidate
/// alone, when it is the best. Else the pieces, each sample going to the nearest curve
/// among those whose pieces hold it, and a piece left with fewer than 4 samples or less
/// than half of its own dropped.
fn accepted_pieces(mut candidates: Vec<Piece>, sample_count: usize) -> Vec<Piece> {
    if let Some(w) = candidates.iter().position(|p| p.whole) {
        // The best whole candidate first: a U round a thin tube's end lies within the
        // wide gate of either outline, and only its pieces draw them.
        let whole = candidates.remove(w);
        candidates.insert(0, whole);
        if let Some(split) = split_from_whole(&candidates, w, sample_count) {
            return split;
        }
        if w == 0 {
            // The stroke fits one curve whole: it draws that curve.
            candidates.truncate(1);
            return candidates;
        }
    }
    // Pieces: where two meet (a corner, an outline running into its end), a sample near
    // both curves goes to the nearer; a piece left with less than half of its samples
    // was mostly another curve's and is dropped.
    candidates.retain(|p| !p.whole);
    let owner = owners(&candidates, sample_count);
    let mut kept = Vec::new();
    for (c, mut piece) in candidates.into_iter().enumerate() {
        let before = piece.indices.len();
        piece.indices.retain(|i| owner[*i] == Some(c));
        if piece.indices.len() >= 4 && 2 * piece.indices.len() >= before {
            kept.push(piece);
        }
    }
    kept
}

/// Per sample, the candidate nearest to it among those whose pieces hold it.
fn owners(candidates: &[Piece], sample_count: usize) -> Vec<Option<usize>> {
    (0..sample_count)
        .map(|i| {
            candidates
                .iter()
                .enumerate()
                .filter(|(_, p)| p.indices.binary_search(&i).is_ok())
                .min_by(|(_, a), (_, b)| a.distances[i].total_cmp(&b.distances[i]))
                .map(|(c, _)| c)
        })
        .collect()
}

/// How much more closely another curve must draw a run of a stroke than the curve that
/// takes it whole, for that run to be split off: its samples' mean distance to the whole
/// curve over their mean distance to their own.
const SPLIT_RATIO: f64 = 3.0;

/// A stroke that an outline (`candidates[0]`, which came `w`-th among the candidates
/// best first) takes whole, split where other curves draw runs of it far more closely:
/// each sample goes to the nearest candidate that holds it, and another outline's
/// samples, or those of a curve that fits its piece better than the outline fits the
/// whole stroke (one that came before it), split off when there are at least 4 and they
/// lie, on average, at least [`SPLIT_RATIO`] times further from the outline than from
/// their own curve and beyond a tenth of the outline's gate (farther than a hand's
/// wobble), and when the piece split off and the one left to the outline each draw at
/// least half of their curve (a neighbour's outline passing by under a thin part's wide
/// gate draws neither of its outlines). The rest stay
/// with the outline, which keeps them when at least 4 are left. `None` when nothing
/// splits off.
///
/// A stroke drawing one outline has every sample near it, so no run lies several times
/// further from it than from another curve; a U drawn down one outline of a thin tube,
/// round its end and back up the other lies within the wide gate of both outlines, and
/// only its pieces draw them. Only an outline is split so: a box edge keeps a stroke
/// whose tip runs on round a corner, as the hand overshot it.
fn split_from_whole(candidates: &[Piece], w: usize, sample_count: usize) -> Option<Vec<Piece>> {
    // A stroke that one curve alone can take (the common case, on every drag frame) has
    // nothing to split off.
    if candidates.len() < 2 {
        return None;
    }
    let whole = candidates.first().filter(|w| w.whole && w.outline)?;
    let owner = owners(candidates, sample_count);
    let mean = |indices: &[usize], distances: &[f64]| {
        indices.iter().map(|i| distances[*i]).sum::<f64>() / indices.len().max(1) as f64
    };
    let floor = 0.1 * whole.gate;
    let split: Vec<(usize, Vec<usize>)> = candidates
        .iter()
        .enumerate()
        .skip(1)
        .filter_map(|(c, piece)| {
            let mine: Vec<usize> = (0..sample_count).filter(|i| owner[*i] == Some(c)).collect();
            let (own, far) = (mean(&mine, &piece.distances), mean(&mine, &whole.distances));
            (mine.len() >= 4
                && draws_half(piece, mine.len())
                && (piece.outline || c <= w)
                && far >= SPLIT_RATIO * own
                && far > floor)
                .then_some((c, mine))
        })
        .collect();
    if split.is_empty() {
        return None;
    }
    let taken: Vec<usize> = split.iter().flat_map(|(_, mine)| mine.clone()).collect();
    let rest: Vec<usize> = (0..sample_count).filter(|i| !taken.contains(i)).collect();
    if !draws_half(whole, rest.len()) {
        return None;
    }
    let mut kept = Vec::new();
    for (c, piece) in candidates.iter().enumerate() {
        let indices = if c == 0 {
            rest.clone()
        } else if let Some((_, mine)) = split.iter().find(|(k, _)| *k == c) {
            mine.clone()
        } else {
            continue;
        };
        if indices.len() >= 4 {
            kept.push(Piece {
                factor: piece.factor,
                k: piece.k,
                whole: false,
                gate: piece.gate,
                outline: piece.outline,
                reach: piece.reach,
                indices,
                distances: piece.distances.clone(),
            });
        }
    }
    Some(kept)
}

/// Whether `count` of a stroke's samples draw at least half of the length of `piece`'s
/// curve (a piece of a stroke that does not is another part's passing by, as
/// `candidate` requires of any piece).
fn draws_half(piece: &Piece, count: usize) -> bool {
    let all = piece.distances.len().max(1) as f64;
    count as f64 / all * piece.reach >= 0.5
}

/// A stroke, or a piece of one, that suits a curve.
struct Piece {
    /// The score factor of its class against the curve's (see `suitability`).
    factor: f64,
    /// The curve.
    k: usize,
    /// Whether it is the whole stroke.
    whole: bool,
    /// The curve's gate (see `Reach`).
    gate: f64,
    /// Whether the curve is an outline.
    outline: bool,
    /// The length of the stroke's samples the curve could take at most, over the
    /// curve's own length: a piece must draw at least half of its curve.
    reach: f64,
    /// The indices of its samples among the stroke's.
    indices: Vec<usize>,
    /// The distance of every sample of the stroke to the curve.
    distances: Vec<f64>,
}

impl Piece {
    fn mean_distance(&self) -> f64 {
        self.indices.iter().map(|i| self.distances[*i]).sum::<f64>()
            / self.indices.len().max(1) as f64
    }

    fn score(&self) -> f64 {
        self.mean_distance() * self.factor
    }
}

/// The strokes of one projected curve as a file stores them: each stroke's id with the
/// indices of the samples taken ([`AssignedStroke::part`]; `None`: the whole stroke).
pub type CurveStrokes = Vec<(StrokeId, Option<Vec<usize>>)>;

/// Why an assignment could not be restored.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RestoreError {
    /// There is not one list of strokes per projected curve.
    #[error("{found} curve(s) of strokes for a primitive with {expected} projected curves")]
    CurveCount {
        /// The primitive's projected curves.
        expected: usize,
        /// The lists given.
        found: usize,
    },
    /// A stroke is not among the strokes that can be snapped to (it is not in the
    /// sketch, or too short to keep).
    #[error("stroke {} is not in the sketch", stroke.0)]
    MissingStroke {
        /// The stroke.
        stroke: StrokeId,
    },
    /// A stroke's sample indices are out of range or not strictly ascending.
    #[error("stroke {} has invalid sample indices", stroke.0)]
    InvalidSamples {
        /// The stroke.
        stroke: StrokeId,
    },
}

/// Rebuilds an assignment from the strokes of each projected curve, as a file stores
/// it: per curve, each stroke's id with the indices of the samples taken when only part
/// of it was (see [`AssignedStroke::part`]). The samples are chosen exactly as
/// [`assign`] chooses them, from the same `context`; the mean distances are measured
/// to `curves` (the primitive's projected curves now).
///
/// # Errors
///
/// [`RestoreError`] when the number of curves differs from `curves`, a stroke is not in
/// `context`, or sample indices are invalid.
pub fn restore_assignment(
    context: &SnapContext,
    curves: &[ProjectedCurve<f64>],
    strokes: &[CurveStrokes],
) -> Result<Assignment, RestoreError> {
    if strokes.len() != curves.len() {
        return Err(RestoreError::CurveCount {
            expected: curves.len(),
            found: strokes.len(),
        });
    }
    let curves = curves
        .iter()
        .zip(strokes)
        .map(|(curve, assigned)| {
            assigned
                .iter()
                .map(|(id, part)| {
                    let stroke = context
                        .stroke(*id)
                        .ok_or(RestoreError::MissingStroke { stroke: *id })?;
                    let samples = taken(&stroke_samples(stroke), part.as_deref())
                        .filter(|s| !s.is_empty())
                        .ok_or(RestoreError::InvalidSamples { stroke: *id })?;
                    let mean_distance = samples
                        .iter()
                        .map(|p| curve_distance(&curve.curve, *p))
                        .sum::<f64>()
                        / samples.len() as f64;
                    Ok(AssignedStroke {
                        stroke: *id,
                        samples,
                        mean_distance,
                        part: part.clone(),
                    })
                })
                .collect::<Result<Vec<_>, _>>()
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Assignment { curves })
}

/// The gate of one curve: `gate`, but for an ellipse no more than its semi-major axis. A
/// stroke further from an end ellipse than that ellipse's own radius is not drawing it:
/// without this, the thin stem of a goblet, whose size is its length, would take the
/// base's wide rim for its small end.
fn curve_gate(curve: &Curve2<f64>, gate: f64) -> f64 {
    match curve {
        Curve2::Ellipse { a, b, .. } => {
            let m = glam::DMat2::from_cols(a.to_dvec2(), b.to_dvec2());
            gate.min(singular_values(m).0)
        }
        Curve2::Polyline(_) => gate,
    }
}

/// Per curve, the widest gate the part's own shape allows once it is fitted: for an
/// outline (a polyline), the distance from its middle to the nearest other visible
/// outline of the part running within 35° of it (the opposite silhouette of a tube, the
/// parallel edge across a box face); no bound for the rest. A stroke further from an
/// outline than the part is wide there is not drawing it: without this, the gate of a
/// rod, a tenth of its length, is wider than the rod, and a neighbouring leg's outline
/// (or the far side of a U drawn round its end) passes it.
fn outline_caps(curves: &[ProjectedCurve<f64>]) -> Vec<f64> {
    (0..curves.len())
        .map(|k| {
            if curves[k].visible {
                distance_across(curves, k, true)
            } else {
                f64::INFINITY
            }
        })
        .collect()
}

/// The distance from the middle of the straight curve `k` of `curves` (its chord's
/// midpoint) to the nearest other straight curve running within 35° of it, among the
/// visible ones when `visible`; infinite for an ellipse or where none runs alongside.
pub(crate) fn distance_across(curves: &[ProjectedCurve<f64>], k: usize, visible: bool) -> f64 {
    let chord = |c: &Curve2<f64>| match c {
        Curve2::Polyline(p) if p.len() >= 2 => {
            let (a, b) = (p[0].to_dvec2(), p[p.len() - 1].to_dvec2());
            Some((a.lerp(b, 0.5), (b - a).normalize_or_zero()))
        }
        _ => None,
    };
    let Some((mid, dir)) = chord(&curves[k].curve) else {
        return f64::INFINITY;
    };
    curves
        .iter()
        .enumerate()
        .filter(|(j, other)| *j != k && (other.visible || !visible))
        .filter_map(|(_, other)| {
            let (_, d) = chord(&other.curve)?;
            (d.dot(dir).abs() >= ROUGHLY_PARALLEL).then(|| curve_distance(&other.curve, mid))
        })
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min)
}

/// cos 35°: two outlines this close in direction run alongside each other.
const ROUGHLY_PARALLEL: f64 = 0.819;

/// Straight strokes must run within 35° of a two-point curve's direction.
fn direction_ok(curve: &Curve2<f64>, stroke: &SnapStroke) -> bool {
    match curve {
        Curve2::Polyline(points)
            if points.len() == 2 && stroke.straightness <= ROUGHLY_STRAIGHT =>
        {
            let dir = (points[1].to_dvec2() - points[0].to_dvec2()).normalize_or_zero();
            dir.dot(stroke.direction).abs() >= 35f64.to_radians().cos()
        }
        _ => true,
    }
}

/// Axis-aligned bounds of a numeric curve.
pub(crate) fn curve_bounds(curve: &Curve2<f64>) -> (DVec2, DVec2) {
    match curve {
        Curve2::Ellipse { center, a, b } => {
            let (c, a, b) = (center.to_dvec2(), a.to_dvec2(), b.to_dvec2());
            let half = DVec2::new(a.x.hypot(b.x), a.y.hypot(b.y));
            (c - half, c + half)
        }
        Curve2::Polyline(points) => points.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p.to_dvec2()), hi.max(p.to_dvec2())),
        ),
    }
}

#[cfg(test)]
pub(super) mod tests {
    use glam::{DVec2, DVec3};

    use super::{assign, assign_within, curve_length};
    use crate::primitive::{Cylinder, Primitive};
    use crate::sketch::{StrokeClass, StrokeId};
    use crate::snap::SnapContext;

    #[test]
    fn strokes_go_to_the_curves_they_trace() {
        // A side-on cylinder (axis up, radius 10, length 40 at the origin) drawn as two
        // vertical lines and the top ellipse; a far stroke is ignored.
        let cyl = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.0, 0.96, 0.28),
            length: 40.0,
            radius: 10.0,
        });
        let shape = cyl.current_shape();
        let line = |x: f64| -> Vec<DVec2> {
            (0..=10)
                .map(|i| DVec2::new(x, -19.0 + 3.8 * f64::from(i)))
                .collect()
        };
        let top: Vec<DVec2> = (0..=24)
            .map(|i| {
                let t = std::f64::consts::TAU * f64::from(i) / 24.0;
                // Sketch space: y down, so the model top (y ≈ 19.2) is at −19.2.
                DVec2::new(10.0 * t.cos(), -19.2 + 2.8 * t.sin())
            })
            .collect();
        let far = line(500.0);
        let strokes = [
            (StrokeId(0), line(-10.3), StrokeClass::Silhouette),
            (StrokeId(1), line(9.8), StrokeClass::Silhouette),
            (StrokeId(2), top, StrokeClass::Feature),
            (StrokeId(3), far, StrokeClass::Silhouette),
        ];
        let ctx = SnapContext::new(strokes.iter().map(|(id, p, c)| (*id, p.as_slice(), *c)));
        let a = assign(&ctx, &shape.curves, 5.0);
        let names: Vec<(String, Vec<StrokeId>)> = shape
            .curves
            .iter()
            .zip(&a.curves)
            .map(|(c, s)| (c.name.clone(), s.iter().map(|x| x.stroke).collect()))
            .collect();
        assert_eq!(
            names,
            vec![
                ("top".to_owned(), vec![StrokeId(2)]),
                ("bottom".to_owned(), vec![]),
                ("left".to_owned(), vec![StrokeId(0)]),
                ("right".to_owned(), vec![StrokeId(1)]),
            ]
        );
        assert_eq!(a.stroke_ids(), vec![StrokeId(0), StrokeId(1), StrokeId(2)]);
        assert!((curve_length(&shape.curves[2].curve) - 40.0 * 0.96).abs() < 1e-6);
    }

    /// A cylinder of length 40 and radius `r` seen from the side and a little above
    /// (axis up the page, tilted 16° towards the viewer).
    fn leaning_cylinder(r: f64) -> Primitive {
        Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.0, 0.96, 0.28),
            length: 40.0,
            radius: r,
        })
    }

    /// [`leaning_cylinder`]`(r)`'s left outline, the front arc of its bottom end (in
    /// `arc` steps) and its right outline drawn as one U-shaped stroke (sketch space,
    /// y down).
    fn u_round_its_bottom(r: f64, arc: u32) -> Vec<DVec2> {
        let mut u: Vec<DVec2> = (0..=12)
            .map(|i| DVec2::new(-r, -19.2 + 3.2 * f64::from(i)))
            .collect();
        u.extend((1..arc).map(|i| {
            let t = std::f64::consts::PI * (1.0 - f64::from(i) / f64::from(arc));
            DVec2::new(r * t.cos(), 19.2 + 0.28 * r * t.sin())
        }));
        u.extend((0..=12).map(|i| DVec2::new(r, 19.2 - 3.2 * f64::from(i))));
        u
    }

    #[test]
    fn one_stroke_down_an_outline_round_an_end_and_back_up_is_taken_in_pieces() {
        // The cylinder of the test above, its left outline, the front arc of its bottom
        // end and its right outline drawn as one U-shaped stroke (sketch space, y down),
        // and its top ellipse.
        let shape = leaning_cylinder(10.0).current_shape();
        let u = u_round_its_bottom(10.0, 24);
        let top: Vec<DVec2> = (0..=24)
            .map(|i| {
                let t = std::f64::consts::TAU * f64::from(i) / 24.0;
                DVec2::new(10.0 * t.cos(), -19.2 + 2.8 * t.sin())
            })
            .collect();
        let strokes = [
            (StrokeId(0), u, StrokeClass::Silhouette),
            (StrokeId(1), top, StrokeClass::Feature),
        ];
        let ctx = SnapContext::new(strokes.iter().map(|(id, p, c)| (*id, p.as_slice(), *c)));
        let a = assign(&ctx, &shape.curves, 5.0);
        for (curve, strokes) in shape.curves.iter().zip(&a.curves) {
            let expected = if curve.name == "top" {
                StrokeId(1)
            } else {
                StrokeId(0)
            };
            assert_eq!(
                strokes.iter().map(|s| s.stroke).collect::<Vec<_>>(),
                vec![expected],
                "{}: {strokes:?}",
                curve.name
            );
        }
        // The pieces do not overlap: each sample of the U serves one curve.
        let mut seen: Vec<usize> = a
            .curves
            .iter()
            .flatten()
            .filter(|s| s.stroke == StrokeId(0))
            .flat_map(|s| s.part.clone().expect("taken in part"))
            .collect();
        let n = seen.len();
        seen.sort_unstable();
        seen.dedup();
        assert!(
            n - seen.len() <= 2,
            "{n} samples taken, {} distinct",
            seen.len()
        );
    }

    #[test]
    fn a_u_round_a_thin_tubes_end_within_both_outlines_gates_is_split_between_them() {
        // A rod of radius 3 seen from the side and a little above: the gate (10) is wider
        // than the rod, so the whole U (left outline, the front arc of its bottom end,
        // right outline; sketch space, y down) lies within either outline's gate; only
        // its pieces draw them.
        let shape = leaning_cylinder(3.0).current_shape();
        let u = u_round_its_bottom(3.0, 8);
        let ctx = SnapContext::new([(StrokeId(0), u.as_slice(), StrokeClass::Silhouette)]);
        let a = assign(&ctx, &shape.curves, 10.0);
        for (curve, taken) in shape.curves.iter().zip(&a.curves) {
            if curve.name != "left" && curve.name != "right" {
                continue;
            }
            let [piece] = taken.as_slice() else {
                panic!("{}: {taken:?}", curve.name);
            };
            let x = if curve.name == "left" { -3.0 } else { 3.0 };
            assert!(piece.part.is_some(), "{}: taken whole", curve.name);
            assert!(
                piece.samples.iter().all(|p| (p.x - x).abs() < 1.5),
                "{}: {:?}",
                curve.name,
                piece.samples
            );
        }
    }

    #[test]
    fn a_stroke_drawn_a_little_past_its_outline_stays_whole() {
        // The rod above, its left outline drawn whole: no run of it lies far from it.
        let shape = leaning_cylinder(3.0).current_shape();
        let line: Vec<DVec2> = (0..=20)
            .map(|i| DVec2::new(-3.0 + 0.2 * f64::from(i % 2), -20.0 + 2.0 * f64::from(i)))
            .collect();
        let ctx = SnapContext::new([(StrokeId(0), line.as_slice(), StrokeClass::Silhouette)]);
        let a = assign(&ctx, &shape.curves, 10.0);
        let taken: Vec<(String, bool)> = shape
            .curves
            .iter()
            .zip(&a.curves)
            .flat_map(|(c, t)| t.iter().map(|s| (c.name.clone(), s.part.is_none())))
            .collect();
        assert_eq!(taken, vec![("left".to_owned(), true)]);
    }

    #[test]
    fn a_stroke_drawn_round_a_box_corner_draws_both_edges() {
        use crate::primitive::Cuboid;
        let b = Cuboid {
            center: DVec3::ZERO,
            rotation: glam::DQuat::from_rotation_x(0.4) * glam::DQuat::from_rotation_y(0.6),
            size: DVec3::new(60.0, 40.0, 30.0),
        };
        let shape = Primitive::Cuboid(b).current_shape();
        // Two visible edges that meet at a corner, drawn as one L-shaped stroke.
        let edges: Vec<(usize, DVec2, DVec2)> = shape
            .curves
            .iter()
            .enumerate()
            .filter(|(_, c)| c.visible)
            .filter_map(|(k, c)| match &c.curve {
                crate::primitive::Curve2::Polyline(p) if p.len() == 2 => {
                    Some((k, p[0].to_dvec2(), p[1].to_dvec2()))
                }
                _ => None,
            })
            .collect();
        let (ka, kb, corner, a_end, b_end) = edges
            .iter()
            .flat_map(|a| edges.iter().map(move |b| (a, b)))
            .find_map(|((ka, a0, a1), (kb, b0, b1))| {
                if ka >= kb {
                    return None;
                }
                let ends = [
                    (*a0, *a1, *b0, *b1),
                    (*a1, *a0, *b0, *b1),
                    (*a0, *a1, *b1, *b0),
                    (*a1, *a0, *b1, *b0),
                ];
                ends.into_iter()
                    .find(|(pa, _, pb, _)| pa.distance(*pb) < 1e-6)
                    .map(|(c, ae, _, be)| (*ka, *kb, c, ae, be))
            })
            .expect("two visible edges meet");
        let leg = |from: DVec2, to: DVec2| -> Vec<DVec2> {
            (0..=20)
                .map(|i| from.lerp(to, f64::from(i) / 20.0))
                .collect()
        };
        let mut l = leg(a_end, corner);
        l.extend(leg(corner, b_end).into_iter().skip(1));
        // View plane → sketch space (y down) for the context.
        let l: Vec<DVec2> = l.into_iter().map(|p| DVec2::new(p.x, -p.y)).collect();
        let ctx = SnapContext::new([(StrokeId(7), l.as_slice(), StrokeClass::Silhouette)]);
        let a = assign(&ctx, &shape.curves, 5.0);
        for k in [ka, kb] {
            assert_eq!(
                a.curves[k].iter().map(|s| s.stroke).collect::<Vec<_>>(),
                vec![StrokeId(7)],
                "edge {k}: {:?}",
                a.curves
            );
        }
    }

    #[test]
    fn a_fitted_rods_hidden_outline_does_not_take_a_neighbours() {
        // A side-on rod (radius 5, length 200) whose right outline is hidden; a
        // neighbouring leg's outline runs 15 to its right: within the tight gate (a tenth
        // of the rod's length) but further from that outline than the rod is wide.
        let rod = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.0, 0.96, 0.28),
            length: 200.0,
            radius: 5.0,
        });
        let shape = rod.current_shape();
        let line = |x: f64| -> Vec<DVec2> {
            (0..=40)
                .map(|i| DVec2::new(x, -90.0 + 4.5 * f64::from(i)))
                .collect()
        };
        let strokes = [
            (StrokeId(0), line(-5.0), StrokeClass::Silhouette),
            (StrokeId(1), line(20.0), StrokeClass::Silhouette),
        ];
        let ctx = SnapContext::new(strokes.iter().map(|(id, p, c)| (*id, p.as_slice(), *c)));
        let taken = |a: &super::Assignment| -> Vec<StrokeId> {
            let mut ids = a.stroke_ids();
            ids.dedup();
            ids
        };
        // From a hand's drop the gate is the gate: the neighbour may be the outline.
        let dropped = assign(&ctx, &shape.curves, 20.0);
        assert_eq!(taken(&dropped), vec![StrokeId(0), StrokeId(1)]);
        // Once fitted, an outline is no wider than the rod.
        let fitted = assign_within(&ctx, &shape.curves, 20.0, true);
        assert_eq!(taken(&fitted), vec![StrokeId(0)]);
    }

    #[test]
    fn a_thin_parts_end_does_not_take_a_wide_rim_nearby() {
        // A stem (radius 4, length 60) standing on a wide rim (radius 40) drawn 12 below
        // its bottom end: the rim is well within 30 % of the stem's size, but further from
        // the stem's small end ellipse than that ellipse's own radius.
        let stem = Primitive::Cylinder(Cylinder {
            center: DVec3::new(0.0, 30.0, 0.0),
            axis: DVec3::new(0.0, 0.96, 0.28),
            length: 60.0,
            radius: 4.0,
        });
        let shape = stem.current_shape();
        let rim: Vec<DVec2> = (0..=48)
            .map(|i| {
                let t = std::f64::consts::TAU * f64::from(i) / 48.0;
                DVec2::new(40.0 * t.cos(), 12.0 + 11.0 * t.sin())
            })
            .collect();
        let ctx = SnapContext::new([(StrokeId(0), rim.as_slice(), StrokeClass::Feature)]);
        let a = assign(&ctx, &shape.curves, 0.3 * stem.size());
        assert!(a.stroke_ids().is_empty(), "{a:?}");
    }

    #[test]
    fn an_arms_end_on_a_stem_does_not_take_the_stems_outline_through_it() {
        // An arm (radius 25, length 300) seen from the side, its bottom end on a stem
        // whose outline runs straight up the page through that end's sliver and on: a
        // piece of the outline draws the sliver, but the line is the stem's.
        let arm = Primitive::Cylinder(Cylinder {
            center: DVec3::new(150.0, 0.0, 0.0),
            axis: DVec3::new(0.99, 0.0, 0.14),
            length: 300.0,
            radius: 25.0,
        });
        let shape = arm.current_shape();
        let bottom = shape
            .curves
            .iter()
            .position(|c| c.name == "bottom")
            .unwrap();
        let outline: Vec<DVec2> = (0..=40)
            .map(|i| DVec2::new(1.5, -300.0 + 15.0 * f64::from(i)))
            .collect();
        // The same stroke ending on the sliver is taken: it draws the end.
        let sliver: Vec<DVec2> = (0..=10)
            .map(|i| DVec2::new(1.5, -30.0 + 6.0 * f64::from(i)))
            .chain((1..=20).map(|i| DVec2::new(1.5 - 9.0 * f64::from(i), 30.0)))
            .collect();
        for (stroke, taken) in [(&outline, false), (&sliver, true)] {
            let ctx = SnapContext::new([(StrokeId(0), stroke.as_slice(), StrokeClass::Feature)]);
            let a = assign_within(&ctx, &shape.curves, 0.1 * arm.size(), true);
            assert_eq!(a.has(bottom), taken, "{a:?}");
        }
    }

    #[test]
    fn an_outline_gone_over_twice_keeps_both_strokes() {
        // A cylinder (radius 50, length 300) seen from the side, its right outline drawn
        // once on it and once again 8 to the right (a rough hand's copy): the copy fits
        // far worse than the first stroke, which alone would win the competition and
        // hold the fit on it; as a copy it stays, and the fit settles between them.
        let cyl = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.0, 0.99, 0.14).normalize(),
            length: 300.0,
            radius: 50.0,
        });
        let shape = cyl.current_shape();
        let right = shape.curves.iter().position(|c| c.name == "right").unwrap();
        let (a, b) = match &shape.curves[right].curve {
            super::Curve2::Polyline(p) => (p[0].to_dvec2(), p[p.len() - 1].to_dvec2()),
            super::Curve2::Ellipse { .. } => panic!("an outline is a polyline"),
        };
        // Away from the axis (the outline runs up the page, the axis through x = 0).
        let outward = DVec2::new((a.x + b.x).signum() * 8.0, 0.0);
        // Sketch space, y down.
        let stroke = |shift: DVec2| -> Vec<DVec2> {
            (0..=30)
                .map(|i| a.lerp(b, f64::from(i) / 30.0) + shift)
                .map(|p| DVec2::new(p.x, -p.y))
                .collect()
        };
        let (first, again) = (stroke(DVec2::ZERO), stroke(outward));
        let ctx = SnapContext::new([
            (StrokeId(0), first.as_slice(), StrokeClass::Silhouette),
            (StrokeId(1), again.as_slice(), StrokeClass::Silhouette),
        ]);
        let assignment = assign_within(&ctx, &shape.curves, 0.1 * cyl.size(), true);
        let ids: Vec<StrokeId> = assignment.curves[right].iter().map(|s| s.stroke).collect();
        assert_eq!(ids, vec![StrokeId(0), StrokeId(1)], "{assignment:?}");
    }

    #[test]
    fn a_long_stems_end_does_not_take_a_smaller_ellipse_set_on_it() {
        // A long stem (radius 10, length 400) seen from the side and a little above, its
        // top end drawn a little wide, and a cup's bottom end (radius 5) drawn where it
        // sits on the stem's top. The cup's ellipse lies inside the stem end's gate, but
        // it runs 1.7 from that end on average where the end's own stroke runs 0.2: a
        // tenth of the part's gate (set by the stem's length, 4) would keep it and let
        // it pull the end in; a tenth of the end's own gate (its radius) does not.
        let stem = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.0, 0.96, 0.28),
            length: 400.0,
            radius: 10.0,
        });
        let shape = stem.current_shape();
        let top = shape.curves.iter().position(|c| c.name == "top").unwrap();
        // Sketch space, y down: the model top (y = 192) is at −192.
        let ellipse = |r: f64| -> Vec<DVec2> {
            (0..=32)
                .map(|i| {
                    let t = std::f64::consts::TAU * f64::from(i) / 32.0;
                    DVec2::new(r * t.cos(), -192.0 + 0.28 * r * t.sin())
                })
                .collect()
        };
        let (own, cup) = (ellipse(10.4), ellipse(5.0));
        let ctx = SnapContext::new([
            (StrokeId(0), own.as_slice(), StrokeClass::Feature),
            (StrokeId(1), cup.as_slice(), StrokeClass::Feature),
        ]);
        let a = assign_within(&ctx, &shape.curves, 0.1 * stem.size(), true);
        let ids: Vec<StrokeId> = a.curves[top].iter().map(|s| s.stroke).collect();
        assert_eq!(ids, vec![StrokeId(0)], "{a:?}");
    }

    #[test]
    fn an_assignment_is_restored_from_its_stroke_ids_and_parts() {
        use super::{restore_assignment, RestoreError};

        // A long stroke runs along the left outline and on past the cylinder, so only
        // part of it is taken; the right outline is taken whole.
        let cyl = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.0, 0.96, 0.28),
            length: 40.0,
            radius: 10.0,
        });
        let shape = cyl.current_shape();
        let line = |x: f64, from: f64, to: f64| -> Vec<DVec2> {
            (0..=40)
                .map(|i| DVec2::new(x, from + (to - from) * f64::from(i) / 40.0))
                .collect()
        };
        let strokes = [
            (
                StrokeId(5),
                line(-10.2, -19.0, 60.0),
                StrokeClass::Silhouette,
            ),
            (StrokeId(8), line(9.9, -19.0, 19.0), StrokeClass::Silhouette),
        ];
        let ctx = SnapContext::new(strokes.iter().map(|(id, p, c)| (*id, p.as_slice(), *c)));
        let a = assign(&ctx, &shape.curves, 5.0);
        assert!(
            a.curves.iter().flatten().any(|s| s.part.is_some()),
            "one stroke is taken in part: {a:?}"
        );
        let ids: Vec<Vec<(StrokeId, Option<Vec<usize>>)>> = a
            .curves
            .iter()
            .map(|c| c.iter().map(|s| (s.stroke, s.part.clone())).collect())
            .collect();
        assert_eq!(restore_assignment(&ctx, &shape.curves, &ids), Ok(a));
        assert_eq!(
            restore_assignment(&ctx, &shape.curves[..2], &ids),
            Err(RestoreError::CurveCount {
                expected: 2,
                found: 4
            })
        );
        let mut missing = ids.clone();
        missing[0].push((StrokeId(77), None));
        assert_eq!(
            restore_assignment(&ctx, &shape.curves, &missing),
            Err(RestoreError::MissingStroke {
                stroke: StrokeId(77)
            })
        );
        let mut bad = ids;
        bad[3] = vec![(StrokeId(8), Some(vec![3, 1]))];
        assert_eq!(
            restore_assignment(&ctx, &shape.curves, &bad),
            Err(RestoreError::InvalidSamples {
                stroke: StrokeId(8)
            })
        );
    }

    /// A plank (826 × 227 × 85) seen a little from its end, its 227 side 27° off the
    /// view direction, with its twelve edges drawn as strokes, its three hidden ones
    /// too, in sketch space; each stroke's id is its edge's index among the box's curves.
    pub(in crate::snap) fn plank_with_its_hidden_edges() -> (Primitive, SnapContext) {
        use crate::geom::projection::sketch_from_view;
        use crate::primitive::{Cuboid, Curve2};
        use glam::{DMat3, DQuat};
        let x = DVec3::new(0.220, -0.393, 0.893).normalize();
        let y = DVec3::new(-0.012, 0.914, 0.406);
        let y = (y - x * x.dot(y)).normalize();
        let cuboid = Primitive::Cuboid(Cuboid {
            center: DVec3::new(1346.5, -1463.6, 0.0),
            rotation: DQuat::from_mat3(&DMat3::from_cols(x, y, x.cross(y))),
            size: DVec3::new(226.7, 85.1, 826.0),
        });
        let strokes: Vec<(StrokeId, Vec<DVec2>)> = cuboid
            .current_shape()
            .curves
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let Curve2::Polyline(p) = &c.curve else {
                    unreachable!("a box's edges are segments")
                };
                let (a, b) = (p[0].to_dvec2(), p[p.len() - 1].to_dvec2());
                let points = (0..=24)
                    .map(|i| sketch_from_view(a.lerp(b, f64::from(i) / 24.0)))
                    .collect();
                (StrokeId(k as u32), points)
            })
            .collect();
        let context = SnapContext::new(
            strokes
                .iter()
                .map(|(id, p)| (*id, p.as_slice(), StrokeClass::Silhouette)),
        );
        (cuboid, context)
    }

    #[test]
    fn a_fitted_boxs_hidden_edges_keep_their_strokes_from_its_visible_ones() {
        let (cuboid, ctx) = plank_with_its_hidden_edges();
        let shape = cuboid.current_shape();
        let gate = 0.3 * cuboid.size();
        let fitted = assign_within(&ctx, &shape.curves, gate, true);
        // Every visible edge takes its own stroke and nothing else; the hidden edges'
        // strokes, which run beside the near face's edges, go to no curve.
        for (k, (curve, taken)) in shape.curves.iter().zip(&fitted.curves).enumerate() {
            let ids: Vec<u32> = taken.iter().map(|s| s.stroke.0).collect();
            if curve.visible {
                assert_eq!(ids, vec![k as u32], "edge {k}");
            } else {
                assert!(ids.is_empty(), "hidden edge {k} took {ids:?}");
            }
        }
        // At a hand's drop the hidden edges do not compete (placed roughly, one can lie
        // on the part's own visible stroke).
        let dropped = assign(&ctx, &shape.curves, gate);
        let hidden: Vec<u32> = (0..shape.curves.len() as u32)
            .filter(|k| !shape.curves[*k as usize].visible)
            .collect();
        assert_eq!(hidden.len(), 3);
        assert!(dropped.stroke_ids().iter().any(|id| hidden.contains(&id.0)));
    }
}
