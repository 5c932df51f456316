//! Strokes cut where they turn round a tube's end.
//!
//! A hand often draws a tube's outline, the arc across its end and its other outline as
//! one U-shaped stroke, or an outline and its end arc as one L. The medial axis pairs an
//! outline with *another* stroke across the tube, so such a stroke would find no partner
//! and its end arc would never be read as an end. [`runs`] cuts a stroke into runs where
//! it turns sharply over a short stretch: the legs, and the turn between them (which
//! holds the end arc). The turning is measured over a stretch of [`WINDOW`] tube radii
//! either side of each point, the scale of the tube and not of the stroke, so that a
//! hand's wobble, which is small against the tube, averages out whatever the stroke's
//! length. Rounding an end turns a stroke by 90° (a flat end's corner) to 180° (a round
//! end's half ellipse, about a radius across) within that stretch; a tube's own outlines
//! bend more slowly: the inner outline of a bend whose radius is 2.5 tube radii turns by
//! under [`TURN`] over it.
//!
//! A stroke that winds round (an end ellipse drawn whole) is never cut: its tips turn
//! sharply, but it draws one curve.

use std::ops::Range;

use glam::DVec2;

use super::medial::arc_lengths;

/// The stretch over which a stroke's turning is measured, either side of each point, in
/// tube radii.
const WINDOW: f64 = 1.5;
/// A point where the stroke turns by more than this (radians) between the stretches
/// either side of it lies on a turn.
const TURN: f64 = 55.0 * std::f64::consts::PI / 180.0;
/// A run between turns shorter than this many tube radii is part of the turn (a flat
/// end's arc between its two corners, or a wobble between two sharp bends, is no leg).
const MIN_LEG: f64 = 2.0;

/// Whether a stroke winds round (an ellipse drawn whole, give or take a hand's miss):
/// its signed turning adds up to more than 270°. A U turns by 180°, an S by about
/// nothing; a hand's wobble cancels in the sum.
fn winds_round(points: &[DVec2]) -> bool {
    let turning: f64 = points
        .windows(3)
        .map(|w| {
            let (a, b) = (w[1] - w[0], w[2] - w[1]);
            if a.length() == 0.0 || b.length() == 0.0 {
                0.0
            } else {
                a.angle_to(b)
            }
        })
        .sum();
    turning.abs() > 1.5 * std::f64::consts::PI
}

/// The point index ranges of `points` cut at its sharp turns for a tube of radius about
/// `r` (see the module docs), in order, covering every point once: the legs and the turns
/// between them. A stroke with no sharp turn, or that closes on itself, is one run.
pub(super) fn runs(points: &[DVec2], r: f64) -> Vec<Range<usize>> {
    let n = points.len();
    let whole: Vec<Range<usize>> = std::iter::once(0..n).collect();
    if n < 8 {
        return whole;
    }
    let s = arc_lengths(points);
    let total = s[n - 1];
    if !(total > 0.0 && r > 0.0) || winds_round(points) {
        return whole;
    }
    let h = WINDOW * r;
    let on_turn: Vec<bool> = (0..n)
        .map(|i| {
            let back = s[..i].partition_point(|x| *x <= s[i] - h).saturating_sub(1);
            let back = if s[i] - s[back] >= h { back } else { 0 };
            let ahead = i + s[i..].partition_point(|x| *x < s[i] + h);
            let ahead = ahead.min(n - 1);
            let (din, dout) = (points[i] - points[back], points[ahead] - points[i]);
            if back == i || ahead == i || din.length() == 0.0 || dout.length() == 0.0 {
                return false;
            }
            din.angle_to(dout).abs() > TURN
        })
        .collect();
    // Runs of equal marks; legs shorter than MIN_LEG join the turns around them.
    let mut cuts: Vec<(Range<usize>, bool)> = Vec::new();
    let mut start = 0;
    for i in 1..=n {
        if i == n || on_turn[i] != on_turn[start] {
            cuts.push((start..i, on_turn[start]));
            start = i;
        }
    }
    let length = |r: &Range<usize>| s[(r.end - 1).min(n - 1)] - s[r.start];
    for cut in &mut cuts {
        if !cut.1 && length(&cut.0) < MIN_LEG * r {
            cut.1 = true;
        }
    }
    let mut merged: Vec<(Range<usize>, bool)> = Vec::new();
    for (range, turn) in cuts {
        match merged.last_mut() {
            Some((last, t)) if *t == turn => last.end = range.end,
            _ => merged.push((range, turn)),
        }
    }
    if !merged.iter().any(|(_, turn)| *turn) || !merged.iter().any(|(_, turn)| !*turn) {
        return whole;
    }
    merged.into_iter().map(|(range, _)| range).collect()
}

