//! Shared by the end-to-end tests: run a placement script headless and judge its fits.

use std::path::{Path, PathBuf};

use geosnap::core::model::{run_steps, Document, SessionSettings, StepOutcome};
use geosnap::core::solve::SolveContext;
use geosnap::io::model_file::{model_json, parse_model};
use geosnap::io::script::load_script;
use geosnap::io::sketch_file::load_sketch;

/// The scripts in a folder, sorted.
#[allow(dead_code, reason = "not every test binary uses every helper")]
pub(crate) fn scripts_in(dir: &Path) -> Vec<PathBuf> {
    let mut scripts: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("the folder is readable")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.to_string_lossy().ends_with(".script.json"))
        .collect();
    scripts.sort();
    scripts
}

/// Runs one script; returns one line per step and the failures.
#[allow(dead_code, reason = "not every test binary uses every helper")]
pub(crate) fn run_script(
    script_path: &Path,
    sketch_dir: Option<&Path>,
) -> (Vec<String>, Vec<String>) {
    let (lines, failures, _) = run_script_document(script_path, sketch_dir);
    (lines, failures)
}

/// Runs one script; returns one line per step, the failures and the document.
#[allow(dead_code, reason = "not every test binary uses every helper")]
pub(crate) fn run_script_document(
    script_path: &Path,
    sketch_dir: Option<&Path>,
) -> (Vec<String>, Vec<String>, Document) {
    let mut script = load_script(script_path).expect("the script loads");
    if let Some(dir) = sketch_dir {
        let name = script
            .sketch
            .file_name()
            .expect("a sketch file name")
            .to_owned();
        script.sketch = dir.join(name);
    }
    let loaded = load_sketch(&script.sketch).expect("the sketch loads");
    let steps = &script.steps;
    let (document, outcomes) = run_steps(
        &loaded.sketch,
        steps,
        &SessionSettings::default(),
        SolveContext::default(),
    );
    let name = script_path
        .file_name()
        .unwrap_or_default()
        .to_string_lossy();
    let mut lines = Vec::new();
    let mut failures = Vec::new();
    for (i, outcome) in outcomes.iter().enumerate() {
        match outcome {
            StepOutcome::Placed {
                snap,
                solve,
                relations,
                ..
            } => {
                let relative = snap.rms / snap.primitive.size();
                lines.push(format!(
                    "{name} step {i}: {} relation(s); solved {} part(s){}",
                    relations.len(),
                    solve.solved.len(),
                    solve.conflicts.iter().fold(String::new(), |mut out, c| {
                        out.push_str("; ");
                        out.push_str(&c.message);
                        out
                    })
                ));
                lines.push(format!(
                    "{name} step {i}: {} rms {:.2} = {:.2} % of size, {} strokes",
                    snap.primitive.kind().name(),
                    snap.rms,
                    100.0 * relative,
                    snap.assignment.stroke_ids().len()
                ));
                if relative > 0.03 {
                    failures.push(format!(
                        "{name} step {i}: rms {:.2} % of size",
                        100.0 * relative
                    ));
                }
            }
            StepOutcome::Skipped(s) | StepOutcome::Refused { skipped: s, .. } => {
                failures.push(format!("{name} step {i}: skipped: {}", s.reason));
            }
        }
    }
    let json = serde_json::to_vec(&model_json(&document, "sketch.svg")).expect("serialises");
    let back = parse_model(&json).expect("the model reads back");
    if back.document.len() != document.len() {
        failures.push(format!("{name}: the model did not round-trip"));
    }
    (lines, failures, document)
}

/// The sketch folder, or `None` (with a note) when the suite is not asked for.
#[allow(dead_code, reason = "not every test binary uses every helper")]
pub(crate) fn shared_dir() -> Option<PathBuf> {
    let Some(dir) = std::env::var_os("GEOSNAP_SHARED_SKETCHES").map(PathBuf::from) else {
        eprintln!("GEOSNAP_SHARED_SKETCHES is not set: the shared-sketch suite was skipped");
        return None;
    };
    assert!(
        dir.is_dir(),
        "GEOSNAP_SHARED_SKETCHES is set but {} is not a folder",
        dir.display()
    );
    Some(dir)
}
