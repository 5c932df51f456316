//! The straight generalized cylinder (SGC): a straight axis and a radius profile.
//!
//! Parameters (7 + K, K = [`PROFILE_SAMPLES`]): centre c (3), axis a (3, unit), length
//! l > 0, radii r₀ … r_{K−1} > 0 sampled uniformly from the bottom (c − a·l/2) to the top
//! (c + a·l/2).
//!
//! Projected curves: the end ellipses (feature strokes) and the two contour polylines
//! through the contour points of every profile ring, using the local slope of the
//! profile (silhouette strokes). Feature curves `top` and `bottom`. Regularisers: the
//! second differences of the radii, so the profile stays smooth where no stroke
//! constrains it.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::cylinder::{MAX_AXIS_Z2, MIN_SIZE_FRACTION};
use super::mesh::revolution;
use super::{
    circle_ellipse, contour_points, dropped_axis, vec3_at, vec3_expr_at, Curve2, CurveClass,
    Feature, FeatureCurve, FeatureGeometry, Placement, ProjectedCurve, Shape, TriMesh,
    PROFILE_SAMPLES,
};
use crate::ad::Real;
use crate::geom::projection::view_from_sketch;

/// A straight generalized cylinder in model space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sgc {
    /// The centre.
    pub center: DVec3,
    /// The unit axis, from bottom to top.
    pub axis: DVec3,
    /// The length along the axis.
    pub length: f64,
    /// The radius profile, sampled uniformly from bottom to top (at least two samples).
    pub radii: Vec<f64>,
}

impl Sgc {
    pub(crate) fn from_placement(p: &Placement, default_size: f64) -> Self {
        let v = view_from_sketch(p.at);
        let (axis, length) = dropped_axis(p, default_size);
        let r = p.radius.unwrap_or(default_size * 0.3).abs().max(1e-9);
        Self {
            center: DVec3::new(v.x, v.y, 0.0),
            axis,
            length,
            radii: vec![r; PROFILE_SAMPLES],
        }
    }

    /// Index of the centre (3 values) in the parameter vector.
    pub const CENTER: usize = 0;
    /// Index of the axis (3 values).
    pub const AXIS: usize = 3;
    /// Index of the length.
    pub const LENGTH: usize = 6;
    /// Index of the first radius; the others follow, from the bottom to the top.
    pub const RADII: usize = 7;

    /// The number of parameters: [`Sgc::RADII`] plus one per radius.
    pub fn param_count(&self) -> usize {
        Self::RADII + self.radii.len()
    }

    pub(crate) fn params(&self) -> Vec<f64> {
        let (c, a) = (self.center, self.axis);
        let mut x = vec![c.x, c.y, c.z, a.x, a.y, a.z, self.length];
        x.extend_from_slice(&self.radii);
        x
    }

    pub(crate) fn with_params(&self, x: &[f64]) -> Self {
        Self {
            center: vec3_at(x, Self::CENTER),
            axis: vec3_at(x, Self::AXIS).normalize_or(self.axis),
            length: x[Self::LENGTH],
            radii: x[Self::RADII..self.param_count()].to_vec(),
        }
    }

    pub(crate) fn center(&self) -> DVec3 {
        self.center
    }

    pub(crate) fn size(&self) -> f64 {
        let widest = self.radii.iter().fold(0.0f64, |m, r| m.max(*r));
        self.length.max(2.0 * widest)
    }

    pub(crate) fn transformed(&self, offset: DVec3, factor: f64) -> Self {
        Self {
            center: (self.center + offset) * factor,
            axis: self.axis,
            length: self.length * factor,
            radii: self.radii.iter().map(|r| r * factor).collect(),
        }
    }

    pub(crate) fn shape<T: Real>(&self, x: &[T]) -> Shape<T> {
        let c = vec3_expr_at(x, Self::CENTER);
        let a = vec3_expr_at(x, Self::AXIS);
        let l = x[Self::LENGTH];
        let radii = &x[Self::RADII..self.param_count()];
        let k = radii.len();
        let step = l / (k - 1) as f64;
        let ring = |i: usize| c + a * (l * (i as f64 / (k - 1) as f64 - 0.5));
        let mut left = Vec::with_capacity(k);
        let mut right = Vec::with_capacity(k);
        for i in 0..k {
            let (lo, hi) = (i.saturating_sub(1), (i + 1).min(k - 1));
            let slope = (radii[hi] - radii[lo]) / (step * (hi - lo) as f64);
            let [r, l] = contour_points(ring(i), a, radii[i], slope);
            left.push(l);
            right.push(r);
        }
        let (bottom, top) = (ring(0), ring(k - 1));
        let curve = ProjectedCurve::shown;
        let min = self.size() * MIN_SIZE_FRACTION;
        let mut inequalities = vec![
            ("positive length", l - min),
            ("axis not along the view", -a.z.square() + MAX_AXIS_Z2),
        ];
        inequalities.extend(radii.iter().map(|r| ("positive radius", *r - min)));
        Shape {
            curves: vec![
                curve(
                    "top",
                    CurveClass::Feature,
                    circle_ellipse(top, a, radii[k - 1]),
                ),
                curve(
                    "bottom",
                    CurveClass::Feature,
                    circle_ellipse(bottom, a, radii[0]),
                ),
                curve("left", CurveClass::Silhouette, Curve2::Polyline(left)),
                curve("right", CurveClass::Silhouette, Curve2::Polyline(right)),
            ],
            features: vec![
                FeatureCurve {
                    feature: Feature::Top,
                    geometry: FeatureGeometry::Circle {
                        center: top,
                        normal: a,
                        radius: radii[k - 1],
                    },
                },
                FeatureCurve {
                    feature: Feature::Bottom,
                    geometry: FeatureGeometry::Circle {
                        center: bottom,
                        normal: -a,
                        radius: radii[0],
                    },
                },
            ],
            equalities: vec![("unit axis", a.norm_squared() - 1.0)],
            inequalities,
            regularizers: radii.windows(3).map(|w| w[0] - w[1] * 2.0 + w[2]).collect(),
            profile: Vec::new(),
            untilted: Vec::new(),
        }
    }

    pub(crate) fn mesh(&self, segments: usize) -> TriMesh {
        let bottom = self.center - self.axis * (self.length / 2.0);
        let k = self.radii.len();
        let profile: Vec<(f64, f64)> = self
            .radii
            .iter()
            .enumerate()
            .map(|(i, r)| (self.length * i as f64 / (k - 1) as f64, *r))
            .collect();
        revolution(bottom, self.axis, &profile, segments)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::Sgc;
    use crate::primitive::{Curve2, Primitive};

    #[test]
    fn a_constant_profile_is_a_cylinder() {
        let p = Primitive::Sgc(Sgc {
            center: DVec3::ZERO,
            axis: DVec3::Y,
            length: 4.0,
            radii: vec![1.0; 8],
        });
        assert_eq!(p.with_params(&p.params()), p);
        let shape = p.current_shape();
        let Curve2::Polyline(left) = &shape.curves[2].curve else {
            panic!("a polyline")
        };
        assert_eq!(left.len(), 8);
        assert!(left.iter().all(|q| (q.x.abs() - 1.0).abs() < 1e-9));
        assert!(shape.regularizers.iter().all(|r| r.abs() < 1e-12));
        let v = p.mesh(256).volume();
        assert!((v - 4.0 * std::f64::consts::PI).abs() < 1e-2, "{v}");
    }
}
