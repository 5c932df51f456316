//! The document: the placed primitives with their fits, addressed by stable ids, the
//! relations between them, and the steps that could not be placed.
//!
//! [`run_steps`] runs a modelling session headless (the script runner's core), as the
//! application does on each release: snap the dropped part, infer its relations with the
//! placed parts ([`Document::infer_relations`]), then solve the model globally
//! ([`Document::solve`], module `solve`), switching off relations that conflict.
//!
//! Sizes the user types for a part are [`Dimension`]s ([`Document::set_dimension`]),
//! held exactly by every solve (module `dimension`).

mod dimension;
pub mod reading;
mod release;
mod solve;
mod unit;

use std::collections::BTreeMap;

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::primitive::{Feature, Placement, Primitive, PrimitiveKind, DEFAULT_SIZE_FRACTION};
use crate::relation::evidence::Inferred;
use crate::relation::{residuals, InferenceSettings, Member, Mode, RelationKind};
use crate::sketch::{Sketch, StrokeId};
use crate::snap::{
    snap, snap_at_with, Assignment, Confidence, Owner, Profile, SnapContext, SnapResult,
    SnapSettings, Verdict,
};
use crate::solve::SolveContext;

pub use dimension::{Dimension, DimensionError, Quantity};
pub use solve::{Companions, Conflict, GlobalOutcome, GlobalSettings, WORSENING_FLOOR};
pub use unit::{clean_name, LengthUnit, MAX_NAME_CHARS};

/// Identifies a primitive of a [`Document`]; ids are never reused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct PrimitiveId(pub u32);

/// Identifies a relation of a [`Document`]: it stays with its relation when others are
/// added or removed, and an undo (which restores an earlier document) brings the
/// relation back under the same id. Relation ids live in memory only: a document read
/// from a file numbers its relations in file order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct RelationId(pub u32);

/// How a primitive was snapped: the strokes it took, how closely it fits them, how sure
/// the snap was and which script step placed it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Fit {
    /// The strokes assigned to it.
    pub strokes: Vec<StrokeId>,
    /// RMS distance of those strokes to its projected curves, in sketch units.
    pub rms: f64,
    /// The snap's verdict (see [`crate::snap::judge`]); `None` for a part that was
    /// not judged (typed in, or read from a file without one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verdict: Option<Verdict>,
    /// The snap's confidence in [0, 1], with the verdict.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub confidence: Option<f64>,
    /// Why a snap is doubtful, in words.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// The index of the script step that placed it, if a script did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<usize>,
}

impl Fit {
    /// The fit of a snap: its strokes and RMS, not yet judged.
    pub fn of(result: &SnapResult) -> Self {
        Self {
            strokes: result.assignment.stroke_ids(),
            rms: result.rms,
            ..Self::default()
        }
    }

    /// This fit with a snap's verdict, confidence and reason.
    #[must_use]
    pub fn judged(self, confidence: &Confidence) -> Self {
        Self {
            verdict: Some(confidence.verdict),
            confidence: Some(confidence.value),
            reason: confidence.reason.clone(),
            ..self
        }
    }
}

/// A primitive in the document.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Placed {
    /// The primitive, in model space.
    pub primitive: Primitive,
    /// Its fit to the strokes.
    pub fit: Fit,
}

/// A geosemantic relation between placed primitives (see [`crate::relation`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Relation {
    /// The kind.
    pub kind: RelationKind,
    /// The primitives it relates, in order.
    pub members: Vec<PrimitiveId>,
    /// The feature of each member it uses (`None` for kinds about a whole solid); empty
    /// when no member names one.
    pub features: Vec<Option<Feature>>,
    /// How it takes part in the global solve.
    pub mode: Mode,
    /// For an inferred relation, its confidence and the evidence it rests on (`None`
    /// for a relation the user made or a file gave without them).
    pub inferred: Option<Inferred>,
}

impl Relation {
    /// A relation of `kind` between `members` (features as given), in `mode`, not
    /// inferred.
    pub fn new(
        kind: RelationKind,
        members: Vec<PrimitiveId>,
        features: Vec<Option<Feature>>,
        mode: Mode,
    ) -> Self {
        Self {
            kind,
            members,
            features,
            mode,
            inferred: None,
        }
    }
}

