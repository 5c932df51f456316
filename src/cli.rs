//! The command line: `geosnap [COMMAND]`.
//!
//! - `geosnap run SCRIPT --out MODEL [--overlay PNG] [--gltf FILE] [--strict]`: a
//!   placement script, headless. Outputs are checked before any work and written
//!   together or not at all.
//! - `geosnap export MODEL --out FILE.glb|FILE.gltf [--scale M] [--segments N]`: glTF 2.0.
//! - `geosnap check FILE…`: loads sketches, scripts or models and reports problems.
//! - `geosnap solve MODEL --out MODEL`: re-solves a model with its relations.
//! - `geosnap selftest`: the solver on the Hock–Schittkowski problems.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use geosnap::clock::MonotonicClock;
use geosnap::core::model::{
    run_steps_with, Companions, GlobalSettings, SessionSettings, StepOutcome,
};
use geosnap::core::sketch::{
    classify_sketch, preprocess, ClassifyOptions, PreprocessOptions, StrokeClass, StrokeId,
};
use geosnap::core::solve::{
    hock_schittkowski, AugLagSettings, InnerSolver, SolveContext, Solver, Start,
};
use geosnap::io::gltf::{
    encode_gltf, ExportReport, ExportSettings, GltfFormat, Origin, DEFAULT_METRES_PER_UNIT,
    DEFAULT_SEGMENTS,
};
use geosnap::io::input::read_input;
use geosnap::io::model_file::{load_model, model_bytes, parse_model};
use geosnap::io::overlay::{classes_png, overlay_png, OverlayItem, OverlayRelation};
use geosnap::io::script::{load_script, parse_script, Script};
use geosnap::io::sketch_file::{load_sketch, LoadedSketch};
use glam::DVec2;

/// Sketch-based 3D modelling with geosemantic snapping.
#[derive(Debug, Parser)]
#[command(
    name = "geosnap",
    version,
    about,
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Without a command: open the desktop application on this file (a session, a
    /// sketch, an SVG drawing or a PNG/JPEG reference image), or on the built-in sample.
    file: Option<PathBuf>,
    /// Measure frame times during a simulated palette drag over this many frames, write
    /// them as JSON to `--frame-times` and quit.
    #[arg(long, value_name = "FRAMES", requires = "frame_times")]
    drag_benchmark: Option<usize>,
    /// Where `--drag-benchmark` writes its figures.
    #[arg(long, value_name = "JSON")]
    frame_times: Option<PathBuf>,
    /// Save a screenshot of the window (PNG) once the work has settled, and quit.
    #[arg(long, value_name = "PNG")]
    screenshot: Option<PathBuf>,
    /// Before showing the window, play this placement script's drops as drags (for
    /// screenshots and demos); its sketch is opened.
    #[arg(long, value_name = "SCRIPT")]
    play: Option<PathBuf>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run a placement script headless and write the model (and an overlay PNG).
    ///
    /// Every output is checked before any work (a supported extension, a writable
    /// folder, not an input) and all are written together or none. The script is refused
    /// before any work when a step is invalid (an unknown field, say) or its sketch has
    /// no strokes; exit status 1 then, and on any error. A step that cannot be snapped is
    /// skipped with a warning; with `--strict` that also exits 1, after writing.
    Run {
        /// The script (`*.script.json`).
        script: PathBuf,
        /// The model file to write (`*.model.json`).
        #[arg(long)]
        out: PathBuf,
        /// An overlay PNG to write: strokes, fitted primitives and their strokes.
        #[arg(long)]
        overlay: Option<PathBuf>,
        /// Also export the model as glTF 2.0 (`.glb` or `.gltf`), with the defaults of
        /// `geosnap export`.
        #[arg(long)]
        gltf: Option<PathBuf>,
        /// Accept every suggested relation (inferred with medium confidence) at the end:
        /// make them hard and solve the model once more.
        #[arg(long)]
        accept_suggestions: bool,
        /// Exit non-zero (after writing the outputs) when any step is skipped or refused,
        /// not only when a step is invalid.
        #[arg(long)]
        strict: bool,
    },
    /// Export a model file as glTF 2.0: metres, +Y up, one node per primitive.
    Export {
        /// The model (`*.model.json`).
        model: PathBuf,
        /// The file to write: `.glb` (binary) or `.gltf` (JSON, buffer embedded).
        #[arg(long)]
        out: PathBuf,
        /// Metres per model unit (one sketch unit); the default makes a unit a millimetre.
        #[arg(long, default_value_t = DEFAULT_METRES_PER_UNIT, allow_negative_numbers = true)]
        scale: f64,
        /// Segments around each circle.
        #[arg(long, default_value_t = DEFAULT_SEGMENTS)]
        segments: usize,
    },
    /// Write the built-in sample sketch and its script into a folder.
    Sample {
        /// The folder (created if missing).
        dir: PathBuf,
    },
    /// Load sketches, scripts or models and report problems.
    Check {
        /// The files.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// For a sketch: list every stroke (as the snapper sees it, after preprocessing)
        /// with its bounds, class and the test that decided it.
        #[arg(long)]
        strokes: bool,
        /// For a single sketch: write a PNG with its strokes coloured by class (features
        /// blue, silhouettes black).
        #[arg(long)]
        overlay: Option<PathBuf>,
    },
    /// Re-solve a model file with its relations (as edited by hand, say): relations that
    /// conflict are switched off with a message; the parts keep the places their fits
    /// gave them, as the model file has no strokes.
    Solve {
        /// The model file (`*.model.json`).
        model: PathBuf,
        /// Where to write the solved model.
        #[arg(long)]
        out: PathBuf,
    },
    /// Solve the built-in Hock–Schittkowski test problems and report each result.
    Selftest {
        /// Print the reports as JSON lines instead of a table.
        #[arg(long)]
        json: bool,
        /// Use argmin's L-BFGS instead of our bounded one for the inner solves.
        #[arg(long)]
        argmin: bool,
    },
}

