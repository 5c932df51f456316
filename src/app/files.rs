//! Files from the app: open (sessions, sketches, SVG, reference images; dialog, typed
//! path, recent list or drag-and-drop), save (atomic), export glTF, the unsaved-changes
//! prompt, and the autosave that is offered back after a crash.
//!
//! Every failure is a message; the current work is never touched by a file that cannot
//! be read.

use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{anyhow, Context as _};

use super::autosave::{Autosave, Recovery, Work};
use super::loader::{Content, Loaded, Loading};
use super::GeosnapApp;
use crate::core::sketch::Sketch;
use crate::io::gltf::{export_gltf, ExportSettings, Origin};
use crate::io::session::{load_session, save_session, Session};

/// The most recent files remembered.
const MAX_RECENT: usize = 10;

/// A question the app is asking in a modal window.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Prompt {
    /// Unsaved changes before `then`.
    Unsaved(After),
    /// An autosave from a crashed run can be recovered.
    Recover(Recovery),
    /// A file path to type (no native dialog, or by choice).
    Path(PathAction, String),
    /// An image opened while a drawing is open: under it, or a new drawing from it.
    Image(PathBuf),
    /// An error to acknowledge.
    Error(String),
    /// The export options, before asking where.
    Export,
}

/// The export dialog's options (kept for the next export in this run).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ExportOptions {
    /// A factor on top of the unit (a model drawn at 1:10, say).
    pub scale: f64,
    /// Segments around each circle.
    pub segments: usize,
    /// Whether the model stands centred on the ground (else: the drawing's origin).
    pub on_ground: bool,
    /// `.glb` (else `.gltf`).
    pub binary: bool,
}

impl Default for ExportOptions {
    fn default() -> Self {
        Self {
            scale: 1.0,
            segments: crate::io::gltf::DEFAULT_SEGMENTS,
            on_ground: true,
            binary: true,
        }
    }
}

impl ExportOptions {
    /// The chosen format's file extension.
    pub(crate) fn extension(&self) -> &'static str {
        if self.binary {
            "glb"
        } else {
            "gltf"
        }
    }
}

/// What follows an unsaved-changes prompt.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum After {
    New,
    Open(Option<PathBuf>),
    /// New work with this image as its reference.
    NewFromImage(PathBuf),
    Quit,
}

/// What a typed path is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PathAction {
    Open,
    SaveAs,
    Export,
}

/// The state of files: the question being asked, the recent files, the autosave, and
/// whether the window may close without asking.
#[derive(Debug)]
pub(crate) struct Files {
    prompt: Option<Prompt>,
    /// Recently opened or saved files, newest first.
    recent: Vec<PathBuf>,
    autosave: Autosave,
    allow_quit: bool,
    /// The typed-path prompt takes the keyboard at its next frame.
    focus_path: bool,
    /// The export dialog's options.
    export: ExportOptions,
}

impl Files {
    /// The recent files (newest first), the autosave folder (the platform's data
    /// folder when `None`) and how long unsaved work waits to be autosaved; asks to
    /// recover an autosave left by a crash.
    pub(crate) fn new(
        recent: Vec<PathBuf>,
        autosave_dir: Option<PathBuf>,
        autosave_every: Duration,
    ) -> Self {
        let autosave = Autosave::new(autosave_dir, autosave_every);
        Self {
            prompt: autosave.pending().map(Prompt::Recover),
            recent,
            autosave,
            allow_quit: false,
            focus_path: false,
            export: ExportOptions::default(),
        }
    }

    /// Recently opened or saved files, newest first.
    pub(crate) fn recent(&self) -> &[PathBuf] {
        &self.recent
    }

    /// Sets how long unsaved work waits before it is autosaved.
    pub(crate) fn set_autosave_delay(&mut self, delay: Duration) {
        self.autosave.set_delay(delay);
    }

    /// A clean exit: removes this run's autosave (one left by a crash and not yet
    /// recovered or discarded stays, to be offered again).
    pub(crate) fn exit(&mut self) {
        self.autosave.exit();
    }

    /// Closes the window without asking about unsaved changes.
    pub(crate) fn quit(&mut self, ctx: &egui::Context) {
        self.allow_quit = true;
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }

    fn remember(&mut self, path: &Path) {
        let path = path.canonicalize().unwrap_or_else(|_| path.to_owned());
        self.recent.retain(|p| *p != path);
        self.recent.insert(0, path);
        self.recent.truncate(MAX_RECENT);
    }
}

