//! On sphere: a circle (a tube's end) sits on a sphere and faces its centre:
//! (‖c − C‖ − R)/s = 0 and n × (c − C)/s = 0, with the sphere's centre C and radius R taken
//! from its `outline` and s = R + r. Inferred when, in the view plane, the circle's centre
//! lies within the sphere's outline grown by [`InferenceSettings::distance`]·s and its
//! axis, projected, points at the sphere's projected centre within θ or passes within
//! 2·[`InferenceSettings::distance`]·s of it (or the circle is seen face-on over the
//! sphere).

use super::{
    circle, components, offset_2d, InferenceSettings, Member, RelationError, RelationKind,
};
use crate::ad::Real;
use crate::primitive::Feature;

const KIND: RelationKind = RelationKind::OnSphere;

pub(super) fn residuals<T: Real>(m: &[Member<'_, T>]) -> Result<Vec<T>, RelationError> {
    let (centre, _, radius) = circle(KIND, m, 0)?;
    let (c, n, r) = circle(KIND, m, 1)?;
    let s = radius + r;
    let d = c - centre;
    let mut out = vec![(d.norm() - radius) / s];
    out.extend(components(n.cross(d)).into_iter().map(|v| v / s));
    Ok(out)
}

pub(super) fn holds(m: &[Member<'_, f64>], settings: &InferenceSettings) -> bool {
    if m[0].feature != Some(Feature::Outline) {
        return false;
    }
    let (Ok((centre, _, radius)), Ok((c, n, r))) = (circle(KIND, m, 0), circle(KIND, m, 1)) else {
        return false;
    };
    let d = offset_2d(centre, c);
    if d.length() > radius + settings.position_tolerance(radius + r) {
        return false;
    }
    let axis = glam::DVec2::new(n.x, n.y);
    if axis.length() < settings.sin_angle() || d.length() < 1e-9 * radius {
        // Seen along its axis, over the sphere: it may face the centre in depth.
        return true;
    }
    // The axis line passes near the centre: within θ in angle, or within twice the
    // distance threshold. A ball is drawn with few strokes, and its centre is the least
    // certain of the positions inference compares.
    let across = axis.normalize().perp_dot(d).abs();
    across <= settings.sin_angle() * d.length()
        || across <= 2.0 * settings.position_tolerance(radius + r)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::testing::{features, invariant_psi};
    use super::super::{holds, InferenceSettings, Member, RelationKind};
    use crate::primitive::{Cylinder, Feature, Primitive, Sphere};

    #[test]
    fn a_tube_on_a_ball() {
        let k = RelationKind::OnSphere;
        let ball = Primitive::Sphere(Sphere {
            center: DVec3::new(1.0, 2.0, 3.0),
            radius: 20.0,
        });
        let dir = DVec3::new(1.0, 0.2, 0.3).normalize();
        // A tube whose bottom end is on the ball, pointing away from its centre.
        let tube = |base: f64, tilt: DVec3| {
            Primitive::Cylinder(Cylinder {
                center: DVec3::new(1.0, 2.0, 3.0) + dir * (base + 15.0),
                axis: (dir + tilt).normalize(),
                length: 30.0,
                radius: 4.0,
            })
        };
        let on = tube(20.0, DVec3::ZERO);
        assert!(
            invariant_psi(
                k,
                &[
                    (&ball, Some(Feature::Outline)),
                    (&on, Some(Feature::Bottom))
                ]
            ) < 1e-9
        );
        let lifted = tube(24.0, DVec3::ZERO);
        assert!(
            invariant_psi(
                k,
                &[
                    (&ball, Some(Feature::Outline)),
                    (&lifted, Some(Feature::Bottom))
                ]
            ) > 0.1
        );
        let s = InferenceSettings::default();
        let (fb, fo) = (features(&ball), features(&on));
        let m = |f, n| {
            [
                Member {
                    features: &fb,
                    feature: Some(Feature::Outline),
                },
                Member {
                    features: f,
                    feature: Some(n),
                },
            ]
        };
        assert!(holds(k, &m(&fo, Feature::Bottom), &s));
        let askew = features(&tube(20.0, DVec3::new(0.0, 0.8, 0.0)));
        assert!(!holds(k, &m(&askew, Feature::Bottom), &s));
        let far = features(&tube(40.0, DVec3::ZERO));
        assert!(!holds(k, &m(&far, Feature::Bottom), &s));
    }
}
