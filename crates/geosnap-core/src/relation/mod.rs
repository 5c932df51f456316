//! Geosemantic relations between primitives: what each kind means, how it is recognised
//! in a snapped model, and the residual equations ψ_g = 0 that make it hold exactly.
//!
//! A relation refers to its members through their feature curves ([`Feature`]: an end
//! circle, a sphere's outline, a box face): a [`Member`] is one primitive's features with
//! the one the relation uses. Every kind lives in its own file
//! with
//! - its **residuals**, written once over [`Real`] so they serve plain numbers and the
//!   solver's expressions alike, and scale-free: directions are unit normals, distances are
//!   divided by the sizes of the features involved, so a relation means the same for a
//!   thimble and a silo, and ‖ψ‖ does not change under a rigid motion or a uniform scale of
//!   the whole model;
//! - its **test** ([`holds`]), deciding whether a snapped model nearly satisfies it, with
//!   thresholds from [`InferenceSettings`] (angles in degrees, distances relative to the
//!   sizes involved);
//! - tests of both.
//!
//! | kind | members | residuals |
//! |---|---|---|
//! | [`parallel`] | 2 directions (circle or face normals) | n₁ × n₂ |
//! | [`orthogonal`] | 2 directions | n₁ · n₂ |
//! | [`coaxial`] | 2 circles | n₁ × n₂, (c₂ − c₁) × n₁ / s |
//! | [`concentric`] | 2 circles | (c₂ − c₁) / s |
//! | [`coplanar`] | 2 circles or faces | n₁ × n₂, (c₂ − c₁) · n₁ / s |
//! | [`collinear_centers`] | 3 circles or faces | (c₂ − c₁) × (c₃ − c₁) / s² |
//! | [`same_radius`] | 2 circles | (r₁ − r₂) / s |
//! | [`equal_length`] | 2 solids with `bottom` and `top` ends | (ℓ₁ − ℓ₂) / (ℓ₁ + ℓ₂) |
//! | [`on_sphere`] | a sphere's outline, a circle | (‖c − C‖ − R) / s, n × (c − C) / s |
//!
//! s is the sum of the features' sizes (a circle's radius, a face's larger half extent).

pub mod coaxial;
pub mod collinear_centers;
pub mod concentric;
pub mod contact;
pub mod coplanar;
pub mod equal_length;
pub mod evidence;
pub mod infer;
pub mod on_sphere;
pub mod orthogonal;
pub mod parallel;
pub mod same_radius;
pub mod standing;
pub mod tilt;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::ad::{Real, Vec3};
use crate::primitive::{Feature, FeatureCurve, FeatureGeometry};
use crate::solve::SettingsError;

/// The least length of a projected unit direction for the drawing to show which way it
/// points in the view plane (an axis within about 17° of the view does not): ends on
/// one projected axis, directions compared in the view plane.
const MIN_PROJECTED_AXIS: f64 = 0.3;

/// The kinds of relation, named as in the model file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RelationKind {
    /// Two directions are parallel.
    Parallel,
    /// Two directions are perpendicular.
    Orthogonal,
    /// Two circles share their axis line.
    Coaxial,
    /// Two circles share their centre.
    Concentric,
    /// Two circles or faces lie in one plane.
    Coplanar,
    /// Three centres lie on one line.
    CollinearCenters,
    /// Two circles have the same radius.
    SameRadius,
    /// Two solids have the same length.
    EqualLength,
    /// A circle sits on a sphere, facing its centre.
    OnSphere,
}

impl RelationKind {
    /// Every kind.
    pub const ALL: [Self; 9] = [
        Self::Parallel,
        Self::Orthogonal,
        Self::Coaxial,
        Self::Concentric,
        Self::Coplanar,
        Self::CollinearCenters,
        Self::SameRadius,
        Self::EqualLength,
        Self::OnSphere,
    ];

