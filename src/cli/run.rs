//! `geosnap run`: a placement script, headless, with its report.

use std::cell::Cell;
use std::io::IsTerminal;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use crate::clock::MonotonicClock;
use crate::core::model::{run_steps_with, SessionSettings, StepOutcome};
use crate::core::sketch::{preprocess_report, PreprocessOptions};
use crate::core::solve::{Iterate, SolveContext};
use crate::io::gltf::{ExportReport, ExportSettings};
use crate::io::model_file::model_bytes;
use crate::io::overlay::{overlay_png, OverlayItem, OverlayRelation};
use crate::io::script::{load_script, Script};
use crate::io::sketch_file::{load_sketch, LoadedSketch};
use anyhow::{bail, Context, Result};

use super::limit::Deadline;
use super::model::{gltf_bytes, print_gltf_report};
use super::outputs::{
    check_outputs, write_outputs, Output, GLTF_EXTENSIONS, MODEL_EXTENSIONS, PNG_EXTENSIONS,
};

/// The sketch path to write into a model file: relative to the model's folder when the
/// sketch lies in it, as resolved otherwise.
pub(super) fn sketch_reference(sketch: &Path, model: &Path) -> String {
    let folder = model.parent().unwrap_or(Path::new(""));
    sketch
        .strip_prefix(folder)
        .unwrap_or(sketch)
        .to_string_lossy()
        .into_owned()
}

/// What `geosnap run` is asked to do.
pub(super) struct RunArgs<'a> {
    pub(super) script: &'a Path,
    pub(super) out: &'a Path,
    pub(super) overlay: Option<&'a Path>,
    pub(super) gltf: Option<&'a Path>,
    pub(super) accept_suggestions: bool,
    pub(super) strict: bool,
    /// The command's `--time-limit`.
    pub(super) deadline: &'a Deadline,
}

/// Reads a script and its sketch for `geosnap run`, refusing before any work a bad
/// output, an invalid step or a sketch without strokes.
pub(super) fn prepare_run(args: &RunArgs<'_>) -> Result<(Script, LoadedSketch)> {
    let (script_path, out) = (args.script, args.out);
    let script = load_script(script_path).context("reading the script")?;
    let mut outputs = vec![Output {
        path: out,
        option: "--out",
        extensions: MODEL_EXTENSIONS,
    }];
    if let Some(path) = args.overlay {
        outputs.push(Output {
            path,
            option: "--overlay",
            extensions: PNG_EXTENSIONS,
        });
    }
    if let Some(path) = args.gltf {
        outputs.push(Output {
            path,
            option: "--gltf",
            extensions: GLTF_EXTENSIONS,
        });
    }
    let mut inputs = vec![script_path, script.sketch.as_path()];
    inputs.extend(script.image.as_deref());
    check_outputs(&outputs, &inputs)?;
    let invalid = script.invalid_steps();
    if !invalid.is_empty() {
        let lines: Vec<String> = invalid
            .iter()
            .take(MAX_LISTED_STEPS)
            .map(|(i, reason)| format!("  step {i}: {reason}"))
            .collect();
        let more = invalid.len().saturating_sub(MAX_LISTED_STEPS);
        bail!(
            "{}: {} invalid step(s); nothing was run or written:\n{}{}",
            script_path.display(),
            invalid.len(),
            lines.join("\n"),
            if more > 0 {
                format!("\n  … and {more} more")
            } else {
                String::new()
            }
        );
    }
    let loaded = load_sketch(&script.sketch)
        .with_context(|| format!("loading the sketch of {}", script_path.display()))?;
    for warning in &loaded.warnings {
        eprintln!("warning: {warning}");
    }
    if loaded.sketch.strokes.is_empty() {
        bail!(
            "the sketch {} has no strokes: there is nothing to snap to; nothing was run or \
             written",
            script.sketch.display()
        );
    }
    if script.steps.is_empty() {
        eprintln!("warning: the script has no steps: the model will be empty");
    }
    let merged = preprocess_report(&loaded.sketch, &PreprocessOptions::default())
        .merged
        .len();
    if let Some(message) = super::check::merged_message(merged) {
        eprintln!("note: {message} of {}", script.sketch.display());
    }
    Ok((script, loaded))
}

