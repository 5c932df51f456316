//! Why a relation was inferred, and how sure inference is of it.
//!
//! A relation that nearly holds in a snapped model may be meant or may be chance: two
//! legs of one table are parallel by design, a lamp's stem and its shade have nearly
//! equal lengths by accident. Inference weighs four pieces of evidence, none of them a
//! constant tuned to one drawing:
//!
//! - **attachment** ([`Contact`]): how the parts meet in the drawing (an end on another
//!   part's side, on its end face, on its end, …) and how many contacts apart they are in
//!   the model's contact graph ([`Evidence::hops`]). Parallel, orthogonal and coaxial
//!   between attached parts are common design; between parts far apart they are chance;
//! - **repetition** ([`Evidence::repeated`]): parts of one kind and size in one object,
//!   not stacked on each other (legs, prongs, arms, candles), are meant alike: equal,
//!   parallel, of one radius;
//! - **closeness** ([`Evidence::closeness`]): how far inside its thresholds the relation
//!   holds, as a fraction of them, and how that compares with the drawing's own noise
//!   for these parts ([`Evidence::noise`]: their fit RMS relative to their size). A
//!   relation within the noise is as exact as the drawing can show; one at the edge of a
//!   threshold much wider than the noise is likely not meant;
//! - a **prior** per kind and situation ([`prior`]).
//!
//! [`confidence`] combines them into one number in [0, 1]; the settings' tiers
//! ([`InferenceSettings::hard_confidence`], [`InferenceSettings::suggest_confidence`])
//! make a candidate hard, a suggestion, or drop it.
//!
//! [`InferenceSettings::hard_confidence`]: super::InferenceSettings::hard_confidence
//! [`InferenceSettings::suggest_confidence`]: super::InferenceSettings::suggest_confidence

use serde::{Deserialize, Serialize};

use super::RelationKind;

/// How two parts meet in the drawing (their projected outlines; the drawing shows no
/// depth).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Contact {
    /// An end of one sits on the other's end, centres together: a stack.
    EndOnEnd,
    /// An end of one lies inside the other's end face or box face: a leg under a table
    /// top, a stud on a brick, a pipe on a box.
    EndOnFace,
    /// An end of one lies on the other's side: a T, an L, a handle on a mug.
    EndOnSide,
    /// An end of one sits on a sphere's outline: a tube on a ball.
    EndOnSphere,
    /// The outlines overlap or touch with no end at the other: parts crossing (a valve
    /// through a trumpet's body), boxes side by side, or one drawn behind the other.
    Crossing,
    /// The outlines do not meet.
    Apart,
}

impl Contact {
    /// Whether an end of one part sits on the other (every contact but crossing and
    /// apart): the joints a designer builds.
    pub fn is_joint(self) -> bool {
        !matches!(self, Self::Crossing | Self::Apart)
    }

    /// The name used in files and messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::EndOnEnd => "end_on_end",
            Self::EndOnFace => "end_on_face",
            Self::EndOnSide => "end_on_side",
            Self::EndOnSphere => "end_on_sphere",
            Self::Crossing => "crossing",
            Self::Apart => "apart",
        }
    }

    /// In words, for people: "an end on the other's side".
    pub fn describe(self) -> &'static str {
        match self {
            Self::EndOnEnd => "stacked end on end",
            Self::EndOnFace => "an end sits on the other's face",
            Self::EndOnSide => "an end meets the other's side (T, L or handle joint)",
            Self::EndOnSphere => "an end sits on the ball",
            Self::Crossing => "their outlines cross",
            Self::Apart => "not touching",
        }
    }
}

