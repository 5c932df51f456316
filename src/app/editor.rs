//! The editor's state without any GUI: the sketch, the document, the user's settings and
//! the undo history. Every change of the work goes through one method here, which records
//! one undo step, so the egui layer only decides *when* an action happens. Changes that
//! need a solve first are proposed (a changed copy of the model, solved off the UI
//! thread) and then applied as one step with [`Editor::apply_document`].

use std::path::PathBuf;

use glam::DVec2;

use crate::core::model::{
    DimensionError, Document, Fit, LengthUnit, Placed, PrimitiveId, Quantity, RelationId,
    SessionSettings,
};
use crate::core::relation::Mode;
use crate::core::sketch::{Sketch, Stroke, StrokeClass, StrokeId};

/// The most undo steps kept; older ones are dropped.
const MAX_UNDO: usize = 200;

/// What one undo step restores.
#[derive(Clone, Debug)]
struct Snapshot {
    label: String,
    sketch: Sketch,
    image: Option<PathBuf>,
    document: Document,
    revision: u64,
}

/// The work: strokes, reference image, model, where it is saved, and its history.
#[derive(Clone, Debug, Default)]
pub struct Editor {
    /// The strokes.
    sketch: Sketch,
    /// The reference image under the strokes.
    image: Option<PathBuf>,
    /// The model.
    document: Document,
    /// Snapping, inference and solve settings.
    settings: SessionSettings,
    /// The unit new work starts in (a preference: the last unit chosen).
    default_unit: LengthUnit,
    /// Where the session was last saved or opened from.
    path: Option<PathBuf>,
    /// The drawing the work was opened from (a sketch or SVG file), when it is not a
    /// session.
    origin: Option<PathBuf>,
    undo: Vec<Snapshot>,
    redo: Vec<Snapshot>,
    /// Bumped by every change; the saved revision tells whether there are unsaved changes.
    revision: u64,
    saved: u64,
    /// Whether the work is unsaved whatever its revision (recovered from an autosave).
    unsaved: bool,
    /// Bumped when the strokes change, so snapping contexts can be rebuilt.
    strokes_revision: u64,
}

impl Editor {
    /// An editor over a sketch, with an empty model and no history.
    pub fn with_sketch(sketch: Sketch, image: Option<PathBuf>) -> Self {
        Self {
            sketch,
            image,
            ..Self::default()
        }
    }

    /// The strokes.
    pub fn sketch(&self) -> &Sketch {
        &self.sketch
    }

    /// The reference image under the strokes.
    pub fn image(&self) -> Option<&PathBuf> {
        self.image.as_ref()
    }

    /// The model.
    pub fn document(&self) -> &Document {
        &self.document
    }

    /// Snapping, inference and solve settings.
    pub fn settings(&self) -> &SessionSettings {
        &self.settings
    }

    /// The settings, to change (they are preferences, not part of the work's history).
    pub fn settings_mut(&mut self) -> &mut SessionSettings {
        &mut self.settings
    }

    /// The unit new work starts in (a preference, not part of the work's history).
    pub fn default_unit(&self) -> LengthUnit {
        self.default_unit
    }

    /// Sets the unit new work starts in; the open work keeps its own.
    pub fn set_default_unit(&mut self, unit: LengthUnit) {
        self.default_unit = unit;
    }

    /// Sets the document's unit (one undo step; the numbers stay as they are, what they
    /// mean changes) and makes it the unit of new work too. Whether it changed.
    pub fn set_unit(&mut self, unit: LengthUnit) -> bool {
        self.default_unit = unit;
        if self.document.unit() == unit {
            return false;
        }
        self.checkpoint(&format!("Lengths in {}", unit.name()));
        self.document.set_unit(unit);
        true
    }

