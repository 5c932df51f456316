//! A stroke drawn round a turn, read as the curves it draws.
//!
//! A hand often draws several curves in one movement: down one outline of a cylinder,
//! round its far end and back up the other outline (a U), along two edges of a box that
//! meet at a corner (an L), or down an outline and on round the end (a J). The starting
//! poses read outlines, edges and end ellipses off whole strokes, and such a stroke is
//! none of those whole: neither straight nor an ellipse, it gave them nothing, and the
//! part started from the drop alone (its length as rough as the drop's).
//!
//! [`turn_pieces`] splits such a stroke where it stops running straight: the longest
//! straight run at each of its ends (an outline, an edge) and what lies between them
//! (an end's front arc). The snap context prepares each piece as a stroke of its own
//! under the stroke's id. Nothing is decided here about which curve a piece draws; the
//! readers weigh pieces as they weigh strokes, and the fit assigns the whole stroke in
//! parts against the pose (`assign.rs`). The split needs no pose and no scale: a run is
//! straight as a whole stroke is (its points within 2 % of its length of their line),
//! relative to its own length.

use std::ops::RangeInclusive;

use glam::DVec2;

/// A straight run at an end of a stroke counts as a piece when it has at least this
/// share of the stroke's length: shorter, it is the hook of a hand's start or stop.
const MIN_LEG: f64 = 0.1;

/// A stroke whose straight run from one end covers this share of its points is a
/// straight stroke drawn by a shaky hand, not two curves.
const ALL_STRAIGHT: f64 = 0.9;

/// A stroke whose direction turns by this much in all (radians, 270°) goes round: an
/// ellipse drawn round, not split, as its straight runs are the flat sides of one curve.
/// A U turns by half a turn, an L by a quarter.
const ROUND: f64 = 1.5 * std::f64::consts::PI;

/// The fewest points a piece has.
const MIN_POINTS: usize = 5;

/// A straight run ends at a turn when the stretch as long as it, centred on its end,
/// lies this much less straight than a straight stroke may (RMS distance to its line
/// twice the 2 % of its length): an arc is straight over a short enough stretch, and its
/// run from an end stops only where the straightness runs out, not at a turn.
const TURN: f64 = 0.04;

/// The pieces of a stroke drawn round a turn (module docs), as ranges of its points:
/// its straight runs at either end and the rest between them, or nothing when the
/// stroke is straight, goes round, is too short to tell, or has no straight run at
/// either end that ends at a turn.
pub(crate) fn turn_pieces(points: &[DVec2]) -> Vec<RangeInclusive<usize>> {
    let n = points.len();
    if n < 3 * MIN_POINTS {
        return Vec::new();
    }
    let length = polyline_length(points);
    if !(length > 0.0) || line_rms(points) <= 0.02 * length {
        return Vec::new();
    }
    if net_turn(points).abs() >= ROUND {
        return Vec::new();
    }
    let reversed: Vec<DVec2> = points.iter().rev().copied().collect();
    let head = straight_run(points);
    let tail = n - 1 - straight_run(&reversed);
    if head as f64 >= ALL_STRAIGHT * (n - 1) as f64
        || (n - 1 - tail) as f64 >= ALL_STRAIGHT * (n - 1) as f64
    {
        return Vec::new();
    }
    // Each run counts only where it ends at a turn.
    let turns_at = |k: usize, run: usize| {
        let half = run / 2;
        let window = &points[k.saturating_sub(half)..=(k + half).min(n - 1)];
        line_rms(window) >= TURN * polyline_length(window)
    };
    // … and, as a whole run is straight within a share of its length, it may carry on a
    // little way round the turn: it is trimmed to where the stroke leaves its line.
    let head = if turns_at(head, head) {
        leg_end(points, head)
    } else {
        0
    };
    let tail = if turns_at(tail, n - 1 - tail) {
        n - 1 - leg_end(&reversed, n - 1 - tail)
    } else {
        n - 1
    };
    let cumulative = arc_lengths(points);
    let long = |a: usize, b: usize| {
        b + 1 >= a + MIN_POINTS && cumulative[b] - cumulative[a] >= MIN_LEG * length
    };
    // The two runs overlap where two straight lines meet at a corner (an L): the corner
    // is the point farthest from the chord, and each run ends there.
    let (head, tail) = if head >= tail {
        let corner = farthest_from_chord(points);
        (corner, corner)
    } else {
        (head, tail)
    };
    let mut bounds: Vec<(usize, usize)> = Vec::new();
    let first = long(0, head).then_some((0, head));
    let last = long(tail, n - 1).then_some((tail, n - 1));
    if first.is_none() && last.is_none() {
        return Vec::new();
    }
    let (from, to) = (first.map_or(0, |(_, b)| b), last.map_or(n - 1, |(a, _)| a));
    bounds.extend(first);
    if to >= from + MIN_POINTS - 1 {
        bounds.push((from, to));
    }
    bounds.extend(last);
    bounds.into_iter().map(|(a, b)| a..=b).collect()
}

