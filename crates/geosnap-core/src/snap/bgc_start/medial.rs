//! The medial axis of a tube's two drawn outlines near its drop, as **chains**.
//!
//! Every sample of an outline near the drop is paired with the nearest point of another
//! outline that lies across the tube (see [`medial_samples`]); the midpoints of the pairs
//! trace the projected spine and their half distances the radius. A drawing holds more
//! than the dropped tube: the outlines of a post drawn across it (or of a part it passes
//! behind) pair among themselves, and one outline drawn along two tubes (an arm that runs
//! on past a joint) pairs with its partner well beyond the tube pointed at. So the samples
//! are grouped into chains, consecutive samples along the same two strokes
//! ([`chains`]); a chain is cut where another tube-like chain crosses it (a junction in
//! the drawing: the tube meets, or passes behind, another part), unless the drop itself
//! clearly spans that junction ([`cut_at_junctions`]); and the piece nearest the drop that
//! runs with it is the tube, with the pieces that continue it (an outline drawn in several
//! strokes) ([`tube_of`]).

use glam::DVec2;

use crate::geom::BoxIndex;

/// At most this many samples of a stroke are paired.
const SAMPLES: usize = 40;

/// A medial sample: the midpoint of a pair of outline points across the tube, its half
/// width, the two strokes (lower index first), and the position of the pair along the
/// first stroke (arc length), which orders a chain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Medial {
    /// The midpoint of the pair.
    pub at: DVec2,
    /// Half the distance between the pair.
    pub half: f64,
    /// The two strokes of the pair, lower index first.
    pub pair: (usize, usize),
    /// Arc length along `pair.0` where the pair lies.
    pub along: f64,
    /// Arc length along `pair.1` where the pair lies.
    pub along_b: f64,
    /// The outline whose sample found the pair (`pair.0` or `pair.1`).
    pub from: usize,
}

/// A piece of a chain: its samples in order, and the junctions where it was cut at its
/// start and at its end (a piece is never continued across a junction).
#[derive(Clone, Debug)]
pub(super) struct Piece {
    samples: Vec<Medial>,
    cut: [Option<Junction>; 2],
}

/// A junction: where another tube-like chain, of the strokes `across`, crosses a chain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Junction {
    /// The crossing point.
    pub at: DVec2,
    /// The two strokes of the crossing chain.
    pub across: (usize, usize),
    /// The crossing chain's unit direction there.
    pub direction: DVec2,
}

/// The far side of a junction, seen from the tube: a line through the junction along the
/// part that crosses it, the unit normal `inward` pointing to the tube, and the tube's
/// half-width there (see [`trimmed`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Wall {
    /// The junction.
    pub at: DVec2,
    /// The crossing part's unit direction.
    pub direction: DVec2,
    /// The unit normal towards the tube.
    pub inward: DVec2,
    /// The tube's half-width at the junction.
    pub half: f64,
}

/// Where the tube's outline `stroke` (an index into the outlines) stops at a junction:
/// the junction's point, and an arc length along the stroke on the tube's side of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Stop {
    /// The outline.
    pub stroke: usize,
    /// The junction.
    pub at: DVec2,
    /// An arc length along the stroke on the tube's side.
    pub inside: f64,
}

