//! Our placement scripts over the hand-drawn sketches of the original system
//! (`tests/shared_scripts/*.script.json`), run when `GEOSNAP_SHARED_SKETCHES` names the
//! folder holding them (CI sets it; the sketches are never copied into the project).
//! Every placed primitive must snap with a fit RMS of at most 3 % of its size.

mod common;

use std::path::{Path, PathBuf};

#[test]
fn our_scripts_over_the_shared_sketches_snap() {
    let Some(dir) = std::env::var_os("GEOSNAP_SHARED_SKETCHES").map(PathBuf::from) else {
        eprintln!("GEOSNAP_SHARED_SKETCHES is not set: the shared-sketch suite was skipped");
        return;
    };
    assert!(
        dir.is_dir(),
        "GEOSNAP_SHARED_SKETCHES is set but {} is not a folder",
        dir.display()
    );
    let scripts =
        common::scripts_in(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/shared_scripts"));
    assert!(scripts.len() >= 6, "{scripts:?}");
    let mut failures = Vec::new();
    for script in &scripts {
        let (lines, fails) = common::run_script(script, Some(&dir));
        for line in lines {
            eprintln!("{line}");
        }
        failures.extend(fails);
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
