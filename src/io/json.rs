//! Strict JSON reading shared by the script and model readers: messages in our words.
//!
//! - [`parse`] turns bytes into a [`Value`], and a syntax error into a [`JsonProblem`]
//!   with its line and column, without the JSON parser's own vocabulary.
//! - [`JsonPath`] names a place in a document (`steps[3].radius`); [`JsonProblem::locate`]
//!   finds its line and column in the original bytes, so problems found in the parsed
//!   value still point into the file.
//! - [`check_fields`] refuses unknown fields, with a near-miss suggestion ([`suggest`]).
//! - [`shown`] echoes a value in a bounded number of characters (a 100k-element array is
//!   never copied whole into a message).

use std::fmt;

use serde_json::{Map, Value};

/// The most characters of a value [`shown`] echoes.
pub const MAX_SHOWN_CHARS: usize = 60;

/// One step of a [`JsonPath`]: a field of an object or an entry of an array.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Segment {
    Key(String),
    Index(usize),
}

/// A place in a JSON document: the fields and indices from the root, written
/// `steps[3].radius` (the root itself is empty).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct JsonPath(Vec<Segment>);

impl JsonPath {
    /// The root of the document.
    pub fn root() -> Self {
        Self::default()
    }

    /// The field `key` of the object at this place.
    #[must_use]
    pub fn key(&self, key: &str) -> Self {
        let mut path = self.clone();
        path.0.push(Segment::Key(key.to_owned()));
        path
    }

    /// The entry `index` of the array at this place.
    #[must_use]
    pub fn index(&self, index: usize) -> Self {
        let mut path = self.clone();
        path.0.push(Segment::Index(index));
        path
    }

    /// Whether this is the root.
    pub fn is_root(&self) -> bool {
        self.0.is_empty()
    }
}

impl fmt::Display for JsonPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, segment) in self.0.iter().enumerate() {
            match segment {
                Segment::Key(key) if i == 0 => write!(f, "{key}")?,
                Segment::Key(key) => write!(f, ".{key}")?,
                Segment::Index(index) => write!(f, "[{index}]")?,
            }
        }
        Ok(())
    }
}

/// A line and column in a file, both counted from 1 (columns in characters).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Position {
    /// The line.
    pub line: usize,
    /// The column.
    pub column: usize,
}

impl Position {
    /// The position of byte `offset` of `data`.
    fn of_offset(data: &[u8], offset: usize) -> Self {
        let before = data.get(..offset).unwrap_or(data);
        let line_start = before
            .iter()
            .rposition(|b| *b == b'\n')
            .map_or(0, |i| i + 1);
        // One more line than newlines: `split` counts the pieces between them.
        let line = before.split(|b| *b == b'\n').count();
        // Count characters, not bytes: skip UTF-8 continuation bytes.
        let column = 1 + before
            .get(line_start..)
            .unwrap_or_default()
            .iter()
            .filter(|b| (**b & 0xC0) != 0x80)
            .count();
        Self { line, column }
    }
}

impl fmt::Display for Position {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}, column {}", self.line, self.column)
    }
}

/// What is wrong with a JSON file, where: its position (when known), the place in the
/// document, and the reason in our words.
///
/// It reads `line 4, column 7: steps[0].raduis: unknown field; did you mean `radius`?`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct JsonProblem {
    /// The line and column in the file, when known.
    pub position: Option<Position>,
    /// The place in the document (empty for the whole document or a syntax error).
    pub path: JsonPath,
    /// What is wrong.
    pub reason: String,
}

impl fmt::Display for JsonProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(position) = self.position {
            write!(f, "{position}: ")?;
        }
        if !self.path.is_root() {
            write!(f, "{}: ", self.path)?;
        }
        f.write_str(&self.reason)
    }
}

impl JsonProblem {
    /// A problem at `path` (its position is found later with [`Self::locate`]).
    pub fn at(path: &JsonPath, reason: impl Into<String>) -> Self {
        Self {
            position: None,
            path: path.clone(),
            reason: reason.into(),
        }
    }

    /// The same problem with its position found in `data`, the bytes it was parsed
    /// from (left unknown when the path cannot be followed).
    #[must_use]
    pub fn locate(mut self, data: &[u8]) -> Self {
        if self.position.is_none() {
            self.position = locate(data, &self.path.0).map(|at| Position::of_offset(data, at));
        }
        self
    }
}