/// Runs the command line and turns errors into a message and exit code 1.
pub(crate) fn main() -> ExitCode {
    let cli = Cli::parse();
    let app = AppArgs {
        file: cli.file,
        drag_benchmark: cli.drag_benchmark.zip(cli.frame_times),
        screenshot: cli.screenshot,
        play: cli.play,
    };
    let result = match cli.command {
        Some(Command::Selftest { json, argmin }) => selftest(json, argmin),
        Some(Command::Run {
            script,
            out,
            overlay,
            gltf,
            accept_suggestions,
            strict,
        }) => run(&RunArgs {
            script: &script,
            out: &out,
            overlay: overlay.as_deref(),
            gltf: gltf.as_deref(),
            accept_suggestions,
            strict,
        }),
        Some(Command::Export {
            model,
            out,
            scale,
            segments,
        }) => export(&model, &out, scale, segments),
        Some(Command::Check {
            files,
            strokes,
            overlay,
        }) => check(&files, strokes, overlay.as_deref()),
        Some(Command::Sample { dir }) => sample(&dir),
        Some(Command::Solve { model, out }) => solve_model(&model, &out),
        None => open_app(app),
    };
    match result {
        Ok(code) => code,
        Err(error) => {
            eprintln!("geosnap: {error:#}");
            ExitCode::FAILURE
        }
    }
}

/// What the desktop application is asked to do.
struct AppArgs {
    file: Option<PathBuf>,
    drag_benchmark: Option<(usize, PathBuf)>,
    screenshot: Option<PathBuf>,
    play: Option<PathBuf>,
}

#[cfg(feature = "gui")]
fn open_app(args: AppArgs) -> Result<ExitCode> {
    geosnap::app::run(geosnap::app::AppOptions {
        file: args.file,
        autosave_dir: None,
        drag_benchmark: args.drag_benchmark,
        screenshot: args.screenshot,
        play: args.play,
    })?;
    Ok(ExitCode::SUCCESS)
}

