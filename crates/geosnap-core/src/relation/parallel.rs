//! Parallel: the normals of two features (end circles, faces) are parallel,
//! n₁ × n₂ = 0 — three equations of rank two, which the solver takes as they are. Inferred
//! when |n₁ × n₂| ≤ sin θ (θ = [`InferenceSettings::angle_degrees`]).

use super::{
    chosen, components, frame, norm, InferenceSettings, Member, RelationError, RelationKind,
};
use crate::ad::Real;

const KIND: RelationKind = RelationKind::Parallel;

pub(super) fn residuals<T: Real>(m: &[Member<'_, T>]) -> Result<Vec<T>, RelationError> {
    let (_, n1, _) = frame(chosen(KIND, m, 0)?);
    let (_, n2, _) = frame(chosen(KIND, m, 1)?);
    Ok(components(n1.cross(n2)))
}

pub(super) fn holds(m: &[Member<'_, f64>], settings: &InferenceSettings) -> bool {
    residuals(m).is_ok_and(|r| norm(&r) <= settings.sin_angle())
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use super::super::testing::features;
    use super::super::testing::invariant_psi;
    use super::super::{holds, InferenceSettings, Member, RelationKind};
    use crate::primitive::{Axis, Cuboid, Feature, Primitive};

    fn cylinder(center: DVec3, axis: DVec3) -> Primitive {
        super::super::testing::cylinder(center, axis, 30.0, 4.0)
    }

    #[test]
    fn parallel_axes_and_faces() {
        let k = RelationKind::Parallel;
        let a = cylinder(DVec3::ZERO, DVec3::new(0.2, 1.0, 0.3));
        let b = cylinder(DVec3::new(50.0, 5.0, -3.0), DVec3::new(0.2, 1.0, 0.3));
        assert!(invariant_psi(k, &[(&a, Some(Feature::Top)), (&b, Some(Feature::Bottom))]) < 1e-12);
        let tilted = cylinder(DVec3::new(50.0, 5.0, -3.0), DVec3::new(0.3, 1.0, 0.3));
        assert!(
            invariant_psi(
                k,
                &[(&a, Some(Feature::Top)), (&tilted, Some(Feature::Top))]
            ) > 0.05
        );
        // A box's top face is parallel to an upright cylinder's ends.
        let upright = cylinder(DVec3::ZERO, DVec3::Y);
        let brick = Primitive::Cuboid(Cuboid {
            center: DVec3::new(9.0, -20.0, 4.0),
            rotation: DQuat::IDENTITY,
            size: DVec3::new(40.0, 10.0, 20.0),
        });
        assert!(
            invariant_psi(
                k,
                &[
                    (&upright, Some(Feature::Top)),
                    (&brick, Some(Feature::face(Axis::Y, true)))
                ]
            ) < 1e-12
        );
        assert!(
            invariant_psi(
                k,
                &[
                    (&upright, Some(Feature::Top)),
                    (&brick, Some(Feature::face(Axis::Z, true)))
                ]
            ) > 0.99
        );
    }

    #[test]
    fn inferred_within_the_angle() {
        let s = InferenceSettings::default();
        let a = features(&cylinder(DVec3::ZERO, DVec3::Y));
        let within = features(&cylinder(DVec3::X * 40.0, DVec3::new(0.1, 1.0, 0.0)));
        let beyond = features(&cylinder(DVec3::X * 40.0, DVec3::new(0.2, 1.0, 0.0)));
        let pair = |b| {
            [
                Member {
                    features: &a,
                    feature: Some(Feature::Top),
                },
                Member {
                    features: b,
                    feature: Some(Feature::Top),
                },
            ]
        };
        assert!(holds(RelationKind::Parallel, &pair(&within), &s)); // 5.7°
        assert!(!holds(RelationKind::Parallel, &pair(&beyond), &s)); // 11.3°
    }
}
