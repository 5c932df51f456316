//! Work off the UI thread, without any GUI: the drag preview (one snapping thread, newest
//! request wins) and document jobs (a placement's snap, inference and global solve, or a
//! re-solve), each cancellable and reporting progress.
//!
//! The UI hands in a `wake` callback (egui's `request_repaint`) that is called whenever a
//! result is ready, so the UI never polls in a busy loop.

use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::editor::Editor;
use crate::clock::MonotonicClock;
use crate::core::geom::projection::sketch_from_model;
use crate::core::model::{Companions, Document, Fit, GlobalOutcome, PrimitiveId, SessionSettings};
use crate::core::primitive::Primitive;
use crate::core::snap::{snap, snap_at, SnapContext, SnapError, SnapResult, SnapSession, Verdict};
use crate::core::solve::{CancelFlag, Iterate, SolveContext};

/// Called from a worker thread when something is ready for the UI.
pub type Wake = Arc<dyn Fn() + Send + Sync>;

/// A drag frame to snap.
#[derive(Clone, Debug)]
pub struct PreviewRequest {
    /// Increases with every request; results carry it back.
    pub generation: u64,
    /// The primitive where the cursor put it.
    pub dragged: Primitive,
    /// The strokes, with the model's parts placed.
    pub context: Arc<SnapContext>,
    /// The context's revision (a new one starts the session afresh: the strokes or the
    /// placed parts changed).
    pub context_revision: u64,
    /// Whether the drop gives no size or direction (a palette drag the wheel has not
    /// sized or turned): the drawing sizes and turns it (`snap_at`), `dragged` giving
    /// only its kind and the point.
    pub point: bool,
}

/// The snapped preview of a drag frame.
#[derive(Clone, Debug)]
pub struct PreviewResult {
    /// The request's generation.
    pub generation: u64,
    /// The snap, or why it failed (too few strokes near the primitive, ...).
    pub result: Result<SnapResult, SnapError>,
    /// How long the snap took.
    pub elapsed: Duration,
    /// For a point drop, the guess (the drop sized and turned by the drawing) its snap
    /// came from, which stands for the drop in its confidence.
    pub guess: Option<Primitive>,
}

#[derive(Default)]
struct Slot {
    request: Option<PreviewRequest>,
    quit: bool,
}

/// The drag-preview thread: the newest request is snapped next; requests that arrive
/// while a frame is being snapped replace each other, so the preview follows the cursor
/// with at most one frame of lag.
pub struct Previewer {
    slot: Arc<(Mutex<Slot>, Condvar)>,
    results: Receiver<PreviewResult>,
    thread: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for Previewer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Previewer").finish_non_exhaustive()
    }
}

impl Previewer {
    /// Starts the thread.
    pub fn start(settings: crate::core::snap::SnapSettings, wake: Wake) -> Self {
        let slot: Arc<(Mutex<Slot>, Condvar)> = Arc::default();
        let (sender, results) = channel();
        let shared = Arc::clone(&slot);
        let thread = std::thread::Builder::new()
            .name("geosnap-preview".into())
            .spawn(move || preview_loop(&shared, &settings, &sender, &wake))
            .ok();
        Self {
            slot,
            results,
            thread,
        }
    }

    /// Asks for a frame; an older request not yet started is dropped.
    pub fn request(&self, request: PreviewRequest) {
        let (lock, ready) = &*self.slot;
        lock.lock().unwrap_or_else(PoisonError::into_inner).request = Some(request);
        ready.notify_one();
    }

    /// Drops a request not yet started (the drag ended).
    pub fn clear(&self) {
        let (lock, _) = &*self.slot;
        lock.lock().unwrap_or_else(PoisonError::into_inner).request = None;
    }

    /// The newest finished frame, if any arrived since the last call.
    pub fn latest(&self) -> Option<PreviewResult> {
        self.results.try_iter().last()
    }