/// The evidence behind an inferred relation (written into the model file beside its
/// confidence).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Evidence {
    /// How the members meet in the drawing (for three members, the first two).
    pub contact: Contact,
    /// How many contacts apart the members are in the contact graph (1: they touch;
    /// 2: both touch one part; 0: one part with itself).
    pub hops: u32,
    /// Whether the members repeat one another: one kind, one size, in one object but not
    /// stacked on each other (legs, prongs, candles).
    pub repeated: bool,
    /// Whether the members lie on opposite sides of a part both join, on one line
    /// across it: arms out of both sides of a stem, pipes on both sides of a valve
    /// (written only when true).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub across: bool,
    /// Whether the members are branches of one part: of one kind, not joined to each
    /// other, each joined to that part with an end in the same way (a menorah's arms on
    /// its stem, pipes on one box, tubes on one ball) (written only when true).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub branches: bool,
    /// How far inside its thresholds the relation holds, as a fraction of them (0
    /// exact, 1 at the edge); above 1 for a part standing on a face drawn leaning
    /// ([`super::standing`]): its angle as a multiple of the angle threshold.
    pub closeness: f64,
    /// The drawing's noise for these parts: their largest fit RMS relative to their
    /// size, in the relative units of the thresholds.
    pub noise: f64,
    /// The prior of this kind in this situation ([`prior`]).
    pub prior: f64,
}

impl Evidence {
    /// The evidence in words, for a tooltip: "legs alike; an end meets the other's side;
    /// holds to 12 % of its threshold (within the drawing's noise)".
    pub fn describe(&self, kind: RelationKind) -> String {
        let mut parts = Vec::new();
        if self.repeated {
            parts.push("repeated parts of one size".to_owned());
        }
        parts.push(match self.hops {
            0 => "one part".to_owned(),
            1 => self.contact.describe().to_owned(),
            n => format!("{n} contacts apart"),
        });
        if self.across {
            parts.push("on both sides of a part they both join".to_owned());
        }
        if self.branches {
            parts.push("branches of one part".to_owned());
        }
        let within = if self.closeness <= 0.0 {
            "exactly".to_owned()
        } else if self.closeness > 1.0 {
            // A part standing on a face, drawn leaning (`super::standing`).
            return format!(
                "{}; {} only {:.1}× past its threshold: the drawing leans it",
                parts.join("; "),
                kind.name().replace('_', " "),
                self.closeness
            );
        } else {
            format!("to {:.0} % of its threshold", 100.0 * self.closeness)
        };
        parts.push(format!("{} holds {within}", kind.name().replace('_', " ")));
        parts.join("; ")
    }
}

/// The prior of a relation of `kind` between parts meeting as `contact`, `hops` contacts
/// apart, repeated or not, and `across` a part both join or not: how often such a
/// relation is meant, before looking at how closely it holds. Attached parts are
/// parallel, orthogonal and coaxial by design; equal lengths and radii are meant between
/// repeated parts and are most often chance elsewhere. Two parts on one line across a
/// part both join (arms out of both sides of a stem) are coaxial as surely as attached
/// ones: lined up on the paper across it by chance, they would have to be offset along
/// the view only. Branches of one part (`branches`) are of one radius by design as
/// often as not (their same radius is weighed at the hard tier exactly).
#[expect(
    clippy::match_same_arms,
    reason = "a table of priors: one row per kind and situation, read top to bottom"
)]
pub fn prior(
    kind: RelationKind,
    contact: Contact,
    hops: u32,
    repeated: bool,
    across: bool,
    branches: bool,
) -> f64 {
    // A joint (an end on the other part) is designed; outlines that merely cross may be
    // parts drawn one behind the other, and count no more than parts apart.
    let joint = hops <= 1 && contact.is_joint();
    if hops > super::infer::MAX_HOPS {
        // Only alike parts are compared this far apart: repetition alone, across the
        // object, is worth a suggestion; their sizes, a hard relation where the drawing
        // shows them exact (within its noise).
        return match kind {
            _ if !repeated => 0.0,
            RelationKind::SameRadius | RelationKind::EqualLength => FAR_REPEATED_SIZE,
            _ => FAR_REPEATED,
        };
    }
    match kind {
        RelationKind::Parallel if repeated => 0.9,
        RelationKind::Parallel if joint => 0.85,
        RelationKind::Parallel if hops == 2 => 0.75,
        RelationKind::Parallel => 0.6,
        RelationKind::Coaxial if joint || across => 0.9,
        RelationKind::Coaxial if hops == 2 => 0.6,
        RelationKind::Coaxial => 0.45,
        // Outlines crossing at a right angle with no end on the other are most often
        // parts drawn one behind the other.
        RelationKind::Orthogonal if joint => 0.85,
        // Alike parts on one hub (tubes on a ball, spokes): square is a common layout,
        // not a sure one.
        RelationKind::Orthogonal if repeated => HUB_SQUARE,
        RelationKind::Orthogonal => 0.2,
        RelationKind::Concentric | RelationKind::OnSphere if joint => 0.9,
        RelationKind::Concentric | RelationKind::OnSphere => 0.4,
        RelationKind::Coplanar if joint => 0.85,
        RelationKind::Coplanar if hops == 2 => 0.55,
        RelationKind::Coplanar => 0.35,
        RelationKind::SameRadius | RelationKind::EqualLength if repeated => 0.9,
        RelationKind::SameRadius if branches => BRANCH_RADIUS,
        RelationKind::SameRadius if joint => 0.55,
        RelationKind::SameRadius | RelationKind::EqualLength => 0.4,
        RelationKind::CollinearCenters => 0.4,
    }
}

