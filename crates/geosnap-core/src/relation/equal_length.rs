//! Equal length: two solids with a `bottom` and a `top` end (cylinders, cones, SGCs,
//! and the chord of a BGC) are equally long, (ℓ₁ − ℓ₂)/(ℓ₁ + ℓ₂) = 0 with ℓ the distance
//! between the end centres. Inferred when |ℓ₁ − ℓ₂| ≤ [`InferenceSettings::length`]·(ℓ₁ + ℓ₂).

use super::{InferenceSettings, Member, RelationError, RelationKind};
use crate::ad::Real;
use crate::primitive::{Feature, FeatureGeometry};

const KIND: RelationKind = RelationKind::EqualLength;

/// The distance between a member's end centres.
fn length<T: Real>(m: &[Member<'_, T>], i: usize) -> Result<T, RelationError> {
    let end = |feature: Feature| match m[i].get(feature) {
        Some(FeatureGeometry::Circle { center, .. }) => Ok(*center),
        _ => Err(RelationError::Unsuited {
            kind: KIND.name(),
            member: i,
            what: format!("shape (it has no `{feature}` end)"),
        }),
    };
    Ok((end(Feature::Top)? - end(Feature::Bottom)?).norm())
}

pub(super) fn residuals<T: Real>(m: &[Member<'_, T>]) -> Result<Vec<T>, RelationError> {
    let (l1, l2) = (length(m, 0)?, length(m, 1)?);
    Ok(vec![(l1 - l2) / (l1 + l2)])
}

pub(super) fn holds(m: &[Member<'_, f64>], settings: &InferenceSettings) -> bool {
    let (Ok(l1), Ok(l2)) = (length(m, 0), length(m, 1)) else {
        return false;
    };
    settings.same_size(l1, l2, settings.length)
}

/// Whether the two members' lengths are one within what their strokes pin: `spread`
/// holds each member's one-standard-deviation error of its length, relative to it (as
/// the snap's fit leaves it; infinite where the strokes do not pin it), and the
/// difference must lie within [`super::evidence::NOISE_ERRORS`] combined deviations.
/// False where a member has no two ends, or no spread is known (0).
pub(super) fn within_spread(m: &[Member<'_, f64>], spread: [f64; 2]) -> bool {
    let (Ok(l1), Ok(l2)) = (length(m, 0), length(m, 1)) else {
        return false;
    };
    if spread.iter().any(|s| s.is_nan() || *s <= 0.0) {
        return false;
    }
    let deviation = (spread[0] * l1).hypot(spread[1] * l2);
    (l1 - l2).abs() <= super::evidence::NOISE_ERRORS * deviation
}

/// Whether [`within_spread`] can tell the members' lengths apart at all: its window
/// ([`super::evidence::NOISE_ERRORS`] combined deviations) is narrower than
/// [`UNINFORMATIVE`] of the longer length. A window wider than that takes any two
/// lengths of one order as one: it says nothing of a designer meaning them equal.
pub(super) fn informative(m: &[Member<'_, f64>], spread: [f64; 2]) -> bool {
    let (Ok(l1), Ok(l2)) = (length(m, 0), length(m, 1)) else {
        return false;
    };
    let deviation = (spread[0] * l1).hypot(spread[1] * l2);
    super::evidence::NOISE_ERRORS * deviation < UNINFORMATIVE * l1.max(l2)
}

/// The widest window, relative to the longer length, within which lengths the strokes
/// leave open are still told apart ([`informative`]).
const UNINFORMATIVE: f64 = 0.5;

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::testing::{features, invariant_psi};
    use super::super::{holds, InferenceSettings, Member, RelationKind};
    use crate::primitive::{Cylinder, Primitive, Sphere};

    #[test]
    fn lengths_the_strokes_leave_open_may_be_one() {
        let leg = |l: f64| {
            features(&Primitive::Cylinder(Cylinder {
                center: DVec3::ZERO,
                axis: DVec3::Y,
                length: l,
                radius: 2.0,
            }))
        };
        let (a, b) = (leg(100.0), leg(120.0));
        let m = [
            Member {
                features: &a,
                feature: None,
            },
            Member {
                features: &b,
                feature: None,
            },
        ];
        // 20 apart: within two deviations of ±10 % each, not of ±2 %.
        assert!(super::within_spread(&m, [0.1, 0.1]));
        assert!(!super::within_spread(&m, [0.02, 0.02]));
        assert!(super::within_spread(&m, [f64::INFINITY, 0.02]));
        assert!(!super::within_spread(&m, [0.0, 0.5]));
        // ±10 % each tells lengths a quarter apart; a length not pinned tells none.
        assert!(super::informative(&m, [0.1, 0.1]));
        assert!(!super::informative(&m, [f64::INFINITY, 0.02]));
        assert!(!super::informative(&m, [0.2, 0.2]));
    }

    #[test]
    fn legs_of_one_length() {
        let k = RelationKind::EqualLength;
        let leg = |x: f64, l: f64| {
            Primitive::Cylinder(Cylinder {
                center: DVec3::X * x,
                axis: DVec3::new(0.0, 0.9, 0.44).normalize(),
                length: l,
                radius: 2.0,
            })
        };
        let (a, b, c) = (leg(0.0, 60.0), leg(30.0, 60.0), leg(30.0, 70.0));
        assert!(invariant_psi(k, &[(&a, None), (&b, None)]) < 1e-12);
        assert!(invariant_psi(k, &[(&a, None), (&c, None)]) > 0.07);
        let s = InferenceSettings::default();
        let (fa, fb, fc) = (features(&a), features(&b), features(&c));
        let m = |f| {
            [
                Member {
                    features: &fa,
                    feature: None,
                },
                Member {
                    features: f,
                    feature: None,
                },
            ]
        };
        assert!(holds(k, &m(&fb), &s));
        assert!(!holds(k, &m(&fc), &s));
        let ball = features(&Primitive::Sphere(Sphere {
            center: DVec3::ZERO,
            radius: 3.0,
        }));
        assert!(!holds(k, &m(&ball), &s));
    }
}