/// Parses JSON, with syntax errors in our words and with their position.
///
/// # Errors
///
/// A [`JsonProblem`] at the root with the line and column of the first syntax error.
pub fn parse(data: &[u8]) -> Result<Value, JsonProblem> {
    serde_json::from_slice(data).map_err(|error| {
        let position = (error.line() > 0).then(|| Position {
            line: error.line(),
            column: error.column(),
        });
        let reason = if data.iter().all(u8::is_ascii_whitespace) {
            "the file is empty; expected a JSON object".to_owned()
        } else if error.is_eof() {
            "the JSON ends before it is complete (a missing `]`, `}` or `\"`?)".to_owned()
        } else {
            // serde_json's syntax messages ("expected `,` or `}`", "trailing comma") are
            // plain words; only its own position suffix is dropped, as we give ours.
            let text = error.to_string();
            let detail = text
                .rfind(" at line ")
                .map_or(text.as_str(), |cut| text.get(..cut).unwrap_or_default());
            format!("invalid JSON: {detail}")
        };
        JsonProblem {
            position,
            path: JsonPath::root(),
            reason,
        }
    })
}

/// A typed reader's error (serde) as a [`JsonProblem`] in our words: its position kept,
/// Rust type names ("u32", "struct StrokeV1") replaced by what they mean.
pub fn from_serde(error: &serde_json::Error, data: &[u8]) -> JsonProblem {
    if !error.is_data() {
        return match parse(data) {
            Err(problem) => problem,
            Ok(_) => JsonProblem::at(&JsonPath::root(), "invalid JSON"),
        };
    }
    let text = error.to_string();
    let detail = text
        .rfind(" at line ")
        .map_or(text.as_str(), |cut| text.get(..cut).unwrap_or_default());
    let mut reason = detail.to_owned();
    for (rust, words) in [
        ("u64", "a whole number"),
        ("u32", "a whole number from 0 to 4294967295"),
        ("usize", "a whole number"),
        ("f64", "a number"),
        ("a boolean", "true or false"),
    ] {
        reason = reason.replace(&format!("expected {rust}"), &format!("expected {words}"));
    }
    if let Some(start) = reason.find("struct ") {
        // "expected struct StrokeV1" names our type, not the file's: say an object.
        let end = reason
            .get(start + 7..)
            .and_then(|rest| rest.find(|c: char| !c.is_alphanumeric()))
            .map_or(reason.len(), |n| start + 7 + n);
        reason.replace_range(start..end, "an object");
    }
    if let Some(rest) = reason.strip_prefix("invalid type: ") {
        if let Some((found, expected)) = rest.split_once(", expected ") {
            reason = format!("found {found} where {expected} was expected");
        }
    }
    JsonProblem {
        position: (error.line() > 0).then(|| Position {
            line: error.line(),
            column: error.column(),
        }),
        path: JsonPath::root(),
        reason,
    }
}

/// What kind of JSON value `value` is, in words: "an array", "a string", ...
pub fn kind_of(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "true or false",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// Stops writing after a limit, so a huge value is never serialized whole.
struct Bounded(Vec<u8>);

impl std::io::Write for Bounded {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        // Four bytes per character at most, plus room to tell a cut.
        let room = (4 * MAX_SHOWN_CHARS + 4).saturating_sub(self.0.len());
        if room == 0 {
            return Err(std::io::Error::other("long enough"));
        }
        let taken = buf.len().min(room);
        self.0
            .extend_from_slice(buf.get(..taken).unwrap_or_default());
        Ok(taken)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// `value` as JSON, cut to [`MAX_SHOWN_CHARS`] characters with `…` (and, for a long
/// array or object, how many entries it has).
pub fn shown(value: &Value) -> String {
    let mut out = Bounded(Vec::new());
    // An error only means the value was cut.
    let complete = serde_json::to_writer(&mut out, value).is_ok();
    let text = String::from_utf8_lossy(&out.0);
    if complete && text.chars().count() <= MAX_SHOWN_CHARS {
        return text.into_owned();
    }
    let cut: String = text.chars().take(MAX_SHOWN_CHARS).collect();
    match value {
        Value::Array(items) => format!("{cut}… ({} entries)", items.len()),
        Value::Object(fields) => format!("{cut}… ({} fields)", fields.len()),
        _ => format!("{cut}…"),
    }
}

/// The `format` tag of JSON data, when it is a JSON object with a string `format`: how
/// the kind of a file is decided by its content, whatever its name.
pub fn format_tag(data: &[u8]) -> Option<String> {
    let data = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data);
    if data.iter().find(|b| !b.is_ascii_whitespace()) != Some(&b'{') {
        return None;
    }
    match serde_json::from_slice::<Value>(data).ok()?.get("format")? {
        Value::String(format) => Some(format.clone()),
        _ => None,
    }
}

/// What a geosnap JSON file is, by its `format` tag, in words with the command that
/// reads it: used to tell a user who gave one kind of file where another was expected.
pub fn describe_format(format: &str) -> Option<&'static str> {
    Some(match format {
        "geosnap-script" => "a placement script (`geosnap run` reads it)",
        "geosnap-model" => "a model file (`geosnap solve` and `geosnap export` read it)",
        "geosnap-sketch" => "a native sketch file (a script names it as its `sketch`)",
        "geosnap-session" => "a session file (the desktop application opens it)",
        _ => return None,
    })
}

