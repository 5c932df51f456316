//! A line gone over more than once: whether one stroke is a hand's copy of another.
//!
//! A rough hand draws a line as two or three strokes that lie a little apart, each of the
//! same shape: the line meant is the middle of them. A curve's competition for strokes
//! keeps only those that fit about as well as its best one (`assign`), so a fit that
//! settles on one copy drops the others and stays on it, a copy's offset off the line.
//! A stroke the competition dropped is a copy of a kept one, and stays, when:
//! - it runs along the kept stroke: shifted by one constant offset ([`copy_offset`]),
//!   most of each lies beside the other (a short neighbour's outline beside a long edge
//!   does not);
//! - so shifted, it fits the curve as well as the competition asks of any stroke (its
//!   shape is the line's: a smaller ellipse set on an end, or a straight line beside an
//!   ellipse, fits no better for being moved);
//! - the offset is less than half the way to the part's next line across ([`widths`]):
//!   a hand keeps the copies of one line nearer to each other than to the next line it
//!   means, and a box's parallel edge or a tube's other outline is a line of its own;
//! - it is taken whole: a hand's copy is a stroke of its own (a piece of a longer
//!   stroke, a neighbour's outline running on, is left to the competition).
//!
//! Only once the pose is fitted: at a hand's drop, the curves are too rough to say
//! which line is which.

use glam::DVec2;

use super::assign::{curve_distance, distance_across, AssignedStroke};
use crate::primitive::{Curve2, ProjectedCurve};

/// Rounds of the offset's estimate (each moves the copy by the mean of its samples'
/// offsets to their nearest points on the other stroke).
const ROUNDS: usize = 6;

/// The share of a copy's samples that must lie along the stroke it copies (beside it,
/// not past its ends), and of that stroke's samples along the copy.
const ALONGSIDE: f64 = 0.8;

/// Whether `stroke`, which the competition for `curve` dropped at `score`, is a copy of
/// one of the strokes it `kept` (module docs): `allowed` is the score the competition
/// asks of a stroke, `within` the farthest a copy may lie from the stroke it copies
/// (half of the curve's entry in [`widths`]).
pub(crate) fn is_copy(
    curve: &Curve2<f64>,
    stroke: &AssignedStroke,
    score: f64,
    kept: &[AssignedStroke],
    allowed: f64,
    within: f64,
) -> bool {
    if stroke.part.is_some() || stroke.samples.is_empty() {
        return false;
    }
    // The score over the mean distance: the factor of the stroke's class for the curve.
    let factor = if stroke.mean_distance > 0.0 {
        score / stroke.mean_distance
    } else {
        1.0
    };
    kept.iter().any(|original| {
        copy_offset(&stroke.samples, &original.samples).is_some_and(|offset| {
            let shifted: Vec<DVec2> = stroke.samples.iter().map(|p| *p - offset).collect();
            let moved = shifted
                .iter()
                .map(|p| curve_distance(curve, *p))
                .sum::<f64>()
                / shifted.len() as f64;
            offset.length() <= within
                && moved * factor <= allowed
                && same_stretch(curve, &shifted, &original.samples)
        })
    })
}

/// Points a curve is cut into to tell which stretch of it a stroke goes over.
const STRETCHES: usize = 64;

