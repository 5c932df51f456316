//! `geosnap solve` and `geosnap export`: a model file re-solved, or exported as glTF.

use std::io::IsTerminal;
use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use crate::clock::MonotonicClock;
use crate::core::model::{Companions, Conflict, GlobalSettings};
use crate::core::solve::{Clock, Iterate};
use crate::io::gltf::{
    encode_gltf, ExportReport, ExportSettings, GltfFormat, Origin, DEFAULT_METRES_PER_UNIT,
};
use crate::io::model_file::{load_model, model_bytes, read_model};
use anyhow::{Context, Result};

use super::limit::Deadline;
use super::outputs::{check_outputs, write_outputs, Output, GLTF_EXTENSIONS, MODEL_EXTENSIONS};

#[expect(clippy::print_stdout, reason = "CLI output")]
pub(super) fn solve_model(path: &Path, out: &Path, deadline: &Deadline) -> Result<ExitCode> {
    check_outputs(
        &[Output {
            path: out,
            option: "--out",
            extensions: MODEL_EXTENSIONS,
        }],
        &[path],
    )?;
    let (original, mut loaded) = read_model(path).context("reading the model")?;
    deadline.check(|| format!("after reading {}, before solving it", path.display()))?;
    let clock = MonotonicClock::start();
    let show = std::io::stderr().is_terminal();
    if show {
        eprintln!(
            "solving {} part(s) with {} relation(s)…",
            loaded.document.len(),
            loaded.document.relations().len()
        );
    }
    let mut begun = 0_usize;
    let mut observer = |iterate: &Iterate<'_>| {
        if iterate.outer == 1 {
            begun += 1;
            if show && begun > 1 {
                eprintln!(
                    "  re-solve {} after a conflict, at {:.0} ms",
                    begun - 1,
                    ms(clock.elapsed())
                );
            }
        }
    };
    let outcome = loaded.document.solve(
        None,
        &GlobalSettings::default(),
        Companions::default()
            .with_clock(&clock)
            .with_cancel(deadline.flag())
            .with_observer(&mut observer),
    );
    deadline.check(|| {
        format!(
            "during the global solve of {} ({} solve(s) begun, {} conflict(s) so far)",
            path.display(),
            outcome.solves,
            outcome.conflicts.len()
        )
    })?;
    print_conflicts(&outcome.conflicts);
    if let Some(report) = &outcome.report {
        println!(
            "solved {} part(s) with {} relation(s){}: {}, ‖ψ‖∞ {:.1e}, {} evaluations, {:.1} ms; \
             {} global solve(s) ({} re-solve(s) after conflicts, {} evaluations in all), \
             {:.1} ms in all",
            outcome.solved.len(),
            outcome.relations,
            implied(outcome.implied),
            report.termination,
            report.max_violation,
            report.evaluations,
            ms(report.elapsed),
            outcome.solves,
            outcome.solves.saturating_sub(1),
            outcome.evaluations,
            ms(clock.elapsed())
        );
    }
    if outcome.reverted {
        // Refused: the file written is the input, byte for byte, and the command fails.
        write_outputs(&[(out, original)])?;
        let why = outcome.report.as_ref().map_or(String::new(), |r| {
            format!(
                "; the last solve {}, with a violation of {:.1e} left",
                r.termination, r.max_violation
            )
        });
        eprintln!(
            "geosnap: the solve of {} was refused ({} conflict(s) switched off before it gave \
             up{why}): {} is written unchanged, byte for byte",
            path.display(),
            outcome.conflicts.len(),
            out.display()
        );
        return Ok(ExitCode::FAILURE);
    }
    let bytes = model_bytes(&loaded.document, &loaded.sketch)
        .with_context(|| format!("encoding {}", out.display()))?;
    write_outputs(&[(out, bytes)])?;
    println!("wrote {}", out.display());
    Ok(ExitCode::SUCCESS)
}

/// Conflict lines printed one by one; beyond them, a count.
const CONFLICTS_SHOWN: usize = 20;

/// Prints the conflicts, the first [`CONFLICTS_SHOWN`] in full and a count of the rest
/// (every one is in the model file written, with mode `off`).
#[expect(clippy::print_stdout, reason = "CLI output")]
fn print_conflicts(conflicts: &[Conflict]) {
    for conflict in conflicts.iter().take(CONFLICTS_SHOWN) {
        println!("conflict: {}", conflict.message);
    }
    if conflicts.len() > CONFLICTS_SHOWN {
        println!(
            "… and {} more conflict(s), each with mode off in the model",
            conflicts.len() - CONFLICTS_SHOWN
        );
    }
}

/// ` (N implied by the others, not solved again)`, or nothing when none is.
fn implied(n: usize) -> String {
    if n == 0 {
        String::new()
    } else {
        format!(" ({n} implied by the others, not solved again)")
    }
}

pub(super) fn export(
    model: &Path,
    out: &Path,
    (scale, segments): (Option<f64>, usize),
    deadline: &Deadline,
) -> Result<ExitCode> {
    check_outputs(
        &[Output {
            path: out,
            option: "--out",
            extensions: GLTF_EXTENSIONS,
        }],
        &[model],
    )?;
    // Bad settings are refused before the model is read.
    let settings = ExportSettings::new(
        scale.unwrap_or(DEFAULT_METRES_PER_UNIT),
        segments,
        Origin::default(),
    )?;
    let loaded = load_model(model).context("reading the model")?;
    // Without `--scale`, one model unit is what the model says it is.
    let settings = match scale {
        Some(_) => settings,
        None => ExportSettings::new(loaded.document.unit().metres(), segments, Origin::default())?,
    };
    deadline.check(|| format!("after reading {}, before exporting it", model.display()))?;
    if std::io::stderr().is_terminal() {
        eprintln!(
            "exporting {} part(s) to {}…",
            loaded.document.len(),
            out.display()
        );
    }
    let (bytes, report) = gltf_bytes(&loaded.document, out, &settings)
        .with_context(|| model.display().to_string())?;
    deadline.check(|| {
        format!(
            "after encoding {}, before writing {}",
            model.display(),
            out.display()
        )
    })?;
    write_outputs(&[(out, bytes)])?;
    print_gltf_report(&report, out, &settings);
    Ok(ExitCode::SUCCESS)
}

/// Encodes a document as glTF for `path` (binary or JSON by its extension).
pub(super) fn gltf_bytes(
    document: &crate::core::model::Document,
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
pub(super) fn print_gltf_report(report: &ExportReport, path: &Path, settings: &ExportSettings) {
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

/// A duration in milliseconds.
fn ms(duration: Duration) -> f64 {
    duration.as_secs_f64() * 1e3
}
