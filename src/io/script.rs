//! Placement scripts (`*.script.json`, formats.md §2): a scripted modelling session, the
//! same actions a person performs with the mouse.
//!
//! Reading is strict: the script must be an object with the fields of formats.md §2
//! ([`SCRIPT_FIELDS`]), and an unknown field is an error naming it with its line and
//! column and, for a near miss, the field meant ("`raduis`: did you mean `radius`?").
//! A step with an unknown field or primitive kind or a bad value is kept as
//! [`Step::Invalid`] with the reason and its position, so `check` lists every invalid
//! step at once and `geosnap run` refuses the script before doing any work.

use std::path::{Path, PathBuf};

use glam::DVec2;
use serde_json::Value;

use crate::core::model::Step;
use crate::core::primitive::{Placement, PrimitiveKind};
use crate::io::input::read_input;
use crate::io::json::{self, JsonPath, JsonProblem};

/// The `format` value of a script.
pub const SCRIPT_FORMAT: &str = "geosnap-script";
/// The newest script version this build reads.
pub const SCRIPT_VERSION: u64 = 1;

/// The fields a script may have (formats.md §2).
pub const SCRIPT_FIELDS: [&str; 5] = ["format", "version", "sketch", "image", "steps"];
/// The fields a step may have (formats.md §2).
pub const STEP_FIELDS: [&str; 8] = [
    "place",
    "at",
    "axis",
    "length",
    "radius",
    "radius_bottom",
    "radius_top",
    "size",
];

/// Why a script could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScriptError {
    /// The file could not be read.
    #[error("cannot read {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The file's content is not a script; the cause says where and why.
    #[error("{}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong with its content.
        #[source]
        source: Box<Self>,
    },
    /// Not valid JSON, not a version-1 geosnap script, or a field that is unknown or of
    /// the wrong kind: where (line, column and field) and why.
    #[error(transparent)]
    Invalid(#[from] JsonProblem),
}

impl ScriptError {
    /// The problem in the content, if that is what this error is.
    pub fn problem(&self) -> Option<&JsonProblem> {
        match self {
            Self::File { source, .. } => source.problem(),
            Self::Invalid(problem) => Some(problem),
            Self::Read { .. } => None,
        }
    }
}

/// A parsed script; paths are resolved against the script's folder.
#[derive(Clone, Debug, PartialEq)]
pub struct Script {
    /// The sketch (SVG or native sketch file).
    pub sketch: PathBuf,
    /// The optional reference image.
    pub image: Option<PathBuf>,
    /// The steps, in order.
    pub steps: Vec<Step>,
}

impl Script {
    /// The invalid steps, as `(index, reason)`.
    pub fn invalid_steps(&self) -> Vec<(usize, &str)> {
        self.steps
            .iter()
            .enumerate()
            .filter_map(|(i, step)| match step {
                Step::Invalid { reason } => Some((i, reason.as_str())),
                Step::Place { .. } => None,
            })
            .collect()
    }
}

/// Reads a script file.
///
/// # Errors
///
/// [`ScriptError::Read`] when the file cannot be read (see
/// [`read_input`]), else [`ScriptError::File`] naming it,
/// with the errors of [`parse_script`].
pub fn load_script(path: impl AsRef<Path>) -> Result<Script, ScriptError> {
    let path = path.as_ref();
    let data = read_input(path).map_err(|source| ScriptError::Read {
        path: path.to_owned(),
        source,
    })?;
    let base = path.parent().unwrap_or(Path::new(""));
    parse_script(&data, base).map_err(|source| ScriptError::File {
        path: path.to_owned(),
        source: Box::new(source),
    })
}

/// Parses script data; relative paths are resolved against `base`.
///
/// # Errors
///
/// [`ScriptError`] when the data is not a version-1 geosnap script.
///
/// # Examples
///
/// ```
/// use geosnap::core::model::Step;
/// use geosnap::io::script::parse_script;
///
/// let script = parse_script(br#"{
///     "format": "geosnap-script", "version": 1, "sketch": "table.svg",
///     "steps": [
///         { "place": "cylinder", "at": [412.0, 230.5], "radius": 12.0 },
///         { "place": "teapot", "at": [1, 2] }
///     ]
/// }"#, std::path::Path::new("sketches"))?;
/// assert_eq!(script.sketch, std::path::Path::new("sketches/table.svg"));
/// assert!(matches!(script.steps[0], Step::Place { .. }));
/// assert!(matches!(&script.steps[1], Step::Invalid { reason } if reason.contains("teapot")));
/// # Ok::<(), geosnap::io::script::ScriptError>(())
/// ```
pub fn parse_script(data: &[u8], base: &Path) -> Result<Script, ScriptError> {
    let value = json::parse(data)?;
    let envelope = read_envelope(&value).map_err(|problem| problem.locate(data))?;
    let steps = envelope
        .steps
        .iter()
        .enumerate()
        .map(|(index, step)| parse_step(step, index, data))
        .collect();
    Ok(Script {
        sketch: base.join(envelope.sketch),
        image: envelope.image.map(|i| base.join(i)),
        steps,
    })
}

