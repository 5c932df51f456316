//! The native sketch file, and [`load_sketch`], which opens a sketch of either kind.
//!
//! # Format (version 1)
//!
//! JSON, UTF-8, one object:
//!
//! ```json
//! {
//!   "format": "geosnap-sketch",
//!   "version": 1,
//!   "image": "photo.jpg",
//!   "view_box": [0.0, 0.0, 2448.0, 3264.0],
//!   "strokes": [
//!     {"id": 0, "points": [[10.0, 20.0], [30.5, 41.0]], "closed": false},
//!     {"id": 7, "points": [[1.0, 2.0], [3.0, 4.0], [5.0, 1.0]], "closed": true, "class": "feature"}
//!   ]
//! }
//! ```
//!
//! - `format` (required) is `"geosnap-sketch"`; `version` (required) is 1. A file with a
//!   newer version is refused with [`LoadError::UnsupportedVersion`] rather than misread;
//!   a future version 2 gets its own reader and a `migrate_v1_to_v2`.
//! - `image` (optional): the reference image, relative to the sketch file.
//! - `view_box` (optional): `[x, y, width, height]` of the drawing in sketch space
//!   (formats.md §1).
//! - `strokes` (required, possibly empty), in drawing order: `id` (unique, `u32`),
//!   `points` (at least two `[x, y]`, finite, sketch space), `closed` (optional, default
//!   `false`), `class` (optional user override: `"feature"` or `"silhouette"`).
//! - Unknown fields are ignored, so later versions may add optional fields.
//!
//! Files are written with [`write_atomic`], one stroke per line.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::core::sketch::{Sketch, Stroke, StrokeClass, StrokeId};
use crate::io::input::read_input;
use crate::io::json;
use crate::io::svg::{import_svg, SvgOptions};
use crate::io::{write_atomic, LoadError, SaveError, SketchError};

/// The `format` value of a sketch file.
pub const SKETCH_FORMAT: &str = "geosnap-sketch";

/// The newest sketch file version this build reads, and the one it writes.
pub const SKETCH_VERSION: u64 = 1;

/// A sketch read from a file, with what the user should know about it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadedSketch {
    /// The strokes and view box, in sketch space.
    pub sketch: Sketch,
    /// Human-readable notes on content that was not imported (see
    /// [`SvgImport::warnings`](crate::io::svg::SvgImport::warnings)).
    pub warnings: Vec<String>,
    /// The reference image named by a native sketch file: as written in the file when
    /// parsed from bytes, resolved against the file's directory by [`load_sketch`].
    /// Always `None` for SVG.
    pub image: Option<PathBuf>,
}

/// The kind of sketch data, decided from its content or file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Svg,
    Json,
}

/// Opens a sketch file, SVG or native JSON, with the default [`SvgOptions`].
///
/// # Errors
///
/// See [`load_sketch_with`].
pub fn load_sketch(path: impl AsRef<Path>) -> Result<LoadedSketch, LoadError> {
    load_sketch_with(path, &SvgOptions::default())
}

/// Opens a sketch file, SVG or native JSON.
///
/// The kind is decided by content (a document starting with `<` is SVG, one starting
/// with `{` is JSON), then by the extension (`.svg`, `.json`). A relative reference image
/// path is resolved against the file's directory.
///
/// # Errors
///
/// [`LoadError::Read`] if the file cannot be read; otherwise [`LoadError::File`] naming
/// the file, whose source is the error of [`import_svg`] or [`parse_sketch_file`], or
/// [`LoadError::UnknownFormat`].
pub fn load_sketch_with(
    path: impl AsRef<Path>,
    options: &SvgOptions,
) -> Result<LoadedSketch, LoadError> {
    let path = path.as_ref();
    let data = read_input(path).map_err(|source| LoadError::Read {
        path: path.to_owned(),
        source,
    })?;
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let by_extension = match extension.as_deref() {
        Some("svg") => Some(Kind::Svg),
        Some("json") => Some(Kind::Json),
        _ => None,
    };
    let wrap = |source: LoadError| LoadError::File {
        path: path.to_owned(),
        source: Box::new(source),
    };
    let kind = sniff(&data)
        .or(by_extension)
        .ok_or_else(|| wrap(LoadError::UnknownFormat))?;
    let mut loaded = load_kind(&data, kind, options).map_err(wrap)?;
    if let (Some(image), Some(dir)) = (&loaded.image, path.parent()) {
        if image.is_relative() {
            loaded.image = Some(dir.join(image));
        }
    }
    Ok(loaded)
}

