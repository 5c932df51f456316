//! Preparing a polyline for drawing: simplified to the pixel grid, then cut into pieces.
//!
//! tiny-skia fills a stroked path scanline by scanline, keeping the edges that cross the
//! current scanline sorted by x. A single path of many long, crossing segments (a 100k
//! point scribble) keeps a huge edge list re-sorted on every scanline, and a path whose
//! points lie a hundredth of a pixel apart steps every one of its edges down every
//! scanline they cross, although they all land on the same pixels. So, before drawing:
//!
//! 1. [`simplify`] replaces every run of points that stays within a strip `tolerance`
//!    wide by at most three of them (its two extremes along the strip and its last
//!    point). The drawn line moves by at most `tolerance` (a sub-pixel distance, which is
//!    invisible), and its ends stay where they were.
//! 2. [`pieces`] cuts what is left into pieces of at most [`PIECE_SEGMENTS`] segments that
//!    share their end points. With round caps and round joins, the union of the pieces'
//!    strokes is the stroke of the whole polyline (a round join is the disc that two
//!    round caps at the same point make), so the picture is the same, but no scanline
//!    ever holds more than one piece's edges.

use glam::DVec2;

/// The most segments drawn as one path.
pub(super) const PIECE_SEGMENTS: usize = 64;

/// The polyline `points` (in pixels) with every run of points that stays within a strip
/// `tolerance` wide replaced by at most three of its points.
///
/// A run starts at the last point kept (its anchor) and follows the line from the anchor
/// to the first point more than `tolerance / 2` away from it; it goes on while the
/// points stay within `tolerance / 2` of that line. Of the run, the points that reach
/// furthest back and forth along the line are kept, in their order, and its last point,
/// which anchors the next run. As both the old and the new run lie in the strip and
/// both sweep the same span along it, each point of either lies within `tolerance` of
/// the other: the line moves by at most `tolerance`. The first and last points are
/// always kept; non-finite points are left out; a non-positive or non-finite
/// `tolerance` is taken as zero.
pub(super) fn simplify(points: &[DVec2], tolerance: f64) -> Vec<DVec2> {
    let points: Vec<DVec2> = points.iter().copied().filter(|p| p.is_finite()).collect();
    let half = if tolerance.is_finite() {
        tolerance.max(0.0) / 2.0
    } else {
        0.0
    };
    let Some(&first) = points.first() else {
        return Vec::new();
    };
    let mut kept = vec![first];
    let mut anchor = 0;
    while anchor + 1 < points.len() {
        let (end, direction) = run(&points, anchor, half);
        keep_run(&points, anchor, end, direction, &mut kept);
        anchor = end;
    }
    kept
}

/// The run that starts at `points[anchor]`: the index of its last point (at least
/// `anchor + 1`) and the direction of its line, from the anchor to the first point more
/// than `half` away from it; the run goes on while the points stay within `half` of that
/// line. Without such a point (everything left lies within `half` of the anchor), the
/// run goes to the end and has no direction.
fn run(points: &[DVec2], anchor: usize, half: f64) -> (usize, Option<DVec2>) {
    let a = points[anchor];
    let direction = points[anchor + 1..]
        .iter()
        .find(|p| p.distance(a) > half)
        .and_then(|p| (*p - a).try_normalize());
    let Some(direction) = direction else {
        return (points.len() - 1, None);
    };
    let normal = direction.perp();
    let mut end = anchor + 1;
    while end + 1 < points.len() && (points[end + 1] - a).dot(normal).abs() <= half {
        end += 1;
    }
    (end, Some(direction))
}