/// The bounds `(min, max)` of a polyline's points (an empty polyline has none: its
/// bounds are not finite, and an index returns it for every query).
fn bounds(points: &[DVec2]) -> (DVec2, DVec2) {
    points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

/// The cumulative arc lengths of a polyline.
pub(super) fn arc_lengths(points: &[DVec2]) -> Vec<f64> {
    let mut s = Vec::with_capacity(points.len());
    let mut total = 0.0;
    for (i, p) in points.iter().enumerate() {
        if i > 0 {
            total += points[i - 1].distance(*p);
        }
        s.push(total);
    }
    s
}

/// Evenly chosen samples of a polyline among its points within `reach` of `center`,
/// with their unit tangents and arc lengths.
fn samples(points: &[DVec2], center: DVec2, reach: f64) -> Vec<(DVec2, DVec2, f64)> {
    let n = points.len();
    let s = arc_lengths(points);
    let near: Vec<usize> = (0..n)
        .filter(|j| points[*j].distance(center) <= reach)
        .collect();
    let count = near.len().min(SAMPLES);
    (0..count)
        .map(|i| {
            let j = near[i * (near.len() - 1) / (count - 1).max(1)];
            let (lo, hi) = (j.saturating_sub(2), (j + 2).min(n - 1));
            (
                points[j],
                (points[hi] - points[lo]).normalize_or_zero(),
                s[j],
            )
        })
        .collect()
}

/// The closest point to `p` on a polyline, with the polyline's unit direction and its arc
/// length there.
fn closest(points: &[DVec2], p: DVec2) -> Option<(DVec2, DVec2, f64)> {
    let mut best: Option<(f64, DVec2, DVec2, f64)> = None;
    let mut s = 0.0;
    for w in points.windows(2) {
        let ab = w[1] - w[0];
        let len2 = ab.length_squared();
        if len2 <= 0.0 {
            continue;
        }
        let len = len2.sqrt();
        let t = ((p - w[0]).dot(ab) / len2).clamp(0.0, 1.0);
        let q = w[0] + ab * t;
        let d = q.distance_squared(p);
        if best.as_ref().is_none_or(|(b, ..)| d < *b) {
            best = Some((d, q, ab / len, s + t * len));
        }
        s += len;
    }
    best.map(|(_, q, dir, at)| (q, dir, at))
}

/// Medial samples of the outlines `outlines` near `center` for a tube of radius about `r`:
/// each sample of an outline within `reach` of `center` is paired with the nearest point
/// of another outline that lies across the tube: the two run within about 45° of each
/// other, the pair lies across the sample's outline, and it is between `widths.0`·r and
/// `widths.1`·r apart. Only the outlines whose bounds come within `widths.1`·r of a
/// sample are measured (an index of their bounds finds them): no other can be its
/// partner.
pub(super) fn medial_samples(
    outlines: &[&[DVec2]],
    center: DVec2,
    reach: f64,
    r: f64,
    widths: (f64, f64),
) -> Vec<Medial> {
    let boxes = BoxIndex::new(outlines.iter().map(|points| bounds(points)));
    pairs_across(outlines, center, reach, r, widths, |p| {
        boxes.near(p, p, widths.1 * r)
    })
}

/// [`medial_samples`], with `candidates(p)` the outlines that may pair with a sample at
/// `p` (in ascending order, so that ties go as in a scan over all outlines).
fn pairs_across(
    outlines: &[&[DVec2]],
    center: DVec2,
    reach: f64,
    r: f64,
    widths: (f64, f64),
    candidates: impl Fn(DVec2) -> Vec<usize>,
) -> Vec<Medial> {
    let mut medial = Vec::new();
    for (i, a) in outlines.iter().enumerate() {
        for (p, tangent, s) in samples(a, center, reach) {
            let mut best: Option<(f64, DVec2, usize, f64)> = None;
            for j in candidates(p) {
                let Some(b) = outlines.get(j).filter(|_| j != i) else {
                    continue;
                };
                let Some((q, dir, t)) = closest(b, p) else {
                    continue;
                };
                let d = q.distance(p);
                let dir = if dir.dot(tangent) < 0.0 { -dir } else { dir };
                let across = (q - p).dot(tangent).abs() <= 0.4 * d;
                let parallel = dir.dot(tangent) >= 0.7;
                if across
                    && parallel
                    && (widths.0 * r..=widths.1 * r).contains(&d)
                    && best.as_ref().is_none_or(|(bd, ..)| d < *bd)
                {
                    best = Some((d, q, j, t));
                }
            }
            if let Some((d, q, j, t)) = best {
                let (pair, along, along_b) = if i < j {
                    ((i, j), s, t)
                } else {
                    ((j, i), t, s)
                };
                medial.push(Medial {
                    at: (p + q) / 2.0,
                    half: d / 2.0,
                    pair,
                    along,
                    along_b,
                    from: i,
                });
            }
        }
    }
    medial
}

/// The share of each outline's samples near `center` (see [`medial_samples`]) that found
/// a partner across the tube in `medial`: about 1 for a tube's outline, low for a stroke
/// that only touches one (an end arc meets its outlines tangentially, so only its tips
/// pair), 0 for a stroke with no samples near the drop.
pub(super) fn paired_shares(
    outlines: &[&[DVec2]],
    center: DVec2,
    reach: f64,
    medial: &[Medial],
) -> Vec<f64> {
    outlines
        .iter()
        .enumerate()
        .map(|(i, points)| {
            let sampled = samples(points, center, reach).len();
            let paired = medial.iter().filter(|m| m.from == i).count();
            if sampled == 0 {
                0.0
            } else {
                paired as f64 / sampled as f64
            }
        })
        .collect()
}

/// The median of some values (0 for none).
fn median(mut values: Vec<f64>) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// The medial samples grouped into chains: the samples of one pair of strokes, in order
/// along them. (Where one outline is missing for a stretch, the chain only has a gap.)
pub(super) fn chains(mut medial: Vec<Medial>) -> Vec<Vec<Medial>> {
    medial.sort_by(|a, b| a.pair.cmp(&b.pair).then(a.along.total_cmp(&b.along)));
    medial
        .chunk_by(|a, b| a.pair == b.pair)
        .map(<[Medial]>::to_vec)
        .collect()
}

/// Where segments a0–a1 and b0–b1 cross: the fractions along each.
fn crossing(a0: DVec2, a1: DVec2, b0: DVec2, b1: DVec2) -> Option<(f64, f64)> {
    let (da, db) = (a1 - a0, b1 - b0);
    let den = da.perp_dot(db);
    if den.abs() <= 1e-12 * da.length() * db.length() {
        return None;
    }
    let w = b0 - a0;
    let (s, t) = (w.perp_dot(db) / den, w.perp_dot(da) / den);
    ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t)).then_some((s, t))
}

