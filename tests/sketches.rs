//! End to end over the project's own sample sketches (`sketches/*.script.json`): every
//! script runs headless, every step snaps with a fit RMS of at most 3 % of the
//! primitive's size, and the model file round-trips.

mod common;

use std::path::Path;

#[test]
fn every_sample_script_snaps_every_step() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("sketches");
    let scripts = common::scripts_in(&dir);
    assert!(scripts.len() >= 6, "six samples or more: {scripts:?}");
    let mut failures = Vec::new();
    for script in &scripts {
        let (lines, fails) = common::run_script(script, None);
        for line in lines {
            eprintln!("{line}");
        }
        failures.extend(fails);
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