/// Keeps, of the run `points[anchor..=end]` whose anchor is already kept, the points
/// that reach furthest back and forth along `direction` (in their order, unless one of
/// them is the anchor or the end), then the end.
fn keep_run(
    points: &[DVec2],
    anchor: usize,
    end: usize,
    direction: Option<DVec2>,
    kept: &mut Vec<DVec2>,
) {
    if let Some(direction) = direction {
        let a = points[anchor];
        let along = |k: usize| (points[k] - a).dot(direction);
        let (mut back, mut forth) = (anchor, anchor);
        for k in anchor + 1..=end {
            if along(k) < along(back) {
                back = k;
            }
            if along(k) > along(forth) {
                forth = k;
            }
        }
        let (first, second) = (back.min(forth), back.max(forth));
        for k in [first, second] {
            if k != anchor && k != end && kept.last() != Some(&points[k]) {
                kept.push(points[k]);
            }
        }
    }
    if kept.last() != Some(&points[end]) || kept.len() == 1 {
        kept.push(points[end]);
    }
}

/// The polyline `points` cut into pieces of at most `segments` segments (at least one),
/// each piece starting where the one before ends. A polyline of one point is one piece.
pub(super) fn pieces(points: &[DVec2], segments: usize) -> impl Iterator<Item = &[DVec2]> {
    let step = segments.max(1);
    let count = points.len().saturating_sub(1).div_ceil(step).max(1);
    (0..count).filter_map(move |k| {
        let start = k * step;
        let end = (start + step + 1).min(points.len());
        points.get(start..end).filter(|piece| !piece.is_empty())
    })
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::{pieces, simplify};

    /// The distance from `p` to the segment `a`–`b`.
    fn to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
        let ab = b - a;
        let t = if ab.length_squared() > 0.0 {
            ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        p.distance(a + ab * t)
    }

    /// The distance from `p` to the polyline `line`.
    fn to_polyline(p: DVec2, line: &[DVec2]) -> f64 {
        if line.len() == 1 {
            return p.distance(line[0]);
        }
        line.windows(2)
            .map(|w| to_segment(p, w[0], w[1]))
            .fold(f64::INFINITY, f64::min)
    }

    /// A bound of the Hausdorff distance between two polylines, from samples along each
    /// (every 0.01 of each segment).
    fn hausdorff(a: &[DVec2], b: &[DVec2]) -> f64 {
        let samples = |line: &[DVec2]| -> Vec<DVec2> {
            let mut out = vec![line[0]];
            for w in line.windows(2) {
                out.extend((1..=100).map(|k| w[0].lerp(w[1], f64::from(k) / 100.0)));
            }
            out
        };
        let one = samples(a)
            .into_iter()
            .map(|p| to_polyline(p, b))
            .fold(0.0, f64::max);
        let other = samples(b)
            .into_iter()
            .map(|p| to_polyline(p, a))
            .fold(0.0, f64::max);
        one.max(other)
    }

    /// A small deterministic generator of numbers in [0, 1).
    fn noise(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn the_ends_are_kept_and_the_line_moves_less_than_the_tolerance() {
        let mut seed = 7;
        let tolerance = 0.25;
        let cases: Vec<Vec<DVec2>> = vec![
            // A dense zigzag, a hundredth of a pixel per step.
            (0..2000)
                .map(|i| DVec2::new(0.01 * f64::from(i), if i % 2 == 0 { 0.0 } else { 70.0 }))
                .collect(),
            // A random walk with small and large steps.
            (0..2000)
                .scan(DVec2::ZERO, |p, i| {
                    let step = if i % 50 == 0 { 30.0 } else { 0.2 };
                    *p += DVec2::new(noise(&mut seed) - 0.5, noise(&mut seed) - 0.5) * step;
                    Some(*p)
                })
                .collect(),
            // A circle sampled finely, and a scribble of long random segments.
            (0..3000)
                .map(|i| DVec2::from_angle(f64::from(i) * 0.002) * 200.0)
                .collect(),
            (0..300)
                .map(|_| DVec2::new(noise(&mut seed), noise(&mut seed)) * 500.0)
                .collect(),
            // Back and forth along one line, then a hook.
            vec![
                DVec2::new(0.0, 0.0),
                DVec2::new(10.0, 0.0),
                DVec2::new(2.0, 0.1),
                DVec2::new(-5.0, 0.0),
                DVec2::new(3.0, 0.0),
                DVec2::new(3.0, 5.0),
            ],
        ];
        for (n, points) in cases.iter().enumerate() {
            let simple = simplify(points, tolerance);
            assert_eq!(simple.first(), points.first(), "case {n}: first point");
            assert_eq!(simple.last(), points.last(), "case {n}: last point");
            assert!(simple.len() <= points.len(), "case {n}: no point added");
            let distance = hausdorff(points, &simple);
            assert!(
                distance <= tolerance + 1e-9,
                "case {n}: moved by {distance} > {tolerance}"
            );
        }
    }

    #[test]
    fn dense_runs_shrink_and_sparse_lines_stay() {
        let zigzag: Vec<DVec2> = (0..10_000)
            .map(|i| DVec2::new(0.01 * f64::from(i), if i % 2 == 0 { 0.0 } else { 700.0 }))
            .collect();
        let simple = simplify(&zigzag, 0.25);
        assert!(simple.len() * 4 <= zigzag.len(), "{} points", simple.len());
        let dense_line: Vec<DVec2> = (0..1000)
            .map(|i| DVec2::new(0.001 * f64::from(i), 0.0))
            .collect();
        assert_eq!(
            simplify(&dense_line, 0.25),
            [dense_line[0], dense_line[999]]
        );
        let square = [
            DVec2::ZERO,
            DVec2::new(10.0, 0.0),
            DVec2::new(10.0, 10.0),
            DVec2::new(0.0, 10.0),
            DVec2::ZERO,
        ];
        assert_eq!(simplify(&square, 0.25), square);
    }

    #[test]
    fn odd_inputs_give_sane_outputs() {
        assert!(simplify(&[], 0.25).is_empty());
        let one = [DVec2::new(1.0, 2.0)];
        assert_eq!(simplify(&one, 0.25), one);
        let same = [DVec2::ONE; 5];
        assert_eq!(simplify(&same, 0.25), [DVec2::ONE, DVec2::ONE]);
        let with_nan = [DVec2::ZERO, DVec2::NAN, DVec2::new(5.0, 0.0)];
        assert_eq!(
            simplify(&with_nan, 0.25),
            [DVec2::ZERO, DVec2::new(5.0, 0.0)]
        );
        let line = [DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(1.0, 0.001)];
        for tolerance in [f64::NAN, -1.0, f64::INFINITY, 0.0] {
            let simple = simplify(&line, tolerance);
            assert_eq!(simple.first(), line.first(), "tolerance {tolerance}");
            assert_eq!(simple.last(), line.last(), "tolerance {tolerance}");
        }
    }

    #[test]
    fn pieces_share_their_ends_and_cover_every_segment() {
        for len in [0usize, 1, 2, 3, 64, 65, 66, 129, 1000] {
            let points: Vec<DVec2> = (0..len).map(|i| DVec2::new(i as f64, 0.0)).collect();
            let cut: Vec<&[DVec2]> = pieces(&points, 64).collect();
            if len == 0 {
                assert!(cut.is_empty(), "nothing to cut");
                continue;
            }
            assert!(
                cut.iter().all(|p| p.len() <= 65),
                "{len}: at most 64 segments"
            );
            for pair in cut.windows(2) {
                assert_eq!(pair[0].last(), pair[1].first(), "{len}: pieces join");
            }
            let segments: usize = cut.iter().map(|p| p.len().saturating_sub(1)).sum();
            assert_eq!(segments, len - 1, "{len}: every segment once");
            assert_eq!(cut[0][0], points[0], "{len}: first point");
            assert_eq!(
                cut.last().and_then(|p| p.last()),
                points.last(),
                "{len}: last point"
            );
        }
    }
}