    /// Waits up to `timeout` for the next finished frame (tests and benchmarks).
    pub fn wait(&self, timeout: Duration) -> Option<PreviewResult> {
        self.results.recv_timeout(timeout).ok()
    }
}

impl Drop for Previewer {
    fn drop(&mut self) {
        let (lock, ready) = &*self.slot;
        lock.lock().unwrap_or_else(PoisonError::into_inner).quit = true;
        ready.notify_one();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn preview_loop(
    slot: &(Mutex<Slot>, Condvar),
    settings: &crate::core::snap::SnapSettings,
    results: &Sender<PreviewResult>,
    wake: &Wake,
) {
    let mut session: Option<(u64, SnapSession)> = None;
    loop {
        let request = {
            let (lock, ready) = slot;
            let mut guard = lock.lock().unwrap_or_else(PoisonError::into_inner);
            loop {
                if guard.quit {
                    return;
                }
                if let Some(request) = guard.request.take() {
                    break request;
                }
                guard = ready.wait(guard).unwrap_or_else(PoisonError::into_inner);
            }
        };
        let fresh = session
            .as_ref()
            .is_none_or(|(revision, _)| *revision != request.context_revision);
        if fresh {
            session = Some((
                request.context_revision,
                SnapSession::new((*request.context).clone(), settings.clone()),
            ));
        }
        let Some((_, session)) = session.as_mut() else {
            continue;
        };
        let started = Instant::now();
        let (result, guess) = if request.point {
            let at = sketch_from_model(request.dragged.center());
            match session.update_at(request.dragged.kind(), at, None, SolveContext::default()) {
                Ok(p) => (Ok(p.result), Some(p.guess)),
                Err(e) => (Err(e), None),
            }
        } else {
            (
                session.update(&request.dragged, SolveContext::default()),
                None,
            )
        };
        let sent = results.send(PreviewResult {
            generation: request.generation,
            result,
            elapsed: started.elapsed(),
            guess,
        });
        if sent.is_err() {
            return;
        }
        wake();
    }
}

/// The app's work off the UI thread: the drag-preview thread, the running job, and the
/// snapping context of the current strokes that both use.
pub(crate) struct Workers {
    wake: Wake,
    previewer: Previewer,
    job: Option<Job>,
    /// The snapping context and the strokes' revision it was built from.
    context: (Arc<SnapContext>, u64),
    /// That context with the model's parts placed (see [`Workers::context`]), what it was
    /// built for and its revision.
    placed: Option<(Arc<SnapContext>, PlacedKey, u64)>,
    /// The revision the next context with parts placed gets.
    next_revision: u64,
}

/// What a snapping context with the model's parts placed was built for: the strokes'
/// revision, the model's revision and the part being moved (not placed: it is the one
/// snapped).
type PlacedKey = (u64, u64, Option<PrimitiveId>);

impl std::fmt::Debug for Workers {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Workers")
            .field("job", &self.job)
            .finish_non_exhaustive()
    }
}

impl Workers {
    /// Starts the preview thread with the editor's snap settings; `wake` is called when
    /// a result is ready.
    pub(crate) fn start(editor: &Editor, wake: Wake) -> Self {
        Self {
            previewer: Previewer::start(editor.settings().snap.clone(), Arc::clone(&wake)),
            wake,
            job: None,
            context: (
                Arc::new(SnapContext::from_sketch(editor.sketch())),
                editor.strokes_revision(),
            ),
            placed: None,
            next_revision: 0,
        }
    }

    /// The callback that wakes the UI (for other threads of the app).
    pub(crate) fn wake(&self) -> Wake {
        Arc::clone(&self.wake)
    }

    /// Takes a snapping context prepared elsewhere (off the UI thread) for the strokes
    /// of `revision`.
    pub(crate) fn set_context(&mut self, context: Arc<SnapContext>, revision: u64) {
        self.context = (context, revision);
    }

