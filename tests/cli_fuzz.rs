//! Issue 19's fuzz acceptance, at the command line and in-process: `check`, `run`,
//! `solve` and `export` ([`geosnap::cli::execute`], as the binary runs them) on generated
//! files of every input kind the commands read (SVG drawings, native sketch files,
//! placement scripts, model files and session files).
//!
//! Each kind gets mutated valid files (byte flips, cuts, insertions, hostile tokens;
//! and for JSON, fields deleted, renamed or retyped, huge or NaN numbers, deep nesting)
//! and grammar-generated ones. Every command of every case must:
//!
//! - not panic (a panic fails the case and proptest shrinks it);
//! - on failure, say the input file's name in its message, keep that message bounded,
//!   leave every pre-existing output byte for byte as it was, and leave no file behind.
//!
//! The number of cases per kind is `GEOSNAP_FUZZ_CASES` (default: 1,000 in the build
//! without the `gui` feature, which CI tests with `cargo test --no-default-features`,
//! about half a minute on a 2-core machine; 100 in the default build, which CI tests
//! too, so that the two runs together stay within budget). Each test asserts that this many cases ran. A longer run:
//! `GEOSNAP_FUZZ_CASES=50000 cargo test --release --no-default-features --test cli_fuzz`.

use std::cell::Cell;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use serde_json::{json, Value};

/// Cases per input kind when `GEOSNAP_FUZZ_CASES` is not set.
const DEFAULT_CASES: u32 = if cfg!(feature = "gui") { 100 } else { 1000 };

/// The longest failure message accepted (messages are bounded; a 100k-element array is
/// never echoed whole).
const MAX_MESSAGE: usize = 4000;

/// The cases per kind: `GEOSNAP_FUZZ_CASES`, or [`DEFAULT_CASES`].
fn cases() -> u32 {
    match std::env::var("GEOSNAP_FUZZ_CASES") {
        Ok(text) => text
            .trim()
            .parse()
            .unwrap_or_else(|_| panic!("GEOSNAP_FUZZ_CASES={text:?} is not a count")),
        Err(_) => DEFAULT_CASES,
    }
}

fn sketches() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("sketches")
}

/// A scratch folder with the fixtures of one kind's test.
struct Scratch(PathBuf);

impl Scratch {
    fn new(kind: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("geosnap-cli-fuzz-{kind}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a scratch folder");
        Self(dir)
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    fn write(&self, name: &str, bytes: &[u8]) -> PathBuf {
        let path = self.path(name);
        std::fs::write(&path, bytes).expect("a fixture is written");
        path
    }

    /// The names of the files in the folder.
    fn listing(&self) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(&self.0)
            .expect("the scratch folder lists")
            .map(|e| {
                e.expect("an entry")
                    .file_name()
                    .to_string_lossy()
                    .into_owned()
            })
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

/// The drawing every fixture is built on: two cylinders, so that runs are cheap.
fn drawing() -> Vec<u8> {
    std::fs::read(sketches().join("cylinders.svg")).expect("the cylinders drawing")
}

/// A script over `sketch` with the first `steps` steps of the cylinders script.
fn script_over(sketch: &str, steps: usize) -> Value {
    let text = std::fs::read_to_string(sketches().join("cylinders.script.json"))
        .expect("the cylinders script");
    let mut script: Value = serde_json::from_str(&text).expect("the script is JSON");
    script["sketch"] = json!(sketch);
    if let Some(all) = script["steps"].as_array_mut() {
        all.truncate(steps);
    }
    script
}

fn to_bytes(value: &Value) -> Vec<u8> {
    serde_json::to_vec_pretty(value).expect("JSON encodes")
}

/// Runs a command line in-process.
fn execute(args: &[&Path]) -> anyhow::Result<ExitCode> {
    let mut line = vec![Path::new("geosnap")];
    line.extend(args);
    let command = geosnap::cli::parse(line).expect("the harness's command lines parse");
    geosnap::cli::execute(command)
}

/// The outputs of a case's commands: pre-existing files with known bytes.
struct Outputs<'a> {
    dir: &'a Scratch,
    names: &'static [&'static str],
}

impl Outputs<'_> {
    fn sentinel(name: &str) -> Vec<u8> {
        format!("sentinel bytes of {name}, never to be changed by a failing command\n").into_bytes()
    }

    /// Puts every output back as its sentinel.
    fn reset(&self) {
        for name in self.names {
            self.dir.write(name, &Self::sentinel(name));
        }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path(name)
    }
}

