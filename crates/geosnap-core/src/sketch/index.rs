//! A spatial index over the segments of a sketch's strokes.
//!
//! The curve assigner asks, every drag frame and for each of hundreds of samples along
//! a primitive's projected curves, which strokes pass near a point and how near.
//! [`StrokeIndex`] answers with an R-tree ([`rstar`]) of the strokes' segments (bulk
//! loaded once per sketch), so a query visits only the few segments near the point
//! instead of every stroke. Queries do not allocate: [`StrokeIndex::within`] iterates
//! lazily over a small inline stack, and [`StrokeIndex::nearest_per_stroke_into`] fills
//! a caller's buffer that can be reused from sample to sample.
//!
//! Segment `i` of a stroke joins its points `i` and `i + 1`; a closed stroke has one more
//! segment, `n − 1`, from its last point back to its first. A stroke with a single point
//! is indexed as one zero-length segment. Segments with a non-finite end are left out.

use glam::DVec2;
use rstar::{PointDistance, RTree, RTreeObject, AABB};

use super::{Sketch, StrokeId};

/// One indexed segment, with what the distance computation needs precomputed.
#[derive(Clone, Debug)]
struct Segment {
    start: DVec2,
    /// `end − start`.
    delta: DVec2,
    /// `1 / |delta|²`, or 0 for a zero-length segment.
    inv_length_squared: f64,
    stroke: StrokeId,
    index: u32,
}

impl Segment {
    fn new(start: DVec2, end: DVec2, stroke: StrokeId, index: u32) -> Self {
        let delta = end - start;
        let length_squared = delta.length_squared();
        Self {
            start,
            delta,
            inv_length_squared: if length_squared > 0.0 {
                1.0 / length_squared
            } else {
                0.0
            },
            stroke,
            index,
        }
    }

    /// The point of the segment closest to `p`.
    fn closest_point(&self, p: DVec2) -> DVec2 {
        let t = ((p - self.start).dot(self.delta) * self.inv_length_squared).clamp(0.0, 1.0);
        self.start + t * self.delta
    }
}

impl RTreeObject for Segment {
    type Envelope = AABB<[f64; 2]>;

    fn envelope(&self) -> Self::Envelope {
        let end = self.start + self.delta;
        AABB::from_corners(self.start.to_array(), end.to_array())
    }
}

impl PointDistance for Segment {
    fn distance_2(&self, point: &[f64; 2]) -> f64 {
        let p = DVec2::from_array(*point);
        self.closest_point(p).distance_squared(p)
    }
}

/// A spatial index over the segments of all strokes of a [`Sketch`].
///
/// It is a snapshot: rebuild it when strokes change.
///
/// # Examples
///
/// ```
/// use geosnap_core::sketch::{Sketch, Stroke, StrokeId, StrokeIndex};
/// use glam::DVec2;
///
/// let line = |id, y| Stroke {
///     id: StrokeId(id),
///     points: vec![DVec2::new(0.0, y), DVec2::new(10.0, y)],
///     closed: false,
///     class_override: None,
/// };
/// let sketch = Sketch { strokes: vec![line(1, 0.0), line(2, 5.0)], view_box: None };
/// let index = StrokeIndex::new(&sketch);
/// let (id, point, distance) = index.nearest(DVec2::new(3.0, 1.0)).unwrap();
/// assert_eq!((id, point, distance), (StrokeId(1), DVec2::new(3.0, 0.0), 1.0));
/// assert_eq!(index.within(DVec2::new(3.0, 1.0), 2.0).count(), 1);
/// ```
#[derive(Clone, Debug)]
pub struct StrokeIndex {
    tree: RTree<Segment>,
}

impl StrokeIndex {
    /// Indexes every segment of every stroke of `sketch`.
    pub fn new(sketch: &Sketch) -> Self {
        let mut segments = Vec::new();
        for stroke in &sketch.strokes {
            let points = &stroke.points;
            if let [single] = points.as_slice() {
                if single.is_finite() {
                    segments.push(Segment::new(*single, *single, stroke.id, 0));
                }
                continue;
            }
            let closing = match (stroke.closed, points.first(), points.last()) {
                (true, Some(&first), Some(&last)) if points.len() > 2 => Some((last, first)),
                _ => None,
            };
            let pairs = points.windows(2).map(|w| (w[0], w[1])).chain(closing);
            for (i, (a, b)) in pairs.enumerate() {
                if a.is_finite() && b.is_finite() {
                    segments.push(Segment::new(a, b, stroke.id, i as u32));
                }
            }
        }
        Self {
            tree: RTree::bulk_load(segments),
        }
    }

    /// The number of indexed segments.
    pub fn len(&self) -> usize {
        self.tree.size()
    }

