//! Dragging a primitive: from the palette, or a placed part being re-snapped. While the
//! drag moves, its snapped preview is asked of the preview thread; on release over the
//! canvas the snap, inference and solve run as a job ([`super::worker`]).

use std::time::Duration;

use glam::DVec2;

use super::worker::{self, Free, PreviewRequest, PreviewResult, Readings};
use super::GeosnapApp;
use crate::core::model::PrimitiveId;
use crate::core::primitive::{Placement, Primitive, PrimitiveKind, DEFAULT_SIZE_FRACTION};
use crate::core::snap::{SnapError, SnapResult};

/// A primitive being dragged: from the palette, or a placed part being re-snapped.
#[derive(Clone, Debug)]
pub struct Drag {
    /// Its kind.
    pub(super) kind: PrimitiveKind,
    /// The part it replaces on release (a re-drag).
    pub(super) replacing: Option<PrimitiveId>,
    /// Where the cursor puts it, with the size and axis the wheel set.
    pub(super) placement: Placement,
    /// The part's own shape when re-dragging (moved with the cursor).
    original: Option<Primitive>,
    /// Whether the cursor is over the canvas.
    pub(super) over_canvas: bool,
    /// The newest preview request.
    generation: u64,
    /// The newest snapped preview.
    preview: Option<SnapResult>,
    /// Why the newest frame did not snap.
    preview_error: Option<SnapError>,
    /// How long the newest preview took to snap.
    preview_time: Duration,
    /// The apparent size of a new primitive: read off the strokes under the cursor when
    /// it enters the drawing, then scaled by the wheel.
    size: Option<f64>,
    /// Where `size` was read off the strokes (`None` once the user has scaled it).
    sized_at: Option<DVec2>,
    /// The request the newest preview answers (equal to `generation` when it is up to
    /// date).
    preview_generation: u64,
    /// For a point drop, the guess (the drop sized and turned by the drawing) the newest
    /// preview came from.
    guess: Option<Primitive>,
    /// The poses the newest cold snap found (its choice, then the alternatives), for
    /// Tab; empty before the first snap.
    poses: Vec<SnapResult>,
    /// The pose shown: 0 is the newest preview (a warm frame refines the cold snap's
    /// choice); another is held until the strokes under the cursor change.
    shown: usize,
}

impl Drag {
    /// A drag of a new primitive of `kind`, not yet over the canvas, with no preview.
    fn new(kind: PrimitiveKind, placement: Placement) -> Self {
        Self {
            kind,
            replacing: None,
            placement,
            original: None,
            over_canvas: false,
            generation: 0,
            preview: None,
            preview_error: None,
            preview_time: Duration::ZERO,
            size: None,
            sized_at: None,
            preview_generation: 0,
            guess: None,
            poses: Vec::new(),
            shown: 0,
        }
    }

    /// Its kind.
    pub fn kind(&self) -> PrimitiveKind {
        self.kind
    }

    /// Whether it is a point drop: a new part whose size was read off the strokes under
    /// the cursor and that the wheel has neither sized nor turned. The drawing then sizes
    /// and turns it (`snap_at`), as a script step that gives only a point.
    pub fn is_point(&self) -> bool {
        self.original.is_none() && self.sized_at.is_some()
    }

    /// The newest preview request.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The request the newest preview answers (equal to [`Self::generation`] when it is
    /// up to date).
    pub fn preview_generation(&self) -> u64 {
        self.preview_generation
    }

    /// The snapped preview shown: the newest, or the pose Tab chose.
    pub fn preview(&self) -> Option<&SnapResult> {
        match self.shown {
            0 => self.preview.as_ref(),
            k => self.poses.get(k),
        }
    }

    /// The pose shown and how many the snap found (Tab shows the next): `(1, 1)` when
    /// it found one, `(0, 0)` before the first snap.
    pub fn pose(&self) -> (usize, usize) {
        if self.preview.is_none() {
            return (0, 0);
        }
        (self.shown + 1, self.poses.len().max(1))
    }

    /// Shows the next pose the snap found (after the last, the first again); whether
    /// there was another.
    pub fn next_pose(&mut self) -> bool {
        if self.preview.is_none() || self.poses.len() < 2 {
            return false;
        }
        self.shown = (self.shown + 1) % self.poses.len();
        true
    }

