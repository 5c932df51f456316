//! Issue 19 at the command line: `--time-limit` ends a command at a safe point with a
//! clear message, exit status 3 and nothing written; long runs are never silent.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// A fresh folder holding the built-in sample (`vase.svg`, `vase.script.json`).
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("geosnap-cli-limits-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a scratch folder");
        let made = geosnap(&["sample".as_ref(), dir.as_os_str()]);
        assert!(made.status.success(), "{made:?}");
        Self(dir)
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// A script over the sample's drawing with its steps repeated to `count`.
    fn long_script(&self, count: usize) -> PathBuf {
        let text = std::fs::read_to_string(self.path("vase.script.json")).expect("the sample");
        let mut script: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        let steps = script["steps"].as_array().expect("steps").clone();
        script["steps"] = steps.iter().cycle().take(count).cloned().collect();
        let path = self.path(&format!("long{count}.script.json"));
        std::fs::write(&path, script.to_string()).expect("written");
        path
    }

    /// The files of the folder, sorted.
    fn listing(&self) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(&self.0)
            .expect("lists")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn geosnap(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_geosnap"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn os(path: &Path) -> &std::ffi::OsStr {
    path.as_os_str()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

const SENTINEL: &[u8] = b"an old output, to be kept byte for byte\n";

/// Asserts a spent time limit: exit status 3, the message, the outputs untouched and no
/// file left behind.
fn assert_time_limit(
    done: &Output,
    says: &str,
    outputs: &[&Path],
    dir: &Scratch,
    before: &[String],
) {
    let message = stderr(done);
    assert_eq!(done.status.code(), Some(3), "exit status 3: {message}");
    assert!(
        message.contains("time limit of ") && message.contains(": nothing written"),
        "{message}"
    );
    assert!(message.contains(says), "expected {says:?} in: {message}");
    for output in outputs {
        assert_eq!(
            std::fs::read(output).expect("the old output"),
            SENTINEL,
            "{} untouched",
            output.display()
        );
    }
    assert_eq!(dir.listing(), before, "no file left behind");
}

#[test]
fn run_stops_between_steps_when_its_time_is_spent() {
    let dir = Scratch::new("run");
    let script = dir.long_script(300);
    let (out, png) = (dir.path("long.model.json"), dir.path("long.png"));
    std::fs::write(&out, SENTINEL).expect("written");
    std::fs::write(&png, SENTINEL).expect("written");
    let before = dir.listing();
    let started = Instant::now();
    let done = geosnap(&[
        "run".as_ref(),
        os(&script),
        "--out".as_ref(),
        os(&out),
        "--overlay".as_ref(),
        os(&png),
        "--time-limit".as_ref(),
        "0.5".as_ref(),
    ]);
    let took = started.elapsed();
    assert_time_limit(
        &done,
        "time limit of 0.5 s reached after ",
        &[&out, &png],
        &dir,
        &before,
    );
    assert!(
        stderr(&done).contains(" of 300 steps of ")
            && stderr(&done).contains("long300.script.json"),
        "{}",
        stderr(&done)
    );
    // Stopped at the next safe point, long before 300 steps were done.
    assert!(took < Duration::from_secs(30), "stopped after {took:?}");

    // A generous limit changes nothing.
    let short = dir.long_script(2);
    let done = geosnap(&[
        "run".as_ref(),
        os(&short),
        "--out".as_ref(),
        os(&out),
        "--time-limit".as_ref(),
        "600".as_ref(),
    ]);
    assert!(done.status.success(), "{}", stderr(&done));
    assert_ne!(std::fs::read(&out).expect("written"), SENTINEL);
}

/// A model of the sample, made by `run`.
fn sample_model(dir: &Scratch) -> PathBuf {
    let model = dir.path("vase.model.json");
    let done = geosnap(&[
        "run".as_ref(),
        os(&dir.path("vase.script.json")),
        "--out".as_ref(),
        os(&model),
    ]);
    assert!(done.status.success(), "{}", stderr(&done));
    model
}

#[test]
fn solve_export_and_check_stop_when_their_time_is_spent() {
    let dir = Scratch::new("model");
    let model = sample_model(&dir);
    let (out, glb) = (dir.path("solved.model.json"), dir.path("vase.glb"));
    std::fs::write(&out, SENTINEL).expect("written");
    std::fs::write(&glb, SENTINEL).expect("written");
    let before = dir.listing();
    let tiny = "0.000001".as_ref();
    let limit = "--time-limit".as_ref();

    let done = geosnap(&[
        "solve".as_ref(),
        os(&model),
        "--out".as_ref(),
        os(&out),
        limit,
        tiny,
    ]);
    assert_time_limit(&done, "vase.model.json", &[&out, &glb], &dir, &before);

    let done = geosnap(&[
        "export".as_ref(),
        os(&model),
        "--out".as_ref(),
        os(&glb),
        limit,
        tiny,
    ]);
    assert_time_limit(&done, "vase.model.json", &[&out, &glb], &dir, &before);

    let done = geosnap(&["check".as_ref(), os(&model), limit, tiny]);
    assert_time_limit(&done, "1 file(s)", &[&out, &glb], &dir, &before);

    // With time enough, each does its work.
    let plenty = "600".as_ref();
    let done = geosnap(&[
        "solve".as_ref(),
        os(&model),
        "--out".as_ref(),
        os(&out),
        limit,
        plenty,
    ]);
    assert!(done.status.success(), "{}", stderr(&done));
    let done = geosnap(&[
        "export".as_ref(),
        os(&model),
        "--out".as_ref(),
        os(&glb),
        limit,
        plenty,
    ]);
    assert!(done.status.success(), "{}", stderr(&done));
}

#[test]
fn a_bad_time_limit_is_a_usage_error_and_help_documents_the_exit_status() {
    for bad in ["0", "-1", "NaN", "soon"] {
        let done = geosnap(&[
            "check".as_ref(),
            "x.svg".as_ref(),
            "--time-limit".as_ref(),
            bad.as_ref(),
        ]);
        assert_eq!(done.status.code(), Some(2), "{bad}: {}", stderr(&done));
        assert!(stderr(&done).contains("--time-limit"), "{}", stderr(&done));
    }
    for command in ["run", "solve", "export", "check"] {
        let help = geosnap(&[command.as_ref(), "--help".as_ref()]);
        let text = String::from_utf8_lossy(&help.stdout);
        assert!(
            text.contains("--time-limit <SECONDS>")
                && text.contains("3 when `--time-limit` is spent"),
            "{command} --help: {text}"
        );
    }
}

/// The number in "N global solve(s)" of a run's summary.
fn global_solves(output: &Output) -> usize {
    let text = String::from_utf8_lossy(&output.stdout);
    let line = text
        .lines()
        .find(|l| l.contains(" global solve(s) ("))
        .unwrap_or_else(|| panic!("a summary line in: {text}"));
    line.split_whitespace()
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("a count in {line}"))
}

