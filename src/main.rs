//! The `geosnap` binary: a thin front to [`geosnap::cli`] and, without a command, the
//! desktop application.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Parser;
use geosnap::cli::{execute, exit_code, Command, EXIT_HELP};

/// Sketch-based 3D modelling with geosemantic snapping.
#[derive(Debug, Parser)]
#[command(
    name = "geosnap",
    version,
    about,
    args_conflicts_with_subcommands = true,
    after_help = EXIT_HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Without a command: open the desktop application on this file (a session, a
    /// sketch, an SVG drawing or a PNG/JPEG reference image), or on the built-in sample.
    file: Option<PathBuf>,
    /// Measure frame times during a simulated palette drag over this many frames, write
    /// them as JSON to `--frame-times` and quit.
    #[arg(long, value_name = "FRAMES", requires = "frame_times")]
    drag_benchmark: Option<usize>,
    /// Where `--drag-benchmark` writes its figures.
    #[arg(long, value_name = "JSON")]
    frame_times: Option<PathBuf>,
    /// Save a screenshot of the window (PNG) once the work has settled, and quit.
    #[arg(long, value_name = "PNG")]
    screenshot: Option<PathBuf>,
    /// Before showing the window, play this placement script's drops as drags (for
    /// screenshots and demos); its sketch is opened.
    #[arg(long, value_name = "SCRIPT")]
    play: Option<PathBuf>,
}

/// What the desktop application is asked to do.
struct AppArgs {
    file: Option<PathBuf>,
    drag_benchmark: Option<(usize, PathBuf)>,
    screenshot: Option<PathBuf>,
    play: Option<PathBuf>,
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    let result = match cli.command {
        Some(command) => execute(command),
        None => open_app(AppArgs {
            file: cli.file,
            drag_benchmark: cli.drag_benchmark.zip(cli.frame_times),
            screenshot: cli.screenshot,
            play: cli.play,
        }),
    };
    exit_code(result)
}

#[cfg(feature = "gui")]
fn open_app(args: AppArgs) -> Result<ExitCode> {
    geosnap::app::run(geosnap::app::AppOptions {
        file: args.file,
        autosave_dir: None,
        drag_benchmark: args.drag_benchmark,
        screenshot: args.screenshot,
        play: args.play,
    })?;
    Ok(ExitCode::SUCCESS)
}

#[cfg(not(feature = "gui"))]
fn open_app(args: AppArgs) -> Result<ExitCode> {
    let _ = (args.file, args.drag_benchmark, args.screenshot, args.play);
    anyhow::bail!(
        "this build has no desktop application (built without the `gui` feature); \
         try `geosnap run sketches/vase.script.json --out vase.model.json --overlay vase.png`, \
         `geosnap selftest`, or `geosnap --help`"
    )
}