/// Reads a sketch from bytes, SVG or native JSON, decided by content alone.
///
/// The reference image path is returned as written in the file.
///
/// # Errors
///
/// [`LoadError::UnknownFormat`] if the data is neither (it does not start with `<` or
/// `{`), else the errors of [`import_svg`] or [`parse_sketch_file`].
pub fn load_sketch_from_bytes(
    data: &[u8],
    options: &SvgOptions,
) -> Result<LoadedSketch, LoadError> {
    let kind = sniff(data).ok_or(LoadError::UnknownFormat)?;
    load_kind(data, kind, options)
}

fn load_kind(data: &[u8], kind: Kind, options: &SvgOptions) -> Result<LoadedSketch, LoadError> {
    match kind {
        Kind::Svg => import_svg(data, options).map(|import| LoadedSketch {
            sketch: import.sketch,
            warnings: import.warnings,
            image: None,
        }),
        Kind::Json => parse_sketch_file(data),
    }
}

/// The kind of data from its first significant byte.
fn sniff(data: &[u8]) -> Option<Kind> {
    let data = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data);
    if data.starts_with(&[0x1f, 0x8b]) {
        return Some(Kind::Svg); // svgz, refused with a clear error by the importer
    }
    match data.iter().find(|b| !b.is_ascii_whitespace()) {
        Some(b'<') => Some(Kind::Svg),
        Some(b'{') => Some(Kind::Json),
        _ => None,
    }
}

/// Version 1 of the file, field by field.
#[derive(Serialize, Deserialize)]
struct FileV1 {
    format: String,
    version: u64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    image: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    view_box: Option<[f64; 4]>,
    strokes: Vec<StrokeV1>,
}

/// One stroke of version 1.
#[derive(Serialize, Deserialize)]
struct StrokeV1 {
    id: u32,
    points: Vec<[f64; 2]>,
    #[serde(default)]
    closed: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    class: Option<StrokeClass>,
}

/// Parses a native sketch file.
///
/// # Errors
///
/// [`LoadError::Json`] for malformed JSON or fields of the wrong type (with line and
/// column), [`LoadError::WrongFormat`], [`LoadError::InvalidVersion`],
/// [`LoadError::UnsupportedVersion`] for a file from a newer geosnap, and
/// [`LoadError::InvalidSketch`] naming the stroke with too few points, a non-finite
/// point or a duplicate id.
///
/// # Examples
///
/// ```
/// let json = br#"{"format": "geosnap-sketch", "version": 1,
///                 "strokes": [{"id": 3, "points": [[0, 0], [10, 5]], "class": "feature"}]}"#;
/// let loaded = geosnap::io::sketch_file::parse_sketch_file(json)?;
/// assert_eq!(loaded.sketch.strokes[0].id.0, 3);
/// assert!(loaded.warnings.is_empty());
/// # Ok::<(), geosnap::io::LoadError>(())
/// ```
pub fn parse_sketch_file(data: &[u8]) -> Result<LoadedSketch, LoadError> {
    let value = json::parse(data).map_err(|problem| LoadError::Json { problem })?;
    let Some(header) = value.as_object() else {
        return Err(LoadError::WrongFormat {
            found: "missing (the data is not a json object)".to_owned(),
        });
    };
    match header.get("format") {
        Some(serde_json::Value::String(format)) if format == SKETCH_FORMAT => {}
        Some(other) => {
            return Err(LoadError::WrongFormat {
                found: json::shown(other),
            })
        }
        None => {
            return Err(LoadError::WrongFormat {
                found: "missing".to_owned(),
            })
        }
    }
    let version = match header.get("version") {
        Some(value) => {
            value
                .as_u64()
                .filter(|v| *v > 0)
                .ok_or_else(|| LoadError::InvalidVersion {
                    found: json::shown(value),
                })?
        }
        None => {
            return Err(LoadError::InvalidVersion {
                found: "missing".to_owned(),
            })
        }
    };
    if version > SKETCH_VERSION {
        return Err(LoadError::UnsupportedVersion {
            found: version,
            supported: SKETCH_VERSION,
        });
    }
    // The header is checked first so that a wrong format or a future version gives a clear
    // error instead of a confusing field error. Only version 1 exists; an older version
    // would be migrated here. Parsing the bytes again keeps line and column in errors.
    let file: FileV1 = serde_json::from_slice(data).map_err(|error| LoadError::Json {
        problem: json::from_serde(&error, data),
    })?;
    let view_box = file
        .view_box
        .map(|[x, y, w, h]| (DVec2::new(x, y), DVec2::new(w, h)));
    let sketch = Sketch {
        strokes: file
            .strokes
            .into_iter()
            .map(|s| Stroke {
                id: StrokeId(s.id),
                points: s.points.into_iter().map(DVec2::from).collect(),
                closed: s.closed,
                class_override: s.class,
            })
            .collect(),
        view_box,
    };
    validate_sketch(&sketch)?;
    let warnings = if sketch.strokes.is_empty() {
        vec!["the sketch file has no strokes".to_owned()]
    } else {
        Vec::new()
    };
    Ok(LoadedSketch {
        sketch,
        warnings,
        image: file.image.map(PathBuf::from),
    })
}