/// Why [`Document::add_relation`] refused a relation.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RelationError {
    /// The relation has the wrong number of members for its kind.
    #[error("a {} relation relates {expected} primitives, not {got}", .kind.name())]
    Arity {
        /// The kind.
        kind: RelationKind,
        /// The members it needs.
        expected: usize,
        /// The members it has.
        got: usize,
    },
    /// The features are named for some members but not one per member.
    #[error("{features} features for {members} members")]
    FeatureCount {
        /// The features given.
        features: usize,
        /// The members.
        members: usize,
    },
    /// A member is not in the document.
    #[error("there is no primitive {}", .id.0)]
    MissingPrimitive {
        /// The member's id.
        id: PrimitiveId,
    },
    /// A member does not have the feature the relation names for it.
    #[error("primitive {} is a {}, which has no feature `{feature}`", .member.0, .kind.name())]
    ForeignFeature {
        /// The member.
        member: PrimitiveId,
        /// Its kind.
        kind: PrimitiveKind,
        /// The feature it lacks.
        feature: Feature,
    },
    /// A member names no feature and its kind has no default one for the relation (see
    /// [`default_feature`]).
    #[error(
        "a {} relation must name the feature of primitive {} (a {}): which of its features \
         it relates is not clear",
        .kind.name(), .member.0, .primitive.name()
    )]
    MissingFeature {
        /// The relation's kind.
        kind: RelationKind,
        /// The member.
        member: PrimitiveId,
        /// The member's kind.
        primitive: PrimitiveKind,
    },
    /// A primitive is named twice among the members: a part is not related to itself.
    #[error("a {} relation names primitive {} twice: a part is not related to itself", .kind.name(), .member.0)]
    RepeatedMember {
        /// The relation's kind.
        kind: RelationKind,
        /// The member named twice.
        member: PrimitiveId,
    },
    /// The named features are not of the sort the relation relates.
    #[error("{reason}")]
    Unsuited {
        /// Why, in words.
        reason: String,
    },
}

/// The feature a relation of kind `relation` uses on a member of kind `primitive` that
/// names none, where the choice is clear:
/// - a primitive with a single feature uses it (a sphere's `outline`);
/// - a cylinder, cone or SGC in `parallel`, `orthogonal` or `coaxial` uses `top`: both its
///   ends lie on its axis, so either end gives the same relation;
/// - a cylinder in `same_radius` uses `top`: both its ends have its radius.
///
/// `None` otherwise (a box's face, a bent tube's end, a cone's end for its radius, an end
/// for concentric or collinear centres): the relation must name it.
pub fn default_feature(relation: RelationKind, primitive: PrimitiveKind) -> Option<Feature> {
    use PrimitiveKind::{Cone, Cylinder, Sgc};
    use RelationKind::{Coaxial, Orthogonal, Parallel, SameRadius};
    if let [only] = primitive.features() {
        return Some(*only);
    }
    match (relation, primitive) {
        (Parallel | Orthogonal | Coaxial, Cylinder | Cone | Sgc) | (SameRadius, Cylinder) => {
            Some(Feature::Top)
        }
        _ => None,
    }
}

/// A step that could not be placed, with the reason.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Skipped {
    /// The step's index in its script.
    pub step: usize,
    /// Why, in words.
    pub reason: String,
}

/// What a part's own snap found: the strokes of each projected curve, which the global
/// solve keeps fitting, and the RMS it reached alone, which the solve must not spoil.
#[derive(Clone, Debug, PartialEq)]
pub struct SnapRecord {
    /// The strokes of each projected curve.
    pub assignment: Assignment,
    /// RMS of the part's own snap, in sketch units.
    pub rms: f64,
    /// How its snap held a bent tube's radii, as every later fit of it does (smooth for a
    /// part read from a file, which does not say).
    pub profile: Profile,
}

/// The assembled model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Document {
    primitives: BTreeMap<PrimitiveId, Placed>,
    next_id: u32,
    /// Steps that were skipped.
    pub skipped: Vec<Skipped>,
    relations: Vec<Relation>,
    /// The id of each relation, in the order of `relations`.
    relation_ids: Vec<RelationId>,
    next_relation: u32,
    /// Sizes the user typed, held exactly by every solve.
    dimensions: Vec<Dimension>,
    /// The snaps of parts placed in this session (parts loaded from a model file have
    /// none and are held where they are).
    snaps: BTreeMap<PrimitiveId, SnapRecord>,
    /// The multipliers of the last global solves by constraint, to warm-start the next
    /// one.
    multipliers: solve::WarmStarts,
    /// The names designers gave parts (cleaned by [`clean_name`]); a part without one
    /// has no entry.
    names: BTreeMap<PrimitiveId, String>,
    /// What one model unit is.
    unit: LengthUnit,
}

impl Document {
    /// An empty document.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a primitive and returns its new id.
    pub fn add(&mut self, placed: Placed) -> PrimitiveId {
        let id = PrimitiveId(self.next_id);
        self.next_id += 1;
        self.primitives.insert(id, placed);
        id
    }

    /// Adds a snapped primitive with its fit.
    pub fn add_snapped(&mut self, result: &SnapResult) -> PrimitiveId {
        self.add_fitted(result, Fit::of(result))
    }

