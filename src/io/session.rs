//! Session files: the whole work, saved and reopened so that it goes on as before.
//!
//! A session holds the sketch (strokes, user class overrides, view box), the reference
//! image path, and the document: primitives with their fits, relations with their modes,
//! the user's [`Dimension`]s, and each part's snap record (which strokes its projected
//! curves were assigned and the RMS of its own snap), which the global solve keeps
//! fitting. Warm-start multipliers are kept too, so a re-solve after reopening follows
//! the same path as one before saving.
//!
//! # Format (version 1)
//!
//! JSON, UTF-8, one object:
//!
//! ```json
//! {
//!   "format": "geosnap-session",
//!   "version": 1,
//!   "sketch": { "format": "geosnap-sketch", "version": 1, "strokes": [ ... ] },
//!   "model": { "format": "geosnap-model", "version": 1, "sketch": "", "primitives": [ ... ] },
//!   "dimensions": [ { "primitive": 0, "quantity": "radius", "value": 12.5 } ],
//!   "snaps": [
//!     { "primitive": 0, "rms": 0.41, "curves": [[4], [], [2, 9], [3]],
//!       "parts": [ { "curve": 2, "stroke": 9, "samples": [0, 1, 2, 3, 4, 5] } ] }
//!   ],
//!   "multipliers": [ { "label": "relation 0 (parallel of #0 top, #1 top)", "occurrence": 0, "value": -0.02 } ],
//!   "next_id": 3
//! }
//! ```
//!
//! - `format` (required) is `"geosnap-session"`; `version` (required) is 1. A newer
//!   version is refused with [`SessionError::UnsupportedVersion`] rather than misread.
//! - `sketch` (required): the object a native sketch file holds
//!   ([`crate::io::sketch_file`]), including its `image`, relative to the session file.
//! - `model` (required): the object a model file holds ([`crate::io::model_file`],
//!   formats.md §3), with relations, their modes and the skipped steps, the parts'
//!   `name`s and the document's `unit` (both optional: no names, millimetres). Its
//!   `sketch` field is empty: the sketch is the one above.
//! - `dimensions` (optional, default none): [`Dimension`]s, `quantity` one of
//!   [`Quantity::name`](crate::core::model::Quantity::name), `value` in model space.
//! - `snaps` (optional, default none): per part placed by snapping, its own snap's `rms`
//!   (sketch units) and, per projected curve of the part in order, the ids of the strokes
//!   assigned to it. `parts` (optional) lists the strokes of which only a stretch was
//!   assigned, with the indices of the samples taken among the stroke's evenly chosen
//!   samples ([`crate::core::snap::stroke_samples`]). The samples themselves are not
//!   stored: they are rebuilt from the sketch exactly as the snap chose them
//!   ([`crate::core::snap::restore_assignment`]).
//! - `multipliers` (optional): the warm start of the next global solve
//!   ([`Document::warm_multipliers`]); it changes speed, not results.
//! - `next_id` (optional): the id the next new part gets, so that the ids of deleted
//!   parts stay retired after reopening.
//! - Unknown fields are ignored.
//!
//! Not kept: undo history, and the cause of a skipped step's failure beyond its
//! message.

use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;
use serde_json::Value;

use crate::core::model::{Dimension, Document, PrimitiveId, SnapRecord};
use crate::core::sketch::{Sketch, StrokeId};
use crate::core::snap::{restore_assignment, CurveStrokes, Profile, RestoreError, SnapContext};
use crate::io::model_file::{model_json, parse_model, ModelError};
use crate::io::sketch_file::{parse_sketch_file, sketch_file_bytes};
use crate::io::{write_atomic, LoadError, SaveError};

/// The `format` value of a session file.
pub const SESSION_FORMAT: &str = "geosnap-session";

/// The newest session file version this build reads, and the one it writes.
pub const SESSION_VERSION: u64 = 1;

/// The whole work: the sketch with its image and the document.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Session {
    /// The strokes, their class overrides and the view box, in sketch space.
    pub sketch: Sketch,
    /// The reference image: stored as given by [`save_session`] (pass a path relative to
    /// the session file), returned as written by [`parse_session`] and resolved against
    /// the file's folder by [`load_session`].
    pub image: Option<PathBuf>,
    /// The primitives, relations, dimensions and snap records.
    pub document: Document,
}