    /// Names part `id` (one undo step); an empty or blank name takes its name away.
    /// Whether the name changed (a missing part, or the same name, changes nothing).
    pub fn rename_primitive(&mut self, id: PrimitiveId, name: &str) -> bool {
        if self.document.get(id).is_none() {
            return false;
        }
        let name = crate::core::model::clean_name(name);
        if self.document.name(id) == name.as_deref() {
            return false;
        }
        let before = super::words::part_name(&self.document, id);
        let label = match &name {
            Some(name) => format!("Rename {before} to “{name}”"),
            None => format!("Remove the name of {before}"),
        };
        self.checkpoint(&label);
        self.document
            .set_name(id, name.as_deref().unwrap_or_default());
        true
    }

    /// Where the session was last saved or opened from.
    pub fn path(&self) -> Option<&PathBuf> {
        self.path.as_ref()
    }

    /// The file the work came from: the session's path, or else the drawing it was
    /// opened from.
    pub fn origin(&self) -> Option<&PathBuf> {
        self.path.as_ref().or(self.origin.as_ref())
    }

    /// Records the drawing the work was opened from (it is not where it is saved).
    pub fn set_origin(&mut self, drawing: PathBuf) {
        self.origin = Some(drawing);
    }

    /// The change counter (every action increments it; undo restores older values).
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// The strokes' change counter.
    pub fn strokes_revision(&self) -> u64 {
        self.strokes_revision
    }

    /// Whether there are changes since the last save (or since opening).
    pub fn is_dirty(&self) -> bool {
        self.unsaved || self.revision != self.saved
    }

    /// Records that the current state was saved to `path`.
    pub fn mark_saved(&mut self, path: PathBuf) {
        self.path = Some(path);
        self.saved = self.revision;
        self.unsaved = false;
    }

    /// Records that the work is not saved anywhere (recovered from an autosave), so
    /// closing or opening asks first, until it is saved.
    pub fn mark_unsaved(&mut self) {
        self.unsaved = true;
    }

    /// The label of the step [`Self::undo`] would take back.
    pub fn undo_label(&self) -> Option<&str> {
        self.undo.last().map(|s| s.label.as_str())
    }

    /// The label of the step [`Self::redo`] would do again.
    pub fn redo_label(&self) -> Option<&str> {
        self.redo.last().map(|s| s.label.as_str())
    }

    fn snapshot(&self, label: &str) -> Snapshot {
        Snapshot {
            label: label.to_owned(),
            sketch: self.sketch.clone(),
            image: self.image.clone(),
            document: self.document.clone(),
            revision: self.revision,
        }
    }

    /// Records the current state as one undo step named `label`, before a change.
    fn checkpoint(&mut self, label: &str) {
        self.undo.push(self.snapshot(label));
        if self.undo.len() > MAX_UNDO {
            self.undo.remove(0);
        }
        self.redo.clear();
        self.revision = self.revision.max(self.max_revision()) + 1;
    }

    /// The largest revision ever handed out (so an undone-then-changed state never takes
    /// the saved revision's number by accident).
    fn max_revision(&self) -> u64 {
        self.undo
            .iter()
            .chain(&self.redo)
            .map(|s| s.revision)
            .max()
            .unwrap_or(0)
            .max(self.saved)
    }

    /// Replaces the model by `document` as one undo step (a placement with its snap and
    /// solve, a re-solve after a mode change, ...).
    pub fn apply_document(&mut self, label: &str, document: Document) {
        self.checkpoint(label);
        self.document = document;
    }

    /// Takes back the last step; returns its label.
    pub fn undo(&mut self) -> Option<String> {
        let snapshot = self.undo.pop()?;
        let (label, current) = self.swap(snapshot);
        self.redo.push(current);
        Some(label)
    }

    /// Does the last undone step again; returns its label.
    pub fn redo(&mut self) -> Option<String> {
        let snapshot = self.redo.pop()?;
        let (label, current) = self.swap(snapshot);
        self.undo.push(current);
        Some(label)
    }

