//! Collinear centres: the centres of three features lie on one line,
//! (c₂ − c₁) × (c₃ − c₁) / s² = 0 (s the sum of the sizes). Inferred when, in the view
//! plane, the third centre lies within [`InferenceSettings::distance`]·s of the line
//! through the first two, which are at least s apart.

use super::{
    chosen, components, frame, offset_2d, InferenceSettings, Member, RelationError, RelationKind,
};
use crate::ad::Real;

const KIND: RelationKind = RelationKind::CollinearCenters;

pub(super) fn residuals<T: Real>(m: &[Member<'_, T>]) -> Result<Vec<T>, RelationError> {
    let (c1, _, s1) = frame(chosen(KIND, m, 0)?);
    let (c2, _, s2) = frame(chosen(KIND, m, 1)?);
    let (c3, _, s3) = frame(chosen(KIND, m, 2)?);
    let s = s1 + s2 + s3;
    let s2_ = s * s;
    Ok(components((c2 - c1).cross(c3 - c1))
        .into_iter()
        .map(|v| v / s2_)
        .collect())
}

pub(super) fn holds(m: &[Member<'_, f64>], settings: &InferenceSettings) -> bool {
    let (Ok(f1), Ok(f2), Ok(f3)) = (chosen(KIND, m, 0), chosen(KIND, m, 1), chosen(KIND, m, 2))
    else {
        return false;
    };
    let ((c1, _, s1), (c2, _, s2), (c3, _, s3)) = (frame(f1), frame(f2), frame(f3));
    let s = s1 + s2 + s3;
    let (d, e) = (offset_2d(c1, c2), offset_2d(c1, c3));
    d.length() >= s && (e.perp_dot(d) / d.length()).abs() <= settings.position_tolerance(s)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::testing::{features, invariant_psi};
    use super::super::{holds, InferenceSettings, Member, RelationKind};
    use crate::primitive::{Feature, Primitive, Sphere};

    #[test]
    fn beads_on_a_string() {
        let k = RelationKind::CollinearCenters;
        let bead = |c: DVec3| {
            Primitive::Sphere(Sphere {
                center: c,
                radius: 2.0,
            })
        };
        let dir = DVec3::new(1.0, 0.3, -0.2);
        let (a, b, c) = (bead(DVec3::ZERO), bead(dir * 10.0), bead(dir * 25.0));
        let parts = |c: &Primitive| {
            invariant_psi(
                k,
                &[
                    (&a, Some(Feature::Outline)),
                    (&b, Some(Feature::Outline)),
                    (c, Some(Feature::Outline)),
                ],
            )
        };
        assert!(parts(&c) < 1e-12);
        let off = bead(dir * 25.0 + DVec3::Y * 2.0);
        assert!(parts(&off) > 0.02);
        let s = InferenceSettings::default();
        let f = [features(&a), features(&b), features(&c), features(&off)];
        let m = |i: usize| {
            [0, 1, i].map(|j| Member {
                features: &f[j],
                feature: Some(Feature::Outline),
            })
        };
        assert!(holds(k, &m(2), &s));
        assert!(!holds(k, &m(3), &s)); // 1.9 off the line, sizes 6: 0.3 > 0.1
    }
}
