//! The command line: `geosnap COMMAND`, parsed by [`Command`] and run by [`execute`].
//!
//! - `geosnap run SCRIPT --out MODEL [--overlay PNG] [--gltf FILE] [--strict]`: a
//!   placement script, headless. Outputs are checked before any work and written
//!   together or not at all.
//! - `geosnap export MODEL --out FILE.glb|FILE.gltf [--scale M] [--segments N]`: glTF 2.0.
//! - `geosnap check FILE…`: loads sketches, scripts, models or sessions and reports
//!   problems.
//! - `geosnap solve MODEL --out MODEL`: re-solves a model with its relations.
//! - `geosnap sample DIR`: the built-in sample sketch and its script.
//! - `geosnap selftest`: the solver on the Hock–Schittkowski problems.
//!
//! `run`, `solve`, `export` and `check` take `--time-limit SECONDS`, a budget for the
//! whole command: when it is spent the command stops at the next safe point (between
//! steps, between files, or inside a global solve through the solver's cancel flag),
//! writes nothing, and ends with [`TimeLimitReached`] (exit status
//! [`EXIT_TIME_LIMIT`]).
//!
//! The binary (`src/main.rs`) adds the desktop application (no command) and turns the
//! result of [`execute`] into an exit status with [`exit_code`]; tests drive the same
//! [`execute`] in-process.

mod check;
mod limit;
mod model;
mod outputs;
mod run;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

use crate::clock::MonotonicClock;
use crate::core::solve::{hock_schittkowski, AugLagSettings, InnerSolver, Solver, Start};
use crate::io::gltf::DEFAULT_SEGMENTS;

pub use limit::{TimeLimitReached, EXIT_HELP, EXIT_TIME_LIMIT};

use check::check;
use limit::{parse_seconds, Deadline};
use model::{export, solve_model};
use run::{run, RunArgs};

/// A command of `geosnap`.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a placement script headless and write the model (and an overlay PNG).
    ///
    /// Every output is checked before any work (a supported extension, a writable
    /// folder, not an input) and all are written together or none. The script is refused
    /// before any work when a step is invalid (an unknown field, say) or its sketch has
    /// no strokes; exit status 1 then, and on any error. A step that cannot be snapped is
    /// skipped with a warning; with `--strict` that also exits 1, after writing.
    #[command(after_help = EXIT_HELP)]
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
        /// A budget for the whole command, in seconds: when it is spent the command
        /// stops at the next safe point, writes nothing and exits with status 3.
        #[arg(long, value_name = "SECONDS", value_parser = parse_seconds, allow_negative_numbers = true)]
        time_limit: Option<Duration>,
    },
    /// Export a model file as glTF 2.0: metres, +Y up, one node per primitive.
    #[command(after_help = EXIT_HELP)]
    Export {
        /// The model (`*.model.json`).
        model: PathBuf,
        /// The file to write: `.glb` (binary) or `.gltf` (JSON, buffer embedded).
        #[arg(long)]
        out: PathBuf,
        /// Metres per model unit (one sketch unit). By default the model's own `unit`
        /// decides (a millimetre, 0.001, for a model file without one).
        #[arg(long, allow_negative_numbers = true)]
        scale: Option<f64>,
        /// Segments around each circle.
        #[arg(long, default_value_t = DEFAULT_SEGMENTS)]
        segments: usize,
        /// A budget for the whole command, in seconds: when it is spent the command
        /// stops at the next safe point, writes nothing and exits with status 3.
        #[arg(long, value_name = "SECONDS", value_parser = parse_seconds, allow_negative_numbers = true)]
        time_limit: Option<Duration>,
    },
    /// Write the built-in sample sketch and its script into a folder.
    Sample {
        /// The folder (created if missing).
        dir: PathBuf,
    },
    /// Load sketches, scripts or models and report problems.
    #[command(after_help = EXIT_HELP)]
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
        /// A budget for the whole command, in seconds: when it is spent the command
        /// stops at the next safe point, writes nothing and exits with status 3.
        #[arg(long, value_name = "SECONDS", value_parser = parse_seconds, allow_negative_numbers = true)]
        time_limit: Option<Duration>,
    },
    /// Re-solve a model file with its relations (as edited by hand, say): relations that
    /// conflict are switched off with a message; the parts keep the places their fits
    /// gave them, as the model file has no strokes.
    #[command(after_help = EXIT_HELP)]
    Solve {
        /// The model file (`*.model.json`).
        model: PathBuf,
        /// Where to write the solved model.
        #[arg(long)]
        out: PathBuf,
        /// A budget for the whole command, in seconds: when it is spent the command
        /// stops at the next safe point, writes nothing and exits with status 3.
        #[arg(long, value_name = "SECONDS", value_parser = parse_seconds, allow_negative_numbers = true)]
        time_limit: Option<Duration>,
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

/// Parses a command line (`args[0]` is the program's name, as in [`std::env::args_os`])
/// into a [`Command`], as the binary does.
///
/// # Errors
///
/// Clap's error for an unknown command or option, a missing argument or a bad value.
pub fn parse<I, T>(args: I) -> Result<Command, clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    /// The command line without the desktop application's options.
    #[derive(Parser)]
    #[command(name = "geosnap")]
    struct Only {
        #[command(subcommand)]
        command: Command,
    }
    Only::try_parse_from(args).map(|only| only.command)
}