/// Why a session could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SessionError {
    /// The file could not be read.
    #[error("cannot read {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// Reading the file failed; the cause says why.
    #[error("cannot load session {}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What was wrong with its content.
        #[source]
        source: Box<Self>,
    },
    /// The data is not JSON.
    #[error("malformed session file: not json")]
    Json {
        /// The JSON parser's error (with line and column).
        #[source]
        source: serde_json::Error,
    },
    /// The JSON is not a geosnap session (its `format` field is wrong or missing).
    #[error("not a geosnap session file: format is {found}, expected \"geosnap-session\"")]
    WrongFormat {
        /// The `format` value found, as JSON, or `missing`.
        found: String,
    },
    /// A version this build does not read (newer, or not a positive integer).
    #[error("unsupported session file version {found}: this geosnap reads version 1")]
    UnsupportedVersion {
        /// The `version` value found, as JSON, or `missing`.
        found: String,
    },
    /// A required part of the session is missing.
    #[error("the session file has no `{0}`")]
    Missing(&'static str),
    /// The embedded sketch is invalid.
    #[error("the session's sketch is invalid")]
    Sketch {
        /// What is wrong with it.
        #[source]
        source: LoadError,
    },
    /// The embedded model is invalid (a relation naming a missing primitive included).
    #[error("the session's model is invalid")]
    Model {
        /// What is wrong with it.
        #[source]
        source: ModelError,
    },
    /// A list has the wrong shape (`dimensions`, `snaps`, `multipliers`).
    #[error("the session's `{field}` entry {index} is malformed")]
    Entry {
        /// The list.
        field: &'static str,
        /// The entry's position in it.
        index: usize,
        /// The decoder's error.
        #[source]
        source: serde_json::Error,
    },
    /// A dimension cannot be applied (a missing primitive, a quantity the part does not
    /// have, a bad value).
    #[error("dimension {index}: {reason}")]
    Dimension {
        /// Its position in `dimensions`.
        index: usize,
        /// What is wrong.
        reason: String,
    },
    /// A snap record cannot be restored (a missing primitive or stroke, the wrong
    /// number of curves, bad sample indices).
    #[error("snap {index}: {reason}")]
    Snap {
        /// Its position in `snaps`.
        index: usize,
        /// What is wrong.
        reason: SnapRecordError,
    },
}

/// What is wrong with one stored snap record.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SnapRecordError {
    /// The record names a primitive the model does not hold.
    #[error("there is no primitive {0}")]
    NoPrimitive(u32),
    /// The stored RMS is negative or not finite.
    #[error("`rms` must be a finite non-negative number, not {0}")]
    Rms(f64),
    /// A partly assigned stroke is not among its curve's strokes.
    #[error("stroke {stroke} is not assigned to curve {curve}")]
    Part {
        /// The stroke.
        stroke: u32,
        /// The curve.
        curve: usize,
    },
    /// The strokes do not fit the primitive's curves or the sketch.
    #[error(transparent)]
    Restore(#[from] RestoreError),
}

/// A snap record as stored.
#[derive(Serialize, Deserialize)]
struct SnapV1 {
    primitive: u32,
    rms: f64,
    curves: Vec<Vec<u32>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    parts: Vec<PartV1>,
}

/// A stroke of which only a stretch was assigned to a curve.
#[derive(Serialize, Deserialize)]
struct PartV1 {
    curve: usize,
    stroke: u32,
    samples: Vec<usize>,
}

/// A warm-start multiplier as stored.
#[derive(Serialize, Deserialize)]
struct MultiplierV1 {
    label: String,
    occurrence: usize,
    value: f64,
}

/// The file, for writing.
#[derive(Serialize)]
struct SessionV1<'a> {
    format: &'static str,
    version: u64,
    sketch: &'a RawValue,
    model: Value,
    dimensions: &'a [Dimension],
    snaps: Vec<SnapV1>,
    multipliers: Vec<MultiplierV1>,
    next_id: u32,
}

fn snap_v1(id: PrimitiveId, record: &SnapRecord) -> SnapV1 {
    let mut parts = Vec::new();
    let curves = record
        .assignment
        .curves
        .iter()
        .enumerate()
        .map(|(k, strokes)| {
            strokes
                .iter()
                .map(|a| {
                    if let Some(samples) = &a.part {
                        parts.push(PartV1 {
                            curve: k,
                            stroke: a.stroke.0,
                            samples: samples.clone(),
                        });
                    }
                    a.stroke.0
                })
                .collect()
        })
        .collect();
    SnapV1 {
        primitive: id.0,
        rms: record.rms,
        curves,
        parts,
    }
}