/// What kind of file a path holds, by content first, then by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FileKind {
    Session,
    Sketch,
    Image,
}

fn file_kind(path: &Path, head: &[u8]) -> Option<FileKind> {
    let text = String::from_utf8_lossy(&head[..head.len().min(4096)]);
    if head.starts_with(b"\x89PNG") || head.starts_with(&[0xFF, 0xD8, 0xFF]) {
        return Some(FileKind::Image);
    }
    if text.trim_start().starts_with('{') {
        return Some(if text.contains("geosnap-session") {
            FileKind::Session
        } else {
            FileKind::Sketch
        });
    }
    if text.trim_start().starts_with('<') {
        return Some(FileKind::Sketch);
    }
    let ext = path.extension()?.to_string_lossy().to_ascii_lowercase();
    match ext.as_str() {
        "png" | "jpg" | "jpeg" => Some(FileKind::Image),
        "svg" => Some(FileKind::Sketch),
        _ => None,
    }
}

impl GeosnapApp {
    /// Asks before `after` when there are unsaved changes.
    pub(crate) fn request(&mut self, ctx: &egui::Context, after: After) {
        if self.editor.is_dirty() && !matches!(after, After::Open(Some(ref p)) if is_image(p)) {
            self.files.prompt = Some(Prompt::Unsaved(after));
        } else {
            self.proceed(ctx, after);
        }
    }

    pub(crate) fn proceed(&mut self, ctx: &egui::Context, after: After) {
        match after {
            After::New => {
                self.cancel_job();
                self.readings.clear();
                self.hidden.clear();
                self.help.first_run_hint = false;
                self.editor.start(Sketch::default(), None);
                self.canvas.image_mut().clear(false);
                self.selection = None;
                self.canvas.request_fit();
                self.say("New work: draw strokes (B) or open a drawing.");
            }
            After::Open(Some(path)) => self.open_or_ask(ctx, &path),
            After::NewFromImage(path) => {
                self.proceed(ctx, After::New);
                self.open_path(ctx, &path);
            }
            After::Open(None) => {
                let asked = Instant::now();
                let picked = rfd::FileDialog::new()
                    .add_filter("geosnap files", &["json", "svg", "png", "jpg", "jpeg"])
                    .add_filter("Sessions and sketches", &["json"])
                    .add_filter("SVG drawings", &["svg"])
                    .add_filter("Reference images", &["png", "jpg", "jpeg"])
                    .pick_file();
                match picked {
                    Some(path) => self.open_or_ask(ctx, &path),
                    None if no_dialog(asked) => {
                        self.ask_path(PathAction::Open);
                    }
                    None => {}
                }
            }
            After::Quit => {
                self.files.quit(ctx);
            }
        }
    }

    /// Opens `path`; an image while a drawing is open asks first whether it goes under
    /// the drawing or starts a new one.
    fn open_or_ask(&mut self, ctx: &egui::Context, path: &Path) {
        if is_image(path) && !self.editor.sketch().strokes.is_empty() {
            self.files.prompt = Some(Prompt::Image(path.to_owned()));
        } else {
            self.open_path(ctx, path);
        }
    }

    /// Opens a session, sketch (native or SVG) or reference image. On failure the work
    /// stays as it was and the reason is shown. Drawings and sessions are read and
    /// prepared off the UI thread (`app/loader.rs`): the work is replaced when they
    /// are ready.
    pub fn open_path(&mut self, ctx: &egui::Context, path: &Path) {
        if self.busy() {
            self.warn("Wait for the running solve to finish (or press Esc) before opening a file.");
            return;
        }
        if let Some(loading) = &self.loading {
            let text = format!(
                "Wait for {} to open (or press Esc) before opening another file.",
                loading.path.display()
            );
            self.warn(text);
            return;
        }
        match self.try_open(ctx, path) {
            Ok(Some(note)) => {
                self.files.remember(path);
                self.say(note);
            }
            Ok(None) => {}
            Err(error) => self.open_failed(path, &error),
        }
    }

    fn open_failed(&mut self, path: &Path, error: &anyhow::Error) {
        let text = format!("Could not open {}: {error:#}", path.display());
        self.warn(text.clone());
        self.files.prompt = Some(Prompt::Error(text));
    }