    /// The poses to release with, the shown one as the preview shows it, dropped as
    /// `dropped`; `None` when the preview lags behind the cursor and no other pose was
    /// chosen (the release then snaps afresh where it is).
    fn readings(&self, dropped: Primitive) -> Option<Readings> {
        let current = self.preview_generation == self.generation;
        if self.preview.is_none() || (self.shown == 0 && !current) {
            return None;
        }
        let mut poses = self.poses.clone();
        if let (Some(first), Some(newest)) = (poses.first_mut(), self.preview.as_ref()) {
            if self.shown == 0 {
                // The newest frame as shown; a warm frame keeps the cold snap's rival
                // readings, which the confidence compares it with.
                let mut shown = newest.clone();
                if shown.explained.is_none() {
                    shown.explained = first.explained;
                    shown.alternatives.clone_from(&first.alternatives);
                }
                *first = shown;
            }
        }
        if poses.is_empty() {
            poses.extend(self.preview.clone());
        }
        Some(Readings {
            dropped,
            poses,
            shown: self.shown,
            by_hand: self.shown != 0,
        })
    }

    /// Why the newest frame did not snap.
    pub fn preview_error(&self) -> Option<&SnapError> {
        self.preview_error.as_ref()
    }

    /// How long the newest preview took to snap.
    pub fn preview_time(&self) -> Duration {
        self.preview_time
    }

    /// Takes in a finished preview, unless it answers a request newer than the drag's.
    pub(super) fn take_preview(&mut self, result: PreviewResult) {
        if result.generation > self.generation {
            return;
        }
        self.preview_time = result.elapsed;
        self.preview_generation = result.generation;
        self.guess = result.guess;
        match result.result {
            Ok(snapped) => {
                // A cold snap (other strokes under the cursor, a new size or axis) reads
                // the drawing afresh: its poses replace the last ones. A warm frame
                // confirms the choice and keeps them, and the pose Tab chose.
                if snapped.explained.is_some() {
                    self.poses = Readings::of(snapped.primitive.clone(), &snapped).poses;
                    self.shown = 0;
                }
                self.preview = Some(snapped);
                self.preview_error = None;
            }
            Err(error) => {
                self.preview = None;
                self.preview_error = Some(error);
                self.poses.clear();
                self.shown = 0;
            }
        }
    }
}

/// The apparent size of the drawn object under `at`: the larger extent of the strokes
/// passing within `reach` of it (a primitive dropped there starts that big), within
/// a third to three times `reach`; `reach` when no stroke is near.
pub fn size_under(sketch: &crate::core::sketch::Sketch, at: DVec2, reach: f64) -> f64 {
    let near = sketch
        .strokes
        .iter()
        .filter(|s| s.points.iter().any(|p| p.distance(at) <= reach));
    let bounds = near
        .flat_map(|s| s.points.iter())
        .fold(None, |acc: Option<(DVec2, DVec2)>, p| {
            Some(acc.map_or((*p, *p), |(lo, hi)| (lo.min(*p), hi.max(*p))))
        });
    match bounds {
        Some((lo, hi)) => (hi - lo).max_element().clamp(reach / 3.0, reach * 3.0),
        None => reach,
    }
}

impl GeosnapApp {
    /// The primitive being dragged.
    pub fn drag(&self) -> Option<&Drag> {
        self.drag.as_ref()
    }

    /// The size a dropped primitive starts with: a fraction of the drawing.
    pub fn default_size(&self) -> f64 {
        let sketch = self.editor.sketch();
        sketch
            .view_box
            .map(|(_, size)| size.max_element())
            .or_else(|| sketch.bounds().map(|(lo, hi)| (hi - lo).max_element()))
            .unwrap_or(100.0)
            * DEFAULT_SIZE_FRACTION
    }

    /// Starts dragging a new primitive of `kind` (from the palette).
    pub fn begin_drag(&mut self, kind: PrimitiveKind) {
        if self.busy() || self.loading.is_some() {
            return;
        }
        self.drag = Some(Drag::new(kind, Placement::at(DVec2::ZERO)));
    }