/// Checks the invariants a saved or loaded sketch must hold: every stroke has at least
/// two points, all finite; ids are unique; the view box, if any, is finite with a
/// positive size.
///
/// # Errors
///
/// The first [`SketchError`] found, in stroke order.
pub fn validate_sketch(sketch: &Sketch) -> Result<(), SketchError> {
    if let Some((min, size)) = sketch.view_box {
        let view_box = [min.x, min.y, size.x, size.y];
        if !(view_box.iter().all(|v| v.is_finite()) && size.x > 0.0 && size.y > 0.0) {
            return Err(SketchError::InvalidViewBox { view_box });
        }
    }
    let mut ids = BTreeSet::new();
    for (position, stroke) in sketch.strokes.iter().enumerate() {
        let id = stroke.id.0;
        if stroke.points.len() < 2 {
            return Err(SketchError::TooFewPoints {
                id,
                position,
                count: stroke.points.len(),
            });
        }
        if let Some(point) = stroke.points.iter().position(|p| !p.is_finite()) {
            return Err(SketchError::NonFinitePoint { id, point });
        }
        if !ids.insert(id) {
            return Err(SketchError::DuplicateId { id });
        }
    }
    Ok(())
}

/// Encodes a sketch as a version-1 sketch file: the header pretty-printed, one stroke
/// per line.
///
/// # Errors
///
/// [`SaveError::InvalidSketch`] if [`validate_sketch`] fails (nothing is encoded), and
/// [`SaveError::NonUnicodeImagePath`] for an image path JSON cannot hold.
pub fn sketch_file_bytes(sketch: &Sketch, image: Option<&Path>) -> Result<Vec<u8>, SaveError> {
    validate_sketch(sketch)?;
    let image = image
        .map(|path| {
            path.to_str()
                .map(str::to_owned)
                .ok_or_else(|| SaveError::NonUnicodeImagePath {
                    path: path.to_owned(),
                })
        })
        .transpose()?;
    // Writing to a String cannot fail, so the results of `write!` are ignored.
    let mut out = String::from("{\n");
    let _ = writeln!(out, "  \"format\": {},", encode(SKETCH_FORMAT)?);
    let _ = writeln!(out, "  \"version\": {SKETCH_VERSION},");
    if let Some(image) = &image {
        let _ = writeln!(out, "  \"image\": {},", encode(image)?);
    }
    if let Some((min, size)) = sketch.view_box {
        let view_box = [min.x, min.y, size.x, size.y];
        let _ = writeln!(out, "  \"view_box\": {},", encode(&view_box)?);
    }
    out.push_str("  \"strokes\": [");
    for (i, stroke) in sketch.strokes.iter().enumerate() {
        let record = StrokeV1 {
            id: stroke.id.0,
            points: stroke.points.iter().map(DVec2::to_array).collect(),
            closed: stroke.closed,
            class: stroke.class_override,
        };
        out.push_str(if i == 0 { "\n    " } else { ",\n    " });
        out.push_str(&encode(&record)?);
    }
    out.push_str(if sketch.strokes.is_empty() {
        "]\n}\n"
    } else {
        "\n  ]\n}\n"
    });
    Ok(out.into_bytes())
}