/// The top level of a script, checked.
struct Envelope<'v> {
    sketch: &'v str,
    image: Option<&'v str>,
    steps: &'v [Value],
}

fn read_envelope(value: &Value) -> Result<Envelope<'_>, JsonProblem> {
    let object = json::root_object(value, "a placement script")?;
    json::check_format(object, SCRIPT_FORMAT)?;
    json::check_version(object, SCRIPT_VERSION, true)?;
    json::check_fields(object, &SCRIPT_FIELDS, &JsonPath::root())?;
    let root = JsonPath::root();
    let sketch = match object.get("sketch") {
        Some(Value::String(sketch)) if !sketch.is_empty() => sketch.as_str(),
        Some(other) => {
            return Err(json::wrong_kind(
                &root.key("sketch"),
                "the path of the sketch (a non-empty string)",
                other,
            ))
        }
        None => {
            return Err(JsonProblem::at(
                &root,
                "`sketch` is missing: the path of the drawing, relative to the script",
            ))
        }
    };
    let image = match object.get("image") {
        None | Some(Value::Null) => None,
        Some(Value::String(image)) => Some(image.as_str()),
        Some(other) => {
            return Err(json::wrong_kind(
                &root.key("image"),
                "the path of an image (a string) or null",
                other,
            ))
        }
    };
    let steps = json::optional_list(object, "steps", "a list of steps")?;
    Ok(Envelope {
        sketch,
        image,
        steps,
    })
}

/// Why a script step is invalid (kept in the script as [`Step::Invalid`] with this
/// text).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum StepError {
    /// The step is not an object.
    #[error("a step must be an object {{\"place\": ..., \"at\": [x, y], ...}}, found {0}")]
    NotObject(String),
    /// The step has a field formats.md does not document (the message names it, with a
    /// suggestion for a near miss).
    #[error("{0}")]
    UnknownField(String),
    /// The step has no `place`.
    #[error("a step needs `place`, the primitive kind")]
    MissingKind,
    /// The `place` names no primitive kind.
    #[error("unknown primitive kind `{0}` (known: cylinder, cone, sphere, cuboid, sgc, bgc)")]
    UnknownKind(String),
    /// The step has no `at`.
    #[error("a step needs `at`, the sketch point [x, y]")]
    MissingAt,
    /// A number field is not a finite number (the JSON found).
    #[error("`{field}` must be a finite number, got {found}")]
    Number {
        /// The field.
        field: &'static str,
        /// The JSON found.
        found: String,
    },
    /// An array field holds something other than finite numbers.
    #[error("`{field}` must hold {len} finite numbers")]
    Entry {
        /// The field.
        field: &'static str,
        /// The number of entries it needs.
        len: usize,
    },
    /// An array field is not an array of the right length (the JSON found).
    #[error("`{field}` must be an array of {len} numbers, got {found}")]
    Array {
        /// The field.
        field: &'static str,
        /// The number of entries it needs.
        len: usize,
        /// The JSON found.
        found: String,
    },
    /// A size is zero or negative.
    #[error("`{field}` must be positive, got {value}")]
    NotPositive {
        /// The field.
        field: &'static str,
        /// The value.
        value: f64,
    },
    /// The image direction is zero.
    #[error("`axis` must not be [0, 0]")]
    ZeroAxis,
    /// A box size is zero or negative.
    #[error("`size` must hold three positive numbers")]
    Size,
}

/// Reads step `index`; any problem becomes [`Step::Invalid`], its reason starting with
/// the position in `data` (of the unknown field, or of the step).
fn parse_step(value: &Value, index: usize, data: &[u8]) -> Step {
    match try_step(value) {
        Ok(step) => step,
        Err(reason) => {
            let path = JsonPath::root().key("steps").index(index);
            let path = match &reason {
                StepError::UnknownField(_) => value
                    .as_object()
                    .and_then(|o| o.keys().find(|k| !STEP_FIELDS.contains(&k.as_str())))
                    .map_or(path.clone(), |field| path.key(field)),
                _ => path,
            };
            let located = JsonProblem::at(&path, reason.to_string()).locate(data);
            Step::Invalid {
                reason: match located.position {
                    Some(position) => format!("{position}: {reason}"),
                    None => reason.to_string(),
                },
            }
        }
    }
}