/// Runs one command on a case and checks what issue 19 asks of it. `input` is the
/// generated file (its name must appear in a failure's message).
fn command_holds(outputs: &Outputs<'_>, input: &Path, args: &[&Path]) -> Result<(), TestCaseError> {
    outputs.reset();
    let before = outputs.dir.listing();
    let result = execute(args);
    let name = input
        .file_name()
        .expect("a file name")
        .to_string_lossy()
        .into_owned();
    let shown = || {
        args.iter()
            .map(|a| a.file_name().unwrap_or(a.as_os_str()).to_string_lossy())
            .collect::<Vec<_>>()
            .join(" ")
    };
    match result {
        Ok(_) => {}
        Err(error) => {
            let message = format!("{error:#}");
            prop_assert!(
                message.contains(&name),
                "`{}` failed without naming {name}: {message}",
                shown()
            );
            prop_assert!(
                message.len() <= MAX_MESSAGE,
                "`{}`: a message of {} bytes: {}…",
                shown(),
                message.len(),
                message.chars().take(300).collect::<String>()
            );
            for output in outputs.names {
                let now = std::fs::read(outputs.path(output)).unwrap_or_default();
                prop_assert!(
                    now == Outputs::sentinel(output),
                    "`{}` failed ({message}) but changed {output}",
                    shown()
                );
            }
            let after = outputs.dir.listing();
            prop_assert_eq!(&after, &before, "`{}` left files behind", shown());
        }
    }
    Ok(())
}

/// Runs `cases()` generated cases of one kind through `case`, and asserts that they all
/// ran.
fn fuzz<S: Strategy>(kind: &str, strategy: S, case: impl Fn(S::Value) -> Result<(), TestCaseError>)
where
    S::Value: std::fmt::Debug,
{
    let wanted = cases();
    let mut runner = TestRunner::new(Config {
        cases: wanted,
        failure_persistence: None,
        max_shrink_iters: 256,
        ..Config::default()
    });
    let ran = Cell::new(0_u32);
    let started = std::time::Instant::now();
    let result = runner.run(&strategy, |value| {
        ran.set(ran.get() + 1);
        case(value)
    });
    if let Err(failure) = result {
        panic!("{kind}: {failure}");
    }
    eprintln!(
        "{kind}: {} cases in {:.1} s",
        ran.get(),
        started.elapsed().as_secs_f64()
    );
    assert_eq!(ran.get(), wanted, "{kind}: every case ran");
}

// ---------------------------------------------------------------------------------
// Mutations of bytes, any kind.

/// Tokens a hostile or sloppy file may hold.
const HOSTILE: &[&str] = &[
    "NaN",
    "nan",
    "Infinity",
    "-Infinity",
    "inf",
    "1e308",
    "-1e308",
    "1e309",
    "1e-400",
    "3.4028235e38",
    "-0",
    "18446744073709551616",
    "-9223372036854775809",
    "\"",
    "\\",
    "{",
    "}",
    "[",
    "]",
    ",",
    ":",
    "null",
    "<",
    ">",
    "&amp;",
    "&bogus;",
    "]]>",
    "<!--",
    "\u{0}",
    "\u{feff}",
    "\u{fffd}",
    "é",
];