    /// The running job.
    pub(crate) fn job(&self) -> Option<&Job> {
        self.job.as_ref()
    }

    /// Whether a job is running.
    pub(crate) fn busy(&self) -> bool {
        self.job.is_some()
    }

    /// The snapping context of the editor's strokes (prepared again when they change)
    /// with the model's parts placed but `moving` (the part being dragged again, if
    /// any): a reading that holds a placed part gives way to one that holds none (see
    /// `SnapContext::with_placed`). With the context's revision, new whenever the strokes,
    /// the model or the part moving change.
    pub(crate) fn context(
        &mut self,
        editor: &Editor,
        moving: Option<PrimitiveId>,
    ) -> (Arc<SnapContext>, u64) {
        let revision = editor.strokes_revision();
        if self.context.1 != revision {
            self.context = (
                Arc::new(SnapContext::from_sketch(editor.sketch())),
                revision,
            );
        }
        let key = (revision, editor.revision(), moving);
        match &self.placed {
            Some((context, built, revision)) if *built == key => (Arc::clone(context), *revision),
            _ => {
                let parts: Vec<Primitive> = editor
                    .document()
                    .primitives()
                    .filter(|(id, _)| Some(*id) != moving)
                    .map(|(_, placed)| placed.primitive.clone())
                    .collect();
                let context = if parts.is_empty() {
                    Arc::clone(&self.context.0)
                } else {
                    Arc::new((*self.context.0).clone().with_placed(parts))
                };
                let revision = self.next_revision;
                self.next_revision += 1;
                self.placed = Some((Arc::clone(&context), key, revision));
                (context, revision)
            }
        }
    }

    /// Asks the preview thread for a frame.
    pub(crate) fn request_preview(&self, request: PreviewRequest) {
        self.previewer.request(request);
    }

    /// Drops a preview request not yet started.
    pub(crate) fn clear_preview(&self) {
        self.previewer.clear();
    }

    /// The newest finished preview, if any arrived since the last call.
    pub(crate) fn latest_preview(&self) -> Option<PreviewResult> {
        self.previewer.latest()
    }

    /// Starts `work` as the running job, labelled `label`, for editor revision
    /// `revision`.
    pub(crate) fn spawn(
        &mut self,
        label: String,
        revision: u64,
        work: impl FnOnce(&CancelFlag, &mut dyn FnMut(&Iterate<'_>)) -> JobOutput + Send + 'static,
    ) {
        self.job = Some(Job::spawn(label, revision, Arc::clone(&self.wake), work));
    }

    /// Asks the running job to stop.
    pub(crate) fn cancel_job(&self) {
        if let Some(job) = &self.job {
            job.cancel();
        }
    }

    /// The running job with its output, once it has finished (it is then no longer
    /// running).
    pub(crate) fn finished(&mut self) -> Option<(Job, JobOutput)> {
        let output = self.job.as_ref().and_then(Job::try_result)?;
        self.job.take().map(|job| (job, output))
    }
}

/// Where a running job stands, for the status bar.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Progress {
    /// Outer iterations of the current solve.
    pub iterations: usize,
    /// ‖c‖∞ of the last iterate.
    pub violation: f64,
    /// Time since the job started.
    pub elapsed: Duration,
}

/// What a job produced.
#[derive(Clone, Debug)]
pub struct JobOutput {
    /// The new model (`None`: nothing to change, see the messages).
    pub document: Option<Document>,
    /// The placed or re-snapped part.
    pub placed: Option<PrimitiveId>,
    /// The global solve.
    pub outcome: Option<GlobalOutcome>,
    /// What the user should read (conflicts, failures).
    pub messages: Vec<String>,
    /// Whether the job was cancelled (nothing changes).
    pub cancelled: bool,
    /// Whether the part was placed as dragged, unsnapped (no strokes supported it).
    pub placed_freely: bool,
    /// The poses the snap found for the placed part (the one placed shown), for the
    /// pose chooser; `None` when it found one only.
    pub readings: Option<Readings>,
    /// How long it took.
    pub elapsed: Duration,
}

impl JobOutput {
    /// An output that changes nothing yet.
    fn empty() -> Self {
        Self {
            document: None,
            placed: None,
            outcome: None,
            messages: Vec::new(),
            cancelled: false,
            placed_freely: false,
            readings: None,
            elapsed: Duration::ZERO,
        }
    }
}

/// The readings of the drawing a snap found for one drop: the pose it chose and the
/// alternatives ([`SnapResult::alternatives`]), each as a snap of its own, with the one
/// shown. Tab during a drag, or on a placed part, shows the next.
#[derive(Clone, Debug)]
pub struct Readings {
    /// The primitive as it was dropped (confidence is judged against it).
    pub dropped: Primitive,
    /// Every pose, the snap's own choice first.
    pub poses: Vec<SnapResult>,
    /// The pose shown (an index into `poses`).
    pub shown: usize,
    /// Whether the pose shown was chosen by hand (Tab), rather than taken as the snap
    /// chose it: the snap's own choice too, when Tab on a placed part came back round
    /// to it.
    pub by_hand: bool,
}

impl Readings {
    /// The poses of a cold snap of `dropped`: its choice, then each alternative.
    pub fn of(dropped: Primitive, snapped: &SnapResult) -> Self {
        let mut poses = vec![snapped.clone()];
        poses.extend((0..snapped.alternatives.len()).filter_map(|i| snapped.with_alternative(i)));
        Self {
            dropped,
            poses,
            shown: 0,
            by_hand: false,
        }
    }