/// Case 8: the summary counts every solve, the one after accepting suggestions too.
#[test]
fn the_summary_counts_the_solve_after_accepting_suggestions() {
    // The stand of `sketches/` infers a suggestion (copies of one part relate to
    // nothing, so a repeated sample would not).
    let dir = Scratch::new("accept");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("sketches/stand.script.json");
    let out = dir.path("accept.model.json");
    let run = |accept: bool| {
        let mut args = vec!["run".as_ref(), os(&script), "--out".as_ref(), os(&out)];
        if accept {
            args.push("--accept-suggestions".as_ref());
        }
        let done = geosnap(&args);
        assert!(done.status.success(), "{}", stderr(&done));
        done
    };
    let (plain, accepted) = (run(false), run(true));
    assert!(
        String::from_utf8_lossy(&accepted.stdout).contains("accepted "),
        "the stand has a suggestion to accept: {}",
        String::from_utf8_lossy(&accepted.stdout)
    );
    assert!(
        global_solves(&accepted) > global_solves(&plain),
        "{} vs {}",
        global_solves(&accepted),
        global_solves(&plain)
    );
}

/// Case 8: on a terminal, `run` says what it does before the first step ends, and each
/// step as it ends (through `script`, which gives the command a terminal).
#[cfg(target_os = "linux")]
#[test]
fn run_shows_progress_on_a_terminal() {
    let available = Command::new("script").arg("--version").output();
    if !available.is_ok_and(|o| o.status.success()) {
        eprintln!("`script` is not installed: skipped");
        return;
    }
    let dir = Scratch::new("terminal");
    let script = dir.long_script(3);
    let line = format!(
        "{} run {} --out {}",
        env!("CARGO_BIN_EXE_geosnap"),
        script.display(),
        dir.path("t.model.json").display()
    );
    let done = Command::new("script")
        .args(["-qec", &line, "/dev/null"])
        .output()
        .expect("script runs");
    let text = String::from_utf8_lossy(&done.stdout);
    assert!(done.status.success(), "{text}");
    for expected in ["running 3 step(s)…", "[1/3] step 0: ", "[3/3] step 2: "] {
        assert!(text.contains(expected), "expected {expected:?} in: {text}");
    }
}

