//! glTF 2.0 export of a model (design.md §7), and the reader of what it stores in
//! `extras`.
//!
//! [`export_gltf`] writes a [`Document`] as `.glb` (one binary file: the JSON chunk and a
//! BIN chunk) or `.gltf` (one JSON file whose only buffer is embedded as a base64
//! `data:` URI, so the export stays a single file written atomically; no side-car
//! `.bin`). The format follows the file's extension. The document structure is built
//! with the `gltf-json` crate; the binary layout (GLB header, chunks, padding) is ours.
//!
//! # Conventions
//!
//! - **Units and axes.** glTF is in metres, right-handed, +Y up, and an asset's front
//!   faces +Z. geosnap's model space (formats.md §1) is right-handed with x to the right,
//!   y up and z towards the viewer, so the drawing's view is the model's front and the
//!   axes carry over unchanged: a model point p becomes `s · (p + o)` with the scale
//!   `s` = [`ExportSettings::metres_per_unit`] (default 0.001: one sketch unit is one
//!   millimetre) and the origin offset `o` of [`Origin`]. The model stays upright and no
//!   handedness flip is needed.
//! - **Nodes.** The scene has one root node, `geosnap_model`, whose translation is
//!   `s · o`; under it one child node per primitive in id order, named by the name its
//!   designer gave it, else by kind and id ([`node_names`]: `Left leg`, `cylinder_3`,
//!   `sgc_5`, …; every node's name is its own). A child's translation and rotation place
//!   its mesh, which is in the primitive's local frame (scale 1): the axis of a cylinder,
//!   cone or SGC is local +Y and its centre the origin; a cuboid's local axes are its
//!   edges; a sphere is centred; a BGC's frame has its spine plane as local z = 0 and its
//!   end-to-end chord along local +Y.
//! - **Meshes** come from [`Primitive::mesh`]: counter-clockwise front faces seen from
//!   outside, smooth normals on curved sides, separate vertices with flat normals on
//!   caps and box faces (sharp edges), caps closing cylinders, cones and both kinds of
//!   generalized cylinder. Positions and normals are `f32`, indices `u16` (`u32` for a
//!   mesh of more than 65 535 vertices), each in its own 4-byte aligned buffer view; a position accessor's `min`/`max` are computed from
//!   the `f32` values written.
//! - **Materials.** One PBR metallic-roughness material per primitive, named like its
//!   node, dielectric, with a base colour of its own (hues spaced by the golden ratio).
//! - **`extras`** keep the editable meaning. Each child node: `id`, `kind` and the
//!   parameters under the model file's field names (formats.md §3, `name` included when
//!   the part has one), lengths in metres,
//!   in the root node's frame (model space times `s`, before the origin offset). The
//!   root node: `format` ([`EXTRAS_FORMAT`]), `version`, `metres_per_unit`,
//!   `origin_offset_m` (its translation) and `relations`, each with `kind`, `members`
//!   (child node names), `features` (when any is named) and `mode`.
//!   [`import_gltf_extras`] reads them back into a [`Document`].
//!
//! An empty model gives a valid file whose scene is empty: it holds only the root node,
//! without children or mesh, still carrying the model-level `extras`; the
//! [`ExportReport`] has a warning. A primitive with a non-finite parameter or a
//! non-positive size is an [`ExportError`] naming it, and nothing is written. The file
//! is replaced atomically ([`write_atomic`]).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use glam::{DMat3, DQuat, DVec3};
use gltf_json as gj;
use gltf_json::validation::{Checked, USize64};
use serde_json::{json, Map, Value};

use crate::core::model::{Document, Fit, Placed, PrimitiveId};
use crate::core::primitive::{Primitive, PrimitiveError, PrimitiveKind};
use crate::io::atomic::write_atomic;
use crate::io::model_file::{parse_primitive, parse_relation_with, primitive_json, relation_json};

/// Metres per sketch unit unless set otherwise: one unit is one millimetre.
pub const DEFAULT_METRES_PER_UNIT: f64 = 0.001;
/// Segments around each circle unless set otherwise.
pub const DEFAULT_SEGMENTS: usize = 32;
/// The fewest segments around a circle.
pub const MIN_SEGMENTS: usize = 3;
/// The most segments around a circle (a bound on the file size, not on quality).
pub const MAX_SEGMENTS: usize = 1024;
/// The `format` value of the model-level `extras`.
pub const EXTRAS_FORMAT: &str = "geosnap-gltf";
/// The version of the `extras` this build writes and reads.
pub const EXTRAS_VERSION: u64 = 1;
/// The name of the root node.
pub const ROOT_NAME: &str = "geosnap_model";

/// Where the exported model's origin is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Origin {
    /// The model stands on the ground plane at the origin: its bounding box is centred
    /// in x and z and its lowest point is at y = 0. Viewers frame it at once.
    #[default]
    Ground,
    /// Model space's own origin (no offset).
    Model,
}

/// How a model is exported, checked when made ([`ExportSettings::new`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ExportSettings {
    metres_per_unit: f64,
    segments: usize,
    origin: Origin,
}

impl Default for ExportSettings {
    fn default() -> Self {
        Self {
            metres_per_unit: DEFAULT_METRES_PER_UNIT,
            segments: DEFAULT_SEGMENTS,
            origin: Origin::default(),
        }
    }
}

impl ExportSettings {
    /// Settings of `metres_per_unit` metres per sketch unit (finite and positive),
    /// `segments` segments around each circle ([`MIN_SEGMENTS`] to [`MAX_SEGMENTS`]; a
    /// sphere gets half as many rings) and the `origin`.
    ///
    /// # Errors
    ///
    /// [`ExportError::InvalidSetting`] naming the first value out of range.
    pub fn new(metres_per_unit: f64, segments: usize, origin: Origin) -> Result<Self, ExportError> {
        let settings = Self {
            metres_per_unit,
            segments,
            origin,
        };
        settings.validate()?;
        Ok(settings)
    }

    /// Metres per sketch unit (default [`DEFAULT_METRES_PER_UNIT`]).
    pub fn metres_per_unit(&self) -> f64 {
        self.metres_per_unit
    }

    /// Segments around each circle (default [`DEFAULT_SEGMENTS`]).
    pub fn segments(&self) -> usize {
        self.segments
    }

    /// Where the origin goes.
    pub fn origin(&self) -> Origin {
        self.origin
    }

