//! Concentric: two circles share their centre, (c₂ − c₁)/s = 0 (s = r₁ + r₂; a sphere's
//! outline is centred on the sphere). Inferred when the projected centres are within
//! [`InferenceSettings::distance`]·s (depth is left to the solve).

use super::{
    circle, components, offset_2d, InferenceSettings, Member, RelationError, RelationKind,
};
use crate::ad::Real;

const KIND: RelationKind = RelationKind::Concentric;

pub(super) fn residuals<T: Real>(m: &[Member<'_, T>]) -> Result<Vec<T>, RelationError> {
    let (c1, _, r1) = circle(KIND, m, 0)?;
    let (c2, _, r2) = circle(KIND, m, 1)?;
    let s = r1 + r2;
    Ok(components(c2 - c1).into_iter().map(|v| v / s).collect())
}

pub(super) fn holds(m: &[Member<'_, f64>], settings: &InferenceSettings) -> bool {
    let (Ok((c1, _, r1)), Ok((c2, _, r2))) = (circle(KIND, m, 0), circle(KIND, m, 1)) else {
        return false;
    };
    offset_2d(c1, c2).length() <= settings.distance * (r1 + r2)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::testing::{features, invariant_psi};
    use super::super::{holds, InferenceSettings, Member, RelationKind};
    use crate::primitive::{Cylinder, Feature, Primitive, Sphere};

    #[test]
    fn a_ring_on_a_ball() {
        let k = RelationKind::Concentric;
        let ball = Primitive::Sphere(Sphere {
            center: DVec3::new(3.0, 4.0, 5.0),
            radius: 10.0,
        });
        let disc = |c: DVec3| {
            Primitive::Cylinder(Cylinder {
                center: c,
                axis: DVec3::Y,
                length: 2.0,
                radius: 10.0,
            })
        };
        let through = disc(DVec3::new(3.0, 3.0, 5.0)); // its top at the ball's centre
        assert!(
            invariant_psi(
                k,
                &[
                    (&ball, Some(Feature::Outline)),
                    (&through, Some(Feature::Top))
                ]
            ) < 1e-12
        );
        let off = disc(DVec3::new(5.0, 3.0, 5.0));
        assert!(
            invariant_psi(
                k,
                &[(&ball, Some(Feature::Outline)), (&off, Some(Feature::Top))]
            ) > 0.09
        );
        let s = InferenceSettings::default();
        let (fb, ft, fo) = (features(&ball), features(&through), features(&off));
        let m = |f| {
            [
                Member {
                    features: &fb,
                    feature: Some(Feature::Outline),
                },
                Member {
                    features: f,
                    feature: Some(Feature::Top),
                },
            ]
        };
        assert!(holds(k, &m(&ft), &s));
        assert!(holds(k, &m(&fo), &s)); // 2 off, radii 20 in all: 0.1
        let far = features(&disc(DVec3::new(6.0, 3.0, 5.0)));
        assert!(!holds(k, &m(&far), &s));
    }
}
