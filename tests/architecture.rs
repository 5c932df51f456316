//! The layering rules of design.md §1. The core is its own crate (`geosnap-core`), so the
//! compiler keeps it from naming io, render, app or the clock; these tests check the rest:
//! the core depends on no GUI, file or clock crate, argmin stays inside its one adapter
//! file, and the outer layers do not reach into the GUI.

use std::fs;
use std::path::{Path, PathBuf};

/// The core crate's sources.
const CORE: &str = "crates/geosnap-core/src";

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

/// The core crate's own dependencies: numerics and data, nothing that draws, windows,
/// reads files or keeps time (its clippy.toml forbids the standard library's files and
/// clocks; the compiler keeps it from naming io, render, app or the clock).
const CORE_DEPENDENCIES: [&str; 9] = [
    "argmin",
    "argmin-math",
    "glam",
    "log",
    "nalgebra",
    "rstar",
    "rustc-hash",
    "serde",
    "thiserror",
];

/// The names of the `[dependencies]` of a manifest.
fn dependencies(manifest: &str) -> Vec<String> {
    let mut names = Vec::new();
    let mut inside = false;
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            inside = line == "[dependencies]";
        } else if inside && !line.is_empty() && !line.starts_with('#') {
            if let Some((name, _)) = line.split_once('=') {
                names.push(name.trim().to_owned());
            }
        }
    }
    names
}

#[test]
fn the_core_crate_depends_on_no_gui_files_or_clock() {
    let manifest = fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/geosnap-core/Cargo.toml"),
    )
    .expect("the core's manifest is readable");
    let names = dependencies(&manifest);
    assert!(!names.is_empty(), "the manifest's dependencies were read");
    let extra: Vec<&String> = names
        .iter()
        .filter(|n| !CORE_DEPENDENCIES.contains(&n.as_str()))
        .collect();
    assert!(extra.is_empty(), "the core depends on {extra:?}");
    let clippy = fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/geosnap-core/clippy.toml"),
    )
    .expect("the core's clippy.toml is readable");
    for forbidden in ["std::fs::File", "std::fs::read", "std::time::Instant"] {
        assert!(
            clippy.contains(&format!("\"{forbidden}\"")),
            "the core's clippy.toml forbids {forbidden}"
        );
    }
}

#[test]
fn argmin_lives_in_one_adapter_file() {
    let adapter_file = "crates/geosnap-core/src/solve/lbfgs.rs";
    let mut found = Vec::new();
    for dir in ["src", CORE] {
        found.extend(violations(dir, &["argmin::"], &[adapter_file]));
        found.extend(violations(dir, &["argmin_math"], &[]));
    }
    assert!(found.is_empty(), "{found:#?}");
    let adapter = Path::new(env!("CARGO_MANIFEST_DIR")).join(adapter_file);
    assert!(
        code_of(&adapter).contains("argmin::"),
        "the adapter is where argmin is used"
    );
}

#[test]
fn only_the_gui_layers_name_the_gui() {
    let mut found = Vec::new();
    for dir in ["src/io", CORE] {
        found.extend(violations(
            dir,
            &["egui", "eframe", "wgpu", "crate::app"],
            &[],
        ));
    }
    found.extend(violations("src/cli", &["egui", "wgpu", "crate::app"], &[]));
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
    let core = rust_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join(CORE));
    assert!(core.len() >= 10, "found {} core files", core.len());
    assert!(!violations(&format!("{CORE}/ad"), &["Expr"], &[]).is_empty());
    let manifest = "[package]\nname = \"x\"\n\n[dependencies]\nglam = \"1\"\n# a note\neframe = { version = \"1\" }\n\n[dev-dependencies]\nproptest = \"1\"\n";
    assert_eq!(
        dependencies(manifest),
        ["glam", "eframe"],
        "the manifest reader"
    );
}
