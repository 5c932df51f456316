//! The layering rules of design.md §1, checked on the source text: the core stays pure
//! (no GUI, GPU, filesystem or clock), argmin stays inside its one adapter file, and the
//! outer layers do not reach into the GUI.

use std::fs;
use std::path::{Path, PathBuf};

fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let Ok(entries) = fs::read_dir(dir) else {
        return files;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            files.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
    files.sort();
    files
}

/// The code of a file without its comments (doc comments may name what code must not).
fn code_of(path: &Path) -> String {
    let text = fs::read_to_string(path).expect("source files are readable");
    text.lines()
        .map(|line| match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn violations(dir: &str, forbidden: &[&str], except: &[&str]) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    let mut found = Vec::new();
    for file in rust_files(&root) {
        let relative = file
            .strip_prefix(env!("CARGO_MANIFEST_DIR"))
            .expect("files lie below the manifest directory")
            .to_string_lossy()
            .replace('\\', "/");
        let code = code_of(&file);
        for word in forbidden {
            if code.contains(word) && !except.iter().any(|e| relative.ends_with(e)) {
                found.push(format!("{relative} uses `{word}`"));
            }
        }
    }
    found
}

#[test]
fn the_core_is_pure() {
    let found = violations(
        "src/core",
        &[
            "egui",
            "eframe",
            "wgpu",
            "winit",
            "std::fs",
            "Instant",
            "SystemTime",
            "crate::io",
            "crate::render",
            "crate::app",
            "crate::clock",
            "println!",
        ],
        &[],
    );
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn argmin_lives_in_one_adapter_file() {
    let mut found = violations("src", &["argmin::"], &["src/core/solve/lbfgs.rs"]);
    found.extend(violations("src", &["argmin_math"], &[]));
    assert!(found.is_empty(), "{found:#?}");
    let adapter = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/core/solve/lbfgs.rs");
    assert!(
        code_of(&adapter).contains("argmin::"),
        "the adapter is where argmin is used"
    );
}

#[test]
fn only_the_gui_layers_name_the_gui() {
    let mut found = Vec::new();
    for dir in ["src/io", "src/core"] {
        found.extend(violations(
            dir,
            &["egui", "eframe", "wgpu", "crate::app"],
            &[],
        ));
    }
    let cli = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/cli.rs");
    let code = code_of(&cli);
    for word in ["egui", "wgpu", "crate::app"] {
        if code.contains(word) {
            found.push(format!("src/cli.rs uses `{word}`"));
        }
    }
    found.extend(violations("src/render", &["crate::app", "crate::io"], &[]));
    // The app's state and workers are plain Rust, testable without a window.
    for file in ["src/app/editor.rs", "src/app/worker.rs"] {
        let code = code_of(&Path::new(env!("CARGO_MANIFEST_DIR")).join(file));
        for word in ["egui", "eframe", "wgpu", "winit"] {
            if code.contains(word) {
                found.push(format!("{file} uses `{word}`"));
            }
        }
    }
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn the_checker_sees_the_sources() {
    // Guards the guards: if the walk found nothing, the tests above would pass vacuously.
    let core = rust_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src/core"));
    assert!(core.len() >= 10, "found {} core files", core.len());
    assert!(!violations("src/core/ad", &["Expr"], &[]).is_empty());
}
