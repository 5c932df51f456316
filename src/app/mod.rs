//! The desktop application (egui/eframe, wgpu backend): the whole workflow in one
//! window. A menu bar; on the left the palette and the tools; in the centre the sketch
//! canvas; on the right the 3D view, the relations and the properties; a status bar with
//! the solver's state.
//!
//! The work and every change of it live in [`editor::Editor`] (no GUI, one undo step per
//! action); snapping and solving run on worker threads ([`worker`]), newest request wins,
//! so the UI never waits for them. Each part of the window owns its state, in the file
//! named after it: the canvas (`canvas.rs`: pan and zoom, tool, reference image), the 3D
//! view (`view3d.rs`), the panels (`panels.rs`), files and their prompts (`files.rs`),
//! the messages and the status bar (`status.rs`), the primitive being dragged
//! (`drag.rs`) and scripted runs (`automation.rs`).
//!
//! ```no_run
//! // Opens the window on the built-in sample (or a file), as `cargo run` does.
//! geosnap::app::run(geosnap::app::AppOptions::default())?;
//! # Ok::<(), anyhow::Error>(())
//! ```

mod automation;
mod autosave;
mod canvas;
mod drag;
pub mod editor;
mod files;
mod help;
mod loader;
mod panels;
mod pose;
mod status;
mod view3d;
mod words;
pub mod worker;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::anyhow;

use crate::core::model::{PrimitiveId, RelationId};
use crate::io::svg::{import_svg, SvgOptions};
use automation::Automation;
use canvas::Canvas;
pub use canvas::{verdict_color, CanvasView, Tool};
pub use drag::{size_under, Drag};
use editor::Editor;
use files::Files;
pub use help::shortcut_descriptions;
use panels::Panels;
pub use status::Message;
use status::Status;
use view3d::{Emphasis, View3d};
use worker::{Job, JobOutput, Wake, Workers};

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

/// The application.
pub struct GeosnapApp {
    /// The work and its history.
    editor: Editor,
    /// The preview thread and the running snap-and-solve or re-solve.
    workers: Workers,
    /// The primitive being dragged.
    drag: Option<Drag>,
    /// The selected part.
    selection: Option<PrimitiveId>,
    /// The relation under the cursor in the relations panel.
    hovered_relation: Option<RelationId>,
    /// Parts hidden in the outliner (on the canvas and in the 3D view; a view setting,
    /// not part of the work).
    hidden: std::collections::BTreeSet<PrimitiveId>,
    /// The file being opened (read and prepared off the UI thread).
    loading: Option<loader::Loading>,
    /// The poses the snap found for parts placed this session, for Tab on a selected
    /// part (not saved: a reopened session has none).
    readings: BTreeMap<PrimitiveId, worker::Readings>,
    canvas: Canvas,
    view3d: View3d,
    panels: Panels,
    files: Files,
    status: Status,
    automation: Automation,
    help: help::Help,
    /// The window title last sent (a title change is a round trip to the window system).
    title: String,
}