/// The prior of a relation between alike parts further apart than
/// [`super::infer::MAX_HOPS`] joints, but of their sizes: under the hard tier, over the
/// suggestion tier. Where such parts point, and where they lie, is carried by the parts
/// between them (a chair turned round the table), and made hard at this distance it
/// overconstrained the relations bench's scenes (5 more switched off at 200 parts).
const FAR_REPEATED: f64 = 0.5;

/// The prior of same radius and equal length between alike parts further apart than
/// [`super::infer::MAX_HOPS`] joints: the default hard tier
/// ([`super::InferenceSettings::hard_confidence`]) exactly, so that [`confidence`] makes
/// it hard only where it holds within the drawing's noise (candles across a menorah
/// drawn of one radius as closely as the drawing can show), and a suggestion anywhere
/// else inside its threshold: alike parts are copies, of one size by design. Measured on
/// the synthetic assemblies at 40 cases per kind (50 same-radius suggestions of this
/// kind, 49 right; 41 equal lengths, 40 right) and the shared sketches (4 more intended
/// hard relations on the menorah, none unwanted).
const FAR_REPEATED_SIZE: f64 = 0.6;

/// The prior of same radius between branches of one part that do not repeat each other
/// (a menorah's arms of different lengths, pipes of one manifold): the default hard
/// tier ([`super::InferenceSettings::hard_confidence`]) exactly, as for alike parts far
/// apart ([`FAR_REPEATED_SIZE`]), so that it is hard where the drawing shows the radii
/// equal within its noise and a suggestion elsewhere inside the threshold. Branches of
/// one hub are cut from one stock more often than not; two parts that merely lie near
/// one another are not ([`prior`]'s 0.4).
const BRANCH_RADIUS: f64 = 0.6;

/// The prior of orthogonal between alike parts joined to one same part (inference
/// proposes it between those only when they do not touch each other): a ball's tubes, a
/// hub's spokes. Their directions are as often at other angles (a star of five, legs
/// splayed under a stool), so even exact it is worth a suggestion, never a hard
/// relation by the default tiers.
const HUB_SQUARE: f64 = 0.55;

/// The relative error a drawing of this `noise` leaves a relation that holds exactly
/// in the design: twice the noise.
pub(crate) const NOISE_ERRORS: f64 = 2.0;

/// The confidence in [0, 1] of a relation with this evidence, where `threshold` is its
/// kind's threshold in the relative units of [`Evidence::noise`] (sin of the angle, or
/// the relative distance).
///
/// The prior is scaled by how closely the relation holds: fully within the drawing's
/// noise (error ≤ 2 × noise), and falling linearly to half at the threshold's edge. A
/// relation at the edge of a wide threshold on a clean drawing is half as likely as one
/// the drawing shows exact.
pub fn confidence(evidence: &Evidence, threshold: f64) -> f64 {
    let error = evidence.closeness * threshold;
    let tolerated = (NOISE_ERRORS * evidence.noise).min(threshold);
    let fit = if error <= tolerated {
        1.0
    } else {
        (1.0 - (error - tolerated) / (threshold - tolerated).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0)
    };
    (evidence.prior * (0.5 + 0.5 * fit)).clamp(0.0, 1.0)
}

/// An inferred relation's confidence and evidence.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Inferred {
    /// The confidence in [0, 1].
    pub confidence: f64,
    /// What it rests on.
    pub evidence: Evidence,
}