    /// Adds a snapped primitive with `fit` (its strokes and RMS, and a verdict, say).
    pub fn add_fitted(&mut self, result: &SnapResult, fit: Fit) -> PrimitiveId {
        let id = self.add(Placed {
            primitive: result.primitive.clone(),
            fit,
        });
        self.snaps.insert(
            id,
            SnapRecord {
                assignment: result.assignment.clone(),
                rms: result.rms,
                profile: result.profile,
            },
        );
        id
    }

    /// Which part owns a piece of stroke: `owner(stroke, sample)` names the part, placed
    /// first, that took that sample of that stroke (its snap's assignment; a part read from
    /// a file without one owns its strokes whole), and `pose(part)` where it lies. What a
    /// new snap is judged against.
    pub fn owner(&self) -> impl Owner + use<> {
        // Per stroke, each owner with the samples it took (`None`: the whole stroke).
        let mut owners: BTreeMap<StrokeId, Vec<Taken>> = BTreeMap::new();
        for (id, placed) in &self.primitives {
            match self.snaps.get(id) {
                Some(record) => {
                    for taken in record.assignment.curves.iter().flatten() {
                        let entry = owners.entry(taken.stroke).or_default();
                        let samples = taken.part.as_ref().map(|_| taken.samples.clone());
                        match entry.iter_mut().find(|(p, _)| *p == id.0) {
                            Some((_, Some(existing))) => match samples {
                                Some(more) => existing.extend(more),
                                None => entry_whole(entry, id.0),
                            },
                            Some((_, None)) => {}
                            None => entry.push((id.0, samples)),
                        }
                    }
                }
                None => {
                    for stroke in &placed.fit.strokes {
                        owners.entry(*stroke).or_default().push((id.0, None));
                    }
                }
            }
        }
        let poses = self
            .primitives
            .iter()
            .map(|(id, placed)| (id.0, placed.primitive.clone()))
            .collect();
        Owners {
            strokes: owners,
            poses,
        }
    }

    /// The snap of a part placed in this session.
    pub fn snap_record(&self, id: PrimitiveId) -> Option<&SnapRecord> {
        self.snaps.get(&id)
    }

    /// The snaps of the parts placed in this session, in id order.
    pub fn snap_records(&self) -> impl Iterator<Item = (PrimitiveId, &SnapRecord)> {
        self.snaps.iter().map(|(id, r)| (*id, r))
    }

    /// Gives part `id` a snap record (reopening a saved session), so the global solve
    /// keeps fitting it to those strokes instead of holding it where it is. The record's
    /// assignment must have one entry per projected curve of the part (see
    /// [`crate::snap::restore_assignment`]). Returns whether the part exists.
    pub fn set_snap_record(&mut self, id: PrimitiveId, record: SnapRecord) -> bool {
        if self.primitives.contains_key(&id) {
            self.snaps.insert(id, record);
            true
        } else {
            false
        }
    }

    /// The multipliers the next global solve starts from, by constraint label and
    /// occurrence of that label, in key order. They only speed solves up, but a saved
    /// session keeps them so that a re-solve after reopening follows the same path.
    pub fn warm_multipliers(&self) -> impl Iterator<Item = (&str, usize, f64)> {
        self.multipliers.named().into_iter()
    }

    /// Sets the warm-start multiplier of the `occurrence`-th constraint labelled
    /// `label` (see [`Document::warm_multipliers`]); non-finite values are ignored.
    pub fn set_warm_multiplier(&mut self, label: String, occurrence: usize, value: f64) {
        if value.is_finite() {
            self.multipliers.set_named(label, occurrence, value);
        }
    }

    /// Inserts a primitive under a given id (loading a file); later ids stay above it.
    pub fn insert(&mut self, id: PrimitiveId, placed: Placed) {
        self.next_id = self.next_id.max(id.0 + 1);
        self.primitives.insert(id, placed);
    }

    /// Removes a primitive with the relations it takes part in and its dimensions.
    pub fn remove(&mut self, id: PrimitiveId) -> Option<Placed> {
        if let Some(first) = self.relations.iter().position(|r| r.members.contains(&id)) {
            self.multipliers
                .forget_relations(&self.relation_ids[first..]);
        }
        let mut keep = self.relations.iter().map(|r| !r.members.contains(&id));
        self.relation_ids.retain(|_| keep.next().unwrap_or(true));
        self.relations.retain(|r| !r.members.contains(&id));
        self.dimensions.retain(|d| d.primitive != id);
        self.snaps.remove(&id);
        self.names.remove(&id);
        self.primitives.remove(&id)
    }

    /// The name a designer gave part `id`, if any.
    pub fn name(&self, id: PrimitiveId) -> Option<&str> {
        self.names.get(&id).map(String::as_str)
    }