/// Whether two chains share a stroke (then they pair the same tube's outlines two ways).
fn shares_a_stroke(a: &[Medial], b: &[Medial]) -> bool {
    let (Some(a), Some(b)) = (a.first(), b.first()) else {
        return false;
    };
    let (a, b) = (a.pair, b.pair);
    a.0 == b.0 || a.0 == b.1 || a.1 == b.0 || a.1 == b.1
}

/// The chains that may make junctions on each chain: the tube-like ones of other parts
/// (sharing no stroke with it) whose bounds meet its own, found by an index of the
/// chains' bounds (two chains cross only where their bounds meet).
struct Others<'a> {
    chains: &'a [Vec<Medial>],
    tube: Vec<bool>,
    bounds: Vec<(DVec2, DVec2)>,
    boxes: BoxIndex,
}

impl<'a> Others<'a> {
    fn new(chains: &'a [Vec<Medial>]) -> Self {
        let bounds: Vec<(DVec2, DVec2)> = chains
            .iter()
            .map(|c| bounds(&c.iter().map(|m| m.at).collect::<Vec<_>>()))
            .collect();
        Self {
            chains,
            tube: chains.iter().map(|c| tube_like(c)).collect(),
            boxes: BoxIndex::new(bounds.iter().copied()),
            bounds,
        }
    }

    /// The chains that may make junctions on chain `i`, in order.
    fn of(&self, i: usize) -> Vec<&'a [Medial]> {
        let (Some(chain), Some(&(lo, hi))) = (self.chains.get(i), self.bounds.get(i)) else {
            return Vec::new();
        };
        self.boxes
            .meeting(lo, hi)
            .into_iter()
            .filter(|&j| j != i && self.tube[j] && !shares_a_stroke(&self.chains[j], chain))
            .map(|j| self.chains[j].as_slice())
            .collect()
    }
}

/// Whether a chain is tube-like: a few samples along a run longer than it is wide.
fn tube_like(chain: &[Medial]) -> bool {
    let (Some(first), Some(last)) = (chain.first(), chain.last()) else {
        return false;
    };
    let width = median(chain.iter().map(|m| m.half).collect());
    chain.len() >= 4 && first.at.distance(last.at) >= 2.0 * width
}

