//! Concentric: two circles share their centre, (c₂ − c₁)/s = 0 (s = r₁ + r₂; a sphere's
//! outline is centred on the sphere). Inferred when the projected centres are within
//! [`InferenceSettings::distance`]·s or the drawing's noise (depth is left to the solve);
//! where the ends sit on each other in the drawing on one projected axis, the offset along
//! the axis may be a few times that (an end's place along its axis is what a snap pins least).

use super::{
    circle, components, offset_2d, InferenceSettings, Member, RelationError, RelationKind,
    MIN_PROJECTED_AXIS,
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
    let (Ok((c1, n1, r1)), Ok((c2, n2, r2))) = (circle(KIND, m, 0), circle(KIND, m, 1)) else {
        return false;
    };
    let (a1, a2) = (n1.to_dvec3().truncate(), n2.to_dvec3().truncate());
    let d = offset_2d(c1, c2);
    let tolerance = settings.position_tolerance(r1 + r2);
    // Ends on one axis line in the drawing (facing each other or the same way; the
    // depth of their normals is what a drawing shows least): along it, they may lie
    // further apart by the slack.
    if settings.axial_slack > 1.0
        && a1.length().min(a2.length()) >= MIN_PROJECTED_AXIS
        && a1.normalize().perp_dot(a2.normalize()).abs() <= settings.sin_angle()
    {
        let axis = (a1.normalize() + a2.normalize() * a1.dot(a2).signum()).normalize();
        return d.perp_dot(axis).abs() <= tolerance
            && d.dot(axis).abs() <= settings.axial_slack * tolerance;
    }
    d.length() <= tolerance
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

    /// A disc of radius 10 on the y axis tilted towards the viewer, whose bottom sits at
    /// `bottom` (a point on that axis, plus an offset).
    fn stacked(bottom: DVec3) -> Primitive {
        let axis = DVec3::new(0.0, 0.94, 0.34).normalize();
        Primitive::Cylinder(Cylinder {
            center: bottom + axis * 5.0,
            axis,
            length: 10.0,
            radius: 10.0,
        })
    }

    fn concentric(a: &Primitive, b: &Primitive, settings: &InferenceSettings) -> bool {
        let (fa, fb) = (features(a), features(b));
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
        holds(RelationKind::Concentric, &m, settings)
    }

    #[test]
    fn stacked_ends_may_lie_apart_along_their_axis_not_across() {
        let axis = DVec3::new(0.0, 0.94, 0.34).normalize();
        let lower = stacked(-axis * 10.0); // its top at the origin
        let s = InferenceSettings::default(); // 0.1 of the radii's sum: 2
        let joint = s.for_members(0.0, 5.0);
        // 6 apart along the axis (5.6 in the drawing): a gap where the parts join.
        let gap = stacked(axis * 6.0);
        assert!(!concentric(&lower, &gap, &s));
        assert!(concentric(&lower, &gap, &joint));
        // 6 apart across it: a part beside the other, joint or not.
        let beside = stacked(DVec3::X * 6.0);
        assert!(!concentric(&lower, &beside, &joint));
    }

    #[test]
    fn the_drawings_noise_widens_the_threshold_a_few_times_at_most() {
        let axis = DVec3::new(0.0, 0.94, 0.34).normalize();
        let lower = stacked(-axis * 10.0);
        let s = InferenceSettings::default(); // 2 for radii summing to 20
        let off = stacked(DVec3::X * 3.0);
        assert!(!concentric(&lower, &off, &s));
        // Strokes 2 units off their curves: centres 3 apart are within the noise.
        assert!(concentric(&lower, &off, &s.for_members(2.0, 1.0)));
        // However rough the drawing, 6 apart (three times the threshold) is apart.
        let far = stacked(DVec3::X * 6.0);
        assert!(!concentric(&lower, &far, &s.for_members(100.0, 1.0)));
    }
}