#[cfg(test)]
mod tests {
    use super::{confidence, prior, Contact, Evidence};
    use crate::relation::RelationKind;

    fn evidence(kind: RelationKind, contact: Contact, hops: u32, closeness: f64) -> Evidence {
        Evidence {
            contact,
            hops,
            repeated: false,
            closeness,
            noise: 0.005,
            across: false,
            branches: false,
            prior: prior(kind, contact, hops, false, false, false),
        }
    }

    #[test]
    fn attached_and_exact_beats_apart_and_rough() {
        let k = RelationKind::Parallel;
        let attached = confidence(&evidence(k, Contact::EndOnSide, 1, 0.05), 0.14);
        let apart = confidence(&evidence(k, Contact::Apart, 3, 0.9), 0.14);
        assert!(attached > 0.8, "{attached}");
        assert!(apart < 0.4, "{apart}");
    }

    #[test]
    fn within_the_noise_counts_as_exact() {
        let k = RelationKind::Coaxial;
        let mut e = evidence(k, Contact::EndOnEnd, 1, 0.5);
        e.noise = 0.05; // an error of 0.05 in a threshold of 0.1 is within 2 × noise
        assert!((confidence(&e, 0.1) - e.prior).abs() < 1e-12);
        e.noise = 0.001;
        assert!(confidence(&e, 0.1) < e.prior);
    }

    #[test]
    fn coincidental_sizes_are_weak_and_repeated_ones_strong() {
        let k = RelationKind::EqualLength;
        let lone = prior(k, Contact::EndOnEnd, 1, false, false, false);
        let legs = prior(k, Contact::Apart, 2, true, false, false);
        assert!(lone < 0.5 && legs > 0.8);
    }

    #[test]
    fn alike_parts_far_apart_are_hard_only_where_the_drawing_shows_them_exact() {
        let hard = crate::relation::InferenceSettings::default().hard_confidence();
        let k = RelationKind::SameRadius;
        let mut far = evidence(k, Contact::Apart, super::super::infer::MAX_HOPS + 1, 0.05);
        far.prior = prior(k, Contact::Apart, far.hops, true, false, false);
        assert!(confidence(&far, 0.05) >= hard, "{far:?}");
        far.closeness = 0.5;
        let loose = confidence(&far, 0.05);
        assert!(loose < hard && loose > 0.3, "{loose}");
        // Where they point is carried by the parts between them: a suggestion even
        // exact.
        let mut parallel = far.clone();
        parallel.closeness = 0.0;
        parallel.prior = prior(
            RelationKind::Parallel,
            Contact::Apart,
            far.hops,
            true,
            false,
            false,
        );
        assert!(confidence(&parallel, 0.14) < hard, "{parallel:?}");
        // Parts that do not repeat each other are not compared this far apart.
        assert!(prior(k, Contact::Apart, far.hops, false, false, false) <= 0.0);
    }

    #[test]
    fn across_is_written_only_when_true_and_read_when_missing() {
        let mut e = evidence(RelationKind::Coaxial, Contact::Apart, 2, 0.3);
        let plain = serde_json::to_string(&e).expect("writes");
        assert!(!plain.contains("across"), "{plain}");
        e.across = true;
        let across = serde_json::to_string(&e).expect("writes");
        assert!(across.contains(r#""across":true"#), "{across}");
        let back: Evidence = serde_json::from_str(&across).expect("reads");
        assert_eq!(back, e);
        let older: Evidence = serde_json::from_str(&plain).expect("reads");
        assert!(!older.across);
    }

    #[test]
    fn parts_across_one_they_both_join_are_coaxial_like_attached_ones() {
        let k = RelationKind::Coaxial;
        let apart = prior(k, Contact::Apart, 2, true, false, false);
        let across = prior(k, Contact::Apart, 2, true, true, false);
        let joint = prior(k, Contact::EndOnEnd, 1, false, false, false);
        assert!(apart < 0.7 && (across - joint).abs() < 1e-12);
        // Across a part changes nothing but the axis line.
        let l = RelationKind::EqualLength;
        let (lone, across) = (
            prior(l, Contact::Apart, 2, false, false, false),
            prior(l, Contact::Apart, 2, false, true, false),
        );
        assert!((lone - across).abs() < 1e-12);
    }
}