    /// Starts re-dragging a placed part.
    pub fn begin_redrag(&mut self, id: PrimitiveId, at: DVec2) {
        if self.busy() || self.loading.is_some() {
            return;
        }
        let Some(placed) = self.editor.document().get(id) else {
            return;
        };
        let primitive = placed.primitive.clone();
        let centre = primitive.center();
        let grab = at - DVec2::new(centre.x, -centre.y);
        let kind = primitive.kind();
        self.drag = Some(Drag {
            replacing: Some(id),
            original: Some(primitive),
            over_canvas: true,
            ..Drag::new(kind, Placement::at(at - grab))
        });
    }

    /// The primitive the drag puts under the cursor, before snapping.
    pub fn dragged_primitive(&self) -> Option<Primitive> {
        let drag = self.drag.as_ref()?;
        Some(match &drag.original {
            Some(original) => {
                let c = original.center();
                let target = drag.placement.at;
                let scale = drag.placement.length.unwrap_or(1.0);
                original
                    .transformed(-c, 1.0)
                    .transformed(glam::DVec3::ZERO, scale)
                    .transformed(glam::DVec3::new(target.x, -target.y, c.z), 1.0)
            }
            None => Primitive::from_placement(
                drag.kind,
                &drag.placement,
                drag.size.unwrap_or_else(|| self.default_size()),
            ),
        })
    }

    /// Moves the drag to sketch point `at` and asks for its snapped preview.
    pub fn drag_to(&mut self, at: DVec2, over_canvas: bool) {
        let Some(drag) = self.drag.as_mut() else {
            return;
        };
        let moved = drag.placement.at != at || drag.over_canvas != over_canvas;
        drag.placement.at = at;
        drag.over_canvas = over_canvas;
        if drag.original.is_none() && over_canvas {
            let far = match (drag.sized_at, drag.size) {
                (Some(from), Some(size)) => from.distance(at) > size * 0.5,
                (None, Some(_)) => false,
                _ => true,
            };
            if far {
                let fallback = self.default_size();
                let Some(drag) = self.drag.as_mut() else {
                    return;
                };
                drag.size = Some(size_under(self.editor.sketch(), at, fallback));
                drag.sized_at = Some(at);
            }
        }
        if moved && over_canvas {
            self.request_preview();
        }
    }

    fn request_preview(&mut self) {
        let Some(dragged) = self.dragged_primitive() else {
            return;
        };
        let moving = self.drag.as_ref().and_then(|d| d.replacing);
        let (context, context_revision) = self.workers.context(&self.editor, moving);
        let Some(drag) = self.drag.as_mut() else {
            return;
        };
        drag.generation += 1;
        let point = drag.is_point();
        self.workers.request_preview(PreviewRequest {
            generation: drag.generation,
            dragged,
            context,
            context_revision,
            point,
        });
    }

    /// Scales the dragged primitive (wheel) or turns its axis (Shift + wheel).
    pub fn adjust_drag(&mut self, scale: f64, turn: f64) {
        let default = self.default_size();
        let Some(drag) = self.drag.as_mut() else {
            return;
        };
        if drag.original.is_some() {
            let s = drag.placement.length.unwrap_or(1.0) * scale;
            drag.placement.length = Some(s.clamp(0.1, 10.0));
        } else {
            let size = drag.size.unwrap_or(default) * scale;
            drag.size = Some(size.clamp(default * 0.02, default * 20.0));
            drag.sized_at = None;
        }
        if turn != 0.0 {
            let (s, c) = turn.sin_cos();
            let a = drag.placement.axis;
            drag.placement.axis = DVec2::new(a.x * c - a.y * s, a.x * s + a.y * c);
        }
        self.request_preview();
    }

    /// Ends the drag: over the canvas it snaps, infers and solves in the background;
    /// elsewhere it is dropped.
    pub fn end_drag(&mut self) {
        self.finish_drag(false);
    }

    /// Ends the drag without snapping (Alt + drop): over the canvas the part is placed
    /// as dragged, unsnapped, as one undo step; elsewhere it is dropped.
    pub fn end_drag_freely(&mut self) {
        self.finish_drag(true);
    }