    /// Whether no segment is indexed.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The stroke passing nearest to `p`, as `(stroke, closest point, distance)`; `None`
    /// when the index is empty or `p` is not finite. Ties go to any of the nearest
    /// segments.
    pub fn nearest(&self, p: DVec2) -> Option<(StrokeId, DVec2, f64)> {
        if !p.is_finite() {
            return None;
        }
        let segment = self.tree.nearest_neighbor(p.to_array())?;
        let closest = segment.closest_point(p);
        Some((segment.stroke, closest, closest.distance(p)))
    }

    /// Every segment within distance `radius` of `p` (inclusive), as
    /// `(stroke, segment index, distance)`, in no particular order. Empty when `p` or
    /// `radius` is not finite or `radius < 0`. Does not allocate unless the R-tree
    /// search stack outgrows its inline capacity.
    pub fn within(
        &self,
        p: DVec2,
        radius: f64,
    ) -> impl Iterator<Item = (StrokeId, usize, f64)> + '_ {
        let valid = p.is_finite() && radius.is_finite() && radius >= 0.0;
        let query = if valid { p } else { DVec2::ZERO };
        // An invalid query still builds the (lazy) iterator, with a radius nothing meets.
        let radius_squared = if valid { radius * radius } else { -1.0 };
        self.tree
            .locate_within_distance(query.to_array(), radius_squared)
            .filter(move |_| valid)
            .map(move |segment| {
                let distance = segment.closest_point(query).distance(query);
                (segment.stroke, segment.index as usize, distance)
            })
    }

    /// For each stroke passing within `radius` of `p`, its distance from `p` (the
    /// smallest over its segments), sorted by stroke id.
    pub fn nearest_per_stroke(&self, p: DVec2, radius: f64) -> Vec<(StrokeId, f64)> {
        let mut out = Vec::new();
        self.nearest_per_stroke_into(p, radius, &mut out);
        out
    }

    /// Like [`StrokeIndex::nearest_per_stroke`], writing into `out` (cleared first) so a
    /// caller querying many points can reuse one buffer and allocate nothing.
    pub fn nearest_per_stroke_into(&self, p: DVec2, radius: f64, out: &mut Vec<(StrokeId, f64)>) {
        out.clear();
        for (stroke, _, distance) in self.within(p, radius) {
            // Few strokes pass near one point, so a linear scan beats a map.
            match out.iter_mut().find(|(id, _)| *id == stroke) {
                Some((_, best)) => *best = best.min(distance),
                None => out.push((stroke, distance)),
            }
        }
        out.sort_unstable_by_key(|&(id, _)| id);
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;
    use proptest::prelude::*;

    use super::StrokeIndex;
    use crate::sketch::{Sketch, Stroke, StrokeId};

    /// Every segment of the sketch with its stroke id and index, the reference for the
    /// index.
    fn segments(sketch: &Sketch) -> Vec<(StrokeId, usize, DVec2, DVec2)> {
        let mut out = Vec::new();
        for s in &sketch.strokes {
            let n = s.points.len();
            if n == 1 {
                out.push((s.id, 0, s.points[0], s.points[0]));
            }
            for i in 0..n.saturating_sub(1) {
                out.push((s.id, i, s.points[i], s.points[i + 1]));
            }
            if s.closed && n > 2 {
                out.push((s.id, n - 1, s.points[n - 1], s.points[0]));
            }
        }
        out
    }

    fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
        let d = b - a;
        let t = if d.length_squared() > 0.0 {
            ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        p.distance(a + t * d)
    }

    fn sketch_strategy() -> impl Strategy<Value = Sketch> {
        let point = (-100.0..100.0_f64, -100.0..100.0_f64).prop_map(|(x, y)| DVec2::new(x, y));
        let stroke = (prop::collection::vec(point, 1..12), any::<bool>());
        prop::collection::vec(stroke, 0..25).prop_map(|strokes| Sketch {
            strokes: strokes
                .into_iter()
                .enumerate()
                .map(|(i, (points, closed))| Stroke {
                    id: StrokeId(100 - i as u32),
                    points,
                    closed,
                    class_override: None,
                })
                .collect(),
            view_box: None,
        })
    }

    proptest! {
        #[test]
        fn queries_match_brute_force(
            sketch in sketch_strategy(),
            queries in prop::collection::vec((-120.0..120.0_f64, -120.0..120.0_f64, 0.0..60.0_f64), 1..10),
        ) {
            let index = StrokeIndex::new(&sketch);
            let reference = segments(&sketch);
            prop_assert_eq!(index.len(), reference.len());
            let mut buffer = Vec::new();
            for (x, y, radius) in queries {
                let p = DVec2::new(x, y);
                // nearest
                let best = reference.iter().map(|&(_, _, a, b)| segment_distance(p, a, b)).fold(f64::INFINITY, f64::min);
                match index.nearest(p) {
                    None => prop_assert!(reference.is_empty()),
                    Some((id, point, distance)) => {
                        prop_assert!((distance - best).abs() < 1e-9);
                        prop_assert!((point.distance(p) - distance).abs() < 1e-9);
                        prop_assert!(sketch.stroke(id).is_some());
                    }
                }
                // within: the same set of (stroke, segment) as brute force; boundary cases
                // within 1e-9 of the radius may go either way.
                let mut got: Vec<(StrokeId, usize, f64)> = index.within(p, radius).collect();
                got.sort_by_key(|&(id, i, _)| (id, i));
                let mut want: Vec<(StrokeId, usize, f64)> = reference
                    .iter()
                    .map(|&(id, i, a, b)| (id, i, segment_distance(p, a, b)))
                    .filter(|&(_, _, d)| d <= radius)
                    .collect();
                want.sort_by_key(|&(id, i, _)| (id, i));
                let near_boundary = reference.iter().any(|&(_, _, a, b)| (segment_distance(p, a, b) - radius).abs() < 1e-9);
                if !near_boundary {
                    prop_assert_eq!(got.len(), want.len());
                    for (g, w) in got.iter().zip(&want) {
                        prop_assert_eq!((g.0, g.1), (w.0, w.1));
                        prop_assert!((g.2 - w.2).abs() < 1e-9);
                    }
                    // nearest per stroke
                    index.nearest_per_stroke_into(p, radius, &mut buffer);
                    let mut per_stroke: Vec<(StrokeId, f64)> = Vec::new();
                    for &(id, _, d) in &want {
                        match per_stroke.iter_mut().find(|(s, _)| *s == id) {
                            Some((_, best)) => *best = best.min(d),
                            None => per_stroke.push((id, d)),
                        }
                    }
                    per_stroke.sort_by_key(|&(id, _)| id);
                    prop_assert_eq!(buffer.len(), per_stroke.len());
                    for (g, w) in buffer.iter().zip(&per_stroke) {
                        prop_assert_eq!(g.0, w.0);
                        prop_assert!((g.1 - w.1).abs() < 1e-9);
                    }
                    prop_assert_eq!(&index.nearest_per_stroke(p, radius), &buffer);
                }
            }
        }
    }

    #[test]
    fn closed_strokes_single_points_and_bad_queries() {
        let sketch = Sketch {
            strokes: vec![
                Stroke {
                    id: StrokeId(4),
                    points: vec![DVec2::ZERO, DVec2::new(10.0, 0.0), DVec2::new(10.0, 10.0)],
                    closed: true,
                    class_override: None,
                },
                Stroke {
                    id: StrokeId(9),
                    points: vec![DVec2::new(50.0, 50.0)],
                    closed: false,
                    class_override: None,
                },
                Stroke {
                    id: StrokeId(11),
                    points: vec![DVec2::new(0.0, 20.0), DVec2::NAN, DVec2::new(5.0, 20.0)],
                    closed: false,
                    class_override: None,
                },
            ],
            view_box: None,
        };
        let index = StrokeIndex::new(&sketch);
        assert_eq!(
            index.len(),
            4,
            "3 segments of the triangle and the single point"
        );
        // The closing segment (index 2) from (10, 10) back to (0, 0).
        let hits: Vec<_> = index.within(DVec2::new(3.0, 5.0), 1.5).collect();
        assert_eq!(hits.len(), 1);
        assert_eq!((hits[0].0, hits[0].1), (StrokeId(4), 2));
        assert!((hits[0].2 - 2.0 / 2f64.sqrt()).abs() < 1e-12);
        let (id, point, d) = index.nearest(DVec2::new(52.0, 50.0)).unwrap();
        assert_eq!((id, point), (StrokeId(9), DVec2::new(50.0, 50.0)));
        assert!((d - 2.0).abs() < 1e-12);
        assert!(index.nearest(DVec2::NAN).is_none());
        assert_eq!(index.within(DVec2::ZERO, -1.0).count(), 0);
        assert_eq!(index.within(DVec2::ZERO, f64::NAN).count(), 0);
        assert_eq!(index.within(DVec2::new(f64::INFINITY, 0.0), 5.0).count(), 0);
        assert_eq!(
            index.nearest_per_stroke(DVec2::new(10.0, 0.0), 0.0),
            vec![(StrokeId(4), 0.0)]
        );
        let empty = StrokeIndex::new(&Sketch::default());
        assert!(empty.is_empty());
        assert!(empty.nearest(DVec2::ZERO).is_none());
        assert_eq!(empty.within(DVec2::ZERO, 10.0).count(), 0);
    }
}
