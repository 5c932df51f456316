//! The automatic stroke classification against labels made by eye for every hand-drawn
//! sketch of the original system (`tests/shared_classes/*.json`: which strokes are
//! features, and the few where either class is defensible). The original made the user
//! classify every stroke; we classify them automatically and must agree with a person.
//!
//! Run when `GEOSNAP_SHARED_SKETCHES` names the folder holding the sketches (CI sets
//! it; the sketches are never copied into the project); set to a missing folder, it
//! fails.

#![expect(clippy::print_stdout, reason = "the test prints its per-sketch table")]

use std::path::{Path, PathBuf};

use geosnap::core::sketch::{
    classify_sketch, preprocess, ClassifyOptions, PreprocessOptions, StrokeClass,
};
use geosnap::io::sketch_file::load_sketch;
use serde::Deserialize;

/// The labels of one sketch.
#[derive(Debug, Deserialize)]
struct Labels {
    /// The sketch's file name in the shared folder.
    sketch: String,
    /// How many strokes the sketch has after preprocessing.
    strokes: usize,
    /// The ids of the feature strokes.
    features: Vec<u32>,
    /// Ids where either class is defensible.
    #[serde(default)]
    either: Vec<u32>,
}

/// The strokes the classifier still gets wrong, each with what it is. The test fails
/// when a stroke outside this list is misclassified, and when one on it is classified
/// right (so the list only shrinks).
const KNOWN_MISSES: [(&str, u32, &str); 0] = [];

fn label_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/shared_classes");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("the labels are there")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

#[test]
fn strokes_are_classified_as_a_person_would() {
    let Some(dir) = std::env::var_os("GEOSNAP_SHARED_SKETCHES").map(PathBuf::from) else {
        println!("GEOSNAP_SHARED_SKETCHES is not set: the shared-sketch suite was skipped");
        return;
    };
    assert!(
        dir.is_dir(),
        "GEOSNAP_SHARED_SKETCHES is set but {} is not a folder",
        dir.display()
    );
    let files = label_files();
    assert!(!files.is_empty(), "no labels in tests/shared_classes");
    let mut mistakes = Vec::new();
    let (mut total, mut wrong) = (0, 0);
    println!("sketch                  strokes  features  unexpected");
    for file in &files {
        let text = std::fs::read_to_string(file).expect("the labels are readable");
        let labels: Labels = serde_json::from_str(&text).expect("the labels parse");
        let loaded = load_sketch(dir.join(&labels.sketch)).expect("the sketch loads");
        let (clean, _) = preprocess(&loaded.sketch, &PreprocessOptions::default());
        assert_eq!(
            clean.strokes.len(),
            labels.strokes,
            "{}: the stroke count changed (preprocessing?), so the labels no longer apply",
            labels.sketch
        );
        let classes = classify_sketch(&clean, &ClassifyOptions::default());
        let mut here = Vec::new();
        for c in &classes {
            let id = c.id.0;
            if labels.either.contains(&id) {
                continue;
            }
            let expected = if labels.features.contains(&id) {
                StrokeClass::Feature
            } else {
                StrokeClass::Silhouette
            };
            let known = KNOWN_MISSES
                .iter()
                .any(|(sketch, stroke, _)| *sketch == labels.sketch && *stroke == id);
            if (c.class != expected) != known {
                here.push(format!(
                    "{} stroke {id}: {}",
                    labels.sketch,
                    if known {
                        "on the list of known misses but classified right: take it off"
                    } else {
                        "misclassified"
                    }
                ));
            }
            if c.class != expected {
                wrong += 1;
                println!(
                    "  {} stroke {id}: {:?} ({:?}), a person says {expected:?}",
                    labels.sketch, c.class, c.reason
                );
            }
        }
        println!(
            "{:<22} {:>8} {:>9} {:>9}",
            labels.sketch,
            classes.len(),
            labels.features.len(),
            here.len()
        );
        println!();
        total += classes.len();
        mistakes.extend(here);
    }
    println!(
        "all: {wrong} of {total} strokes classified differently from the labels ({} known)",
        KNOWN_MISSES.len()
    );
    assert!(mistakes.is_empty(), "{mistakes:#?}");
}