    /// Checks every field (settings made by [`ExportSettings::new`] always pass).
    ///
    /// # Errors
    ///
    /// [`ExportError::InvalidSetting`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ExportError> {
        if !(self.metres_per_unit.is_finite() && self.metres_per_unit > 0.0) {
            return Err(ExportError::InvalidSetting {
                name: "metres_per_unit",
                value: self.metres_per_unit,
                expected: "a finite number above 0",
            });
        }
        if !(MIN_SEGMENTS..=MAX_SEGMENTS).contains(&self.segments) {
            return Err(ExportError::InvalidSetting {
                name: "segments",
                value: self.segments as f64,
                expected: "3 to 1024",
            });
        }
        Ok(())
    }
}

/// The two encodings of glTF 2.0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GltfFormat {
    /// Binary glTF: one `.glb` file.
    Glb,
    /// JSON glTF: one `.gltf` file with the buffer embedded as a base64 data URI.
    Gltf,
}

impl GltfFormat {
    /// The format a path's extension asks for (`.glb` or `.gltf`, any case).
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "glb" => Some(Self::Glb),
            "gltf" => Some(Self::Gltf),
            _ => None,
        }
    }

    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Glb => "glb",
            Self::Gltf => "gltf",
        }
    }
}

/// What an export wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportReport {
    /// The encoding.
    pub format: GltfFormat,
    /// The file's size in bytes.
    pub bytes: usize,
    /// The number of primitive nodes (the root not counted).
    pub nodes: usize,
    /// The number of triangles over all meshes.
    pub triangles: usize,
    /// Things worth telling the user that did not stop the export (an empty model).
    pub warnings: Vec<String>,
}

/// Why a model could not be exported.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExportError {
    /// An [`ExportSettings`] field is out of range.
    #[error("invalid export setting {name} = {value}: expected {expected}")]
    InvalidSetting {
        /// The field.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// What the field accepts.
        expected: &'static str,
    },
    /// The path ends neither in `.glb` nor in `.gltf`.
    #[error("cannot tell the glTF format from the file name (expected .glb or .gltf): {}", path.display())]
    UnknownExtension {
        /// The path.
        path: PathBuf,
    },
    /// A primitive cannot be meshed: a non-finite parameter, a non-positive size, a
    /// zero axis (see [`Primitive::validate`]). Field names show without backticks.
    #[error("primitive {node}: {}", .reason.to_string().replace('`', ""))]
    InvalidPrimitive {
        /// Its node name (`cylinder_3`).
        node: String,
        /// What is wrong.
        reason: PrimitiveError,
    },
    /// A valid primitive gave an empty mesh.
    #[error("primitive {node}: its mesh is empty")]
    EmptyMesh {
        /// Its node name (`cylinder_3`).
        node: String,
    },
    /// The model does not fit glTF's limits (`f32` coordinates, a 4 GiB GLB).
    #[error("the model is too large for glTF: {reason}")]
    TooLarge {
        /// Which limit.
        reason: String,
    },
    /// The glTF JSON could not be encoded.
    #[error("cannot encode the glTF json")]
    Json {
        /// The encoder's error.
        #[source]
        source: serde_json::Error,
    },
    /// Writing the file failed; a previous file at the path is untouched.
    #[error("cannot write {}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
}

/// Why the geosnap `extras` of a glTF file could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImportError {
    /// The file could not be read.
    #[error("cannot read {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The data is not a well-formed GLB container.
    #[error("malformed glb: {0}")]
    Glb(String),
    /// The glTF JSON is malformed.
    #[error("malformed glTF json")]
    Json {
        /// The parser's error.
        #[source]
        source: serde_json::Error,
    },
    /// The file holds no geosnap `extras`, or they are invalid.
    #[error("geosnap extras: {0}")]
    Extras(String),
}

/// A model read back from the `extras` of an exported file.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedModel {
    /// The primitives (in model units, under their ids; fits are empty) and relations.
    pub document: Document,
    /// The scale the file was written with.
    pub metres_per_unit: f64,
}

/// The name of an unnamed primitive's node, mesh and material: kind and id,
/// `cylinder_3`.
pub fn node_name(kind: PrimitiveKind, id: PrimitiveId) -> String {
    format!("{}_{}", kind.name(), id.0)
}

/// The node (and mesh and material) name of every primitive of `document`, by id: the
/// name its designer gave it ([`Document::name`]), else its kind and id ([`node_name`]).
/// Relations in the extras name their members by node, so no two nodes share a name: a
/// given name that another node (or the root) already has takes the part's id after it
/// (two parts called `Leg` become `Leg` and `Leg_4`).
pub fn node_names(document: &Document) -> BTreeMap<PrimitiveId, String> {
    let mut taken: BTreeSet<String> = document
        .primitives()
        .filter(|(id, _)| document.name(*id).is_none())
        .map(|(id, p)| node_name(p.primitive.kind(), id))
        .collect();
    taken.insert(ROOT_NAME.to_owned());
    let mut names = BTreeMap::new();
    for (id, placed) in document.primitives() {
        let default = node_name(placed.primitive.kind(), id);
        let name = match document.name(id) {
            None => default,
            Some(given) => [given.to_owned(), format!("{given}_{}", id.0)]
                .into_iter()
                // One more candidate than names taken: one of them is free.
                .chain((0..=taken.len()).map(|n| format!("{default}_{n}")))
                .find(|name| !taken.contains(name))
                .unwrap_or(default),
        };
        taken.insert(name.clone());
        names.insert(id, name);
    }
    names
}