/// [`runs`] of a stroke that draws both outlines of a tube: cut only where two of its
/// legs run alongside each other between `widths.0`·r and `widths.1`·r apart (a U round
/// the tube's end), else the whole stroke. A stroke that turns only where the tube
/// flares, or where an S-bend turns, draws one outline and stays whole.
pub(super) fn u_runs(points: &[DVec2], r: f64, widths: (f64, f64)) -> Vec<Range<usize>> {
    let whole: Vec<Range<usize>> = std::iter::once(0..points.len()).collect();
    let cut = runs(points, r);
    if cut.len() < 3 {
        return whole;
    }
    let s = arc_lengths(points);
    let length = |range: &Range<usize>| s[range.end - 1] - s[range.start];
    let mut legs: Vec<&Range<usize>> = cut.iter().filter(|x| length(x) >= MIN_LEG * r).collect();
    legs.sort_by(|a, b| length(b).total_cmp(&length(a)));
    let [a, b, ..] = legs.as_slice() else {
        return whole;
    };
    let (a, b) = (&points[(*a).clone()], &points[(*b).clone()]);
    let middle = a[a.len() / 2];
    let across = b
        .windows(2)
        .map(|w| crate::geom::segment_distance(w[0], w[1], middle))
        .fold(f64::INFINITY, f64::min);
    if (widths.0 * r..=widths.1 * r).contains(&across) {
        cut
    } else {
        whole
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::{runs, u_runs};

    /// A U: down a line, across a flat end and back up, as a thin tube seen from the side
    /// is drawn in one stroke.
    fn u_stroke() -> Vec<DVec2> {
        let mut u: Vec<DVec2> = (0..=40)
            .map(|i| DVec2::new(0.0, 2.5 * f64::from(i)))
            .collect();
        u.extend((1..10).map(|i| DVec2::new(2.0 * f64::from(i), 100.0 + f64::from(i % 2))));
        u.extend((0..=40).map(|i| DVec2::new(20.0, 100.0 - 2.5 * f64::from(i))));
        u
    }

    #[test]
    fn a_u_is_cut_into_two_legs_and_the_end_between_them() {
        let u = u_stroke();
        let r = runs(&u, 10.0);
        assert_eq!(r.len(), 3, "{r:?}");
        assert_eq!(r[0].start, 0);
        assert_eq!(r[2].end, u.len());
        for w in r.windows(2) {
            assert_eq!(w[0].end, w[1].start);
        }
        // The legs are the long straight parts; the end (x 0–20 at y ≈ 100) is in the
        // middle run.
        assert!(r[0].len() > 30 && r[2].len() > 30, "{r:?}");
        assert!(r[1].clone().any(|i| (u[i].x - 10.0).abs() < 2.5));
        assert!(r[0].clone().all(|i| u[i].y < 100.0 && u[i].x < 1.0));
        // Its legs lie 2 radii apart: a U round a tube's end.
        assert_eq!(u_runs(&u, 10.0, (0.8, 4.0)), r);
        // Round a tube of radius 2 they are 10 radii apart: no tube's outlines.
        assert_eq!(u_runs(&u, 2.0, (0.8, 4.0)), vec![0..u.len()]);
    }

    #[test]
    fn degenerate_strokes_stay_whole() {
        // Too short, all one point, NaN coordinates, a NaN radius: one run, no panic.
        let short = vec![DVec2::ZERO, DVec2::X];
        assert_eq!(runs(&short, 10.0), vec![0..2]);
        let point = vec![DVec2::ONE; 20];
        assert_eq!(runs(&point, 10.0), vec![0..20]);
        let mut u = u_stroke();
        u[5] = DVec2::NAN;
        assert_eq!(u_runs(&u, 10.0, (0.8, 4.0)), vec![0..u.len()]);
        assert_eq!(runs(&u_stroke(), f64::NAN), vec![0..u.len()]);
    }

    #[test]
    fn a_slowly_bending_outline_and_a_closed_ellipse_stay_whole() {
        // 61 points round an axis-aligned ellipse of semi-axes `a` and `b`, through
        // `turn` radians from its +x tip.
        let round = |turn: f64, a: f64, b: f64| -> Vec<DVec2> {
            (0..=60)
                .map(|i| {
                    let t = turn * f64::from(i) / 60.0;
                    DVec2::new(a * t.cos(), b * t.sin())
                })
                .collect()
        };
        // A quarter circle of radius 100: a C-tube's outline.
        let arc = round(std::f64::consts::FRAC_PI_2, 100.0, 100.0);
        assert_eq!(runs(&arc, 10.0), vec![0..arc.len()]);
        // The inner outline of a tight bend: radius 25 for a tube of radius 10.
        let inner: Vec<DVec2> = arc.iter().map(|p| *p / 4.0).collect();
        assert_eq!(runs(&inner, 10.0), vec![0..inner.len()]);
        // A flat ellipse drawn all round: sharp at its tips, but one curve.
        let ellipse = round(std::f64::consts::TAU, 50.0, 8.0);
        assert_eq!(runs(&ellipse, 10.0), vec![0..ellipse.len()]);
    }
}
