//! The errors of the `io` layer: [`LoadError`] for reading sketches, [`SaveError`] for
//! writing them, and [`SketchError`] for a sketch that breaks the invariants of
//! [`Stroke`](crate::core::sketch::Stroke) (shared by both directions).
//!
//! Messages are lowercase, name the offending stroke or file, put paths last, and leave
//! causes to [`std::error::Error::source`] so a `{:#}` chain (anyhow) reads as one line.

use std::path::PathBuf;

use crate::io::json::JsonProblem;

/// Why a sketch (SVG or native sketch file) could not be loaded.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LoadError {
    /// The file could not be read.
    #[error("cannot read {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// Loading the file failed; the cause says why.
    #[error("cannot load sketch {}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What was wrong with its content.
        #[source]
        source: Box<Self>,
    },
    /// The data is not well-formed SVG (bad XML, no `<svg>` root, invalid size, not UTF-8).
    #[error("malformed svg")]
    Svg {
        /// The parser's error.
        #[source]
        source: usvg::Error,
    },
    /// The data is gzip-compressed SVG, which this build does not decompress.
    #[error("compressed svg (svgz) is not supported; decompress it first")]
    CompressedSvg,
    /// The drawing exceeds a safety limit (nesting depth, number of points).
    #[error("the drawing is too complex to import: {reason}")]
    TooComplex {
        /// Which limit was exceeded.
        reason: String,
    },
    /// An [`SvgOptions`](crate::io::svg::SvgOptions) value is out of range.
    #[error("invalid svg import option {name} = {value}: {expected}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// What the option accepts.
        expected: &'static str,
    },
    /// The data is not valid JSON or does not have the structure of a sketch file.
    #[error("malformed sketch file: {problem}")]
    Json {
        /// Where (line and column) and what, in our words.
        problem: JsonProblem,
    },
    /// The JSON is not a geosnap sketch file (its `format` field is wrong or missing).
    #[error(
        "not a geosnap sketch file: format is {found}, expected \"geosnap-sketch\"{}",
        format_hint(found)
    )]
    WrongFormat {
        /// The `format` value found, as JSON, or `missing`.
        found: String,
    },
    /// The sketch file was written by a newer geosnap.
    #[error(
        "unsupported sketch file version {found}: this geosnap reads versions 1 to {supported}; \
         the file was written by a newer geosnap"
    )]
    UnsupportedVersion {
        /// The file's version.
        found: u64,
        /// The newest version this build reads.
        supported: u64,
    },
    /// The `version` field is missing or not a positive integer.
    #[error("invalid sketch file version {found}: expected a positive integer")]
    InvalidVersion {
        /// The `version` value found, as JSON, or `missing`.
        found: String,
    },
    /// The data is neither SVG nor JSON.
    #[error("unrecognised sketch data: neither svg nor a geosnap sketch file")]
    UnknownFormat,
    /// The sketch breaks an invariant (too few points, non-finite values, duplicate ids).
    #[error(transparent)]
    InvalidSketch(#[from] SketchError),
}

/// What a file with the `format` found (as JSON) is, when it is another geosnap file.
fn format_hint(found: &str) -> String {
    serde_json::from_str::<String>(found)
        .ok()
        .and_then(|format| crate::io::json::describe_format(&format))
        .map(|what| format!("; this is {what}"))
        .unwrap_or_default()
}

/// Why a sketch could not be saved.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SaveError {
    /// The sketch breaks an invariant; nothing was written.
    #[error(transparent)]
    InvalidSketch(#[from] SketchError),
    /// The reference image path cannot be stored in JSON (it is not valid Unicode).
    #[error("the reference image path is not valid unicode: {}", path.display())]
    NonUnicodeImagePath {
        /// The path.
        path: PathBuf,
    },
    /// The sketch could not be encoded as JSON.
    #[error("cannot encode the sketch as json")]
    Json {
        /// The encoder's error.
        #[source]
        source: serde_json::Error,
    },
    /// Writing the file failed; the previous file, if any, is untouched.
    #[error("cannot write {}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
}

/// A sketch that breaks the invariants of its strokes or extent.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SketchError {
    /// A stroke has fewer than two points.
    #[error(
        "stroke {id} (position {position} in the list) has {count} point(s); a stroke needs \
         at least 2"
    )]
    TooFewPoints {
        /// The stroke's id.
        id: u32,
        /// Its 0-based position in the list of strokes.
        position: usize,
        /// How many points it has.
        count: usize,
    },
    /// A stroke has a NaN or infinite coordinate.
    #[error("stroke {id} has a non-finite coordinate at point {point}")]
    NonFinitePoint {
        /// The stroke's id.
        id: u32,
        /// The 0-based index of the point.
        point: usize,
    },
    /// Two strokes share an id.
    #[error("stroke id {id} is used by more than one stroke")]
    DuplicateId {
        /// The id.
        id: u32,
    },
    /// The view box is not finite or has a non-positive width or height.
    #[error(
        "invalid view box {view_box:?}: expected finite [x, y, width, height] with a positive size"
    )]
    InvalidViewBox {
        /// The view box as `[x, y, width, height]`.
        view_box: [f64; 4],
    },
}

#[cfg(test)]
mod tests {
    use super::{LoadError, SaveError, SketchError};

    /// Loading runs on background threads in the app, so the errors must cross threads.
    #[test]
    fn errors_are_send_sync_and_static() {
        fn check<T: Send + Sync + 'static>() {}
        check::<LoadError>();
        check::<SaveError>();
        check::<SketchError>();
    }

    #[test]
    fn messages_are_lowercase_with_the_path_last_and_causes_as_sources() {
        let error = LoadError::File {
            path: "/tmp/goblet.svg".into(),
            source: Box::new(LoadError::CompressedSvg),
        };
        assert_eq!(error.to_string(), "cannot load sketch /tmp/goblet.svg");
        let cause = std::error::Error::source(&error).map(ToString::to_string);
        assert_eq!(
            cause.as_deref(),
            Some("compressed svg (svgz) is not supported; decompress it first")
        );
        let error = LoadError::from(SketchError::DuplicateId { id: 4 });
        assert_eq!(
            error.to_string(),
            "stroke id 4 is used by more than one stroke"
        );
    }
}
