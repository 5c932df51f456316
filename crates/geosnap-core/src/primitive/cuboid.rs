//! The cuboid (box).
//!
//! Parameters (10): centre c (3), orientation quaternion q = (w, x, y, z) (4, unit by
//! the constraint |q|² = 1), sizes (width, height, depth) (3, each > 0). The rotation R(q)
//! maps the box's local axes to model space: local x is the width direction, y the
//! height, z the depth.
//!
//! Inequalities: positive sizes, and no axis within 11.5° of the view direction (a size
//! along the view shows in no edge, and a fit could run away along it).
//!
//! Projected curves: the 12 edges (matched to straight strokes of either class); an edge
//! is *visible* when one of its two faces faces the viewer (outward normal z > 0),
//! judged at the primitive's current orientation. Feature curves: the six faces
//! [`Feature::FACES`] as rectangles.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::cylinder::{MAX_AXIS_Z2, MIN_SIZE_FRACTION};
use super::mesh::TriMesh;
use super::{
    quaternion_at, quaternion_columns, vec3_at, vec3_expr_at, Curve2, CurveClass, Feature,
    FeatureCurve, FeatureGeometry, Placement, ProjectedCurve, Shape,
};
use crate::ad::{Real, Vec3};
use crate::geom::projection::view_from_sketch;

/// A box in model space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Cuboid {
    /// The centre.
    pub center: DVec3,
    /// The orientation (local → model).
    pub rotation: DQuat,
    /// Width, height and depth along the local x, y and z axes.
    pub size: DVec3,
}

/// The edges as (axis along the edge, signs of the other two axes), with the two faces
/// each edge borders as indices into [`Feature::FACES`].
fn edges() -> Vec<(usize, [f64; 3], [usize; 2])> {
    let mut out = Vec::with_capacity(12);
    for along in 0..3 {
        let (i, j) = ((along + 1) % 3, (along + 2) % 3);
        for (si, sj) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let mut signs = [0.0; 3];
            signs[i] = si;
            signs[j] = sj;
            let face = |axis: usize, s: f64| 2 * axis + usize::from(s < 0.0);
            out.push((along, signs, [face(i, si), face(j, sj)]));
        }
    }
    out
}

impl Cuboid {
    pub(crate) fn from_placement(p: &Placement, default_size: f64) -> Self {
        let v = view_from_sketch(p.at);
        let size = p.size.map_or(DVec3::splat(default_size * 0.6), |s| {
            DVec3::from_array(s).abs()
        });
        // Tilted so three faces show (front, left, top), then rolled so the box's up
        // follows the placement axis.
        let up = DVec3::new(p.axis.x, -p.axis.y, 0.0);
        let roll = if up.length() > 0.0 {
            (-up.x).atan2(up.y)
        } else {
            0.0
        };
        let rotation = DQuat::from_rotation_z(roll)
            * DQuat::from_rotation_x(20f64.to_radians())
            * DQuat::from_rotation_y(-30f64.to_radians());
        Self {
            center: DVec3::new(v.x, v.y, 0.0),
            rotation,
            size: size.max(DVec3::splat(1e-9)),
        }
    }

    /// Index of the centre (3 values) in the parameter vector.
    pub const CENTER: usize = 0;
    /// Index of the quaternion's w; x, y and z follow (4 values).
    pub const ROTATION: usize = 3;
    /// Index of the width; height and depth follow (3 values).
    pub const SIZE: usize = 7;
    /// Index of the width.
    pub const WIDTH: usize = Self::SIZE;
    /// Index of the height.
    pub const HEIGHT: usize = Self::SIZE + 1;
    /// Index of the depth.
    pub const DEPTH: usize = Self::SIZE + 2;
    /// The number of parameters.
    pub const LEN: usize = 10;

    pub(crate) fn params(&self) -> Vec<f64> {
        let (c, q, s) = (self.center, self.rotation, self.size);
        vec![c.x, c.y, c.z, q.w, q.x, q.y, q.z, s.x, s.y, s.z]
    }

    pub(crate) fn with_params(&self, x: &[f64]) -> Self {
        let [w, qx, qy, qz] = quaternion_at(x, Self::ROTATION);
        let q = DQuat::from_xyzw(qx, qy, qz, w);
        Self {
            center: vec3_at(x, Self::CENTER),
            rotation: match q.length() {
                len if (len - 1.0).abs() < 1e-12 => q,
                len if len > 0.0 => q / len,
                _ => self.rotation,
            },
            size: vec3_at(x, Self::SIZE),
        }
    }

    pub(crate) fn center(&self) -> DVec3 {
        self.center
    }

    pub(crate) fn size(&self) -> f64 {
        self.size.max_element()
    }

    pub(crate) fn transformed(&self, offset: DVec3, factor: f64) -> Self {
        Self {
            center: (self.center + offset) * factor,
            rotation: self.rotation,
            size: self.size * factor,
        }
    }

    /// The local axes in model space.
    pub fn axes(&self) -> [DVec3; 3] {
        let m = glam::DMat3::from_quat(self.rotation);
        [m.x_axis, m.y_axis, m.z_axis]
    }