#[cfg(not(feature = "gui"))]
fn open_app(args: AppArgs) -> Result<ExitCode> {
    let _ = (args.file, args.drag_benchmark, args.screenshot, args.play);
    bail!(
        "this build has no desktop application (built without the `gui` feature); \
         try `geosnap run sketches/vase.script.json --out vase.model.json --overlay vase.png`, \
         `geosnap selftest`, or `geosnap --help`"
    )
}

#[expect(clippy::print_stdout, reason = "CLI output")]
fn selftest(json: bool, argmin: bool) -> Result<ExitCode> {
    let inner = if argmin {
        InnerSolver::Argmin
    } else {
        InnerSolver::Bounded
    };
    let settings = AugLagSettings::default().with_inner_solver(inner);
    if !json {
        println!(
            "{:<6} {:>16} {:>16} {:>9} {:>9} {:>6} {:>6} {:>10}  stop",
            "name", "f", "f*", "|f-f*|", "|c|inf", "outer", "inner", "time"
        );
    }
    let mut failures = 0;
    for test in hock_schittkowski::all() {
        let clock = MonotonicClock::start();
        let mut problem = test.compile();
        let report = Solver::new(&settings)
            .clock(&clock)
            .solve(&mut problem, &Start::cold(test.start))
            .with_context(|| format!("solving {}", test.name))?;
        let error = (report.objective - test.optimum).abs() / test.optimum.abs().max(1.0);
        let ok = report.termination.is_converged() && error <= 1e-6 && report.max_violation <= 1e-8;
        failures += usize::from(!ok);
        if json {
            println!(
                "{}",
                serde_json::json!({ "name": test.name, "optimum": test.optimum, "ok": ok, "report": report })
            );
        } else {
            println!(
                "{:<6} {:>16.9} {:>16.9} {:>9.1e} {:>9.1e} {:>6} {:>6} {:>8.3}ms  {}",
                test.name,
                report.objective,
                test.optimum,
                error,
                report.max_violation,
                report.outer_iterations,
                report.inner_iterations,
                report.elapsed.as_secs_f64() * 1e3,
                report.termination
            );
        }
    }
    if failures > 0 {
        anyhow::bail!("{failures} problem(s) did not reach f* within 1e-6 and |c| within 1e-8");
    }
    Ok(ExitCode::SUCCESS)
}

/// The sketch path to write into a model file: relative to the model's folder when the
/// sketch lies in it, as resolved otherwise.
fn sketch_reference(sketch: &Path, model: &Path) -> String {
    let folder = model.parent().unwrap_or(Path::new(""));
    sketch
        .strip_prefix(folder)
        .unwrap_or(sketch)
        .to_string_lossy()
        .into_owned()
}

/// What `geosnap run` is asked to do.
struct RunArgs<'a> {
    script: &'a Path,
    out: &'a Path,
    overlay: Option<&'a Path>,
    gltf: Option<&'a Path>,
    accept_suggestions: bool,
    strict: bool,
}

/// The extensions a model file output takes.
const MODEL_EXTENSIONS: &[&str] = &["json"];
/// The extensions a glTF output takes.
const GLTF_EXTENSIONS: &[&str] = &["glb", "gltf"];
/// The extensions an overlay output takes.
const PNG_EXTENSIONS: &[&str] = &["png"];

/// An output file of a command: its path, the option that names it, and the
/// extensions it takes.
struct Output<'a> {
    path: &'a Path,
    option: &'static str,
    extensions: &'static [&'static str],
}