/// One edit of a byte string.
#[derive(Clone, Debug)]
enum ByteEdit {
    /// Sets the byte at a fraction of the length.
    Flip(f64, u8),
    /// Cuts the file at a fraction of its length.
    Truncate(f64),
    /// Inserts bytes at a fraction of the length.
    Insert(f64, Vec<u8>),
    /// Deletes a stretch: from a fraction, this many bytes.
    Delete(f64, usize),
    /// Repeats a stretch in place.
    Duplicate(f64, usize),
    /// Inserts a hostile token.
    Token(f64, &'static str),
}

fn byte_edit() -> impl Strategy<Value = ByteEdit> {
    let at = 0.0f64..1.0;
    prop_oneof![
        4 => (at.clone(), any::<u8>()).prop_map(|(a, b)| ByteEdit::Flip(a, b)),
        2 => at.clone().prop_map(ByteEdit::Truncate),
        2 => (at.clone(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(a, b)| ByteEdit::Insert(a, b)),
        2 => (at.clone(), 1usize..64).prop_map(|(a, n)| ByteEdit::Delete(a, n)),
        1 => (at.clone(), 1usize..200).prop_map(|(a, n)| ByteEdit::Duplicate(a, n)),
        3 => (at, prop::sample::select(HOSTILE)).prop_map(|(a, t)| ByteEdit::Token(a, t)),
    ]
}

fn apply_byte_edits(mut data: Vec<u8>, edits: &[ByteEdit]) -> Vec<u8> {
    let place = |len: usize, at: f64| ((len as f64) * at) as usize;
    for edit in edits {
        let len = data.len();
        match edit {
            ByteEdit::Flip(at, byte) => {
                if let Some(b) = data.get_mut(place(len, *at)) {
                    *b = *byte;
                }
            }
            ByteEdit::Truncate(at) => data.truncate(place(len, *at)),
            ByteEdit::Insert(at, bytes) => {
                let i = place(len, *at);
                data.splice(i..i, bytes.iter().copied());
            }
            ByteEdit::Delete(at, n) => {
                let i = place(len, *at);
                data.drain(i..(i + n).min(len));
            }
            ByteEdit::Duplicate(at, n) => {
                let i = place(len, *at);
                let stretch = data[i..(i + n).min(len)].to_vec();
                data.splice(i..i, stretch);
            }
            ByteEdit::Token(at, token) => {
                let i = place(len, *at);
                data.splice(i..i, token.bytes());
            }
        }
    }
    data
}

/// A valid file with 1 to 4 byte edits.
fn bytes_mutated(base: Vec<u8>) -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(byte_edit(), 1..5)
        .prop_map(move |edits| apply_byte_edits(base.clone(), &edits))
}

// ---------------------------------------------------------------------------------
// Mutations of JSON values.

/// One structural edit of a JSON document, at the node a path of choices leads to.
#[derive(Clone, Debug)]
enum JsonEdit {
    /// Deletes a field (or an array element).
    Delete,
    /// Renames a field with a typo.
    Rename(Typo),
    /// Replaces the value.
    Replace(Value),
    /// Replaces the value by a number that JSON text can hold but `f64` cannot, or
    /// NaN spelt out: written as text after encoding.
    Raw(&'static str),
    /// Wraps the value in this many arrays.
    Nest(usize),
    /// Repeats an array's first element this many times.
    Grow(usize),
}

/// A typo in a field name.
#[derive(Clone, Copy, Debug)]
enum Typo {
    Swap,
    Drop,
    Double,
    Upper,
}

fn typo(name: &str, typo: Typo) -> String {
    let mut chars: Vec<char> = name.chars().collect();
    match typo {
        Typo::Swap if chars.len() >= 2 => chars.swap(0, 1),
        Typo::Drop if !chars.is_empty() => {
            chars.pop();
        }
        Typo::Upper => return name.to_uppercase() + "_",
        _ => chars.push('x'),
    }
    chars.into_iter().collect()
}

/// Any JSON value, small.
fn any_json() -> impl Strategy<Value = Value> {
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(|v| json!(v)),
        any::<f64>().prop_map(|v| json!(v)),
        prop::sample::select(vec![
            "",
            "x",
            "cylinder",
            "cone",
            "sphere",
            "cuboid",
            "hard",
            "off",
            "parallel",
            "geosnap-model",
            "geosnap-script",
            "geosnap-sketch",
            "geosnap-session",
            "top",
            "axis",
            "../../etc/passwd",
            "/dev/zero",
            "nodir/x.svg",
        ])
        .prop_map(|s| json!(s)),
    ];
    leaf.prop_recursive(3, 24, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4).prop_map(Value::Array),
            prop::collection::btree_map("[a-z_]{1,8}", inner, 0..4)
                .prop_map(|m| Value::Object(m.into_iter().collect())),
        ]
    })
}

/// Structural edits; `grow` is how many copies an array may gain.
fn json_edit(grow: std::ops::Range<usize>) -> impl Strategy<Value = JsonEdit> {
    prop_oneof![
        3 => Just(JsonEdit::Delete),
        3 => prop::sample::select(vec![Typo::Swap, Typo::Drop, Typo::Double, Typo::Upper])
            .prop_map(JsonEdit::Rename),
        4 => any_json().prop_map(JsonEdit::Replace),
        2 => prop::sample::select(vec![
            "1e308", "-1e308", "1e309", "-1e999", "NaN", "Infinity", "5e-324", "1e-400",
            "18446744073709551616", "-1", "0", "4294967296", "1.5",
        ])
        .prop_map(JsonEdit::Raw),
        1 => prop_oneof![1usize..40, 100usize..3000].prop_map(JsonEdit::Nest),
        1 => prop_oneof![1usize..4, grow].prop_map(JsonEdit::Grow),
    ]
}

/// The placeholder a [`JsonEdit::Raw`] leaves in the value, replaced in the text.
const RAW_MARK: &str = "@@raw@@";

