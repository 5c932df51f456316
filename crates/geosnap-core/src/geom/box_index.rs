//! A spatial index of axis-aligned boxes, for the passes that look at each stroke's
//! neighbours: which boxes meet a query box.
//!
//! Such passes used to test every other stroke (a cheap bounds test, then the real one),
//! which is quadratic in the number of strokes: seconds for a drawing of ten thousand.
//! [`BoxIndex`] holds the boxes in an R-tree ([`rstar`], bulk loaded once), so a query
//! visits only the boxes near it. Its answer is exact, not approximate: every box that
//! meets the query box (boundaries included), in ascending index order, so that a pass
//! that filters it as before gives the same result as a scan over all boxes.

use glam::DVec2;
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};

/// An indexed box with its item's index.
type Entry = GeomWithData<Rectangle<[f64; 2]>, usize>;

/// A snapshot index of axis-aligned boxes `(min, max)`, one per item, by item index.
///
/// A box with a non-finite corner (or with `min > max`) cannot be placed: it is returned
/// by every query, and the caller's own test decides, as it would in a scan.
///
/// # Examples
///
/// ```
/// use geosnap_core::geom::BoxIndex;
/// use glam::DVec2;
///
/// let index = BoxIndex::new([
///     (DVec2::ZERO, DVec2::splat(1.0)),
///     (DVec2::splat(5.0), DVec2::splat(6.0)),
///     (DVec2::new(0.5, 0.0), DVec2::new(2.0, 1.0)),
/// ]);
/// assert_eq!(index.meeting(DVec2::splat(0.8), DVec2::splat(1.5)), [0, 2]);
/// assert!(index.meeting(DVec2::splat(10.0), DVec2::splat(11.0)).is_empty());
/// ```
#[derive(Clone, Debug, Default)]
pub struct BoxIndex {
    tree: RTree<Entry>,
    /// The items whose boxes could not be placed (returned by every query).
    unplaced: Vec<usize>,
}

impl BoxIndex {
    /// Indexes `boxes`, the box of item `i` being the `i`-th.
    pub fn new(boxes: impl IntoIterator<Item = (DVec2, DVec2)>) -> Self {
        let mut entries = Vec::new();
        let mut unplaced = Vec::new();
        for (i, (lo, hi)) in boxes.into_iter().enumerate() {
            if lo.is_finite() && hi.is_finite() && lo.cmple(hi).all() {
                entries.push(Entry::new(
                    Rectangle::from_corners(lo.to_array(), hi.to_array()),
                    i,
                ));
            } else {
                unplaced.push(i);
            }
        }
        Self {
            tree: RTree::bulk_load(entries),
            unplaced,
        }
    }

    /// The number of boxes indexed (placed or not).
    pub fn len(&self) -> usize {
        self.tree.size() + self.unplaced.len()
    }

    /// Whether no box is indexed.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The items whose boxes meet the box `lo`–`hi` (touching counts), ascending, with
    /// those whose boxes could not be placed. A query box with a non-finite corner meets
    /// every box.
    pub fn meeting(&self, lo: DVec2, hi: DVec2) -> Vec<usize> {
        let mut found: Vec<usize> = if lo.is_finite() && hi.is_finite() {
            let query = AABB::from_corners(lo.min(hi).to_array(), lo.max(hi).to_array());
            self.tree
                .locate_in_envelope_intersecting(query)
                .map(|e| e.data)
                .chain(self.unplaced.iter().copied())
                .collect()
        } else {
            self.tree
                .iter()
                .map(|e| e.data)
                .chain(self.unplaced.iter().copied())
                .collect()
        };
        found.sort_unstable();
        found
    }