/// Runs a command: its report goes to stdout, warnings and progress to stderr.
///
/// # Errors
///
/// Any failure, with a message that names the file concerned; nothing is written then
/// (`run --strict` excepted, which fails after writing). A spent `--time-limit` is a
/// [`TimeLimitReached`] (see [`exit_code`]).
pub fn execute(command: Command) -> Result<ExitCode> {
    match command {
        Command::Selftest { json, argmin } => selftest(json, argmin),
        Command::Run {
            script,
            out,
            overlay,
            gltf,
            accept_suggestions,
            strict,
            time_limit,
        } => run(&RunArgs {
            script: &script,
            out: &out,
            overlay: overlay.as_deref(),
            gltf: gltf.as_deref(),
            accept_suggestions,
            strict,
            deadline: &Deadline::new(time_limit),
        }),
        Command::Export {
            model,
            out,
            scale,
            segments,
            time_limit,
        } => export(&model, &out, (scale, segments), &Deadline::new(time_limit)),
        Command::Check {
            files,
            strokes,
            overlay,
            time_limit,
        } => check(
            &files,
            strokes,
            overlay.as_deref(),
            &Deadline::new(time_limit),
        ),
        Command::Sample { dir } => sample(&dir),
        Command::Solve {
            model,
            out,
            time_limit,
        } => solve_model(&model, &out, &Deadline::new(time_limit)),
    }
}

/// The exit status of a command's result, its error printed on stderr: 0 or the
/// command's own on success, [`EXIT_TIME_LIMIT`] for a spent `--time-limit`, 1 for any
/// other error.
pub fn exit_code(result: Result<ExitCode>) -> ExitCode {
    match result {
        Ok(code) => code,
        Err(error) => {
            eprintln!("geosnap: {error:#}");
            if error.downcast_ref::<TimeLimitReached>().is_some() {
                ExitCode::from(EXIT_TIME_LIMIT)
            } else {
                ExitCode::FAILURE
            }
        }
    }
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
    crate::io::write_atomic(&svg, crate::samples::VASE_SVG.as_bytes())
        .with_context(|| format!("writing {}", svg.display()))?;
    crate::io::write_atomic(&script, crate::samples::VASE_SCRIPT.as_bytes())
        .with_context(|| format!("writing {}", script.display()))?;
    println!(
        "wrote {} and {}\ntry: geosnap run {} --out vase.model.json --overlay vase.png",
        svg.display(),
        script.display(),
        script.display()
    );
    Ok(ExitCode::SUCCESS)
}
