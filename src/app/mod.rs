//! The desktop application (egui/eframe, wgpu backend): the whole workflow in one
//! window. A menu bar; on the left the palette and the tools; in the centre the sketch
//! canvas; on the right the 3D view, the relations and the properties; a status bar with
//! the solver's state.
//!
//! The state and every action live in [`editor::Editor`] (no GUI, one undo step per
//! action); snapping and solving run on worker threads ([`worker`]), newest request wins,
//! so the UI never waits for them.
//!
//! ```no_run
//! // Opens the window on the built-in sample (or a file), as `cargo run` does.
//! geosnap::app::run(geosnap::app::AppOptions::default())?;
//! # Ok::<(), anyhow::Error>(())
//! ```

mod canvas;
pub mod editor;
mod files;
mod panels;
mod view3d;
pub mod worker;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::anyhow;
use glam::DVec2;

use crate::core::model::{PrimitiveId, RelationId};
use crate::core::primitive::{Placement, Primitive, PrimitiveKind, DEFAULT_SIZE_FRACTION};
use crate::core::snap::{SnapContext, SnapResult};
use crate::io::svg::{import_svg, SvgOptions};
pub use canvas::CanvasView;
use editor::Editor;
use view3d::{Emphasis, View3d};
use worker::{Job, JobOutput, PreviewRequest, Previewer, Wake};

/// How the app starts.
#[derive(Clone, Debug, Default)]
pub struct AppOptions {
    /// A file to open (sketch, SVG, image or session); the built-in sample otherwise.
    pub file: Option<PathBuf>,
    /// Where autosaves go (default: the platform's data folder for geosnap).
    pub autosave_dir: Option<PathBuf>,
    /// Simulate a palette drag across the canvas for this many frames, write the frame
    /// times to this file and quit (the frame-time measurement of the README).
    pub drag_benchmark: Option<(usize, PathBuf)>,
    /// Save a screenshot of the window to this PNG after the first frames, and quit.
    pub screenshot: Option<PathBuf>,
    /// A placement script to play as drags on its sketch (demos and screenshots).
    pub play: Option<PathBuf>,
}

/// Opens the main window and runs until it is closed.
///
/// # Errors
///
/// When no window or graphics device can be had: the message says why and what to try.
pub fn run(options: AppOptions) -> anyhow::Result<()> {
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("geosnap")
            .with_inner_size([1280.0, 800.0])
            .with_min_inner_size([720.0, 480.0])
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        ..eframe::NativeOptions::default()
    };
    eframe::run_native(
        "geosnap",
        native,
        Box::new(move |cc| Ok(Box::new(GeosnapApp::new(cc, options)))),
    )
    .map_err(|error| {
        let text = error.to_string().trim_end_matches('.').to_owned();
        let hint = if text.contains("DISPLAY") {
            "There is no display to open a window on: run geosnap in a desktop session \
             (or set DISPLAY / WAYLAND_DISPLAY, e.g. under Xvfb)."
        } else {
            "geosnap draws with wgpu (Vulkan, Metal, DX12 or OpenGL, tried in turn). \
             Without a GPU, install a software driver (Debian: `apt-get install \
             mesa-vulkan-drivers`), or check that WGPU_BACKEND, if set, names a backend \
             this machine has (`WGPU_BACKEND=gl` for OpenGL)."
        };
        anyhow!(
            "the window could not be opened: {text}.\n{hint} The command line \
             (`geosnap --help`) works without a window."
        )
    })
}

/// The tools of the canvas.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Click a part to select it; drag a part to move and re-snap it.
    Select,
    /// Draw strokes.
    Draw,
    /// Click or drag over strokes to erase them.
    Erase,
    /// Click a stroke to switch it between feature and silhouette.
    Reclassify,
}

