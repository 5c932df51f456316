//! The cylinder.
//!
//! Parameters (8): centre c (3), axis a (3, unit by the constraint |a|² = 1), length
//! l > 0, radius r > 0. The bottom end is c − a·l/2, the top end c + a·l/2.
//!
//! Projected curves: the two end ellipses (feature strokes) and the two contour lines
//! joining the contour points of the ends (silhouette strokes). Feature curves: the
//! `top` and `bottom` circles, with outward normals ±a.
//!
//! Degenerate cases: an axis pointing at the viewer shows no contour lines (the ends
//! project to one circle); the projection formulas stay finite (see
//! [`circle_basis`](super::circle_basis)).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::mesh::revolution;
use super::{
    circle_ellipse, contour_points, dropped_axis, vec3_at, vec3_expr_at, Curve2, CurveClass,
    Feature, FeatureCurve, FeatureGeometry, Placement, ProjectedCurve, Shape, TriMesh,
};
use crate::ad::{Real, Vec3};
use crate::geom::projection::view_from_sketch;

/// Smallest size as a fraction of the primitive's size when it was made.
pub(crate) const MIN_SIZE_FRACTION: f64 = 1e-3;

/// The largest a_z² of a solid of revolution's axis (|a_z| ≤ 0.98, within 11.5° of the
/// view direction). Looking straight down an axis, a drawing shows the length of nothing:
/// without this bound a fit can run away towards the view with an ever longer body whose
/// projection does not change.
pub(crate) const MAX_AXIS_Z2: f64 = 0.9604;

/// A cylinder in model space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Cylinder {
    /// The centre.
    pub center: DVec3,
    /// The unit axis, from bottom to top.
    pub axis: DVec3,
    /// The length along the axis.
    pub length: f64,
    /// The radius.
    pub radius: f64,
}

impl Cylinder {
    /// Index of the centre (3 values) in the parameter vector.
    pub const CENTER: usize = 0;
    /// Index of the axis (3 values).
    pub const AXIS: usize = 3;
    /// Index of the length.
    pub const LENGTH: usize = 6;
    /// Index of the radius.
    pub const RADIUS: usize = 7;
    /// The number of parameters.
    pub const LEN: usize = 8;

    pub(crate) fn from_placement(p: &Placement, default_size: f64) -> Self {
        let v = view_from_sketch(p.at);
        let (axis, length) = dropped_axis(p, default_size);
        Self {
            center: DVec3::new(v.x, v.y, 0.0),
            axis,
            length,
            radius: p.radius.unwrap_or(default_size * 0.3).abs().max(1e-9),
        }
    }

    pub(crate) fn params(&self) -> Vec<f64> {
        let (c, a) = (self.center, self.axis);
        vec![c.x, c.y, c.z, a.x, a.y, a.z, self.length, self.radius]
    }

    pub(crate) fn with_params(&self, x: &[f64]) -> Self {
        Self {
            center: vec3_at(x, Self::CENTER),
            axis: vec3_at(x, Self::AXIS).normalize_or(self.axis),
            length: x[Self::LENGTH],
            radius: x[Self::RADIUS],
        }
    }

    pub(crate) fn center(&self) -> DVec3 {
        self.center
    }

    pub(crate) fn size(&self) -> f64 {
        self.length.max(2.0 * self.radius)
    }

    pub(crate) fn transformed(&self, offset: DVec3, factor: f64) -> Self {
        Self {
            center: (self.center + offset) * factor,
            axis: self.axis,
            length: self.length * factor,
            radius: self.radius * factor,
        }
    }

    pub(crate) fn shape<T: Real>(&self, x: &[T]) -> Shape<T> {
        let c = vec3_expr_at(x, Self::CENTER);
        let a = vec3_expr_at(x, Self::AXIS);
        let (l, r) = (x[Self::LENGTH], x[Self::RADIUS]);
        revolved_shape(c, a, l, r, r, self.size() * MIN_SIZE_FRACTION)
    }

    pub(crate) fn mesh(&self, segments: usize) -> TriMesh {
        let bottom = self.center - self.axis * (self.length / 2.0);
        revolution(
            bottom,
            self.axis,
            &[(0.0, self.radius), (self.length, self.radius)],
            segments,
        )
    }
}