/// The junctions on `chain`: the positions (along) and points where one of the tube-like
/// chains `others` crosses it at more than 30°.
fn junctions(chain: &[Medial], others: &[&[Medial]]) -> Vec<(f64, Junction)> {
    let mut cuts = Vec::new();
    for other in others {
        for a in chain.windows(2) {
            for b in other.windows(2) {
                let (da, db) = (a[1].at - a[0].at, b[1].at - b[0].at);
                let cos = da.normalize_or_zero().dot(db.normalize_or_zero()).abs();
                if cos > 0.87 {
                    continue;
                }
                if let Some((s, _)) = crossing(a[0].at, a[1].at, b[0].at, b[1].at) {
                    let junction = Junction {
                        at: a[0].at + da * s,
                        across: b[0].pair,
                        direction: db.normalize_or_zero(),
                    };
                    cuts.push((a[0].along + s * (a[1].along - a[0].along), junction));
                }
            }
        }
    }
    cuts
}

/// Whether the drop from `first` to `last` clearly spans `point`: it lies over the
/// drop's middle three fifths.
fn spans(drop: [DVec2; 2], point: DVec2) -> bool {
    let d = drop[1] - drop[0];
    let t = (point - drop[0]).dot(d) / d.length_squared().max(f64::MIN_POSITIVE);
    (0.2..=0.8).contains(&t)
}

/// The chains cut at their junctions (see the module docs) into pieces; a junction that
/// the drop from `drop[0]` to `drop[1]` clearly spans does not cut.
pub(super) fn cut_at_junctions(chains: &[Vec<Medial>], drop: [DVec2; 2]) -> Vec<Piece> {
    let mut pieces = Vec::new();
    let others = Others::new(chains);
    for (i, chain) in chains.iter().enumerate() {
        let mut cuts: Vec<(f64, Junction)> = junctions(chain, &others.of(i))
            .into_iter()
            .filter(|(_, j)| !spans(drop, j.at))
            .collect();
        cuts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut piece = Piece {
            samples: Vec::new(),
            cut: [None, None],
        };
        let mut next = 0;
        for m in chain {
            let mut at = None;
            while next < cuts.len() && m.along > cuts[next].0 {
                at = Some(cuts[next].1);
                next += 1;
            }
            if at.is_some() {
                if piece.samples.is_empty() {
                    piece.cut[0] = at;
                } else {
                    piece.cut[1] = at;
                    let fresh = Piece {
                        samples: Vec::new(),
                        cut: [at, None],
                    };
                    pieces.push(std::mem::replace(&mut piece, fresh));
                }
            }
            piece.samples.push(*m);
        }
        if !piece.samples.is_empty() {
            pieces.push(piece);
        }
    }
    pieces
}

/// The distance from `p` to a polyline through the samples.
fn distance_to(samples: &[Medial], p: DVec2) -> f64 {
    if samples.len() == 1 {
        return samples[0].at.distance(p);
    }
    samples
        .windows(2)
        .map(|w| {
            let ab = w[1].at - w[0].at;
            let t = ((p - w[0].at).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE))
                .clamp(0.0, 1.0);
            (w[0].at + ab * t).distance(p)
        })
        .fold(f64::INFINITY, f64::min)
}

/// How far a piece lies from the drop: the mean distance of points along the drop to the
/// piece; `None` when the piece runs across the drop (its chord more than 66° from the
/// drop's axis) or is too short to tell.
fn remoteness(piece: &Piece, drop: [DVec2; 2]) -> Option<f64> {
    let s = &piece.samples;
    if s.len() < 3 {
        return None;
    }
    let chord = (s[s.len() - 1].at - s[0].at).normalize_or_zero();
    let axis = (drop[1] - drop[0]).normalize_or_zero();
    if chord.dot(axis).abs() < 0.4 {
        return None;
    }
    let n = 9;
    Some(
        (0..n)
            .map(|i| distance_to(s, drop[0].lerp(drop[1], i as f64 / (n - 1) as f64)))
            .sum::<f64>()
            / n as f64,
    )
}

/// Where a sample lies along `stroke`, one of its pair.
fn along_on(m: &Medial, stroke: usize) -> f64 {
    if m.pair.0 == stroke {
        m.along
    } else {
        m.along_b
    }
}