/// Acceptance of issue 19: `geosnap run` on a 300-step script shows progress from its
/// first second. On a terminal (through `script`), the run's first line comes within a
/// second of the command's start, and the steps are reported one by one as they end,
/// long before the run would (its time limit cuts it short after a few steps).
#[cfg(target_os = "linux")]
#[test]
fn a_300_step_run_shows_progress_from_its_first_second() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;

    let available = Command::new("script").arg("--version").output();
    if !available.is_ok_and(|o| o.status.success()) {
        eprintln!("`script` is not installed: skipped");
        return;
    }
    let dir = Scratch::new("first-second");
    let script = dir.long_script(300);
    let line = format!(
        "{} run {} --out {} --time-limit 3",
        env!("CARGO_BIN_EXE_geosnap"),
        script.display(),
        dir.path("long.model.json").display()
    );
    let started = Instant::now();
    let mut child = Command::new("script")
        .args(["-qec", &line, "/dev/null"])
        .stdout(Stdio::piped())
        .spawn()
        .expect("script runs");
    let output = child.stdout.take().expect("piped");
    // Each line of the terminal with when it came.
    let lines: Vec<(Duration, String)> = BufReader::new(output)
        .lines()
        .map_while(Result::ok)
        .map(|l| (started.elapsed(), l))
        .collect();
    let ended = started.elapsed();
    child.wait().expect("script ends");
    let shown = |what: &str| {
        lines
            .iter()
            .find(|(_, l)| l.contains(what))
            .map(|(t, _)| *t)
    };
    let all = || {
        lines
            .iter()
            .map(|(t, l)| format!("{:6.0} ms  {}", t.as_secs_f64() * 1e3, l.trim_end()))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let first = shown("running 300 step(s)…").unwrap_or_else(|| panic!("no progress: {}", all()));
    assert!(
        first < Duration::from_secs(1),
        "first shown at {first:?}:\n{}",
        all()
    );
    let steps: Vec<Duration> = lines
        .iter()
        .filter(|(_, l)| l.contains("/300] step "))
        .map(|(t, _)| *t)
        .collect();
    assert!(steps.len() >= 2, "steps shown:\n{}", all());
    assert!(
        steps.windows(2).all(|w| w[0] <= w[1]) && steps[0] + Duration::from_millis(200) < ended,
        "each step as it ends:\n{}",
        all()
    );
    assert!(
        lines
            .iter()
            .any(|(_, l)| l.contains("time limit of 3 s reached")),
        "{}",
        all()
    );
}