    /// Names part `id` (`name` is cleaned by [`clean_name`]: an empty or blank name
    /// takes the name away). Returns whether the part exists; a missing part is left
    /// unnamed.
    pub fn set_name(&mut self, id: PrimitiveId, name: &str) -> bool {
        if !self.primitives.contains_key(&id) {
            return false;
        }
        match clean_name(name) {
            Some(name) => self.names.insert(id, name),
            None => self.names.remove(&id),
        };
        true
    }

    /// What one model unit is (millimetres unless set).
    pub fn unit(&self) -> LengthUnit {
        self.unit
    }

    /// Sets what one model unit is; the numbers stay as they are.
    pub fn set_unit(&mut self, unit: LengthUnit) {
        self.unit = unit;
    }

    /// Adds a relation between primitives of the document and returns its new id. A
    /// member that names no feature takes its [`default_feature`], and the relation is
    /// stored with it named.
    ///
    /// # Errors
    ///
    /// [`RelationError`] when a member is not in the document or named twice, the number
    /// of members or features does not suit the kind, a member lacks the feature named for
    /// it, names none where no default is clear, or names one of the wrong sort for the
    /// kind (a box face for concentric); the document is then unchanged.
    pub fn add_relation(&mut self, mut relation: Relation) -> Result<RelationId, RelationError> {
        if relation.members.len() != relation.kind.arity() {
            return Err(RelationError::Arity {
                kind: relation.kind,
                expected: relation.kind.arity(),
                got: relation.members.len(),
            });
        }
        if !relation.features.is_empty() && relation.features.len() != relation.members.len() {
            return Err(RelationError::FeatureCount {
                features: relation.features.len(),
                members: relation.members.len(),
            });
        }
        if let Some(k) = (1..relation.members.len())
            .find(|k| relation.members[..*k].contains(&relation.members[*k]))
        {
            return Err(RelationError::RepeatedMember {
                kind: relation.kind,
                member: relation.members[k],
            });
        }
        let mut defaulted = Vec::with_capacity(relation.members.len());
        for (k, &member) in relation.members.iter().enumerate() {
            let placed = self
                .get(member)
                .ok_or(RelationError::MissingPrimitive { id: member })?;
            let kind = placed.primitive.kind();
            let feature = match relation.features.get(k).copied().flatten() {
                Some(feature) if !kind.has(feature) => {
                    return Err(RelationError::ForeignFeature {
                        member,
                        kind,
                        feature,
                    });
                }
                Some(feature) => Some(feature),
                // Equal length relates the primitives themselves: it needs no feature.
                None if relation.kind == RelationKind::EqualLength => None,
                None => Some(default_feature(relation.kind, kind).ok_or(
                    RelationError::MissingFeature {
                        kind: relation.kind,
                        member,
                        primitive: kind,
                    },
                )?),
            };
            defaulted.push(feature);
        }
        if defaulted.iter().any(Option::is_some) {
            relation.features = defaulted;
        }
        self.check_relation(&relation)?;
        let id = RelationId(self.next_relation);
        self.next_relation += 1;
        self.relations.push(relation);
        self.relation_ids.push(id);
        Ok(id)
    }

    /// Whether `relation`'s residuals can be written for its members as they are now:
    /// each named feature must be of the sort its kind relates (a circle for concentric,
    /// say, not a box face).
    fn check_relation(&self, relation: &Relation) -> Result<(), RelationError> {
        let shapes: Vec<_> = relation
            .members
            .iter()
            .filter_map(|m| self.get(*m))
            .map(|p| p.primitive.current_shape().features)
            .collect();
        let members: Vec<Member<'_, f64>> = shapes
            .iter()
            .zip(
                relation
                    .features
                    .iter()
                    .copied()
                    .chain(std::iter::repeat(None)),
            )
            .map(|(features, feature)| Member { features, feature })
            .collect();
        residuals(relation.kind, &members)
            .map(|_| ())
            .map_err(|error| RelationError::Unsuited {
                reason: error.to_string(),
            })
    }

    /// The relations, in the order they were added.
    pub fn relations(&self) -> &[Relation] {
        &self.relations
    }

    /// The relations with their ids, in the order they were added.
    pub fn relations_with_ids(&self) -> impl Iterator<Item = (RelationId, &Relation)> {
        self.relation_ids.iter().copied().zip(&self.relations)
    }

    /// The relation with this id.
    pub fn relation(&self, id: RelationId) -> Option<&Relation> {
        self.relation_position(id).map(|i| &self.relations[i])
    }

    /// The relation with this id, to change its mode.
    pub fn relation_mut(&mut self, id: RelationId) -> Option<&mut Relation> {
        self.relation_position(id).map(|i| &mut self.relations[i])
    }

    /// Where relation `id` stands in [`Document::relations`] (how messages number it).
    pub fn relation_position(&self, id: RelationId) -> Option<usize> {
        self.relation_ids.iter().position(|r| *r == id)
    }

