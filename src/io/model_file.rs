//! Model files (`*.model.json`, formats.md §3): the assembled result in model space.
//!
//! Field names follow formats.md exactly; geosnap adds `fit` and `name` per primitive,
//! the BGC's `plane_normal`, and the top-level `skipped` list and `unit`. Reading validates what it reads (unit
//! axes, positive sizes, finite numbers, unique ids) and names the offending primitive.

use std::path::{Path, PathBuf};

use glam::{DMat3, DQuat, DVec3};
use serde_json::{json, Map, Value};

use crate::core::model::{
    Document, Fit, LengthUnit, Placed, PrimitiveId, Relation, RelationError, Skipped,
};
use crate::core::primitive::{
    Bgc, Cone, Cuboid, Cylinder, Feature, Primitive, PrimitiveError, Sgc, Sphere, UNIT_TOLERANCE,
};
use crate::core::relation::evidence::{Evidence, Inferred};
use crate::core::relation::{Mode, RelationKind};
use crate::core::sketch::StrokeId;
use crate::core::snap::Verdict;
use crate::io::atomic::write_atomic;
use crate::io::input::read_input;
use crate::io::json::{self, JsonPath, JsonProblem, Position};

/// The `format` value of a model file.
pub const MODEL_FORMAT: &str = "geosnap-model";
/// The newest model version this build writes and reads.
pub const MODEL_VERSION: u64 = 1;

/// Why a model file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read or written.
    #[error("cannot access {}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The file's content is not a model; the cause says where and why.
    #[error("{}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong with its content.
        #[source]
        source: Box<Self>,
    },
    /// The model could not be encoded as JSON.
    #[error("cannot encode the model as json")]
    Json {
        /// The encoder's error.
        #[source]
        source: serde_json::Error,
    },
    /// Not valid JSON, not a version-1 geosnap model, or a field that is unknown or of
    /// the wrong kind: where (line, column and field) and why.
    #[error(transparent)]
    Invalid(#[from] JsonProblem),
    /// A relation is invalid.
    #[error("{}relation {index}: {reason}", at_prefix(*.at))]
    Relation {
        /// Its position in the `relations` list.
        index: usize,
        /// What is wrong.
        reason: RelationReadError,
        /// Where it is in the file, when known.
        at: Option<Position>,
    },
    /// A primitive is invalid.
    #[error("{}primitive {id}: {reason}", at_prefix(*.at))]
    Primitive {
        /// The primitive's id (or its index when the id is missing).
        id: String,
        /// What is wrong.
        reason: PrimitiveReadError,
        /// Where it is in the file, when known.
        at: Option<Position>,
    },
}

/// `line L, column C: ` for a known position.
fn at_prefix(at: Option<Position>) -> String {
    at.map(|p| format!("{p}: ")).unwrap_or_default()
}

/// The fields of a model file (formats.md §3).
pub const MODEL_FIELDS: [&str; 7] = [
    "format",
    "version",
    "sketch",
    "primitives",
    "relations",
    "skipped",
    "unit",
];
/// The fields of a relation (formats.md §3).
pub const RELATION_FIELDS: [&str; 6] = [
    "kind",
    "members",
    "features",
    "mode",
    "confidence",
    "evidence",
];
/// The fields of a primitive's `fit` (formats.md §3).
pub const FIT_FIELDS: [&str; 5] = ["strokes", "rms", "verdict", "confidence", "reason"];
/// The fields of an entry of `skipped` (formats.md §3).
pub const SKIPPED_FIELDS: [&str; 2] = ["step", "reason"];

/// What is wrong with one relation of a model file (or of a glTF file's extras).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RelationReadError {
    /// `kind` is missing or names no relation kind.
    #[error("unknown `kind` {}", json::shown(.0))]
    Kind(Value),
    /// `members` is missing or not a list.
    #[error("`members` must be a list of primitives")]
    Members,
    /// A member names no primitive.
    #[error("member {} is not a primitive", json::shown(.0))]
    Member(Value),
    /// `features` is not a list.
    #[error("`features` {} is not a list", json::shown(.0))]
    Features(Value),
    /// An entry of `features` is not a name.
    #[error("feature {} is not a name", json::shown(.0))]
    FeatureName(Value),
    /// A member's kind has no feature of that name.
    #[error("unknown feature `{name}` for a {kind}")]
    UnknownFeature {
        /// The name read.
        name: String,
        /// The member's kind.
        kind: &'static str,
    },
    /// `mode` names no mode.
    #[error("unknown `mode` {} (hard, soft, off or suggested)", json::shown(.0))]
    Mode(Value),
    /// The confidence is not a number in [0, 1].
    #[error("`confidence` {} is not a number in [0, 1]", json::shown(.0))]
    Confidence(Value),
    /// The relation does not suit its members (see [`Document::add_relation`]).
    #[error(transparent)]
    Relation(#[from] RelationError),
}