/// Checks the `format` field of `object` against `expected`; the message says what the
/// file is when it is another geosnap file.
///
/// # Errors
///
/// A [`JsonProblem`] at `format` (or at the root when it is missing).
pub fn check_format(object: &Map<String, Value>, expected: &str) -> Result<(), JsonProblem> {
    let path = JsonPath::root().key("format");
    match object.get("format") {
        Some(Value::String(found)) if found == expected => Ok(()),
        Some(Value::String(found)) => Err(JsonProblem::at(
            &path,
            match describe_format(found) {
                Some(what) => format!(
                    "this is {what}, not {}",
                    describe_format(expected).unwrap_or(expected)
                ),
                None => format!(
                    "format is {}, expected \"{expected}\"",
                    shown(&Value::String(found.clone()))
                ),
            },
        )),
        Some(other) => Err(JsonProblem::at(
            &path,
            format!("format is {}, expected \"{expected}\"", shown(other)),
        )),
        None => Err(JsonProblem::at(
            &JsonPath::root(),
            format!("`format` is missing: expected \"format\": \"{expected}\""),
        )),
    }
}

/// Checks the `version` field of `object`: a whole number from 1 to `newest`; a missing
/// version reads as 1 when `optional`.
///
/// # Errors
///
/// A [`JsonProblem`] at `version` that says which version was found.
pub fn check_version(
    object: &Map<String, Value>,
    newest: u64,
    optional: bool,
) -> Result<u64, JsonProblem> {
    let path = JsonPath::root().key("version");
    match object.get("version") {
        None if optional => Ok(1),
        None => Err(JsonProblem::at(
            &JsonPath::root(),
            format!(
                "`version` is missing: this geosnap reads version {}",
                versions(newest)
            ),
        )),
        Some(v) => match v.as_u64() {
            Some(found) if (1..=newest).contains(&found) => Ok(found),
            Some(found) if found > newest => Err(JsonProblem::at(
                &path,
                format!(
                    "version {found} is not supported: this geosnap reads version {}; the \
                     file was written by a newer geosnap",
                    versions(newest)
                ),
            )),
            _ => Err(JsonProblem::at(
                &path,
                format!(
                    "version {} is not valid: expected a whole number ({})",
                    shown(v),
                    versions(newest)
                ),
            )),
        },
    }
}

fn versions(newest: u64) -> String {
    if newest == 1 {
        "1".to_owned()
    } else {
        format!("1 to {newest}")
    }
}

/// The object at the root of a document, or a problem saying what was found instead and
/// what `what` (for example "a placement script") must look like.
///
/// # Errors
///
/// A [`JsonProblem`] at the root when `value` is not an object.
pub fn root_object<'v>(
    value: &'v Value,
    what: &str,
) -> Result<&'v Map<String, Value>, JsonProblem> {
    value.as_object().ok_or_else(|| {
        JsonProblem::at(
            &JsonPath::root(),
            format!(
                "{what} must be a JSON object {{\"format\": ..., \"version\": ..., ...}}, \
                 found {} {}",
                kind_of(value),
                shown(value)
            ),
        )
    })
}

/// A value of the wrong kind at `path`: "must be {expected}, found an array `[1,2]`".
pub fn wrong_kind(path: &JsonPath, expected: &str, found: &Value) -> JsonProblem {
    JsonProblem::at(
        path,
        format!(
            "must be {expected}, found {} {}",
            kind_of(found),
            shown(found)
        ),
    )
}