    pub(crate) fn shape<T: Real>(&self, x: &[T]) -> Shape<T> {
        let c = vec3_expr_at(x, Self::CENTER);
        let axes = quaternion_columns(quaternion_at(x, Self::ROTATION));
        let [width, height, depth] = [Self::WIDTH, Self::HEIGHT, Self::DEPTH].map(|i| x[i]);
        let half = [width * 0.5, height * 0.5, depth * 0.5];
        // Visibility from the current numeric orientation.
        let numeric_axes = self.axes();
        let face_faces_viewer = |face: usize| {
            let sign = if face.is_multiple_of(2) { 1.0 } else { -1.0 };
            numeric_axes[face / 2].z * sign > 1e-9
        };
        let mut curves = Vec::with_capacity(12);
        for (k, (along, signs, faces)) in edges().into_iter().enumerate() {
            let mut mid = c;
            for (axis, s) in signs.iter().enumerate() {
                if *s != 0.0 {
                    mid = mid + axes[axis] * (half[axis] * *s);
                }
            }
            let d = axes[along] * half[along];
            curves.push(ProjectedCurve {
                name: format!("edge {k}"),
                class: CurveClass::Edge,
                visible: faces.iter().any(|f| face_faces_viewer(*f)),
                curve: Curve2::Polyline(vec![(mid - d).xy(), (mid + d).xy()]),
            });
        }
        let features = Feature::FACES
            .into_iter()
            .enumerate()
            .map(|(face, feature)| {
                let axis = face / 2;
                let sign = if face.is_multiple_of(2) { 1.0 } else { -1.0 };
                let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
                FeatureCurve {
                    feature,
                    geometry: FeatureGeometry::Rectangle {
                        center: c + axes[axis] * (half[axis] * sign),
                        normal: axes[axis].scale(sign),
                        half_extents: [(axes[i], half[i]), (axes[j], half[j])],
                    },
                }
            })
            .collect();
        let [w, qx, qy, qz] = quaternion_at(x, Self::ROTATION);
        let q = Vec3::new(qx, qy, qz);
        let min = self.size() * MIN_SIZE_FRACTION;
        Shape {
            curves,
            features,
            equalities: vec![("unit quaternion", w.square() + q.norm_squared() - 1.0)],
            inequalities: vec![
                ("positive width", width - min),
                ("positive height", height - min),
                ("positive depth", depth - min),
                (
                    "width not along the view",
                    -axes[0].z.square() + MAX_AXIS_Z2,
                ),
                (
                    "height not along the view",
                    -axes[1].z.square() + MAX_AXIS_Z2,
                ),
                (
                    "depth not along the view",
                    -axes[2].z.square() + MAX_AXIS_Z2,
                ),
            ],
            regularizers: Vec::new(),
            profile: Vec::new(),
            untilted: Vec::new(),
        }
    }

    pub(crate) fn mesh(&self, _segments: usize) -> TriMesh {
        let axes = self.axes();
        let half = self.size * 0.5;
        let mut mesh = TriMesh::default();
        for face in 0..6usize {
            let axis = face / 2;
            let sign = if face.is_multiple_of(2) { 1.0 } else { -1.0 };
            let n = axes[axis] * sign;
            // (u, v, n) right-handed so the quad winds counter-clockwise seen from outside.
            let u = axes[(axis + 1) % 3] * sign;
            let v = n.cross(u);
            let (hu, hv) = (half[(axis + 1) % 3], half[(axis + 2) % 3]);
            let center = self.center + n * half[axis];
            let base = mesh.positions.len() as u32;
            for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                mesh.positions.push(center + u * (hu * su) + v * (hv * sv));
                mesh.normals.push(n);
            }
            mesh.triangles.push([base, base + 1, base + 2]);
            mesh.triangles.push([base, base + 2, base + 3]);
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec2, DVec3};

    use super::super::quaternion_columns;
    use crate::primitive::{Placement, Primitive, PrimitiveKind};

    #[test]
    fn quaternion_columns_match_glam() {
        let q = DQuat::from_euler(glam::EulerRot::YXZ, 0.3, -0.7, 1.1);
        let cols = quaternion_columns([q.w, q.x, q.y, q.z]);
        let m = glam::DMat3::from_quat(q);
        for (c, g) in cols.iter().zip([m.x_axis, m.y_axis, m.z_axis]) {
            assert!((c.to_dvec3() - g).length() < 1e-12);
        }
    }

    #[test]
    fn a_placed_box_shows_three_faces_and_nine_edges() {
        let mut place = Placement::at(DVec2::new(0.0, 0.0));
        place.size = Some([2.0, 3.0, 4.0]);
        let p = Primitive::from_placement(PrimitiveKind::Cuboid, &place, 1.0);
        let shape = p.current_shape();
        assert_eq!(shape.curves.len(), 12);
        assert_eq!(shape.curves.iter().filter(|c| c.visible).count(), 9);
        assert_eq!(p.with_params(&p.params()), p);
        let v = p.mesh(8).volume();
        assert!((v - 24.0).abs() < 1e-9, "{v}");
        let Primitive::Cuboid(b) = p else {
            panic!("a box")
        };
        assert!((b.axes()[0].length() - 1.0).abs() < 1e-12);
        assert!(b.center == DVec3::ZERO);
    }
}
