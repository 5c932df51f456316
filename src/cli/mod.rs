//! The command line: `geosnap [COMMAND]`.
//!
//! - `geosnap run SCRIPT --out MODEL [--overlay PNG] [--gltf FILE] [--strict]`: a
//!   placement script, headless. Outputs are checked before any work and written
//!   together or not at all.
//! - `geosnap export MODEL --out FILE.glb|FILE.gltf [--scale M] [--segments N]`: glTF 2.0.
//! - `geosnap check FILE…`: loads sketches, scripts or models and reports problems.
//! - `geosnap solve MODEL --out MODEL`: re-solves a model with its relations.
//! - `geosnap selftest`: the solver on the Hock–Schittkowski problems.

mod check;
mod model;
mod outputs;
mod run;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use geosnap::clock::MonotonicClock;
use geosnap::core::solve::{hock_schittkowski, AugLagSettings, InnerSolver, Solver, Start};
use geosnap::io::gltf::{DEFAULT_METRES_PER_UNIT, DEFAULT_SEGMENTS};

use check::check;
use model::{export, solve_model};
use run::{run, RunArgs};

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
    anyhow::bail!(
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