/// Applies `edit` at the node `choices` lead to (each choice picks a child, modulo
/// their count, until a leaf or the choices run out).
fn apply_json_edit(value: &mut Value, choices: &[usize], edit: &JsonEdit) {
    let (first, rest) = match choices.split_first() {
        Some((first, rest)) if is_container_with_children(value) => (*first, rest),
        _ => {
            edit_here(value, edit);
            return;
        }
    };
    match value {
        Value::Object(map) => {
            let key = map
                .keys()
                .nth(first % map.len())
                .cloned()
                .unwrap_or_default();
            let descend = !rest.is_empty() && map.get(&key).is_some_and(is_container_with_children);
            if descend {
                if let Some(child) = map.get_mut(&key) {
                    apply_json_edit(child, rest, edit);
                }
                return;
            }
            match edit {
                JsonEdit::Delete => {
                    map.remove(&key);
                }
                JsonEdit::Rename(t) => {
                    if let Some(child) = map.remove(&key) {
                        map.insert(typo(&key, *t), child);
                    }
                }
                _ => {
                    if let Some(child) = map.get_mut(&key) {
                        edit_here(child, edit);
                    }
                }
            }
        }
        Value::Array(items) => {
            let i = first % items.len();
            if matches!(edit, JsonEdit::Delete) && rest.is_empty() {
                items.remove(i);
            } else if let Some(child) = items.get_mut(i) {
                apply_json_edit(child, rest, edit);
            }
        }
        _ => edit_here(value, edit),
    }
}

fn is_container_with_children(value: &Value) -> bool {
    match value {
        Value::Object(map) => !map.is_empty(),
        Value::Array(items) => !items.is_empty(),
        _ => false,
    }
}

fn edit_here(value: &mut Value, edit: &JsonEdit) {
    match edit {
        JsonEdit::Delete => *value = Value::Null,
        JsonEdit::Rename(_) => {
            if let Value::Object(map) = value {
                map.insert("unknwon_field".to_owned(), json!(1));
            }
        }
        JsonEdit::Replace(new) => *value = new.clone(),
        JsonEdit::Raw(_) => *value = json!(RAW_MARK),
        JsonEdit::Nest(depth) => {
            let mut nested = value.take();
            for _ in 0..*depth {
                nested = Value::Array(vec![nested]);
            }
            *value = nested;
        }
        JsonEdit::Grow(count) => match value {
            Value::Array(items) if !items.is_empty() => {
                let first = items[0].clone();
                let copies = (*count).min(copies_within_budget(&first));
                items.extend(std::iter::repeat_n(first, copies));
            }
            other => {
                let copies = (*count).min(2000).min(copies_within_budget(other));
                *other = Value::Array(vec![other.take(); copies]);
            }
        },
    }
}

/// The most bytes one [`JsonEdit::Grow`] may add. Two grow edits compose (a stroke's
/// points grown 20,000 times, then the strokes grown 20,000 times from that stroke), and
/// without a budget the file itself took gigabytes and the test run was killed for
/// memory. 16 MiB is large for every reader and well under [`MAX_INPUT_BYTES`].
///
/// [`MAX_INPUT_BYTES`]: geosnap::io::input::MAX_INPUT_BYTES
const GROW_BUDGET_BYTES: usize = 16 << 20;

/// How many copies of `element` fit in [`GROW_BUDGET_BYTES`] (at least one).
fn copies_within_budget(element: &Value) -> usize {
    let size = serde_json::to_vec(element).map_or(1, |bytes| bytes.len().max(1));
    (GROW_BUDGET_BYTES / size).max(1)
}

/// Encodes a value, writing any [`JsonEdit::Raw`] token in place of its mark.
fn encode_with_raw(value: &Value, edits: &[(Vec<usize>, JsonEdit)]) -> Vec<u8> {
    // Deep nesting goes past serde_json's recursion limit only when reading; writing is
    // fine at any depth.
    let mut text = serde_json::to_string(value).expect("JSON encodes");
    for (_, edit) in edits {
        if let JsonEdit::Raw(token) = edit {
            text = text.replacen(&format!("\"{RAW_MARK}\""), token, 1);
        }
    }
    text.into_bytes()
}

/// A valid JSON file with 1 to 3 structural edits.
fn json_mutated(base: Value, grow: std::ops::Range<usize>) -> impl Strategy<Value = Vec<u8>> {
    let edit = (prop::collection::vec(any::<usize>(), 0..6), json_edit(grow));
    prop::collection::vec(edit, 1..4).prop_map(move |edits| {
        on_a_deep_stack(|| {
            let mut value = base.clone();
            for (choices, edit) in &edits {
                apply_json_edit(&mut value, choices, edit);
            }
            encode_with_raw(&value, &edits)
        })
    })
}

/// The stack [`on_a_deep_stack`] gives: room for values nested [`JsonEdit::Nest`]'s
/// 3,000 levels deep at any optimization level, with a wide margin.
const DEEP_STACK_BYTES: usize = 256 << 20;