/// A primitive being dragged: from the palette, or a placed part being re-snapped.
#[derive(Clone, Debug)]
pub struct Drag {
    /// Its kind.
    pub kind: PrimitiveKind,
    /// The part it replaces on release (a re-drag).
    pub replacing: Option<PrimitiveId>,
    /// Where the cursor puts it, with the size and axis the wheel set.
    pub placement: Placement,
    /// The part's own shape when re-dragging (moved with the cursor).
    pub original: Option<Primitive>,
    /// Whether the cursor is over the canvas.
    pub over_canvas: bool,
    /// The newest preview request.
    pub generation: u64,
    /// The newest snapped preview.
    pub preview: Option<SnapResult>,
    /// Why the newest frame did not snap.
    pub preview_error: Option<String>,
    /// How long the newest preview took to snap.
    pub preview_time: Duration,
    /// The apparent size of a new primitive: read off the strokes under the cursor when
    /// it enters the drawing, then scaled by the wheel.
    pub size: Option<f64>,
    /// Where `size` was read off the strokes (`None` once the user has scaled it).
    pub sized_at: Option<DVec2>,
    /// The request the newest preview answers (equal to `generation` when it is up to
    /// date).
    pub preview_generation: u64,
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
        }
    }
}

/// A message in the log.
#[derive(Clone, Debug)]
pub struct Message {
    /// The text.
    pub text: String,
    /// Whether it reports a problem.
    pub warning: bool,
}

/// A question the app is asking in a modal window.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Prompt {
    /// Unsaved changes before `then`.
    Unsaved(After),
    /// An autosave from a crashed run can be recovered.
    Recover(PathBuf),
    /// A file path to type (no native dialog, or by choice).
    Path(PathAction, String),
    /// An error to acknowledge.
    Error(String),
}

/// What follows an unsaved-changes prompt.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum After {
    New,
    Open(Option<PathBuf>),
    Quit,
}

/// What a typed path is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PathAction {
    Open,
    SaveAs,
    Export,
}

/// Frame times, for the status bar and the drag benchmark.
#[derive(Debug, Default)]
pub(crate) struct FrameTimer {
    last: Option<Instant>,
    /// Recent frame intervals.
    pub intervals: std::collections::VecDeque<Duration>,
    /// Time spent building the UI in recent frames.
    pub cpu: std::collections::VecDeque<Duration>,
}

impl FrameTimer {
    fn tick(&mut self, cpu: Duration) {
        let now = Instant::now();
        if let Some(last) = self.last {
            self.intervals.push_back(now - last);
            if self.intervals.len() > 240 {
                self.intervals.pop_front();
            }
        }
        self.last = Some(now);
        self.cpu.push_back(cpu);
        if self.cpu.len() > 240 {
            self.cpu.pop_front();
        }
    }
}

/// The application.
pub struct GeosnapApp {
    /// The work and its history.
    pub editor: Editor,
    context: Arc<SnapContext>,
    context_revision: u64,
    previewer: Previewer,
    wake: Wake,
    /// The running snap-and-solve or re-solve.
    pub job: Option<Job>,
    /// The primitive being dragged.
    pub drag: Option<Drag>,
    /// The canvas tool.
    pub tool: Tool,
    /// The selected part.
    pub selection: Option<PrimitiveId>,
    /// The relation under the cursor in the relations panel.
    pub hovered_relation: Option<RelationId>,
    /// The canvas's pan and zoom.
    pub canvas: CanvasView,
    view3d: View3d,
    image: Option<(PathBuf, egui::TextureHandle, [usize; 2])>,
    /// A reference image that could not be read (not tried again).
    image_failed: Option<PathBuf>,
    /// The reference image's opacity.
    pub image_opacity: f32,
    /// The message log (newest last).
    pub messages: Vec<Message>,
    /// The last solve, for the status bar: (iterations, ‖c‖∞, seconds, how it ended).
    pub last_solve: Option<(usize, f64, f64, String)>,
    /// Recently opened or saved files, newest first.
    pub recent: Vec<PathBuf>,
    pub(crate) prompt: Option<Prompt>,
    pub(crate) show_settings: bool,
    drawing: Option<Vec<DVec2>>,
    /// The window title last sent (a title change is a round trip to the window system).
    title: String,
    pub(crate) timer: FrameTimer,
    pub(crate) autosave: files::Autosave,
    benchmark: Option<canvas::DragBenchmark>,
    screenshot: Option<files::Screenshot>,
    /// Placements still to play (`--play`).
    play: std::collections::VecDeque<crate::core::model::Step>,
    /// Typed dimension values being edited in the properties panel.
    pub(crate) typed: std::collections::BTreeMap<String, String>,
    allow_quit: bool,
}

impl std::fmt::Debug for GeosnapApp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GeosnapApp")
            .field("parts", &self.editor.document.len())
            .field("strokes", &self.editor.sketch.strokes.len())
            .finish_non_exhaustive()
    }
}