/// Whether piece `b` continues piece `a` (an outline drawn in several strokes, or with a
/// stretch missing): they share an outline, along which `b` follows on from `a` (within
/// `reach`, from an end of `a` that no junction cut) with about its width.
fn continues(a: &Piece, b: &Piece, reach: f64) -> bool {
    let (pa, pb) = (a.samples[0].pair, b.samples[0].pair);
    if pa == pb || b.samples.len() < 3 {
        return false;
    }
    let width = |p: &Piece| median(p.samples.iter().map(|m| m.half).collect());
    let ratio = width(b) / width(a).max(f64::MIN_POSITIVE);
    if !(0.6..=1.67).contains(&ratio) {
        return false;
    }
    [pa.0, pa.1]
        .into_iter()
        .filter(|s| *s == pb.0 || *s == pb.1)
        .any(|stroke| {
            let range = |p: &Piece| {
                p.samples
                    .iter()
                    .map(|m| along_on(m, stroke))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                        (lo.min(x), hi.max(x))
                    })
            };
            let ((a_lo, a_hi), (b_lo, b_hi)) = (range(a), range(b));
            let after = b_lo - a_hi;
            let before = a_lo - b_hi;
            let slack = width(a);
            let (gap, joint) = if after >= before {
                (after, a_hi)
            } else {
                (before, a_lo)
            };
            // The end of `a` at the joint must not be a junction, and `b` runs on from it
            // the way `a` runs out there.
            let (sa, sb) = (&a.samples, &b.samples);
            let at = |p: &[Medial], i: usize| p[i].at;
            let (na, nb) = (sa.len(), sb.len());
            let first = (along_on(&sa[0], stroke) - joint).abs();
            let last = (along_on(&sa[na - 1], stroke) - joint).abs();
            let (end, inner, cut) = if first < last {
                (at(sa, 0), at(sa, na / 3), a.cut[0])
            } else {
                (at(sa, na - 1), at(sa, na - 1 - na / 3), a.cut[1])
            };
            let (near, far) = if at(sb, 0).distance(end) <= at(sb, nb - 1).distance(end) {
                (at(sb, 0), at(sb, nb - 1))
            } else {
                (at(sb, nb - 1), at(sb, 0))
            };
            let out = (end - inner).normalize_or_zero();
            let on = (far - near).normalize_or_zero();
            cut.is_none()
                && gap >= -slack
                && gap <= reach
                && near.distance(end) <= gap.max(0.0) + 2.0 * slack
                && out.dot(on) >= 0.5
        })
}

/// The tube that [`tube_of`] finds.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Tube {
    /// Its medial samples (midpoint, half-width).
    pub samples: Vec<(DVec2, f64)>,
    /// Where its outlines stop at junctions.
    pub stops: Vec<Stop>,
    /// The outlines of the parts it meets at those junctions (they cross it: none of
    /// them is its own).
    pub across: Vec<usize>,
    /// The far sides of those junctions.
    pub walls: Vec<Wall>,
}