/// Checks every output of a command before any work: a supported extension, a folder
/// that exists and takes files, not the same file as an input, not the same as another
/// output.
fn check_outputs(outputs: &[Output<'_>], inputs: &[&Path]) -> Result<()> {
    for (index, output) in outputs.iter().enumerate() {
        let (option, path) = (output.option, output.path.display());
        let extension = output
            .path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        if !extension
            .as_deref()
            .is_some_and(|e| output.extensions.contains(&e))
        {
            let takes: Vec<String> = output.extensions.iter().map(|e| format!(".{e}")).collect();
            bail!(
                "{option} {path}: unsupported extension; {option} takes a {} file",
                takes.join(" or ")
            );
        }
        if let Some(input) = inputs.iter().find(|i| same_file(output.path, i)) {
            bail!(
                "{option} {path} is an input of this command ({}): refusing to overwrite it; \
                 name another file",
                input.display()
            );
        }
        if let Some(other) = outputs
            .get(..index)
            .unwrap_or_default()
            .iter()
            .find(|o| same_target(o.path, output.path))
        {
            bail!(
                "{option} and {} both name {path}: give each output its own file",
                other.option
            );
        }
        geosnap::io::check_target(output.path)
            .with_context(|| format!("{option} {path}: cannot write there"))?;
    }
    Ok(())
}

/// Whether two existing paths are the same file (through links and `..` too).
fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!(
            (std::fs::canonicalize(a), std::fs::canonicalize(b)),
            (Ok(x), Ok(y)) if x == y
        )
    }
}

/// Whether two output paths (which may not exist yet) name the same file.
fn same_target(a: &Path, b: &Path) -> bool {
    let resolved = |p: &Path| {
        let folder = match p.parent() {
            Some(f) if !f.as_os_str().is_empty() => f,
            _ => Path::new("."),
        };
        std::fs::canonicalize(folder)
            .ok()
            .zip(p.file_name())
            .map(|(folder, name)| folder.join(name))
    };
    same_file(a, b) || matches!((resolved(a), resolved(b)), (Some(x), Some(y)) if x == y)
}

/// Reads a script and its sketch for `geosnap run`, refusing before any work a bad
/// output, an invalid step or a sketch without strokes.
fn prepare_run(args: &RunArgs<'_>) -> Result<(Script, LoadedSketch)> {
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
    Ok((script, loaded))
}

