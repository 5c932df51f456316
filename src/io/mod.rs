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
//! - [`json`]: strict JSON reading for scripts and models: unknown fields refused with a
//!   suggestion, messages in our words with the line and column.
//! - [`input`]: [`read_input`](input::read_input), which reads only regular files up to
//!   a size limit.
//! - [`atomic`]: [`write_atomic`], which replaces a file so that a crash or a full disk
//!   never leaves it half written, [`write_all_atomic`] for the several outputs of one
//!   command (all or none), and [`check_target`] to check an output before any work.
//!
//! Errors are typed: [`LoadError`] when reading, [`SaveError`] when writing, and
//! [`SketchError`] for a sketch that breaks the stroke invariants.

pub mod atomic;
mod error;
pub mod gltf;
pub mod input;
pub mod json;
pub mod model_file;
pub mod overlay;
pub mod script;
pub mod session;
pub mod sketch_file;
pub mod svg;

pub use atomic::{check_target, write_all_atomic, write_atomic};
pub use error::{LoadError, SaveError, SketchError};
pub use session::{
    load_session, parse_session, save_session, session_bytes, Session, SessionError,
};
pub use sketch_file::{load_sketch, save_sketch, LoadedSketch};
pub use svg::{import_svg, SvgImport, SvgOptions};
