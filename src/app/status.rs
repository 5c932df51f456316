//! What the app tells the user: the message log, the status bar with the running job or
//! the last solve, and the frame times it shows.

use std::collections::VecDeque;
use std::time::Duration;

use egui::{Color32, RichText, Ui};

use super::worker::{Job, JobOutput};
use super::GeosnapApp;

/// A message in the log.
#[derive(Clone, Debug)]
pub struct Message {
    /// The text.
    pub text: String,
    /// Whether it reports a problem.
    pub warning: bool,
}

/// The last solve, for the status bar.
#[derive(Clone, Debug)]
struct LastSolve {
    iterations: usize,
    /// ‖c‖∞ at the end.
    violation: f64,
    seconds: f64,
    /// How it ended.
    how: String,
}

/// The message log, the last solve and the frame times.
#[derive(Debug, Default)]
pub(crate) struct Status {
    /// Newest last.
    messages: Vec<Message>,
    last_solve: Option<LastSolve>,
    timer: FrameTimer,
}

impl Status {
    /// A log starting with `messages`.
    pub(crate) fn new(messages: Vec<Message>) -> Self {
        Self {
            messages,
            ..Self::default()
        }
    }

    /// The log, newest last.
    pub(crate) fn messages(&self) -> &[Message] {
        &self.messages
    }

    /// Logs a message.
    pub(crate) fn push(&mut self, text: String, warning: bool) {
        self.messages.push(Message { text, warning });
    }

    /// Records the solve of a finished job, if it ran one.
    pub(crate) fn solved(&mut self, output: &JobOutput) {
        if let Some(report) = output.outcome.as_ref().and_then(|o| o.report.as_ref()) {
            self.last_solve = Some(LastSolve {
                iterations: report.outer_iterations,
                violation: report.max_violation,
                seconds: output.elapsed.as_secs_f64(),
                how: format!("{:?}", report.termination),
            });
        }
    }

    /// The timer of the UI's frames.
    pub(crate) fn timer(&self) -> &FrameTimer {
        &self.timer
    }

    /// Records a frame that took `cpu` to build.
    pub(crate) fn tick(&mut self, cpu: Duration) {
        self.timer.tick(cpu);
    }

    /// The message log, newest first, with a button that clears it.
    pub(crate) fn messages_ui(&mut self, ui: &mut Ui) {
        if ui.small_button("Clear").clicked() {
            self.messages.clear();
        }
        for message in self.messages.iter().rev().take(30) {
            let text = RichText::new(&message.text).small();
            if message.warning {
                ui.colored_label(Color32::from_rgb(200, 90, 20), text);
            } else {
                ui.label(text);
            }
        }
    }

    /// The left of the status bar: the running job's progress, or the last solve.
    fn job_ui(&self, ui: &mut Ui, job: Option<&Job>) {
        if let Some(job) = job {
            let p = job.progress();
            ui.spinner();
            ui.label(format!(
                "{} — solving: iteration {}, |c| {:.1e}, {:.1} s   (Esc cancels)",
                job.label,
                p.iterations,
                p.violation,
                p.elapsed.as_secs_f64()
            ));
            if ui.button("Cancel").clicked() {
                job.cancel();
            }
        } else if let Some(LastSolve {
            iterations,
            violation,
            seconds,
            how,
        }) = &self.last_solve
        {
            ui.label(format!(
                "Last solve: {how}, {iterations} iterations, |c| {violation:.1e}, {:.0} ms",
                seconds * 1e3
            ));
        } else {
            ui.label("Ready");
        }
    }
}

/// The time spent building the UI in recent frames, for the status bar and the drag
/// benchmark.
#[derive(Debug, Default)]
pub(crate) struct FrameTimer {
    cpu: VecDeque<Duration>,
}

impl FrameTimer {
    fn tick(&mut self, cpu: Duration) {
        self.cpu.push_back(cpu);
        if self.cpu.len() > 240 {
            self.cpu.pop_front();
        }
    }

    /// Time spent building the UI in the newest frame.
    pub(crate) fn last_cpu(&self) -> Option<Duration> {
        self.cpu.back().copied()
    }

    /// The median time spent building the UI in recent frames, in milliseconds.
    fn median_cpu_ms(&self) -> Option<f64> {
        let mut frames: Vec<f64> = self.cpu.iter().map(|d| d.as_secs_f64() * 1e3).collect();
        frames.sort_by(f64::total_cmp);
        frames.get(frames.len() / 2).copied()
    }
}

impl GeosnapApp {
    pub(crate) fn status_bar(&mut self, ui: &mut Ui) {
        egui::Panel::bottom("status")
            .frame(super::unfilled(3.0))
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    self.status.job_ui(ui, self.workers.job());
                    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                        if let Some(median) = self.status.timer.median_cpu_ms() {
                            ui.label(RichText::new(format!("UI {median:.1} ms")).small().weak());
                        }
                        if let Some(drag) = &self.drag {
                            ui.label(
                                RichText::new(format!(
                                    "snap {:.0} ms",
                                    drag.preview_time().as_secs_f64() * 1e3
                                ))
                                .small()
                                .weak(),
                            );
                        }
                        let document = self.editor.document();
                        ui.label(format!(
                            "{} strokes · {} parts · {} relations",
                            self.editor.sketch().strokes.len(),
                            document.len(),
                            document.relations().len()
                        ));
                    });
                });
            });
    }
}
