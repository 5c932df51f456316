//! The command line: `geosnap [COMMAND]`.
//!
//! Today the numerical core is in place; the snapping, relations, export and the desktop
//! application arrive in later releases. `geosnap selftest` runs the solver on the
//! Hock–Schittkowski problems and prints how each went.

use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use geosnap::clock::MonotonicClock;
use geosnap::core::solve::{hock_schittkowski, AugLagSettings, InnerSolver, Solver, Start};

/// Sketch-based 3D modelling with geosemantic snapping.
#[derive(Debug, Parser)]
#[command(name = "geosnap", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
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
    let result = match cli.command {
        Some(Command::Selftest { json, argmin }) => selftest(json, argmin),
        None => Ok(no_command()),
    };
    match result {
        Ok(code) => code,
        Err(error) => {
            eprintln!("geosnap: {error:#}");
            ExitCode::FAILURE
        }
    }
}

#[expect(clippy::print_stdout, reason = "CLI output")]
fn no_command() -> ExitCode {
    println!(
        "geosnap {}: the numerical core (automatic differentiation and the constrained \
         solver) is in place; the desktop application is not built yet.\n\
         Try `geosnap selftest`, or `geosnap --help`.",
        env!("CARGO_PKG_VERSION")
    );
    ExitCode::SUCCESS
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
