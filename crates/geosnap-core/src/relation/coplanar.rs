//! Coplanar: two features (circles or faces) lie in one plane: n₁ × n₂ = 0 and
//! (c₂ − c₁) · n₁ / s = 0 (s the sum of the features' sizes). Inferred when the normals
//! are parallel within θ and, in the view plane (depth is not drawn), the second
//! feature's centre lies within the first's projected outline grown by
//! [`InferenceSettings::distance`]·s: a stud drawn on a brick's top face, a leg's end
//! drawn on a table's underside.

use glam::DVec2;

use super::{
    chosen, components, frame, norm, offset_2d, InferenceSettings, Member, RelationError,
    RelationKind,
};
use crate::ad::Real;
use crate::primitive::FeatureGeometry;

const KIND: RelationKind = RelationKind::Coplanar;

pub(super) fn residuals<T: Real>(m: &[Member<'_, T>]) -> Result<Vec<T>, RelationError> {
    let (c1, n1, s1) = frame(chosen(KIND, m, 0)?);
    let (c2, n2, s2) = frame(chosen(KIND, m, 1)?);
    let mut out = components(n1.cross(n2));
    out.push((c2 - c1).dot(n1) / (s1 + s2));
    Ok(out)
}

/// Whether `p` (relative to the feature's projected centre) lies within the projected
/// outline of `f`, grown by `grow`.
fn inside(f: &FeatureGeometry<f64>, p: DVec2, grow: f64) -> bool {
    // Both outlines are images of a unit disc or square under a linear map [u v].
    let (u, v, square) = match f {
        FeatureGeometry::Circle { normal, radius, .. } => {
            let n = normal.to_dvec3();
            let w = n.any_orthonormal_vector();
            let k = n.cross(w);
            ((w * *radius).truncate(), (k * *radius).truncate(), false)
        }
        FeatureGeometry::Rectangle { half_extents, .. } => (
            (half_extents[0].0.to_dvec3() * half_extents[0].1).truncate(),
            (half_extents[1].0.to_dvec3() * half_extents[1].1).truncate(),
            true,
        ),
    };
    let m = glam::DMat2::from_cols(u, v);
    if m.determinant().abs() < 1e-12 * (u.length_squared() + v.length_squared()) {
        // Seen edge-on: the outline is a segment.
        let seg = if u.length() > v.length() { u } else { v };
        let t = (p.dot(seg) / seg.length_squared()).clamp(-1.0, 1.0);
        return (p - seg * t).length() <= grow;
    }
    let q = m.inverse() * p;
    let scale = grow / u.length().min(v.length());
    if square {
        q.x.abs().max(q.y.abs()) <= 1.0 + scale
    } else {
        q.length() <= 1.0 + scale
    }
}

pub(super) fn holds(m: &[Member<'_, f64>], settings: &InferenceSettings) -> bool {
    let (Ok(f1), Ok(f2)) = (chosen(KIND, m, 0), chosen(KIND, m, 1)) else {
        return false;
    };
    let ((c1, n1, s1), (c2, n2, s2)) = (frame(f1), frame(f2));
    norm(&components(n1.cross(n2))) <= settings.sin_angle()
        && inside(f1, offset_2d(c1, c2), settings.position_tolerance(s1 + s2))
}

/// Whether two like features of repeated parts (the rims of a row of cups, the feet of
/// a table's legs) lie level: normals parallel within θ and each centre within the
/// position tolerance of the other's plane, wherever they are drawn (the outline test of
/// [`holds`] is for a part drawn on another's face).
pub(super) fn level(m: &[Member<'_, f64>], settings: &InferenceSettings) -> bool {
    let (Ok(f1), Ok(f2)) = (chosen(KIND, m, 0), chosen(KIND, m, 1)) else {
        return false;
    };
    let ((c1, n1, s1), (c2, n2, s2)) = (frame(f1), frame(f2));
    let d = (c2 - c1).to_dvec3();
    let tolerance = settings.position_tolerance(s1 + s2);
    norm(&components(n1.cross(n2))) <= settings.sin_angle()
        && d.dot(n1.to_dvec3()).abs() <= tolerance
        && d.dot(n2.to_dvec3()).abs() <= tolerance
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use super::super::testing::{features, invariant_psi};
    use super::super::{holds, InferenceSettings, Member, RelationKind};
    use crate::primitive::{Axis, Cuboid, Cylinder, Feature, Primitive};

    #[test]
    fn a_stud_on_a_brick() {
        let k = RelationKind::Coplanar;
        let view = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.6);
        let brick = Primitive::Cuboid(Cuboid {
            center: DVec3::ZERO,
            rotation: view,
            size: DVec3::new(80.0, 20.0, 40.0),
        });
        let up = view * DVec3::Y;
        let stud = |c: DVec3| {
            Primitive::Cylinder(Cylinder {
                center: c,
                axis: up,
                length: 6.0,
                radius: 5.0,
            })
        };
        let on = stud(up * 13.0 + view * DVec3::new(25.0, 0.0, 10.0));
        assert!(
            invariant_psi(
                k,
                &[
                    (&brick, Some(Feature::face(Axis::Y, true))),
                    (&on, Some(Feature::Bottom))
                ]
            ) < 1e-12
        );
        let floating = stud(up * 15.0 + view * DVec3::new(25.0, 0.0, 10.0));
        assert!(
            invariant_psi(
                k,
                &[
                    (&brick, Some(Feature::face(Axis::Y, true))),
                    (&floating, Some(Feature::Bottom))
                ]
            ) > 0.02
        );
        let s = InferenceSettings::default();
        let (fb, fs) = (features(&brick), features(&on));
        let m = |f| {
            [
                Member {
                    features: &fb,
                    feature: Some(Feature::face(Axis::Y, true)),
                },
                Member {
                    features: f,
                    feature: Some(Feature::Bottom),
                },
            ]
        };
        assert!(holds(k, &m(&fs), &s));
        // Off the face in the drawing: not coplanar, whatever the depth.
        let beside = features(&stud(up * 13.0 + view * DVec3::new(70.0, 0.0, 10.0)));
        assert!(!holds(k, &m(&beside), &s));
    }
}