#[expect(clippy::print_stdout, reason = "CLI output")]
pub(super) fn run(args: &RunArgs<'_>) -> Result<ExitCode> {
    let (script, loaded) = prepare_run(args)?;
    let steps = &script.steps;
    let deadline = args.deadline;
    let clock = MonotonicClock::start();
    let settings = SessionSettings::default();
    let mut progress = Progress::new(steps.len(), std::io::stderr().is_terminal());
    let first_solve = FirstSolve::default();
    let mut observer = |iterate: &Iterate<'_>| first_solve.iterate(iterate);
    let (mut document, outcomes) = run_steps_with(
        &loaded.sketch,
        steps,
        &settings,
        SolveContext::default()
            .with_clock(&clock)
            .with_cancel(deadline.flag())
            .with_observer(&mut observer),
        &mut |index, outcome| {
            progress.step(index, outcome, first_solve.take(), deadline.expired());
        },
    );
    let done = progress.done.unwrap_or(outcomes.len());
    deadline.check(|| {
        format!(
            "after {done} of {} steps of {}",
            steps.len(),
            args.script.display()
        )
    })?;
    // The solve after accepting suggestions, counted in the summary with the steps'.
    let mut last_solves = 0;
    if args.accept_suggestions {
        let accepted = document.accept_suggestions();
        if !accepted.is_empty() {
            let outcome = document.solve(
                None,
                &settings.global,
                SolveContext::default()
                    .with_clock(&clock)
                    .with_cancel(deadline.flag()),
            );
            last_solves = outcome.solves;
            deadline.check(|| {
                format!(
                    "after all {} steps, in the solve with the accepted suggestions",
                    steps.len()
                )
            })?;
            println!(
                "accepted {} suggested relation(s); {}",
                accepted.len(),
                if outcome.conflicts.is_empty() {
                    "the model holds them".to_owned()
                } else {
                    format!("{} switched off as conflicts", outcome.conflicts.len())
                }
            );
            for c in &outcome.conflicts {
                println!("  {}", c.message);
            }
        }
    }
    let elapsed = crate::core::solve::Clock::elapsed(&clock);

    let gltf_report = write_run_outputs(args, &script, &loaded, &document)?;
    run_summary(
        args,
        &script,
        &loaded,
        (&document, &outcomes, last_solves),
        (elapsed, &progress.step_ms),
        gltf_report,
    )?;
    Ok(ExitCode::SUCCESS)
}

/// When the first global solve of a step ended, told by the solver's iterates (each
/// solve's first outer iteration is number 1): the rest of the step is spent on
/// conflicts and their re-solves.
#[derive(Default)]
pub(super) struct FirstSolve {
    /// Solves begun in this step.
    solves: Cell<usize>,
    /// The last iterate of the step's first solve.
    end: Cell<Option<Instant>>,
}

impl FirstSolve {
    fn iterate(&self, iterate: &Iterate<'_>) {
        if iterate.outer == 1 {
            self.solves.set(self.solves.get() + 1);
        }
        if self.solves.get() <= 1 {
            self.end.set(Some(Instant::now()));
        }
    }

    /// The end of this step's first solve, if it had any, and a fresh start for the next.
    fn take(&self) -> Option<Instant> {
        self.solves.set(0);
        self.end.take()
    }
}

/// Renders every output of a run, then writes them together (all or none); returns the
/// glTF export's report, if one was asked for.
pub(super) fn write_run_outputs(
    args: &RunArgs<'_>,
    script: &Script,
    loaded: &LoadedSketch,
    document: &crate::core::model::Document,
) -> Result<Option<ExportReport>> {
    let out = args.out;
    // Everything is rendered before anything is written, then written together.
    let mut files: Vec<(&Path, Vec<u8>)> = vec![(
        out,
        model_bytes(document, &sketch_reference(&script.sketch, out))
            .with_context(|| format!("encoding {}", out.display()))?,
    )];
    if let Some(png) = args.overlay {
        let items: Vec<OverlayItem<'_>> = document
            .primitives()
            .map(|(_, placed)| OverlayItem {
                primitive: &placed.primitive,
                strokes: &placed.fit.strokes,
            })
            .collect();
        let relations = OverlayRelation::of_document(document);
        let bytes = overlay_png(&loaded.sketch, &items, &relations)
            .with_context(|| format!("drawing the overlay {}", png.display()))?;
        files.push((png, bytes));
    }
    let gltf_report = match args.gltf {
        Some(path) => {
            let (bytes, report) = gltf_bytes(document, path, &ExportSettings::default())?;
            files.push((path, bytes));
            Some(report)
        }
        None => None,
    };
    args.deadline.check(|| {
        format!(
            "after all {} steps, before writing the outputs",
            script.steps.len()
        )
    })?;
    write_outputs(&files)?;
    Ok(gltf_report)
}

