//! The truncated cone.
//!
//! Parameters (9): centre c (3), axis a (3, unit), length l > 0, bottom radius
//! r_b > 0, top radius r_t > 0. Ends, curves and feature curves as for the
//! [`Cylinder`](super::Cylinder); the contour lines are the exact contour generators of
//! the cone (tangent to both end ellipses), see
//! [`contour_points`](super::contour_points). Seen straight down its axis a cone has no
//! contour lines; the formulas then clamp to the axis-side points.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::cylinder::{revolved_shape, MIN_SIZE_FRACTION};
use super::mesh::revolution;
use super::{dropped_axis, vec3_at, vec3_expr_at, Placement, Shape, TriMesh};
use crate::ad::Real;
use crate::geom::projection::view_from_sketch;

/// A truncated cone in model space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Cone {
    /// The centre (halfway between the end centres).
    pub center: DVec3,
    /// The unit axis, from bottom to top.
    pub axis: DVec3,
    /// The length along the axis.
    pub length: f64,
    /// The radius of the bottom end.
    pub radius_bottom: f64,
    /// The radius of the top end.
    pub radius_top: f64,
}

impl Cone {
    /// Index of the centre (3 values) in the parameter vector.
    pub const CENTER: usize = 0;
    /// Index of the axis (3 values).
    pub const AXIS: usize = 3;
    /// Index of the length.
    pub const LENGTH: usize = 6;
    /// Index of the bottom radius.
    pub const RADIUS_BOTTOM: usize = 7;
    /// Index of the top radius.
    pub const RADIUS_TOP: usize = 8;
    /// The number of parameters.
    pub const LEN: usize = 9;

    pub(crate) fn from_placement(p: &Placement, default_size: f64) -> Self {
        let v = view_from_sketch(p.at);
        let (axis, length) = dropped_axis(p, default_size);
        let r = p.radius.unwrap_or(default_size * 0.3).abs();
        Self {
            center: DVec3::new(v.x, v.y, 0.0),
            axis,
            length,
            radius_bottom: p.radius_bottom.unwrap_or(r).abs().max(1e-9),
            radius_top: p.radius_top.unwrap_or(r * 0.5).abs().max(1e-9),
        }
    }

    pub(crate) fn params(&self) -> Vec<f64> {
        let (c, a) = (self.center, self.axis);
        vec![
            c.x,
            c.y,
            c.z,
            a.x,
            a.y,
            a.z,
            self.length,
            self.radius_bottom,
            self.radius_top,
        ]
    }

    pub(crate) fn with_params(&self, x: &[f64]) -> Self {
        Self {
            center: vec3_at(x, Self::CENTER),
            axis: vec3_at(x, Self::AXIS).normalize_or(self.axis),
            length: x[Self::LENGTH],
            radius_bottom: x[Self::RADIUS_BOTTOM],
            radius_top: x[Self::RADIUS_TOP],
        }
    }

    pub(crate) fn center(&self) -> DVec3 {
        self.center
    }

    pub(crate) fn size(&self) -> f64 {
        self.length
            .max(2.0 * self.radius_bottom)
            .max(2.0 * self.radius_top)
    }

    pub(crate) fn transformed(&self, offset: DVec3, factor: f64) -> Self {
        Self {
            center: (self.center + offset) * factor,
            axis: self.axis,
            length: self.length * factor,
            radius_bottom: self.radius_bottom * factor,
            radius_top: self.radius_top * factor,
        }
    }

    pub(crate) fn shape<T: Real>(&self, x: &[T]) -> Shape<T> {
        let c = vec3_expr_at(x, Self::CENTER);
        let a = vec3_expr_at(x, Self::AXIS);
        let (l, rb, rt) = (x[Self::LENGTH], x[Self::RADIUS_BOTTOM], x[Self::RADIUS_TOP]);
        revolved_shape(c, a, l, rb, rt, self.size() * MIN_SIZE_FRACTION)
    }

    pub(crate) fn mesh(&self, segments: usize) -> TriMesh {
        let bottom = self.center - self.axis * (self.length / 2.0);
        revolution(
            bottom,
            self.axis,
            &[(0.0, self.radius_bottom), (self.length, self.radius_top)],
            segments,
        )
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::Cone;
    use crate::primitive::Primitive;

    #[test]
    fn params_round_trip_and_volume() {
        let cone = Primitive::Cone(Cone {
            center: DVec3::new(1.0, 2.0, 3.0),
            axis: DVec3::Z,
            length: 3.0,
            radius_bottom: 2.0,
            radius_top: 1.0,
        });
        assert_eq!(cone.with_params(&cone.params()), cone);
        // Frustum volume πh(R² + Rr + r²)/3 = 7π.
        let v = cone.mesh(512).volume();
        assert!((v - 7.0 * std::f64::consts::PI).abs() < 1e-2, "{v}");
        assert!((cone.size() - 4.0).abs() < 1e-12);
    }
}