    /// The name used in files and messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Parallel => "parallel",
            Self::Orthogonal => "orthogonal",
            Self::Coaxial => "coaxial",
            Self::Concentric => "concentric",
            Self::Coplanar => "coplanar",
            Self::CollinearCenters => "collinear_centers",
            Self::SameRadius => "same_radius",
            Self::EqualLength => "equal_length",
            Self::OnSphere => "on_sphere",
        }
    }

    /// The number of members.
    pub fn arity(self) -> usize {
        match self {
            Self::CollinearCenters => 3,
            _ => 2,
        }
    }
}

/// How a relation takes part in the global solve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Enforced exactly, as a constraint.
    #[default]
    Hard,
    /// A weighted term of the objective.
    Soft,
    /// Kept, but ignored.
    Off,
    /// Inferred with medium confidence: shown to the user with its evidence, not
    /// enforced until accepted (made [`Mode::Hard`]).
    Suggested,
}

impl Mode {
    /// Whether the global solve uses a relation in this mode (hard or soft).
    pub fn is_enforced(self) -> bool {
        matches!(self, Self::Hard | Self::Soft)
    }

    /// The name used in files and messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Hard => "hard",
            Self::Soft => "soft",
            Self::Off => "off",
            Self::Suggested => "suggested",
        }
    }
}

/// One member of a relation: a primitive's feature curves and the one the relation uses
/// (`None` for kinds about the whole solid, such as [`equal_length`]).
#[derive(Clone, Copy, Debug)]
pub struct Member<'a, T> {
    /// All feature curves of the primitive.
    pub features: &'a [FeatureCurve<T>],
    /// The feature the relation uses.
    pub feature: Option<Feature>,
}

impl<'a, T> Member<'a, T> {
    /// The geometry of `feature`, if the primitive has it.
    pub fn get(&self, feature: Feature) -> Option<&'a FeatureGeometry<T>> {
        self.features
            .iter()
            .find(|f| f.feature == feature)
            .map(|f| &f.geometry)
    }

    /// The feature the relation uses.
    pub fn chosen(&self) -> Option<&'a FeatureGeometry<T>> {
        self.get(self.feature?)
    }
}

/// Why residuals could not be written.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum RelationError {
    /// The relation has the wrong number of members.
    #[error("a {kind} relation needs {expected} members, not {got}")]
    Arity {
        /// The kind.
        kind: &'static str,
        /// Members it needs.
        expected: usize,
        /// Members it has.
        got: usize,
    },
    /// A member lacks the feature the kind needs, or has one of the wrong sort.
    #[error("a {kind} relation cannot use member {member}'s {what}")]
    Unsuited {
        /// The kind.
        kind: &'static str,
        /// Which member (0-based).
        member: usize,
        /// What is wrong with it.
        what: String,
    },
}

/// Thresholds of relation inference; every kind can be switched off. Made (and read)
/// through [`InferenceSettings::new`], which checks them; a missing field reads as its
/// default.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "InferenceFields")]
pub struct InferenceSettings {
    enabled: Vec<RelationKind>,
    angle_degrees: f64,
    distance: f64,
    radius: f64,
    length: f64,
    hard_confidence: f64,
    suggest_confidence: f64,
    /// The drawing's noise for the members of the relation in hand (sketch units; 0
    /// outside inference): set per candidate by [`InferenceSettings::for_members`].
    #[serde(skip_serializing)]
    noise: f64,
    /// How many times the position tolerance an end may lie from the other along their
    /// common axis (1 outside a joint): set per candidate.
    #[serde(skip_serializing)]
    axial_slack: f64,
}

/// The noise of a rough drawing widens a position threshold at most this many times:
/// beyond it, centres are visibly apart in any drawing of the parts' size.
const NOISE_WIDENING: f64 = 2.5;

/// The fields of [`InferenceSettings`] as stored, before they are checked.
#[derive(Deserialize)]
#[serde(default)]
struct InferenceFields {
    enabled: Vec<RelationKind>,
    angle_degrees: f64,
    distance: f64,
    radius: f64,
    length: f64,
    hard_confidence: f64,
    suggest_confidence: f64,
}