    /// The relations, to change their modes.
    pub fn relations_mut(&mut self) -> &mut [Relation] {
        &mut self.relations
    }

    /// The id the next added primitive gets.
    pub fn next_id(&self) -> PrimitiveId {
        PrimitiveId(self.next_id)
    }

    /// Makes later ids start at `next` or above (a reopened document keeps the ids of
    /// deleted parts retired).
    pub fn reserve_ids(&mut self, next: PrimitiveId) {
        self.next_id = self.next_id.max(next.0);
    }

    /// Removes relation `id`; the other relations keep their ids.
    pub fn remove_relation(&mut self, id: RelationId) -> Option<Relation> {
        let index = self.relation_position(id)?;
        self.multipliers
            .forget_relations(&self.relation_ids[index..]);
        self.relation_ids.remove(index);
        Some(self.relations.remove(index))
    }

    /// The primitive with this id.
    pub fn get(&self, id: PrimitiveId) -> Option<&Placed> {
        self.primitives.get(&id)
    }

    /// The primitives in id order.
    pub fn primitives(&self) -> impl Iterator<Item = (PrimitiveId, &Placed)> {
        self.primitives.iter().map(|(id, p)| (*id, p))
    }

    /// The number of primitives.
    pub fn len(&self) -> usize {
        self.primitives.len()
    }

    /// Whether there are no primitives.
    pub fn is_empty(&self) -> bool {
        self.primitives.is_empty()
    }
}

/// One step of a modelling session: drop a primitive of `kind` with `placement`, or a
/// step that cannot be carried out (an unknown kind, a bad value) with the reason.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// Drop and snap a primitive.
    Place {
        /// The kind.
        kind: PrimitiveKind,
        /// Where and how big.
        placement: Placement,
    },
    /// A step that is skipped, with the reason.
    Invalid {
        /// Why.
        reason: String,
    },
}

/// What happened to one step of [`run_steps`].
#[derive(Clone, Debug, PartialEq)]
pub enum StepOutcome {
    /// The primitive was snapped and added.
    Placed {
        /// Its id.
        id: PrimitiveId,
        /// The snap.
        snap: Box<SnapResult>,
        /// How sure the snap is.
        confidence: Box<Confidence>,
        /// The relations inferred on its release.
        relations: Vec<RelationId>,
        /// The earlier part it coincides with, when it is a copy of one
        /// ([`Document::duplicate_of`]): no relations were inferred for it.
        duplicate_of: Option<PrimitiveId>,
        /// The global solve that followed.
        solve: Box<GlobalOutcome>,
    },
    /// The step was skipped (it could not be snapped, or it was not a valid step).
    Skipped(Skipped),
    /// The primitive snapped, but its confidence refused the snap (see
    /// [`crate::snap::judge`]): nothing was added, and the step is recorded in
    /// [`Document::skipped`] with the reason.
    Refused {
        /// The refused snap.
        snap: Box<SnapResult>,
        /// Its confidence.
        confidence: Box<Confidence>,
        /// The step as [`Document::skipped`] records it.
        skipped: Skipped,
    },
}

/// Settings of a modelling session: snapping, inference and the global solve.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SessionSettings {
    /// Snapping.
    pub snap: SnapSettings,
    /// Relation inference.
    pub inference: InferenceSettings,
    /// The global solve.
    pub global: GlobalSettings,
}

/// Runs steps over a sketch as the interactive tool would: each step is snapped, its
/// relations with the placed parts are inferred, and the model is solved globally. A step
/// that cannot be snapped is recorded in [`Document::skipped`] and the run goes on.
/// `solve` carries the solves' cancel flag, clock and observer.
pub fn run_steps(
    sketch: &Sketch,
    steps: &[Step],
    settings: &SessionSettings,
    solve: SolveContext<'_>,
) -> (Document, Vec<StepOutcome>) {
    run_steps_with(sketch, steps, settings, solve, &mut |_, _| {})
}

/// The snap of one step and the drop it stands for. A step that gives no size is sized
/// (and, without an axis of its own, turned) by the drawing, as the palette's drop is
/// (see [`snap_at_with`]); the guess it was snapped from stands for the drop in its
/// confidence.
fn snap_step(
    context: &SnapContext,
    step: &Step,
    default_size: f64,
    settings: &SessionSettings,
    solve: SolveContext<'_>,
) -> Result<(SnapResult, Primitive), String> {
    match step {
        Step::Invalid { reason } => Err(reason.clone()),
        Step::Place { kind, placement } if placement.is_unsized() => snap_at_with(
            context,
            *kind,
            placement.at,
            placement.given_axis(),
            &settings.snap,
            solve,
        )
        .map(|p| (p.result, p.guess))
        .map_err(|e| e.to_string()),
        Step::Place { kind, placement } => {
            let dropped = Primitive::from_placement(*kind, placement, default_size);
            snap(context, &dropped, &settings.snap)
                .map(|result| (result, dropped))
                .map_err(|e| e.to_string())
        }
    }
}