    /// Shows an image at once; starts reading a drawing or session (`None`).
    fn try_open(&mut self, ctx: &egui::Context, path: &Path) -> anyhow::Result<Option<String>> {
        let head = read_head(path).with_context(|| "the file cannot be read".to_owned())?;
        let kind = file_kind(path, &head).ok_or_else(|| {
            anyhow!("not a geosnap session, sketch, SVG drawing or PNG/JPEG image")
        })?;
        if kind != FileKind::Image {
            let wake = self.workers.wake();
            self.loading = Some(Loading::start(path, kind == FileKind::Session, wake));
            return Ok(None);
        }
        let bytes = std::fs::read(path).with_context(|| "the file cannot be read".to_owned())?;
        let texture = load_texture(ctx, path, &bytes)?;
        let size = texture.size();
        self.canvas.image_mut().show(path.to_owned(), texture);
        self.editor.set_image(Some(path.to_owned()));
        self.canvas.request_fit();
        Ok(Some(format!(
            "Reference image {} ({}×{} px) under the strokes.",
            path.display(),
            size[0],
            size[1]
        )))
    }

    /// Takes in the file being opened, once it is ready: it replaces the work.
    pub(crate) fn poll_loading(&mut self, ctx: &egui::Context) {
        let Some(loading) = &self.loading else {
            return;
        };
        let Some(result) = loading.try_result() else {
            // The step shown changes when the thread wakes the UI; this keeps the
            // spinner turning between steps.
            ctx.request_repaint_after(Duration::from_millis(100));
            return;
        };
        let Some(loading) = self.loading.take() else {
            return;
        };
        let path = loading.path;
        match result {
            Ok(loaded) => {
                let note = self.take_loaded(ctx, &path, loaded);
                self.files.remember(&path);
                self.say(note);
            }
            Err(error) => self.open_failed(&path, &error),
        }
    }

    /// Replaces the work by what `path` held; says what was opened.
    fn take_loaded(&mut self, ctx: &egui::Context, path: &Path, loaded: Loaded) -> String {
        let Loaded {
            content,
            classes,
            context,
            merged,
        } = loaded;
        let note = match content {
            Content::Drawing {
                sketch,
                image,
                warnings,
            } => {
                let strokes = sketch.strokes.len();
                self.editor.start(sketch, image);
                self.editor.set_origin(path.to_owned());
                self.after_replace(ctx);
                for w in warnings {
                    self.warn(w);
                }
                format!("Opened {} ({strokes} strokes).", path.display())
            }
            Content::Session(session) => {
                let session = *session;
                let parts = session.document.len();
                self.editor
                    .replace(session.sketch, session.image, session.document);
                self.editor.mark_saved(path.to_owned());
                self.after_replace(ctx);
                format!("Opened the session {} ({parts} parts).", path.display())
            }
        };
        // What the thread prepared, for the strokes as they now are.
        let revision = self.editor.strokes_revision();
        self.workers.set_context(Arc::new(context), revision);
        self.canvas.set_classes(revision, classes);
        if merged > 0 {
            self.say(format!(
                "Merged {merged} duplicate stroke{} (drawn again over the same line): \
                 parts snap to each line once.",
                if merged == 1 { "" } else { "s" }
            ));
        }
        note
    }

    /// Stops opening the file being read; whether one was.
    pub(crate) fn cancel_loading(&mut self) -> bool {
        let Some(loading) = self.loading.take() else {
            return false;
        };
        self.say(format!(
            "Opening {} was cancelled; the work is as it was.",
            loading.path.display()
        ));
        true
    }

    /// The file being opened and the step it is at, in words, while one is.
    pub fn loading(&self) -> Option<String> {
        self.loading.as_ref().map(|l| {
            let name = l.path.file_name().map_or_else(
                || l.path.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            );
            let seconds = l.elapsed().as_secs();
            if seconds >= 1 {
                format!("Opening {name}: {}… ({seconds} s)", l.phase().text())
            } else {
                format!("Opening {name}: {}…", l.phase().text())
            }
        })
    }

    /// Whether a question is being asked in a modal window.
    pub(crate) fn asking(&self) -> bool {
        self.files.prompt.is_some()
    }

    fn after_replace(&mut self, ctx: &egui::Context) {
        // The welcome is about the sample, which is no longer open.
        self.help.first_run_hint = false;
        self.selection = None;
        self.readings.clear();
        self.hidden.clear();
        self.hovered_relation = None;
        self.drag = None;
        self.canvas.image_mut().clear(true);
        self.canvas.request_fit();
        self.view3d.request_fit();
        self.sync_image(ctx);
    }