/// Whether `copy` goes over the same stretch of `curve` as `original`: most of its
/// samples lie nearest to a piece of the curve (one of [`STRETCHES`]) that `original`
/// lies nearest to, or one beside such a piece. The back half of a flat ellipse, shifted
/// onto the curve, lies beside its front half's strokes but goes over the other half.
pub(crate) fn same_stretch(curve: &Curve2<f64>, copy: &[DVec2], original: &[DVec2]) -> bool {
    let points = curve.points(STRETCHES);
    if points.len() < 2 || copy.is_empty() {
        return false;
    }
    let closed = matches!(curve, Curve2::Ellipse { .. });
    let n = if closed {
        points.len() - 1
    } else {
        points.len()
    };
    let piece = |p: DVec2| crate::geom::nearest_index(&points[..n], p);
    let mut covered = vec![false; n];
    for p in original {
        // The piece and its neighbours, round the seam of a closed curve.
        let i = piece(*p);
        let before = if i > 0 {
            Some(i - 1)
        } else {
            closed.then_some(n - 1)
        };
        let after = if i + 1 < n {
            Some(i + 1)
        } else {
            closed.then_some(0)
        };
        for j in [before, Some(i), after].into_iter().flatten() {
            covered[j] = true;
        }
    }
    let over = copy.iter().filter(|p| covered[piece(**p)]).count();
    over as f64 >= ALONGSIDE * copy.len() as f64
}

/// How far each of `curves` (a part's projected curves) lies from the next line of the
/// part across from it: for a straight curve, the nearest other straight curve that runs
/// alongside it (measured from its middle); for an ellipse, its minor diameter (its
/// other side). A copy of one of its strokes lies less than half of it away.
/// Infinite where nothing lies across.
pub(crate) fn widths(curves: &[ProjectedCurve<f64>]) -> Vec<f64> {
    (0..curves.len())
        .map(|k| match &curves[k].curve {
            Curve2::Ellipse { a, b, .. } => 2.0 * a.to_dvec2().length().min(b.to_dvec2().length()),
            Curve2::Polyline(_) => distance_across(curves, k, false),
        })
        .collect()
}