    /// The items whose boxes come within `distance` of the box `lo`–`hi` along each axis
    /// (see [`BoxIndex::meeting`]): those meeting it grown by `distance` on every side, so
    /// every box within that distance in the Euclidean sense is among them. A negative
    /// `distance` counts as 0; a NaN or infinite one reaches every box.
    pub fn near(&self, lo: DVec2, hi: DVec2, distance: f64) -> Vec<usize> {
        let grow = DVec2::splat(if distance < 0.0 { 0.0 } else { distance });
        self.meeting(lo - grow, hi + grow)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::BoxIndex;

    /// A small deterministic generator of numbers in [0, 1).
    fn noise(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Whether two boxes meet, boundaries included (the scan's test).
    fn meet(a: (DVec2, DVec2), b: (DVec2, DVec2)) -> bool {
        !(a.1.x < b.0.x || a.1.y < b.0.y || b.1.x < a.0.x || b.1.y < a.0.y)
    }

    #[test]
    fn queries_return_exactly_what_a_scan_finds() {
        let mut seed = 19;
        let mut boxes: Vec<(DVec2, DVec2)> = (0..2000)
            .map(|_| {
                let lo = DVec2::new(noise(&mut seed), noise(&mut seed)) * 1000.0;
                let size = DVec2::new(noise(&mut seed), noise(&mut seed)) * 40.0;
                (lo, lo + size)
            })
            .collect();
        // Points, a shared edge and a huge box.
        boxes.push((DVec2::splat(500.0), DVec2::splat(500.0)));
        boxes.push((DVec2::new(100.0, 0.0), DVec2::new(200.0, 100.0)));
        boxes.push((DVec2::splat(-1e6), DVec2::splat(1e6)));
        let index = BoxIndex::new(boxes.iter().copied());
        assert_eq!(index.len(), boxes.len());
        let mut queries: Vec<(DVec2, DVec2)> = (0..300)
            .map(|_| {
                let lo = DVec2::new(noise(&mut seed), noise(&mut seed)) * 1100.0 - 50.0;
                let size = DVec2::new(noise(&mut seed), noise(&mut seed)) * 120.0;
                (lo, lo + size)
            })
            .collect();
        queries.push((DVec2::splat(500.0), DVec2::splat(500.0)));
        queries.push((DVec2::new(200.0, 50.0), DVec2::new(300.0, 60.0)));
        for (lo, hi) in queries {
            let scan: Vec<usize> = (0..boxes.len())
                .filter(|i| meet(boxes[*i], (lo, hi)))
                .collect();
            assert_eq!(index.meeting(lo, hi), scan, "query {lo} – {hi}");
            let grown: Vec<usize> = (0..boxes.len())
                .filter(|i| meet(boxes[*i], (lo - 7.5, hi + 7.5)))
                .collect();
            assert_eq!(index.near(lo, hi, 7.5), grown, "near {lo} – {hi}");
        }
        let all: Vec<usize> = (0..boxes.len()).collect();
        assert_eq!(
            index.near(DVec2::ZERO, DVec2::ONE, f64::NAN),
            all,
            "NaN reaches all"
        );
        assert_eq!(index.near(DVec2::ZERO, DVec2::ONE, f64::INFINITY), all);
        assert_eq!(
            index.near(DVec2::splat(500.0), DVec2::splat(500.0), -3.0),
            index.meeting(DVec2::splat(500.0), DVec2::splat(500.0)),
            "a negative distance counts as 0"
        );
    }

    #[test]
    fn boxes_that_cannot_be_placed_are_always_returned() {
        let index = BoxIndex::new([
            (DVec2::ZERO, DVec2::ONE),
            (DVec2::NAN, DVec2::ONE),
            (DVec2::splat(3.0), DVec2::splat(2.0)),
            (DVec2::splat(50.0), DVec2::splat(f64::INFINITY)),
        ]);
        assert_eq!(index.len(), 4);
        assert_eq!(
            index.meeting(DVec2::splat(10.0), DVec2::splat(11.0)),
            [1, 2, 3]
        );
        assert_eq!(index.meeting(DVec2::ZERO, DVec2::ONE), [0, 1, 2, 3]);
        assert_eq!(
            index.meeting(DVec2::NAN, DVec2::ONE),
            [0, 1, 2, 3],
            "a non-finite query meets everything"
        );
        // Corners given the wrong way round are sorted out.
        assert_eq!(index.meeting(DVec2::ONE, DVec2::ZERO), [0, 1, 2, 3]);
        assert!(BoxIndex::new([]).is_empty());
        assert!(BoxIndex::default()
            .meeting(DVec2::ZERO, DVec2::ONE)
            .is_empty());
    }
}