    /// Shows the editor's reference image (after undo, redo or opening), once per change.
    pub(crate) fn sync_image(&mut self, ctx: &egui::Context) {
        if let Some(warning) = self.canvas.image_mut().sync(ctx, self.editor.image()) {
            self.warn(warning);
        }
    }

    pub(crate) fn recover(&mut self, ctx: &egui::Context, path: &Path) {
        match load_session(path) {
            Ok(session) => {
                self.editor
                    .replace(session.sketch, session.image, session.document);
                if let Some(origin) = self.files.autosave.pending().and_then(|r| r.work) {
                    self.editor.set_origin(origin);
                }
                self.editor.mark_unsaved();
                self.after_replace(ctx);
                self.say("The autosaved work was recovered; save it to keep it.");
            }
            Err(error) => self.warn(format!("The autosave could not be read: {error}")),
        }
    }

    fn session(&self) -> Session {
        Session {
            sketch: self.editor.sketch().clone(),
            image: self.editor.image().cloned(),
            document: self.editor.document().clone(),
        }
    }

    /// Saves to the session's path, or asks for one; returns whether it was saved.
    pub fn save(&mut self, ctx: &egui::Context) -> bool {
        match self.editor.path().cloned() {
            Some(path) if is_session_path(&path) => self.save_to(ctx, &path),
            _ => self.save_as(ctx),
        }
    }

    /// Asks for a path (native dialog, or a typed path) and saves there.
    pub fn save_as(&mut self, ctx: &egui::Context) -> bool {
        let asked = Instant::now();
        let picked = rfd::FileDialog::new()
            .add_filter("geosnap session", &["json"])
            .set_file_name("untitled.geosnap.json")
            .save_file();
        match picked {
            Some(path) => self.save_to(ctx, &path),
            None if no_dialog(asked) => {
                self.ask_path(PathAction::SaveAs);
                false
            }
            None => false,
        }
    }

    /// Saves the session to `path` (atomically); returns whether it was saved.
    pub fn save_to(&mut self, _ctx: &egui::Context, path: &Path) -> bool {
        match save_session(path, &self.session()) {
            Ok(()) => {
                self.editor.mark_saved(path.to_owned());
                self.files.remember(path);
                self.files.autosave.clear();
                self.say(format!("Saved {}.", path.display()));
                true
            }
            Err(error) => {
                let text = format!("Could not save {}: {error}", path.display());
                self.warn(text.clone());
                self.files.prompt = Some(Prompt::Error(text));
                false
            }
        }
    }

    /// Opens the export dialog: the unit and scale, the segments, the origin and the
    /// format, then where to write the file.
    pub fn export_dialog(&mut self) {
        if self.editor.document().is_empty() {
            self.warn("There is nothing to export yet: place a primitive first.");
            return;
        }
        self.files.prompt = Some(Prompt::Export);
    }

    /// The export settings the dialog's options give.
    fn export_settings(&self) -> anyhow::Result<ExportSettings> {
        let options = &self.files.export;
        let origin = if options.on_ground {
            Origin::Ground
        } else {
            Origin::Model
        };
        Ok(ExportSettings::new(
            self.unit().metres() * options.scale,
            options.segments,
            origin,
        )?)
    }

    /// Asks where to write the file (native dialog, or a typed path), in the format the
    /// dialog chose.
    fn export_where(&mut self) {
        let ext = self.files.export.extension();
        let asked = Instant::now();
        let picked = rfd::FileDialog::new()
            .add_filter(if ext == "glb" { "glTF binary" } else { "glTF" }, &[ext])
            .set_file_name(format!("model.{ext}"))
            .save_file();
        match picked {
            Some(path) => self.export_to(&path),
            None if no_dialog(asked) => {
                self.ask_path(PathAction::Export);
            }
            None => {}
        }
    }

