//! What the app tells the user: the message log, the status bar naming the action in
//! progress (a drag, its snapping, a solve) or the last solve in words, and the
//! developer figures (iterations, residuals, frame and snap times) shown only with
//! View → Developer info.

use std::collections::VecDeque;
use std::time::Duration;

use egui::{Color32, RichText, Ui};

use super::worker::{Job, JobOutput};
use super::{words, GeosnapApp};
use crate::core::solve::Termination;

/// The storage key of [`Status::developer`].
pub(crate) const DEVELOPER_KEY: &str = "developer_info";

/// A message in the log.
#[derive(Clone, Debug)]
pub struct Message {
    /// The text.
    pub text: String,
    /// Whether it reports a problem.
    pub warning: bool,
    /// Developer figures behind it (a residual, an RMS), shown only with View →
    /// Developer info.
    pub detail: Option<String>,
}

/// The last solve, for the status bar.
#[derive(Clone, Debug)]
struct LastSolve {
    iterations: usize,
    /// ‖c‖∞ at the end.
    violation: f64,
    seconds: f64,
    /// How it ended.
    how: Termination,
}

/// The message log, the last solve and the frame times.
#[derive(Debug, Default)]
pub(crate) struct Status {
    /// Newest last.
    messages: Vec<Message>,
    last_solve: Option<LastSolve>,
    timer: FrameTimer,
    /// Whether developer figures are shown (View → Developer info).
    pub(crate) developer: bool,
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
        self.push_detailed(text, None, warning);
    }

    /// Logs a message with developer figures behind it.
    pub(crate) fn push_detailed(&mut self, text: String, detail: Option<String>, warning: bool) {
        self.messages.push(Message {
            text,
            warning,
            detail,
        });
    }

    /// Records the solve of a finished job, if it ran one.
    pub(crate) fn solved(&mut self, output: &JobOutput) {
        if let Some(report) = output.outcome.as_ref().and_then(|o| o.report.as_ref()) {
            self.last_solve = Some(LastSolve {
                iterations: report.outer_iterations,
                violation: report.max_violation,
                seconds: output.elapsed.as_secs_f64(),
                how: report.termination,
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

    /// Empties the log.
    pub(crate) fn clear(&mut self) {
        self.messages.clear();
    }

    /// The message log, newest first; problems in their colour.
    pub(crate) fn messages_ui(&self, ui: &mut Ui) {
        for message in self.messages.iter().rev().take(30) {
            let text = match (&message.detail, self.developer) {
                (Some(detail), true) => format!("{} ({detail})", message.text),
                _ => message.text.clone(),
            };
            if message.warning {
                ui.colored_label(Color32::from_rgb(190, 70, 10), text);
            } else {
                ui.label(text);
            }
        }
    }

    /// The left of the status bar: the running job, or the last solve, in words
    /// (with the figures when developer info is on).
    fn job_ui(&self, ui: &mut Ui, job: Option<&Job>) {
        if let Some(job) = job {
            let p = job.progress();
            ui.spinner();
            let what = if job.label.starts_with("Place") || job.label.starts_with("Move") {
                "snapping and solving…"
            } else {
                "solving…"
            };
            ui.label(format!("{} — {what} (Esc cancels)", job.label));
            if self.developer {
                ui.label(
                    RichText::new(format!(
                        "round {}, |c| {:.1e}, {:.1} s",
                        p.iterations,
                        p.violation,
                        p.elapsed.as_secs_f64()
                    ))
                    .small()
                    .weak(),
                );
            }
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
                "Ready. The last solve {} ({:.1} s).",
                words::termination(*how),
                seconds
            ));
            if self.developer {
                ui.label(
                    RichText::new(format!("{how:?}, {iterations} rounds, |c| {violation:.1e}"))
                        .small()
                        .weak(),
                );
            }
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
    /// What the user is doing now, for the status bar: a drag and its snapping; `None`
    /// when no drag is on (the running job or the last solve is shown then).
    pub fn action_text(&self) -> Option<String> {
        let drag = self.drag.as_ref()?;
        let noun = words::kind_noun(drag.kind());
        let what = match drag.replacing {
            Some(id) => format!("Moving {}", words::part_name(self.editor.document(), id)),
            None => format!("Dragging a {noun}"),
        };
        if !drag.over_canvas {
            return Some(format!("{what} — move it over the drawing"));
        }
        let state = if drag.generation() != drag.preview_generation() {
            "Snapping…".to_owned()
        } else if let Some(preview) = drag.preview() {
            format!(
                "snapped to {} strokes",
                preview.assignment.stroke_ids().len()
            )
        } else if let Some(error) = drag.preview_error() {
            format!("no snap here: {}", words::snap_error(error, false))
        } else {
            "Snapping…".to_owned()
        };
        Some(format!("{what} — release to place · {state}"))
    }

    pub(crate) fn status_bar(&mut self, ui: &mut Ui) {
        let action = self.action_text();
        let loading = self.loading();
        let mut cancel_loading = false;
        egui::Panel::bottom("status")
            .frame(super::unfilled(3.0))
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    match (&loading, &action) {
                        (Some(loading), _) => {
                            ui.spinner();
                            ui.label(format!("{loading} (Esc cancels)"));
                            cancel_loading = ui.button("Cancel").clicked();
                        }
                        (None, Some(action)) => {
                            ui.label(action);
                        }
                        (None, None) => self.status.job_ui(ui, self.workers.job()),
                    }
                    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                        if self.status.developer {
                            if let Some(median) = self.status.timer.median_cpu_ms() {
                                ui.label(
                                    RichText::new(format!("UI {median:.1} ms")).small().weak(),
                                );
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
                        }
                        let document = self.editor.document();
                        let count = |n: usize, one: &str, many: &str| {
                            format!("{n} {}", if n == 1 { one } else { many })
                        };
                        ui.label(format!(
                            "{} · {} · {}",
                            count(self.editor.sketch().strokes.len(), "stroke", "strokes"),
                            count(document.len(), "part", "parts"),
                            count(document.relations().len(), "relation", "relations")
                        ));
                    });
                });
            });
        if cancel_loading {
            self.cancel_loading();
        }
    }
}