/// Runs `work` on a thread of its own with [`DEEP_STACK_BYTES`] of stack. A nesting edit
/// makes a value thousands of levels deep, and encoding, measuring and dropping it
/// recurse once per level (serde_json); how many levels a test thread's 2 MiB hold
/// depends on how the dependencies were optimized (they overflowed it with serde_json at
/// `opt-level = 1`). The programs under test read such files with serde_json's recursion
/// limit, so only the test's own making of them needs the room.
fn on_a_deep_stack<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    std::thread::scope(|scope| {
        let worker = std::thread::Builder::new()
            .name("deep-json".to_owned())
            .stack_size(DEEP_STACK_BYTES)
            .spawn_scoped(scope, work)
            .expect("a thread for the deep values");
        worker
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    })
}

/// Arrays grown by up to 20,000 copies (or a few): for readers.
const GROW_LARGE: std::ops::Range<usize> = 1000..20_000;

/// Arrays grown by a few copies only: for scripts, whose steps `run` does one by one.
const GROW_SMALL: std::ops::Range<usize> = 1..4;

/// Any mutation of a valid JSON file: structural, byte-level or both.
fn json_file(base: Value, grow: std::ops::Range<usize>) -> impl Strategy<Value = Vec<u8>> {
    let bytes = to_bytes(&base);
    prop_oneof![
        4 => json_mutated(base.clone(), grow.clone()),
        3 => bytes_mutated(bytes),
        1 => json_mutated(base, grow).prop_flat_map(bytes_mutated),
    ]
}

/// JSON from a grammar: objects with the kind's own keys (and near misses), values of
/// every type, `format` and `version` mostly right.
fn json_grammar(
    format: &'static str,
    keys: &'static [&'static str],
) -> impl Strategy<Value = Vec<u8>> {
    let value = prop_oneof![
        3 => any_json(),
        1 => prop::collection::vec(prop_oneof![(-2000.0f64..2000.0).prop_map(|v| json!(v)), any_json()], 0..5)
            .prop_map(Value::Array),
    ];
    let member = (prop::sample::select(keys), value.clone());
    let record = prop::collection::btree_map(prop::sample::select(keys), value, 0..6)
        .prop_map(|m| Value::Object(m.into_iter().map(|(k, v)| (k.to_owned(), v)).collect()));
    (
        prop::sample::select(vec![format, format, format, "geosnap-other", ""]),
        prop::sample::select(vec![
            json!(1),
            json!(1),
            json!(1),
            json!(2),
            json!("1"),
            json!(-1),
            Value::Null,
        ]),
        prop::collection::vec(member, 0..8),
        prop::collection::vec(record, 0..4),
    )
        .prop_map(|(format, version, members, records)| {
            let mut object: BTreeMap<String, Value> = BTreeMap::new();
            object.insert("format".to_owned(), json!(format));
            object.insert("version".to_owned(), version);
            for (key, value) in members {
                object.insert(key.to_owned(), value);
            }
            if !records.is_empty() {
                object.insert(keys[0].to_owned(), Value::Array(records));
            }
            to_bytes(&Value::Object(object.into_iter().collect()))
        })
}

// ---------------------------------------------------------------------------------
// SVG: mutations and a grammar.

/// Numbers for SVG attributes, plausible and hostile.
fn svg_number() -> impl Strategy<Value = String> {
    prop_oneof![
        6 => (-100.0f64..1300.0).prop_map(|v| format!("{v:.1}")),
        1 => prop::sample::select(vec![
            "NaN", "inf", "-inf", "1e39", "3.4028235e38", "-3.4e38", "1e308", "1e-320", "0",
            "-0", "1e", ".", "--5", "1.2.3", "99999999999999999999999", "",
        ])
        .prop_map(str::to_owned),
    ]
}