/// The index of the last point of the longest straight run from the first point: the
/// largest k such that points 0..=k lie as close to their principal line as a straight
/// stroke's do (RMS within 2 % of their length). Running sums keep it linear.
fn straight_run(points: &[DVec2]) -> usize {
    let origin = points[0];
    let (mut sx, mut sy, mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let mut length = 0.0;
    let mut last = 0;
    for (k, p) in points.iter().enumerate() {
        let d = *p - origin;
        sx += d.x;
        sy += d.y;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
        if k > 0 {
            length += p.distance(points[k - 1]);
        }
        let m = (k + 1) as f64;
        if k < 2 || !(length > 0.0) {
            continue;
        }
        // The scatter about the mean; its smaller eigenvalue is the squared distances'
        // sum to the principal line.
        let (cxx, cxy, cyy) = (sxx - sx * sx / m, sxy - sx * sy / m, syy - sy * sy / m);
        let rms = (smaller_eigenvalue(cxx, cxy, cyy).max(0.0) / m).sqrt();
        if rms <= 0.02 * length {
            last = k;
        }
    }
    last
}

/// The end of the straight run 0..=`run` trimmed to where the stroke leaves its line:
/// the line through its first two thirds (surely on the leg), which a hand's wobble
/// leaves at most its largest distance from there; the leg ends at the last point
/// within that (a fifth more, and at least a two-hundredth of the run) of the line.
fn leg_end(points: &[DVec2], run: usize) -> usize {
    let sure = 2 * run / 3;
    if sure < MIN_POINTS {
        return run;
    }
    let first = &points[..=sure];
    let (mean, normal, _) = principal_line(first);
    let off = |p: &DVec2| (*p - mean).dot(normal).abs();
    let widest = first.iter().map(off).fold(0.0, f64::max);
    let tolerance = (1.2 * widest).max(0.005 * polyline_length(&points[..=run]));
    (sure..=run)
        .take_while(|k| off(&points[*k]) <= tolerance)
        .last()
        .unwrap_or(run)
}

/// How far a stroke's direction turns from its start to its end (radians, signed),
/// read over 32 chords so that a hand's jitter does not count.
fn net_turn(points: &[DVec2]) -> f64 {
    let step = (points.len() / 32).max(1);
    let chords: Vec<DVec2> = points
        .iter()
        .step_by(step)
        .collect::<Vec<_>>()
        .windows(2)
        .map(|w| *w[1] - *w[0])
        .filter(|d| d.length_squared() > 0.0)
        .collect();
    chords.windows(2).map(|w| w[0].angle_to(w[1])).sum()
}

/// The RMS distance of points to their principal line.
fn line_rms(points: &[DVec2]) -> f64 {
    principal_line(points).2
}

/// The principal line of points (at least one): their mean, the line's unit normal and
/// their RMS distance to it.
fn principal_line(points: &[DVec2]) -> (DVec2, DVec2, f64) {
    let m = points.len() as f64;
    let mean = points.iter().copied().sum::<DVec2>() / m;
    let (mut cxx, mut cxy, mut cyy) = (0.0, 0.0, 0.0);
    for p in points {
        let d = *p - mean;
        cxx += d.x * d.x;
        cxy += d.x * d.y;
        cyy += d.y * d.y;
    }
    let normal = DVec2::from_angle(0.5 * (2.0 * cxy).atan2(cxx - cyy)).perp();
    (
        mean,
        normal,
        (smaller_eigenvalue(cxx, cxy, cyy).max(0.0) / m).sqrt(),
    )
}

/// The smaller eigenvalue of the symmetric 2×2 matrix [[xx, xy], [xy, yy]].
fn smaller_eigenvalue(xx: f64, xy: f64, yy: f64) -> f64 {
    0.5 * (xx + yy) - (0.25 * (xx - yy).powi(2) + xy * xy).sqrt()
}

/// A polyline's length.
fn polyline_length(points: &[DVec2]) -> f64 {
    points.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// The cumulative arc length at each point.
fn arc_lengths(points: &[DVec2]) -> Vec<f64> {
    let mut total = 0.0;
    let mut out = Vec::with_capacity(points.len());
    out.push(0.0);
    for w in points.windows(2) {
        total += w[0].distance(w[1]);
        out.push(total);
    }
    out
}

/// The index of the point farthest from the chord between the first and last points.
fn farthest_from_chord(points: &[DVec2]) -> usize {
    let (a, b) = (points[0], points[points.len() - 1]);
    let normal = (b - a).perp().normalize_or_zero();
    (0..points.len())
        .max_by(|i, j| {
            let d = |k: usize| (points[k] - a).dot(normal).abs();
            d(*i).total_cmp(&d(*j))
        })
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use glam::DVec2;

    use super::turn_pieces;
    use crate::sketch::{StrokeClass, StrokeId};
    use crate::snap::context::{prepare, SnapStroke};

    /// The pieces of `points`, prepared as strokes.
    fn pieces(points: &[DVec2]) -> Vec<SnapStroke> {
        turn_pieces(points)
            .into_iter()
            .filter_map(|r| prepare(StrokeId(3), points[r].to_vec(), StrokeClass::Silhouette))
            .collect()
    }

    /// Evenly spaced points from `a` to `b`, `b` left out.
    fn line(a: DVec2, b: DVec2, n: usize) -> Vec<DVec2> {
        (0..n).map(|i| a.lerp(b, i as f64 / n as f64)).collect()
    }

    /// Down one outline, round the front arc of a flattened end, back up the other: the
    /// two outlines and the arc, each under the stroke's id.
    #[test]
    fn a_u_stroke_gives_its_outlines_and_its_end_arc() {
        let (r, flat) = (40.0, 0.4);
        let mut points = line(DVec2::new(-r, 200.0), DVec2::new(-r, 0.0), 40);
        points.extend((0..=30).map(|i| {
            let t = PI + PI * f64::from(i) / 30.0;
            DVec2::new(r * t.cos(), flat * r * t.sin())
        }));
        points.extend(
            line(DVec2::new(r, 0.0), DVec2::new(r, 200.0), 41)
                .into_iter()
                .skip(1),
        );
        let pieces = pieces(&points);
        assert_eq!(pieces.len(), 3, "{pieces:?}");
        for outline in [&pieces[0], &pieces[2]] {
            assert!(outline.straight, "{outline:?}");
            assert!(outline.direction.x.abs() < 0.05, "{:?}", outline.direction);
            assert!(
                outline.length > 180.0 && outline.length < 215.0,
                "{}",
                outline.length
            );
        }
        let arc = &pieces[1];
        assert!(!arc.straight);
        let (lo, hi) = arc.bounds;
        assert!((hi.x - lo.x - 2.0 * r).abs() < 0.1 * r, "{:?}", arc.bounds);
        assert!(
            hi.y < 0.2 * r,
            "the arc stays below the outlines' ends: {:?}",
            arc.bounds
        );
    }

    /// Two box edges drawn as one stroke round their corner: two straight pieces that
    /// meet there.
    #[test]
    fn an_l_stroke_gives_its_two_edges() {
        let corner = DVec2::new(100.0, 20.0);
        let mut points = line(DVec2::ZERO, corner, 30);
        points.extend(line(corner, DVec2::new(70.0, 140.0), 30));
        points.push(DVec2::new(70.0, 140.0));
        let pieces = pieces(&points);
        assert_eq!(pieces.len(), 2, "{pieces:?}");
        assert!(pieces.iter().all(|p| p.straight));
        let meets = |p: &SnapStroke| {
            [p.points[0], p.points[p.points.len() - 1]]
                .iter()
                .any(|q| q.distance(corner) < 8.0)
        };
        assert!(pieces.iter().all(meets), "{pieces:?}");
    }

    /// A straight stroke, an ellipse drawn round and an arc alone are not split.
    #[test]
    fn strokes_of_one_curve_are_not_split() {
        let straight = line(DVec2::ZERO, DVec2::new(300.0, 40.0), 60);
        let ellipse: Vec<DVec2> = (0..=80)
            .map(|i| DVec2::from_angle(2.0 * PI * f64::from(i) / 82.0) * DVec2::new(90.0, 20.0))
            .collect();
        let arc: Vec<DVec2> = (0..=40)
            .map(|i| DVec2::from_angle(PI * f64::from(i) / 40.0) * 80.0)
            .collect();
        for points in [straight, ellipse, arc] {
            assert!(turn_pieces(&points).is_empty());
        }
    }
}
