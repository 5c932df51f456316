//! The product of geosnap, pure: numerics, geometry, snapping, relations and the
//! document, with no GUI, GPU, filesystem or clock (time comes in through
//! [`solve::Clock`]). Files, the clock, the 3D view and the application live in the
//! `geosnap` crate above it, which re-exports this one as `geosnap::core`.
//!
//! Layers, each depending only on those before it:
//!
//! ```text
//! ad ◄─ solve ◄─ geom, sketch ◄─ primitive ◄─ snap, relation ◄─ model
//! ```
//!
//! - [`ad`]: reverse-mode automatic differentiation (expression graph and tape).
//! - [`solve`]: the augmented-Lagrangian solver with its settings, reports and context.
//! - [`geom`]: the camera convention and the fits of lines, circles and ellipses.
//! - [`sketch`]: strokes, their preprocessing, classification and spatial index.
//! - [`primitive`]: the six kinds, their parameter layouts, features, validation and
//!   meshes.
//! - [`snap`]: curve assignment, starting poses, the snapping objective and confidence.
//! - [`relation`]: the relation kinds, their residuals and inference.
//! - [`model`]: the document (parts, relations, dimensions), the release of a placed
//!   part and the global solve.

pub mod ad;
pub mod geom;
pub mod model;
pub mod primitive;
pub mod relation;
pub mod sketch;
pub mod snap;
pub mod solve;