impl GeosnapApp {
    /// The app, opening `options.file` or the built-in sample.
    pub fn new(cc: &eframe::CreationContext<'_>, options: AppOptions) -> Self {
        cc.egui_ctx.set_theme(egui::Theme::Light);
        let ctx = cc.egui_ctx.clone();
        let wake: Wake = Arc::new(move || ctx.request_repaint());
        let mut editor = Editor::default();
        let mut messages = Vec::new();
        match import_svg(crate::samples::VASE_SVG.as_bytes(), &SvgOptions::default()) {
            Ok(sample) => editor = Editor::with_sketch(sample.sketch, None),
            Err(error) => messages.push(Message {
                text: format!("The built-in sample could not be read: {error}"),
                warning: true,
            }),
        }
        let recent = cc
            .storage
            .and_then(|s| eframe::get_value::<Vec<PathBuf>>(s, "recent"))
            .unwrap_or_default();
        if let Some(inference) = cc
            .storage
            .and_then(|s| eframe::get_value(s, "inference_settings"))
        {
            editor.settings.inference = inference;
        }
        let previewer = Previewer::start(editor.settings.snap.clone(), Arc::clone(&wake));
        let autosave = files::Autosave::new(options.autosave_dir.clone());
        let mut app = Self {
            context: Arc::new(SnapContext::from_sketch(&editor.sketch)),
            context_revision: editor.strokes_revision(),
            editor,
            previewer,
            wake,
            job: None,
            drag: None,
            tool: Tool::Select,
            selection: None,
            hovered_relation: None,
            canvas: CanvasView::default(),
            view3d: View3d::default(),
            image: None,
            image_failed: None,
            image_opacity: 0.5,
            messages,
            last_solve: None,
            recent,
            prompt: None,
            show_settings: false,
            drawing: None,
            title: String::new(),
            timer: FrameTimer::default(),
            autosave,
            benchmark: options
                .drag_benchmark
                .map(|(frames, out)| canvas::DragBenchmark::new(frames, out)),
            screenshot: options.screenshot.map(files::Screenshot::new),
            typed: std::collections::BTreeMap::new(),
            allow_quit: false,
            play: std::collections::VecDeque::new(),
        };
        if let Some(found) = app.autosave.pending() {
            app.prompt = Some(Prompt::Recover(found));
        }
        if let Some(script) = &options.play {
            match crate::io::script::load_script(script) {
                Ok(script) => {
                    app.open_path(&cc.egui_ctx, &script.sketch);
                    app.play = script.steps.into();
                }
                Err(error) => app.warn(format!("Could not play {}: {error}", script.display())),
            }
        } else if let Some(path) = options.file {
            app.open_path(&cc.egui_ctx, &path);
        } else {
            app.say(
                "The sample sketch (a vase) is open: drag a primitive from the palette onto it.",
            );
        }
        app
    }

    /// Logs a message for the user.
    pub fn say(&mut self, text: impl Into<String>) {
        self.messages.push(Message {
            text: text.into(),
            warning: false,
        });
    }

    /// Logs a problem for the user.
    pub fn warn(&mut self, text: impl Into<String>) {
        let text = text.into();
        log::warn!("{text}");
        self.messages.push(Message {
            text,
            warning: true,
        });
    }

    /// The snapping context of the current strokes (rebuilt when they change).
    fn context(&mut self) -> Arc<SnapContext> {
        if self.context_revision != self.editor.strokes_revision() {
            self.context = Arc::new(SnapContext::from_sketch(&self.editor.sketch));
            self.context_revision = self.editor.strokes_revision();
        }
        Arc::clone(&self.context)
    }

    /// The size a dropped primitive starts with: a fraction of the drawing.
    pub fn default_size(&self) -> f64 {
        self.editor
            .sketch
            .view_box
            .map(|(_, size)| size.max_element())
            .or_else(|| {
                self.editor
                    .sketch
                    .bounds()
                    .map(|(lo, hi)| (hi - lo).max_element())
            })
            .unwrap_or(100.0)
            * DEFAULT_SIZE_FRACTION
    }

    /// Whether a snap-and-solve is running (edits wait for it).
    pub fn busy(&self) -> bool {
        self.job.is_some()
    }

    /// Starts dragging a new primitive of `kind` (from the palette).
    pub fn begin_drag(&mut self, kind: PrimitiveKind) {
        if self.busy() {
            return;
        }
        self.drag = Some(Drag::new(kind, Placement::at(DVec2::ZERO)));
    }

