//! The bent generalized cylinder (BGC): a tube along a planar curved spine with a radius
//! profile.
//!
//! Parameters (4K + 3, K = [`PROFILE_SAMPLES`]): spine points P₀ … P_{K−1} (3 each), radii
//! r₀ … r_{K−1} > 0, and the unit normal n of the spine's plane (3). Constraints: |n|² = 1;
//! planarity (Pᵢ − P₀)·n = 0; equal spacing |P_{i+1} − Pᵢ|² = |P₁ − P₀|²; a positive
//! spacing and positive radii.
//!
//! Projected curves: the end ellipses (circles at P₀ and P_{K−1} whose normals follow the
//! spine's end tangents; feature strokes) and two contour polylines Pᵢ ± rᵢ·νᵢ, νᵢ the
//! view-plane normal of the projected spine at Pᵢ (silhouette strokes; exact when the
//! spine lies in the view plane, close when it tilts moderately). Feature curves `bottom`
//! (at P₀) and `top` (at P_{K−1}). Regularisers: second differences of the spine points
//! and of the radii (a smooth bend, a smooth profile).

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::cylinder::MIN_SIZE_FRACTION;
use super::mesh::{orthonormal_basis, TriMesh};
use super::{
    circle_ellipse, Curve2, CurveClass, FeatureCurve, FeatureGeometry, Placement, ProjectedCurve,
    Shape, PROFILE_SAMPLES,
};
use crate::core::ad::{Real, Vec2, Vec3};
use crate::core::geom::projection::{model_direction_from_sketch, view_from_sketch};

/// A bent generalized cylinder in model space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bgc {
    /// Spine points from one end to the other (at least three).
    pub spine: Vec<DVec3>,
    /// Radii at the spine points.
    pub radii: Vec<f64>,
    /// The unit normal of the spine's plane.
    pub plane_normal: DVec3,
}

impl Bgc {
    pub(crate) fn from_placement(p: &Placement, default_size: f64) -> Self {
        let v = view_from_sketch(p.at);
        let center = DVec3::new(v.x, v.y, 0.0);
        let axis = model_direction_from_sketch(p.axis).unwrap_or(DVec3::Y);
        let length = p.length.unwrap_or(default_size).abs().max(1e-9);
        let r = p.radius.unwrap_or(default_size * 0.15).abs().max(1e-9);
        let k = PROFILE_SAMPLES;
        let spine = (0..k)
            .map(|i| center + axis * (length * (i as f64 / (k - 1) as f64 - 0.5)))
            .collect();
        Self {
            spine,
            radii: vec![r; k],
            plane_normal: DVec3::Z,
        }
    }

    /// A BGC through the given spine points (for example a medial axis found in the
    /// strokes) with a constant radius.
    pub fn through(spine: Vec<DVec3>, radius: f64) -> Self {
        let radii = vec![radius; spine.len()];
        Self {
            spine,
            radii,
            plane_normal: DVec3::Z,
        }
    }

    pub(crate) fn params(&self) -> Vec<f64> {
        let mut x: Vec<f64> = self.spine.iter().flat_map(DVec3::to_array).collect();
        x.extend_from_slice(&self.radii);
        x.extend_from_slice(&self.plane_normal.to_array());
        x
    }

    pub(crate) fn with_params(&self, x: &[f64]) -> Self {
        let k = self.spine.len();
        let spine = (0..k)
            .map(|i| DVec3::new(x[3 * i], x[3 * i + 1], x[3 * i + 2]))
            .collect();
        let n = DVec3::new(x[4 * k], x[4 * k + 1], x[4 * k + 2]);
        Self {
            spine,
            radii: x[3 * k..4 * k].to_vec(),
            plane_normal: n.normalize_or(self.plane_normal),
        }
    }

    /// The spine's length.
    pub fn spine_length(&self) -> f64 {
        self.spine.windows(2).map(|w| w[0].distance(w[1])).sum()
    }

    pub(crate) fn center(&self) -> DVec3 {
        self.spine.iter().copied().sum::<DVec3>() / self.spine.len().max(1) as f64
    }

    pub(crate) fn size(&self) -> f64 {
        let widest = self.radii.iter().fold(0.0f64, |m, r| m.max(*r));
        self.spine_length().max(2.0 * widest)
    }

    pub(crate) fn transformed(&self, offset: DVec3, factor: f64) -> Self {
        Self {
            spine: self.spine.iter().map(|p| (*p + offset) * factor).collect(),
            radii: self.radii.iter().map(|r| r * factor).collect(),
            plane_normal: self.plane_normal,
        }
    }

