//! Same radius: two circles have the same radius, (r₁ − r₂)/(r₁ + r₂) = 0. Inferred when
//! |r₁ − r₂| ≤ [`InferenceSettings::radius`]·(r₁ + r₂).

use super::{circle, InferenceSettings, Member, RelationError, RelationKind};
use crate::ad::Real;

const KIND: RelationKind = RelationKind::SameRadius;

pub(super) fn residuals<T: Real>(m: &[Member<'_, T>]) -> Result<Vec<T>, RelationError> {
    let (_, _, r1) = circle(KIND, m, 0)?;
    let (_, _, r2) = circle(KIND, m, 1)?;
    Ok(vec![(r1 - r2) / (r1 + r2)])
}

pub(super) fn holds(m: &[Member<'_, f64>], settings: &InferenceSettings) -> bool {
    let (Ok((_, _, r1)), Ok((_, _, r2))) = (circle(KIND, m, 0), circle(KIND, m, 1)) else {
        return false;
    };
    settings.same_size(r1, r2, settings.radius)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::testing::{features, invariant_psi};
    use super::super::{holds, InferenceSettings, Member, RelationKind};
    use crate::primitive::{Cone, Feature, Primitive};

    #[test]
    fn legs_of_one_thickness() {
        let k = RelationKind::SameRadius;
        let leg = |x: f64, r: f64| {
            Primitive::Cone(Cone {
                center: DVec3::X * x,
                axis: DVec3::Y,
                length: 50.0,
                radius_bottom: r,
                radius_top: 3.0,
            })
        };
        let (a, b, c) = (leg(0.0, 2.0), leg(40.0, 2.0), leg(40.0, 2.6));
        assert!(
            invariant_psi(
                k,
                &[(&a, Some(Feature::Bottom)), (&b, Some(Feature::Bottom))]
            ) < 1e-12
        );
        assert!(
            invariant_psi(
                k,
                &[(&a, Some(Feature::Bottom)), (&c, Some(Feature::Bottom))]
            ) > 0.1
        );
        let s = InferenceSettings::default();
        let (fa, fb, fc) = (features(&a), features(&b), features(&c));
        let m = |f, n| {
            [
                Member {
                    features: &fa,
                    feature: Some(Feature::Bottom),
                },
                Member {
                    features: f,
                    feature: Some(n),
                },
            ]
        };
        assert!(holds(k, &m(&fb, Feature::Bottom), &s));
        assert!(!holds(k, &m(&fc, Feature::Bottom), &s));
        assert!(!holds(k, &m(&fb, Feature::Top), &s));
    }
}