    /// Restores `snapshot` and returns its label with the state it replaced, under the
    /// same label (for the opposite stack).
    fn swap(&mut self, snapshot: Snapshot) -> (String, Snapshot) {
        let label = snapshot.label.clone();
        let current = self.snapshot(&label);
        self.restore(snapshot);
        (label, current)
    }

    fn restore(&mut self, snapshot: Snapshot) {
        if snapshot.sketch != self.sketch {
            self.strokes_revision += 1;
        }
        self.sketch = snapshot.sketch;
        self.image = snapshot.image;
        self.document = snapshot.document;
        self.revision = snapshot.revision;
    }

    /// Puts a reference image under the strokes (one undo step).
    pub fn set_image(&mut self, image: Option<PathBuf>) {
        if self.image != image {
            self.checkpoint("Reference image");
            self.image = image;
        }
    }

    /// Deletes a primitive with its relations.
    pub fn delete_primitive(&mut self, id: PrimitiveId) -> bool {
        if self.document.get(id).is_none() {
            return false;
        }
        self.checkpoint(&format!(
            "Delete {}",
            super::words::part_name(&self.document, id)
        ));
        self.document.remove(id);
        true
    }

    /// Sets a relation's mode without solving (the caller re-solves in the background
    /// and applies the result with [`Self::apply_document`] when it wants one step).
    pub fn relation_mode_changed(&self, id: RelationId, mode: Mode) -> Option<Document> {
        let mut document = self.document.clone();
        document.relation_mut(id)?.mode = mode;
        Some(document)
    }

    /// The model with part `id`'s `quantity` fixed at `value`, not yet solved (the
    /// caller re-solves the part in the background and applies the result with
    /// [`Self::apply_document`] as one step).
    ///
    /// # Errors
    ///
    /// When the part does not exist, has no such quantity, or the value is not a
    /// positive finite number ([`Document::set_dimension`]).
    pub fn dimension_set(
        &self,
        id: PrimitiveId,
        quantity: Quantity,
        value: f64,
    ) -> Result<Document, DimensionError> {
        let mut document = self.document.clone();
        document.set_dimension(id, quantity, value)?;
        Ok(document)
    }

    /// Frees part `id`'s `quantity` (one undo step); whether it was fixed.
    pub fn free_dimension(&mut self, id: PrimitiveId, quantity: Quantity) -> bool {
        let fixed = self
            .document
            .dimensions()
            .iter()
            .any(|d| d.primitive == id && d.quantity == quantity);
        if !fixed {
            return false;
        }
        self.checkpoint(&format!(
            "Free {}'s {}",
            super::words::part_name(&self.document, id),
            super::words::quantity_name(quantity)
        ));
        self.document.remove_dimension(id, quantity);
        true
    }

    /// Adds an unsnapped copy of part `id` beside it (one undo step); the copy's id.
    pub fn duplicate_primitive(&mut self, id: PrimitiveId) -> Option<PrimitiveId> {
        let primitive = self.document.get(id)?.primitive.clone();
        let offset = primitive.size() * 0.6;
        self.checkpoint(&format!(
            "Duplicate {}",
            super::words::part_name(&self.document, id)
        ));
        Some(self.document.add(Placed {
            primitive: primitive.transformed(glam::DVec3::new(offset, 0.0, 0.0), 1.0),
            fit: Fit::default(),
        }))
    }

    /// Deletes relation `id`.
    pub fn delete_relation(&mut self, id: RelationId) -> bool {
        if self.document.relation(id).is_none() {
            return false;
        }
        self.checkpoint("Delete relation");
        self.document.remove_relation(id);
        true
    }