    /// Exports the model as glTF 2.0 with the dialog's options: `.glb` or `.gltf` as the
    /// path ends (the chosen format's extension is added to a path with neither).
    pub fn export_to(&mut self, path: &Path) {
        if self.editor.document().is_empty() {
            self.warn("There is nothing to export yet: place a primitive first.");
            return;
        }
        let path = if crate::io::gltf::GltfFormat::from_path(path).is_some() {
            path.to_owned()
        } else {
            let mut named = path.as_os_str().to_owned();
            named.push(format!(".{}", self.files.export.extension()));
            PathBuf::from(named)
        };
        let exported = self.export_settings().and_then(|settings| {
            export_gltf(self.editor.document(), &path, &settings)?;
            Ok(settings)
        });
        match exported {
            Ok(settings) => self.say(format!(
                "Exported {} (in metres: one {} of the drawing is {} m; {} segments around \
                 circles).",
                path.display(),
                self.unit().singular(),
                settings.metres_per_unit(),
                settings.segments()
            )),
            Err(error) => {
                let text = format!("Could not export {}: {error:#}", path.display());
                self.warn(text.clone());
                self.files.prompt = Some(Prompt::Error(text));
            }
        }
    }

    /// The export dialog's options and buttons.
    fn export_prompt(&mut self, ui: &mut egui::Ui) {
        ui.heading("Export glTF");
        let busy = self.busy();
        let mut unit = self.unit();
        egui::Grid::new("export_options")
            .num_columns(2)
            .show(ui, |ui| {
                let label = ui.label("One drawing unit is one").id;
                ui.add_enabled_ui(!busy, |ui| {
                    egui::ComboBox::from_id_salt("export_unit")
                        .selected_text(unit.name())
                        .show_ui(ui, |ui| {
                            for u in super::words::Unit::ALL {
                                ui.selectable_value(&mut unit, u, u.name());
                            }
                        })
                        .response
                        .labelled_by(label)
                        .on_hover_text(UNIT_HOVER)
                        .on_disabled_hover_text("Wait for the running solve to change the unit");
                });
                ui.end_row();
                let options = &mut self.files.export;
                ui.label("Scale");
                ui.add(
                    egui::DragValue::new(&mut options.scale)
                        .range(0.001..=1000.0)
                        .speed(0.01)
                        .prefix("× "),
                );
                ui.end_row();
                ui.label("Segments around circles");
                ui.add(egui::Slider::new(
                    &mut options.segments,
                    8..=crate::io::gltf::MAX_SEGMENTS.min(256),
                ));
                ui.end_row();
                ui.label("Origin");
                ui.vertical(|ui| {
                    ui.radio_value(&mut options.on_ground, true, "On the ground, centred");
                    ui.radio_value(&mut options.on_ground, false, "The drawing's own origin");
                });
                ui.end_row();
                ui.label("Format");
                ui.vertical(|ui| {
                    ui.radio_value(&mut options.binary, true, ".glb (one binary file)");
                    ui.radio_value(&mut options.binary, false, ".gltf (text, for reading)");
                });
                ui.end_row();
            });
        self.set_unit(unit);
        let metres = self.unit().metres() * self.files.export.scale;
        ui.label(
            egui::RichText::new(format!(
                "Lengths are written in metres: 1 {} of the drawing becomes {metres} m.",
                self.unit().symbol()
            ))
            .weak(),
        );
        ui.horizontal(|ui| {
            if ui.button("Export…").clicked() {
                self.files.prompt = None;
                self.export_where();
            }
            if ui.button("Export to path…").clicked() {
                self.ask_path(PathAction::Export);
            }
            if ui.button("Cancel").clicked() {
                self.files.prompt = None;
            }
        });
    }

    /// Asks for a path to `action` in a window, suggesting one.
    pub(crate) fn ask_path(&mut self, action: PathAction) {
        let suggested = match action {
            PathAction::Open => String::new(),
            PathAction::SaveAs => self.suggested_path("geosnap.json"),
            PathAction::Export => self.suggested_path(self.files.export.extension()),
        };
        self.files.prompt = Some(Prompt::Path(action, suggested));
        self.files.focus_path = true;
    }

    fn suggested_path(&self, extension: &str) -> String {
        let base = self.editor.path().cloned().unwrap_or_else(|| {
            std::env::current_dir()
                .unwrap_or_default()
                .join("untitled.json")
        });
        let stem = base
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let stem = stem
            .trim_end_matches(".json")
            .trim_end_matches(".geosnap")
            .trim_end_matches(".svg")
            .to_owned();
        base.with_file_name(format!("{stem}.{extension}"))
            .display()
            .to_string()
    }