/// A valid drawing with its attribute values replaced, elements nested deeply or
/// repeated.
fn svg_mutated(base: Vec<u8>) -> impl Strategy<Value = Vec<u8>> {
    let text = String::from_utf8(base.clone()).expect("the drawing is UTF-8");
    let hostile_values = (any::<usize>(), svg_number()).prop_map({
        let text = text.clone();
        move |(pick, number)| {
            let spots: Vec<usize> = text.match_indices("=\"").map(|(i, _)| i + 2).collect();
            let start = spots[pick % spots.len()];
            let end = start + text[start..].find('"').unwrap_or(0);
            let mut out = text.clone();
            out.replace_range(start..end, &number);
            out.into_bytes()
        }
    });
    let nested = prop_oneof![1usize..50, 200usize..5000].prop_map({
        let text = text.clone();
        move |depth| {
            let body_start = text.find("<path").unwrap_or(text.len());
            let body_end = text.rfind("</svg>").unwrap_or(text.len());
            let mut out = text[..body_start].to_owned();
            out.push_str(&"<g transform=\"scale(1.0001)\">".repeat(depth));
            out.push_str(&text[body_start..body_end]);
            out.push_str(&"</g>".repeat(depth));
            out.push_str(&text[body_end..]);
            out.into_bytes()
        }
    });
    let repeated = (1usize..300).prop_map(move |times| {
        let start = text.find("<path").unwrap_or(0);
        let end = text[start..]
            .find("/>")
            .map_or(text.len(), |e| start + e + 2);
        let mut out = text.clone();
        out.insert_str(end, &text[start..end].repeat(times));
        out.into_bytes()
    });
    prop_oneof![
        4 => bytes_mutated(base),
        3 => hostile_values,
        1 => nested,
        1 => repeated,
    ]
}

/// A drawing from a grammar: shapes, paths and groups with transforms.
fn svg_grammar() -> impl Strategy<Value = Vec<u8>> {
    let n = svg_number;
    let command = prop::sample::select(vec![
        ("M", 2),
        ("L", 2),
        ("l", 2),
        ("H", 1),
        ("v", 1),
        ("C", 6),
        ("Q", 4),
        ("A", 7),
        ("Z", 0),
        ("X", 2),
    ]);
    let path = prop::collection::vec((command, prop::collection::vec(n(), 7)), 0..12).prop_map(
        |segments| {
            let mut d = String::from("M 100 100");
            for ((c, arity), numbers) in segments {
                let _ = write!(d, " {c} {}", numbers[..arity].join(","));
            }
            format!("<path fill=\"none\" stroke=\"black\" d=\"{d}\"/>")
        },
    );
    let shape = prop_oneof![
        3 => path,
        1 => (n(), n(), n(), n()).prop_map(|(x, y, w, h)| format!("<rect x=\"{x}\" y=\"{y}\" width=\"{w}\" height=\"{h}\" stroke=\"black\" fill=\"none\"/>")),
        1 => (n(), n(), n()).prop_map(|(x, y, r)| format!("<circle cx=\"{x}\" cy=\"{y}\" r=\"{r}\" stroke=\"black\"/>")),
        1 => (n(), n(), n(), n()).prop_map(|(a, b, c, d)| format!("<line x1=\"{a}\" y1=\"{b}\" x2=\"{c}\" y2=\"{d}\" stroke=\"black\"/>")),
        1 => prop::collection::vec(n(), 0..9).prop_map(|p| format!("<polyline points=\"{}\" stroke=\"black\" fill=\"none\"/>", p.join(" "))),
        1 => Just("<text x=\"1\" y=\"1\">hi</text>".to_owned()),
    ];
    let transform = prop_oneof![
        Just(String::new()),
        (n(), n()).prop_map(|(a, b)| format!(" transform=\"translate({a} {b})\"")),
        n().prop_map(|a| format!(" transform=\"scale({a})\"")),
        (n(), n(), n(), n(), n(), n()).prop_map(|(a, b, c, d, e, f)| format!(
            " transform=\"matrix({a} {b} {c} {d} {e} {f})\""
        )),
    ];
    let tree = shape.prop_recursive(3, 24, 5, move |inner| {
        (transform.clone(), prop::collection::vec(inner, 0..5))
            .prop_map(|(t, children)| format!("<g{t}>{}</g>", children.concat()))
    });
    (
        prop::option::of((n(), n(), n(), n())),
        prop::option::of(n()),
        prop::collection::vec(tree, 0..6),
    )
        .prop_map(|(view_box, width, children)| {
            let mut out = String::from("<svg xmlns=\"http://www.w3.org/2000/svg\"");
            if let Some((a, b, c, d)) = view_box {
                let _ = write!(out, " viewBox=\"{a} {b} {c} {d}\"");
            }
            if let Some(w) = width {
                let _ = write!(out, " width=\"{w}\"");
            }
            out.push('>');
            out.push_str(&children.concat());
            out.push_str("</svg>");
            out.into_bytes()
        })
}

// ---------------------------------------------------------------------------------
// The kinds.

/// The budget of each `run`: far more than a case needs (milliseconds); a case that
/// needs more (a script grown to thousands of steps by a byte edit) ends through the
/// time limit, which must name the script and leave the outputs untouched too.
const RUN_TIME_LIMIT: &str = "2";

/// Outputs of `run`: the model and its overlay.
const RUN_OUTPUTS: &[&str] = &["out.model.json", "out.png"];

