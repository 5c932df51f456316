//! Directions the drawing pins in the view plane only.
//!
//! A drawing shows where an axis points across the paper exactly, but how far it leans
//! towards or away from the viewer (its depth component, the *tilt*) only through its end
//! ellipses: an end of radius r drawn with noise σ gives its normal's depth component
//! (the ellipse's minor-to-major ratio) to about ±2σ/r, and a part whose ends are not
//! drawn at all (a stem between a bowl and a foot, a tube whose ends are hidden in what
//! it joins) does not give it at all. A snap still picks one tilt for such a part, and
//! two parts a designer drew parallel can come out tens of degrees apart in depth while
//! they agree within a degree on the paper.
//!
//! So parallel and coaxial candidates that fail in 3D are tested once more with each
//! member's tilt free to move within its slack ([`slack`]): the projected directions
//! must agree as they are (the drawing shows them), and the depth components must be
//! reconcilable within what the ends show. Orthogonal likewise (`square_within`): a
//! thin branch's small end ellipse leaves its depth open by tens of degrees, so a T
//! drawn square comes out 10–20° off in 3D. A candidate that holds only this way is at
//! the edge of its thresholds, so inference makes it a suggestion at most; accepted, the
//! solve settles the depth the drawing left open. One exception: repeated parts on one
//! line across a part both join (a menorah's paired arms) are built coaxial, and are
//! weighed by how closely they hold with their tilts reconciled
//! (`infer::Inference::paired_across`).

use glam::{DVec2, DVec3};

use super::{
    chosen, circle, coaxial, frame, InferenceSettings, Member, RelationKind, MIN_PROJECTED_AXIS,
};

/// The slack of a tilt the drawing does not pin at all: any depth component, from −1
/// to 1, is within reach of any other.
pub const FREE: f64 = 2.0;

/// The slack of the tilt of an axis whose drawn ends have `radius` (the largest drawn)
/// and whose snap lies `rms` from its strokes (both in sketch units): twice the noise
/// relative to the radius, as an ellipse's minor axis is known to about the noise. No
/// ends drawn (`radius` `None`) leaves it [`FREE`].
pub fn slack(radius: Option<f64>, rms: f64) -> f64 {
    match radius {
        Some(r) if r > 0.0 && rms.is_finite() => {
            (super::evidence::NOISE_ERRORS * rms.max(0.0) / r).min(FREE)
        }
        Some(_) => 0.0,
        None => FREE,
    }
}