/// Prints a run's summary after its outputs are written: a line per step, the counts
/// and the solve times, and a warning for skipped steps (an error with `--strict`).
#[expect(clippy::print_stdout, reason = "CLI output")]
pub(super) fn run_summary(
    args: &RunArgs<'_>,
    script: &Script,
    loaded: &LoadedSketch,
    (document, outcomes, last_solves): (&crate::core::model::Document, &[StepOutcome], usize),
    (elapsed, step_ms): (std::time::Duration, &[f64]),
    gltf_report: Option<ExportReport>,
) -> Result<()> {
    let (script_path, out, steps) = (args.script, args.out, &script.steps);
    println!(
        "{}: {} strokes, {} steps",
        script_path.display(),
        loaded.sketch.strokes.len(),
        steps.len()
    );
    let (mut solve_ms, conflicts) = print_steps(outcomes);
    let kinds = relation_counts(document);
    println!(
        "{} primitives, {} skipped; {} relations{}{}",
        document.len(),
        document.skipped.len(),
        document.relations().len(),
        if kinds.is_empty() {
            String::new()
        } else {
            format!(": {}", kinds.join(", "))
        },
        if conflicts.is_empty() {
            String::new()
        } else {
            format!("; {} conflict(s) resolved", conflicts.len())
        }
    );
    solve_ms.sort_by(f64::total_cmp);
    let (solves, resolves) = solve_counts(outcomes);
    let (solves, resolves) = (
        solves + last_solves,
        resolves + last_solves.saturating_sub(1),
    );
    let slowest = step_ms
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, ms)| format!("; slowest step {i}: {ms:.1} ms with its re-solves"))
        .unwrap_or_default();
    println!(
        "{solves} global solve(s) ({resolves} re-solve(s) after conflicts); last solve per \
         step median {:.1} ms, max {:.1} ms{slowest}; {:.1} ms in all; wrote {}",
        solve_ms.get(solve_ms.len() / 2).copied().unwrap_or(0.0),
        solve_ms.last().copied().unwrap_or(0.0),
        elapsed.as_secs_f64() * 1e3,
        out.display()
    );
    if let Some(png) = args.overlay {
        println!("overlay: {}", png.display());
    }
    if let (Some(path), Some(report)) = (args.gltf, gltf_report) {
        print_gltf_report(&report, path, &ExportSettings::default());
    }
    let skipped = outcomes
        .iter()
        .filter(|o| !matches!(o, StepOutcome::Placed { .. }))
        .count();
    if skipped > 0 {
        eprintln!(
            "warning: {skipped} of {} step(s) were skipped or refused (listed above){}",
            steps.len(),
            if document.is_empty() {
                "; no step placed a primitive: the model written is empty"
            } else {
                ""
            }
        );
        if args.strict {
            bail!("--strict: {skipped} step(s) were skipped or refused (the outputs were written)");
        }
    }
    Ok(())
}

/// Every global solve of a run's steps, and how many of them were re-solves after a
/// conflict was switched off.
pub(super) fn solve_counts(outcomes: &[StepOutcome]) -> (usize, usize) {
    outcomes
        .iter()
        .filter_map(|o| match o {
            StepOutcome::Placed { solve, .. } => Some(solve.solves),
            _ => None,
        })
        .fold((0, 0), |(all, again), n| {
            (all + n, again + n.saturating_sub(1))
        })
}

/// Per-step progress of `geosnap run`: each step's wall time, and a line per step on
/// stderr when it is a terminal (a long script is never silent), with the time spent on
/// conflicts and their re-solves.
pub(super) struct Progress {
    total: usize,
    show: bool,
    last: Instant,
    /// Each step's wall time (snap, inference and every solve), in ms.
    step_ms: Vec<f64>,
    /// The steps wholly done when the time limit was found spent.
    done: Option<usize>,
}

impl Progress {
    fn new(total: usize, show: bool) -> Self {
        if show && total > 0 {
            eprintln!("running {total} step(s)…");
        }
        Self {
            total,
            show,
            last: Instant::now(),
            step_ms: Vec::with_capacity(total),
            done: None,
        }
    }

    /// Records step `index`, ended now; `first_solve_end` is when its first global solve
    /// ended; `expired`, whether the time limit is spent (the step may have been cut
    /// short, and no more steps run).
    fn step(
        &mut self,
        index: usize,
        outcome: &StepOutcome,
        first_solve_end: Option<Instant>,
        expired: bool,
    ) {
        let now = Instant::now();
        let ms = now.duration_since(self.last).as_secs_f64() * 1e3;
        self.last = now;
        self.step_ms.push(ms);
        if expired && self.done.is_none() {
            self.done = Some(index);
        }
        if !self.show {
            return;
        }
        let what = match outcome {
            StepOutcome::Placed {
                id, snap, solve, ..
            } => {
                let again = solve.solves.saturating_sub(1);
                let conflicts_ms = first_solve_end
                    .filter(|_| again > 0)
                    .map_or(0.0, |end| now.duration_since(end).as_secs_f64() * 1e3);
                format!(
                    "{} #{} placed{}",
                    snap.primitive.kind().name(),
                    id.0,
                    if again > 0 {
                        format!(
                            ", {again} re-solve(s) after {} conflict(s) ({conflicts_ms:.0} ms)",
                            solve.conflicts.len()
                        )
                    } else {
                        String::new()
                    }
                )
            }
            StepOutcome::Skipped(_) => "skipped".to_owned(),
            StepOutcome::Refused { .. } => "refused".to_owned(),
        };
        eprintln!(
            "[{}/{}] step {index}: {what} in {ms:.0} ms",
            index + 1,
            self.total
        );
    }
}

