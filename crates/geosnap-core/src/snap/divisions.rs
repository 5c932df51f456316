//! Lines drawn across a reading from one side of its outline to another: where two parts
//! read as one meet.
//!
//! A designer draws no edge across a part's face from outline to outline. Such a line is
//! where two parts meet (drawers in a chest, books on a shelf), and the reading that
//! holds it is two parts read as one (`snap::divides` weighs it).
//!
//! A hand does not draw that line in one clean stroke. It breaks it with gaps, stops it
//! short of the outline or runs it on past it, and draws it in two or three pieces. So:
//! - the straight pieces the reading swallows (`swallowed::swallowed_runs`, lines that run
//!   on out of the outline included) that lie on one line are joined into one line;
//! - a line counts as drawn across when its two ends come within `reach` of the reading's
//!   visible curves;
//! - it also counts when it stops short, if what is drawn of it covers at least
//!   [`ACROSS`] of the way between the two visible curves it runs towards (the first each
//!   end's ray crosses).
//!
//! Before pieces were joined and short lines counted, a row of five drawers whose division
//! lines were drawn with gaps and undershoots held one line where four were drawn, and the
//! drawer meant, which holds one line of its neighbour's, could not divide it.

use glam::DVec2;

use super::assign::{curve_distance, Assignment};
use super::context::SnapContext;
use super::cut::{self, MIN_LINE};
use super::swallowed::swallowed_runs;
use crate::primitive::Primitive;

/// A straight piece shorter than this share of the reading's size is too short to say
/// which way it runs: left out.
const MIN_PIECE: f64 = 0.05;

/// Two pieces lie on one line when the angle between them is under this (radians) …
const COLLINEAR_ANGLE: f64 = 0.1;

/// … and each end of the shorter lies within this many bands of the longer's line.
const COLLINEAR_BANDS: f64 = 2.0;

/// A line that stops short of the outline divides the reading when what is drawn of it
/// covers at least this share of the way between the visible curves it runs towards: a
/// hand's undershoot at either end, not a mark on the face.
pub(crate) const ACROSS: f64 = 0.6;

/// The lines `primitive` holds across it from one side of its outline to another (module
/// docs), each as its two drawn ends, with `band` the hand's noise about a curve and
/// `reach` how near the outline a line's end must come.
pub(crate) fn divisions(
    context: &SnapContext,
    primitive: &Primitive,
    assignment: &Assignment,
    (band, reach): (f64, f64),
) -> Vec<Vec<DVec2>> {
    // A line across may run on out of the outline (a hand's overshoot): every line
    // inside counts, as for a cut.
    let runs = swallowed_runs(context, primitive, assignment, band, true);
    if runs.is_empty() {
        return Vec::new();
    }
    let size = primitive.size();
    let pieces: Vec<(DVec2, DVec2)> = runs
        .iter()
        .filter(|run| cut::straight(run).is_some_and(|l| l >= MIN_PIECE * size))
        .map(|run| (run[0], run[run.len() - 1]))
        .collect();
    let visible = cut::visible_curves(primitive);
    let near_curve = |p: DVec2, within: f64| visible.iter().any(|c| curve_distance(c, p) <= within);
    // The visible curves as segments, for a line's way across (an ellipse in 48).
    let segments: Vec<(DVec2, DVec2)> = visible
        .iter()
        .flat_map(|c| {
            let points = c.points(48);
            (1..points.len())
                .map(|k| (points[k - 1], points[k]))
                .collect::<Vec<_>>()
        })
        .collect();
    lines(&pieces, band)
        .into_iter()
        .filter(|line| {
            let (a, b) = line.ends;
            if a.distance(b) < MIN_LINE * size {
                return false;
            }
            if near_curve(a, reach) && near_curve(b, reach) {
                return true;
            }
            // Stopped short: on from each end to the visible curve it runs towards, no
            // farther than would leave what is drawn under [`ACROSS`] of the way.
            let farthest = line.drawn * (1.0 / ACROSS - 1.0);
            let towards =
                |from: DVec2, direction: DVec2| meets_curve(from, direction, farthest, &segments);
            let along = (b - a).normalize_or_zero();
            match (towards(a, -along), towards(b, along)) {
                (Some(ea), Some(eb)) => line.drawn >= ACROSS * ea.distance(eb),
                _ => false,
            }
        })
        .map(|line| vec![line.ends.0, line.ends.1])
        .collect()
}

/// Straight pieces joined into one line: its two extreme ends and the length drawn along
/// it (the union of its pieces' extents).
#[derive(Clone, Debug)]
struct Line {
    ends: (DVec2, DVec2),
    drawn: f64,
}