/// [`run_steps`], calling `on_step` with each step's index and outcome as soon as the
/// step is done (for progress reports on long scripts). Once `solve`'s cancel flag is
/// raised no further step starts: the outcomes then cover only the steps begun.
pub fn run_steps_with(
    sketch: &Sketch,
    steps: &[Step],
    settings: &SessionSettings,
    mut solve: SolveContext<'_>,
    on_step: &mut dyn FnMut(usize, &StepOutcome),
) -> (Document, Vec<StepOutcome>) {
    let mut context = SnapContext::from_sketch(sketch);
    let default_size = sketch
        .view_box
        .map(|(_, size)| size.max_element())
        .or_else(|| sketch.bounds().map(|(lo, hi)| (hi - lo).max_element()))
        .unwrap_or(100.0)
        * DEFAULT_SIZE_FRACTION;
    let mut document = Document::new();
    let mut outcomes = Vec::with_capacity(steps.len());
    for (index, step) in steps.iter().enumerate() {
        if solve
            .cancel
            .is_some_and(crate::solve::CancelFlag::is_cancelled)
        {
            break; // cancelled: no more steps, the outcomes cover those done
        }
        // A reading that holds a part placed before gives way to one that holds none.
        context.set_placed(document.primitives().map(|(_, p)| p.primitive.clone()));
        let snapped = snap_step(&context, step, default_size, settings, solve.reborrow());
        let outcome = snapped.map(|(result, dropped)| {
            let confidence = result.confidence(&dropped, &document.owner(), &settings.snap);
            (result, confidence)
        });
        let skip = |reason: String| Skipped {
            step: index,
            reason,
        };
        outcomes.push(match outcome {
            Ok((result, confidence)) if confidence.verdict == Verdict::Refused => {
                let skipped = skip(format!(
                    "the snap was refused: {}",
                    confidence.reason.as_deref().unwrap_or("no evidence for it")
                ));
                document.skipped.push(skipped.clone());
                StepOutcome::Refused {
                    snap: Box::new(result),
                    confidence: Box::new(confidence),
                    skipped,
                }
            }
            Ok((result, confidence)) => {
                let fit = Fit {
                    step: Some(index),
                    ..Fit::of(&result).judged(&confidence)
                };
                let id = document.add_fitted(&result, fit);
                let (relations, solve) =
                    document.release(id, &settings.inference, &settings.global, solve.reborrow());
                StepOutcome::Placed {
                    id,
                    snap: Box::new(result),
                    confidence: Box::new(confidence),
                    relations,
                    duplicate_of: document.duplicate_of(id),
                    solve: Box::new(solve),
                }
            }
            Err(reason) => {
                let skipped = skip(reason);
                document.skipped.push(skipped.clone());
                StepOutcome::Skipped(skipped)
            }
        });
        if let Some(done) = outcomes.last() {
            on_step(index, done);
        }
    }
    (document, outcomes)
}

/// A part's id with the samples of one stroke it took (`None`: the whole stroke).
type Taken = (u32, Option<Vec<DVec2>>);

/// What [`Document::owner`] tells a new snap: per stroke, each part with the samples it
/// took (`None`: the whole stroke), and where each part lies.
struct Owners {
    strokes: BTreeMap<StrokeId, Vec<Taken>>,
    poses: BTreeMap<u32, Primitive>,
}

impl Owner for Owners {
    fn owner(&self, stroke: StrokeId, sample: DVec2) -> Option<u32> {
        self.strokes.get(&stroke).and_then(|list| {
            list.iter()
                .find(|(_, samples)| {
                    samples.as_ref().is_none_or(|s| {
                        // Both snaps take the same evenly chosen samples of a stroke
                        // (`stroke_samples`), so a taken sample is found again exactly
                        // (up to rounding).
                        s.iter().any(|q| {
                            q.distance_squared(sample) <= 1e-12 * (1.0 + q.length_squared())
                        })
                    })
                })
                .map(|(p, _)| *p)
        })
    }

    fn pose(&self, part: u32) -> Option<Primitive> {
        self.poses.get(&part).cloned()
    }
}

