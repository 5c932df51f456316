//! Placement scripts (`*.script.json`, formats.md §2): a scripted modelling session, the
//! same actions a person performs with the mouse.
//!
//! Reading is strict about the envelope (`format`, `version`, `sketch`, `steps`) and
//! lenient about steps: a step with an unknown primitive kind or a bad value is kept as
//! [`Step::Invalid`] with the reason, so the run reports it as skipped instead of
//! aborting (formats.md: a step never aborts the run).

use std::path::{Path, PathBuf};

use glam::DVec2;
use serde::Deserialize;
use serde_json::Value;

use crate::core::model::Step;
use crate::core::primitive::{Placement, PrimitiveKind};

/// The `format` value of a script.
pub const SCRIPT_FORMAT: &str = "geosnap-script";
/// The newest script version this build reads.
pub const SCRIPT_VERSION: u64 = 1;

/// Why a script could not be read.
#[derive(Debug, thiserror::Error)]
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
    /// Not valid JSON, or not an object with the script fields.
    #[error("malformed script")]
    Json {
        /// The parser's error.
        #[source]
        source: serde_json::Error,
    },
    /// The `format` field is not `geosnap-script`.
    #[error("not a geosnap script: format is {found}, expected \"geosnap-script\"")]
    WrongFormat {
        /// What was found.
        found: String,
    },
    /// A version this build does not read.
    #[error("unsupported script version {found}: this geosnap reads version 1")]
    UnsupportedVersion {
        /// The version found.
        found: u64,
    },
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

#[derive(Deserialize)]
struct Envelope {
    format: Option<Value>,
    version: Option<u64>,
    sketch: String,
    #[serde(default)]
    image: Option<String>,
    #[serde(default)]
    steps: Vec<Value>,
}

/// Reads a script file.
///
/// # Errors
///
/// [`ScriptError`] when the file cannot be read or is not a version-1 geosnap script.
pub fn load_script(path: impl AsRef<Path>) -> Result<Script, ScriptError> {
    let path = path.as_ref();
    let data = std::fs::read(path).map_err(|source| ScriptError::Read {
        path: path.to_owned(),
        source,
    })?;
    let base = path.parent().unwrap_or(Path::new(""));
    parse_script(&data, base)
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
    let envelope: Envelope =
        serde_json::from_slice(data).map_err(|source| ScriptError::Json { source })?;
    match &envelope.format {
        Some(Value::String(f)) if f == SCRIPT_FORMAT => {}
        other => {
            return Err(ScriptError::WrongFormat {
                found: other
                    .as_ref()
                    .map_or("missing".to_owned(), Value::to_string),
            })
        }
    }
    let version = envelope.version.unwrap_or(1);
    if version != SCRIPT_VERSION {
        return Err(ScriptError::UnsupportedVersion { found: version });
    }
    Ok(Script {
        sketch: base.join(&envelope.sketch),
        image: envelope.image.map(|i| base.join(i)),
        steps: envelope.steps.iter().map(parse_step).collect(),
    })
}

/// Why a script step is invalid (kept in the script as [`Step::Invalid`] with this
/// text).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum StepError {
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

/// Reads one step; any problem becomes [`Step::Invalid`].
fn parse_step(value: &Value) -> Step {
    match try_step(value) {
        Ok(step) => step,
        Err(reason) => Step::Invalid {
            reason: reason.to_string(),
        },
    }
}

fn number(value: &Value, field: &'static str) -> Result<Option<f64>, StepError> {
    match value.get(field) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => match v.as_f64() {
            Some(x) if x.is_finite() => Ok(Some(x)),
            _ => Err(StepError::Number {
                field,
                found: v.to_string(),
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
            found: v.to_string(),
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

    use super::{parse_script, ScriptError};
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
        assert!(matches!(
            parse_script(b"{}", Path::new("")),
            Err(ScriptError::Json { .. })
        ));
        assert!(matches!(
            parse_script(br#"{"format":"x","sketch":"a"}"#, Path::new("")),
            Err(ScriptError::WrongFormat { .. })
        ));
        assert!(matches!(
            parse_script(
                br#"{"format":"geosnap-script","version":2,"sketch":"a"}"#,
                Path::new("")
            ),
            Err(ScriptError::UnsupportedVersion { found: 2 })
        ));
    }
}