/// Saves a sketch as a native sketch file, atomically (the old file survives any failure).
///
/// `image` is stored as given; pass a path relative to the sketch file so the pair can be
/// moved together.
///
/// # Errors
///
/// The errors of [`sketch_file_bytes`], and [`SaveError::Write`] if the file cannot be
/// written.
///
/// # Examples
///
/// ```
/// use geosnap::core::sketch::{Sketch, Stroke, StrokeId};
/// use glam::DVec2;
///
/// let sketch = Sketch {
///     strokes: vec![Stroke {
///         id: StrokeId(0),
///         points: vec![DVec2::ZERO, DVec2::new(3.0, 4.0)],
///         closed: false,
///         class_override: None,
///     }],
///     view_box: None,
/// };
/// let path = std::env::temp_dir().join(format!("geosnap-doc-{}.json", std::process::id()));
/// geosnap::io::save_sketch(&path, &sketch, None)?;
/// assert_eq!(geosnap::io::load_sketch(&path)?.sketch, sketch);
/// # std::fs::remove_file(&path).ok();
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn save_sketch(
    path: impl AsRef<Path>,
    sketch: &Sketch,
    image: Option<&Path>,
) -> Result<(), SaveError> {
    let path = path.as_ref();
    let bytes = sketch_file_bytes(sketch, image)?;
    write_atomic(path, &bytes).map_err(|source| SaveError::Write {
        path: path.to_owned(),
        source,
    })
}

/// Compact JSON for one value.
fn encode<T: Serialize + ?Sized>(value: &T) -> Result<String, SaveError> {
    serde_json::to_string(value).map_err(|source| SaveError::Json { source })
}

#[cfg(test)]
mod tests {
    use std::fs;
    use std::path::{Path, PathBuf};

    use glam::DVec2;
    use proptest::prelude::*;

    use super::{
        load_sketch, load_sketch_from_bytes, parse_sketch_file, save_sketch, sketch_file_bytes,
        validate_sketch, LoadedSketch,
    };
    use crate::core::sketch::{Sketch, Stroke, StrokeClass, StrokeId};
    use crate::io::svg::SvgOptions;
    use crate::io::{LoadError, SaveError, SketchError};

    fn stroke(id: u32, points: &[(f64, f64)]) -> Stroke {
        Stroke {
            id: StrokeId(id),
            points: points.iter().map(|&(x, y)| DVec2::new(x, y)).collect(),
            closed: false,
            class_override: None,
        }
    }

    fn sample() -> Sketch {
        let mut closed = stroke(7, &[(1.0, 2.0), (3.0, 4.0), (5.0, 1.0)]);
        closed.closed = true;
        closed.class_override = Some(StrokeClass::Feature);
        let mut silhouette = stroke(2, &[(0.1, 0.2), (1e-300, -1.5e300)]);
        silhouette.class_override = Some(StrokeClass::Silhouette);
        Sketch {
            strokes: vec![stroke(0, &[(10.0, 20.0), (30.5, 41.0)]), closed, silhouette],
            view_box: Some((DVec2::new(-1.0, 0.0), DVec2::new(2448.0, 3264.0))),
        }
    }

    fn parse(json: &str) -> Result<LoadedSketch, LoadError> {
        parse_sketch_file(json.as_bytes())
    }

