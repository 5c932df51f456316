//! Files: reading and writing what the designer works on.
//!
//! This layer may use `std::fs` and depends on [`crate::core`]; it never names the GUI
//! (design.md §1). Today it holds:
//!
//! - [`svg`]: SVG import through usvg: every path, basic shape, group and transform
//!   becomes polylines in *sketch space* (formats.md §1), with a list of warnings for
//!   content that is not imported (text, images, hidden elements).
//! - [`sketch_file`]: the native, versioned JSON sketch file, and [`load_sketch`], which
//!   opens either kind of file.
//! - [`script`]: placement scripts (formats.md §2); [`model_file`]: model files
//!   (formats.md §3); [`overlay`]: the overlay PNG of a run.
//! - [`session`]: session files, the whole work (sketch, image, document with its
//!   relations, dimensions and snap records) saved and reopened.
//! - [`gltf`]: glTF 2.0 export (`.glb`, `.gltf`) with the model's meaning in `extras`,
//!   and the reader of those extras.
//! - [`atomic`]: [`write_atomic`], which replaces a file so that a crash or a full disk
//!   never leaves it half written.
//!
//! Errors are typed: [`LoadError`] when reading, [`SaveError`] when writing, and
//! [`SketchError`] for a sketch that breaks the stroke invariants.

pub mod atomic;
mod error;
pub mod gltf;
pub mod model_file;
pub mod overlay;
pub mod script;
pub mod session;
pub mod sketch_file;
pub mod svg;

pub use atomic::write_atomic;
pub use error::{LoadError, SaveError, SketchError};
pub use session::{
    load_session, parse_session, save_session, session_bytes, Session, SessionError,
};
pub use sketch_file::{load_sketch, save_sketch, LoadedSketch};
pub use svg::{import_svg, SvgImport, SvgOptions};
