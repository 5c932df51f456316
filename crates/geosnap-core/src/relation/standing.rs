//! Parts standing on a face, drawn leaning.
//!
//! An end drawn inside another part's face (a stud on a brick, a leg under a table top,
//! a candle on a dish) is, in made things, nearly always square to that face: the part
//! stands up from it. Freehand drawings often show such a part leaning all the same. Its
//! end ellipse is drawn slanted along the face's edges rather than across the view, or
//! squashed flatter than the face's, and the snap, which must honour that ellipse, leans
//! the part by tens of degrees while its silhouettes stand up straight. Inference then
//! finds neither "stands upright on it" nor "sits on it": both ask for the end's normal
//! along the face's within the angle threshold.
//!
//! So where a part's end sits on another's face ([`Contact::EndOnFace`]), and parallel
//! or coplanar does not hold between a direction of the part with ends and the other's
//! directions or faces, each is tested once more with the angle between them allowed up
//! to [`LEAN`] degrees: the part then leans nearer to standing up from the face than to
//! lying along it. Positions keep their thresholds (the end's centre must be drawn inside
//! the face). A candidate that holds only this way is beyond its thresholds: inference
//! keeps it as a suggestion at most (its `closeness` in the evidence is the lean as a
//! multiple of the angle threshold, above 1), which the user accepts with one click;
//! accepted, the solve stands the part up, and a part whose strokes that fits much worse
//! has it switched off and is told so, as for any relation.
//!
//! Boxes on boxes are left out: two boxes always have directions within about 55° of
//! each other, so any stacked pair would be offered as aligned.
//!
//! [`Contact::EndOnFace`]: super::evidence::Contact::EndOnFace

use super::InferenceSettings;

/// The largest angle (degrees) between a part's end and the face it sits on at which it
/// is still taken as meant standing on it: nearer the face's normal than its plane.
pub const LEAN: f64 = 45.0;

/// `settings` with the angle threshold widened to [`LEAN`] (never narrowed), positions,
/// radii and lengths as they are.
pub(super) fn settings(settings: &InferenceSettings) -> InferenceSettings {
    settings.with_angle(settings.angle_degrees().max(LEAN))
}

/// The closeness reported for a candidate that holds at `fraction` of the widened
/// thresholds ([`settings`]): the lean as a multiple of the ordinary angle threshold
/// (above 1 for a lean beyond it).
pub(super) fn closeness(fraction: f64, settings: &InferenceSettings) -> f64 {
    fraction * LEAN / settings.angle_degrees()
}

#[cfg(test)]
mod tests {
    use super::{closeness, settings, LEAN};
    use crate::relation::InferenceSettings;

    #[test]
    fn only_the_angle_widens() {
        let s = InferenceSettings::default();
        let wide = settings(&s);
        assert!((wide.angle_degrees() - LEAN).abs() < 1e-6);
        assert!((wide.distance() - s.distance()).abs() < 1e-15);
        assert!((wide.radius() - s.radius()).abs() < 1e-15);
        assert!((wide.length() - s.length()).abs() < 1e-15);
        let reported = closeness(1.0, &s);
        assert!(reported > 1.0, "{reported}");
    }
}