impl Default for InferenceFields {
    fn default() -> Self {
        let d = InferenceSettings::default();
        Self {
            enabled: d.enabled,
            angle_degrees: d.angle_degrees,
            distance: d.distance,
            radius: d.radius,
            length: d.length,
            hard_confidence: d.hard_confidence,
            suggest_confidence: d.suggest_confidence,
        }
    }
}

impl TryFrom<InferenceFields> for InferenceSettings {
    type Error = SettingsError;

    fn try_from(f: InferenceFields) -> Result<Self, SettingsError> {
        Self::new(f.enabled, f.angle_degrees, f.distance, f.radius, f.length)?
            .with_confidences(f.hard_confidence, f.suggest_confidence)
    }
}

impl Default for InferenceSettings {
    fn default() -> Self {
        Self {
            enabled: RelationKind::ALL.to_vec(),
            angle_degrees: 8.0,
            distance: 0.1,
            radius: 0.05,
            length: 0.03,
            hard_confidence: 0.6,
            suggest_confidence: 0.3,
            noise: 0.0,
            axial_slack: 1.0,
        }
    }
}

impl InferenceSettings {
    /// Settings inferring the kinds `enabled`, with the largest angle (degrees, in
    /// (0, 90)) between directions taken as parallel, or off a right angle for
    /// orthogonal; the largest offset between positions taken as the same (concentric
    /// centres, a point on an axis or in a plane) relative to the sum of the sizes
    /// involved; and the largest differences of radii and of lengths taken as the same,
    /// relative to their sums (each finite and above zero).
    ///
    /// # Errors
    ///
    /// [`SettingsError::OutOfRange`] for the angle, [`SettingsError::NotPositive`] for
    /// the others, naming the first bad value.
    pub fn new(
        enabled: Vec<RelationKind>,
        angle_degrees: f64,
        distance: f64,
        radius: f64,
        length: f64,
    ) -> Result<Self, SettingsError> {
        if !(angle_degrees > 0.0 && angle_degrees < 90.0) {
            return Err(SettingsError::OutOfRange {
                name: "angle_degrees",
                value: angle_degrees,
                range: "(0, 90)",
            });
        }
        for (name, value) in [
            ("distance", distance),
            ("radius", radius),
            ("length", length),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(SettingsError::NotPositive { name, value });
            }
        }
        let d = Self::default();
        Ok(Self {
            enabled,
            angle_degrees,
            distance,
            radius,
            length,
            ..d
        })
    }

    /// These settings with the confidence tiers of inferred relations: a candidate at
    /// `hard` or above becomes a hard relation, one at `suggest` or above a suggestion
    /// ([`Mode::Suggested`]), one below is not kept (see [`evidence`]). Both in [0, 1],
    /// `suggest` ≤ `hard`.
    ///
    /// # Errors
    ///
    /// [`SettingsError::OutOfRange`] naming the first bad value.
    pub fn with_confidences(self, hard: f64, suggest: f64) -> Result<Self, SettingsError> {
        if !(0.0..=1.0).contains(&hard) {
            return Err(SettingsError::OutOfRange {
                name: "hard_confidence",
                value: hard,
                range: "[0, 1]",
            });
        }
        if !(0.0..=hard).contains(&suggest) {
            return Err(SettingsError::OutOfRange {
                name: "suggest_confidence",
                value: suggest,
                range: "[0, hard_confidence]",
            });
        }
        Ok(Self {
            hard_confidence: hard,
            suggest_confidence: suggest,
            ..self
        })
    }

    /// The least confidence of an inferred relation made hard (default 0.6).
    pub fn hard_confidence(&self) -> f64 {
        self.hard_confidence
    }

    /// The least confidence of an inferred relation kept as a suggestion (default 0.3).
    pub fn suggest_confidence(&self) -> f64 {
        self.suggest_confidence
    }

    /// These settings with every threshold scaled by `s` (angles and relative
    /// distances), for measuring how far inside its thresholds a relation holds.
    fn scaled(&self, s: f64) -> Self {
        Self {
            angle_degrees: self.angle_degrees * s,
            distance: self.distance * s,
            radius: self.radius * s,
            length: self.length * s,
            noise: self.noise * s,
            ..self.clone()
        }
    }

    /// These settings with the angle threshold `degrees` (in (0, 90); kept as it is
    /// otherwise), everything else as it is.
    pub(crate) fn with_angle(&self, degrees: f64) -> Self {
        Self {
            angle_degrees: if degrees > 0.0 && degrees < 90.0 {
                degrees
            } else {
                self.angle_degrees
            },
            ..self.clone()
        }
    }

    /// These settings with the radius and length thresholds at least `relative` (of
    /// the sum of the two sizes), everything else as it is.
    pub(crate) fn with_sizes_at_least(&self, relative: f64) -> Self {
        Self {
            radius: self.radius.max(relative),
            length: self.length.max(relative),
            ..self.clone()
        }
    }

    /// These settings for one candidate: `noise` is the drawing's noise for its members
    /// (sketch units: how far their snapped curves lie from their strokes, combined), and
    /// `axial_slack` how many times the position tolerance stacked ends may lie apart
    /// along their common axis (1 for none).
    ///
    /// A drawing cannot place anything more exactly than its own noise, so positions,
    /// radii and lengths within [`evidence::NOISE_ERRORS`] times it hold where the
    /// relative thresholds are tighter (up to [`NOISE_WIDENING`] times them): on a rough
    /// drawing a threshold relative to small ends would otherwise ask more than the
    /// strokes show. Where one end sits on another in
    /// the drawing, where the end stops along its axis is what a snap pins least (a
    /// stroke's end, an overshoot, a gap where the parts join: the part's length), while
    /// its place across the axis is pinned by both silhouettes; the slack lets the
    /// former go further.
    pub(crate) fn for_members(&self, noise: f64, axial_slack: f64) -> Self {
        Self {
            noise: if noise.is_finite() {
                noise.max(0.0)
            } else {
                0.0
            },
            axial_slack: axial_slack.max(1.0),
            ..self.clone()
        }
    }

    /// The largest offset between positions taken as the same, where the sizes
    /// involved sum to `s`: the relative threshold, or the drawing's noise where that
    /// is more, up to [`NOISE_WIDENING`] times the threshold (thin parts drawn roughly
    /// would otherwise be centred on every neighbour).
    fn position_tolerance(&self, s: f64) -> f64 {
        self.tolerance(self.distance, s)
    }

    /// The largest difference taken as none for a threshold `relative` to sizes
    /// summing to `s`: `relative`·s, or the drawing's noise where that is more, up to
    /// [`NOISE_WIDENING`] times `relative`·s.
    fn tolerance(&self, relative: f64, s: f64) -> f64 {
        let noise = (evidence::NOISE_ERRORS * self.noise).min(NOISE_WIDENING * relative * s);
        (relative * s).max(noise)
    }

    /// Whether sizes `a` and `b` (radii, lengths) are the same within `relative` of
    /// their sum, or within the drawing's noise ([`InferenceSettings::tolerance`]).
    fn same_size(&self, a: f64, b: f64, relative: f64) -> bool {
        (a - b).abs() <= self.tolerance(relative, a + b)
    }

    /// The kinds inferred (default: all).
    pub fn enabled_kinds(&self) -> &[RelationKind] {
        &self.enabled
    }

    /// Largest angle (degrees) between directions taken as parallel, or off a right
    /// angle for orthogonal (default 8°).
    pub fn angle_degrees(&self) -> f64 {
        self.angle_degrees
    }

    /// Largest offset between positions taken as the same, relative to the sum of the
    /// sizes involved (default 0.1).
    pub fn distance(&self) -> f64 {
        self.distance
    }

    /// Largest difference of radii taken as the same, relative to their sum (default
    /// 0.05: radii 10 % apart).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Largest difference of lengths taken as equal, relative to their sum (default
    /// 0.03: lengths 6 % apart; a snap's length is good to a few per cent, and parts
    /// 10 % apart are more often meant to differ).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Whether `kind` is inferred.
    pub fn enabled(&self, kind: RelationKind) -> bool {
        self.enabled.contains(&kind)
    }

    /// sin of the angle threshold, compared with |n₁ × n₂| or |n₁ · n₂|.
    fn sin_angle(&self) -> f64 {
        self.angle_degrees.to_radians().sin()
    }
}