/// Exports a model as glTF 2.0 to `path`, `.glb` or `.gltf` by its extension (module
/// docs: conventions, what `extras` hold).
///
/// # Errors
///
/// [`ExportError`]: a bad setting, an unknown extension, an invalid primitive (nothing
/// is written then), or a failed write (the previous file stays as it was).
///
/// # Examples
///
/// ```
/// use geosnap::core::model::{Document, Fit, Placed};
/// use geosnap::core::primitive::{Primitive, Sphere};
/// use geosnap::io::gltf::{export_gltf, import_gltf_extras, ExportSettings};
///
/// let mut model = Document::new();
/// model.add(Placed {
///     primitive: Primitive::Sphere(Sphere { center: glam::DVec3::ZERO, radius: 50.0 }),
///     fit: Fit::default(),
/// });
/// let path = std::env::temp_dir().join(format!("geosnap-doc-{}.glb", std::process::id()));
/// let report = export_gltf(&model, &path, &ExportSettings::default())?;
/// assert_eq!(report.nodes, 1);
/// assert!(report.warnings.is_empty());
/// // The parameters come back from the extras, in model units.
/// let back = import_gltf_extras(&path)?;
/// assert_eq!(back.document.len(), 1);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn export_gltf(
    document: &Document,
    path: impl AsRef<Path>,
    settings: &ExportSettings,
) -> Result<ExportReport, ExportError> {
    let path = path.as_ref();
    settings.validate()?;
    let format = GltfFormat::from_path(path).ok_or_else(|| ExportError::UnknownExtension {
        path: path.to_owned(),
    })?;
    let (bytes, report) = encode_gltf(document, format, settings)?;
    write_atomic(path, &bytes).map_err(|source| ExportError::Write {
        path: path.to_owned(),
        source,
    })?;
    Ok(report)
}