/// The most invalid steps a refused script lists.
pub(super) const MAX_LISTED_STEPS: usize = 20;

/// Prints one line per step (and its solve); returns the solve times (ms) and the
/// conflict messages.
#[expect(clippy::print_stdout, reason = "CLI output")]
pub(super) fn print_steps(outcomes: &[StepOutcome]) -> (Vec<f64>, Vec<String>) {
    let mut solve_ms = Vec::new();
    let mut conflicts = Vec::new();
    for (index, outcome) in outcomes.iter().enumerate() {
        match outcome {
            StepOutcome::Placed {
                id,
                snap,
                confidence,
                relations,
                duplicate_of,
                solve,
            } => {
                println!(
                    "  step {index}: {} #{} snapped to {} strokes, rms {:.2} ({:.1} % of its size), {} evaluations, {}; {} (confidence {:.2})",
                    snap.primitive.kind().name(),
                    id.0,
                    snap.assignment.stroke_ids().len(),
                    snap.rms,
                    100.0 * snap.rms / snap.primitive.size(),
                    snap.evaluations,
                    snap.termination,
                    confidence.verdict,
                    confidence.value,
                );
                if let Some(reason) = &confidence.reason {
                    println!("    {}: {reason}", confidence.verdict);
                    for (k, alt) in snap.alternatives.iter().enumerate() {
                        println!(
                            "    alternative {}: {} strokes, rms {:.1} % of its size, {:.0} % of the size away",
                            k + 1,
                            alt.assignment.stroke_ids().len(),
                            100.0 * alt.rms / alt.primitive.size(),
                            100.0 * alt.distance
                        );
                    }
                }
                if let Some(first) = duplicate_of {
                    println!(
                        "    a copy of part #{} (same kind, size and place): no relations inferred for it",
                        first.0
                    );
                }
                if let Some(report) = &solve.report {
                    let ms = report.elapsed.as_secs_f64() * 1e3;
                    solve_ms.push(ms);
                    println!(
                        "    {} new relation(s); global solve of {} part(s), {} relation(s): {}, ‖ψ‖∞ {:.1e}, {} evaluations, {ms:.1} ms",
                        relations.len(),
                        solve.solved.len(),
                        solve.relations,
                        report.termination,
                        report.max_violation,
                        report.evaluations,
                    );
                }
                for c in &solve.conflicts {
                    println!("    conflict: {}", c.message);
                    conflicts.push(c.message.clone());
                }
                if solve.reverted {
                    println!("    the solve was refused: the parts keep their previous pose");
                }
            }
            StepOutcome::Skipped(s) => println!("  step {index}: skipped: {}", s.reason),
            StepOutcome::Refused {
                snap, confidence, ..
            } => {
                println!(
                    "  step {index}: {} refused (confidence {:.2}): {}",
                    snap.primitive.kind().name(),
                    confidence.value,
                    confidence.reason.as_deref().unwrap_or("no evidence for it")
                );
            }
        }
    }
    (solve_ms, conflicts)
}

/// The relations by kind, in words: `2 coaxial, 1 concentric (+1 suggested, +1 off)`.
pub(super) fn relation_counts(document: &crate::core::model::Document) -> Vec<String> {
    use crate::core::relation::Mode;
    let mut by_kind: std::collections::BTreeMap<&str, (usize, usize, usize)> =
        std::collections::BTreeMap::new();
    for r in document.relations() {
        let entry = by_kind.entry(r.kind.name()).or_default();
        match r.mode {
            Mode::Off => entry.2 += 1,
            Mode::Suggested => entry.1 += 1,
            Mode::Hard | Mode::Soft => entry.0 += 1,
        }
    }
    by_kind
        .iter()
        .map(|(kind, (on, suggested, off))| {
            let mut extra = Vec::new();
            if *suggested > 0 {
                extra.push(format!("+{suggested} suggested"));
            }
            if *off > 0 {
                extra.push(format!("+{off} off"));
            }
            if extra.is_empty() {
                format!("{on} {kind}")
            } else {
                format!("{on} {kind} ({})", extra.join(", "))
            }
        })
        .collect()
}