/// The tube dropped from `drop[0]` to `drop[1]`: the nearest piece that runs with the
/// drop, with the pieces that continue it (see the module docs).
pub(super) fn tube_of(pieces: &[Piece], drop: [DVec2; 2]) -> Tube {
    let reach = drop[0].distance(drop[1]);
    let best = pieces
        .iter()
        .enumerate()
        .filter_map(|(i, p)| remoteness(p, drop).map(|d| (i, d)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let Some((best, _)) = best else {
        return Tube::default();
    };
    // Only the pieces that continue the nearest one itself: a chain of continuations
    // would run on into the parts the tube meets (a cup set on an arm's end).
    let mut taken = vec![best];
    for (i, p) in pieces.iter().enumerate() {
        if i != best
            && p.samples.len() >= 4
            && !taken
                .iter()
                .any(|t| pieces[*t].samples[0].pair == p.samples[0].pair)
            && continues(&pieces[best], p, reach)
            && remoteness(p, drop).is_some()
        {
            taken.push(i);
        }
    }
    let mut tube = Tube::default();
    for piece in taken.iter().map(|i| &pieces[*i]) {
        let s = &piece.samples;
        for (junction, m) in piece.cut.iter().zip([s[0], s[s.len() - 1]]) {
            if let Some(j) = junction {
                for (stroke, inside) in [(m.pair.0, m.along), (m.pair.1, m.along_b)] {
                    tube.stops.push(Stop {
                        stroke,
                        at: j.at,
                        inside,
                    });
                }
                tube.across.extend([j.across.0, j.across.1]);
                let mean = s.iter().map(|m| m.at).sum::<DVec2>() / s.len() as f64;
                let normal = j.direction.perp();
                let inward = if (mean - j.at).dot(normal) < 0.0 {
                    -normal
                } else {
                    normal
                };
                tube.walls.push(Wall {
                    at: j.at,
                    direction: j.direction,
                    inward,
                    half: m.half,
                });
            }
        }
        tube.samples.extend(s.iter().map(|m| (m.at, m.half)));
    }
    tube
}

impl Wall {
    /// Whether `p` lies beyond the wall, within a few tube widths of the junction.
    pub(super) fn beyond(&self, p: DVec2) -> bool {
        let d = p - self.at;
        d.dot(self.inward) < 0.0 && d.dot(self.direction).abs() <= 4.0 * self.half
    }
}

/// A stroke `points` trimmed at a junction's `wall`: without its points beyond the wall
/// within a few tube widths of the junction (an outline drawn on across the part the tube
/// meets), the longest run that is left; `None` when nothing is trimmed.
pub(super) fn trimmed(points: &[DVec2], wall: &Wall) -> Option<Vec<DVec2>> {
    let beyond = |p: &DVec2| wall.beyond(*p);
    if !points.iter().any(beyond) {
        return None;
    }
    let mut best: &[DVec2] = &[];
    for run in points.split(beyond) {
        if run.len() > best.len() {
            best = run;
        }
    }
    Some(best.to_vec())
}

/// The outline `points` clipped at its junctions `stops` (see [`Stop`]): the part on the
/// tube's side of the points nearest the junctions, or `None` when nothing is clipped.
pub(super) fn clipped(points: &[DVec2], stops: &[&Stop]) -> Option<Vec<DVec2>> {
    let s = arc_lengths(points);
    let total = *s.last()?;
    let (mut lo, mut hi) = (0.0f64, total);
    for stop in stops {
        let (_, _, at) = closest(points, stop.at)?;
        if stop.inside < at {
            hi = hi.min(at);
        } else {
            lo = lo.max(at);
        }
    }
    if !(lo > 0.0 || hi < total) || hi - lo <= 0.0 {
        return None;
    }
    let point_at = |x: f64| {
        let j = s.partition_point(|c| *c < x).clamp(1, points.len() - 1);
        let seg = s[j] - s[j - 1];
        let t = if seg > 0.0 { (x - s[j - 1]) / seg } else { 0.0 };
        points[j - 1].lerp(points[j], t)
    };
    let mut out = vec![point_at(lo)];
    out.extend(
        points
            .iter()
            .zip(&s)
            .filter(|(_, c)| **c > lo && **c < hi)
            .map(|(p, _)| *p),
    );
    out.push(point_at(hi));
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A U of radius `radius` round (0, 0), from the left top down and up to the right.
    fn u(radius: f64) -> Vec<DVec2> {
        (0..=60)
            .map(|i| {
                let a = std::f64::consts::PI * (1.0 + f64::from(i) / 60.0);
                DVec2::new(radius * a.cos(), radius * a.sin())
            })
            .collect()
    }

    /// A vertical line at `x` from y = −150 to 50.
    fn post(x: f64) -> Vec<DVec2> {
        (0..=40)
            .map(|i| DVec2::new(x, -150.0 + 5.0 * f64::from(i)))
            .collect()
    }

    /// The tube for a drop from `a` to `b`, radius 10, among `strokes`.
    fn tube(strokes: &[Vec<DVec2>], a: DVec2, b: DVec2) -> Tube {
        let outlines: Vec<&[DVec2]> = strokes.iter().map(Vec::as_slice).collect();
        let drop = [a, b];
        let samples = medial_samples(&outlines, (a + b) / 2.0, 400.0, 10.0, (0.8, 4.0));
        tube_of(&cut_at_junctions(&chains(samples), drop), drop)
    }

    /// Outlines of a cluttered drawing: pairs of wavy parallel strokes (tubes) at random
    /// places and angles, some crossing, and short strokes between them.
    fn clutter(count: usize) -> Vec<Vec<DVec2>> {
        let mut seed = 23u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut strokes = Vec::new();
        for k in 0..count {
            let at = DVec2::new(next(), next()) * 600.0;
            let along = DVec2::from_angle(next() * std::f64::consts::TAU);
            let (length, width) = if k % 3 == 0 {
                (20.0 + 30.0 * next(), 0.0)
            } else {
                (80.0 + 150.0 * next(), 8.0 + 20.0 * next())
            };
            for side in [-1.0, 1.0] {
                if width == 0.0 && side > 0.0 {
                    continue;
                }
                let wave = next();
                strokes.push(
                    (0..=24)
                        .map(|i| {
                            let t = f64::from(i) / 24.0;
                            at + along * (length * t)
                                + along.perp() * (side * width + 3.0 * (wave + 6.0 * t).sin())
                        })
                        .collect(),
                );
            }
        }
        strokes
    }

    #[test]
    fn the_index_pairs_the_samples_a_scan_over_all_outlines_pairs() {
        let strokes = clutter(120);
        let outlines: Vec<&[DVec2]> = strokes.iter().map(Vec::as_slice).collect();
        let all = |_| (0..outlines.len()).collect::<Vec<usize>>();
        for (center, reach, r) in [
            (DVec2::splat(300.0), 250.0, 10.0),
            (DVec2::new(100.0, 500.0), 400.0, 6.0),
            (DVec2::splat(300.0), 2000.0, 25.0),
        ] {
            let scanned = pairs_across(&outlines, center, reach, r, (0.8, 4.0), all);
            let indexed = medial_samples(&outlines, center, reach, r, (0.8, 4.0));
            assert!(scanned.len() > 50, "the clutter pairs ({})", scanned.len());
            assert_eq!(indexed, scanned, "centre {center}, reach {reach}, r {r}");
            // Every chain meets the same junctions as when it is tested against every
            // other chain.
            let chains = chains(indexed);
            let others = Others::new(&chains);
            for (i, chain) in chains.iter().enumerate() {
                let every: Vec<&[Medial]> = chains
                    .iter()
                    .enumerate()
                    .filter(|(j, c)| *j != i && tube_like(c) && !shares_a_stroke(c, chain))
                    .map(|(_, c)| c.as_slice())
                    .collect();
                assert_eq!(
                    junctions(chain, &others.of(i)),
                    junctions(chain, &every),
                    "chain {i}"
                );
            }
        }
    }

    #[test]
    fn an_arm_drawn_across_a_post_stops_at_the_post() {
        // Two concentric U outlines (an arm pair) and a post drawn across their bottom.
        let strokes = vec![u(90.0), u(110.0), post(-12.0), post(12.0)];
        let found = tube(&strokes, DVec2::new(-30.0, -95.0), DVec2::new(-95.0, -20.0));
        assert!(found.samples.len() >= 8);
        assert!(
            found.samples.iter().all(|(p, _)| p.x < 3.0),
            "only the left half: {:?}",
            found.samples
        );
        assert!(found
            .samples
            .iter()
            .any(|(p, _)| p.x > -15.0 && p.y < -90.0));
        assert!(found.samples.iter().all(|(_, w)| (*w - 10.0).abs() < 2.0));
        // Both outlines stop at the post's centre line, and the post is not the arm's.
        assert_eq!(found.stops.len(), 2);
        assert!(found.stops.iter().all(|s| s.at.x.abs() < 3.0));
        let mut across = found.across.clone();
        across.sort_unstable();
        assert_eq!(across, vec![2, 3]);
        // The other arm is found from a drop on the right.
        let right = tube(&strokes, DVec2::new(30.0, -95.0), DVec2::new(95.0, -20.0));
        assert!(right.samples.iter().all(|(p, _)| p.x > -3.0));
    }

    #[test]
    fn only_another_parts_outlines_make_a_junction() {
        // A chain of the pair (0, 1) along x, crossed at x = 0 by a chain of the same
        // tube's outline 1 paired another way, and by one of another part's pair (2, 3).
        let chain = |pair: (usize, usize), from: DVec2, to: DVec2| -> Vec<Medial> {
            (0..=20)
                .map(|i| {
                    let t = f64::from(i) / 20.0;
                    Medial {
                        at: from.lerp(to, t),
                        half: 5.0,
                        pair,
                        along: 200.0 * t,
                        along_b: 200.0 * t,
                        from: pair.0,
                    }
                })
                .collect()
        };
        let tube = chain((0, 1), DVec2::new(-100.0, 0.0), DVec2::new(100.0, 0.0));
        let same = chain((1, 4), DVec2::new(0.0, -100.0), DVec2::new(0.0, 100.0));
        let other = chain((2, 3), DVec2::new(0.0, -100.0), DVec2::new(0.0, 100.0));
        let drop = [DVec2::new(20.0, 0.0), DVec2::new(90.0, 0.0)];
        let count = |chains: &[Vec<Medial>]| {
            cut_at_junctions(chains, drop)
                .iter()
                .filter(|p| p.samples[0].pair == (0, 1))
                .count()
        };
        assert_eq!(count(&[tube.clone(), same]), 1);
        assert_eq!(count(&[tube, other]), 2);
    }

    #[test]
    fn a_drop_over_the_junction_keeps_the_whole_tube() {
        let strokes = vec![u(90.0), u(110.0), post(-12.0), post(12.0)];
        let found = tube(&strokes, DVec2::new(-90.0, -40.0), DVec2::new(90.0, -40.0));
        assert!(found.stops.is_empty());
        assert!(found.samples.iter().any(|(p, _)| p.x < -60.0));
        assert!(found.samples.iter().any(|(p, _)| p.x > 60.0));
    }

    #[test]
    fn an_outline_drawn_in_two_strokes_is_read_whole() {
        // A straight tube along x: one outline whole, the other in two strokes with a gap.
        let line = |y: f64, x0: f64, x1: f64| -> Vec<DVec2> {
            (0..=20)
                .map(|i| DVec2::new(x0 + (x1 - x0) * f64::from(i) / 20.0, y))
                .collect()
        };
        let strokes = vec![
            line(-10.0, 0.0, 200.0),
            line(10.0, 0.0, 80.0),
            line(10.0, 110.0, 200.0),
        ];
        let found = tube(&strokes, DVec2::new(20.0, 0.0), DVec2::new(180.0, 0.0));
        assert!(found.samples.iter().any(|(p, _)| p.x < 40.0));
        assert!(found.samples.iter().any(|(p, _)| p.x > 160.0));
    }

    #[test]
    fn an_outline_is_clipped_on_the_tubes_side_of_a_junction() {
        let points: Vec<DVec2> = (0..=10)
            .map(|i| DVec2::new(f64::from(i) * 10.0, 0.0))
            .collect();
        let keep_start = Stop {
            stroke: 0,
            at: DVec2::new(45.0, 3.0),
            inside: 10.0,
        };
        let clipped_start = clipped(&points, &[&keep_start]).unwrap();
        assert!(clipped_start.first().unwrap().distance(DVec2::ZERO) < 1e-9);
        assert!(
            clipped_start
                .last()
                .unwrap()
                .distance(DVec2::new(45.0, 0.0))
                < 1e-9
        );
        let keep_end = Stop {
            inside: 90.0,
            ..keep_start
        };
        let clipped_end = clipped(&points, &[&keep_end]).unwrap();
        assert!(clipped_end.first().unwrap().distance(DVec2::new(45.0, 0.0)) < 1e-9);
        assert!(clipped_end.last().unwrap().distance(DVec2::new(100.0, 0.0)) < 1e-9);
    }

    #[test]
    fn a_stroke_drawn_on_across_a_post_is_trimmed_at_the_post() {
        // A wall at x = 0 along y (a post), the tube on the side of negative x, 10 wide.
        let wall = Wall {
            at: DVec2::ZERO,
            direction: DVec2::Y,
            inward: DVec2::NEG_X,
            half: 10.0,
        };
        let through: Vec<DVec2> = (0..=10)
            .map(|i| DVec2::new(f64::from(i) * 10.0 - 60.0, 5.0))
            .collect();
        let kept = trimmed(&through, &wall).unwrap();
        assert!(kept.iter().all(|p| p.x <= 0.0));
        assert_eq!(kept.len(), 7);
        // Far along the post (beyond four tube widths) nothing is the tube's business.
        let far: Vec<DVec2> = through
            .iter()
            .map(|p| *p + DVec2::new(0.0, 100.0))
            .collect();
        assert!(trimmed(&far, &wall).is_none());
    }
}