/// The residuals ψ of a relation of `kind` over its members.
///
/// # Errors
///
/// [`RelationError`] when the members do not suit the kind.
///
/// # Examples
///
/// ```
/// use glam::DVec3;
/// use geosnap_core::primitive::{Cylinder, Feature, Primitive};
/// use geosnap_core::relation::{residuals, Member, RelationKind};
///
/// let upright = |x: f64| Primitive::Cylinder(Cylinder {
///     center: DVec3::new(x, 0.0, 0.0),
///     axis: DVec3::Y,
///     length: 10.0,
///     radius: 2.0,
/// });
/// let (a, b) = (upright(0.0).current_shape(), upright(5.0).current_shape());
/// let members = [
///     Member { features: &a.features, feature: Some(Feature::Top) },
///     Member { features: &b.features, feature: Some(Feature::Bottom) },
/// ];
/// // Parallel holds; coaxial does not (the axes are 5 apart).
/// let norm = |r: Vec<f64>| r.iter().map(|v| v * v).sum::<f64>().sqrt();
/// assert!(norm(residuals(RelationKind::Parallel, &members)?) < 1e-12);
/// assert!(norm(residuals(RelationKind::Coaxial, &members)?) > 0.5);
/// # Ok::<(), geosnap_core::relation::RelationError>(())
/// ```
pub fn residuals<T: Real>(
    kind: RelationKind,
    members: &[Member<'_, T>],
) -> Result<Vec<T>, RelationError> {
    if members.len() != kind.arity() {
        return Err(RelationError::Arity {
            kind: kind.name(),
            expected: kind.arity(),
            got: members.len(),
        });
    }
    match kind {
        RelationKind::Parallel => parallel::residuals(members),
        RelationKind::Orthogonal => orthogonal::residuals(members),
        RelationKind::Coaxial => coaxial::residuals(members),
        RelationKind::Concentric => concentric::residuals(members),
        RelationKind::Coplanar => coplanar::residuals(members),
        RelationKind::CollinearCenters => collinear_centers::residuals(members),
        RelationKind::SameRadius => same_radius::residuals(members),
        RelationKind::EqualLength => equal_length::residuals(members),
        RelationKind::OnSphere => on_sphere::residuals(members),
    }
}

/// Whether a relation of `kind` nearly holds between `members` (the inference test).
pub fn holds(
    kind: RelationKind,
    members: &[Member<'_, f64>],
    settings: &InferenceSettings,
) -> bool {
    if members.len() != kind.arity() {
        return false;
    }
    match kind {
        RelationKind::Parallel => parallel::holds(members, settings),
        RelationKind::Orthogonal => orthogonal::holds(members, settings),
        RelationKind::Coaxial => coaxial::holds(members, settings),
        RelationKind::Concentric => concentric::holds(members, settings),
        RelationKind::Coplanar => coplanar::holds(members, settings),
        RelationKind::CollinearCenters => collinear_centers::holds(members, settings),
        RelationKind::SameRadius => same_radius::holds(members, settings),
        RelationKind::EqualLength => equal_length::holds(members, settings),
        RelationKind::OnSphere => on_sphere::holds(members, settings),
    }
}

/// How far inside its thresholds a relation of `kind` holds between `members`: the
/// least fraction s ∈ (0, 1] of every threshold of `settings` at which it still holds
/// ([`holds`] with thresholds scaled by s), to 1/64; `None` when it does not hold. 0
/// is exact, 1 at the edge.
pub fn closeness(
    kind: RelationKind,
    members: &[Member<'_, f64>],
    settings: &InferenceSettings,
) -> Option<f64> {
    closeness_by(|s| holds(kind, members, s), settings)
}

/// [`closeness`] for any `test` of settings: the least fraction of every threshold of
/// `settings` at which `test` passes, to 1/64; `None` when it fails at `settings`.
pub(crate) fn closeness_by(
    test: impl Fn(&InferenceSettings) -> bool,
    settings: &InferenceSettings,
) -> Option<f64> {
    if !test(settings) {
        return None;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..6 {
        let mid = 0.5 * (lo + hi);
        if test(&settings.scaled(mid)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}

/// The chosen feature of member `i`, or why it cannot be used.
fn chosen<'a, T>(
    kind: RelationKind,
    members: &[Member<'a, T>],
    i: usize,
) -> Result<&'a FeatureGeometry<T>, RelationError> {
    members[i].chosen().ok_or_else(|| RelationError::Unsuited {
        kind: kind.name(),
        member: i,
        what: match members[i].feature {
            Some(feature) => format!("feature `{feature}` (it has no such feature)"),
            None => "missing feature name".to_owned(),
        },
    })
}

/// The circle of member `i`: centre, unit normal, radius.
fn circle<T: Real>(
    kind: RelationKind,
    members: &[Member<'_, T>],
    i: usize,
) -> Result<(Vec3<T>, Vec3<T>, T), RelationError> {
    match chosen(kind, members, i)? {
        FeatureGeometry::Circle {
            center,
            normal,
            radius,
        } => Ok((*center, *normal, *radius)),
        FeatureGeometry::Rectangle { .. } => Err(RelationError::Unsuited {
            kind: kind.name(),
            member: i,
            what: "face (a circle is needed)".to_owned(),
        }),
    }
}

/// The centre, unit normal and size of a feature: a circle's radius, a face's larger
/// half extent.
fn frame<T: Real>(feature: &FeatureGeometry<T>) -> (Vec3<T>, Vec3<T>, T) {
    match feature {
        FeatureGeometry::Circle {
            center,
            normal,
            radius,
        } => (*center, *normal, *radius),
        FeatureGeometry::Rectangle {
            center,
            normal,
            half_extents,
        } => (*center, *normal, half_extents[0].1.max(half_extents[1].1)),
    }
}

/// The offset of `b` from `a` in the view plane: orthographic views do not show depth, so
/// inference judges positions by their projections and leaves depths to the solve.
fn offset_2d(a: Vec3<f64>, b: Vec3<f64>) -> glam::DVec2 {
    glam::DVec2::new(b.x - a.x, b.y - a.y)
}

/// The three components of a vector as residuals.
fn components<T: Real>(v: Vec3<T>) -> Vec<T> {
    v.to_array().to_vec()
}

/// ‖ψ‖ of plain residuals.
fn norm(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum::<f64>().sqrt()
}

#[cfg(test)]
pub(crate) mod testing {
    //! Helpers of the per-kind tests: features of real primitives, and the same model
    //! moved rigidly and scaled.

    use glam::{DQuat, DVec3};

    use super::{norm, residuals, Member, RelationKind};
    use crate::ad::Vec3;
    use crate::primitive::{Feature, FeatureCurve, FeatureGeometry, Primitive};

    /// The feature curves of a primitive.
    pub(crate) fn features(p: &Primitive) -> Vec<FeatureCurve<f64>> {
        p.current_shape().features
    }

    /// A cylinder at `center` along `axis` (normalised) of `length` and `radius`.
    pub(crate) fn cylinder(center: DVec3, axis: DVec3, length: f64, radius: f64) -> Primitive {
        Primitive::Cylinder(crate::primitive::Cylinder {
            center,
            axis: axis.normalize(),
            length,
            radius,
        })
    }

    /// A feature moved by the similarity x ↦ s·R·x + t.
    fn moved(f: &FeatureCurve<f64>, r: DQuat, t: DVec3, s: f64) -> FeatureCurve<f64> {
        let point = |v: Vec3<f64>| Vec3::from_dvec3(r * v.to_dvec3() * s + t);
        let dir = |v: Vec3<f64>| Vec3::from_dvec3(r * v.to_dvec3());
        let geometry = match &f.geometry {
            FeatureGeometry::Circle {
                center,
                normal,
                radius,
            } => FeatureGeometry::Circle {
                center: point(*center),
                normal: dir(*normal),
                radius: radius * s,
            },
            FeatureGeometry::Rectangle {
                center,
                normal,
                half_extents,
            } => FeatureGeometry::Rectangle {
                center: point(*center),
                normal: dir(*normal),
                half_extents: half_extents.map(|(a, h)| (dir(a), h * s)),
            },
        };
        FeatureCurve {
            feature: f.feature,
            geometry,
        }
    }

    /// ‖ψ‖ of `kind` between primitives with the named features.
    pub(crate) fn psi(kind: RelationKind, parts: &[(&Primitive, Option<Feature>)]) -> f64 {
        psi_of(
            kind,
            &parts
                .iter()
                .map(|(p, n)| (features(p), *n))
                .collect::<Vec<_>>(),
        )
    }

    fn psi_of(kind: RelationKind, parts: &[(Vec<FeatureCurve<f64>>, Option<Feature>)]) -> f64 {
        let members: Vec<Member<'_, f64>> = parts
            .iter()
            .map(|(f, n)| Member {
                features: f,
                feature: *n,
            })
            .collect();
        norm(&residuals(kind, &members).expect("the members suit the kind"))
    }

    /// Checks ‖ψ‖ is the same after a rigid motion and a uniform scale of the whole
    /// model, and returns it.
    pub(crate) fn invariant_psi(
        kind: RelationKind,
        parts: &[(&Primitive, Option<Feature>)],
    ) -> f64 {
        let before = psi(kind, parts);
        let r = DQuat::from_axis_angle(DVec3::new(0.3, -0.8, 0.5).normalize(), 1.1);
        for (t, s) in [
            (DVec3::new(40.0, -7.0, 3.0), 1.0),
            (DVec3::ZERO, 7.5),
            (DVec3::X, 0.01),
        ] {
            let after: Vec<(Vec<FeatureCurve<f64>>, Option<Feature>)> = parts
                .iter()
                .map(|(p, n)| (features(p).iter().map(|f| moved(f, r, t, s)).collect(), *n))
                .collect();
            let a = psi_of(kind, &after);
            assert!(
                (a - before).abs() <= 1e-9 * before.max(1.0),
                "{kind:?}: ‖ψ‖ {before} became {a} after moving and scaling by {s}"
            );
        }
        before
    }
}

#[cfg(test)]
mod tests {
    use super::{InferenceSettings, RelationKind};
    use crate::solve::SettingsError;

    #[test]
    fn bad_inference_settings_are_refused_also_when_read() {
        let d = InferenceSettings::default();
        let good = InferenceSettings::new(RelationKind::ALL.to_vec(), 8.0, 0.1, 0.05, 0.03);
        assert_eq!(good, Ok(d.clone()), "the defaults are valid");
        for angle in [0.0, -1.0, 90.0, f64::NAN] {
            let error = InferenceSettings::new(Vec::new(), angle, 0.1, 0.05, 0.03).unwrap_err();
            assert!(
                matches!(
                    error,
                    SettingsError::OutOfRange {
                        name: "angle_degrees",
                        ..
                    }
                ),
                "{error}"
            );
        }
        for (distance, radius, length, bad) in [
            (0.0, 0.05, 0.03, "distance"),
            (0.1, f64::INFINITY, 0.03, "radius"),
            (0.1, 0.05, -0.03, "length"),
        ] {
            let error =
                InferenceSettings::new(Vec::new(), 8.0, distance, radius, length).unwrap_err();
            assert!(
                matches!(error, SettingsError::NotPositive { name, .. } if name == bad),
                "{error}"
            );
        }
        let text = serde_json::to_string(&d).unwrap();
        let back: InferenceSettings = serde_json::from_str(&text).unwrap();
        assert_eq!(back, d, "round trip");
        let partial: InferenceSettings = serde_json::from_str(r#"{"distance":0.2}"#).unwrap();
        assert!((partial.distance() - 0.2).abs() < 1e-15, "the field read");
        assert!(
            (partial.angle_degrees() - d.angle_degrees()).abs() < 1e-15,
            "a missing field defaults"
        );
        assert!(
            serde_json::from_str::<InferenceSettings>(r#"{"radius":-1}"#).is_err(),
            "a bad stored value is refused"
        );
    }
}
