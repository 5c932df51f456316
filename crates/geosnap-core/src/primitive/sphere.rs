//! The sphere.
//!
//! Parameters (4): centre c (3) and radius r > 0. Its projected outline is the circle of
//! radius r about (cₓ, c_y) (a silhouette stroke). Its feature curve `outline` is the
//! great circle facing the viewer (normal +z), which relations such as "on sphere"
//! use. The depth c_z does not change the projection; relations decide it.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::cylinder::MIN_SIZE_FRACTION;
use super::mesh::TriMesh;
use super::{
    vec3_at, vec3_expr_at, Curve2, CurveClass, Feature, FeatureCurve, FeatureGeometry, Placement,
    ProjectedCurve, Shape,
};
use crate::ad::{Real, Vec2, Vec3};
use crate::geom::projection::view_from_sketch;

/// A sphere in model space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sphere {
    /// The centre.
    pub center: DVec3,
    /// The radius.
    pub radius: f64,
}

impl Sphere {
    /// Index of the centre (3 values) in the parameter vector.
    pub const CENTER: usize = 0;
    /// Index of the radius.
    pub const RADIUS: usize = 3;
    /// The number of parameters.
    pub const LEN: usize = 4;

    pub(crate) fn from_placement(p: &Placement, default_size: f64) -> Self {
        let v = view_from_sketch(p.at);
        Self {
            center: DVec3::new(v.x, v.y, 0.0),
            radius: p.radius.unwrap_or(default_size * 0.5).abs().max(1e-9),
        }
    }

    pub(crate) fn params(&self) -> Vec<f64> {
        let c = self.center;
        vec![c.x, c.y, c.z, self.radius]
    }

    #[expect(clippy::unused_self, reason = "every kind has the same signature")]
    pub(crate) fn with_params(&self, x: &[f64]) -> Self {
        Self {
            center: vec3_at(x, Self::CENTER),
            radius: x[Self::RADIUS],
        }
    }

    pub(crate) fn center(&self) -> DVec3 {
        self.center
    }

    pub(crate) fn size(&self) -> f64 {
        2.0 * self.radius
    }

    pub(crate) fn transformed(&self, offset: DVec3, factor: f64) -> Self {
        Self {
            center: (self.center + offset) * factor,
            radius: self.radius * factor,
        }
    }

    pub(crate) fn shape<T: Real>(&self, x: &[T]) -> Shape<T> {
        let c = vec3_expr_at(x, Self::CENTER);
        let r = x[Self::RADIUS];
        let (zero, one) = (r.lit(0.0), r.lit(1.0));
        Shape {
            curves: vec![ProjectedCurve {
                name: "outline".to_owned(),
                class: CurveClass::Silhouette,
                visible: true,
                curve: Curve2::Ellipse {
                    center: c.xy(),
                    a: Vec2::new(r, zero),
                    b: Vec2::new(zero, r),
                },
            }],
            features: vec![FeatureCurve {
                feature: Feature::Outline,
                geometry: FeatureGeometry::Circle {
                    center: c,
                    normal: Vec3::new(zero, zero, one),
                    radius: r,
                },
            }],
            equalities: Vec::new(),
            inequalities: vec![("positive radius", r - self.size() * MIN_SIZE_FRACTION)],
            regularizers: Vec::new(),
            profile: Vec::new(),
            untilted: Vec::new(),
        }
    }

    pub(crate) fn mesh(&self, segments: usize) -> TriMesh {
        let rings = (segments / 2).max(2);
        let mut mesh = TriMesh::default();
        // Latitude rings from the south pole to the north pole (poles duplicated per
        // segment so every vertex has its own smooth normal).
        for i in 0..=rings {
            let phi = std::f64::consts::PI * i as f64 / rings as f64 - std::f64::consts::FRAC_PI_2;
            for j in 0..=segments {
                let theta = std::f64::consts::TAU * j as f64 / segments as f64;
                let n = DVec3::new(phi.cos() * theta.cos(), phi.sin(), -phi.cos() * theta.sin());
                mesh.positions.push(self.center + n * self.radius);
                mesh.normals.push(n);
            }
        }
        let row = (segments + 1) as u32;
        for i in 0..rings as u32 {
            for j in 0..segments as u32 {
                let a = i * row + j;
                let (b, c, d) = (a + 1, a + row, a + row + 1);
                if i > 0 {
                    mesh.triangles.push([a, b, d]);
                }
                if i + 1 < rings as u32 {
                    mesh.triangles.push([a, d, c]);
                }
            }
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::Sphere;
    use crate::primitive::Primitive;

    #[test]
    fn mesh_volume_and_round_trip() {
        let s = Primitive::Sphere(Sphere {
            center: DVec3::new(1.0, 0.0, -2.0),
            radius: 2.0,
        });
        assert_eq!(s.with_params(&s.params()), s);
        let v = s.mesh(256).volume();
        let exact = 4.0 / 3.0 * std::f64::consts::PI * 8.0;
        assert!((v - exact).abs() < 1e-2 * exact, "{v} vs {exact}");
    }
}