    pub(crate) fn shape<T: Real>(&self, x: &[T]) -> Shape<T> {
        let k = self.spine.len();
        let p: Vec<Vec3<T>> = (0..k)
            .map(|i| Vec3::new(x[3 * i], x[3 * i + 1], x[3 * i + 2]))
            .collect();
        let radii = &x[3 * k..4 * k];
        let n = Vec3::new(x[4 * k], x[4 * k + 1], x[4 * k + 2]);
        let mut left = Vec::with_capacity(k);
        let mut right = Vec::with_capacity(k);
        for i in 0..k {
            let (lo, hi) = (i.saturating_sub(1), (i + 1).min(k - 1));
            let t = p[hi].xy() - p[lo].xy();
            let len = t.norm() + 1e-12;
            let nu = Vec2::new(-t.y / len, t.x / len);
            left.push(p[i].xy() + nu * radii[i]);
            right.push(p[i].xy() - nu * radii[i]);
        }
        let tangent = |a: Vec3<T>, b: Vec3<T>| (b - a).normalize();
        let bottom_normal = tangent(p[1], p[0]);
        let top_normal = tangent(p[k - 2], p[k - 1]);
        let curve = |name: &str, class, curve| ProjectedCurve {
            name: name.to_owned(),
            class,
            visible: true,
            curve,
        };
        let min = self.size() * MIN_SIZE_FRACTION;
        let spacing = (p[1] - p[0]).norm_squared();
        let mut equalities = vec![("unit plane normal", n.norm_squared() - 1.0)];
        for i in 1..k {
            equalities.push(("planar spine", (p[i] - p[0]).dot(n)));
        }
        for i in 1..k - 1 {
            equalities.push(("even spacing", (p[i + 1] - p[i]).norm_squared() - spacing));
        }
        let mut inequalities = vec![("positive spacing", spacing - min * min)];
        inequalities.extend(radii.iter().map(|r| ("positive radius", *r - min)));
        let mut regularizers = Vec::new();
        for w in p.windows(3) {
            let bend = w[0] - w[1].scale(2.0) + w[2];
            regularizers.extend(bend.to_array());
        }
        regularizers.extend(radii.windows(3).map(|w| w[0] - w[1] * 2.0 + w[2]));
        Shape {
            curves: vec![
                curve(
                    "top",
                    CurveClass::Feature,
                    circle_ellipse(p[k - 1], top_normal, radii[k - 1]),
                ),
                curve(
                    "bottom",
                    CurveClass::Feature,
                    circle_ellipse(p[0], bottom_normal, radii[0]),
                ),
                curve("left", CurveClass::Silhouette, Curve2::Polyline(left)),
                curve("right", CurveClass::Silhouette, Curve2::Polyline(right)),
            ],
            features: vec![
                FeatureCurve {
                    name: "top",
                    geometry: FeatureGeometry::Circle {
                        center: p[k - 1],
                        normal: top_normal,
                        radius: radii[k - 1],
                    },
                },
                FeatureCurve {
                    name: "bottom",
                    geometry: FeatureGeometry::Circle {
                        center: p[0],
                        normal: bottom_normal,
                        radius: radii[0],
                    },
                },
            ],
            equalities,
            inequalities,
            regularizers,
        }
    }

    pub(crate) fn mesh(&self, segments: usize) -> TriMesh {
        let k = self.spine.len();
        // Rotation-minimising frames: carry u along the spine by projecting it.
        let tangent = |i: usize| {
            let (lo, hi) = (i.saturating_sub(1), (i + 1).min(k - 1));
            (self.spine[hi] - self.spine[lo]).normalize_or(DVec3::Y)
        };
        let (mut u, _) = orthonormal_basis(tangent(0));
        let mut rings = Vec::with_capacity(k);
        let mut normals = Vec::with_capacity(k);
        for i in 0..k {
            let t = tangent(i);
            u = (u - t * u.dot(t)).normalize_or(orthonormal_basis(t).0);
            let v = t.cross(u);
            let mut ring = Vec::with_capacity(segments);
            let mut ring_normals = Vec::with_capacity(segments);
            for j in 0..segments {
                let angle = std::f64::consts::TAU * j as f64 / segments as f64;
                let e = u * angle.cos() + v * angle.sin();
                ring.push(self.spine[i] + e * self.radii[i]);
                ring_normals.push(e);
            }
            rings.push(ring);
            normals.push(ring_normals);
        }
        TriMesh::tube(&self.spine, &rings, &normals)
    }

    /// The spine projected to the view plane.
    pub fn projected_spine(&self) -> Vec<DVec2> {
        self.spine.iter().map(|p| DVec2::new(p.x, p.y)).collect()
    }
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::Bgc;
    use crate::core::primitive::{Placement, Primitive, PrimitiveKind};

    #[test]
    fn a_straight_placement_satisfies_its_constraints() {
        let mut place = Placement::at(DVec2::new(10.0, 20.0));
        place.length = Some(70.0);
        place.radius = Some(5.0);
        let p = Primitive::from_placement(PrimitiveKind::Bgc, &place, 30.0);
        assert_eq!(p.with_params(&p.params()), p);
        let shape = p.current_shape();
        assert!(shape.equalities.iter().all(|(_, c)| c.abs() < 1e-9));
        assert!(shape.inequalities.iter().all(|(_, g)| *g > 0.0));
        let Primitive::Bgc(b) = &p else {
            panic!("a bgc")
        };
        assert!((b.spine_length() - 70.0).abs() < 1e-9);
        let v = p.mesh(256).volume();
        let exact = std::f64::consts::PI * 25.0 * 70.0;
        assert!((v - exact).abs() < 1e-2 * exact, "{v} vs {exact}");
    }

    #[test]
    fn a_quarter_torus_mesh_is_closed() {
        let spine: Vec<DVec3> = (0..8)
            .map(|i| {
                let t = std::f64::consts::FRAC_PI_2 * f64::from(i) / 7.0;
                DVec3::new(10.0 * t.cos(), 10.0 * t.sin(), 0.0)
            })
            .collect();
        let tube = Bgc::through(spine, 1.0);
        let v = tube.mesh(64).volume();
        // Pappus: π r² · (π/2 · R), up to the polygonal spine.
        let exact = std::f64::consts::PI * std::f64::consts::FRAC_PI_2 * 10.0;
        assert!((v - exact).abs() < 0.05 * exact, "{v} vs {exact}");
    }
}
