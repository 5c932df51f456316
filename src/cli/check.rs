//! `geosnap check`: files loaded by their content and their problems reported.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::core::sketch::{
    classify_sketch, preprocess, ClassifyOptions, PreprocessOptions, StrokeClass, StrokeId,
};
use crate::core::snap::SnapContext;
use crate::io::input::read_input;
use crate::io::model_file::parse_model;
use crate::io::overlay::classes_png;
use crate::io::script::parse_script;
use crate::io::sketch_file::load_sketch;
use anyhow::{bail, Context, Result};
use glam::DVec2;

use super::limit::Deadline;
use super::outputs::{check_outputs, write_outputs, Output, PNG_EXTENSIONS};

#[expect(clippy::print_stdout, reason = "CLI output")]
pub(super) fn check(
    files: &[PathBuf],
    strokes: bool,
    overlay: Option<&Path>,
    deadline: &Deadline,
) -> Result<ExitCode> {
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
    let mut failures = Vec::new();
    for (index, file) in files.iter().enumerate() {
        deadline.check(|| format!("after checking {index} of {} file(s)", files.len()))?;
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
                eprintln!("{}: error: {error:#}", file.display());
                failures.push(file.display().to_string());
            }
        }
    }
    deadline.check(|| format!("after checking all {} file(s)", files.len()))?;
    if !failures.is_empty() {
        let more = failures.len().saturating_sub(MAX_LISTED_FILES);
        failures.truncate(MAX_LISTED_FILES);
        bail!(
            "{} of {} file(s) have problems: {}{}",
            failures.len() + more,
            files.len(),
            failures.join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The most failing files the final error of `check` names (each has its own message
/// before it).
const MAX_LISTED_FILES: usize = 10;

/// Lists a sketch's strokes as the snapper sees them and/or draws them by class.
#[expect(clippy::print_stdout, reason = "CLI output")]
pub(super) fn stroke_classes(file: &Path, list: bool, overlay: Option<&Path>) -> Result<()> {
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

/// The message on duplicate strokes merged while preparing a sketch, if any were.
pub(super) fn merged_message(merged: usize) -> Option<String> {
    match merged {
        0 => None,
        1 => Some("merged 1 duplicate stroke".to_owned()),
        n => Some(format!("merged {n} duplicate strokes")),
    }
}

/// What a file holds, decided by its content (the `format` tag of a JSON file), not its
/// name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum FileKind {
    Script,
    Model,
    Session,
    Sketch,
}

/// The kind of a file's content: a geosnap JSON file by its `format`, else a sketch (SVG
/// or anything the sketch reader can tell about).
pub(super) fn file_kind(data: &[u8]) -> FileKind {
    match crate::io::json::format_tag(data).as_deref() {
        Some("geosnap-script") => FileKind::Script,
        Some("geosnap-model") => FileKind::Model,
        Some("geosnap-session") => FileKind::Session,
        _ => FileKind::Sketch,
    }
}

/// Checks one file by what it holds: a script, a model, a session or a sketch.
pub(super) fn check_one(file: &Path) -> Result<(String, FileKind)> {
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
            let session = crate::io::parse_session(&data)?;
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
pub(super) fn check_sketch(file: &Path) -> Result<String> {
    let loaded = load_sketch(file)?;
    if loaded.sketch.strokes.is_empty() {
        bail!("the sketch has no strokes");
    }
    // The strokes as the snapper sees them: cleaned, duplicates merged, classified.
    let prepared = SnapContext::prepare(&loaded.sketch);
    let strokes = &prepared.context.strokes;
    let features = strokes
        .iter()
        .filter(|s| s.class == StrokeClass::Feature)
        .count();
    let mut report = format!(
        "sketch with {} strokes ({features} feature, {} silhouette)",
        loaded.sketch.strokes.len(),
        strokes.len() - features
    );
    if let Some(merged) = merged_message(prepared.merged.len()) {
        report.push_str("; ");
        report.push_str(&merged);
    }
    for warning in &loaded.warnings {
        report.push_str("; warning: ");
        report.push_str(warning);
    }
    Ok(report)
}