/// What is wrong with one primitive of a model file (or of a glTF file's extras).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PrimitiveReadError {
    /// The `id` is missing or not a non-negative integer.
    #[error("`id` must be a non-negative integer")]
    Id,
    /// Another primitive has the same id.
    #[error("the id is used twice")]
    DuplicateId,
    /// The `kind` is missing.
    #[error("`kind` is missing")]
    MissingKind,
    /// The `kind` names no primitive kind.
    #[error("unknown kind `{0}`")]
    UnknownKind(String),
    /// A number field is missing or not a finite number.
    #[error("`{0}` must be a finite number")]
    Number(&'static str),
    /// A vector field is missing or not three numbers.
    #[error("`{0}` must be [x, y, z]")]
    Vector(&'static str),
    /// A vector field holds something other than finite numbers.
    #[error("`{0}` must hold finite numbers")]
    VectorEntry(&'static str),
    /// A radius list is missing or shorter than two.
    #[error("`{0}` must be a list of at least two radii")]
    Radii(&'static str),
    /// A radius list holds something other than positive numbers.
    #[error("`{0}` must hold positive numbers")]
    Radius(&'static str),
    /// A cuboid's `axes` are not three vectors.
    #[error("`axes` must be three vectors")]
    Axes,
    /// A cuboid's `axes` are not an orthonormal right-handed frame.
    #[error("`axes` must be an orthonormal right-handed frame")]
    Frame,
    /// A bent tube's `spine` is missing or shorter than three points.
    #[error("`spine` must hold at least three points")]
    Spine,
    /// The `fit.verdict` is not one of the verdicts (the JSON found).
    #[error("`fit.verdict` must be \"good\", \"doubtful\" or \"refused\", not {0}")]
    Verdict(String),
    /// The `fit.confidence` is not a number in [0, 1] (the JSON found).
    #[error("`fit.confidence` must be a number in [0, 1], not {0}")]
    Confidence(String),
    /// The `name` is not a text (the JSON found).
    #[error("`name` must be a text, not {0}")]
    Name(String),
    /// An object has a field formats.md does not document (the message names it, with a
    /// suggestion for a near miss).
    #[error("{0}")]
    UnknownField(String),
    /// A required field is missing, and an unknown field looks like a typo for it.
    #[error("`{missing}` is missing; `{found}` looks like a typo for it")]
    Misspelt {
        /// The required field.
        missing: &'static str,
        /// The field found instead.
        found: String,
    },
    /// The primitive breaks an invariant of its kind.
    #[error(transparent)]
    Invalid(#[from] PrimitiveError),
}

fn v3(v: DVec3) -> Value {
    json!([v.x, v.y, v.z])
}

/// The JSON of one primitive (without `id` and `fit`).
pub(crate) fn primitive_json(p: &Primitive) -> Map<String, Value> {
    let value = match p {
        Primitive::Cylinder(c) => json!({
            "kind": "cylinder", "center": v3(c.center), "axis": v3(c.axis),
            "length": c.length, "radius": c.radius,
        }),
        Primitive::Cone(c) => json!({
            "kind": "cone", "center": v3(c.center), "axis": v3(c.axis), "length": c.length,
            "radius_bottom": c.radius_bottom, "radius_top": c.radius_top,
        }),
        Primitive::Sphere(s) => {
            json!({ "kind": "sphere", "center": v3(s.center), "radius": s.radius })
        }
        Primitive::Cuboid(b) => {
            let [x, y, z] = b.axes();
            json!({
                "kind": "cuboid", "center": v3(b.center), "axes": [v3(x), v3(y), v3(z)],
                "size": v3(b.size),
            })
        }
        Primitive::Sgc(s) => json!({
            "kind": "sgc", "center": v3(s.center), "axis": v3(s.axis), "length": s.length,
            "radii": s.radii,
        }),
        Primitive::Bgc(b) => json!({
            "kind": "bgc", "spine": b.spine.iter().map(|p| v3(*p)).collect::<Vec<_>>(),
            "radii": b.radii, "plane_normal": v3(b.plane_normal),
        }),
    };
    match value {
        Value::Object(map) => map,
        _ => Map::new(),
    }
}

/// The JSON of a relation, its members written by `member` (an id here, a node name in
/// glTF extras).
pub(crate) fn relation_json(r: &Relation, member: impl Fn(PrimitiveId) -> Value) -> Value {
    let mut map = Map::new();
    map.insert("kind".into(), json!(r.kind));
    let members: Vec<Value> = r.members.iter().map(|m| member(*m)).collect();
    map.insert("members".into(), Value::Array(members));
    if r.features.iter().any(Option::is_some) {
        let names: Vec<Option<&str>> = r.features.iter().map(|f| f.map(Feature::name)).collect();
        map.insert("features".into(), json!(names));
    }
    map.insert("mode".into(), json!(r.mode));
    if let Some(inferred) = &r.inferred {
        map.insert("confidence".into(), json!(inferred.confidence));
        map.insert(
            "evidence".into(),
            serde_json::to_value(&inferred.evidence).unwrap_or(Value::Null),
        );
    }
    Value::Object(map)
}

/// An inferred relation's `confidence` and `evidence` (formats.md §3), when it has them.
/// Evidence is free-form in the format: an object that is not ours (another tool's)
/// is kept out, not refused; a confidence outside [0, 1] is an error.
fn parse_inferred(r: &Value) -> Result<Option<Inferred>, RelationReadError> {
    let Some(c) = r.get("confidence") else {
        return Ok(None);
    };
    let confidence = c
        .as_f64()
        .filter(|c| (0.0..=1.0).contains(c))
        .ok_or_else(|| RelationReadError::Confidence(c.clone()))?;
    let evidence = r
        .get("evidence")
        .and_then(|e| serde_json::from_value::<Evidence>(e.clone()).ok());
    Ok(evidence.map(|evidence| Inferred {
        confidence,
        evidence,
    }))
}

/// The `fit` object of a primitive (formats.md §3): its strokes and RMS, and the snap's
/// verdict, confidence and reason when it was judged.
fn fit_json(fit: &Fit) -> Value {
    let mut map = Map::new();
    map.insert(
        "strokes".into(),
        json!(fit.strokes.iter().map(|s| s.0).collect::<Vec<_>>()),
    );
    map.insert("rms".into(), json!(fit.rms));
    if let Some(verdict) = fit.verdict {
        map.insert("verdict".into(), json!(verdict.name()));
    }
    if let Some(confidence) = fit.confidence {
        map.insert("confidence".into(), json!(confidence));
    }
    if let Some(reason) = &fit.reason {
        map.insert("reason".into(), json!(reason));
    }
    Value::Object(map)
}

/// The `fit` object of primitive `p` and its `step` (formats.md §3); a missing `fit` is an
/// empty one.
fn parse_fit(p: &Value) -> Result<Fit, PrimitiveReadError> {
    let step = p
        .get("step")
        .and_then(Value::as_u64)
        .and_then(|s| usize::try_from(s).ok());
    let Some(f) = p.get("fit") else {
        return Ok(Fit {
            step,
            ..Fit::default()
        });
    };
    if let Some(fit) = f.as_object() {
        if let Some(field) = fit.keys().find(|k| !FIT_FIELDS.contains(&k.as_str())) {
            return Err(PrimitiveReadError::UnknownField(format!(
                "`fit`: {}",
                json::unknown_field(field, &FIT_FIELDS)
            )));
        }
    }
    let verdict = match f.get("verdict") {
        None => None,
        Some(v) => Some(
            v.as_str()
                .and_then(Verdict::from_name)
                .ok_or_else(|| PrimitiveReadError::Verdict(json::shown(v)))?,
        ),
    };
    Ok(Fit {
        strokes: f
            .get("strokes")
            .and_then(Value::as_array)
            .map(|s| {
                s.iter()
                    .filter_map(Value::as_u64)
                    .filter_map(|i| u32::try_from(i).ok())
                    .map(StrokeId)
                    .collect()
            })
            .unwrap_or_default(),
        rms: f.get("rms").and_then(Value::as_f64).unwrap_or(0.0),
        verdict,
        confidence: match f.get("confidence") {
            None => None,
            Some(c) => Some(
                c.as_f64()
                    .filter(|c| (0.0..=1.0).contains(c))
                    .ok_or_else(|| PrimitiveReadError::Confidence(json::shown(c)))?,
            ),
        },
        reason: f.get("reason").and_then(Value::as_str).map(str::to_owned),
        step,
    })
}

/// The model file's JSON for a document.
pub fn model_json(document: &Document, sketch: &str) -> Value {
    let primitives: Vec<Value> = document
        .primitives()
        .map(|(id, placed)| {
            let mut map = Map::new();
            map.insert("id".into(), json!(id.0));
            map.extend(primitive_json(&placed.primitive));
            map.insert("fit".into(), fit_json(&placed.fit));
            if let Some(step) = placed.fit.step {
                map.insert("step".into(), json!(step));
            }
            if let Some(name) = document.name(id) {
                map.insert("name".into(), json!(name));
            }
            Value::Object(map)
        })
        .collect();
    let skipped: Vec<Value> = document
        .skipped
        .iter()
        .map(|s| json!({ "step": s.step, "reason": s.reason }))
        .collect();
    let relations: Vec<Value> = document
        .relations()
        .iter()
        .map(|r| relation_json(r, |m| json!(m.0)))
        .collect();
    let mut model = json!({
        "format": MODEL_FORMAT,
        "version": MODEL_VERSION,
        "sketch": sketch,
        "primitives": primitives,
        "relations": relations,
        "skipped": skipped,
    });
    // Millimetres, the default, are left unsaid: such a file reads as before.
    if let (Value::Object(map), unit) = (&mut model, document.unit()) {
        if unit != LengthUnit::default() {
            map.insert("unit".into(), json!(unit.symbol()));
        }
    }
    model
}

/// The bytes of a model file for a document (pretty JSON, ending with a newline).
///
/// # Errors
///
/// [`ModelError::Json`] if encoding fails.
pub fn model_bytes(document: &Document, sketch: &str) -> Result<Vec<u8>, ModelError> {
    let mut text = serde_json::to_string_pretty(&model_json(document, sketch))
        .map_err(|source| ModelError::Json { source })?;
    text.push('\n');
    Ok(text.into_bytes())
}

/// Writes a model file atomically.
///
/// # Errors
///
/// [`ModelError::Io`] when the file cannot be written (the old file is then untouched).
pub fn save_model(
    path: impl AsRef<Path>,
    document: &Document,
    sketch: &str,
) -> Result<(), ModelError> {
    let path = path.as_ref();
    let bytes = model_bytes(document, sketch)?;
    write_atomic(path, &bytes).map_err(|source| ModelError::Io {
        path: path.to_owned(),
        source,
    })
}

/// A model read back: the document and the sketch path it names.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedModel {
    /// The document.
    pub document: Document,
    /// The `sketch` field.
    pub sketch: String,
}

/// Reads a model file.
///
/// # Errors
///
/// [`ModelError::Io`] when the file cannot be read (see
/// [`read_input`]); else [`ModelError::File`] naming it, with the errors of
/// [`parse_model`].
pub fn load_model(path: impl AsRef<Path>) -> Result<LoadedModel, ModelError> {
    read_model(path.as_ref()).map(|(_, model)| model)
}

/// As [`load_model`], with the bytes read: a command that may have to write the model
/// back unchanged keeps exactly what it parsed.
///
/// # Errors
///
/// As [`load_model`].
pub fn read_model(path: &Path) -> Result<(Vec<u8>, LoadedModel), ModelError> {
    let data = read_input(path).map_err(|source| ModelError::Io {
        path: path.to_owned(),
        source,
    })?;
    let model = parse_model(&data).map_err(|source| ModelError::File {
        path: path.to_owned(),
        source: Box::new(source),
    })?;
    Ok((data, model))
}

fn get_f64(map: &Value, field: &'static str) -> Result<f64, PrimitiveReadError> {
    map.get(field)
        .and_then(Value::as_f64)
        .filter(|v| v.is_finite())
        .ok_or(PrimitiveReadError::Number(field))
}

fn get_v3(value: Option<&Value>, field: &'static str) -> Result<DVec3, PrimitiveReadError> {
    let items = value
        .and_then(Value::as_array)
        .filter(|a| a.len() == 3)
        .ok_or(PrimitiveReadError::Vector(field))?;
    let mut out = [0.0; 3];
    for (o, item) in out.iter_mut().zip(items) {
        *o = item
            .as_f64()
            .filter(|v| v.is_finite())
            .ok_or(PrimitiveReadError::VectorEntry(field))?;
    }
    Ok(DVec3::from_array(out))
}

fn get_radii(map: &Value, field: &'static str) -> Result<Vec<f64>, PrimitiveReadError> {
    let items = map
        .get(field)
        .and_then(Value::as_array)
        .filter(|a| a.len() >= 2)
        .ok_or(PrimitiveReadError::Radii(field))?;
    items
        .iter()
        .map(|v| {
            v.as_f64()
                .filter(|r| r.is_finite() && *r > 0.0)
                .ok_or(PrimitiveReadError::Radius(field))
        })
        .collect()
}

/// The rotation of a cuboid's `axes`: three unit vectors forming an orthonormal
/// right-handed frame.
fn frame_rotation(v: &Value) -> Result<DQuat, PrimitiveReadError> {
    let axes = v
        .get("axes")
        .and_then(Value::as_array)
        .filter(|a| a.len() == 3)
        .ok_or(PrimitiveReadError::Axes)?;
    let [x, y, z] = [0, 1, 2].map(|i| get_v3(axes.get(i), "axes"));
    let [x, y, z] = [x?, y?, z?];
    for axis in [x, y, z] {
        let length = axis.length();
        if (length - 1.0).abs() > UNIT_TOLERANCE {
            return Err(PrimitiveError::NotUnit {
                field: "axes",
                length,
            }
            .into());
        }
    }
    let m = DMat3::from_cols(x, y, z);
    if (m.transpose() * m - DMat3::IDENTITY)
        .to_cols_array()
        .iter()
        .any(|e| e.abs() > UNIT_TOLERANCE)
        || m.determinant() < 0.0
    {
        return Err(PrimitiveReadError::Frame);
    }
    Ok(DQuat::from_mat3(&m).normalize())
}

/// One primitive from its JSON, checked with [`Primitive::validate`].
pub(crate) fn parse_primitive(v: &Value) -> Result<Primitive, PrimitiveReadError> {
    let kind = v
        .get("kind")
        .and_then(Value::as_str)
        .ok_or(PrimitiveReadError::MissingKind)?;
    let primitive = match kind {
        "cylinder" => Primitive::Cylinder(Cylinder {
            center: get_v3(v.get("center"), "center")?,
            axis: get_v3(v.get("axis"), "axis")?,
            length: get_f64(v, "length")?,
            radius: get_f64(v, "radius")?,
        }),
        "cone" => Primitive::Cone(Cone {
            center: get_v3(v.get("center"), "center")?,
            axis: get_v3(v.get("axis"), "axis")?,
            length: get_f64(v, "length")?,
            radius_bottom: get_f64(v, "radius_bottom")?,
            radius_top: get_f64(v, "radius_top")?,
        }),
        "sphere" => Primitive::Sphere(Sphere {
            center: get_v3(v.get("center"), "center")?,
            radius: get_f64(v, "radius")?,
        }),
        "cuboid" => {
            let rotation = frame_rotation(v)?;
            Primitive::Cuboid(Cuboid {
                size: get_v3(v.get("size"), "size")?,
                center: get_v3(v.get("center"), "center")?,
                rotation,
            })
        }
        "sgc" => Primitive::Sgc(Sgc {
            center: get_v3(v.get("center"), "center")?,
            axis: get_v3(v.get("axis"), "axis")?,
            length: get_f64(v, "length")?,
            radii: get_radii(v, "radii")?,
        }),
        "bgc" => {
            let spine: Vec<DVec3> = v
                .get("spine")
                .and_then(Value::as_array)
                .filter(|a| a.len() >= 3)
                .ok_or(PrimitiveReadError::Spine)?
                .iter()
                .map(|p| get_v3(Some(p), "spine"))
                .collect::<Result<_, _>>()?;
            Primitive::Bgc(Bgc {
                spine,
                radii: get_radii(v, "radii")?,
                plane_normal: match v.get("plane_normal") {
                    Some(n) => get_v3(Some(n), "plane_normal")?,
                    None => DVec3::Z,
                },
            })
        }
        other => return Err(PrimitiveReadError::UnknownKind(other.to_owned())),
    };
    primitive.validate()?;
    Ok(primitive)
}

/// Parses model data.
///
/// # Errors
///
/// [`ModelError`] as [`load_model`].
pub fn parse_model(data: &[u8]) -> Result<LoadedModel, ModelError> {
    let v = json::parse(data)?;
    let (sketch, unit, primitives, relations, skipped) =
        read_envelope(&v).map_err(|problem| ModelError::Invalid(problem.locate(data)))?;
    let mut document = Document::new();
    document.set_unit(unit);
    let root = JsonPath::root();
    for (index, p) in primitives.iter().enumerate() {
        let id_text = p.get("id").map_or_else(|| format!("#{index}"), json::shown);
        let fail = |reason: PrimitiveReadError| {
            let at = JsonProblem::at(&root.key("primitives").index(index), "")
                .locate(data)
                .position;
            ModelError::Primitive {
                id: id_text.clone(),
                reason,
                at,
            }
        };
        let id = p
            .get("id")
            .and_then(Value::as_u64)
            .and_then(|i| u32::try_from(i).ok())
            .ok_or_else(|| fail(PrimitiveReadError::Id))?;
        if document.get(PrimitiveId(id)).is_some() {
            return Err(fail(PrimitiveReadError::DuplicateId));
        }
        let primitive = parse_primitive(p)
            .map_err(|reason| misspelt(p, reason))
            .map_err(fail)?;
        let fit = parse_fit(p).map_err(fail)?;
        let name = parse_name(p).map_err(fail)?;
        document.insert(PrimitiveId(id), Placed { primitive, fit });
        if let Some(name) = name {
            document.set_name(PrimitiveId(id), name);
        }
    }
    document.skipped = skipped
        .iter()
        .map(|s| Skipped {
            step: s
                .get("step")
                .and_then(Value::as_u64)
                .map_or(0, |x| usize::try_from(x).unwrap_or(usize::MAX)),
            reason: s
                .get("reason")
                .and_then(Value::as_str)
                .unwrap_or_default()
                .to_owned(),
        })
        .collect();
    for (index, r) in relations.iter().enumerate() {
        let fail = |reason: RelationReadError| ModelError::Relation {
            index,
            reason,
            at: JsonProblem::at(&root.key("relations").index(index), "")
                .locate(data)
                .position,
        };
        let relation = parse_relation(r, &document).map_err(fail)?;
        document
            .add_relation(relation)
            .map_err(|e| fail(e.into()))?;
    }
    Ok(LoadedModel { document, sketch })
}

/// The `name` of primitive `p`, when it has one (formats.md §3): a text, cleaned by
/// [`Document::set_name`]; `null` is no name.
fn parse_name(p: &Value) -> Result<Option<&str>, PrimitiveReadError> {
    match p.get("name") {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(name)) => Ok(Some(name)),
        Some(other) => Err(PrimitiveReadError::Name(json::shown(other))),
    }
}

/// The symbols of the units a model file may name (formats.md §3).
const UNIT_SYMBOLS: [&str; 4] = ["mm", "cm", "m", "in"];

/// The model's `unit` (formats.md §3): millimetres when missing or null.
fn read_unit(object: &Map<String, Value>) -> Result<LengthUnit, JsonProblem> {
    let path = JsonPath::root().key("unit");
    match object.get("unit") {
        None | Some(Value::Null) => Ok(LengthUnit::default()),
        Some(Value::String(symbol)) => LengthUnit::from_symbol(symbol).ok_or_else(|| {
            let shown = json::shown(&Value::String(symbol.clone()));
            JsonProblem::at(
                &path,
                match json::suggest(symbol, &UNIT_SYMBOLS) {
                    Some(near) => format!("unknown unit {shown}; did you mean \"{near}\"?"),
                    None => format!("unknown unit {shown} (\"mm\", \"cm\", \"m\" or \"in\")"),
                },
            )
        }),
        Some(other) => Err(json::wrong_kind(
            &path,
            "a unit (\"mm\", \"cm\", \"m\" or \"in\")",
            other,
        )),
    }
}

/// The lists of a model file.
type Lists<'v> = (String, LengthUnit, &'v [Value], &'v [Value], &'v [Value]);

/// Checks the top level of a model file and the fields of its relations and skipped
/// steps; returns the sketch, the unit and the lists.
fn read_envelope(v: &Value) -> Result<Lists<'_>, JsonProblem> {
    let object = json::root_object(v, "a model file")?;
    json::check_format(object, MODEL_FORMAT)?;
    json::check_version(object, MODEL_VERSION, false)?;
    let root = JsonPath::root();
    json::check_fields(object, &MODEL_FIELDS, &root)?;
    let sketch = match object.get("sketch") {
        None | Some(Value::Null) => String::new(),
        Some(Value::String(sketch)) => sketch.clone(),
        Some(other) => {
            return Err(json::wrong_kind(
                &root.key("sketch"),
                "a path (a string)",
                other,
            ))
        }
    };
    let unit = read_unit(object)?;
    let list = |field| json::optional_list(object, field, "a list");
    let (primitives, relations, skipped) =
        (list("primitives")?, list("relations")?, list("skipped")?);
    for (field, items, known) in [
        ("primitives", primitives, &[][..]),
        ("relations", relations, &RELATION_FIELDS[..]),
        ("skipped", skipped, &SKIPPED_FIELDS[..]),
    ] {
        for (index, item) in items.iter().enumerate() {
            let path = root.key(field).index(index);
            let Some(entry) = item.as_object() else {
                return Err(json::wrong_kind(&path, "an object", item));
            };
            // A primitive may carry further fields (formats.md §3); its misspelt
            // required fields are caught by `misspelt`.
            if !known.is_empty() {
                json::check_fields(entry, known, &path)?;
            }
        }
    }
    Ok((sketch, unit, primitives, relations, skipped))
}

/// The fields a primitive of some kind may need.
const PRIMITIVE_FIELDS: [&str; 13] = [
    "id",
    "name",
    "kind",
    "center",
    "axis",
    "axes",
    "length",
    "radius",
    "radius_bottom",
    "radius_top",
    "size",
    "radii",
    "spine",
];

/// A missing required field of a primitive named as a typo when one of the primitive's
/// further fields is a near miss for it ("`radius` is missing; `raduis` looks like a
/// typo for it"); other reasons unchanged.
fn misspelt(p: &Value, reason: PrimitiveReadError) -> PrimitiveReadError {
    let missing = match &reason {
        PrimitiveReadError::Number(field)
        | PrimitiveReadError::Vector(field)
        | PrimitiveReadError::Radii(field) => *field,
        PrimitiveReadError::Axes => "axes",
        PrimitiveReadError::Spine => "spine",
        _ => return reason,
    };
    let Some(object) = p.as_object() else {
        return reason;
    };
    if object.contains_key(missing) {
        return reason;
    }
    object
        .keys()
        .filter(|k| !PRIMITIVE_FIELDS.contains(&k.as_str()))
        .find(|k| json::suggest(k, &[missing]).is_some())
        .map_or(reason, |found| PrimitiveReadError::Misspelt {
            missing,
            found: found.clone(),
        })
}

/// One entry of `relations` (the caller adds it to `document`, which checks it).
fn parse_relation(r: &Value, document: &Document) -> Result<Relation, RelationReadError> {
    parse_relation_with(r, document, |m| {
        m.as_u64()
            .and_then(|i| u32::try_from(i).ok())
            .map(PrimitiveId)
    })
}

/// One relation's JSON, its members read by `member` (an id here, a node name in glTF
/// extras). Feature names are read for the kinds of the members' primitives in
/// `document`; a name the member's kind does not have is an error naming both.
pub(crate) fn parse_relation_with(
    r: &Value,
    document: &Document,
    member: impl Fn(&Value) -> Option<PrimitiveId>,
) -> Result<Relation, RelationReadError> {
    let kind: RelationKind = serde_json::from_value(r.get("kind").cloned().unwrap_or_default())
        .map_err(|_| RelationReadError::Kind(r.get("kind").cloned().unwrap_or(Value::Null)))?;
    let members = r
        .get("members")
        .and_then(Value::as_array)
        .ok_or(RelationReadError::Members)?
        .iter()
        .map(|m| member(m).ok_or_else(|| RelationReadError::Member(m.clone())))
        .collect::<Result<Vec<_>, _>>()?;
    let features = match r.get("features") {
        None | Some(Value::Null) => Vec::new(),
        Some(Value::Array(names)) => names
            .iter()
            .enumerate()
            .map(|(k, n)| match n {
                Value::Null => Ok(None),
                Value::String(name) => parse_feature(document, members.get(k).copied(), name),
                other => Err(RelationReadError::FeatureName(other.clone())),
            })
            .collect::<Result<Vec<_>, _>>()?,
        Some(other) => return Err(RelationReadError::Features(other.clone())),
    };
    let mode: Mode = match r.get("mode") {
        None => Mode::Hard,
        Some(m) => {
            serde_json::from_value(m.clone()).map_err(|_| RelationReadError::Mode(m.clone()))?
        }
    };
    Ok(Relation {
        kind,
        members,
        features,
        mode,
        inferred: parse_inferred(r)?,
    })
}

/// The feature called `name` of `member`'s primitive in `document`. A member that is
/// missing (or a name beyond the members) is left to [`Document::add_relation`] to
/// report, and reads as no feature here.
fn parse_feature(
    document: &Document,
    member: Option<PrimitiveId>,
    name: &str,
) -> Result<Option<Feature>, RelationReadError> {
    let Some(kind) = member
        .and_then(|m| document.get(m))
        .map(|p| p.primitive.kind())
    else {
        return Ok(None);
    };
    Feature::from_name(kind, name)
        .map(Some)
        .ok_or_else(|| RelationReadError::UnknownFeature {
            name: name.to_owned(),
            kind: kind.name(),
        })
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::{model_json, parse_model};
    use crate::core::model::{Document, Fit, LengthUnit, Placed, PrimitiveId, Skipped};
    use crate::core::primitive::{Placement, Primitive, PrimitiveKind};
    use crate::core::sketch::StrokeId;
    use crate::core::snap::Verdict;

    /// A same-radius suggestion between primitives 0 and 1, with its evidence.
    fn suggested_same_radius() -> crate::core::model::Relation {
        use crate::core::relation::evidence::{Contact, Evidence, Inferred};
        use crate::core::relation::{Mode, RelationKind};
        use crate::core::{model::PrimitiveId, model::Relation, primitive::Feature};
        Relation {
            kind: RelationKind::SameRadius,
            members: vec![PrimitiveId(0), PrimitiveId(1)],
            features: vec![Some(Feature::Top), Some(Feature::Top)],
            mode: Mode::Suggested,
            inferred: Some(Inferred {
                confidence: 0.42,
                evidence: Evidence {
                    contact: Contact::Apart,
                    hops: 2,
                    repeated: false,
                    across: false,
                    branches: false,
                    closeness: 0.25,
                    noise: 0.004,
                    prior: 0.4,
                },
            }),
        }
    }

    #[test]
    fn relations_round_trip_and_bad_ones_are_named() {
        use crate::core::relation::{Mode, RelationKind};
        use crate::core::{model::PrimitiveId, model::Relation, primitive::Feature};
        let mut document = Document::new();
        for x in [0.0, 50.0] {
            let p = Primitive::from_placement(
                PrimitiveKind::Cylinder,
                &Placement::at(DVec2::new(x, 0.0)),
                40.0,
            );
            document.add(Placed {
                primitive: p,
                fit: Fit::default(),
            });
        }
        let coaxial = Relation {
            kind: RelationKind::Coaxial,
            members: vec![PrimitiveId(0), PrimitiveId(1)],
            features: vec![Some(Feature::Top), Some(Feature::Bottom)],
            mode: Mode::Soft,
            inferred: None,
        };
        let equal = Relation {
            kind: RelationKind::EqualLength,
            members: vec![PrimitiveId(1), PrimitiveId(0)],
            features: Vec::new(),
            mode: Mode::Hard,
            inferred: None,
        };
        let suggested = suggested_same_radius();
        document.add_relation(coaxial.clone()).expect("valid");
        document.add_relation(equal.clone()).expect("valid");
        document.add_relation(suggested.clone()).expect("valid");
        let json = model_json(&document, "s.svg");
        let text = json.to_string();
        assert!(text.contains(r#""features":["top","bottom"]"#), "{text}");
        assert!(
            text.contains(r#""kind":"equal_length","members":[1,0],"mode":"hard""#),
            "{text}"
        );
        assert!(
            text.contains(
                r#""confidence":0.42,"evidence":{"closeness":0.25,"contact":"apart","hops":2"#
            ) && text.contains(r#""mode":"suggested""#),
            "{text}"
        );
        let back = parse_model(text.as_bytes()).expect("reads back");
        assert_eq!(back.document.relations(), &[coaxial, equal, suggested]);
        // Another tool's evidence is not ours: read as none; a confidence of 2 is refused.
        let foreign = text.replace(
            r#""evidence":{"closeness""#,
            r#""evidence":{"why":"x","closeness""#,
        );
        let back = parse_model(foreign.as_bytes()).expect("reads back");
        assert!(back.document.relations()[2].inferred.is_none());
        let bad = text.replace(r#""confidence":0.42"#, r#""confidence":2"#);
        assert!(parse_model(bad.as_bytes()).is_err());
        // A member that does not exist, an unknown kind, a wrong count, a bad mode.
        for (bad, says) in [
            (r#"{"kind":"parallel","members":[0,7]}"#, "no primitive 7"),
            (r#"{"kind":"glued","members":[0,1]}"#, "unknown `kind`"),
            (
                r#"{"kind":"coaxial","members":[0]}"#,
                "relates 2 primitives",
            ),
            (
                r#"{"kind":"coaxial","members":[0,1],"mode":"maybe"}"#,
                "unknown `mode`",
            ),
            (
                r#"{"kind":"coaxial","members":[0,1],"features":["top","lid"]}"#,
                "unknown feature `lid` for a cylinder",
            ),
            (
                r#"{"kind":"coplanar","members":[0,1],"features":["front","top"]}"#,
                "unknown feature `front` for a cylinder",
            ),
        ] {
            let error =
                refused(&text.replacen(r#""relations":["#, &format!(r#""relations":[{bad},"#), 1));
            assert!(
                error.contains("relation 0") && error.contains(says),
                "{error}"
            );
        }
    }

    #[test]
    fn a_fit_with_an_unknown_verdict_or_a_confidence_out_of_range_is_refused() {
        let model = |fit: &str| {
            format!(
                r#"{{"format":"geosnap-model","version":1,"sketch":"a.svg","primitives":[{{"id":0,"kind":"sphere","center":[0,0,0],"radius":5,"fit":{fit}}}],"relations":[]}}"#
            )
        };
        let ok = model(
            r#"{"strokes":[1],"rms":0.1,"verdict":"doubtful","confidence":0.3,"reason":"why"}"#,
        );
        assert!(parse_model(ok.as_bytes()).is_ok());
        for fit in [
            r#"{"strokes":[1],"rms":0.1,"verdict":"great"}"#,
            r#"{"strokes":[1],"rms":0.1,"verdict":"good","confidence":7}"#,
            r#"{"strokes":[1],"rms":0.1,"confidence":"high"}"#,
        ] {
            let err = parse_model(model(fit).as_bytes())
                .expect_err(fit)
                .to_string();
            assert!(err.contains("fit."), "{fit}: {err}");
        }
    }

    #[test]
    fn every_kind_round_trips_through_json() {
        let mut doc = Document::new();
        for (i, kind) in PrimitiveKind::ALL.into_iter().enumerate() {
            let mut place = Placement::at(DVec2::new(10.0 * i as f64, 5.0));
            place.axis = DVec2::new(0.3, -1.0);
            let primitive = Primitive::from_placement(kind, &place, 40.0);
            let fit = Fit {
                strokes: vec![StrokeId(3), StrokeId(4)],
                rms: 0.5,
                ..Fit::default()
            };
            // Half the parts judged by a script step, as `geosnap run` writes them.
            let fit = if i % 2 == 0 {
                Fit {
                    verdict: Some(Verdict::Doubtful),
                    confidence: Some(0.25),
                    reason: Some("only 40 % of its visible outline is drawn".into()),
                    step: Some(i),
                    ..fit
                }
            } else {
                fit
            };
            doc.add(Placed { primitive, fit });
        }
        doc.skipped.push(Skipped {
            step: 7,
            reason: "no strokes".into(),
        });
        // Millimetres and no names are left unsaid.
        let plain = serde_json::to_string(&model_json(&doc, "a.svg")).unwrap();
        assert!(
            !plain.contains(r#""unit""#) && !plain.contains(r#""name""#),
            "{plain}"
        );
        assert_eq!(
            parse_model(plain.as_bytes()).unwrap().document.unit(),
            LengthUnit::Millimetre
        );
        doc.set_unit(LengthUnit::Inch);
        assert!(doc.set_name(PrimitiveId(1), "Pied de la table ⌀ 12 — «gauche» 🪑"));
        assert!(doc.set_name(PrimitiveId(4), "\"quoted\" \\ back"));
        let text = serde_json::to_string(&model_json(&doc, "a.svg")).unwrap();
        assert!(text.contains(r#""unit":"in""#), "{text}");
        let back = parse_model(text.as_bytes()).unwrap();
        assert_eq!(back.sketch, "a.svg");
        assert_eq!(back.document.unit(), LengthUnit::Inch);
        for id in 0..6 {
            let id = PrimitiveId(id);
            assert_eq!(back.document.name(id), doc.name(id), "{id:?}");
        }
        assert_eq!(back.document.skipped, doc.skipped);
        for ((_, a), (_, b)) in doc.primitives().zip(back.document.primitives()) {
            let (pa, pb) = (a.primitive.params(), b.primitive.params());
            let close = pa.iter().zip(&pb).all(|(x, y)| (x - y).abs() < 1e-9);
            // A quaternion and its negative are the same rotation.
            let negated = pa
                .iter()
                .zip(&pb)
                .skip(3)
                .take(4)
                .all(|(x, y)| (x + y).abs() < 1e-9);
            assert!(close || negated, "{pa:?} vs {pb:?}");
            assert_eq!(a.fit, b.fit);
        }
    }

    /// The example of formats.md §3, numbers filled in, with every optional field.
    const FORMATS_EXAMPLE: &str = r#"{
      "format": "geosnap-model",
      "version": 1,
      "sketch": "table.svg",
      "unit": "cm",
      "primitives": [
        { "id": 0, "kind": "cylinder", "center": [1, 2, 3], "axis": [0, 1, 0], "length": 180.0, "radius": 12.0,
          "fit": { "strokes": [1, 2], "rms": 0.5, "verdict": "doubtful", "confidence": 0.4, "reason": "why" },
          "step": 0, "name": "Left leg", "colour": "red" },
        { "id": 1, "kind": "cone", "center": [0, 0, 0], "axis": [0, 1, 0], "length": 120.0, "radius_bottom": 40.0, "radius_top": 15.0 },
        { "id": 2, "kind": "sphere", "center": [0, 0, 0], "radius": 90.0 },
        { "id": 3, "kind": "cuboid", "center": [0, 0, 0], "axes": [[1,0,0],[0,1,0],[0,0,1]], "size": [200.0, 80.0, 120.0] },
        { "id": 4, "kind": "sgc", "center": [0, 0, 0], "axis": [0, 1, 0], "length": 300.0, "radii": [60.0, 55.0, 40.0] },
        { "id": 5, "kind": "bgc", "spine": [[0, 0, 0], [10, 0, 0], [20, 5, 0]], "radii": [20.0, 20.0, 20.0] }
      ],
      "relations": [
        { "kind": "parallel", "members": [0, 1], "mode": "hard" },
        { "kind": "concentric", "members": [0, 1], "features": ["top", "bottom"], "mode": "soft",
          "confidence": 0.8, "evidence": { "anything": "free-form" } }
      ],
      "skipped": [ { "step": 3, "reason": "no strokes near it" } ]
    }"#;

    /// Strictness refuses nothing formats.md documents: optional fields, a primitive's
    /// further fields, free-form evidence.
    #[test]
    fn the_example_of_formats_md_with_every_optional_field_reads() {
        let model = parse_model(FORMATS_EXAMPLE.as_bytes()).expect("the documented example reads");
        assert_eq!(model.document.len(), 6);
        assert_eq!(model.document.unit(), LengthUnit::Centimetre);
        assert_eq!(model.document.name(PrimitiveId(0)), Some("Left leg"));
        assert_eq!(model.document.name(PrimitiveId(1)), None);
        assert_eq!(model.document.relations().len(), 2);
        assert_eq!(model.document.skipped.len(), 1);
    }

    /// Issue 19, case 4: typos in a model are errors naming the field, its position and
    /// the field meant.
    #[test]
    fn unknown_fields_are_refused_with_their_place_and_a_suggestion() {
        for (from, to, says) in [
            (
                r#""skipped":"#,
                r#""skiped":"#,
                "skiped: unknown field `skiped`; did you mean `skipped`?",
            ),
            (
                r#""mode": "hard""#,
                r#""mdoe": "hard""#,
                "relations[0].mdoe: unknown field `mdoe`; did you mean `mode`?",
            ),
            (
                r#""rms": 0.5"#,
                r#""rsm": 0.5"#,
                "primitive 0: `fit`: unknown field `rsm`; did you mean `rms`?",
            ),
            (
                r#""radius": 90.0"#,
                r#""raduis": 90.0"#,
                "primitive 2: `radius` is missing; `raduis` looks like a typo for it",
            ),
            (
                r#""step": 3, "reason""#,
                r#""step": 3, "reasons""#,
                "skipped[0].reasons: unknown field `reasons`; did you mean `reason`?",
            ),
            (
                r#""unit": "cm""#,
                r#""units": "cm""#,
                "units: unknown field `units`; did you mean `unit`?",
            ),
            (
                r#""unit": "cm""#,
                r#""unit": "CM""#,
                r#"unit: unknown unit "CM"; did you mean "cm"?"#,
            ),
            (
                r#""unit": "cm""#,
                r#""unit": "furlong""#,
                r#"unit: unknown unit "furlong" ("mm", "cm", "m" or "in")"#,
            ),
            (r#""unit": "cm""#, r#""unit": 10"#, "unit: must be a unit"),
            (
                r#""name": "Left leg""#,
                r#""name": ["Left", "leg"]"#,
                "primitive 0: `name` must be a text",
            ),
        ] {
            let error = refused(&FORMATS_EXAMPLE.replacen(from, to, 1));
            assert!(
                error.starts_with("line ") && error.contains(says),
                "{to}: {error}"
            );
        }
    }

    /// Why a model text is refused (it must be).
    fn refused(text: &str) -> String {
        parse_model(text.as_bytes())
            .expect_err("the model is refused")
            .to_string()
    }

    /// Issue 19, case 9: a wrong version says which was found; wrong shapes in our words.
    #[test]
    fn wrong_versions_and_shapes_say_what_was_found() {
        let newer = FORMATS_EXAMPLE.replacen(r#""version": 1"#, r#""version": 3"#, 1);
        let error = refused(&newer);
        assert!(error.contains("version 3 is not supported"), "{error}");
        let text = FORMATS_EXAMPLE.replacen(r#""version": 1"#, r#""version": "one""#, 1);
        let error = refused(&text);
        assert!(error.contains(r#"version "one" is not valid"#), "{error}");
        let error = refused(r#"["geosnap-model", 1]"#);
        assert!(
            error.contains("a model file must be a JSON object"),
            "{error}"
        );
        let error = refused(r#"{"format": "geosnap-script", "version": 1, "sketch": "a.svg"}"#);
        assert!(error.contains("this is a placement script"), "{error}");
        let members: Vec<String> = (0..100_000).map(|i| i.to_string()).collect();
        let text = FORMATS_EXAMPLE.replacen(
            r#""members": [0, 1], "mode": "hard""#,
            &format!(r#""members": [{}], "mode": "hard""#, members.join(",")),
            1,
        );
        let error = refused(&text);
        assert!(error.len() < 300, "{error}");
    }

    #[test]
    fn invalid_primitives_are_named() {
        let bad = br#"{"format":"geosnap-model","version":1,"sketch":"s","primitives":[
            {"id":4,"kind":"cylinder","center":[0,0,0],"axis":[0,2,0],"length":1,"radius":1}]}"#;
        let err = parse_model(bad).unwrap_err().to_string();
        assert!(err.contains("primitive 4") && err.contains("unit"), "{err}");
        assert!(parse_model(b"[]").is_err());
        let zero = br#"{"format":"geosnap-model","version":1,"sketch":"s","primitives":[
            {"id":1,"kind":"sphere","center":[0,0,0],"radius":0}]}"#;
        assert!(parse_model(zero).is_err());
    }

    /// A name is free text: a long or odd one is cleaned and cut, never refused; an
    /// empty one is no name.
    #[test]
    fn odd_names_are_cleaned_not_refused() {
        let model = |name: &str| {
            format!(
                r#"{{"format":"geosnap-model","version":1,"primitives":[{{"id":3,"kind":"sphere","center":[0,0,0],"radius":5,"name":{name}}}]}}"#
            )
        };
        let long = serde_json::to_string(&"ж".repeat(10_000)).unwrap();
        for (name, expected) in [
            (
                long.as_str(),
                Some("ж".repeat(crate::core::model::MAX_NAME_CHARS)),
            ),
            (r#""  \n ""#, None),
            (r#""""#, None),
            ("null", None),
            (r#""tab\there""#, Some("tab here".to_owned())),
        ] {
            let back = parse_model(model(name).as_bytes()).expect(name);
            assert_eq!(
                back.document.name(PrimitiveId(3)).map(str::to_owned),
                expected,
                "{name}"
            );
        }
    }
}
