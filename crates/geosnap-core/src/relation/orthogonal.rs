//! Orthogonal: the normals of two features are perpendicular, n₁ · n₂ = 0. Inferred when
//! |n₁ · n₂| ≤ sin θ (θ = [`InferenceSettings::angle_degrees`] off the right angle).

use super::{chosen, frame, InferenceSettings, Member, RelationError, RelationKind};
use crate::ad::Real;

const KIND: RelationKind = RelationKind::Orthogonal;

pub(super) fn residuals<T: Real>(m: &[Member<'_, T>]) -> Result<Vec<T>, RelationError> {
    let (_, n1, _) = frame(chosen(KIND, m, 0)?);
    let (_, n2, _) = frame(chosen(KIND, m, 1)?);
    Ok(vec![n1.dot(n2)])
}

pub(super) fn holds(m: &[Member<'_, f64>], settings: &InferenceSettings) -> bool {
    residuals(m).is_ok_and(|r| r[0].abs() <= settings.sin_angle())
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::testing::{features, invariant_psi};
    use super::super::{holds, InferenceSettings, Member, RelationKind};
    use crate::primitive::{Cylinder, Feature, Primitive};

    fn cylinder(axis: DVec3) -> Primitive {
        Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: axis.normalize(),
            length: 30.0,
            radius: 4.0,
        })
    }

    #[test]
    fn perpendicular_axes() {
        let k = RelationKind::Orthogonal;
        let (a, b) = (cylinder(DVec3::Y), cylinder(DVec3::new(1.0, 0.0, 0.4)));
        assert!(invariant_psi(k, &[(&a, Some(Feature::Top)), (&b, Some(Feature::Top))]) < 1e-12);
        let c = cylinder(DVec3::new(1.0, 0.5, 0.4));
        assert!(invariant_psi(k, &[(&a, Some(Feature::Top)), (&c, Some(Feature::Top))]) > 0.3);
        let s = InferenceSettings::default();
        let (fa, fb) = (features(&a), features(&cylinder(DVec3::new(1.0, 0.1, 0.0))));
        let m = [
            Member {
                features: &fa,
                feature: Some(Feature::Top),
            },
            Member {
                features: &fb,
                feature: Some(Feature::Bottom),
            },
        ];
        assert!(holds(k, &m, &s)); // 84.3°
        let fc = features(&c);
        let m = [
            Member {
                features: &fa,
                feature: Some(Feature::Top),
            },
            Member {
                features: &fc,
                feature: Some(Feature::Top),
            },
        ];
        assert!(!holds(k, &m, &s));
    }
}