/// A drawing case: `check` it, and `run` a one-step script over it with an overlay.
fn drawing_case(dir: &Scratch, name: &str, data: &[u8]) -> Result<(), TestCaseError> {
    let input = dir.write(name, data);
    let outputs = Outputs {
        dir,
        names: RUN_OUTPUTS,
    };
    command_holds(&outputs, &input, &[Path::new("check"), &input])?;
    let script = dir.path("over.script.json");
    command_holds(
        &outputs,
        &input,
        &[
            Path::new("run"),
            &script,
            Path::new("--out"),
            &outputs.path("out.model.json"),
            Path::new("--overlay"),
            &outputs.path("out.png"),
            Path::new("--time-limit"),
            Path::new(RUN_TIME_LIMIT),
        ],
    )
}

#[test]
fn svg_drawings() {
    let dir = Scratch::new("svg");
    dir.write("over.script.json", &to_bytes(&script_over("d.svg", 1)));
    let strategy = prop_oneof![
        3 => svg_mutated(drawing()),
        2 => svg_grammar(),
    ];
    fuzz("SVG drawings", strategy, |data| {
        drawing_case(&dir, "d.svg", &data)
    });
}

/// The cylinders drawing as a native sketch file.
fn native_sketch() -> Value {
    let import = geosnap::io::import_svg(&drawing(), &geosnap::io::SvgOptions::default())
        .expect("the drawing imports");
    let bytes = geosnap::io::sketch_file::sketch_file_bytes(&import.sketch, None)
        .expect("the sketch encodes");
    serde_json::from_slice(&bytes).expect("the sketch file is JSON")
}

/// Found in CI: two grow edits composed (a stroke's points, then the strokes from that
/// stroke) made a file of gigabytes, and the run was killed for memory.
#[test]
fn grow_edits_that_compose_stay_within_the_budget() {
    let mut sketch = native_sketch();
    // The choices are positions among an object's keys: `strokes`, then its first
    // stroke, then that stroke's `points`.
    let first_key = sketch
        .as_object()
        .and_then(|m| m.keys().position(|k| k == "strokes"))
        .expect("a sketch has strokes");
    let stroke = sketch["strokes"][0]
        .as_object()
        .and_then(|m| m.keys().position(|k| k == "points"))
        .expect("a stroke has points");
    apply_json_edit(
        &mut sketch,
        &[first_key, 0, stroke],
        &JsonEdit::Grow(19_999),
    );
    assert!(
        sketch["strokes"][0]["points"]
            .as_array()
            .map_or(0, Vec::len)
            > 19_999
    );
    apply_json_edit(&mut sketch, &[first_key], &JsonEdit::Grow(19_999));
    let size = serde_json::to_vec(&sketch).expect("JSON encodes").len();
    assert!(size <= 3 * GROW_BUDGET_BYTES, "{size} bytes");
}

const SKETCH_KEYS: &[&str] = &[
    "strokes", "view_box", "image", "id", "points", "closed", "class", "stroke", "viewbox",
];

#[test]
fn sketch_files() {
    let dir = Scratch::new("sketch");
    dir.write(
        "over.script.json",
        &to_bytes(&script_over("d.sketch.json", 1)),
    );
    let strategy = prop_oneof![
        4 => json_file(native_sketch(), GROW_LARGE),
        1 => json_grammar("geosnap-sketch", SKETCH_KEYS),
    ];
    fuzz("sketch files", strategy, |data| {
        drawing_case(&dir, "d.sketch.json", &data)
    });
}

const SCRIPT_KEYS: &[&str] = &[
    "steps", "sketch", "image", "place", "at", "axis", "radius", "length", "size", "radii",
    "raduis", "plcae", "top", "bottom",
];

#[test]
fn placement_scripts() {
    let dir = Scratch::new("script");
    dir.write("d.svg", &drawing());
    let outputs = Outputs {
        dir: &dir,
        names: &["out.model.json", "out.glb"],
    };
    let strategy = prop_oneof![
        4 => json_file(script_over("d.svg", 2), GROW_SMALL),
        1 => json_grammar("geosnap-script", SCRIPT_KEYS),
    ];
    fuzz("placement scripts", strategy, |data| {
        let input = dir.write("s.script.json", &data);
        command_holds(&outputs, &input, &[Path::new("check"), &input])?;
        command_holds(
            &outputs,
            &input,
            &[
                Path::new("run"),
                &input,
                Path::new("--out"),
                &outputs.path("out.model.json"),
                Path::new("--gltf"),
                &outputs.path("out.glb"),
                Path::new("--time-limit"),
                Path::new(RUN_TIME_LIMIT),
            ],
        )
    });
}

