//! Where a box read off the drawing stands in the image: where its own edges lie on
//! drawn lines.
//!
//! [`super::box_poses`] reads a box's orientation and sizes off the straight strokes near
//! a drop, and its image centre from the middle of their bounds. Next to parts drawn the
//! same way (a plug's blades, a row of studs, a table's legs) those bounds take in the
//! neighbours, and the middle falls between two parts, where no start reads one part
//! alone. Here the box is also set, unturned and unscaled, where its projected edges lie
//! on the strokes: a box edge and a stroke parallel to it fix how far across
//! that direction the box stands, and two such pairs of different directions fix its
//! image centre. Of the centres so found, the one whose edges the strokes cover most
//! wins; among those covered nearly as well, the one nearest the drop (a row of equal
//! parts covers each part's place equally well, and the drop says which was meant). It
//! is one more start where no centre tried already is covered nearly as well.

use glam::DVec2;

use super::super::context::SnapStroke;
use crate::primitive::{Cuboid, Primitive};

/// A stroke within this angle (radians) of an edge's direction may draw it: twice the
/// tolerance within which strokes share an edge direction, as a shaky hand's do.
const PARALLEL: f64 = 0.28;

/// Two edges whose directions differ by more than this angle (radians) fix a centre
/// between them; closer, the two offsets barely tell it.
const CROSSING: f64 = 0.35;

/// A stroke lies on an edge when its mean point is within this fraction of the gap to
/// the edge's nearest parallel edge across it …
const GAP_SHARE: f64 = 0.4;

/// … and within this fraction of the box's image diagonal.
const DIAGONAL_SHARE: f64 = 0.04;

/// Centres covered at least this fraction as well as the best are as good: the nearest
/// to the drop among them is kept.
const AS_GOOD: f64 = 0.9;

/// A visible edge of the box, relative to its image centre.
struct BoxEdge {
    mid: DVec2,
    dir: DVec2,
    half: f64,
    /// How far across it a stroke's mean point may lie.
    reach: f64,
}

/// A straight stroke as a piece of line: its unit direction, mean point and points.
struct Drawn<'a> {
    dir: DVec2,
    mean: DVec2,
    points: &'a [DVec2],
}

/// The visible edges of `read` in the image, relative to its image centre.
fn box_edges(read: &Cuboid) -> Vec<BoxEdge> {
    let centre = read.center.truncate();
    let segments: Vec<(DVec2, DVec2)> = Primitive::Cuboid(read.clone())
        .current_shape()
        .curves
        .iter()
        .filter(|c| c.visible)
        .filter_map(|c| {
            let p = c.curve.points(1);
            (p.len() == 2).then(|| (p[0] - centre, p[1] - centre))
        })
        .collect();
    let (lo, hi) = segments.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), (a, b)| (lo.min(*a).min(*b), hi.max(*a).max(*b)),
    );
    let diagonal = (hi - lo).length();
    let edges: Vec<(DVec2, DVec2, f64)> = segments
        .iter()
        .filter_map(|(a, b)| {
            let d = *b - *a;
            let length = d.length();
            (length > 1e-9 * diagonal.max(1e-300)).then(|| ((*a + *b) / 2.0, d / length, length))
        })
        .collect();
    edges
        .iter()
        .map(|&(mid, dir, length)| {
            let gap = edges
                .iter()
                .filter(|(_, d, _)| d.perp_dot(dir).abs() <= PARALLEL.sin())
                .map(|(m, _, _)| (*m - mid).dot(dir.perp()).abs())
                .filter(|g| *g > 1e-6 * diagonal)
                .fold(f64::INFINITY, f64::min);
            BoxEdge {
                mid,
                dir,
                half: length / 2.0,
                reach: (GAP_SHARE * gap).min(DIAGONAL_SHARE * diagonal),
            }
        })
        .collect()
}

/// How much of `edges`' total length the strokes `drawn` cover with the box's image
/// centre at `at`: for each edge, the union of the parallel strokes lying on it, clipped
/// to its ends.
fn coverage(edges: &[BoxEdge], parallel: &[Vec<usize>], drawn: &[Drawn<'_>], at: DVec2) -> f64 {
    let mut covered = 0.0;
    let mut spans: Vec<(f64, f64)> = Vec::new();
    for (edge, strokes) in edges.iter().zip(parallel) {
        let mid = at + edge.mid;
        let normal = edge.dir.perp();
        spans.clear();
        for s in strokes.iter().map(|&i| &drawn[i]) {
            if (s.mean - mid).dot(normal).abs() > edge.reach {
                continue;
            }
            let (lo, hi) =
                s.points
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                        let t = (*p - mid).dot(edge.dir);
                        (lo.min(t), hi.max(t))
                    });
            let (lo, hi) = (lo.max(-edge.half), hi.min(edge.half));
            if hi > lo {
                spans.push((lo, hi));
            }
        }
        spans.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut end = f64::NEG_INFINITY;
        for &(lo, hi) in &spans {
            covered += (hi - lo.max(end)).max(0.0);
            end = end.max(hi);
        }
    }
    covered
}