    /// A fresh directory under the system temporary directory, removed on drop.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> Self {
            let dir = std::env::temp_dir()
                .join(format!("geosnap-sketch-file-{name}-{}", std::process::id()));
            let _ = fs::remove_dir_all(&dir);
            fs::create_dir_all(&dir).unwrap();
            Self(dir)
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = fs::remove_dir_all(&self.0);
        }
    }

    #[test]
    fn round_trips_through_bytes() {
        let sketch = sample();
        let bytes = sketch_file_bytes(&sketch, Some(Path::new("photos/goblet.jpg"))).unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        assert!(text.starts_with("{\n  \"format\": \"geosnap-sketch\",\n  \"version\": 1,\n"));
        assert_eq!(text.lines().count(), 11, "one stroke per line:\n{text}");
        assert!(text.contains(r#""class":"feature""#), "{text}");
        let loaded = parse_sketch_file(&bytes).unwrap();
        assert_eq!(loaded.sketch, sketch);
        assert_eq!(loaded.image, Some(PathBuf::from("photos/goblet.jpg")));
        assert!(loaded.warnings.is_empty());
    }

    #[test]
    fn an_empty_sketch_round_trips_with_a_warning() {
        let bytes = sketch_file_bytes(&Sketch::default(), None).unwrap();
        let loaded = parse_sketch_file(&bytes).unwrap();
        assert_eq!(loaded.sketch, Sketch::default());
        assert_eq!(loaded.image, None);
        assert_eq!(loaded.warnings.len(), 1);
    }

    #[test]
    fn reads_the_documented_example_with_optional_fields_missing_or_extra() {
        let loaded = parse(
            r#"{"format": "geosnap-sketch", "version": 1, "future_field": {"x": 1},
                "strokes": [{"id": 4, "points": [[0, 0], [1, 1]], "note": "extra"},
                            {"id": 1, "points": [[0, 0], [1, 1]], "closed": true, "class": null}]}"#,
        )
        .unwrap();
        let s = &loaded.sketch;
        assert_eq!(s.view_box, None);
        assert_eq!(s.strokes[0].id, StrokeId(4));
        assert!(!s.strokes[0].closed);
        assert!(s.strokes[1].closed);
        assert_eq!(s.strokes[1].class_override, None);
    }

    #[test]
    fn checks_format_and_version() {
        let err = |json: &str| parse(json).unwrap_err();
        assert!(matches!(
            err(r#"{"format": "geosnap-model", "version": 1, "strokes": []}"#),
            LoadError::WrongFormat { found } if found == "\"geosnap-model\""
        ));
        assert!(matches!(
            err(r#"{"version": 1, "strokes": []}"#),
            LoadError::WrongFormat { found } if found == "missing"
        ));
        for not_a_sketch in [
            r#"{"format": 3, "version": 1, "strokes": []}"#,
            "[1, 2]",
            "7",
        ] {
            assert!(
                matches!(err(not_a_sketch), LoadError::WrongFormat { .. }),
                "{not_a_sketch}"
            );
        }
        let future = err(r#"{"format": "geosnap-sketch", "version": 2, "strokes": "new"}"#);
        assert!(matches!(
            future,
            LoadError::UnsupportedVersion {
                found: 2,
                supported: 1
            }
        ));
        assert!(future.to_string().contains("newer geosnap"), "{future}");
        for version in ["0", "-1", "1.5", "\"1\"", "null"] {
            let json =
                format!(r#"{{"format": "geosnap-sketch", "version": {version}, "strokes": []}}"#);
            assert!(
                matches!(err(&json), LoadError::InvalidVersion { .. }),
                "{version}"
            );
        }
        assert!(matches!(
            err(r#"{"format": "geosnap-sketch", "strokes": []}"#),
            LoadError::InvalidVersion { found } if found == "missing"
        ));
    }

    #[test]
    fn malformed_json_is_a_json_error_with_a_position() {
        for json in [
            "",
            "{",
            r#"{"format": "geosnap-sketch", "version": 1}"#,
            r#"{"format": "geosnap-sketch", "version": 1, "strokes": [{"id": -1, "points": []}]}"#,
            r#"{"format": "geosnap-sketch", "version": 1, "strokes": [{"id": 0, "points": [[1]]}]}"#,
            r#"{"format": "geosnap-sketch", "version": 1, "strokes": [{"id": 0, "points": [[1, 2], [1e400, 0]]}]}"#,
            r#"{"format": "geosnap-sketch", "version": 1, "strokes": [{"id": 0, "points": [[0,0],[1,1]], "class": "edge"}]}"#,
        ] {
            let error = parse(json).unwrap_err();
            assert!(matches!(error, LoadError::Json { .. }), "{json}: {error:?}");
        }
        let error = parse(
            "{\n\"format\": \"geosnap-sketch\", \"version\": 1,\n\"strokes\": [{\"id\": \"a\"}]}",
        )
        .unwrap_err();
        let message = error.to_string();
        assert!(message.contains("line 3"), "{message}");
        assert!(!message.contains("u32"), "{message}");
    }

    #[test]
    fn invalid_strokes_are_named() {
        let error = parse(
            r#"{"format": "geosnap-sketch", "version": 1,
                "strokes": [{"id": 0, "points": [[0, 0], [1, 1]]}, {"id": 9, "points": [[0, 0]]}]}"#,
        )
        .unwrap_err();
        assert!(matches!(
            error,
            LoadError::InvalidSketch(SketchError::TooFewPoints {
                id: 9,
                position: 1,
                count: 1
            })
        ));
        assert_eq!(
            error.to_string(),
            "stroke 9 (position 1 in the list) has 1 point(s); a stroke needs at least 2"
        );
        let error = parse(
            r#"{"format": "geosnap-sketch", "version": 1,
                "strokes": [{"id": 3, "points": [[0, 0], [1, 1]]}, {"id": 3, "points": [[0, 0], [2, 2]]}]}"#,
        )
        .unwrap_err();
        assert!(matches!(
            error,
            LoadError::InvalidSketch(SketchError::DuplicateId { id: 3 })
        ));
        let error = parse(
            r#"{"format": "geosnap-sketch", "version": 1, "view_box": [0, 0, 0, 10], "strokes": []}"#,
        )
        .unwrap_err();
        assert!(matches!(
            error,
            LoadError::InvalidSketch(SketchError::InvalidViewBox { .. })
        ));
    }

    #[test]
    fn invalid_sketches_are_not_written() {
        let mut sketch = sample();
        sketch.strokes[1].points[2].x = f64::NAN;
        assert!(matches!(
            sketch_file_bytes(&sketch, None),
            Err(SaveError::InvalidSketch(SketchError::NonFinitePoint {
                id: 7,
                point: 2
            }))
        ));
        assert_eq!(
            validate_sketch(&sketch).unwrap_err().to_string(),
            "stroke 7 has a non-finite coordinate at point 2"
        );
        let mut sketch = sample();
        sketch.view_box = Some((DVec2::ZERO, DVec2::new(f64::INFINITY, 1.0)));
        assert!(matches!(
            sketch_file_bytes(&sketch, None),
            Err(SaveError::InvalidSketch(SketchError::InvalidViewBox { .. }))
        ));
    }

    #[test]
    fn save_and_load_through_files() {
        let dir = TempDir::new("files");
        let path = dir.0.join("goblet.json");
        save_sketch(&path, &sample(), Some(Path::new("goblet.jpg"))).unwrap();
        let loaded = load_sketch(&path).unwrap();
        assert_eq!(loaded.sketch, sample());
        assert_eq!(
            loaded.image,
            Some(dir.0.join("goblet.jpg")),
            "resolved next to the file"
        );

        // An absolute image path is kept.
        let absolute = dir.0.join("elsewhere.png");
        save_sketch(&path, &sample(), Some(&absolute)).unwrap();
        assert_eq!(load_sketch(&path).unwrap().image, Some(absolute));

        // A failed save (invalid sketch) leaves the previous file as it was.
        let before = fs::read(&path).unwrap();
        let mut bad = sample();
        bad.strokes[0].points.truncate(1);
        assert!(save_sketch(&path, &bad, None).is_err());
        assert_eq!(fs::read(&path).unwrap(), before);

        let error = save_sketch(dir.0.join("missing/dir/x.json"), &sample(), None).unwrap_err();
        assert!(matches!(error, SaveError::Write { .. }), "{error:?}");
        assert!(error.to_string().ends_with("x.json"), "{error}");
    }

    #[test]
    fn load_sketch_dispatches_by_content_then_extension() {
        let dir = TempDir::new("dispatch");
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"><path d="M 0 0 L 5 5"/></svg>"#;
        let json = String::from_utf8(sketch_file_bytes(&sample(), None).unwrap()).unwrap();
        let cases = [
            ("a.svg", svg, 1),
            ("a.SVG", svg, 1),
            ("svg-named.json", svg, 1),
            ("no-extension", svg, 1),
            ("b.json", json.as_str(), 3),
            ("json-named.svg", json.as_str(), 3),
            ("b.sketch", json.as_str(), 3),
        ];
        for (name, content, strokes) in cases {
            let path = dir.0.join(name);
            fs::write(&path, content).unwrap();
            let loaded = load_sketch(&path).unwrap();
            assert_eq!(loaded.sketch.strokes.len(), strokes, "{name}");
        }

        // An empty .svg is an empty drawing; empty or garbage data elsewhere is not a sketch.
        fs::write(dir.0.join("empty.svg"), "").unwrap();
        let empty = load_sketch(dir.0.join("empty.svg")).unwrap();
        assert!(empty.sketch.strokes.is_empty() && !empty.warnings.is_empty());
        fs::write(dir.0.join("garbage.txt"), "hello").unwrap();
        let error = load_sketch(dir.0.join("garbage.txt")).unwrap_err();
        assert!(matches!(&error, LoadError::File { source, .. }
            if matches!(**source, LoadError::UnknownFormat)));
        assert!(error.to_string().ends_with("garbage.txt"), "{error}");
        fs::write(dir.0.join("empty.json"), "").unwrap();
        assert!(load_sketch(dir.0.join("empty.json")).is_err());

        // Content errors name the file; read errors too.
        fs::write(dir.0.join("broken.svg"), "<svg").unwrap();
        let error = load_sketch(dir.0.join("broken.svg")).unwrap_err();
        assert!(matches!(&error, LoadError::File { source, .. }
            if matches!(**source, LoadError::Svg { .. })));
        let error = load_sketch(dir.0.join("absent.svg")).unwrap_err();
        assert!(matches!(error, LoadError::Read { .. }), "{error:?}");
    }

    #[test]
    fn from_bytes_sniffs_the_content() {
        let options = SvgOptions::default();
        let svg =
            b"\xEF\xBB\xBF  <svg xmlns='http://www.w3.org/2000/svg'><path d='M 0 0 L 1 1'/></svg>";
        assert_eq!(
            load_sketch_from_bytes(svg, &options)
                .unwrap()
                .sketch
                .strokes
                .len(),
            1
        );
        let json = sketch_file_bytes(&sample(), Some(Path::new("x.png"))).unwrap();
        let loaded = load_sketch_from_bytes(&json, &options).unwrap();
        assert_eq!(loaded.image, Some(PathBuf::from("x.png")), "as written");
        for garbage in [&b""[..], b"   ", b"hello", b"\x00\x01"] {
            assert!(matches!(
                load_sketch_from_bytes(garbage, &options),
                Err(LoadError::UnknownFormat)
            ));
        }
    }

    fn any_stroke() -> impl Strategy<Value = Stroke> {
        (
            any::<u32>(),
            prop::collection::vec((-1e12f64..1e12, -1e12f64..1e12), 2..20),
            any::<bool>(),
            prop::option::of(prop_oneof![
                Just(StrokeClass::Feature),
                Just(StrokeClass::Silhouette)
            ]),
        )
            .prop_map(|(id, points, closed, class_override)| Stroke {
                id: StrokeId(id),
                points: points.into_iter().map(|(x, y)| DVec2::new(x, y)).collect(),
                closed,
                class_override,
            })
    }

    proptest! {
        #[test]
        fn any_valid_sketch_round_trips_exactly(
            strokes in prop::collection::vec(any_stroke(), 0..8),
            view_box in prop::option::of((-1e6f64..1e6, -1e6f64..1e6, 1e-6f64..1e6, 1e-6f64..1e6)),
        ) {
            let mut strokes = strokes;
            strokes.sort_by_key(|s| s.id);
            strokes.dedup_by_key(|s| s.id);
            let sketch = Sketch {
                strokes,
                view_box: view_box.map(|(x, y, w, h)| (DVec2::new(x, y), DVec2::new(w, h))),
            };
            let bytes = sketch_file_bytes(&sketch, None).unwrap();
            let loaded = parse_sketch_file(&bytes).unwrap();
            prop_assert_eq!(loaded.sketch, sketch);
        }
    }
}