/// Marks `part` as owning the whole stroke in `entry`.
fn entry_whole(entry: &mut [Taken], part: u32) {
    if let Some(e) = entry.iter_mut().find(|(p, _)| *p == part) {
        e.1 = None;
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::{
        Document, Fit, LengthUnit, Placed, PrimitiveId, Relation, RelationError, RelationId,
    };
    use crate::primitive::{Cylinder, Feature, Primitive, PrimitiveKind, Sphere};
    use crate::relation::{Mode, RelationKind};

    fn rod(x: f64) -> Placed {
        Placed {
            primitive: Primitive::Cylinder(Cylinder {
                center: DVec3::new(x, 0.0, 0.0),
                axis: DVec3::Y,
                length: 10.0,
                radius: 1.0,
            }),
            fit: Fit::default(),
        }
    }

    fn parallel(a: PrimitiveId, b: PrimitiveId) -> Relation {
        Relation {
            kind: RelationKind::Parallel,
            members: vec![a, b],
            features: vec![Some(Feature::Top), Some(Feature::Top)],
            mode: Mode::Hard,
            inferred: None,
        }
    }

    /// A document of three rods related in a chain and once across.
    fn related() -> (Document, [RelationId; 3]) {
        let mut doc = Document::new();
        let [a, b, c] = [0.0, 5.0, 10.0].map(|x| doc.add(rod(x)));
        let ids =
            [(a, b), (b, c), (a, c)].map(|(m, n)| doc.add_relation(parallel(m, n)).expect("valid"));
        (doc, ids)
    }

    #[test]
    fn removing_a_relation_leaves_the_others_ids_unchanged() {
        let (mut doc, [ab, bc, ac]) = related();
        assert_eq!([ab, bc, ac], [RelationId(0), RelationId(1), RelationId(2)]);
        let kept = [ab, ac].map(|id| doc.relation(id).cloned());
        assert!(doc.remove_relation(bc).is_some());
        assert_eq!(doc.remove_relation(bc), None, "removed once");
        assert_eq!(doc.relation(bc), None);
        assert_eq!([ab, ac].map(|id| doc.relation(id).cloned()), kept);
        assert_eq!(doc.relation_position(ac), Some(1), "listed second now");
        let ids: Vec<RelationId> = doc.relations_with_ids().map(|(id, _)| id).collect();
        assert_eq!(ids, [ab, ac]);
        let (a, b) = (PrimitiveId(0), PrimitiveId(1));
        assert_eq!(
            doc.add_relation(parallel(a, b)).expect("valid"),
            RelationId(3),
            "ids are not reused"
        );
        // Removing a part removes its relations; the others keep their ids.
        doc.remove(PrimitiveId(2));
        let ids: Vec<RelationId> = doc.relations_with_ids().map(|(id, _)| id).collect();
        assert_eq!(ids, [ab, RelationId(3)]);
    }

    #[test]
    fn a_relation_id_survives_removal_and_undo() {
        let (mut doc, [ab, bc, ac]) = related();
        let snapshot = doc.clone();
        doc.remove_relation(ab);
        doc.relation_mut(ac).expect("kept").mode = Mode::Off;
        // Undo restores the snapshot: every relation is back under its id.
        doc = snapshot;
        for (id, members) in [(ab, [0, 1]), (bc, [1, 2]), (ac, [0, 2])] {
            let relation = doc.relation(id).expect("back");
            assert_eq!(relation.members, members.map(PrimitiveId), "{id:?}");
        }
        assert_eq!(doc.relation(ac).expect("back").mode, Mode::Hard);
    }

    #[test]
    fn a_relation_is_refused_with_a_typed_error() {
        let mut doc = Document::new();
        let a = doc.add(rod(0.0));
        let ball = doc.add(Placed {
            primitive: Primitive::Sphere(Sphere {
                center: DVec3::ZERO,
                radius: 1.0,
            }),
            fit: Fit::default(),
        });
        let mut r = parallel(a, ball);
        assert_eq!(
            doc.add_relation(r.clone()),
            Err(RelationError::ForeignFeature {
                member: ball,
                kind: PrimitiveKind::Sphere,
                feature: Feature::Top,
            })
        );
        r.members[1] = a;
        let error = doc.add_relation(r.clone()).expect_err("a part with itself");
        assert_eq!(
            error,
            RelationError::RepeatedMember {
                kind: RelationKind::Parallel,
                member: a,
            }
        );
        r.members[1] = PrimitiveId(9);
        assert_eq!(
            doc.add_relation(r.clone()),
            Err(RelationError::MissingPrimitive { id: PrimitiveId(9) })
        );
        r.members.pop();
        let error = doc.add_relation(r).expect_err("one member");
        assert_eq!(
            error.to_string(),
            "a parallel relation relates 2 primitives, not 1"
        );
        assert!(doc.relations().is_empty(), "nothing was added");
    }

    #[test]
    fn a_relation_without_features_takes_the_documented_default_or_is_refused() {
        let mut doc = Document::new();
        let (a, b) = (doc.add(rod(0.0)), doc.add(rod(5.0)));
        let ball = doc.add(Placed {
            primitive: Primitive::Sphere(Sphere {
                center: DVec3::new(0.0, 20.0, 0.0),
                radius: 3.0,
            }),
            fit: Fit::default(),
        });
        let bare = |kind, members: Vec<PrimitiveId>| Relation {
            kind,
            members,
            features: Vec::new(),
            mode: Mode::Hard,
            inferred: None,
        };
        // A rod's axis: either end gives it, so `top` is used.
        let id = doc
            .add_relation(bare(RelationKind::Parallel, vec![a, b]))
            .expect("defaulted");
        let features = &doc.relation(id).expect("added").features;
        assert_eq!(features, &[Some(Feature::Top), Some(Feature::Top)]);
        // A sphere has one feature; the rod's end is not clear for a sphere contact.
        let on_sphere = doc.add_relation(bare(RelationKind::OnSphere, vec![ball, a]));
        assert_eq!(
            on_sphere,
            Err(RelationError::MissingFeature {
                kind: RelationKind::OnSphere,
                member: a,
                primitive: PrimitiveKind::Cylinder,
            })
        );
        let mut named = bare(RelationKind::OnSphere, vec![ball, a]);
        named.features = vec![None, Some(Feature::Bottom)];
        let id = doc
            .add_relation(named)
            .expect("the sphere's outline is its only feature");
        let features = &doc.relation(id).expect("added").features;
        assert_eq!(features, &[Some(Feature::Outline), Some(Feature::Bottom)]);
        // Which ends are concentric is never guessed.
        let error = doc
            .add_relation(bare(RelationKind::Concentric, vec![a, b]))
            .expect_err("no default end");
        assert!(
            error.to_string().contains("must name the feature"),
            "{error}"
        );
        // Equal length needs no feature.
        doc.add_relation(bare(RelationKind::EqualLength, vec![a, b]))
            .expect("lengths");
        // A named feature of the wrong sort: a box face has no centre circle.
        let brick = doc.add(Placed {
            primitive: Primitive::Cuboid(crate::primitive::Cuboid {
                center: DVec3::new(0.0, -10.0, 0.0),
                rotation: glam::DQuat::IDENTITY,
                size: DVec3::new(8.0, 2.0, 8.0),
            }),
            fit: Fit::default(),
        });
        let mut face = bare(RelationKind::Concentric, vec![a, brick]);
        face.features = vec![
            Some(Feature::Bottom),
            Some(Feature::face(crate::primitive::Axis::Y, true)),
        ];
        let error = doc.add_relation(face).expect_err("a face is no circle");
        assert!(matches!(error, RelationError::Unsuited { .. }), "{error}");
        assert_eq!(doc.relations().len(), 3, "only the valid ones were added");
    }

    #[test]
    fn ids_are_stable_and_never_reused() {
        let placed = Placed {
            primitive: Primitive::Sphere(Sphere {
                center: DVec3::ZERO,
                radius: 1.0,
            }),
            fit: Fit::default(),
        };
        let mut doc = Document::new();
        let a = doc.add(placed.clone());
        let b = doc.add(placed.clone());
        assert!(doc.remove(a).is_some());
        let c = doc.add(placed.clone());
        assert_eq!((a, b, c), (PrimitiveId(0), PrimitiveId(1), PrimitiveId(2)));
        doc.insert(PrimitiveId(10), placed.clone());
        assert_eq!(doc.add(placed), PrimitiveId(11));
        assert_eq!(doc.len(), 4);
    }

    #[test]
    fn names_belong_to_their_parts_and_go_with_them() {
        let placed = Placed {
            primitive: Primitive::Sphere(Sphere {
                center: DVec3::ZERO,
                radius: 1.0,
            }),
            fit: Fit::default(),
        };
        let mut doc = Document::new();
        let a = doc.add(placed.clone());
        let b = doc.add(placed);
        assert!(doc.set_name(a, "  Knob\n"));
        assert_eq!(doc.name(a), Some("Knob"), "cleaned");
        assert_eq!(doc.name(b), None);
        assert!(!doc.set_name(PrimitiveId(9), "ghost"), "no such part");
        assert_eq!(doc.name(PrimitiveId(9)), None);
        let named = doc.clone();
        assert!(doc.set_name(a, "   "));
        assert_eq!(doc.name(a), None, "a blank name takes the name away");
        assert_ne!(doc, named, "names are part of the document");
        assert!(doc.set_name(a, "Knob"));
        doc.remove(a);
        let c = doc.add(doc.get(b).cloned().expect("b"));
        assert_eq!(doc.name(c), None, "a removed part's name does not linger");
        assert_eq!(doc.unit(), LengthUnit::Millimetre);
        doc.set_unit(LengthUnit::Inch);
        assert_eq!(doc.unit(), LengthUnit::Inch);
    }
}