/// Encodes a model as glTF 2.0 in memory, as [`export_gltf`] writes it.
///
/// # Errors
///
/// [`ExportError`] as [`export_gltf`], but for the path.
pub fn encode_gltf(
    document: &Document,
    format: GltfFormat,
    settings: &ExportSettings,
) -> Result<(Vec<u8>, ExportReport), ExportError> {
    settings.validate()?;
    let s = settings.metres_per_unit;
    let mut names = node_names(document);
    let parts = document
        .primitives()
        .map(|(id, placed)| {
            let node = names.remove(&id).unwrap_or_default();
            let given = document.name(id).map(str::to_owned);
            Part::new(id, (node, given), &placed.primitive, settings.segments)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let offset = match settings.origin {
        Origin::Model => DVec3::ZERO,
        Origin::Ground => ground_offset(&parts),
    };

    let mut out = Builder::default();
    let mut children = Vec::with_capacity(parts.len());
    let mut triangles = 0;
    for (index, part) in parts.iter().enumerate() {
        triangles += part.indices.len() / 3;
        children.push(out.part(part, index, s)?);
    }
    // The root node is always there, so the scene is never without nodes (glTF allows
    // that, but the `gltf` crate, and so Rust viewers, cannot read it); an empty model's
    // root has neither children nor a mesh.
    let root = out.root.push(gj::Node {
        name: Some(ROOT_NAME.to_owned()),
        children: (!children.is_empty()).then_some(children),
        translation: Some(f32s(offset * s, "the origin offset")?),
        extras: raw(&model_extras(document, &parts, s, offset * s))?,
        ..gj::Node::default()
    });
    let scene = gj::Scene {
        extensions: None,
        extras: None,
        name: Some("geosnap".to_owned()),
        nodes: vec![root],
    };
    let scene = out.root.push(scene);
    out.root.scene = Some(scene);
    out.root.asset.generator = Some(format!("geosnap {}", env!("CARGO_PKG_VERSION")));

    let bytes = out.finish(format)?;
    let mut warnings = Vec::new();
    if parts.is_empty() {
        warnings.push("the model has no primitives: wrote an empty scene".to_owned());
    }
    let report = ExportReport {
        format,
        bytes: bytes.len(),
        nodes: parts.len(),
        triangles,
        warnings,
    };
    Ok((bytes, report))
}

/// One primitive ready to write: its node name, validated primitive, frame and mesh in
/// model units (positions relative to the frame, not yet scaled).
struct Part {
    id: PrimitiveId,
    /// The node's name ([`node_names`]).
    name: String,
    /// The name the designer gave the part, if any.
    given: Option<String>,
    primitive: Primitive,
    center: DVec3,
    rotation: DQuat,
    /// Local positions (model units) and unit normals.
    positions: Vec<DVec3>,
    normals: Vec<DVec3>,
    indices: Vec<u32>,
    /// Model-space bounds of the mesh.
    bounds: (DVec3, DVec3),
}

impl Part {
    fn new(
        id: PrimitiveId,
        (name, given): (String, Option<String>),
        primitive: &Primitive,
        segments: usize,
    ) -> Result<Self, ExportError> {
        let primitive = primitive.normalized();
        primitive
            .validate()
            .map_err(|reason| ExportError::InvalidPrimitive {
                node: name.clone(),
                reason,
            })?;
        let (center, rotation) = frame(&primitive);
        let mesh = primitive.mesh(segments);
        let bounds = mesh
            .bounds()
            .ok_or_else(|| ExportError::EmptyMesh { node: name.clone() })?;
        let to_local = rotation.inverse();
        Ok(Self {
            id,
            name,
            given,
            center,
            rotation,
            positions: mesh
                .positions
                .iter()
                .map(|p| to_local * (*p - center))
                .collect(),
            normals: mesh
                .normals
                .iter()
                .map(|n| (to_local * *n).normalize_or_zero())
                .collect(),
            indices: mesh.triangles.iter().flatten().copied().collect(),
            bounds,
            primitive,
        })
    }
}

/// The offset that puts the model on the ground at the origin (see [`Origin::Ground`]).
fn ground_offset(parts: &[Part]) -> DVec3 {
    let Some((lo, hi)) = parts
        .iter()
        .map(|p| p.bounds)
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
    else {
        return DVec3::ZERO;
    };
    let mid = (lo + hi) / 2.0;
    // `+ 0.0` turns a −0 into 0 so the file does not show "-0.0".
    DVec3::new(-mid.x, -lo.y, -mid.z) + 0.0
}

/// The node frame of a (checked) primitive in model space: its centre and the rotation
/// from its local frame (module docs) to model space.
fn frame(p: &Primitive) -> (DVec3, DQuat) {
    match p {
        Primitive::Cylinder(c) => (c.center, DQuat::from_rotation_arc(DVec3::Y, c.axis)),
        Primitive::Cone(c) => (c.center, DQuat::from_rotation_arc(DVec3::Y, c.axis)),
        Primitive::Sgc(s) => (s.center, DQuat::from_rotation_arc(DVec3::Y, s.axis)),
        Primitive::Sphere(s) => (s.center, DQuat::IDENTITY),
        Primitive::Cuboid(b) => (b.center, b.rotation),
        Primitive::Bgc(b) => {
            let z = b.plane_normal;
            let (first, last) = (b.spine[0], b.spine[b.spine.len() - 1]);
            let chord = last - first;
            let y = (chord - z * chord.dot(z))
                .try_normalize()
                .unwrap_or_else(|| z.any_orthonormal_vector());
            let x = y.cross(z);
            let rotation = DQuat::from_mat3(&DMat3::from_cols(x, y, z)).normalize();
            (p.center(), rotation)
        }
    }
}

/// `v` as `f32`, or [`ExportError::TooLarge`] when it does not fit.
fn f32s(v: DVec3, what: &str) -> Result<[f32; 3], ExportError> {
    let out = [v.x as f32, v.y as f32, v.z as f32];
    if out.iter().all(|c| c.is_finite()) {
        Ok(out)
    } else {
        Err(ExportError::TooLarge {
            reason: format!(
                "{what} does not fit in f32: [{:.3e}, {:.3e}, {:.3e}]",
                v.x, v.y, v.z
            ),
        })
    }
}

/// A value as glTF `extras`.
fn raw(value: &Value) -> Result<gj::Extras, ExportError> {
    serde_json::value::to_raw_value(value)
        .map(Some)
        .map_err(|source| ExportError::Json { source })
}

/// The model-level extras: format, scale, offset and relations (members named by
/// their parts' nodes).
fn model_extras(document: &Document, parts: &[Part], s: f64, offset_m: DVec3) -> Value {
    let name_of = |id: PrimitiveId| {
        parts
            .iter()
            .find(|p| p.id == id)
            .map_or_else(|| format!("missing_{}", id.0), |p| p.name.clone())
    };
    let relations: Vec<Value> = document
        .relations()
        .iter()
        .map(|r| relation_json(r, |m| json!(name_of(m))))
        .collect();
    json!({
        "format": EXTRAS_FORMAT,
        "version": EXTRAS_VERSION,
        "metres_per_unit": s,
        "origin_offset_m": [offset_m.x, offset_m.y, offset_m.z],
        "relations": relations,
    })
}

/// A primitive's node extras: its id, kind and parameters in metres.
fn node_extras(part: &Part, s: f64) -> Value {
    let mut map = Map::new();
    map.insert("id".into(), json!(part.id.0));
    map.extend(primitive_json(&part.primitive.transformed(DVec3::ZERO, s)));
    if let Some(given) = &part.given {
        map.insert("name".into(), json!(given));
    }
    Value::Object(map)
}

/// A material colour per primitive index: hues spaced by the golden ratio at fixed
/// saturation and value, as linear RGB (glTF's base colour is linear).
fn colour(index: usize) -> [f32; 4] {
    const GOLDEN: f64 = 0.618_033_988_749_895;
    let hue = (0.08 + GOLDEN * index as f64).fract() * 6.0;
    let (s, v) = (0.55, 0.9);
    let c = v * s;
    let x = c * (1.0 - (hue % 2.0 - 1.0).abs());
    let (r, g, b) = match hue as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    let linear = |srgb: f64| {
        if srgb <= 0.040_45 {
            srgb / 12.92
        } else {
            ((srgb + 0.055) / 1.055).powf(2.4)
        }
    };
    [
        linear(r + m) as f32,
        linear(g + m) as f32,
        linear(b + m) as f32,
        1.0,
    ]
}

/// The glTF document and its binary buffer under construction.
#[derive(Default)]
struct Builder {
    root: gj::Root,
    bin: Vec<u8>,
}

impl Builder {
    /// Appends `bytes` as a 4-byte aligned buffer view.
    fn view(&mut self, bytes: &[u8], target: gj::buffer::Target) -> gj::Index<gj::buffer::View> {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(gj::buffer::View {
            buffer: gj::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: Some(Checked::Valid(target)),
            extensions: None,
            extras: None,
        })
    }

    /// An accessor of `count` elements over `bytes` (one buffer view of its own).
    fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        (component, kind): (gj::accessor::ComponentType, gj::accessor::Type),
        bounds: Option<(Value, Value)>,
    ) -> gj::Index<gj::Accessor> {
        let target = match kind {
            gj::accessor::Type::Scalar => gj::buffer::Target::ElementArrayBuffer,
            _ => gj::buffer::Target::ArrayBuffer,
        };
        let view = self.view(bytes, target);
        let (min, max) = bounds.unzip();
        self.root.push(gj::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Checked::Valid(gj::accessor::GenericComponentType(component)),
            extensions: None,
            extras: None,
            type_: Checked::Valid(kind),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// A `VEC3` float vertex attribute, with `min`/`max` (of these `f32` values) when
    /// `bounds` is set.
    fn vec3(&mut self, data: &[[f32; 3]], bounds: bool) -> gj::Index<gj::Accessor> {
        let bytes: Vec<u8> = data
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        let bounds = bounds.then(|| {
            let mut lo = [f32::INFINITY; 3];
            let mut hi = [f32::NEG_INFINITY; 3];
            for p in data {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            let value = |v: [f32; 3]| json!(v.map(f64::from));
            (value(lo), value(hi))
        });
        let layout = (gj::accessor::ComponentType::F32, gj::accessor::Type::Vec3);
        self.accessor(&bytes, data.len(), layout, bounds)
    }

    /// Triangle indices: a `SCALAR` accessor, `u16` when every index fits (a mesh of at
    /// most 65 535 vertices, as at the usual tessellations), else `u32`.
    fn indices(&mut self, indices: &[u32]) -> gj::Index<gj::Accessor> {
        // 65 535 itself would be the primitive-restart value.
        let short = indices.iter().all(|i| *i < u32::from(u16::MAX));
        let (bytes, component): (Vec<u8>, _) = if short {
            let bytes = indices
                .iter()
                .flat_map(|i| (*i as u16).to_le_bytes())
                .collect();
            (bytes, gj::accessor::ComponentType::U16)
        } else {
            let bytes = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
            (bytes, gj::accessor::ComponentType::U32)
        };
        let layout = (component, gj::accessor::Type::Scalar);
        self.accessor(&bytes, indices.len(), layout, None)
    }

    /// Adds one primitive's accessors, material, mesh and node; returns the node.
    fn part(
        &mut self,
        part: &Part,
        index: usize,
        s: f64,
    ) -> Result<gj::Index<gj::Node>, ExportError> {
        let positions = part
            .positions
            .iter()
            .map(|p| f32s(*p * s, &part.name))
            .collect::<Result<Vec<_>, _>>()?;
        let normals: Vec<[f32; 3]> = part
            .normals
            .iter()
            .map(|n| n.as_vec3().to_array())
            .collect();
        let position = self.vec3(&positions, true);
        let normal = self.vec3(&normals, false);
        let indices = self.indices(&part.indices);
        let material = self.root.push(gj::Material {
            name: Some(part.name.clone()),
            pbr_metallic_roughness: gj::material::PbrMetallicRoughness {
                base_color_factor: gj::material::PbrBaseColorFactor(colour(index)),
                metallic_factor: gj::material::StrengthFactor(0.0),
                roughness_factor: gj::material::StrengthFactor(0.6),
                ..Default::default()
            },
            ..Default::default()
        });
        let attributes = BTreeMap::from([
            (Checked::Valid(gj::mesh::Semantic::Positions), position),
            (Checked::Valid(gj::mesh::Semantic::Normals), normal),
        ]);
        let mesh = self.root.push(gj::Mesh {
            extensions: None,
            extras: None,
            name: Some(part.name.clone()),
            primitives: vec![gj::mesh::Primitive {
                attributes,
                extensions: None,
                extras: None,
                indices: Some(indices),
                material: Some(material),
                mode: Checked::Valid(gj::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        });
        let q = part.rotation.as_quat();
        Ok(self.root.push(gj::Node {
            name: Some(part.name.clone()),
            mesh: Some(mesh),
            translation: Some(f32s(part.center * s, &part.name)?),
            rotation: Some(gj::scene::UnitQuaternion([q.x, q.y, q.z, q.w])),
            extras: raw(&node_extras(part, s))?,
            ..gj::Node::default()
        }))
    }

    /// Adds the buffer and encodes the file.
    fn finish(mut self, format: GltfFormat) -> Result<Vec<u8>, ExportError> {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        if !self.bin.is_empty() {
            let uri = match format {
                GltfFormat::Glb => None,
                GltfFormat::Gltf => Some(format!(
                    "data:application/octet-stream;base64,{}",
                    base64(&self.bin)
                )),
            };
            self.root.push(gj::Buffer {
                byte_length: USize64::from(self.bin.len()),
                name: None,
                uri,
                extensions: None,
                extras: None,
            });
        }
        match format {
            GltfFormat::Gltf => {
                let mut text = self
                    .root
                    .to_vec_pretty()
                    .map_err(|source| ExportError::Json { source })?;
                text.push(b'\n');
                Ok(text)
            }
            GltfFormat::Glb => {
                let json = self
                    .root
                    .to_vec()
                    .map_err(|source| ExportError::Json { source })?;
                glb(json, &self.bin)
            }
        }
    }
}

/// The GLB container: a 12-byte header, the JSON chunk padded with spaces and, when
/// there is a buffer, the BIN chunk padded with zeros, each chunk 4-byte aligned.
fn glb(mut json: Vec<u8>, bin: &[u8]) -> Result<Vec<u8>, ExportError> {
    json.resize(json.len().next_multiple_of(4), b' ');
    let bin_chunk = if bin.is_empty() {
        0
    } else {
        8 + bin.len().next_multiple_of(4)
    };
    let total = 12 + 8 + json.len() + bin_chunk;
    let too_large = || ExportError::TooLarge {
        reason: format!("{total} bytes exceed the 4 GiB of a glb"),
    };
    let len32 = |n: usize| u32::try_from(n).map_err(|_| too_large());
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&len32(total)?.to_le_bytes());
    out.extend_from_slice(&len32(json.len())?.to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    if !bin.is_empty() {
        let padded = bin.len().next_multiple_of(4);
        out.extend_from_slice(&len32(padded)?.to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(bin);
        out.resize(total, 0);
    }
    Ok(out)
}

/// Standard base64 (RFC 4648, with padding).
fn base64(data: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(data.len().div_ceil(3) * 4);
    for chunk in data.chunks(3) {
        let byte = |i: usize| u32::from(chunk.get(i).copied().unwrap_or(0));
        let n = (byte(0) << 16) | (byte(1) << 8) | byte(2);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(char::from(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Reads the model back from the `extras` of a file written by [`export_gltf`].
///
/// # Errors
///
/// [`ImportError`] when the file cannot be read, is not glTF, or holds no valid geosnap
/// extras.
pub fn import_gltf_extras(path: impl AsRef<Path>) -> Result<ImportedModel, ImportError> {
    let path = path.as_ref();
    let data = std::fs::read(path).map_err(|source| ImportError::Read {
        path: path.to_owned(),
        source,
    })?;
    parse_gltf_extras(&data)
}

/// The JSON of a glTF file: the whole file, or the JSON chunk of a GLB.
fn json_chunk(data: &[u8]) -> Result<&[u8], ImportError> {
    if !data.starts_with(b"glTF") {
        return Ok(data);
    }
    let word = |at: usize| {
        data.get(at..at + 4)
            .and_then(|b| b.try_into().ok())
            .map(u32::from_le_bytes)
            .ok_or_else(|| ImportError::Glb(format!("truncated at byte {at}")))
    };
    if word(4)? != 2 {
        return Err(ImportError::Glb("not glTF version 2".to_owned()));
    }
    let length = word(12)? as usize;
    if data.get(16..20) != Some(b"JSON".as_slice()) {
        return Err(ImportError::Glb("the first chunk is not JSON".to_owned()));
    }
    data.get(20..20 + length)
        .ok_or_else(|| ImportError::Glb("the JSON chunk is truncated".to_owned()))
}

/// Parses the bytes of a `.glb` or `.gltf` file as [`import_gltf_extras`] does.
///
/// # Errors
///
/// [`ImportError`] as [`import_gltf_extras`].
pub fn parse_gltf_extras(data: &[u8]) -> Result<ImportedModel, ImportError> {
    let root =
        gj::Root::from_slice(json_chunk(data)?).map_err(|source| ImportError::Json { source })?;
    let bad = |reason: String| ImportError::Extras(reason);
    let extras_of = |extras: &gj::Extras| -> Result<Value, ImportError> {
        let text = extras.as_ref().map_or("null", |r| r.get());
        serde_json::from_str(text).map_err(|source| ImportError::Json { source })
    };
    let scene = root
        .scene
        .and_then(|i| root.scenes.get(i.value()))
        .or_else(|| root.scenes.first())
        .ok_or_else(|| bad("the file has no scene".to_owned()))?;
    let [node] = scene.nodes.as_slice() else {
        return Err(bad(
            "the scene does not have exactly one root node".to_owned()
        ));
    };
    let node = root
        .nodes
        .get(node.value())
        .ok_or_else(|| bad("the root node is missing".to_owned()))?;
    let model = extras_of(&node.extras)?;
    let children = node.children.clone().unwrap_or_default();
    if model.get("format").and_then(Value::as_str) != Some(EXTRAS_FORMAT) {
        return Err(bad(format!("the root's format is not \"{EXTRAS_FORMAT}\"")));
    }
    match model.get("version").and_then(Value::as_u64) {
        Some(v) if (1..=EXTRAS_VERSION).contains(&v) => {}
        other => return Err(bad(format!("unsupported version {other:?}"))),
    }
    let s = model
        .get("metres_per_unit")
        .and_then(Value::as_f64)
        .filter(|s| s.is_finite() && *s > 0.0)
        .ok_or_else(|| bad("`metres_per_unit` must be a positive number".to_owned()))?;

    let mut document = Document::new();
    let mut ids = BTreeMap::new();
    for child in children {
        let node = root
            .nodes
            .get(child.value())
            .ok_or_else(|| bad(format!("node {} is missing", child.value())))?;
        let name = node.name.clone().unwrap_or_default();
        let value = extras_of(&node.extras)?;
        let id = value
            .get("id")
            .and_then(Value::as_u64)
            .and_then(|i| u32::try_from(i).ok())
            .map(PrimitiveId)
            .ok_or_else(|| bad(format!("node {name}: `id` is missing")))?;
        let primitive = parse_primitive(&value).map_err(|e| bad(format!("node {name}: {e}")))?;
        if ids.insert(name.clone(), id).is_some() || document.get(id).is_some() {
            return Err(bad(format!("node {name}: its name or id is used twice")));
        }
        document.insert(
            id,
            Placed {
                primitive: primitive.transformed(DVec3::ZERO, 1.0 / s),
                fit: Fit::default(),
            },
        );
        if let Some(given) = value.get("name").and_then(Value::as_str) {
            document.set_name(id, given);
        }
    }
    let relations = match model.get("relations") {
        None => &Vec::new(),
        Some(Value::Array(list)) => list,
        Some(_) => return Err(bad("`relations` is not a list".to_owned())),
    };
    for (index, r) in relations.iter().enumerate() {
        let relation = parse_relation_with(r, &document, |m| {
            m.as_str().and_then(|n| ids.get(n).copied())
        })
        .map_err(|e| bad(format!("relation {index}: {e}")))?;
        document
            .add_relation(relation)
            .map_err(|e| bad(format!("relation {index}: {e}")))?;
    }
    Ok(ImportedModel {
        document,
        metres_per_unit: s,
    })
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};
    use serde_json::Value;

    use super::{
        base64, colour, encode_gltf, export_gltf, ground_offset, parse_gltf_extras, primitive_json,
        ExportError, ExportSettings, GltfFormat, Origin, Part, DEFAULT_METRES_PER_UNIT,
        DEFAULT_SEGMENTS,
    };
    use crate::core::model::{Document, Fit, Placed, PrimitiveId, Relation};
    use crate::core::primitive::{Bgc, Cone, Cuboid, Cylinder, Feature, Primitive, Sgc, Sphere};
    use crate::core::relation::{Mode, RelationKind};

    /// One primitive of every kind, tilted, off the origin, with three relations.
    fn every_kind() -> Document {
        let tilted = DVec3::new(0.3, 0.9, 0.2).normalize();
        let arc: Vec<DVec3> = (0..7)
            .map(|i| {
                let t = 0.25 * f64::from(i);
                DVec3::new(400.0 + 80.0 * t.cos(), 80.0 * t.sin(), -20.0)
            })
            .collect();
        let primitives = [
            Primitive::Cylinder(Cylinder {
                center: DVec3::new(10.0, -200.0, 5.0),
                axis: tilted,
                length: 120.0,
                radius: 20.0,
            }),
            Primitive::Cone(Cone {
                center: DVec3::new(-150.0, -100.0, 0.0),
                axis: -DVec3::Y,
                length: 90.0,
                radius_bottom: 40.0,
                radius_top: 10.0,
            }),
            Primitive::Sphere(Sphere {
                center: DVec3::new(100.0, 50.0, -30.0),
                radius: 35.0,
            }),
            Primitive::Cuboid(Cuboid {
                center: DVec3::new(250.0, -300.0, 10.0),
                rotation: DQuat::from_euler(glam::EulerRot::YXZ, 0.4, -0.2, 0.7),
                size: DVec3::new(80.0, 40.0, 60.0),
            }),
            Primitive::Sgc(Sgc {
                center: DVec3::new(-300.0, -250.0, 0.0),
                axis: DVec3::new(0.0, 0.8, 0.6),
                length: 200.0,
                radii: vec![30.0, 45.0, 50.0, 42.0, 30.0, 22.0, 20.0, 25.0],
            }),
            Primitive::Bgc(Bgc::through(arc, 12.0)),
        ];
        let mut doc = Document::new();
        for primitive in primitives {
            doc.add(Placed {
                primitive,
                fit: Fit::default(),
            });
        }
        let relation = |kind, members: &[u32], features: &[Option<Feature>], mode| Relation {
            kind,
            members: members.iter().map(|m| PrimitiveId(*m)).collect(),
            features: features.to_vec(),
            mode,
            inferred: None,
        };
        let relations = [
            relation(
                RelationKind::Parallel,
                &[0, 4],
                &[Some(Feature::Top), Some(Feature::Bottom)],
                Mode::Hard,
            ),
            relation(
                RelationKind::CollinearCenters,
                &[0, 1, 4],
                &[
                    Some(Feature::Top),
                    Some(Feature::Top),
                    Some(Feature::Bottom),
                ],
                Mode::Soft,
            ),
            relation(RelationKind::EqualLength, &[0, 1], &[], Mode::Off),
        ];
        for r in relations {
            doc.add_relation(r).unwrap();
        }
        doc
    }

    fn temp_path(name: &str) -> std::path::PathBuf {
        std::env::temp_dir().join(format!("geosnap-gltf-unit-{}-{name}", std::process::id()))
    }

    /// The numbers of a JSON value, depth first.
    fn numbers(v: &Value, out: &mut Vec<f64>) {
        match v {
            Value::Number(n) => out.extend(n.as_f64()),
            Value::Array(a) => a.iter().for_each(|x| numbers(x, out)),
            Value::Object(m) => m.values().for_each(|x| numbers(x, out)),
            _ => {}
        }
    }

    #[test]
    fn base64_matches_the_rfc_4648_examples() {
        let cases = [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ];
        for (plain, encoded) in cases {
            assert_eq!(base64(plain.as_bytes()), encoded, "{plain:?}");
        }
        assert_eq!(base64(&[0xff, 0xfe, 0x00]), "//4A");
    }

    #[test]
    fn settings_out_of_range_are_named() {
        assert!(ExportSettings::default().validate().is_ok());
        for scale in [f64::NAN, 0.0, -0.001, f64::INFINITY] {
            let error =
                ExportSettings::new(scale, DEFAULT_SEGMENTS, Origin::default()).unwrap_err();
            assert!(
                matches!(
                    error,
                    ExportError::InvalidSetting {
                        name: "metres_per_unit",
                        ..
                    }
                ),
                "{error}"
            );
        }
        for segments in [0, 2, 1025] {
            let error = ExportSettings::new(DEFAULT_METRES_PER_UNIT, segments, Origin::default())
                .unwrap_err();
            assert!(error.to_string().contains("segments"), "{error}");
        }
    }

    #[test]
    fn the_format_follows_the_extension() {
        use std::path::Path;
        assert_eq!(
            GltfFormat::from_path(Path::new("a/b.GLB")),
            Some(GltfFormat::Glb)
        );
        assert_eq!(
            GltfFormat::from_path(Path::new("b.gltf")),
            Some(GltfFormat::Gltf)
        );
        assert_eq!(GltfFormat::from_path(Path::new("b.obj")), None);
        assert_eq!(GltfFormat::from_path(Path::new("glb")), None);
        let path = temp_path("model.obj");
        let error = export_gltf(&every_kind(), &path, &ExportSettings::default()).unwrap_err();
        assert!(
            matches!(error, ExportError::UnknownExtension { .. }),
            "{error}"
        );
        assert!(!path.exists(), "nothing is written");
    }

    #[test]
    fn bad_primitives_are_clear_errors_and_leave_the_old_file() {
        let sphere = |radius| {
            Primitive::Sphere(Sphere {
                center: DVec3::ZERO,
                radius,
            })
        };
        let cylinder = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::ZERO,
            length: 1.0,
            radius: 1.0,
        });
        let mut bgc = Bgc::through(vec![DVec3::ZERO, DVec3::X, DVec3::X], 1.0);
        let twin = Primitive::Bgc(bgc.clone());
        bgc.spine[1] = DVec3::new(f64::NAN, 0.0, 0.0);
        let cases = [
            (sphere(f64::NAN), "sphere_0", "NaN"),
            (sphere(-2.0), "sphere_0", "radius must be positive, got -2"),
            (sphere(0.0), "sphere_0", "radius must be positive, got 0"),
            (cylinder, "cylinder_0", "axis has no direction"),
            (twin, "bgc_0", "spine points 1 and 2 coincide"),
            (Primitive::Bgc(bgc), "bgc_0", "NaN"),
        ];
        let path = temp_path("bad.glb");
        std::fs::write(&path, b"the old file").unwrap();
        for (primitive, node, reason) in cases {
            let mut doc = Document::new();
            doc.add(Placed {
                primitive,
                fit: Fit::default(),
            });
            let error = export_gltf(&doc, &path, &ExportSettings::default()).unwrap_err();
            let text = error.to_string();
            assert!(
                matches!(error, ExportError::InvalidPrimitive { .. }),
                "{text}"
            );
            assert!(text.contains(node) && text.contains(reason), "{text}");
            assert_eq!(std::fs::read(&path).unwrap(), b"the old file");
        }
        std::fs::remove_file(&path).unwrap();
    }

    /// Given names become node names, each node's its own, and come back on import
    /// with the relations that name their members by node.
    #[test]
    fn node_names_follow_given_names_and_stay_unique() {
        let mut doc = every_kind();
        // 0 and 2 alike; 3 takes 1's default name; 4 the root's; 5 stays unnamed.
        for (id, name) in [
            (0, "Leg"),
            (2, "  Leg "),
            (3, "cone_1"),
            (4, "geosnap_model"),
        ] {
            assert!(doc.set_name(PrimitiveId(id), name));
        }
        let names: Vec<String> = super::node_names(&doc).into_values().collect();
        assert_eq!(
            names,
            [
                "Leg",
                "cone_1",
                "Leg_2",
                "cone_1_3",
                "geosnap_model_4",
                "bgc_5"
            ]
        );
        let (bytes, _) =
            encode_gltf(&doc, GltfFormat::Gltf, &ExportSettings::default()).expect("exports");
        let back = parse_gltf_extras(&bytes).expect("reads back");
        assert_eq!(back.document.relations(), doc.relations());
        for id in 0..6 {
            let id = PrimitiveId(id);
            assert_eq!(back.document.name(id), doc.name(id), "{id:?}");
        }
        assert_eq!(back.document.name(PrimitiveId(2)), Some("Leg"), "as given");
    }

    #[test]
    fn an_empty_model_is_a_valid_file_with_an_empty_scene_and_a_warning() {
        for format in [GltfFormat::Glb, GltfFormat::Gltf] {
            let (bytes, report) =
                encode_gltf(&Document::new(), format, &ExportSettings::default()).unwrap();
            assert_eq!(report.nodes, 0);
            assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
            let back = parse_gltf_extras(&bytes).unwrap();
            assert!(back.document.is_empty());
            let json = super::json_chunk(&bytes).unwrap();
            let root: Value = serde_json::from_slice(json).unwrap();
            assert_eq!(root["nodes"].as_array().unwrap().len(), 1, "{root}");
            assert!(root["nodes"][0].get("children").is_none(), "{root}");
            assert!(root.get("meshes").is_none(), "{root}");
            assert!(root.get("buffers").is_none(), "no empty buffer");
        }
    }

    #[test]
    fn the_glb_container_is_sized_and_aligned() {
        let (bytes, report) =
            encode_gltf(&every_kind(), GltfFormat::Glb, &ExportSettings::default()).unwrap();
        assert_eq!(report.bytes, bytes.len());
        let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        assert_eq!(&bytes[0..4], b"glTF");
        assert_eq!(word(4), 2);
        assert_eq!(word(8), bytes.len());
        let json = word(12);
        assert_eq!(&bytes[16..20], b"JSON");
        assert_eq!(json % 4, 0);
        let bin = 20 + json;
        assert_eq!(&bytes[bin + 4..bin + 8], b"BIN\0");
        assert_eq!(word(bin) % 4, 0);
        assert_eq!(bin + 8 + word(bin), bytes.len());
        let root: Value = serde_json::from_slice(&bytes[20..20 + json]).unwrap();
        assert_eq!(
            root["buffers"][0]["byteLength"].as_u64(),
            Some(word(bin) as u64)
        );
        for view in root["bufferViews"].as_array().unwrap() {
            assert_eq!(view["byteOffset"].as_u64().unwrap() % 4, 0, "{view}");
        }
    }

    #[test]
    fn local_meshes_face_outwards_with_unit_normals_and_centred_frames() {
        for (id, placed) in every_kind().primitives() {
            let part = Part::new(id, (String::new(), None), &placed.primitive, 24).unwrap();
            assert!(part
                .normals
                .iter()
                .all(|n| (n.length() - 1.0).abs() < 1e-12));
            for t in part.indices.chunks(3) {
                let [a, b, c] = [0, 1, 2].map(|k| t[k] as usize);
                let (pa, pb, pc) = (part.positions[a], part.positions[b], part.positions[c]);
                let face = (pb - pa).cross(pc - pa);
                let normal = part.normals[a] + part.normals[b] + part.normals[c];
                assert!(
                    face.dot(normal) > 0.0,
                    "{}: triangle {t:?} winds clockwise",
                    part.name
                );
            }
            // Solids of revolution run along local +Y, centred.
            let (lo, hi) = part
                .positions
                .iter()
                .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(*p), hi.max(*p))
                });
            match &placed.primitive {
                Primitive::Cylinder(c) => {
                    assert!((hi.y - c.length / 2.0).abs() < 1e-9 && (lo.y + hi.y).abs() < 1e-9);
                    let sag = c.radius * (1.0 - (std::f64::consts::PI / 24.0).cos());
                    assert!(hi.x <= c.radius && hi.x >= c.radius - sag - 1e-9, "{hi}");
                }
                Primitive::Cuboid(b) => assert!((hi - b.size / 2.0).length() < 1e-9),
                Primitive::Bgc(_) => assert!(lo.z.abs() < 13.0 && hi.z.abs() < 13.0),
                _ => assert!((lo + hi).length() < 1e-9 * hi.length(), "{lo} {hi}"),
            }
        }
    }

    #[test]
    fn extras_round_trip_every_kind_and_the_relations() {
        let doc = every_kind();
        let settings = ExportSettings::new(0.0254, DEFAULT_SEGMENTS, Origin::Model).unwrap();
        for format in [GltfFormat::Glb, GltfFormat::Gltf] {
            let (bytes, report) = encode_gltf(&doc, format, &settings).unwrap();
            assert_eq!(report.nodes, 6);
            assert!(report.warnings.is_empty());
            let back = parse_gltf_extras(&bytes).unwrap();
            assert!((back.metres_per_unit - 0.0254).abs() < 1e-15);
            assert_eq!(back.document.relations(), doc.relations());
            let ids: Vec<_> = back.document.primitives().map(|(id, _)| id).collect();
            assert_eq!(ids, doc.primitives().map(|(id, _)| id).collect::<Vec<_>>());
            for (id, placed) in doc.primitives() {
                let again = &back.document.get(id).unwrap().primitive;
                assert_eq!(again.kind(), placed.primitive.kind());
                let (mut a, mut b) = (Vec::new(), Vec::new());
                numbers(&Value::Object(primitive_json(&placed.primitive)), &mut a);
                numbers(&Value::Object(primitive_json(again)), &mut b);
                assert_eq!(a.len(), b.len());
                for (x, y) in a.iter().zip(&b) {
                    assert!(
                        (x - y).abs() <= 1e-12 * x.abs().max(1.0),
                        "{id:?}: {x} vs {y}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_ground_origin_centres_the_model_on_y_0() {
        let doc = every_kind();
        let parts: Vec<Part> = doc
            .primitives()
            .map(|(id, p)| Part::new(id, (String::new(), None), &p.primitive, 16).unwrap())
            .collect();
        let offset = ground_offset(&parts);
        let (lo, hi) = parts
            .iter()
            .map(|p| p.bounds)
            .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
            .unwrap();
        let (lo, hi) = (lo + offset, hi + offset);
        assert!(lo.y.abs() < 1e-9 && (lo.x + hi.x).abs() < 1e-9 && (lo.z + hi.z).abs() < 1e-9);
    }

    #[test]
    fn indices_are_u16_unless_a_mesh_needs_u32() {
        let sphere = |segments| {
            let mut doc = Document::new();
            doc.add(Placed {
                primitive: Primitive::Sphere(Sphere {
                    center: DVec3::ZERO,
                    radius: 1.0,
                }),
                fit: Fit::default(),
            });
            let settings =
                ExportSettings::new(DEFAULT_METRES_PER_UNIT, segments, Origin::default()).unwrap();
            let (bytes, _) = encode_gltf(&doc, GltfFormat::Glb, &settings).unwrap();
            let root: Value = serde_json::from_slice(super::json_chunk(&bytes).unwrap()).unwrap();
            root["accessors"][2]["componentType"].as_u64()
        };
        assert_eq!(sphere(32), Some(5123), "u16");
        // 200 rings of 401 vertices: more than u16 can index.
        assert_eq!(sphere(400), Some(5125), "u32");
    }

    #[test]
    fn colours_are_distinct_and_in_range() {
        let colours: Vec<[f32; 4]> = (0..200).map(colour).collect();
        for (i, a) in colours.iter().enumerate() {
            assert!(a.iter().all(|c| (0.0..=1.0).contains(c)), "{a:?}");
            for b in &colours[..i] {
                let d: f32 = (0..3).map(|k| (a[k] - b[k]).abs()).sum();
                assert!(d > 1e-4, "colour {i} repeats: {a:?}");
            }
        }
        // Neighbours differ visibly.
        for w in colours.windows(2) {
            let d: f32 = (0..3).map(|k| (w[0][k] - w[1][k]).abs()).sum();
            assert!(d > 0.1, "{w:?}");
        }
    }
}
