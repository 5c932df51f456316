//! Issue 19 ("nothing wrong passes silently") at the command line: typos and wrong
//! shapes are refused in our words, outputs are checked before any work and written
//! together, and bad input paths give a clear error instead of a hang.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A fresh folder holding the built-in sample (`vase.svg`, `vase.script.json`).
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("geosnap-cli-strict-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a scratch folder");
        let made = geosnap(&["sample", &dir.to_string_lossy()]);
        assert!(made.status.success(), "{made:?}");
        Self(dir)
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// Writes a script over the sample's drawing with these steps.
    fn script(&self, name: &str, steps: &str) -> PathBuf {
        let path = self.path(name);
        let text = format!(
            r#"{{"format": "geosnap-script", "version": 1, "sketch": "vase.svg", "steps": [{steps}]}}"#
        );
        std::fs::write(&path, text).expect("script written");
        path
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn geosnap(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_geosnap"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn run(args: &[&Path]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_geosnap"));
    command.arg("run");
    for arg in args {
        command.arg(arg);
    }
    command.output().expect("the binary runs")
}

/// Runs `geosnap run` with `args`, which must fail; returns its stderr.
fn run_refused(args: &[&Path]) -> String {
    let done = run(args);
    let message = stderr(&done);
    assert!(!done.status.success(), "must fail: {message}");
    message
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Asserts that the command's stderr says `text`.
fn assert_says(output: &Output, text: &str) {
    let message = stderr(output);
    assert!(message.contains(text), "expected {text:?} in: {message}");
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// The first step of the sample script, which snaps.
fn sample_step(dir: &Scratch) -> String {
    let text = std::fs::read_to_string(dir.path("vase.script.json")).expect("the sample");
    let value: serde_json::Value = serde_json::from_str(&text).expect("json");
    value["steps"][0].to_string()
}

/// Case 4: a typo in a step is an error with the field, its position and a suggestion,
/// and nothing is run or written.
#[test]
fn a_typo_in_a_step_is_refused_before_any_work() {
    let dir = Scratch::new("typo");
    let script = dir.script(
        "typo.script.json",
        r#"{"place": "cylinder", "at": [1, 2], "raduis": 4}"#,
    );
    let out = dir.path("typo.model.json");
    let message = run_refused(&[&script, Path::new("--out"), &out]);
    assert!(
        message.contains("step 0: line 1, column ")
            && message.contains("unknown field `raduis`; did you mean `radius`?"),
        "{message}"
    );
    assert!(!out.exists(), "nothing written");
}

/// Case 4: a script of the wrong shape is refused in our words.
#[test]
fn a_script_of_the_wrong_shape_is_refused_in_our_words() {
    let dir = Scratch::new("shape");
    let script = dir.path("array.script.json");
    std::fs::write(&script, r#"["geosnap-script", 1, "vase.svg"]"#).expect("written");
    let out = dir.path("array.model.json");
    let message = run_refused(&[&script, Path::new("--out"), &out]);
    assert!(
        message.contains("a placement script must be a JSON object")
            && message.contains("array.script.json"),
        "{message}"
    );
    for internal in ["struct", "expected u64", "Envelope"] {
        assert!(!message.contains(internal), "{message}");
    }
    assert!(!out.exists(), "nothing written");
}

/// Case 4: a sketch without strokes is an error, not an empty model.
#[test]
fn a_sketch_without_strokes_is_refused() {
    let dir = Scratch::new("empty");
    std::fs::write(
        dir.path("vase.svg"),
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"></svg>"#,
    )
    .expect("written");
    let out = dir.path("empty.model.json");
    let message = run_refused(&[&dir.path("vase.script.json"), Path::new("--out"), &out]);
    assert!(message.contains("has no strokes"), "{message}");
    assert!(!out.exists(), "nothing written");
}

/// Case 4: a skipped step is a warning, and with `--strict` an error (after writing).
#[test]
fn strict_fails_when_a_step_is_skipped() {
    let dir = Scratch::new("strict");
    let steps = format!(
        r#"{}, {{"place": "sphere", "at": [-5000, -5000], "radius": 3}}"#,
        sample_step(&dir)
    );
    let script = dir.script("skip.script.json", &steps);
    let out = dir.path("skip.model.json");
    let lenient = run(&[&script, Path::new("--out"), &out]);
    assert!(lenient.status.success(), "{}", stderr(&lenient));
    assert_says(&lenient, "warning: 1 of 2 step(s) were skipped");
    std::fs::remove_file(&out).expect("written");
    let strict = run(&[&script, Path::new("--out"), &out, Path::new("--strict")]);
    assert!(!strict.status.success(), "{}", stdout(&strict));
    assert_says(&strict, "--strict: 1 step(s)");
    assert!(out.exists(), "--strict still writes the outputs");
}

/// Case 5: an output that is an input (the script, the sketch it names) is refused
/// before any work, and the inputs are untouched.
#[test]
fn outputs_that_are_inputs_are_refused() {
    let dir = Scratch::new("inputs");
    let script = dir.path("vase.script.json");
    let before = std::fs::read(&script).expect("the script");
    let done = run(&[&script, Path::new("--out"), &script]);
    assert!(!done.status.success());
    assert_says(&done, "is an input of this command");
    assert_eq!(std::fs::read(&script).expect("the script"), before);

    // The sketch named inside the script, through another spelling of its path.
    let sketch = dir.path("drawing.json");
    let native = r#"{"format": "geosnap-sketch", "version": 1, "strokes": [{"id": 0, "points": [[0, 0], [10, 10]]}]}"#;
    std::fs::write(&sketch, native).expect("written");
    let script = dir.path("native.script.json");
    std::fs::write(
        &script,
        r#"{"format": "geosnap-script", "sketch": "drawing.json", "steps": []}"#,
    )
    .expect("written");
    let other_spelling = dir.0.join(".").join("drawing.json");
    let done = run(&[&script, Path::new("--out"), &other_spelling]);
    assert_says(&done, "is an input of this command");
    assert_eq!(std::fs::read_to_string(&sketch).expect("sketch"), native);

    // The same for `solve`.
    let model = dir.path("m.model.json");
    let made = run(&[&dir.path("vase.script.json"), Path::new("--out"), &model]);
    assert!(made.status.success(), "{}", stderr(&made));
    let model_text = model.to_string_lossy();
    let done = geosnap(&["solve", &model_text, "--out", &model_text]);
    assert_says(&done, "is an input of this command");
}

/// Case 5: a missing folder or an unsupported extension of any output is found before
/// the model is written.
#[test]
fn bad_outputs_are_refused_before_anything_is_written() {
    let dir = Scratch::new("outputs");
    let script = dir.path("vase.script.json");
    let out = dir.path("vase.model.json");
    for (option, path, says) in [
        ("--overlay", dir.path("nodir/x.png"), "does not exist"),
        (
            "--gltf",
            dir.path("x.obj"),
            "--gltf takes a .glb or .gltf file",
        ),
        (
            "--overlay",
            dir.path("x.jpg"),
            "--overlay takes a .png file",
        ),
    ] {
        let done = run(&[&script, Path::new("--out"), &out, Path::new(option), &path]);
        assert!(!done.status.success(), "{option} {}", path.display());
        assert_says(&done, says);
        assert!(!out.exists(), "the model is not written");
    }
    let done = run(&[&script, Path::new("--out"), &dir.path("vase.svg.bak")]);
    assert_says(&done, "--out takes a .json file");

    // All outputs at once, when they are fine.
    let (png, glb) = (dir.path("vase.png"), dir.path("vase.glb"));
    let done = run(&[
        &script,
        Path::new("--out"),
        &out,
        Path::new("--overlay"),
        &png,
        Path::new("--gltf"),
        &glb,
    ]);
    assert!(done.status.success(), "{}", stderr(&done));
    assert!(out.exists() && png.exists() && glb.exists());
    // Case 8: the summary counts every solve, re-solves after conflicts included.
    assert!(
        stdout(&done).contains("re-solve(s) after conflicts)"),
        "{}",
        stdout(&done)
    );
    let export = geosnap(&[
        "export",
        &out.to_string_lossy(),
        "--out",
        &dir.path("x.stl").to_string_lossy(),
    ]);
    assert_says(&export, "--out takes a .glb or .gltf file");
}

/// Case 9: a script named where a sketch is expected gets a hint, and `check` decides
/// the kind by content and puts its reasons on stderr.
#[test]
fn kinds_are_decided_by_content_with_hints() {
    let dir = Scratch::new("kinds");
    let script = dir.path("outer.script.json");
    std::fs::write(
        &script,
        r#"{"format": "geosnap-script", "sketch": "vase.script.json", "steps": []}"#,
    )
    .expect("written");
    let done = run(&[&script, Path::new("--out"), &dir.path("o.model.json")]);
    assert_says(&done, "this is a placement script");

    // A script under a plain name is checked as a script.
    let plain = dir.path("plain.json");
    std::fs::copy(dir.path("vase.script.json"), &plain).expect("copied");
    let checked = geosnap(&["check", &plain.to_string_lossy()]);
    assert!(checked.status.success(), "{}", stderr(&checked));
    assert!(
        stdout(&checked).contains("ok: script with"),
        "{}",
        stdout(&checked)
    );

    // Reasons on stderr, the exit code non-zero.
    let typo = dir.script("typo.script.json", r#"{"plcae": "cone", "at": [1, 2]}"#);
    let checked = geosnap(&["check", &typo.to_string_lossy()]);
    assert!(!checked.status.success());
    assert_says(&checked, "did you mean `place`?");
    assert!(
        !stdout(&checked).contains("did you mean"),
        "{}",
        stdout(&checked)
    );
}

/// Waits for a child at most `limit`, killing it past that.
fn wait_at_most(mut child: std::process::Child, limit: Duration) -> Option<Output> {
    let start = Instant::now();
    while start.elapsed() < limit {
        if child.try_wait().expect("waits").is_some() {
            return Some(child.wait_with_output().expect("output"));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = child.kill();
    None
}

/// Case 7: a sketch path naming a device or a FIFO is a clear error, never a hang.
#[cfg(target_os = "linux")]
#[test]
fn special_files_are_refused_without_a_hang() {
    let dir = Scratch::new("special");
    let fifo = dir.path("pipe.svg");
    let made = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    for (sketch, says) in [("/dev/zero", "a device"), ("pipe.svg", "named pipe")] {
        let script = dir.path("special.script.json");
        std::fs::write(
            &script,
            format!(r#"{{"format": "geosnap-script", "sketch": "{sketch}", "steps": []}}"#),
        )
        .expect("written");
        let child = Command::new(env!("CARGO_BIN_EXE_geosnap"))
            .arg("check")
            .arg(&script)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawned");
        let done = wait_at_most(child, Duration::from_secs(30)).expect("no hang");
        assert!(!done.status.success());
        assert_says(&done, says);
    }
}

/// Case 8: the runner reports each step as soon as it is done, in order, with the
/// outcome the run returns.
#[test]
fn each_step_is_reported_as_it_ends() {
    use geosnap::core::model::{run_steps_with, SessionSettings, StepOutcome};
    use geosnap::core::solve::SolveContext;

    let dir = Scratch::new("progress");
    let script =
        geosnap::io::script::load_script(dir.path("vase.script.json")).expect("the sample");
    let sketch = geosnap::io::load_sketch(&script.sketch).expect("its drawing");
    let mut seen = Vec::new();
    let (_, outcomes) = run_steps_with(
        &sketch.sketch,
        &script.steps,
        &SessionSettings::default(),
        SolveContext::default(),
        &mut |index, outcome| seen.push((index, matches!(outcome, StepOutcome::Placed { .. }))),
    );
    let expected: Vec<(usize, bool)> = outcomes
        .iter()
        .enumerate()
        .map(|(i, o)| (i, matches!(o, StepOutcome::Placed { .. })))
        .collect();
    assert_eq!(seen, expected);
    assert_eq!(seen.len(), script.steps.len());
}

/// Issue 18: a model file's optional part `name` and `unit` are read, checked and kept
/// by `geosnap check` and `solve`; a typo in either is refused with the field meant.
#[test]
fn names_and_the_unit_are_kept_by_solve_and_typos_in_them_refused() {
    let dir = Scratch::new("names");
    let model = dir.path("m.model.json");
    let made = run(&[&dir.path("vase.script.json"), Path::new("--out"), &model]);
    assert!(made.status.success(), "{}", stderr(&made));
    let text = std::fs::read_to_string(&model).expect("the model");
    let mut value: serde_json::Value = serde_json::from_str(&text).expect("json");
    value["unit"] = "cm".into();
    value["primitives"][0]["name"] = "Vase «body» ⌀".into();
    std::fs::write(&model, value.to_string()).expect("written");
    let model_text = model.to_string_lossy();
    let checked = geosnap(&["check", &model_text]);
    assert!(checked.status.success(), "{}", stderr(&checked));

    let solved = dir.path("solved.model.json");
    let solved_text = solved.to_string_lossy();
    let done = geosnap(&["solve", &model_text, "--out", &solved_text]);
    assert!(done.status.success(), "{}", stderr(&done));
    let back: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&solved).expect("solved")).expect("json");
    assert_eq!(back["unit"], "cm", "{back}");
    assert_eq!(back["primitives"][0]["name"], "Vase «body» ⌀", "{back}");

    for (field, bad, says) in [
        ("units", serde_json::json!("cm"), "did you mean `unit`?"),
        ("unit", serde_json::json!("CM"), r#"did you mean "cm"?"#),
    ] {
        let mut wrong = value.clone();
        let object = wrong.as_object_mut().expect("an object");
        object.remove("unit");
        object.insert(field.to_owned(), bad);
        std::fs::write(&model, wrong.to_string()).expect("written");
        let checked = geosnap(&["check", &model_text]);
        assert!(!checked.status.success(), "{field} must be refused");
        assert_says(&checked, says);
    }
}