/// The list in the optional field `field` of the root `object` (empty when missing or
/// null).
///
/// # Errors
///
/// A [`wrong_kind`] problem when the field is neither a list nor null.
pub fn optional_list<'v>(
    object: &'v Map<String, Value>,
    field: &str,
    expected: &str,
) -> Result<&'v [Value], JsonProblem> {
    match object.get(field) {
        None | Some(Value::Null) => Ok(&[]),
        Some(Value::Array(items)) => Ok(items.as_slice()),
        Some(other) => Err(wrong_kind(&JsonPath::root().key(field), expected, other)),
    }
}

/// The known name closest to `word`, if it is close enough to be a typo: at most two
/// edits (insertions, deletions, substitutions or swaps of neighbours) and fewer than
/// half its letters, or the same name in another case.
pub fn suggest(word: &str, known: &[&'static str]) -> Option<&'static str> {
    let lower = word.to_lowercase();
    known
        .iter()
        .map(|k| (strsim::damerau_levenshtein(&lower, k), *k))
        .filter(|(distance, k)| *distance <= 2 && 2 * distance < k.chars().count().max(2))
        .min_by_key(|(distance, _)| *distance)
        .map(|(_, k)| k)
}

/// The message for an unknown field `name`, with a suggestion among `known`.
pub fn unknown_field(name: &str, known: &[&'static str]) -> String {
    match suggest(name, known) {
        Some(near) => format!(
            "unknown field `{}`; did you mean `{near}`?",
            shown_key(name)
        ),
        None => format!(
            "unknown field `{}` (known: {})",
            shown_key(name),
            known.join(", ")
        ),
    }
}

/// A field name cut to [`MAX_SHOWN_CHARS`] characters.
fn shown_key(name: &str) -> String {
    if name.chars().count() <= MAX_SHOWN_CHARS {
        name.to_owned()
    } else {
        let cut: String = name.chars().take(MAX_SHOWN_CHARS).collect();
        format!("{cut}…")
    }
}

/// Refuses the first field of `object` (at `path`) that is not in `known`.
///
/// # Errors
///
/// A [`JsonProblem`] at the unknown field, with a suggestion for a near miss.
pub fn check_fields(
    object: &Map<String, Value>,
    known: &[&'static str],
    path: &JsonPath,
) -> Result<(), JsonProblem> {
    match object.keys().find(|k| !known.contains(&k.as_str())) {
        Some(name) => Err(JsonProblem::at(&path.key(name), unknown_field(name, known))),
        None => Ok(()),
    }
}

/// The byte offset of the place `path` in the JSON text `data` (for a field, where its
/// name starts; for an array entry, where the entry starts). `None` if the path cannot be
/// followed.
fn locate(data: &[u8], path: &[Segment]) -> Option<usize> {
    let mut scan = Scanner { data, at: 0 };
    scan.skip_bom();
    scan.space();
    let mut key_start = None;
    for segment in path {
        key_start = None;
        match segment {
            Segment::Key(wanted) => {
                scan.expect(b'{')?;
                loop {
                    scan.space();
                    let start = scan.at;
                    let key = scan.string()?;
                    scan.space();
                    scan.expect(b':')?;
                    scan.space();
                    if key == *wanted {
                        key_start = Some(start);
                        break;
                    }
                    scan.value()?;
                    scan.space();
                    scan.expect(b',')?;
                }
            }
            Segment::Index(index) => {
                scan.expect(b'[')?;
                for _ in 0..*index {
                    scan.space();
                    scan.value()?;
                    scan.space();
                    scan.expect(b',')?;
                }
                scan.space();
            }
        }
    }
    Some(key_start.unwrap_or(scan.at))
}

/// A forward reader over JSON text that can skip values.
struct Scanner<'a> {
    data: &'a [u8],
    at: usize,
}

impl Scanner<'_> {
    fn peek(&self) -> Option<u8> {
        self.data.get(self.at).copied()
    }

    fn skip_bom(&mut self) {
        if self.data.starts_with(b"\xEF\xBB\xBF") {
            self.at = 3;
        }
    }

    fn space(&mut self) {
        while self.peek().is_some_and(|b| b.is_ascii_whitespace()) {
            self.at += 1;
        }
    }

    fn expect(&mut self, byte: u8) -> Option<()> {
        (self.peek()? == byte).then(|| self.at += 1)
    }

    /// Reads a string and returns its value.
    fn string(&mut self) -> Option<String> {
        let start = self.at;
        self.expect(b'"')?;
        let mut escaped = false;
        loop {
            let b = self.peek()?;
            self.at += 1;
            match b {
                b'\\' => {
                    escaped = true;
                    self.at += 1;
                }
                b'"' => break,
                _ => {}
            }
        }
        let raw = self.data.get(start..self.at)?;
        if escaped {
            serde_json::from_slice(raw).ok()
        } else {
            std::str::from_utf8(raw.get(1..raw.len() - 1)?)
                .ok()
                .map(str::to_owned)
        }
    }

    /// Skips one value (of any depth, without recursion).
    fn value(&mut self) -> Option<()> {
        let mut depth = 0usize;
        loop {
            match self.peek()? {
                b'"' => {
                    self.string()?;
                }
                b'{' | b'[' => {
                    depth += 1;
                    self.at += 1;
                }
                b'}' | b']' => {
                    depth = depth.checked_sub(1)?;
                    self.at += 1;
                }
                b',' | b':' if depth > 0 => self.at += 1,
                b if b.is_ascii_whitespace() => self.at += 1,
                _ => {
                    while self.peek().is_some_and(|b| {
                        !matches!(b, b',' | b'}' | b']' | b':') && !b.is_ascii_whitespace()
                    }) {
                        self.at += 1;
                    }
                }
            }
            if depth == 0 {
                return Some(());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::{check_fields, parse, shown, suggest, JsonPath, JsonProblem, Position};

    #[test]
    fn near_misses_are_suggested_and_far_ones_are_not() {
        let step = ["place", "at", "axis", "length", "radius"];
        assert_eq!(suggest("raduis", &step), Some("radius"));
        assert_eq!(suggest("plcae", &step), Some("place"));
        assert_eq!(suggest("Radius", &step), Some("radius"));
        assert_eq!(suggest("lenght", &step), Some("length"));
        assert_eq!(suggest("colour", &step), None);
        assert_eq!(suggest("x", &step), None);
    }

    #[test]
    fn unknown_fields_are_found_with_their_path_and_position() {
        let data =
            b"{\"steps\": [\n  {\"place\": \"cone\"},\n  {\"at\": [1, 2], \"raduis\": 3}\n]}";
        let value = parse(data).expect("valid json");
        let step = value["steps"][1].as_object().expect("an object");
        let path = JsonPath::root().key("steps").index(1);
        let problem = check_fields(step, &["place", "at", "radius"], &path)
            .expect_err("raduis is unknown")
            .locate(data);
        assert_eq!(
            problem.to_string(),
            "line 3, column 18: steps[1].raduis: unknown field `raduis`; did you mean `radius`?"
        );
        let entry = JsonProblem::at(&path, "x").locate(data);
        assert_eq!(entry.position, Some(Position { line: 3, column: 3 }));
    }

    #[test]
    fn syntax_errors_are_in_our_words_with_a_position() {
        let problem = parse(b"{\n  \"a\": 1,\n}").expect_err("trailing comma");
        assert_eq!(problem.position, Some(Position { line: 3, column: 1 }));
        assert!(problem.reason.starts_with("invalid JSON"), "{problem}");
        assert!(!problem.reason.contains(" at line "), "{problem}");
        assert!(parse(b"  ").expect_err("empty").reason.contains("empty"));
        assert!(parse(b"{\"a\": [1,")
            .expect_err("eof")
            .reason
            .contains("ends"));
    }

    #[test]
    fn typed_errors_lose_their_rust_names() {
        #[derive(Debug, serde::Deserialize)]
        #[expect(dead_code, reason = "only the error is read")]
        struct StrokeV1 {
            id: u32,
        }
        let data = b"{\n \"id\": \"a\"}";
        let error = serde_json::from_slice::<StrokeV1>(data).expect_err("wrong type");
        let problem = super::from_serde(&error, data);
        assert_eq!(
            problem.to_string(),
            "line 2, column 10: found string \"a\" where a whole number from 0 to 4294967295 was expected"
        );
        let error = serde_json::from_slice::<StrokeV1>(b"[]").expect_err("wrong shape");
        let problem = super::from_serde(&error, b"[]");
        assert!(!problem.reason.contains("struct"), "{problem}");
    }

    #[test]
    fn shown_values_are_bounded() {
        assert_eq!(shown(&json!([1, 2])), "[1,2]");
        let long = serde_json::Value::Array((0..100_000).map(|i| json!(i)).collect());
        let text = shown(&long);
        assert!(text.len() < 120, "{text}");
        assert!(text.ends_with("… (100000 entries)"), "{text}");
        let string = json!("é".repeat(1000));
        assert!(shown(&string).chars().count() <= 61, "cut on characters");
    }
}