    pub(crate) fn files_dropped(&mut self, ctx: &egui::Context) {
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        });
        if let Some(path) = dropped.into_iter().next() {
            self.request(ctx, After::Open(Some(path)));
        }
    }

    pub(crate) fn close_requested(&mut self, ctx: &egui::Context) {
        if ctx.input(|i| i.viewport().close_requested())
            && !self.files.allow_quit
            && self.editor.is_dirty()
        {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.files.prompt = Some(Prompt::Unsaved(After::Quit));
        }
    }

    /// Hands unsaved work to the autosave thread, which writes it on its own timer
    /// (frames or not); removes this run's autosave once nothing is unsaved.
    pub(crate) fn autosave_tick(&mut self) {
        let (revision, dirty) = (self.editor.revision(), self.editor.is_dirty());
        if self.files.autosave.wants(revision, dirty) {
            let work = self.autosave_work();
            self.files.autosave.hand(revision, work);
        }
    }

    fn autosave_work(&self) -> Work {
        Work {
            session: self.session(),
            origin: self.editor.origin().cloned(),
        }
    }

    /// Writes the work to the autosave file now (tests, and before risky steps).
    pub fn autosave_now(&mut self) {
        let work = self.autosave_work();
        if let Err(error) = self.files.autosave.write_now(self.editor.revision(), &work) {
            log::warn!("autosave failed: {error:#}");
        }
    }

    /// The autosave left by a run that did not end well, if any: the recovery prompt
    /// offers it at start.
    pub fn pending_autosave(&self) -> Option<PathBuf> {
        self.files.autosave.pending().map(|r| r.path)
    }

    /// The modal window of the question being asked, if any.
    pub(crate) fn prompts(&mut self, ctx: &egui::Context) {
        let Some(prompt) = self.files.prompt.clone() else {
            return;
        };
        let modal = egui::Modal::new(egui::Id::unique("prompt")).show(ctx, |ui| {
            ui.set_max_width(460.0);
            match prompt {
                Prompt::Unsaved(after) => {
                    ui.heading("Unsaved changes");
                    ui.label("Save the changes to this work first?");
                    ui.horizontal(|ui| {
                        if ui.button("Save").clicked() {
                            self.files.prompt = None;
                            if self.save(ctx) {
                                self.proceed(ctx, after.clone());
                            }
                        }
                        if ui.button("Don't save").clicked() {
                            self.files.prompt = None;
                            // The user discarded the work: no later start offers it back.
                            self.files.autosave.clear();
                            self.proceed(ctx, after.clone());
                        }
                        if ui.button("Cancel").clicked() {
                            self.files.prompt = None;
                        }
                    });
                }
                Prompt::Recover(recovery) => {
                    ui.heading("Recover unsaved work?");
                    let zone = jiff::tz::TimeZone::try_system().unwrap_or(jiff::tz::TimeZone::UTC);
                    ui.label(format!(
                        "{}.",
                        recovery.describe(std::time::SystemTime::now(), &zone)
                    ));
                    ui.label("geosnap did not close properly last time; this work was autosaved.");
                    ui.horizontal(|ui| {
                        if ui.button("Recover").clicked() {
                            self.files.prompt = None;
                            self.recover(ctx, &recovery.path);
                        }
                        if ui.button("Discard").clicked() {
                            self.files.prompt = None;
                            self.files.autosave.clear();
                        }
                    });
                }
                Prompt::Path(action, mut text) => {
                    ui.heading(match action {
                        PathAction::Open => "Open a file",
                        PathAction::SaveAs => "Save the session as",
                        PathAction::Export => "Export glTF (.glb or .gltf) as",
                    });
                    let edit = ui.add(
                        egui::TextEdit::singleline(&mut text)
                            .desired_width(420.0)
                            .hint_text("/path/to/file"),
                    );
                    let edit = edit.on_hover_text("File path");
                    if std::mem::take(&mut self.files.focus_path) {
                        // Typing goes to the path at once, without a click.
                        edit.request_focus();
                    }
                    let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                    self.files.prompt = Some(Prompt::Path(action, text.clone()));
                    ui.horizontal(|ui| {
                        if ui.button("OK").clicked() || enter {
                            self.files.prompt = None;
                            let path = PathBuf::from(text.trim());
                            match action {
                                PathAction::Open => self.request(ctx, After::Open(Some(path))),
                                PathAction::SaveAs => {
                                    self.save_to(ctx, &path);
                                }
                                PathAction::Export => self.export_to(&path),
                            }
                        }
                        if ui.button("Cancel").clicked() {
                            self.files.prompt = None;
                        }
                    });
                }
                Prompt::Image(path) => self.image_prompt(ui, &path),
                Prompt::Export => self.export_prompt(ui),
                Prompt::Error(text) => {
                    ui.heading("Problem");
                    ui.label(text);
                    if ui.button("OK").clicked() {
                        self.files.prompt = None;
                    }
                }
            }
        });
        if modal.should_close()
            && matches!(
                self.files.prompt,
                Some(Prompt::Error(_) | Prompt::Path(..) | Prompt::Image(_) | Prompt::Export)
            )
        {
            self.files.prompt = None;
        }
    }
}

