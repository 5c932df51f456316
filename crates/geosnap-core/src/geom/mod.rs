//! Geometry: projection and camera conventions, fitting of lines, circles and ellipses
//! to points, meshes, and a spatial index of boxes ([`BoxIndex`]).

pub mod projection;

mod box_index;
mod fit;

use glam::DVec2;

pub use box_index::BoxIndex;
pub use fit::{
    fit_circle, fit_ellipse, fit_line, refine_ellipse, refine_ellipse_within, AngularSpan, Circle2,
    Ellipse2, Line2,
};

/// The index of the point of `points` nearest to `p` (the first of equals; 0 for none).
pub(crate) fn nearest_index(points: &[DVec2], p: DVec2) -> usize {
    (0..points.len())
        .min_by(|i, j| {
            points[*i]
                .distance_squared(p)
                .total_cmp(&points[*j].distance_squared(p))
        })
        .unwrap_or(0)
}

/// The distance from `p` to the segment `a`–`b`.
pub(crate) fn segment_distance(a: DVec2, b: DVec2, p: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t).distance(p)
}