    /// Starts re-dragging a placed part.
    pub fn begin_redrag(&mut self, id: PrimitiveId, at: DVec2) {
        if self.busy() {
            return;
        }
        let Some(placed) = self.editor.document.get(id) else {
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
                drag.size = Some(size_under(&self.editor.sketch, at, fallback));
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
        let context = self.context();
        let strokes_revision = self.context_revision;
        let Some(drag) = self.drag.as_mut() else {
            return;
        };
        drag.generation += 1;
        self.previewer.request(PreviewRequest {
            generation: drag.generation,
            dragged,
            context,
            strokes_revision,
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
        self.previewer.clear();
        let Some(dragged) = self.dragged_primitive() else {
            return;
        };
        let Some(drag) = self.drag.take() else {
            return;
        };
        if !drag.over_canvas {
            return;
        }
        let start = drag
            .preview
            .as_ref()
            .map_or(dragged, |p| p.primitive.clone());
        let context = self.context();
        let document = self.editor.document.clone();
        let settings = self.editor.settings.clone();
        let replacing = drag.replacing;
        let label = match replacing {
            Some(id) => format!("Move #{}", id.0),
            None => format!("Place {}", drag.kind.name()),
        };
        self.job = Some(Job::spawn(
            label,
            self.editor.revision(),
            Arc::clone(&self.wake),
            move |cancel, observe| {
                worker::place(
                    document, &context, &start, replacing, &settings, cancel, observe,
                )
            },
        ));
    }

    /// Drops the drag without placing anything.
    pub fn cancel_drag(&mut self) {
        self.previewer.clear();
        self.drag = None;
    }

    /// Re-solves the model (or the components of `changed`) in the background and
    /// applies the result as one undo step named `label`.
    pub fn resolve_in_background(
        &mut self,
        label: &str,
        document: crate::core::model::Document,
        changed: Option<Vec<PrimitiveId>>,
    ) {
        if self.busy() {
            self.warn("Wait for the running solve to finish (or press Esc).");
            return;
        }
        let settings = self.editor.settings.clone();
        self.job = Some(Job::spawn(
            label.to_owned(),
            self.editor.revision(),
            Arc::clone(&self.wake),
            move |cancel, observe| {
                let mut output = worker::resolve(
                    document.clone(),
                    changed.as_deref(),
                    &settings,
                    cancel,
                    observe,
                );
                if output.document.is_none() && !output.cancelled {
                    output.document = Some(document);
                }
                output
            },
        ));
    }

    /// Stops the running job; nothing changes.
    pub fn cancel_job(&mut self) {
        if let Some(job) = &self.job {
            job.cancel();
        }
    }

    /// Takes in finished work: the newest preview and a finished job.
    fn poll_workers(&mut self) {
        if let Some(result) = self.previewer.latest() {
            if let Some(drag) = self.drag.as_mut() {
                if result.generation <= drag.generation {
                    drag.preview_time = result.elapsed;
                    drag.preview_generation = result.generation;
                    match result.result {
                        Ok(snapped) => {
                            drag.preview = Some(snapped);
                            drag.preview_error = None;
                        }
                        Err(error) => {
                            drag.preview = None;
                            drag.preview_error = Some(error);
                        }
                    }
                }
            }
        }
        let finished = self.job.as_ref().and_then(Job::try_result);
        if let Some(output) = finished {
            let job = self.job.take().expect("a finished job was running");
            self.finish_job(&job, output);
        }
    }

    fn finish_job(&mut self, job: &Job, output: JobOutput) {
        if let Some(report) = output.outcome.as_ref().and_then(|o| o.report.as_ref()) {
            self.last_solve = Some((
                report.outer_iterations,
                report.max_violation,
                output.elapsed.as_secs_f64(),
                format!("{:?}", report.termination),
            ));
        }
        if output.cancelled {
            self.say(format!("{}: cancelled; nothing changed.", job.label));
            return;
        }
        if job.revision != self.editor.revision() {
            self.warn(format!(
                "{}: the work changed while it was solving; the result was dropped.",
                job.label
            ));
            return;
        }
        let warning = output
            .outcome
            .as_ref()
            .is_some_and(|o| !o.conflicts.is_empty() || o.reverted);
        for text in &output.messages {
            self.messages.push(Message {
                text: format!("{}: {text}", job.label),
                warning,
            });
        }
        if let Some(document) = output.document {
            self.editor.apply_document(&job.label, document);
            if let Some(id) = output.placed {
                self.selection = Some(id);
            }
        } else if output.messages.is_empty() {
            self.warn(format!("{}: nothing changed.", job.label));
        }
    }

    /// Takes the last step back.
    pub fn undo(&mut self) {
        if self.busy() {
            return;
        }
        match self.editor.undo() {
            Some(label) => self.say(format!("Undid: {label}")),
            None => self.say("Nothing to undo."),
        }
        self.forget_missing_selection();
    }

    /// Does the last undone step again.
    pub fn redo(&mut self) {
        if self.busy() {
            return;
        }
        match self.editor.redo() {
            Some(label) => self.say(format!("Redid: {label}")),
            None => self.say("Nothing to redo."),
        }
        self.forget_missing_selection();
    }

    fn forget_missing_selection(&mut self) {
        if self
            .selection
            .is_some_and(|id| self.editor.document.get(id).is_none())
        {
            self.selection = None;
        }
        if self
            .hovered_relation
            .is_some_and(|id| self.editor.document.relation(id).is_none())
        {
            self.hovered_relation = None;
        }
    }

    /// Deletes the selected part.
    pub fn delete_selected(&mut self) {
        if self.busy() {
            return;
        }
        if let Some(id) = self.selection.take() {
            self.editor.delete_primitive(id);
        }
    }

    /// Duplicates the selected part beside itself (unsnapped: drag it onto its strokes
    /// to snap it).
    pub fn duplicate_selected(&mut self) {
        let Some(id) = self.selection else { return };
        let Some(placed) = self.editor.document.get(id) else {
            return;
        };
        let p = placed.primitive.clone();
        let offset = p.size() * 0.6;
        let mut document = self.editor.document.clone();
        let copy = document.add(crate::core::model::Placed {
            primitive: p.transformed(glam::DVec3::new(offset, 0.0, 0.0), 1.0),
            fit: crate::core::model::Fit::default(),
        });
        self.editor
            .apply_document(&format!("Duplicate #{}", id.0), document);
        self.selection = Some(copy);
    }

    /// Sets relation `id`'s mode and re-solves in the background (one undo step).
    pub fn set_relation_mode(&mut self, id: RelationId, mode: crate::core::relation::Mode) {
        let Some(document) = self.editor.relation_mode_changed(id, mode) else {
            return;
        };
        let (Some(index), Some(relation)) = (document.relation_position(id), document.relation(id))
        else {
            return;
        };
        let members = relation.members.clone();
        self.resolve_in_background(
            &format!("Relation {index} {}", mode_name(mode)),
            document,
            Some(members),
        );
    }

    /// Drops the next scripted placement once the previous one has been solved.
    fn play_step(&mut self) {
        if self.busy() || self.drag.is_some() {
            return;
        }
        let Some(step) = self.play.pop_front() else {
            return;
        };
        if let crate::core::model::Step::Place { kind, placement } = step {
            self.begin_drag(kind);
            if let Some(drag) = self.drag.as_mut() {
                drag.placement = placement.clone();
                drag.over_canvas = true;
            }
            self.end_drag();
        }
    }

    fn shortcuts(&mut self, ctx: &egui::Context) {
        use egui::{Key, KeyboardShortcut, Modifiers};
        let typing = ctx.egui_wants_keyboard_input();
        let shortcut = |m, k| ctx.input_mut(|i| i.consume_shortcut(&KeyboardShortcut::new(m, k)));
        if shortcut(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z)
            || shortcut(Modifiers::COMMAND, Key::Y)
        {
            self.redo();
        }
        if shortcut(Modifiers::COMMAND, Key::Z) {
            self.undo();
        }
        if shortcut(Modifiers::COMMAND | Modifiers::SHIFT, Key::S) {
            self.save_as(ctx);
        }
        if shortcut(Modifiers::COMMAND, Key::S) {
            self.save(ctx);
        }
        if shortcut(Modifiers::COMMAND, Key::O) {
            self.request(ctx, After::Open(None));
        }
        if shortcut(Modifiers::COMMAND, Key::N) {
            self.request(ctx, After::New);
        }
        if shortcut(Modifiers::COMMAND, Key::E) {
            self.export_dialog();
        }
        if shortcut(Modifiers::COMMAND, Key::D) {
            self.duplicate_selected();
        }
        if typing {
            return;
        }
        if ctx.input(|i| i.key_pressed(Key::Escape)) {
            if self.drag.is_some() {
                self.cancel_drag();
                self.say("Drag cancelled.");
            } else if self.job.is_some() {
                self.cancel_job();
            } else if self.drawing.is_some() {
                self.drawing = None;
            } else {
                self.selection = None;
            }
        }
        if ctx.input(|i| i.key_pressed(Key::Delete) || i.key_pressed(Key::Backspace)) {
            self.delete_selected();
        }
        if ctx.input(|i| i.key_pressed(Key::F)) {
            self.canvas.request_fit();
            self.view3d.request_fit();
        }
        for (key, tool) in [
            (Key::V, Tool::Select),
            (Key::B, Tool::Draw),
            (Key::E, Tool::Erase),
            (Key::C, Tool::Reclassify),
        ] {
            if ctx.input(|i| i.key_pressed(key) && i.modifiers.is_none()) {
                self.tool = tool;
            }
        }
    }

    fn emphasis(&self) -> Emphasis {
        Emphasis {
            selected: self.selection,
            related: self
                .hovered_relation
                .and_then(|id| self.editor.document.relation(id))
                .map(|r| r.members.clone())
                .unwrap_or_default(),
        }
    }

    fn window_title(&self) -> String {
        let name = self
            .editor
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map_or_else(
                || "untitled".to_owned(),
                |n| n.to_string_lossy().into_owned(),
            );
        format!(
            "{}{name} — geosnap",
            if self.editor.is_dirty() { "• " } else { "" }
        )
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

/// The colour of the window's background: the canvas's paper and the panels'.
pub(crate) const PAPER: egui::Color32 = egui::Color32::from_rgb(250, 250, 249);

/// A panel frame without a fill: panels show the window's clear colour ([`PAPER`]), so
/// a software rasterizer (llvmpipe, with no GPU) shades no full-size backgrounds each
/// frame, which is most of its frame time.
fn unfilled(margin: f32) -> egui::Frame {
    egui::Frame::NONE.inner_margin(margin)
}

fn mode_name(mode: crate::core::relation::Mode) -> &'static str {
    match mode {
        crate::core::relation::Mode::Hard => "hard",
        crate::core::relation::Mode::Soft => "soft",
        crate::core::relation::Mode::Off => "off",
    }
}

impl eframe::App for GeosnapApp {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let started = Instant::now();
        let ctx = ui.ctx().clone();
        self.poll_workers();
        self.files_dropped(&ctx);
        self.sync_image(&ctx);
        self.shortcuts(&ctx);
        self.close_requested(&ctx);
        self.benchmark_step(&ctx);
        self.play_step();

        self.menu_bar(ui);
        self.status_bar(ui);
        self.palette(ui);
        egui::Panel::right("inspector")
            .frame(unfilled(6.0))
            .resizable(true)
            .default_size(420.0)
            .min_size(280.0)
            .show(ui, |ui| {
                let height = ui.available_height();
                egui::Panel::bottom("side_panels")
                    .frame(unfilled(4.0))
                    .resizable(true)
                    .default_size(height * 0.5)
                    .show(ui, |ui| self.side_panels(ui));
                egui::CentralPanel::default()
                    .frame(unfilled(0.0))
                    .show(ui, |ui| {
                        let preview = self
                            .drag
                            .as_ref()
                            .and_then(|d| d.preview.as_ref().map(|p| p.primitive.clone()));
                        let emphasis = self.emphasis();
                        self.view3d.show(
                            ui,
                            frame,
                            &self.editor.document,
                            self.editor.revision(),
                            preview.as_ref(),
                            &emphasis,
                        );
                    });
            });
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| self.canvas_ui(ui));
        self.prompts(&ctx);
        self.settings_window(&ctx);

        self.autosave_tick();
        let title = self.window_title();
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
        if self.job.is_some() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
        self.screenshot_step(&ctx);
        self.timer.tick(started.elapsed());
    }

    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        // The paper of the canvas and the panels, which paint no background.
        egui::Rgba::from(PAPER).to_array()
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, "recent", &self.recent);
        eframe::set_value(
            storage,
            "inference_settings",
            &self.editor.settings.inference,
        );
    }

    fn on_exit(&mut self) {
        self.autosave.clear();
    }
}