impl GeosnapApp {
    /// The question of an image opened while a drawing is open.
    fn image_prompt(&mut self, ui: &mut egui::Ui, path: &Path) {
        let ctx = ui.ctx().clone();
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        ui.heading(format!("Open the image {name}"));
        ui.label("A drawing is open. Use the image as the reference under this drawing, or start a new drawing on it?");
        ui.horizontal(|ui| {
            if ui.button("Reference under this drawing").clicked() {
                self.files.prompt = None;
                self.open_path(&ctx, path);
            }
            if ui.button("New drawing from it").clicked() {
                self.files.prompt = None;
                self.request(&ctx, After::NewFromImage(path.to_owned()));
            }
            if ui.button("Cancel").clicked() {
                self.files.prompt = None;
            }
        });
    }
}

/// What the document's unit means (the unit's hover text in Settings and the export
/// dialog).
pub(crate) const UNIT_HOVER: &str = "What one unit of the drawing is: every length is shown \
     in it, the export converts it to metres, and the session file keeps it";

/// Whether a file dialog that came back empty was never shown (no desktop portal, as
/// headless): nobody cancels a dialog within a fraction of a second. The typed-path
/// window then takes its place.
fn no_dialog(asked: Instant) -> bool {
    asked.elapsed() < Duration::from_millis(400)
}

/// The start of a file, enough to tell what it holds ([`file_kind`]).
fn read_head(path: &Path) -> std::io::Result<Vec<u8>> {
    let mut head = Vec::with_capacity(4096);
    std::fs::File::open(path)?
        .take(4096)
        .read_to_end(&mut head)?;
    Ok(head)
}

fn is_image(path: &Path) -> bool {
    path.extension().is_some_and(|e| {
        ["png", "jpg", "jpeg"].contains(&e.to_string_lossy().to_ascii_lowercase().as_str())
    })
}

fn is_session_path(path: &Path) -> bool {
    path.to_string_lossy().ends_with(".json")
        && std::fs::read(path).map_or(true, |b| {
            String::from_utf8_lossy(&b[..b.len().min(4096)]).contains("geosnap-session")
        })
}

pub(super) fn load_texture(
    ctx: &egui::Context,
    path: &Path,
    bytes: &[u8],
) -> anyhow::Result<egui::TextureHandle> {
    let image = image::load_from_memory(bytes)
        .map_err(|e| anyhow!("not a PNG or JPEG image this build can read ({e})"))?
        .to_rgba8();
    let size = [image.width() as usize, image.height() as usize];
    let color = egui::ColorImage::from_rgba_unmultiplied(size, image.as_raw());
    Ok(ctx.load_texture(
        path.display().to_string(),
        color,
        egui::TextureOptions::LINEAR,
    ))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::{file_kind, FileKind};

    #[test]
    fn files_are_told_apart_by_content_then_extension() {
        let p = Path::new("x.dat");
        assert_eq!(file_kind(p, b"\x89PNG\r\n"), Some(FileKind::Image));
        assert_eq!(
            file_kind(p, &[0xFF, 0xD8, 0xFF, 0xE0]),
            Some(FileKind::Image)
        );
        assert_eq!(
            file_kind(p, br#"{"format": "geosnap-session"}"#),
            Some(FileKind::Session)
        );
        assert_eq!(
            file_kind(p, br#"{"format": "geosnap-sketch"}"#),
            Some(FileKind::Sketch)
        );
        assert_eq!(file_kind(p, b"<svg/>"), Some(FileKind::Sketch));
        assert_eq!(
            file_kind(Path::new("a.jpeg"), b"garbage"),
            Some(FileKind::Image)
        );
        assert_eq!(file_kind(p, b"garbage"), None);
    }
}
