//! Our placement scripts over the hand-drawn sketches of the original system
//! (`tests/shared_scripts/*.script.json`), run when `GEOSNAP_SHARED_SKETCHES` names the
//! folder holding them (CI sets it; the sketches are never copied into the project).
//! Every placed primitive must snap with a fit RMS of at most 3 % of its size, but for
//! at most [`REFUSED_CEILING`] steps whose snap refuses itself (its confidence says the
//! part is not the one meant).

mod common;

use std::path::{Path, PathBuf};

/// Today's ceiling of steps refused by their own confidence (1): the first goblet's
/// stem, since a curve began to count as drawn by how close its strokes run. Its snap
/// is wrong against the 2D reference measured from the drawing (`shared_parts`: its top
/// end 11 % of its size off) and was accepted silently before; refusing a wrong part is
/// what the confidence is for, so a refusal is counted here, not failed, and any other
/// skipped step still fails.
const REFUSED_CEILING: usize = 1;

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
    let (refused, failures): (Vec<String>, Vec<String>) = failures
        .into_iter()
        .partition(|f| f.contains("the snap was refused"));
    assert!(failures.is_empty(), "{failures:#?}");
    assert!(
        refused.len() <= REFUSED_CEILING,
        "{} steps refused, above today's ceiling {REFUSED_CEILING}: {refused:#?}",
        refused.len()
    );
}