    /// Adds a drawn stroke (sketch space), classified automatically; returns its id, or
    /// `None` for a stroke too short to keep.
    pub fn add_stroke(&mut self, points: Vec<DVec2>) -> Option<StrokeId> {
        if points.len() < 2 || points.iter().any(|p| !p.is_finite()) {
            return None;
        }
        let length: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
        if length <= 0.0 {
            return None;
        }
        self.checkpoint("Draw stroke");
        let id = self.sketch.next_id();
        self.sketch.strokes.push(Stroke {
            id,
            points,
            closed: false,
            class_override: None,
        });
        self.strokes_revision += 1;
        Some(id)
    }

    /// Erases a stroke; parts keep their fits (their records still name it, harmlessly).
    pub fn erase_stroke(&mut self, id: StrokeId) -> bool {
        let Some(index) = self.sketch.strokes.iter().position(|s| s.id == id) else {
            return false;
        };
        self.checkpoint("Erase stroke");
        self.sketch.strokes.remove(index);
        self.strokes_revision += 1;
        true
    }

    /// Overrides a stroke's class (`None` goes back to the automatic class).
    pub fn reclassify(&mut self, id: StrokeId, class: Option<StrokeClass>) -> bool {
        let Some(index) = self.sketch.strokes.iter().position(|s| s.id == id) else {
            return false;
        };
        if self.sketch.strokes[index].class_override == class {
            return false;
        }
        self.checkpoint("Reclassify stroke");
        self.sketch.strokes[index].class_override = class;
        self.strokes_revision += 1;
        true
    }

    /// Replaces the whole work (opening a file): history cleared, nothing unsaved; the
    /// preferences stay.
    pub fn replace(&mut self, sketch: Sketch, image: Option<PathBuf>, document: Document) {
        let settings = self.settings.clone();
        *self = Self {
            sketch,
            image,
            document,
            settings,
            default_unit: self.default_unit,
            strokes_revision: self.strokes_revision + 1,
            ..Self::default()
        };
    }

    /// Starts new work on a drawing ([`Self::replace`] with an empty model in the
    /// default unit).
    pub fn start(&mut self, sketch: Sketch, image: Option<PathBuf>) {
        let mut document = Document::new();
        document.set_unit(self.default_unit);
        self.replace(sketch, image, document);
    }
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::{Document, Editor};
    use crate::core::model::{Fit, Placed};
    use crate::core::primitive::{Primitive, Sphere};
    use crate::core::sketch::StrokeClass;

    fn ball() -> Placed {
        Placed {
            primitive: Primitive::Sphere(Sphere {
                center: DVec3::ZERO,
                radius: 3.0,
            }),
            fit: Fit::default(),
        }
    }

    #[test]
    fn every_action_is_one_undo_step_and_redo_restores_it() {
        let mut editor = Editor::default();
        assert!(!editor.is_dirty(), "a new editor has nothing to save");
        let stroke = editor
            .add_stroke(vec![DVec2::ZERO, DVec2::new(10.0, 0.0)])
            .expect("a stroke with length is kept");
        let mut doc = editor.document.clone();
        let id = doc.add(ball());
        editor.apply_document("Place sphere", doc);
        assert!(editor.reclassify(stroke, Some(StrokeClass::Feature)));
        assert!(editor.delete_primitive(id));
        assert!(editor.is_dirty(), "changes are unsaved");

        assert_eq!(editor.undo().as_deref(), Some("Delete Sphere 0"));
        assert!(
            editor.document.get(id).is_some(),
            "undo brings the part back"
        );
        assert_eq!(editor.undo().as_deref(), Some("Reclassify stroke"));
        assert_eq!(editor.sketch.strokes[0].class_override, None);
        assert_eq!(editor.undo().as_deref(), Some("Place sphere"));
        assert!(editor.document.is_empty(), "undo takes the placement back");
        assert_eq!(editor.redo().as_deref(), Some("Place sphere"));
        assert_eq!(editor.document.len(), 1, "redo places it again");
        assert_eq!(editor.undo().as_deref(), Some("Place sphere"));
        assert_eq!(editor.undo().as_deref(), Some("Draw stroke"));
        assert!(editor.sketch.strokes.is_empty());
        assert!(!editor.is_dirty(), "back at the opened state");
        assert_eq!(editor.undo(), None, "nothing more to undo");
    }