impl std::fmt::Debug for GeosnapApp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GeosnapApp")
            .field("parts", &self.editor.document().len())
            .field("strokes", &self.editor.sketch().strokes.len())
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
        // New work (the sample included) starts in the unit last chosen.
        if let Some(unit) = cc
            .storage
            .and_then(|s| eframe::get_value::<String>(s, UNIT_KEY))
            .and_then(|u| words::Unit::from_symbol(&u))
        {
            editor.set_default_unit(unit);
        }
        let mut messages = Vec::new();
        match import_svg(crate::samples::VASE_SVG.as_bytes(), &SvgOptions::default()) {
            Ok(sample) => editor.start(sample.sketch, None),
            Err(error) => messages.push(Message {
                text: format!("The built-in sample could not be read: {error}"),
                warning: true,
                detail: None,
            }),
        }
        let recent = cc
            .storage
            .and_then(|s| eframe::get_value::<Vec<PathBuf>>(s, "recent"))
            .unwrap_or_default();
        let hint_seen = cc
            .storage
            .and_then(|s| eframe::get_value::<bool>(s, help::HINT_SEEN_KEY))
            .unwrap_or(false);
        let developer = cc
            .storage
            .and_then(|s| eframe::get_value::<bool>(s, status::DEVELOPER_KEY))
            .unwrap_or(false);
        if let Some(inference) = cc
            .storage
            .and_then(|s| eframe::get_value(s, "inference_settings"))
        {
            editor.settings_mut().inference = inference;
        }
        let mut app = Self {
            workers: Workers::start(&editor, wake),
            editor,
            drag: None,
            selection: None,
            hovered_relation: None,
            readings: BTreeMap::new(),
            loading: None,
            hidden: std::collections::BTreeSet::new(),
            canvas: Canvas::default(),
            view3d: View3d::default(),
            panels: Panels::default(),
            files: Files::new(
                recent,
                options.autosave_dir.clone(),
                autosave::AUTOSAVE_EVERY,
            ),
            status: Status::new(messages),
            automation: Automation::new(&options),
            help: help::Help {
                hint_seen,
                ..help::Help::default()
            },
            title: String::new(),
        };
        app.status.developer = developer;
        if let Some(script) = &options.play {
            match crate::io::script::load_script(script) {
                Ok(script) => {
                    app.open_path(&cc.egui_ctx, &script.sketch);
                    app.automation.play(script.steps);
                }
                Err(error) => app.warn(format!("Could not play {}: {error}", script.display())),
            }
        } else if let Some(path) = options.file {
            app.open_path(&cc.egui_ctx, &path);
        } else {
            app.say(
                "The sample sketch (a vase) is open: drag a primitive from the palette onto it.",
            );
            // Not over the frame-time measurement: it measures the drag alone.
            app.help.first_run_hint = !app.help.hint_seen && options.drag_benchmark.is_none();
        }
        app
    }

    /// Logs a message for the user.
    pub fn say(&mut self, text: impl Into<String>) {
        self.status.push(text.into(), false);
    }

    /// Logs a problem for the user.
    pub fn warn(&mut self, text: impl Into<String>) {
        let text = text.into();
        log::warn!("{text}");
        self.status.push(text, true);
    }

    /// The work and its history.
    pub fn editor(&self) -> &Editor {
        &self.editor
    }

    /// The message log (newest last).
    pub fn messages(&self) -> &[Message] {
        self.status.messages()
    }

    /// The selected part.
    pub fn selection(&self) -> Option<PrimitiveId> {
        self.selection
    }

    /// Selects a part (or nothing).
    pub fn select(&mut self, id: Option<PrimitiveId>) {
        self.selection = id;
    }

    /// Whether part `id` is hidden (outliner).
    pub fn is_hidden(&self, id: PrimitiveId) -> bool {
        self.hidden.contains(&id)
    }

    /// The part being renamed in the outliner, with the name typed so far.
    pub fn renaming(&self) -> Option<(PrimitiveId, &str)> {
        self.panels.renaming()
    }

    /// The document's unit: every length is shown in it and the export converts it.
    pub(crate) fn unit(&self) -> words::Unit {
        self.editor.document().unit()
    }

    /// Sets the document's unit (one undo step; Settings and the export dialog), not
    /// while a solve runs (its result would be dropped); new work starts in it too.
    pub fn set_unit(&mut self, unit: crate::core::model::LengthUnit) {
        if unit == self.unit() {
            return;
        }
        if self.busy() {
            self.warn("Wait for the running solve to finish (or press Esc) to change the unit.");
            return;
        }
        if self.editor.set_unit(unit) {
            self.say(format!(
                "Lengths are now in {}: the numbers stay as they are, one unit of the \
                 drawing is one {}.",
                unit.name(),
                unit.singular()
            ));
        }
    }

    /// Names part `id` (one undo step; an empty name takes the name away), not while a
    /// solve runs; whether the rename was done (or had nothing to do).
    pub fn rename(&mut self, id: PrimitiveId, name: &str) -> bool {
        if self.busy() {
            self.warn("Wait for the running solve to finish (or press Esc) to rename a part.");
            return false;
        }
        self.editor.rename_primitive(id, name);
        true
    }

    /// Sets how long unsaved work waits before it is autosaved (30 s unless set; tests
    /// shorten it).
    pub fn set_autosave_delay(&mut self, delay: Duration) {
        self.files.set_autosave_delay(delay);
    }

    /// Why the last drop placed nothing, while its note is shown on the canvas at the
    /// drop point.
    pub fn drop_note(&self) -> Option<&str> {
        self.canvas.drop_note()
    }

    /// The screen rectangles of the canvas's labels in the last frame: part ids with
    /// their badges, then the relation labels (placed so that none overlaps another).
    pub fn canvas_labels(&self) -> &[egui::Rect] {
        self.canvas.labels()
    }

    /// The snap verdict badges on the canvas in the last frame: each part's, in the
    /// colour of its verdict ([`verdict_color`]).
    pub fn canvas_badges(&self) -> &[(PrimitiveId, egui::Color32)] {
        self.canvas.badges()
    }

    /// The canvas's pan and zoom.
    pub fn canvas_view(&self) -> &CanvasView {
        self.canvas.view()
    }

    /// The 3D view's camera.
    pub fn camera_3d(&self) -> crate::render::OrbitCamera {
        self.view3d.camera
    }

    /// Whether the 3D view is the view from the drawing (its default: the drawing's
    /// camera, the strokes and image behind the model).
    pub fn view_from_drawing(&self) -> bool {
        self.view3d.is_drawing_view()
    }

    /// The running snap-and-solve or re-solve.
    pub fn job(&self) -> Option<&Job> {
        self.workers.job()
    }

    /// Whether a snap-and-solve is running (edits wait for it).
    pub fn busy(&self) -> bool {
        self.workers.busy()
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
        let settings = self.editor.settings().clone();
        self.workers.spawn(
            label.to_owned(),
            self.editor.revision(),
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
        );
    }

    /// Stops the running job; nothing changes.
    pub fn cancel_job(&mut self) {
        self.workers.cancel_job();
    }

    /// Takes in finished work: the newest preview and a finished job.
    fn poll_workers(&mut self) {
        self.poll_preview();
        if let Some((job, output)) = self.workers.finished() {
            self.finish_job(&job.label, job.revision, output);
        }
    }

    /// Takes in the output of a job labelled `label`, started at editor revision
    /// `revision`.
    fn finish_job(&mut self, label: &str, revision: u64, output: JobOutput) {
        self.status.solved(&output);
        // A drop that placed nothing, or placed it freely, says so where it was released.
        let note = (output.placed_freely || (output.document.is_none() && !output.cancelled))
            .then(|| output.messages.first())
            .flatten()
            .map(|text| words::split_figures(text).0);
        self.canvas.drop_ended(note);
        if output.cancelled {
            self.say(format!("{label}: cancelled; nothing changed."));
            return;
        }
        if revision != self.editor.revision() {
            self.warn(format!(
                "{label}: the work changed while it was solving; the result was dropped."
            ));
            return;
        }
        let warning = output
            .outcome
            .as_ref()
            .is_some_and(|o| !o.conflicts.is_empty() || o.reverted);
        for text in &output.messages {
            let (text, detail) = words::split_figures(text);
            self.status
                .push_detailed(format!("{label}: {text}"), detail, warning);
        }
        if let Some(document) = output.document {
            self.editor.apply_document(label, document);
            if let Some(id) = output.placed {
                self.selection = Some(id);
                // Ids come back after an undo: a part without a choice drops any
                // readings an earlier part of its id left.
                match output.readings {
                    Some(readings) => self.readings.insert(id, readings),
                    None => self.readings.remove(&id),
                };
            }
        } else if output.messages.is_empty() {
            self.warn(format!("{label}: nothing changed."));
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
            .is_some_and(|id| self.editor.document().get(id).is_none())
        {
            self.selection = None;
        }
        if self
            .hovered_relation
            .is_some_and(|id| self.editor.document().relation(id).is_none())
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
        if let Some(copy) = self.editor.duplicate_primitive(id) {
            self.selection = Some(copy);
        }
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

    /// Places part `id` exactly as `primitive` (typed in the properties): off its
    /// strokes, its relations and dimensions kept, and solved in the background as one
    /// undo step.
    pub fn place_exactly(&mut self, id: PrimitiveId, primitive: crate::core::primitive::Primitive) {
        if !primitive.is_finite() {
            self.warn("That position or angle gives no valid part.");
            return;
        }
        let Some(document) = pose::placed_exactly(self.editor.document(), id, primitive) else {
            return;
        };
        let c = document
            .get(id)
            .map(|p| p.primitive.center())
            .unwrap_or_default();
        self.resolve_in_background(
            &format!(
                "{} placed at ({:.1}, {:.1}, {:.1}) {}",
                words::part_name(&document, id),
                c.x,
                c.y,
                c.z,
                self.unit().symbol()
            ),
            document,
            Some(vec![id]),
        );
    }

    /// Accepts every suggested relation (makes it hard) and re-solves the parts they
    /// relate, as one undoable step.
    pub fn accept_all_suggestions(&mut self) {
        let mut document = self.editor.document().clone();
        let accepted = document.accept_suggestions();
        if accepted.is_empty() {
            return;
        }
        let members: Vec<PrimitiveId> = accepted
            .iter()
            .filter_map(|id| document.relation(*id))
            .flat_map(|r| r.members.iter().copied())
            .collect();
        self.resolve_in_background(
            &format!("Accept {} suggested relation(s)", accepted.len()),
            document,
            Some(members),
        );
    }

    fn emphasis(&self) -> Emphasis {
        Emphasis {
            selected: self.selection,
            related: self
                .hovered_relation
                .and_then(|id| self.editor.document().relation(id))
                .map(|r| r.members.clone())
                .unwrap_or_default(),
            hidden: self.hidden.iter().copied().collect(),
        }
    }

    fn window_title(&self) -> String {
        let name = self
            .editor
            .origin()
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

/// The storage key of the unit new work starts in.
const UNIT_KEY: &str = "unit";

/// The colour of the window's background: the canvas's paper and the panels'.
pub(crate) const PAPER: egui::Color32 = egui::Color32::from_rgb(250, 250, 249);

/// A panel frame without a fill: panels show the window's clear colour ([`PAPER`]), so
/// a software rasterizer (llvmpipe, with no GPU) shades no full-size backgrounds each
/// frame, which is most of its frame time.
fn unfilled(margin: f32) -> egui::Frame {
    egui::Frame::NONE.inner_margin(margin)
}

fn mode_name(mode: crate::core::relation::Mode) -> &'static str {
    mode.name()
}

impl eframe::App for GeosnapApp {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let started = Instant::now();
        let ctx = ui.ctx().clone();
        self.poll_workers();
        self.poll_loading(&ctx);
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
                            .and_then(|d| d.preview().map(|p| p.primitive.clone()));
                        let emphasis = self.emphasis();
                        let image = self.canvas.image();
                        let content = view3d::Content {
                            document: self.editor.document(),
                            revision: self.editor.revision(),
                            preview: preview.as_ref(),
                            emphasis: &emphasis,
                            backdrop: view3d::Backdrop {
                                strokes: &self.editor.sketch().strokes,
                                image: image.texture(),
                            },
                        };
                        self.view3d.show(ui, frame, &content);
                    });
            });
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| self.canvas_ui(ui));
        self.prompts(&ctx);
        self.settings_window(&ctx);
        self.shortcuts_window(&ctx);

        self.autosave_tick();
        let title = self.window_title();
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
        if self.busy() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
        self.screenshot_step(&ctx);
        self.status.tick(started.elapsed());
    }

    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        // The paper of the canvas and the panels, which paint no background.
        egui::Rgba::from(PAPER).to_array()
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, "recent", &self.files.recent());
        eframe::set_value(
            storage,
            "inference_settings",
            &self.editor.settings().inference,
        );
        eframe::set_value(storage, help::HINT_SEEN_KEY, &self.help.hint_seen);
        eframe::set_value(storage, status::DEVELOPER_KEY, &self.status.developer);
        eframe::set_value(storage, UNIT_KEY, &self.editor.default_unit().symbol());
    }

    fn on_exit(&mut self) {
        self.files.exit();
    }
}