/// The nearest point of the polyline `line` to `p`, and whether it lies at one of the
/// polyline's ends (`p` is past it, not beside it).
fn nearest(line: &[DVec2], p: DVec2) -> (DVec2, bool) {
    let mut best = (line[0], f64::INFINITY, true);
    let last = line.len() - 1;
    for (i, w) in line.windows(2).enumerate() {
        let d = w[1] - w[0];
        let t = if d.length_squared() > 0.0 {
            ((p - w[0]).dot(d) / d.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = w[0] + d * t;
        let dist = q.distance_squared(p);
        if dist < best.1 {
            let end = (i == 0 && t <= 0.0) || (i + 1 == last && t >= 1.0);
            best = (q, dist, end);
        }
    }
    (best.0, best.2)
}

/// The offset by which `stroke` runs along `of` (`of` ≈ `stroke` shifted back by it),
/// when it does: shifted by the offset, most of its samples lie beside `of` (not past
/// its ends), most of `of`'s beside it, and the two are about as long. The offset is estimated as the mean of the
/// samples' offsets to their nearest points on `of`, in a few rounds. `None` for a
/// stroke of fewer than three samples, one that does not run along `of`, or one that
/// lies on it already (no offset).
pub(crate) fn copy_offset(stroke: &[DVec2], of: &[DVec2]) -> Option<DVec2> {
    if stroke.len() < 3 || of.len() < 2 {
        return None;
    }
    let mut shift = DVec2::ZERO;
    for _ in 0..ROUNDS {
        let (sum, n) = stroke
            .iter()
            .map(|p| (*p + shift, nearest(of, *p + shift)))
            .filter(|(_, (_, end))| !end)
            .fold((DVec2::ZERO, 0usize), |(s, n), (p, (q, _))| {
                (s + (q - p), n + 1)
            });
        if n == 0 {
            return None;
        }
        shift += sum / n as f64;
    }
    let along = stroke
        .iter()
        .filter(|p| !nearest(of, **p + shift).1)
        .count();
    let back = of
        .iter()
        .filter(|p| !nearest(stroke, **p - shift).1)
        .count();
    // Beside each other for most of their lengths, and about as long (so that, say, a
    // flat ellipse's two halves, both beside one arc, do not pass for a copy of it).
    let length = |line: &[DVec2]| line.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
    let (a, b) = (length(stroke), length(of));
    let mutual = along as f64 >= ALONGSIDE * stroke.len() as f64
        && back as f64 >= ALONGSIDE * of.len() as f64
        && a.min(b) >= ALONGSIDE * a.max(b);
    let offset = shift.length();
    (mutual && offset > 0.0 && offset.is_finite()).then_some(-shift)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn circle(center: DVec2, r: f64, n: usize) -> Vec<DVec2> {
        (0..=n)
            .map(|i| center + DVec2::from_angle(std::f64::consts::TAU * i as f64 / n as f64) * r)
            .collect()
    }

    #[test]
    fn a_circle_gone_over_a_little_apart_runs_along_it_by_its_offset() {
        let first = circle(DVec2::ZERO, 100.0, 48);
        // The second time round, 6 off to the upper right and a little wobbly.
        let second: Vec<DVec2> = circle(DVec2::new(4.0, 4.5), 100.0, 40)
            .into_iter()
            .enumerate()
            .map(|(i, p)| p + DVec2::splat(0.4 * (i as f64 * 1.7).sin()))
            .collect();
        let offset = copy_offset(&second, &first).expect("a copy");
        assert!(offset.distance(DVec2::new(4.0, 4.5)) < 1.0, "{offset}");
    }

    #[test]
    fn a_short_line_beside_a_long_one_does_not_run_along_it() {
        let edge: Vec<DVec2> = (0..=20).map(|i| DVec2::new(0.0, 10.0 * i as f64)).collect();
        let short: Vec<DVec2> = (0..=5)
            .map(|i| DVec2::new(6.0, 80.0 + 10.0 * i as f64))
            .collect();
        assert_eq!(copy_offset(&short, &edge), None);
        let again: Vec<DVec2> = (0..=20)
            .map(|i| DVec2::new(6.0, 3.0 + 10.0 * i as f64))
            .collect();
        let offset = copy_offset(&again, &edge).expect("a copy");
        assert!((offset.x - 6.0).abs() < 0.1, "{offset}");
    }

    #[test]
    fn a_whole_flat_ellipse_does_not_run_along_its_front_arc() {
        let ellipse: Vec<DVec2> = (0..=48)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / 48.0;
                DVec2::new(100.0 * t.cos(), 12.0 * t.sin())
            })
            .collect();
        let front: Vec<DVec2> = ellipse[..=24].iter().map(|p| *p + DVec2::Y * 3.0).collect();
        assert_eq!(copy_offset(&ellipse, &front), None);
        assert_eq!(copy_offset(&front, &ellipse), None);
    }

    #[test]
    fn the_back_half_of_an_ellipse_goes_over_another_stretch_than_the_front() {
        use crate::ad::Vec2;
        let curve = Curve2::Ellipse {
            center: Vec2::new(0.0, 0.0),
            a: Vec2::new(100.0, 0.0),
            b: Vec2::new(0.0, 12.0),
        };
        let arc = |from: f64| -> Vec<DVec2> {
            (0..=24)
                .map(|i| DVec2::from_angle(from + std::f64::consts::PI * i as f64 / 24.0))
                .map(|d| DVec2::new(100.0 * d.x, 12.0 * d.y))
                .collect()
        };
        let (front, back) = (arc(0.0), arc(std::f64::consts::PI));
        let again: Vec<DVec2> = front.iter().map(|p| *p + DVec2::new(1.0, -0.5)).collect();
        assert!(same_stretch(&curve, &again, &front));
        assert!(!same_stretch(&curve, &back, &front));
    }

    #[test]
    fn a_line_ending_where_the_other_begins_does_not_run_along_it() {
        let first: Vec<DVec2> = (0..=20).map(|i| DVec2::new(10.0 * i as f64, 0.0)).collect();
        let next: Vec<DVec2> = (0..=20)
            .map(|i| DVec2::new(200.0 + 10.0 * i as f64, 0.0))
            .collect();
        assert_eq!(copy_offset(&next, &first), None);
    }
}