/// Encodes a session as a version-1 session file (pretty JSON; the sketch one stroke
/// per line, as sketch files are).
///
/// # Errors
///
/// The errors of [`sketch_file_bytes`] ([`SaveError::InvalidSketch`],
/// [`SaveError::NonUnicodeImagePath`]), and [`SaveError::Json`] if encoding fails.
pub fn session_bytes(session: &Session) -> Result<Vec<u8>, SaveError> {
    let json = |source| SaveError::Json { source };
    let sketch = sketch_file_bytes(&session.sketch, session.image.as_deref())?;
    let sketch = String::from_utf8_lossy(&sketch).trim_end().to_owned();
    let sketch = RawValue::from_string(sketch).map_err(json)?;
    let document = &session.document;
    let file = SessionV1 {
        format: SESSION_FORMAT,
        version: SESSION_VERSION,
        sketch: &sketch,
        model: model_json(document, ""),
        dimensions: document.dimensions(),
        snaps: document
            .snap_records()
            .map(|(id, record)| snap_v1(id, record))
            .collect(),
        multipliers: document
            .warm_multipliers()
            .map(|(label, occurrence, value)| MultiplierV1 {
                label: label.to_owned(),
                occurrence,
                value,
            })
            .collect(),
        next_id: document.next_id().0,
    };
    let mut bytes = serde_json::to_vec_pretty(&file).map_err(json)?;
    bytes.push(b'\n');
    Ok(bytes)
}

/// Saves a session, atomically (the old file survives any failure).
///
/// # Errors
///
/// The errors of [`session_bytes`], and [`SaveError::Write`] if the file cannot be
/// written.
pub fn save_session(path: impl AsRef<Path>, session: &Session) -> Result<(), SaveError> {
    let path = path.as_ref();
    let bytes = session_bytes(session)?;
    write_atomic(path, &bytes).map_err(|source| SaveError::Write {
        path: path.to_owned(),
        source,
    })
}

/// Opens a session file; a relative reference image path is resolved against the
/// file's folder.
///
/// # Errors
///
/// [`SessionError::Read`] if the file cannot be read, otherwise [`SessionError::File`]
/// naming the file, whose source is the error of [`parse_session`].
pub fn load_session(path: impl AsRef<Path>) -> Result<Session, SessionError> {
    let path = path.as_ref();
    let data = crate::io::input::read_input(path).map_err(|source| SessionError::Read {
        path: path.to_owned(),
        source,
    })?;
    let mut session = parse_session(&data).map_err(|source| SessionError::File {
        path: path.to_owned(),
        source: Box::new(source),
    })?;
    if let (Some(image), Some(dir)) = (&session.image, path.parent()) {
        if image.is_relative() {
            session.image = Some(dir.join(image));
        }
    }
    Ok(session)
}

/// The entries of an optional list field, decoded one by one.
fn entries<T: DeserializeOwned>(
    file: &serde_json::Map<String, Value>,
    field: &'static str,
) -> Result<Vec<T>, SessionError> {
    let items = match file.get(field) {
        None | Some(Value::Null) => return Ok(Vec::new()),
        Some(Value::Array(items)) => items,
        Some(other) => {
            return Err(SessionError::Entry {
                field,
                index: 0,
                source: <serde_json::Error as serde::de::Error>::custom(format!(
                    "expected a list, found {other}"
                )),
            })
        }
    };
    items
        .iter()
        .enumerate()
        .map(|(index, item)| {
            T::deserialize(item).map_err(|source| SessionError::Entry {
                field,
                index,
                source,
            })
        })
        .collect()
}