    /// The pose shown.
    pub fn pose(&self) -> Option<&SnapResult> {
        self.poses.get(self.shown)
    }

    /// Whether there is more than one pose to choose from.
    pub fn has_choice(&self) -> bool {
        self.poses.len() > 1
    }

    /// These readings with the next pose shown (after the last, the first again).
    #[must_use]
    pub fn next(&self) -> Self {
        Self {
            shown: (self.shown + 1) % self.poses.len().max(1),
            by_hand: true,
            ..self.clone()
        }
    }
}

/// A running job.
#[derive(Debug)]
pub struct Job {
    /// The undo label of its result ("Place cylinder").
    pub label: String,
    /// The editor revision it started from: a result for an older revision is dropped.
    pub revision: u64,
    cancel: CancelFlag,
    progress: Arc<Mutex<Progress>>,
    result: Receiver<JobOutput>,
    started: Instant,
}

impl Job {
    /// Runs `work` on a new thread with a cancel flag and a progress observer.
    pub fn spawn(
        label: String,
        revision: u64,
        wake: Wake,
        work: impl FnOnce(&CancelFlag, &mut dyn FnMut(&Iterate<'_>)) -> JobOutput + Send + 'static,
    ) -> Self {
        let cancel = CancelFlag::new();
        let progress: Arc<Mutex<Progress>> = Arc::default();
        let (sender, result) = channel();
        let (flag, shared) = (cancel.clone(), Arc::clone(&progress));
        let started = Instant::now();
        let spawned = std::thread::Builder::new()
            .name("geosnap-solve".into())
            .spawn(move || {
                let mut last_wake = Instant::now();
                let mut observe = |it: &Iterate<'_>| {
                    let mut p = shared.lock().unwrap_or_else(PoisonError::into_inner);
                    p.iterations = it.outer;
                    p.violation = it.max_violation;
                    p.elapsed = started.elapsed();
                    drop(p);
                    if last_wake.elapsed() > Duration::from_millis(50) {
                        last_wake = Instant::now();
                        wake();
                    }
                };
                let mut output = work(&flag, &mut observe);
                output.elapsed = started.elapsed();
                let _ = sender.send(output);
                wake();
            });
        if let Err(error) = spawned {
            log::error!("cannot start a solve thread: {error}");
        }
        Self {
            label,
            revision,
            cancel,
            progress,
            result,
            started,
        }
    }

    /// Asks the job to stop; its result then says `cancelled`.
    pub fn cancel(&self) {
        self.cancel.cancel();
    }

    /// Whether cancelling was asked for.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.is_cancelled()
    }