    #[test]
    fn a_new_action_after_undo_drops_the_redo_steps_and_stays_dirty() {
        let mut editor = Editor::default();
        editor.add_stroke(vec![DVec2::ZERO, DVec2::X]);
        editor.mark_saved("a.json".into());
        editor.add_stroke(vec![DVec2::ZERO, DVec2::Y]);
        editor.undo();
        assert!(!editor.is_dirty(), "undo back to the saved state");
        editor.add_stroke(vec![DVec2::ZERO, DVec2::NEG_Y]);
        assert!(
            editor.is_dirty(),
            "a different change is not the saved state"
        );
        assert_eq!(editor.redo(), None, "a new action drops the redo steps");
    }

    #[test]
    fn a_deleted_relation_comes_back_under_its_id_on_undo() {
        use crate::core::model::{PrimitiveId, Relation};
        use crate::core::primitive::Feature;
        use crate::core::relation::{Mode, RelationKind};

        let mut editor = Editor::default();
        let mut doc = editor.document.clone();
        let [a, b, c] = [0.0, 8.0, 16.0].map(|x| {
            let mut part = ball();
            part.primitive = part.primitive.transformed(DVec3::X * x, 1.0);
            doc.add(part)
        });
        let on = |m: PrimitiveId, n: PrimitiveId| Relation {
            kind: RelationKind::Concentric,
            members: vec![m, n],
            features: vec![Some(Feature::Outline), Some(Feature::Outline)],
            mode: Mode::Soft,
            inferred: None,
        };
        let first = doc.add_relation(on(a, b)).expect("valid");
        let second = doc.add_relation(on(b, c)).expect("valid");
        editor.apply_document("Relate", doc);
        assert!(editor.delete_relation(first));
        assert!(!editor.delete_relation(first), "deleted already");
        assert_eq!(
            editor.document.relation(second).map(|r| r.members.clone()),
            Some(vec![b, c]),
            "the other relation keeps its id"
        );
        assert_eq!(editor.undo().as_deref(), Some("Delete relation"));
        assert_eq!(
            editor.document.relation(first).map(|r| r.members.clone()),
            Some(vec![a, b]),
            "undo brings the relation back under its id"
        );
        assert_eq!(editor.document.relation_position(second), Some(1));
    }

    #[test]
    fn dimensions_and_duplicates_change_the_model_only_through_steps() {
        use crate::core::model::Quantity;
        let mut editor = Editor::default();
        let mut doc = editor.document.clone();
        let id = doc.add(ball());
        editor.apply_document("Place sphere", doc);

        let proposed = editor
            .dimension_set(id, Quantity::Radius, 5.0)
            .expect("a sphere has a radius");
        assert!(
            editor.document.dimensions().is_empty(),
            "a proposed dimension leaves the model as it is"
        );
        assert!(
            editor.dimension_set(id, Quantity::Radius, -1.0).is_err(),
            "a negative radius is refused"
        );
        editor.apply_document("#0 radius = 5", proposed);
        assert_eq!(editor.document.dimensions().len(), 1);
        assert!(editor.free_dimension(id, Quantity::Radius));
        assert!(editor.document.dimensions().is_empty(), "freed");
        assert!(
            !editor.free_dimension(id, Quantity::Radius),
            "nothing left to free"
        );
        assert_eq!(editor.undo_label(), Some("Free Sphere 0's radius"));

        let copy = editor.duplicate_primitive(id).expect("the part exists");
        assert_ne!(copy, id);
        assert_eq!(editor.document.len(), 2, "the copy is added");
        assert_eq!(editor.undo().as_deref(), Some("Duplicate Sphere 0"));
        assert_eq!(editor.document.len(), 1, "undo takes the copy back");
        assert_eq!(editor.undo().as_deref(), Some("Free Sphere 0's radius"));
        assert_eq!(editor.document.dimensions().len(), 1, "fixed again");
    }