/// The model of the two-cylinder script, as `run` writes it.
fn base_model(dir: &Scratch) -> Value {
    dir.write("d.svg", &drawing());
    let script = dir.write("base.script.json", &to_bytes(&script_over("d.svg", 2)));
    let model = dir.path("base.model.json");
    let done = execute(&[Path::new("run"), &script, Path::new("--out"), &model]);
    assert!(done.is_ok(), "the base model is made: {done:?}");
    let text = std::fs::read(&model).expect("the base model");
    std::fs::remove_file(&model).expect("removed");
    std::fs::remove_file(&script).expect("removed");
    serde_json::from_slice(&text).expect("the model is JSON")
}

const MODEL_KEYS: &[&str] = &[
    "primitives",
    "relations",
    "sketch",
    "skipped",
    "kind",
    "id",
    "mode",
    "features",
    "a",
    "b",
    "fit",
    "center",
    "axis",
    "radius",
    "length",
    "confidence",
    "evidence",
    "step",
];

#[test]
fn model_files() {
    let dir = Scratch::new("model");
    let base = base_model(&dir);
    let outputs = Outputs {
        dir: &dir,
        names: &["out.model.json", "out.glb"],
    };
    let strategy = prop_oneof![
        4 => json_file(base, GROW_LARGE),
        1 => json_grammar("geosnap-model", MODEL_KEYS),
    ];
    fuzz("model files", strategy, |data| {
        let input = dir.write("m.model.json", &data);
        command_holds(&outputs, &input, &[Path::new("check"), &input])?;
        command_holds(
            &outputs,
            &input,
            &[
                Path::new("solve"),
                &input,
                Path::new("--out"),
                &outputs.path("out.model.json"),
            ],
        )?;
        command_holds(
            &outputs,
            &input,
            &[
                Path::new("export"),
                &input,
                Path::new("--out"),
                &outputs.path("out.glb"),
            ],
        )
    });
}

/// A session of the two-cylinder model over its drawing.
fn base_session(dir: &Scratch) -> Value {
    let model = base_model(dir);
    let loaded = geosnap::io::model_file::parse_model(&to_bytes(&model)).expect("the model");
    let import = geosnap::io::import_svg(&drawing(), &geosnap::io::SvgOptions::default())
        .expect("the drawing imports");
    let session = geosnap::io::Session {
        sketch: import.sketch,
        document: loaded.document,
        ..geosnap::io::Session::default()
    };
    let bytes = geosnap::io::session_bytes(&session).expect("the session encodes");
    serde_json::from_slice(&bytes).expect("the session is JSON")
}

const SESSION_KEYS: &[&str] = &[
    "model",
    "sketch",
    "dimensions",
    "snaps",
    "multipliers",
    "next_id",
    "primitive",
    "quantity",
    "value",
    "rms",
    "curves",
    "parts",
    "label",
    "occurrence",
];

/// Sessions are read by `check` (and the desktop application): `check` on each.
#[test]
fn session_files() {
    let dir = Scratch::new("session");
    let base = base_session(&dir);
    let outputs = Outputs {
        dir: &dir,
        names: &[],
    };
    let strategy = prop_oneof![
        4 => json_file(base, GROW_LARGE),
        1 => json_grammar("geosnap-session", SESSION_KEYS),
    ];
    fuzz("session files", strategy, |data| {
        let input = dir.write("w.geosnap.json", &data);
        command_holds(&outputs, &input, &[Path::new("check"), &input])
    });
}

/// Found by [`model_files`]: a model whose part is too large for glTF's `f32` failed
/// `export` without naming the model, and echoed a 280-digit number.
#[test]
fn an_export_too_large_for_gltf_names_the_model_briefly() {
    let dir = Scratch::new("too-large");
    let mut model = base_model(&dir);
    model["primitives"][0]["length"] = json!(1.967e279);
    let input = dir.write("m.model.json", &to_bytes(&model));
    let outputs = Outputs {
        dir: &dir,
        names: &["out.glb"],
    };
    let case = command_holds(
        &outputs,
        &input,
        &[
            Path::new("export"),
            &input,
            Path::new("--out"),
            &outputs.path("out.glb"),
        ],
    );
    assert!(case.is_ok(), "{case:?}");
    let error = execute(&[
        Path::new("export"),
        &input,
        Path::new("--out"),
        &outputs.path("out.glb"),
    ])
    .expect_err("too large for glTF");
    let message = format!("{error:#}");
    assert!(
        message.contains("does not fit in f32") && message.len() < 400,
        "{message}"
    );
}
