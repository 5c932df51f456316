//! Prints a sketch's strokes as JSON (the `Sketch` type: every stroke's id and points in
//! sketch space, as loaded, before any preprocessing), for measuring the shared sketches'
//! parts independently of the snapper (`tools/measure_parts.py`, see
//! `tests/shared_parts.rs`).
//!
//! ```text
//! cargo run --release --no-default-features --example dump_strokes -- SKETCH.svg > strokes.json
//! ```

use std::io::Write;
use std::process::ExitCode;

use geosnap::io::sketch_file::load_sketch;

fn main() -> ExitCode {
    let Some(path) = std::env::args_os().nth(1) else {
        eprintln!("usage: dump_strokes SKETCH");
        return ExitCode::FAILURE;
    };
    let loaded = match load_sketch(&path) {
        Ok(loaded) => loaded,
        Err(e) => {
            eprintln!("{}: {e}", path.to_string_lossy());
            return ExitCode::FAILURE;
        }
    };
    let written = serde_json::to_writer(std::io::stdout().lock(), &loaded.sketch)
        .map_err(std::io::Error::from)
        .and_then(|()| writeln!(std::io::stdout()));
    if let Err(e) = written {
        eprintln!("writing the strokes: {e}");
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