    /// The progress so far.
    pub fn progress(&self) -> Progress {
        let mut p = self
            .progress
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone();
        p.elapsed = self.started.elapsed();
        p
    }

    /// The result, once the job is done.
    pub fn try_result(&self) -> Option<JobOutput> {
        self.result.try_recv().ok()
    }

    /// Waits up to `timeout` for the result (tests).
    pub fn wait(&self, timeout: Duration) -> Option<JobOutput> {
        self.result.recv_timeout(timeout).ok()
    }
}

/// The snap of `dragged` and the drop it stands for: itself, or for a point drop
/// (`point`: no size or direction given) the guess the drawing sized and turned.
fn snap_drop(
    context: &SnapContext,
    dragged: &Primitive,
    point: bool,
    settings: &crate::core::snap::SnapSettings,
) -> Result<(SnapResult, Primitive), SnapError> {
    if point {
        let at = sketch_from_model(dragged.center());
        snap_at(context, dragged.kind(), at, None, settings).map(|p| (p.result, p.guess))
    } else {
        snap(context, dragged, settings).map(|s| (s, dragged.clone()))
    }
}

/// The job of a release: snap `dragged` (or take the pose `readings` shows, as its
/// preview showed it), add it (in place of `replacing` when re-dragging a part), infer
/// its relations and solve.
#[expect(
    clippy::too_many_arguments,
    reason = "a job's inputs, moved to its thread"
)]
pub(crate) fn place(
    mut document: Document,
    context: &SnapContext,
    (dragged, point): (&Primitive, bool),
    readings: Option<Readings>,
    replacing: Option<PrimitiveId>,
    (settings, unit): (&SessionSettings, super::words::Unit),
    cancel: &CancelFlag,
    observer: &mut dyn FnMut(&Iterate<'_>),
) -> JobOutput {
    let mut output = JobOutput::empty();
    // A part moved keeps the name it was given.
    let name = replacing
        .and_then(|old| document.name(old))
        .map(str::to_owned);
    let (snapped, dropped, readings) = match readings {
        Some(readings) if readings.pose().is_some() => {
            let Some(pose) = readings.pose().cloned() else {
                return output;
            };
            let dropped = readings.dropped.clone();
            (pose, dropped, readings)
        }
        _ => match snap_drop(context, dragged, point, &settings.snap) {
            Ok((s, dropped)) => {
                let readings = Readings::of(dropped.clone(), &s);
                (s, dropped, readings)
            }
            Err(SnapError::Cancelled) => {
                output.cancelled = true;
                return output;
            }
            // Strokes that do not support the part (none, or a fit that runs away from
            // the drop): it goes where it was dropped, as the drag legend says.
            Err(error) => {
                let why = match error {
                    SnapError::NotEnoughStrokes { .. } => "no strokes here support it".to_owned(),
                    other => super::words::snap_error(&other, false),
                };
                let free = Free {
                    replacing,
                    name: None,
                    why: &why,
                };
                return place_freely(document, dragged, &free, settings, cancel, observer);
            }
        },
    };
    if cancel.is_cancelled() {
        output.cancelled = true;
        return output;
    }
    if let Some(old) = replacing {
        document.remove(old);
    }
    let confidence = judge(&snapped, &dropped, &document, &readings, settings);
    if confidence.verdict == Verdict::Refused {
        // Nothing here supports it: it goes where it was dropped, unsnapped.
        let why = confidence
            .reason
            .as_deref()
            .unwrap_or("nothing in the drawing supports it");
        let free = Free {
            replacing: None,
            name: name.as_deref(),
            why,
        };
        return place_freely(document, &dropped, &free, settings, cancel, observer);
    }
    let id = document.add_fitted(&snapped, Fit::of(&snapped).judged(&confidence));
    if let Some(name) = &name {
        document.set_name(id, name);
    }
    let Some((relations, outcome)) = release(&mut document, id, settings, cancel, observer) else {
        output.cancelled = true;
        return output;
    };
    if let Some(placed) = document.get(id) {
        let name = super::words::part_name(&document, id);
        output.messages.push(format!(
            "{name} snapped to {} strokes, {} off on average.",
            placed.fit.strokes.len(),
            super::words::length(placed.fit.rms, unit)
        ));
        if let Some(reason) = &placed.fit.reason {
            output
                .messages
                .push(format!("{name} is doubtful: {reason}."));
        }
        if readings.has_choice() {
            output.messages.push(format!(
                "{name} is pose {} of the {} the drawing allows: Tab shows the next.",
                readings.shown + 1,
                readings.poses.len()
            ));
        }
    }
    output
        .messages
        .extend(describe(&document, &outcome, relations.len()));
    output.placed = Some(id);
    output.outcome = Some(outcome);
    output.document = Some(document);
    output.readings = readings.has_choice().then_some(readings);
    output
}

/// The confidence of `snapped`, a snap of `dropped` into `document`. A pose the user
/// chose with Tab settles the question of which reading is meant: it is judged without
/// its rivals, and never refused (at worst doubtful, saying why). That holds for the
/// snap's own choice too when Tab came back round to it: refused, it would be placed
/// unsnapped and its readings lost, and Tab could not go on to the next.
fn judge(
    snapped: &SnapResult,
    dropped: &Primitive,
    document: &Document,
    readings: &Readings,
    settings: &SessionSettings,
) -> crate::core::snap::Confidence {
    if !readings.by_hand {
        return snapped.confidence(dropped, &document.owner(), &settings.snap);
    }
    let mut chosen = snapped.clone();
    chosen.alternatives.clear();
    let mut confidence = chosen.confidence(dropped, &document.owner(), &settings.snap);
    if confidence.verdict == Verdict::Refused {
        confidence.verdict = Verdict::Doubtful;
        confidence.reason = Some(format!(
            "a pose chosen by hand, although {}",
            confidence
                .reason
                .as_deref()
                .unwrap_or("the drawing hardly supports it")
        ));
    }
    confidence
}

/// Infers part `id`'s relations and solves its component; `None` when cancelled.
fn release(
    document: &mut Document,
    id: PrimitiveId,
    settings: &SessionSettings,
    cancel: &CancelFlag,
    observer: &mut dyn FnMut(&Iterate<'_>),
) -> Option<(Vec<crate::core::model::RelationId>, GlobalOutcome)> {
    let clock = MonotonicClock::start();
    let mut observe = |it: &Iterate<'_>| observer(it);
    let (relations, outcome) = document.release(
        id,
        &settings.inference,
        &settings.global,
        Companions {
            cancel: Some(cancel),
            clock: Some(&clock),
            observer: Some(&mut observe),
        },
    );
    (!cancel.is_cancelled()).then_some((relations, outcome))
}

/// The job of a re-solve (after a relation's mode or a dimension changed): every part
/// in the components of `changed`, or the whole model.
pub fn resolve(
    mut document: Document,
    changed: Option<&[PrimitiveId]>,
    settings: &SessionSettings,
    cancel: &CancelFlag,
    observer: &mut dyn FnMut(&Iterate<'_>),
) -> JobOutput {
    let clock = MonotonicClock::start();
    let global = settings.global.clone().with_reach(None);
    let mut observe = |it: &Iterate<'_>| observer(it);
    let outcome = document.solve(
        changed,
        &global,
        Companions {
            cancel: Some(cancel),
            clock: Some(&clock),
            observer: Some(&mut observe),
        },
    );
    let cancelled = cancel.is_cancelled();
    JobOutput {
        messages: describe(&document, &outcome, 0),
        document: (!cancelled).then_some(document),
        placed: None,
        outcome: Some(outcome),
        cancelled,
        ..JobOutput::empty()
    }
}

/// Why and in place of what a part is placed freely.
#[derive(Clone, Copy, Debug)]
pub struct Free<'a> {
    /// The part it replaces (a placed part moved).
    pub replacing: Option<PrimitiveId>,
    /// The name it takes (`None`: the name of the part it replaces, if any).
    pub name: Option<&'a str>,
    /// Why it was not snapped, in words.
    pub why: &'a str,
}

/// Places `dragged` as it is, unsnapped (in place of `free.replacing` when moving a
/// part): a drop where no strokes support a part, or an Alt + drop. The part has no
/// strokes in its fit, which marks it "placed freely" on the canvas, in the panel and
/// in the saved session.
///
/// The user put it there on purpose, so it is related to the other parts as a snapped
/// part is (the same inference, with the same confidence tiers) and the model solved;
/// with no strokes of its own, the solve holds it near where it was dropped (an
/// anchor) while its hard relations are met.
pub fn place_freely(
    mut document: Document,
    dragged: &Primitive,
    free: &Free<'_>,
    settings: &SessionSettings,
    cancel: &CancelFlag,
    observer: &mut dyn FnMut(&Iterate<'_>),
) -> JobOutput {
    let name = free
        .name
        .or_else(|| free.replacing.and_then(|old| document.name(old)))
        .map(str::to_owned);
    if let Some(old) = free.replacing {
        document.remove(old);
    }
    let id = document.add(crate::core::model::Placed {
        primitive: dragged.clone(),
        fit: Fit::default(),
    });
    if let Some(name) = &name {
        document.set_name(id, name);
    }
    let Some((relations, outcome)) = release(&mut document, id, settings, cancel, observer) else {
        return JobOutput {
            cancelled: true,
            ..JobOutput::empty()
        };
    };
    let name = super::words::part_name(&document, id);
    let mut messages = vec![format!(
        "{name} was placed freely, where it was dropped: {}. Drag it onto its strokes \
         to snap it.",
        free.why
    )];
    messages.extend(describe(&document, &outcome, relations.len()));
    JobOutput {
        messages,
        document: Some(document),
        placed: Some(id),
        outcome: Some(outcome),
        placed_freely: true,
        ..JobOutput::empty()
    }
}

/// The messages of a solve for the user, in words (the relations and parts by name).
fn describe(document: &Document, outcome: &GlobalOutcome, inferred: usize) -> Vec<String> {
    let mut messages: Vec<String> = outcome
        .conflicts
        .iter()
        .map(|c| super::words::conflict(document, document.relation(c.relation), &c.message))
        .collect();
    if outcome.reverted {
        messages.push(
            "The solve could not make the model consistent; the parts were put back as \
             they were."
                .to_owned(),
        );
    }
    if inferred > 0 && messages.is_empty() {
        messages.push(format!(
            "{inferred} relation{} inferred.",
            if inferred == 1 { "" } else { "s" }
        ));
    }
    messages
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;
    use std::time::Duration;

    use glam::DVec2;

    use super::{place, Job, PreviewRequest, Previewer};
    use crate::core::model::{Document, SessionSettings};
    use crate::core::primitive::{Placement, Primitive, PrimitiveKind};
    use crate::core::snap::{SnapContext, SnapSettings};
    use crate::io::svg::{import_svg, SvgOptions};
    use crate::samples::VASE_SVG;

    fn vase() -> (Arc<SnapContext>, Primitive) {
        let sketch = import_svg(VASE_SVG.as_bytes(), &SvgOptions::default())
            .expect("the sample imports")
            .sketch;
        let (lo, hi) = sketch.bounds().expect("the sample has strokes");
        let centre = (lo + hi) / 2.0;
        let at = centre + DVec2::new(3.0, 2.0);
        let size = crate::app::size_under(&sketch, at, (hi - lo).max_element() * 0.3);
        let dragged = Primitive::from_placement(PrimitiveKind::Sgc, &Placement::at(at), size);
        (Arc::new(SnapContext::from_sketch(&sketch)), dragged)
    }

    #[test]
    fn the_snapping_context_holds_the_models_parts_but_the_one_moving() {
        use super::Workers;
        use crate::app::editor::Editor;
        use crate::core::model::{Fit, Placed};
        let sketch = import_svg(VASE_SVG.as_bytes(), &SvgOptions::default())
            .expect("the sample imports")
            .sketch;
        let mut editor = Editor::with_sketch(sketch, None);
        let mut workers = Workers::start(&editor, Arc::new(|| {}));
        let (empty, first) = workers.context(&editor, None);
        assert_eq!(empty.placed().count(), 0);
        // Asked again for the same model, the same context.
        assert_eq!(workers.context(&editor, None).1, first);
        let part = Primitive::from_placement(
            PrimitiveKind::Cylinder,
            &Placement::at(DVec2::new(100.0, 100.0)),
            50.0,
        );
        let mut document = Document::new();
        let id = document.add(Placed {
            primitive: part.clone(),
            fit: Fit::default(),
        });
        editor.apply_document("place a part", document);
        let (placed, second) = workers.context(&editor, None);
        assert_ne!(second, first, "a new model is a new context");
        assert_eq!(placed.placed().cloned().collect::<Vec<_>>(), vec![part]);
        assert_eq!(placed.strokes, empty.strokes);
        // The part being moved is the one snapped, not a placed one.
        let (moving, third) = workers.context(&editor, Some(id));
        assert_ne!(third, second);
        assert_eq!(moving.placed().count(), 0);
    }

    #[test]
    fn the_previewer_answers_the_newest_request() {
        let (context, dragged) = vase();
        let previewer = Previewer::start(SnapSettings::default(), Arc::new(|| {}));
        for generation in 0..5 {
            previewer.request(PreviewRequest {
                generation,
                dragged: dragged.clone(),
                context: Arc::clone(&context),
                context_revision: 0,
                point: false,
            });
        }
        let mut last = None;
        while let Some(result) = previewer.wait(Duration::from_secs(20)) {
            last = Some(result.generation);
            if result.generation == 4 {
                break;
            }
        }
        assert_eq!(last, Some(4), "the newest request is always answered");
    }

    #[test]
    fn a_placement_job_snaps_and_adds_the_part_and_can_be_cancelled() {
        let (context, dragged) = vase();
        let settings = SessionSettings::default();
        let job = {
            let (context, dragged, settings) =
                (Arc::clone(&context), dragged.clone(), settings.clone());
            Job::spawn(
                "Place".into(),
                0,
                Arc::new(|| {}),
                move |cancel, observe| {
                    place(
                        Document::new(),
                        &context,
                        (&dragged, false),
                        None,
                        None,
                        (&settings, crate::app::words::Unit::default()),
                        cancel,
                        observe,
                    )
                },
            )
        };
        let output = job.wait(Duration::from_mins(1)).expect("the job ends");
        let document = output.document.expect("the SGC snaps onto the vase");
        let id = output.placed.expect("a part was placed");
        assert!(!document.get(id).expect("placed").fit.strokes.is_empty());

        let job = Job::spawn(
            "Place".into(),
            0,
            Arc::new(|| {}),
            move |cancel, observe| {
                cancel.cancel();
                place(
                    Document::new(),
                    &context,
                    (&dragged, false),
                    None,
                    None,
                    (&settings, crate::app::words::Unit::default()),
                    cancel,
                    observe,
                )
            },
        );
        let output = job.wait(Duration::from_mins(1)).expect("the job ends");
        assert!(output.cancelled && output.document.is_none());
    }
}