    fn finish_drag(&mut self, freely: bool) {
        self.workers.clear_preview();
        let Some(dragged) = self.dragged_primitive() else {
            return;
        };
        let Some(drag) = self.drag.take() else {
            return;
        };
        if !drag.over_canvas {
            return;
        }
        let (context, _) = self.workers.context(&self.editor, drag.replacing);
        let document = self.editor.document().clone();
        let settings = self.editor.settings().clone();
        let replacing = drag.replacing;
        self.canvas.dropped(drag.placement.at);
        let noun = super::words::kind_noun(drag.kind);
        if freely {
            let label = match replacing {
                Some(id) => format!(
                    "Move {} freely",
                    super::words::part_name(self.editor.document(), id)
                ),
                None => format!("Place {noun} freely"),
            };
            self.workers
                .spawn(label, self.editor.revision(), move |cancel, observe| {
                    let free = Free {
                        replacing,
                        name: None,
                        why: "Alt was held",
                    };
                    worker::place_freely(document, &dragged, &free, &settings, cancel, observe)
                });
            return;
        }
        // The pose the preview shows is placed as it is; a preview behind the cursor (of
        // an earlier pointer position, perhaps over other strokes) is not used: the part
        // is snapped afresh from where it was dropped.
        // A point drop's poses were found from the guess the drawing sized and turned:
        // that guess stands for the drop in the confidence.
        let point = drag.is_point();
        let readings = drag.readings(drag.guess.clone().unwrap_or_else(|| dragged.clone()));
        let (start, point) = match (&readings, drag.preview.as_ref()) {
            (Some(_), Some(p)) => (p.primitive.clone(), false),
            _ => (dragged, point),
        };
        let label = match replacing {
            Some(id) => format!(
                "Move {}",
                super::words::part_name(self.editor.document(), id)
            ),
            None => format!("Place {noun}"),
        };
        let unit = self.unit();
        self.workers
            .spawn(label, self.editor.revision(), move |cancel, observe| {
                worker::place(
                    document,
                    &context,
                    (&start, point),
                    readings,
                    replacing,
                    (&settings, unit),
                    cancel,
                    observe,
                )
            });
    }

    /// Tab: the next pose the snap found, for the drag, or else for the selected part
    /// (placed again in that pose, inferred and solved: one undo step).
    pub fn next_pose(&mut self) {
        if let Some(drag) = self.drag.as_mut() {
            // Shown at once by the preview, the hint and the legend.
            drag.next_pose();
            return;
        }
        let Some(id) = self.selection else { return };
        if self.busy() {
            return;
        }
        let Some(readings) = self.readings.get(&id).map(Readings::next) else {
            return;
        };
        let (context, _) = self.workers.context(&self.editor, Some(id));
        let document = self.editor.document().clone();
        let settings = self.editor.settings().clone();
        let label = format!(
            "{} pose {} of {}",
            super::words::part_name(self.editor.document(), id),
            readings.shown + 1,
            readings.poses.len()
        );
        let dropped = readings.dropped.clone();
        let unit = self.unit();
        self.workers
            .spawn(label, self.editor.revision(), move |cancel, observe| {
                worker::place(
                    document,
                    &context,
                    (&dropped, false),
                    Some(readings),
                    Some(id),
                    (&settings, unit),
                    cancel,
                    observe,
                )
            });
    }

    /// The poses the snap found for part `id` (placed this session), with the one it
    /// shows; `None` when there was no choice.
    pub fn part_poses(&self, id: PrimitiveId) -> Option<(usize, usize)> {
        self.readings.get(&id).map(|r| (r.shown + 1, r.poses.len()))
    }

    /// Drops the drag without placing anything.
    pub fn cancel_drag(&mut self) {
        self.workers.clear_preview();
        self.drag = None;
    }

    /// Takes in the newest finished preview, if the drag is still on.
    pub(super) fn poll_preview(&mut self) {
        if let Some(result) = self.workers.latest_preview() {
            if let Some(drag) = self.drag.as_mut() {
                drag.take_preview(result);
            }
        }
    }

    /// Moves the drag to a placement (centre, axis and size), as a script step played
    /// with `--play` places it.
    pub fn place_drag(&mut self, placement: Placement) {
        if let Some(drag) = self.drag.as_mut() {
            drag.placement = placement;
            drag.over_canvas = true;
        }
    }
}