#[expect(clippy::print_stdout, reason = "CLI output")]
fn run(args: &RunArgs<'_>) -> Result<ExitCode> {
    let (script, loaded) = prepare_run(args)?;
    let steps = &script.steps;
    let clock = MonotonicClock::start();
    let settings = SessionSettings::default();
    let mut progress = Progress::new(steps.len(), std::io::stderr().is_terminal());
    let (mut document, outcomes) = run_steps_with(
        &loaded.sketch,
        steps,
        &settings,
        SolveContext::default().with_clock(&clock),
        &mut |index, outcome| progress.step(index, outcome),
    );
    if args.accept_suggestions {
        let accepted = document.accept_suggestions();
        if !accepted.is_empty() {
            let outcome = document.solve(
                None,
                &settings.global,
                SolveContext::default().with_clock(&clock),
            );
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
    let elapsed = geosnap::core::solve::Clock::elapsed(&clock);

    let gltf_report = write_run_outputs(args, &script, &loaded, &document)?;
    run_summary(
        args,
        &script,
        &loaded,
        (&document, &outcomes),
        (elapsed, &progress.step_ms),
        gltf_report,
    )?;
    Ok(ExitCode::SUCCESS)
}

/// Renders every output of a run, then writes them together (all or none); returns the
/// glTF export's report, if one was asked for.
fn write_run_outputs(
    args: &RunArgs<'_>,
    script: &Script,
    loaded: &LoadedSketch,
    document: &geosnap::core::model::Document,
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
    write_outputs(&files)?;
    Ok(gltf_report)
}

/// Prints a run's summary after its outputs are written: a line per step, the counts
/// and the solve times, and a warning for skipped steps (an error with `--strict`).
#[expect(clippy::print_stdout, reason = "CLI output")]
fn run_summary(
    args: &RunArgs<'_>,
    script: &Script,
    loaded: &LoadedSketch,
    (document, outcomes): (&geosnap::core::model::Document, &[StepOutcome]),
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
fn solve_counts(outcomes: &[StepOutcome]) -> (usize, usize) {
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
/// stderr when it is a terminal (a long script is never silent).
struct Progress {
    total: usize,
    show: bool,
    last: std::time::Instant,
    /// Each step's wall time (snap, inference and every solve), in ms.
    step_ms: Vec<f64>,
}

impl Progress {
    fn new(total: usize, show: bool) -> Self {
        if show && total > 0 {
            eprintln!("running {total} step(s)…");
        }
        Self {
            total,
            show,
            last: std::time::Instant::now(),
            step_ms: Vec::with_capacity(total),
        }
    }

    fn step(&mut self, index: usize, outcome: &StepOutcome) {
        let now = std::time::Instant::now();
        let ms = now.duration_since(self.last).as_secs_f64() * 1e3;
        self.last = now;
        self.step_ms.push(ms);
        if !self.show {
            return;
        }
        let what = match outcome {
            StepOutcome::Placed {
                id, snap, solve, ..
            } => {
                let again = solve.solves.saturating_sub(1);
                format!(
                    "{} #{} placed{}",
                    snap.primitive.kind().name(),
                    id.0,
                    if again > 0 {
                        format!(", {again} re-solve(s) after conflicts")
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
const MAX_LISTED_STEPS: usize = 20;

/// Writes the outputs of one command together: all of them, or none.
fn write_outputs(files: &[(&Path, Vec<u8>)]) -> Result<()> {
    let borrowed: Vec<(&Path, &[u8])> = files.iter().map(|(p, b)| (*p, b.as_slice())).collect();
    let written = geosnap::io::write_all_atomic(&borrowed);
    written.map_err(|error| {
        let none = if files.len() > 1 {
            "; no output was written"
        } else {
            "; the old file, if any, is untouched"
        };
        anyhow::Error::new(error).context(format!("writing the outputs{none}"))
    })
}

/// Prints one line per step (and its solve); returns the solve times (ms) and the
/// conflict messages.
#[expect(clippy::print_stdout, reason = "CLI output")]
fn print_steps(outcomes: &[StepOutcome]) -> (Vec<f64>, Vec<String>) {
    let mut solve_ms = Vec::new();
    let mut conflicts = Vec::new();
    for (index, outcome) in outcomes.iter().enumerate() {
        match outcome {
            StepOutcome::Placed {
                id,
                snap,
                confidence,
                relations,
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
fn relation_counts(document: &geosnap::core::model::Document) -> Vec<String> {
    use geosnap::core::relation::Mode;
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

#[expect(clippy::print_stdout, reason = "CLI output")]
fn solve_model(path: &Path, out: &Path) -> Result<ExitCode> {
    check_outputs(
        &[Output {
            path: out,
            option: "--out",
            extensions: MODEL_EXTENSIONS,
        }],
        &[path],
    )?;
    let mut loaded = load_model(path).context("reading the model")?;
    let clock = MonotonicClock::start();
    let outcome = loaded.document.solve(
        None,
        &GlobalSettings::default(),
        Companions {
            clock: Some(&clock),
            ..Companions::default()
        },
    );
    for conflict in &outcome.conflicts {
        println!("conflict: {}", conflict.message);
    }
    if outcome.reverted {
        println!("the solve was refused: the model is written as it was");
    }
    if let Some(report) = &outcome.report {
        println!(
            "solved {} part(s) with {} relation(s): {}, ‖ψ‖∞ {:.1e}, {} evaluations, {:.1} ms",
            outcome.solved.len(),
            outcome.relations,
            report.termination,
            report.max_violation,
            report.evaluations,
            report.elapsed.as_secs_f64() * 1e3
        );
    }
    let bytes = model_bytes(&loaded.document, &loaded.sketch)
        .with_context(|| format!("encoding {}", out.display()))?;
    write_outputs(&[(out, bytes)])?;
    println!("wrote {}", out.display());
    Ok(ExitCode::SUCCESS)
}

fn export(model: &Path, out: &Path, scale: f64, segments: usize) -> Result<ExitCode> {
    check_outputs(
        &[Output {
            path: out,
            option: "--out",
            extensions: GLTF_EXTENSIONS,
        }],
        &[model],
    )?;
    let settings = ExportSettings::new(scale, segments, Origin::default())?;
    let loaded = load_model(model).context("reading the model")?;
    let (bytes, report) = gltf_bytes(&loaded.document, out, &settings)?;
    write_outputs(&[(out, bytes)])?;
    print_gltf_report(&report, out, &settings);
    Ok(ExitCode::SUCCESS)
}

/// Encodes a document as glTF for `path` (binary or JSON by its extension).
fn gltf_bytes(
    document: &geosnap::core::model::Document,
    path: &Path,
    settings: &ExportSettings,
) -> Result<(Vec<u8>, ExportReport)> {
    let format = GltfFormat::from_path(path).with_context(|| {
        format!(
            "{}: unsupported extension; glTF is .glb or .gltf",
            path.display()
        )
    })?;
    encode_gltf(document, format, settings)
        .with_context(|| format!("exporting glTF {}", path.display()))
}

/// Reports what a glTF export wrote.
#[expect(clippy::print_stdout, reason = "CLI output")]
fn print_gltf_report(report: &ExportReport, path: &Path, settings: &ExportSettings) {
    for warning in &report.warnings {
        eprintln!("warning: {warning}");
    }
    println!(
        "glTF: {} primitive nodes, {} triangles, {} bytes, {} m per unit; wrote {}",
        report.nodes,
        report.triangles,
        report.bytes,
        settings.metres_per_unit(),
        path.display()
    );
}

#[expect(clippy::print_stdout, reason = "CLI output")]
fn check(files: &[PathBuf], strokes: bool, overlay: Option<&Path>) -> Result<ExitCode> {
    if overlay.is_some() && files.len() != 1 {
        bail!("--overlay needs exactly one sketch file");
    }
    if let Some(png) = overlay {
        let inputs: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
        check_outputs(
            &[Output {
                path: png,
                option: "--overlay",
                extensions: PNG_EXTENSIONS,
            }],
            &inputs,
        )?;
    }
    let mut failures = 0;
    for file in files {
        match check_one(file) {
            Ok((report, kind)) => {
                println!("{}: ok: {report}", file.display());
                if strokes || overlay.is_some() {
                    if kind != FileKind::Sketch {
                        bail!("--strokes and --overlay take a sketch file");
                    }
                    stroke_classes(file, strokes, overlay)?;
                }
            }
            Err(error) => {
                failures += 1;
                eprintln!("{}: error: {error:#}", file.display());
            }
        }
    }
    if failures > 0 {
        bail!("{failures} of {} file(s) have problems", files.len());
    }
    Ok(ExitCode::SUCCESS)
}

/// Lists a sketch's strokes as the snapper sees them and/or draws them by class.
#[expect(clippy::print_stdout, reason = "CLI output")]
fn stroke_classes(file: &Path, list: bool, overlay: Option<&Path>) -> Result<()> {
    let loaded = load_sketch(file)?;
    let (clean, _notes) = preprocess(&loaded.sketch, &PreprocessOptions::default());
    let classes = classify_sketch(&clean, &ClassifyOptions::default());
    if list {
        println!(
            "  stroke   points   bounds (sketch units)                      class       reason"
        );
        for (stroke, c) in clean.strokes.iter().zip(&classes) {
            let (lo, hi) = stroke.points.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            println!(
                "  {:>6} {:>8}   ({:>8.1}, {:>8.1}) – ({:>8.1}, {:>8.1})   {:<11} {:?}",
                stroke.id.0,
                stroke.points.len(),
                lo.x,
                lo.y,
                hi.x,
                hi.y,
                format!("{:?}", c.class).to_lowercase(),
                c.reason
            );
        }
    }
    if let Some(png) = overlay {
        let pairs: Vec<(StrokeId, StrokeClass)> = classes.iter().map(|c| (c.id, c.class)).collect();
        let bytes = classes_png(&clean, &pairs)?;
        write_outputs(&[(png, bytes)])?;
        println!(
            "  classes: {} (features blue, silhouettes black)",
            png.display()
        );
    }
    Ok(())
}

/// What a file holds, decided by its content (the `format` tag of a JSON file), not its
/// name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FileKind {
    Script,
    Model,
    Session,
    Sketch,
}

/// The kind of a file's content: a geosnap JSON file by its `format`, else a sketch (SVG
/// or anything the sketch reader can tell about).
fn file_kind(data: &[u8]) -> FileKind {
    match geosnap::io::json::format_tag(data).as_deref() {
        Some("geosnap-script") => FileKind::Script,
        Some("geosnap-model") => FileKind::Model,
        Some("geosnap-session") => FileKind::Session,
        _ => FileKind::Sketch,
    }
}

/// Checks one file by what it holds: a script, a model, a session or a sketch.
fn check_one(file: &Path) -> Result<(String, FileKind)> {
    let data = read_input(file).context("cannot read it")?;
    let kind = file_kind(&data);
    let report = match kind {
        FileKind::Script => {
            let base = file.parent().unwrap_or(Path::new(""));
            let script = parse_script(&data, base)?;
            let invalid: Vec<String> = script
                .invalid_steps()
                .iter()
                .map(|(i, reason)| format!("step {i}: {reason}"))
                .collect();
            let sketch = load_sketch(&script.sketch)
                .with_context(|| format!("its sketch {}", script.sketch.display()))?;
            if !invalid.is_empty() {
                bail!("{} invalid step(s): {}", invalid.len(), invalid.join("; "));
            }
            if sketch.sketch.strokes.is_empty() {
                bail!("its sketch {} has no strokes", script.sketch.display());
            }
            format!(
                "script with {} steps over {} strokes",
                script.steps.len(),
                sketch.sketch.strokes.len()
            )
        }
        FileKind::Model => {
            let model = parse_model(&data)?;
            format!(
                "model with {} primitives, {} skipped steps",
                model.document.len(),
                model.document.skipped.len()
            )
        }
        FileKind::Session => {
            let session = geosnap::io::parse_session(&data)?;
            format!(
                "session with {} strokes and {} primitives",
                session.sketch.strokes.len(),
                session.document.len()
            )
        }
        FileKind::Sketch => check_sketch(file)?,
    };
    Ok((report, kind))
}

/// Checks a sketch file: it loads and has strokes.
fn check_sketch(file: &Path) -> Result<String> {
    let loaded = load_sketch(file)?;
    if loaded.sketch.strokes.is_empty() {
        bail!("the sketch has no strokes");
    }
    let classes = classify_sketch(&loaded.sketch, &ClassifyOptions::default());
    let features = classes
        .iter()
        .filter(|c| c.class == StrokeClass::Feature)
        .count();
    let mut report = format!(
        "sketch with {} strokes ({features} feature, {} silhouette)",
        loaded.sketch.strokes.len(),
        classes.len() - features
    );
    for warning in &loaded.warnings {
        report.push_str("; warning: ");
        report.push_str(warning);
    }
    Ok(report)
}

#[expect(clippy::print_stdout, reason = "CLI output")]
fn sample(dir: &Path) -> Result<ExitCode> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let svg = dir.join("vase.svg");
    let script = dir.join("vase.script.json");
    geosnap::io::write_atomic(&svg, geosnap::samples::VASE_SVG.as_bytes())
        .with_context(|| format!("writing {}", svg.display()))?;
    geosnap::io::write_atomic(&script, geosnap::samples::VASE_SCRIPT.as_bytes())
        .with_context(|| format!("writing {}", script.display()))?;
    println!(
        "wrote {} and {}\ntry: geosnap run {} --out vase.model.json --overlay vase.png",
        svg.display(),
        script.display(),
        script.display()
    );
    Ok(ExitCode::SUCCESS)
}