/// The image centre at which `read` (turned and sized as read) has its visible edges
/// best covered by the straight strokes `strokes`, the nearest to `dropped` among those
/// covered nearly as well (see the module's documentation). `None` when no stroke lies
/// on two edges of different directions at once, or when one of the centres `tried`
/// already has the box covered nearly as well (an isolated box's bounds' middle does:
/// a new start there would only give the fit another chance to go astray).
pub(super) fn aligned_centre(
    strokes: &[&SnapStroke],
    read: &Cuboid,
    dropped: DVec2,
    tried: &[DVec2],
) -> Option<DVec2> {
    let edges = box_edges(read);
    let drawn: Vec<Drawn<'_>> = strokes
        .iter()
        .filter(|s| !s.points.is_empty())
        .map(|s| Drawn {
            dir: s.direction,
            mean: s.points.iter().copied().sum::<DVec2>() / s.points.len() as f64,
            points: &s.points,
        })
        .collect();
    let parallel: Vec<Vec<usize>> = edges
        .iter()
        .map(|e| {
            (0..drawn.len())
                .filter(|&i| drawn[i].dir.perp_dot(e.dir).abs() <= PARALLEL.sin())
                .collect()
        })
        .collect();
    // Each (edge, stroke) pair fixes the centre's offset across the edge; two pairs of
    // crossing edges fix the centre.
    let pairs: Vec<(usize, usize)> = parallel
        .iter()
        .enumerate()
        .flat_map(|(e, strokes)| strokes.iter().map(move |&s| (e, s)))
        .collect();
    let offset = |(e, s): (usize, usize)| {
        let n = edges[e].dir.perp();
        (n, (drawn[s].mean - edges[e].mid).dot(n))
    };
    let mut centres = Vec::new();
    for (k, &first) in pairs.iter().enumerate() {
        for &second in &pairs[k + 1..] {
            let (d1, d2) = (edges[first.0].dir, edges[second.0].dir);
            if d1.perp_dot(d2).abs() < CROSSING.sin() {
                continue;
            }
            let ((n1, b1), (n2, b2)) = (offset(first), offset(second));
            let det = n1.perp_dot(n2);
            // n1·t = b1 and n2·t = b2.
            let t = DVec2::new(b1 * n2.y - b2 * n1.y, n1.x * b2 - n2.x * b1) / det;
            if t.is_finite() {
                centres.push(t);
            }
        }
    }
    let scored: Vec<(DVec2, f64)> = centres
        .into_iter()
        .map(|t| (t, coverage(&edges, &parallel, &drawn, t)))
        .collect();
    let best = scored.iter().map(|(_, c)| *c).fold(0.0, f64::max);
    // A centre tried already whose edges the strokes cover nearly as well needs no new
    // start.
    let tried_as_well = tried
        .iter()
        .any(|t| coverage(&edges, &parallel, &drawn, *t) >= AS_GOOD * best);
    if tried_as_well {
        return None;
    }
    scored
        .into_iter()
        .filter(|(_, c)| best > 0.0 && *c >= AS_GOOD * best)
        .map(|(t, _)| t)
        .min_by(|a, b| a.distance(dropped).total_cmp(&b.distance(dropped)))
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use super::*;
    use crate::sketch::{StrokeClass, StrokeId};
    use crate::snap::context::prepare;

    fn blade(x: f64) -> Cuboid {
        Cuboid {
            center: DVec3::new(x, 0.0, 0.0),
            rotation: DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.4),
            size: DVec3::new(12.0, 100.0, 6.0),
        }
    }

    /// The visible edges of `parts` drawn as strokes.
    fn drawn(parts: &[Cuboid]) -> Vec<SnapStroke> {
        let strokes: Vec<Vec<DVec2>> = parts
            .iter()
            .flat_map(|p| {
                Primitive::Cuboid(p.clone())
                    .current_shape()
                    .curves
                    .into_iter()
                    .filter(|c| c.visible)
                    .map(|c| {
                        let p = c.curve.points(1);
                        (0..=20)
                            .map(|k| p[0].lerp(p[1], f64::from(k) / 20.0))
                            .collect()
                    })
            })
            .collect();
        strokes
            .into_iter()
            .zip(0..)
            .filter_map(|(points, i)| prepare(StrokeId(i), points, StrokeClass::Silhouette))
            .collect()
    }

    #[test]
    fn a_box_between_two_drawn_neighbours_stands_on_the_one_nearest_the_drop() {
        let parts = [blade(0.0), blade(30.0), blade(60.0)];
        let drawn = drawn(&parts);
        let strokes: Vec<&SnapStroke> = drawn.iter().collect();
        // Read between the first two blades, dropped nearer the second. A start only has
        // to stand on the right blade (its fit does the rest): within a sixth of the pitch.
        let read = Cuboid {
            center: DVec3::new(15.0, 2.0, 0.0),
            ..blade(0.0)
        };
        let centre = aligned_centre(&strokes, &read, DVec2::new(24.0, -3.0), &[]).unwrap();
        assert!(centre.distance(DVec2::new(30.0, 0.0)) < 5.0, "{centre}");
        let centre = aligned_centre(&strokes, &read, DVec2::new(8.0, 5.0), &[]).unwrap();
        assert!(centre.distance(DVec2::ZERO) < 5.0, "{centre}");
    }

    #[test]
    fn a_box_already_standing_on_its_edges_gets_no_new_centre() {
        let parts = [blade(0.0), blade(30.0)];
        let drawn = drawn(&parts);
        let strokes: Vec<&SnapStroke> = drawn.iter().collect();
        let read = blade(30.0);
        let at = DVec2::new(30.0, 0.0);
        assert!(aligned_centre(&strokes, &read, at, &[at]).is_none());
        assert!(aligned_centre(&strokes, &read, at, &[DVec2::new(15.0, 0.0)]).is_some());
    }

    #[test]
    fn nothing_drawn_gives_no_centre() {
        let read = blade(0.0);
        assert!(aligned_centre(&[], &read, DVec2::ZERO, &[]).is_none());
    }
}