    #[test]
    fn bad_strokes_are_refused_without_a_step() {
        let mut editor = Editor::default();
        assert_eq!(editor.add_stroke(vec![DVec2::ZERO]), None);
        assert_eq!(editor.add_stroke(vec![DVec2::ZERO, DVec2::ZERO]), None);
        assert_eq!(
            editor.add_stroke(vec![DVec2::ZERO, DVec2::new(f64::NAN, 1.0)]),
            None
        );
        assert_eq!(editor.undo_label(), None, "nothing was recorded");
    }

    #[test]
    fn a_rename_is_one_undo_step_and_blank_or_same_names_are_none() {
        let mut editor = Editor::default();
        let mut doc = editor.document.clone();
        let id = doc.add(ball());
        editor.apply_document("Place sphere", doc);
        assert!(editor.rename_primitive(id, "  Knob "));
        assert_eq!(editor.document.name(id), Some("Knob"));
        assert_eq!(editor.undo_label(), Some("Rename Sphere 0 to “Knob”"));
        assert!(!editor.rename_primitive(id, "Knob"), "the same name");
        assert!(!editor.rename_primitive(crate::core::model::PrimitiveId(7), "x"));
        assert_eq!(editor.undo_label(), Some("Rename Sphere 0 to “Knob”"));
        assert!(editor.rename_primitive(id, " \t"));
        assert_eq!(editor.document.name(id), None, "a blank name is no name");
        assert_eq!(editor.undo_label(), Some("Remove the name of Knob"));
        assert_eq!(editor.undo().as_deref(), Some("Remove the name of Knob"));
        assert_eq!(editor.document.name(id), Some("Knob"));
        assert_eq!(editor.undo().as_deref(), Some("Rename Sphere 0 to “Knob”"));
        assert_eq!(editor.document.name(id), None);
        assert_eq!(editor.redo().as_deref(), Some("Rename Sphere 0 to “Knob”"));
        assert_eq!(editor.document.name(id), Some("Knob"));
        let long = "ß".repeat(1000);
        assert!(editor.rename_primitive(id, &long));
        assert_eq!(
            editor.document.name(id).map(|n| n.chars().count()),
            Some(crate::core::model::MAX_NAME_CHARS)
        );
        assert!(editor
            .undo_label()
            .is_some_and(|l| l.starts_with("Rename Knob to")));
    }

    #[test]
    fn the_unit_is_the_documents_undoably_and_new_work_takes_the_last_one() {
        use crate::core::model::LengthUnit;
        let mut editor = Editor::default();
        assert_eq!(editor.document.unit(), LengthUnit::Millimetre);
        assert!(editor.set_unit(LengthUnit::Inch));
        assert!(!editor.set_unit(LengthUnit::Inch), "no change");
        assert!(editor.is_dirty(), "a change of the work");
        assert_eq!(editor.undo().as_deref(), Some("Lengths in inches"));
        assert_eq!(editor.document.unit(), LengthUnit::Millimetre);
        assert_eq!(
            editor.default_unit(),
            LengthUnit::Inch,
            "still the preference"
        );
        editor.start(crate::core::sketch::Sketch::default(), None);
        assert_eq!(editor.document.unit(), LengthUnit::Inch, "new work");
        assert!(!editor.is_dirty());
        let mut opened = Document::new();
        opened.set_unit(LengthUnit::Centimetre);
        editor.replace(crate::core::sketch::Sketch::default(), None, opened);
        assert_eq!(
            editor.document.unit(),
            LengthUnit::Centimetre,
            "a file's own"
        );
        assert_eq!(editor.default_unit(), LengthUnit::Inch);
    }
}