/// The shape of a cylinder or truncated cone: centre c, unit axis a, length l, bottom
/// and top radii; sizes bounded below by `min_size`.
pub(crate) fn revolved_shape<T: Real>(
    c: Vec3<T>,
    a: Vec3<T>,
    l: T,
    r_bottom: T,
    r_top: T,
    min_size: f64,
) -> Shape<T> {
    let half = a * (l * 0.5);
    let (bottom, top) = (c - half, c + half);
    let slope = (r_top - r_bottom) / l;
    let pb = contour_points(bottom, a, r_bottom, slope);
    let pt = contour_points(top, a, r_top, slope);
    let curve = ProjectedCurve::shown;
    Shape {
        curves: vec![
            curve("top", CurveClass::Feature, circle_ellipse(top, a, r_top)),
            curve(
                "bottom",
                CurveClass::Feature,
                circle_ellipse(bottom, a, r_bottom),
            ),
            curve(
                "left",
                CurveClass::Silhouette,
                Curve2::Polyline(vec![pb[1], pt[1]]),
            ),
            curve(
                "right",
                CurveClass::Silhouette,
                Curve2::Polyline(vec![pb[0], pt[0]]),
            ),
        ],
        features: vec![
            FeatureCurve {
                feature: Feature::Top,
                geometry: FeatureGeometry::Circle {
                    center: top,
                    normal: a,
                    radius: r_top,
                },
            },
            FeatureCurve {
                feature: Feature::Bottom,
                geometry: FeatureGeometry::Circle {
                    center: bottom,
                    normal: -a,
                    radius: r_bottom,
                },
            },
        ],
        equalities: vec![("unit axis", a.norm_squared() - 1.0)],
        inequalities: vec![
            ("positive length", l - min_size),
            ("positive bottom radius", r_bottom - min_size),
            ("positive top radius", r_top - min_size),
            ("axis not along the view", -a.z.square() + MAX_AXIS_Z2),
        ],
        regularizers: Vec::new(),
        profile: Vec::new(),
        untilted: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::Cylinder;
    use crate::ad::{Graph, Tape};
    use crate::primitive::{Curve2, Placement, Primitive, PrimitiveKind};

    #[test]
    fn placement_round_trip_and_shape() {
        let mut place = Placement::at(DVec2::new(100.0, 200.0));
        place.length = Some(50.0);
        place.radius = Some(10.0);
        let p = Primitive::from_placement(PrimitiveKind::Cylinder, &place, 30.0);
        let Primitive::Cylinder(cyl) = &p else {
            panic!("a cylinder")
        };
        assert_eq!(cyl.center, DVec3::new(100.0, -200.0, 0.0));
        // Tilted towards the viewer, keeping the projected length.
        assert!(cyl.axis.x.abs() < 1e-12 && cyl.axis.y > 0.9 && cyl.axis.z > 0.3);
        assert!((cyl.length * cyl.axis.y - 50.0).abs() < 1e-9);
        assert_eq!(p.with_params(&p.params()), p);
        let shape = p.current_shape();
        assert_eq!(shape.curves.len(), 4);
        let Curve2::Polyline(left) = &shape.curves[2].curve else {
            panic!("a segment")
        };
        // Axis up the page, viewed side-on: contours at x = 100 ± 10, from y −225 to −175.
        let xs: Vec<f64> = left.iter().map(|q| q.x).collect();
        assert!(xs
            .iter()
            .all(|x| (x - 110.0).abs() < 1e-9 || (x - 90.0).abs() < 1e-9));
        assert!((left[1].y - left[0].y - 50.0).abs() < 1e-9);
        assert!(shape.equalities[0].1.abs() < 1e-12, "unit axis holds");
        assert!(shape.inequalities.iter().all(|(_, g)| *g > 0.0));
    }

    #[test]
    fn the_expression_shape_matches_the_numeric_one() {
        let cyl = Cylinder {
            center: DVec3::new(1.0, 2.0, 3.0),
            axis: DVec3::new(0.3, 0.8, 0.4).normalize(),
            length: 4.0,
            radius: 1.5,
        };
        let p = Primitive::Cylinder(cyl);
        let numeric = p.current_shape();
        let g = Graph::new();
        let vars = g.vars(8);
        let symbolic = p.shape(&vars);
        let Curve2::Polyline(sym) = &symbolic.curves[3].curve else {
            panic!("a segment")
        };
        let Curve2::Polyline(num) = &numeric.curves[3].curve else {
            panic!("a segment")
        };
        let mut tape = Tape::compile(&g, &[sym[0].x, sym[1].y]);
        let values = tape.eval(&p.params()).to_vec();
        assert!((values[0] - num[0].x).abs() < 1e-12);
        assert!((values[1] - num[1].y).abs() < 1e-12);
        assert!(p.mesh(32).volume() > 0.0);
    }
}
