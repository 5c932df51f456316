//! Coaxial: two end circles share their axis line: n₁ × n₂ = 0 and (c₂ − c₁) × n₁ / s = 0
//! (s = r₁ + r₂). Inferred when the normals are parallel within θ and, in the view plane
//! (depth is not drawn), each centre lies within [`InferenceSettings::distance`]·s of the
//! other's projected axis line.

use super::{
    circle, components, norm, offset_2d, InferenceSettings, Member, RelationError, RelationKind,
};
use crate::ad::{Real, Vec3};

const KIND: RelationKind = RelationKind::Coaxial;

pub(super) fn residuals<T: Real>(m: &[Member<'_, T>]) -> Result<Vec<T>, RelationError> {
    let (c1, n1, r1) = circle(KIND, m, 0)?;
    let (c2, n2, r2) = circle(KIND, m, 1)?;
    let s = r1 + r2;
    let mut out = components(n1.cross(n2));
    out.extend(components((c2 - c1).cross(n1)).into_iter().map(|v| v / s));
    Ok(out)
}

pub(super) fn holds(m: &[Member<'_, f64>], settings: &InferenceSettings) -> bool {
    let (Ok((c1, n1, r1)), Ok((c2, n2, r2))) = (circle(KIND, m, 0), circle(KIND, m, 1)) else {
        return false;
    };
    norm(&components(n1.cross(n2))) <= settings.sin_angle()
        && on_one_line(c1, n1, c2, n2, settings.position_tolerance(r1 + r2))
}

/// Whether, in the view plane, each centre lies within `tolerance` of the other's
/// projected axis line (`c` a centre, `n` its axis; only their projections count).
pub(super) fn on_one_line(
    c1: Vec3<f64>,
    n1: Vec3<f64>,
    c2: Vec3<f64>,
    n2: Vec3<f64>,
    tolerance: f64,
) -> bool {
    let d = offset_2d(c1, c2);
    let off_line = |n: Vec3<f64>| {
        let axis = glam::DVec2::new(n.x, n.y);
        // An axis along the view projects to a point: the offset itself counts.
        if axis.length() < 1e-6 {
            d.length()
        } else {
            d.perp_dot(axis.normalize()).abs()
        }
    };
    off_line(n1).max(off_line(n2)) <= tolerance
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::testing::{features, invariant_psi};
    use super::super::{holds, InferenceSettings, Member, RelationKind};
    use crate::primitive::{Cylinder, Feature, Primitive};

    fn cylinder(center: DVec3, radius: f64) -> Primitive {
        let axis = DVec3::new(0.0, 0.94, 0.34);
        Primitive::Cylinder(Cylinder {
            center,
            axis,
            length: 20.0,
            radius,
        })
    }

    #[test]
    fn a_stack_shares_its_axis() {
        let k = RelationKind::Coaxial;
        let axis = DVec3::new(0.0, 0.94, 0.34);
        let a = cylinder(DVec3::ZERO, 10.0);
        let b = cylinder(axis * 20.0, 5.0);
        assert!(invariant_psi(k, &[(&a, Some(Feature::Top)), (&b, Some(Feature::Bottom))]) < 1e-12);
        let off = cylinder(axis * 20.0 + DVec3::X * 3.0, 5.0);
        assert!(
            invariant_psi(
                k,
                &[(&a, Some(Feature::Top)), (&off, Some(Feature::Bottom))]
            ) > 0.1
        );
        let s = InferenceSettings::default();
        let (fa, fb, fo) = (features(&a), features(&b), features(&off));
        let m = |f| {
            [
                Member {
                    features: &fa,
                    feature: Some(Feature::Top),
                },
                Member {
                    features: f,
                    feature: Some(Feature::Bottom),
                },
            ]
        };
        assert!(holds(k, &m(&fb), &s));
        assert!(!holds(k, &m(&fo), &s)); // 3 off a line, radii 15 in all: 0.2 > 0.1
                                         // Depth is not drawn: the same stack with the top part pushed back still counts.
        let deeper = features(&cylinder(axis * 20.0 + DVec3::Z * 7.0, 5.0));
        assert!(holds(k, &m(&deeper), &s));
    }
}