/// The `pieces` (each a chord) grouped into lines ([`COLLINEAR_ANGLE`],
/// [`COLLINEAR_BANDS`]), longest pieces first, each piece in one line.
fn lines(pieces: &[(DVec2, DVec2)], band: f64) -> Vec<Line> {
    let mut order: Vec<usize> = (0..pieces.len()).collect();
    order.sort_by(|&i, &j| {
        let length = |k: usize| pieces[k].0.distance(pieces[k].1);
        length(j).total_cmp(&length(i))
    });
    let mut used = vec![false; pieces.len()];
    let mut lines = Vec::new();
    for &i in &order {
        if used[i] {
            continue;
        }
        used[i] = true;
        let (a, b) = pieces[i];
        let along = (b - a).normalize_or_zero();
        let normal = along.perp();
        let mut members = vec![i];
        for &j in &order {
            if used[j] {
                continue;
            }
            let (c, d) = pieces[j];
            let direction = (d - c).normalize_or_zero();
            let parallel = direction.dot(along).abs() >= COLLINEAR_ANGLE.cos();
            let on_line = [c, d]
                .iter()
                .all(|p| (*p - a).dot(normal).abs() <= COLLINEAR_BANDS * band);
            if parallel && on_line {
                used[j] = true;
                members.push(j);
            }
        }
        // The members' extents along the line, merged.
        let mut spans: Vec<(f64, f64)> = members
            .iter()
            .map(|&k| {
                let (t0, t1) = ((pieces[k].0 - a).dot(along), (pieces[k].1 - a).dot(along));
                (t0.min(t1), t0.max(t1))
            })
            .collect();
        spans.sort_by(|x, y| x.0.total_cmp(&y.0));
        let (mut drawn, mut current) = (0.0, spans[0]);
        for s in &spans[1..] {
            if s.0 <= current.1 {
                current.1 = current.1.max(s.1);
            } else {
                drawn += current.1 - current.0;
                current = *s;
            }
        }
        drawn += current.1 - current.0;
        let (lo, hi) = (
            spans[0].0,
            spans.iter().map(|s| s.1).fold(f64::MIN, f64::max),
        );
        lines.push(Line {
            ends: (a + along * lo, a + along * hi),
            drawn,
        });
    }
    lines
}

/// Where the ray from `from` along `direction` (a unit vector) first crosses one of the
/// `segments` (the reading's visible curves as polylines), within `farthest`; `None`
/// when it crosses none that near.
fn meets_curve(
    from: DVec2,
    direction: DVec2,
    farthest: f64,
    segments: &[(DVec2, DVec2)],
) -> Option<DVec2> {
    segments
        .iter()
        .filter_map(|&(p, q)| {
            // from + t·direction = p + s·(q − p), 0 ≤ t ≤ farthest, 0 ≤ s ≤ 1.
            let edge = q - p;
            let denominator = direction.perp_dot(edge);
            if denominator.abs() <= f64::EPSILON * edge.length().max(1.0) {
                return None;
            }
            let offset = p - from;
            let t = offset.perp_dot(edge) / denominator;
            let s = offset.perp_dot(direction) / denominator;
            ((0.0..=farthest).contains(&t) && (0.0..=1.0).contains(&s)).then_some(t)
        })
        .min_by(f64::total_cmp)
        .map(|t| from + direction * t)
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec2, DVec3};

    use super::divisions;
    use crate::primitive::{Cuboid, Primitive};
    use crate::snap::swallowed::tests::{context, line, nothing};

    /// Two drawers read as one box, seen face on: a 300 × 200 outline centred at the
    /// origin, the line between the drawers at x = 0.
    fn pair() -> Primitive {
        Primitive::Cuboid(Cuboid {
            center: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
            size: DVec3::new(300.0, 200.0, 50.0),
        })
    }

    /// The divisions `strokes` draw across [`pair`], with a band of 3 and the reach of a
    /// tenth of its size beyond it.
    fn lines_across(strokes: &[Vec<DVec2>]) -> usize {
        let part = pair();
        let reach = 3.0 + 0.1 * part.size();
        divisions(&context(strokes), &part, &nothing(&part), (3.0, reach)).len()
    }

    #[test]
    fn a_line_across_drawn_whole_divides() {
        let whole = line(DVec2::new(0.0, -101.0), DVec2::new(0.0, 101.0));
        assert_eq!(lines_across(&[whole]), 1);
    }

    #[test]
    fn a_line_across_drawn_in_two_pieces_with_a_gap_divides_once() {
        let below = line(DVec2::new(0.0, -99.0), DVec2::new(0.0, -15.0));
        let above = line(DVec2::new(1.0, 20.0), DVec2::new(1.0, 99.0));
        assert_eq!(lines_across(&[below, above]), 1);
    }

    #[test]
    fn a_line_across_that_stops_short_of_the_outline_divides() {
        // Drawn over three quarters of the way: 45 short of one side, 5 of the other.
        let short = line(DVec2::new(0.0, -55.0), DVec2::new(0.0, 95.0));
        assert_eq!(lines_across(&[short]), 1);
    }

    #[test]
    fn a_mark_on_the_face_does_not_divide() {
        // Drawn over 40 % of the way across.
        let mark = line(DVec2::new(0.0, -30.0), DVec2::new(0.0, 50.0));
        assert_eq!(lines_across(&[mark]), 0);
        // Two marks that do not lie on one line.
        let left = line(DVec2::new(-40.0, -99.0), DVec2::new(-40.0, -15.0));
        let right = line(DVec2::new(40.0, 20.0), DVec2::new(40.0, 99.0));
        assert_eq!(lines_across(&[left, right]), 0);
    }
}