/// Parses a session file; the reference image path is returned as written.
///
/// # Errors
///
/// [`SessionError::Json`] for data that is not JSON, [`SessionError::WrongFormat`],
/// [`SessionError::UnsupportedVersion`], [`SessionError::Missing`] without a sketch or
/// model, [`SessionError::Sketch`] and [`SessionError::Model`] for an invalid sketch or
/// model (a relation naming a missing primitive is a model error),
/// [`SessionError::Entry`] for a malformed list entry, and [`SessionError::Dimension`]
/// or [`SessionError::Snap`] for one naming a missing primitive or stroke or not fitting
/// its part. Never panics, whatever the bytes.
pub fn parse_session(data: &[u8]) -> Result<Session, SessionError> {
    let value: Value =
        serde_json::from_slice(data).map_err(|source| SessionError::Json { source })?;
    let Some(file) = value.as_object() else {
        return Err(SessionError::WrongFormat {
            found: "missing (the data is not a json object)".to_owned(),
        });
    };
    match file.get("format") {
        Some(Value::String(format)) if format == SESSION_FORMAT => {}
        other => {
            return Err(SessionError::WrongFormat {
                found: other.map_or_else(|| "missing".to_owned(), crate::io::json::shown),
            })
        }
    }
    match file.get("version") {
        Some(v) if v.as_u64() == Some(SESSION_VERSION) => {}
        other => {
            return Err(SessionError::UnsupportedVersion {
                found: other.map_or_else(|| "missing".to_owned(), crate::io::json::shown),
            })
        }
    }
    let embedded = |field: &'static str| -> Result<Vec<u8>, SessionError> {
        let value = file.get(field).ok_or(SessionError::Missing(field))?;
        serde_json::to_vec(value).map_err(|source| SessionError::Json { source })
    };
    let loaded = parse_sketch_file(&embedded("sketch")?)
        .map_err(|source| SessionError::Sketch { source })?;
    let mut document = parse_model(&embedded("model")?)
        .map_err(|source| SessionError::Model { source })?
        .document;

    for (index, d) in entries::<Dimension>(file, "dimensions")?
        .into_iter()
        .enumerate()
    {
        document
            .set_dimension(d.primitive, d.quantity, d.value)
            .map_err(|e| SessionError::Dimension {
                index,
                reason: e.to_string(),
            })?;
    }

    let snaps = entries::<SnapV1>(file, "snaps")?;
    if !snaps.is_empty() {
        let context = SnapContext::from_sketch(&loaded.sketch);
        for (index, snap) in snaps.into_iter().enumerate() {
            let record = snap_record(&document, &context, snap)
                .map_err(|reason| SessionError::Snap { index, reason })?;
            document.set_snap_record(record.0, record.1);
        }
    }

    for m in entries::<MultiplierV1>(file, "multipliers")? {
        document.set_warm_multiplier(m.label, m.occurrence, m.value);
    }
    if let Some(next) = file.get("next_id") {
        let next = next
            .as_u64()
            .and_then(|n| u32::try_from(n).ok())
            .ok_or_else(|| SessionError::Entry {
                field: "next_id",
                index: 0,
                source: <serde_json::Error as serde::de::Error>::custom(format!(
                    "{next} is not a primitive id"
                )),
            })?;
        document.reserve_ids(PrimitiveId(next));
    }

    Ok(Session {
        sketch: loaded.sketch,
        image: loaded.image,
        document,
    })
}

/// One snap record rebuilt against the document and the sketch's strokes.
fn snap_record(
    document: &Document,
    context: &SnapContext,
    snap: SnapV1,
) -> Result<(PrimitiveId, SnapRecord), SnapRecordError> {
    let id = PrimitiveId(snap.primitive);
    let placed = document.get(id).ok_or(SnapRecordError::NoPrimitive(id.0))?;
    if !(snap.rms.is_finite() && snap.rms >= 0.0) {
        return Err(SnapRecordError::Rms(snap.rms));
    }
    let mut strokes: Vec<CurveStrokes> = snap
        .curves
        .iter()
        .map(|ids| ids.iter().map(|s| (StrokeId(*s), None)).collect())
        .collect();
    for part in snap.parts {
        let slot = strokes
            .get_mut(part.curve)
            .and_then(|c| c.iter_mut().find(|(s, _)| s.0 == part.stroke))
            .ok_or(SnapRecordError::Part {
                stroke: part.stroke,
                curve: part.curve,
            })?;
        slot.1 = Some(part.samples);
    }
    let curves = placed.primitive.current_shape().curves;
    let assignment = restore_assignment(context, &curves, &strokes)?;
    Ok((
        id,
        SnapRecord {
            assignment,
            rms: snap.rms,
            // The file does not say how its snap held a bent tube's radii.
            profile: Profile::Smooth,
        },
    ))
}