fn number(value: &Value, field: &'static str) -> Result<Option<f64>, StepError> {
    match value.get(field) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => match v.as_f64() {
            Some(x) if x.is_finite() => Ok(Some(x)),
            _ => Err(StepError::Number {
                field,
                found: json::shown(v),
            }),
        },
    }
}

fn numbers<const N: usize>(
    value: &Value,
    field: &'static str,
) -> Result<Option<[f64; N]>, StepError> {
    match value.get(field) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::Array(items)) if items.len() == N => {
            let mut out = [0.0; N];
            for (o, item) in out.iter_mut().zip(items) {
                match item.as_f64() {
                    Some(x) if x.is_finite() => *o = x,
                    _ => return Err(StepError::Entry { field, len: N }),
                }
            }
            Ok(Some(out))
        }
        Some(v) => Err(StepError::Array {
            field,
            len: N,
            found: json::shown(v),
        }),
    }
}

fn positive(value: Option<f64>, field: &'static str) -> Result<Option<f64>, StepError> {
    match value {
        Some(v) if v <= 0.0 => Err(StepError::NotPositive { field, value: v }),
        other => Ok(other),
    }
}

fn try_step(value: &Value) -> Result<Step, StepError> {
    let Some(object) = value.as_object() else {
        return Err(StepError::NotObject(format!(
            "{} {}",
            json::kind_of(value),
            json::shown(value)
        )));
    };
    if let Some(field) = object.keys().find(|k| !STEP_FIELDS.contains(&k.as_str())) {
        return Err(StepError::UnknownField(json::unknown_field(
            field,
            &STEP_FIELDS,
        )));
    }
    let kind_name = value
        .get("place")
        .and_then(Value::as_str)
        .ok_or(StepError::MissingKind)?;
    let kind = PrimitiveKind::from_name(kind_name)
        .ok_or_else(|| StepError::UnknownKind(kind_name.to_owned()))?;
    let at = numbers::<2>(value, "at")?.ok_or(StepError::MissingAt)?;
    let axis = numbers::<2>(value, "axis")?.map_or(DVec2::new(0.0, -1.0), DVec2::from_array);
    if axis.length() == 0.0 {
        return Err(StepError::ZeroAxis);
    }
    let size = numbers::<3>(value, "size")?;
    if size.is_some_and(|s| s.iter().any(|v| *v <= 0.0)) {
        return Err(StepError::Size);
    }
    Ok(Step::Place {
        kind,
        placement: Placement {
            at: DVec2::from_array(at),
            axis,
            length: positive(number(value, "length")?, "length")?,
            radius: positive(number(value, "radius")?, "radius")?,
            radius_bottom: positive(number(value, "radius_bottom")?, "radius_bottom")?,
            radius_top: positive(number(value, "radius_top")?, "radius_top")?,
            size,
        },
    })
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::parse_script;
    use crate::core::model::Step;

    #[test]
    fn the_example_of_formats_md_parses() {
        let data = br#"{
          "format": "geosnap-script",
          "version": 1,
          "sketch": "table.svg",
          "image": null,
          "steps": [
            { "place": "cylinder", "at": [412.0, 230.5], "axis": [0.0, -1.0], "length": 180.0, "radius": 12.0 },
            { "place": "cone", "at": [300, 400], "axis": [0.1, -1.0], "length": 120, "radius_bottom": 40, "radius_top": 15 },
            { "place": "sphere", "at": [250, 260], "radius": 90 },
            { "place": "cuboid", "at": [600, 500], "size": [200, 80, 120] },
            { "place": "sgc", "at": [220, 640], "axis": [0, -1], "length": 300, "radius": 60 },
            { "place": "bgc", "at": [800, 300], "axis": [1, -1], "length": 260, "radius": 20 }
          ]
        }"#;
        let script = parse_script(data, Path::new("/tmp")).unwrap();
        assert_eq!(script.steps.len(), 6);
        assert!(script.steps.iter().all(|s| matches!(s, Step::Place { .. })));
        assert_eq!(script.image, None);
    }

    #[test]
    fn bad_steps_are_kept_with_a_reason_and_bad_envelopes_are_errors() {
        let data = br#"{"format":"geosnap-script","version":1,"sketch":"a.svg","steps":[
            {"place":"cylinder"},
            {"place":"cylinder","at":[1,"x"]},
            {"place":"cylinder","at":[1,2],"radius":-3},
            {"place":"cylinder","at":[1,2],"axis":[0,0]},
            {"at":[1,2]},
            7
        ]}"#;
        let script = parse_script(data, Path::new("")).unwrap();
        for step in &script.steps {
            assert!(matches!(step, Step::Invalid { .. }), "{step:?}");
        }
        let error = |data: &[u8]| {
            parse_script(data, Path::new(""))
                .expect_err("not a valid script")
                .to_string()
        };
        assert!(
            error(b"{}").contains("`format` is missing"),
            "{}",
            error(b"{}")
        );
        let wrong = error(br#"{"format":"x","sketch":"a"}"#);
        assert!(
            wrong.contains(r#"format is "x", expected "geosnap-script""#),
            "{wrong}"
        );
        let newer = error(br#"{"format":"geosnap-script","version":2,"sketch":"a"}"#);
        assert!(
            newer.starts_with("line 1, column 28: version: version 2 is not supported"),
            "{newer}"
        );
    }

    /// Issue 19, case 4: typos are errors, with the field's path and a suggestion.
    #[test]
    fn unknown_fields_are_refused_with_a_suggestion_and_a_position() {
        let data = b"{\"format\":\"geosnap-script\",\"version\":1,\"sketch\":\"a.svg\",\"steps\":[\n  {\"place\":\"cylinder\",\"at\":[1,2],\"raduis\":4},\n  {\"plcae\":\"cone\",\"at\":[1,2]}\n]}";
        let script = parse_script(data, Path::new("")).expect("the envelope is valid");
        let reasons: Vec<(usize, &str)> = script.invalid_steps();
        assert_eq!(
            reasons,
            vec![
                (
                    0,
                    "line 2, column 34: unknown field `raduis`; did you mean `radius`?"
                ),
                (
                    1,
                    "line 3, column 4: unknown field `plcae`; did you mean `place`?"
                ),
            ]
        );
        let error = parse_script(
            br#"{"format":"geosnap-script","version":1,"sketch":"a.svg","stpes":[]}"#,
            Path::new(""),
        )
        .expect_err("stpes is a typo")
        .to_string();
        assert_eq!(
            error,
            "line 1, column 57: stpes: unknown field `stpes`; did you mean `steps`?"
        );
    }

    /// Issue 19, case 4: wrong shapes are refused in our words, not read as a struct.
    #[test]
    fn wrong_shapes_are_refused_in_our_words() {
        for (data, says) in [
            (
                &br#"["geosnap-script",1,"x.svg"]"#[..],
                "a placement script must be a JSON object",
            ),
            (
                br#"{"format":"geosnap-script","version":"1","sketch":"a.svg"}"#,
                r#"version "1" is not valid: expected a whole number"#,
            ),
            (
                br#"{"format":"geosnap-script","sketch":7}"#,
                "sketch: must be the path of the sketch",
            ),
            (
                br#"{"format":"geosnap-script","sketch":"a.svg","steps":"none"}"#,
                "steps: must be a list of steps, found a string",
            ),
            (
                br#"{"format":"geosnap-model","version":1,"sketch":"a.svg"}"#,
                "this is a model file",
            ),
        ] {
            let error = parse_script(data, Path::new(""))
                .expect_err("refused")
                .to_string();
            assert!(error.contains(says), "{error}");
            for internal in ["struct", "expected u64", "invalid type"] {
                assert!(!error.contains(internal), "{error}");
            }
        }
    }

    /// Issue 19, case 9: error text is bounded; a huge value is not echoed whole.
    #[test]
    fn messages_are_bounded() {
        let huge: Vec<String> = (0..100_000).map(|i| i.to_string()).collect();
        let data = format!(
            r#"{{"format":"geosnap-script","sketch":"a.svg","steps":[{{"place":"cone","at":[{}]}}]}}"#,
            huge.join(",")
        );
        let script = parse_script(data.as_bytes(), Path::new("")).expect("valid envelope");
        let reasons = script.invalid_steps();
        assert!(reasons[0].1.len() < 200, "{}", reasons[0].1);
        let data = format!(r#"{{"format":[{}]}}"#, huge.join(","));
        let error = parse_script(data.as_bytes(), Path::new(""))
            .expect_err("bad format")
            .to_string();
        assert!(error.len() < 200, "{error}");
    }
}