/// Whether a relation of `kind` between two members holds once each member's tilt may
/// move within its `slack` (parallel, coaxial and orthogonal; false for every other
/// kind and where a direction is seen nearly end-on).
pub(super) fn holds(
    kind: RelationKind,
    m: &[Member<'_, f64>],
    settings: &InferenceSettings,
    slack: [f64; 2],
) -> bool {
    if m.len() != 2 || slack.iter().all(|s| *s <= 0.0) {
        return false;
    }
    match kind {
        RelationKind::Parallel => {
            let (Ok(f1), Ok(f2)) = (chosen(kind, m, 0), chosen(kind, m, 1)) else {
                return false;
            };
            let ((_, n1, _), (_, n2, _)) = (frame(f1), frame(f2));
            parallel_within(n1.to_dvec3(), n2.to_dvec3(), slack, settings)
        }
        RelationKind::Coaxial => {
            let (Ok((c1, n1, r1)), Ok((c2, n2, r2))) = (circle(kind, m, 0), circle(kind, m, 1))
            else {
                return false;
            };
            parallel_within(n1.to_dvec3(), n2.to_dvec3(), slack, settings)
                && coaxial::on_one_line(c1, n1, c2, n2, settings.position_tolerance(r1 + r2))
        }
        RelationKind::Orthogonal => {
            let (Ok(f1), Ok(f2)) = (chosen(kind, m, 0), chosen(kind, m, 1)) else {
                return false;
            };
            let ((_, n1, _), (_, n2, _)) = (frame(f1), frame(f2));
            square_within(n1.to_dvec3(), n2.to_dvec3(), slack)
                .is_some_and(|cos| cos <= settings.sin_angle())
        }
        _ => false,
    }
}

/// Whether unit directions `n1` and `n2` are parallel within the settings' angle once
/// their tilts move within `slack` ([`retilted`]).
fn parallel_within(n1: DVec3, n2: DVec3, slack: [f64; 2], settings: &InferenceSettings) -> bool {
    retilted(n1, n2, slack).is_some_and(|(a, b)| a.cross(b).length() <= settings.sin_angle())
}

/// Steps of the first direction's tilt over its range in [`square_within`]: at most
/// π / 128 apart, so that the smallest |cos| found is within about 0.012 of the true
/// one (under a tenth of the sine of the default angle threshold, 0.14).
const SQUARE_STEPS: usize = 128;

/// The smallest |cos| of the angle between unit directions `n1` and `n2` once their
/// depth components move within `slack` each (and within [−1, 1]), their projected
/// directions kept: 0 where some pair of tilts makes them square. `None` where either
/// is seen within about 17° of end-on (its projected direction is then the noise's).
///
/// With the tilts as angles (z = sin φ) the cosine is cos φ₁ cos φ₂ (p̂₁·p̂₂) +
/// sin φ₁ sin φ₂, continuous over the rectangle of the two ranges: where it takes both
/// signs it is 0 somewhere. For a fixed φ₁ it is a sinusoid in φ₂, whose smallest
/// magnitude over an interval shorter than π without a change of sign lies at an end;
/// φ₁ is stepped over its range ([`SQUARE_STEPS`]).
fn square_within(n1: DVec3, n2: DVec3, slack: [f64; 2]) -> Option<f64> {
    let (p1, p2) = (n1.truncate(), n2.truncate());
    if p1.length() < MIN_PROJECTED_AXIS || p2.length() < MIN_PROJECTED_AXIS {
        return None;
    }
    let across = p1.normalize().dot(p2.normalize());
    let range = |z: f64, s: f64| {
        let s = s.max(0.0);
        (
            (z - s).clamp(-1.0, 1.0).asin(),
            (z + s).clamp(-1.0, 1.0).asin(),
        )
    };
    let (a, b) = (range(n1.z, slack[0]), range(n2.z, slack[1]));
    let cos = |phi1: f64, phi2: f64| phi1.cos() * phi2.cos() * across + phi1.sin() * phi2.sin();
    let (mut lowest, mut highest, mut smallest) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..=SQUARE_STEPS {
        let phi1 = a.0 + (a.1 - a.0) * k as f64 / SQUARE_STEPS as f64;
        for phi2 in [b.0, b.1] {
            let c = cos(phi1, phi2);
            lowest = lowest.min(c);
            highest = highest.max(c);
            smallest = smallest.min(c.abs());
        }
    }
    Some(if lowest <= 0.0 && highest >= 0.0 {
        0.0
    } else {
        smallest
    })
}

/// The directions `n1` and `n2` (unit) with their depth components moved within
/// `slack` each (and within [−1, 1]) as near to one another as they can come, their
/// projected directions kept: a common depth component where the ranges meet (the one
/// nearest the middle of the two), else the ends of the ranges that face each other.
/// `n2` is turned round where it points against `n1` on the paper (parallel has no
/// sign). `None` where either is seen within about 17° of end-on: its projected
/// direction is then the noise's.
fn retilted(n1: DVec3, n2: DVec3, slack: [f64; 2]) -> Option<(DVec3, DVec3)> {
    let (p1, p2) = (n1.truncate(), n2.truncate());
    if p1.length() < MIN_PROJECTED_AXIS || p2.length() < MIN_PROJECTED_AXIS {
        return None;
    }
    let n2 = if p1.dot(p2) < 0.0 { -n2 } else { n2 };
    let range = |z: f64, s: f64| ((z - s).max(-1.0), (z + s).min(1.0));
    let (a, b) = (range(n1.z, slack[0]), range(n2.z, slack[1]));
    let (z1, z2) = if a.0 <= b.1 && b.0 <= a.1 {
        let z = (0.5 * (n1.z + n2.z)).clamp(a.0.max(b.0), a.1.min(b.1));
        (z, z)
    } else if a.1 < b.0 {
        (a.1, b.0)
    } else {
        (a.0, b.1)
    };
    let tilt = |p: DVec2, z: f64| (p.normalize() * (1.0 - z * z).max(0.0).sqrt()).extend(z);
    Some((tilt(n1.truncate(), z1), tilt(n2.truncate(), z2)))
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::testing::features;
    use super::super::{InferenceSettings, Member, RelationKind};
    use super::{holds, retilted, slack, square_within, FREE};
    use crate::primitive::{Feature, Primitive};

    fn cylinder(center: DVec3, axis: DVec3) -> Primitive {
        super::super::testing::cylinder(center, axis, 40.0, 5.0)
    }

    /// The axis leaning `lean` (radians) off the paper's up direction towards the viewer.
    fn up(lean: f64) -> DVec3 {
        DVec3::new(0.0, lean.cos(), lean.sin())
    }

    fn tops<'a>(
        a: &'a [crate::primitive::FeatureCurve<f64>],
        b: &'a [crate::primitive::FeatureCurve<f64>],
    ) -> [Member<'a, f64>; 2] {
        [
            Member {
                features: a,
                feature: Some(Feature::Top),
            },
            Member {
                features: b,
                feature: Some(Feature::Top),
            },
        ]
    }

    #[test]
    fn the_slack_follows_the_drawn_ends() {
        let near = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(near(slack(None, 1.0), FREE));
        assert!(near(slack(Some(20.0), 1.0), 0.1));
        assert!(near(slack(Some(1.0), 100.0), FREE));
        assert!(near(slack(Some(20.0), f64::NAN), 0.0));
    }

    #[test]
    fn tilts_meet_within_their_slack_and_not_beyond() {
        let (a, b) = (up(0.5), up(-0.2));
        // 40° apart in depth, one on the paper: free tilts meet, pinned ones do not.
        let (x, y) = retilted(a, b, [0.0, FREE]).expect("both seen from the side");
        assert!(x.cross(y).length() < 1e-12);
        assert!((x - a).length() < 1e-12, "the pinned one stays");
        let (x, y) = retilted(a, b, [0.05, 0.05]).expect("both seen from the side");
        assert!(x.cross(y).length() > 0.5);
        // An axis seen end-on says nothing about its direction on the paper.
        assert!(retilted(DVec3::Z, a, [FREE, FREE]).is_none());
        // Opposite on the paper is parallel too.
        let (x, y) = retilted(a, -up(0.45), [0.1, 0.0]).expect("seen from the side");
        assert!(x.cross(y).length() < 1e-12);
    }

    #[test]
    fn directions_are_square_for_some_tilts_within_their_slack_and_not_beyond() {
        // Square in 3D: (1, 0, 0.6) and (−0.3, 1, 0.5); the second drawn 0.7 shallower.
        let a = DVec3::new(1.0, 0.0, 0.6).normalize();
        let square = DVec3::new(-0.3, 1.0, 0.5).normalize();
        let b = DVec3::new(-0.3, 1.0, -0.2).normalize();
        let off = square_within(a, b, [0.0; 2]).expect("both seen from the side");
        assert!((off - a.dot(b).abs()).abs() < 1e-12, "pinned: as drawn");
        assert!(off > 0.3);
        let depth_gap = square.z - b.z;
        assert!(square_within(a, b, [0.0, depth_gap + 0.01]) == Some(0.0));
        let short = square_within(a, b, [0.0, depth_gap - 0.1]).expect("seen from the side");
        assert!(short > 0.02 && short < off, "{short}");
        // Either member's slack will do; the first one's range is stepped.
        let first = square_within(b, a, [depth_gap + 0.01, 0.0]).expect("seen from the side");
        assert!(first < 0.013, "{first}");
        // Parallel on the paper, both in its plane: no tilt within 0.3 makes them square.
        let flat = DVec3::X;
        let beside = DVec3::new(1.0, 0.0, 0.1).normalize();
        assert!(square_within(flat, beside, [0.3, 0.3]).expect("seen from the side") > 0.7);
        assert!(
            square_within(DVec3::Z, a, [FREE, FREE]).is_none(),
            "seen end-on"
        );
    }

    #[test]
    fn parallel_and_coaxial_on_the_paper_with_free_depth() {
        let s = InferenceSettings::default();
        let lower = features(&cylinder(DVec3::ZERO, up(0.5)));
        let upper = features(&cylinder(DVec3::new(0.0, 40.0, 0.0), up(-0.2)));
        let beside = features(&cylinder(DVec3::new(30.0, 0.0, 0.0), up(-0.2)));
        let turned = features(&cylinder(
            DVec3::new(0.0, 40.0, 0.0),
            DVec3::new(0.3, 1.0, -0.2),
        ));
        let k = RelationKind::Coaxial;
        assert!(!super::super::holds(k, &tops(&lower, &upper), &s));
        assert!(holds(k, &tops(&lower, &upper), &s, [0.0, FREE]));
        assert!(!holds(k, &tops(&lower, &upper), &s, [0.05, 0.05]));
        // Beside it: parallel, not on its axis.
        assert!(!holds(k, &tops(&lower, &beside), &s, [0.0, FREE]));
        assert!(holds(
            RelationKind::Parallel,
            &tops(&lower, &beside),
            &s,
            [0.0, FREE]
        ));
        // Turned on the paper: no depth makes it parallel.
        assert!(!holds(
            RelationKind::Parallel,
            &tops(&lower, &turned),
            &s,
            [FREE, FREE]
        ));
        // Other kinds are not judged here.
        assert!(!holds(
            RelationKind::Concentric,
            &tops(&lower, &upper),
            &s,
            [FREE, FREE]
        ));
    }
}
