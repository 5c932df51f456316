//! geosnap: sketch-based 3D modelling with geosemantic snapping.
//!
//! A designer draws strokes over a reference image, drags primitives (cylinders, cones,
//! spheres, boxes, generalized cylinders) onto the drawing, and each primitive snaps to
//! the strokes while it is dragged. On release, geosnap infers relations between the
//! parts and solves one global constrained problem so the model becomes consistent.
//!
//! # Layers
//!
//! ```text
//! app ──► render ──► core          core (the geosnap-core crate):
//!  │  └─► io ──────► core            ad ◄─ solve ◄─ geom, sketch ◄─ primitive
//!  └──────────────► core                 ◄─ snap, relation ◄─ model
//!                                  cli ──► io, core
//! ```
//!
//! - [`core`]: the product, pure (no GUI, GPU, filesystem or clock), in a crate of its
//!   own (`geosnap-core`) so that the compiler keeps it so: automatic differentiation,
//!   the solver, geometry, sketches, primitives, snapping, relations and the document.
//! - [`io`]: files (may use `std::fs`, never the GUI): SVG import into sketch space, the
//!   native sketch file, sessions, scripts and model files, glTF export
//!   ([`io::gltf`]), overlays and atomic writes. Their formats are specified in
//!   `docs/formats.md`.
//! - [`clock`]: the real clock handed to solves.
//! - [`cli`]: the command line's commands (`run`, `check`, `solve`, `export`, …), which
//!   the binary parses and runs, and tests drive in-process.
//! - `render` (the wgpu 3D view) and `app` (the egui/eframe application): the desktop
//!   application, behind the default `gui` feature.
//!
//! # Example
//!
//! Minimise a sum of squared residuals on a constraint surface: the point of the plane
//! x + y + z = 1 closest to (1, 2, 3), with the AD expressions and the solver.
//!
//! ```
//! use geosnap::core::ad::{Graph, Vec3};
//! use geosnap::core::solve::{solve, AugLagSettings, Problem};
//!
//! let g = Graph::new();
//! let p = Vec3::new_vars(&g);
//! let target = Vec3::constant(&g, glam::DVec3::new(1.0, 2.0, 3.0));
//! let mut problem = Problem::builder(&g, (p - target).norm_squared())
//!     .equality("plane", p.x + p.y + p.z - 1.0)
//!     .build();
//! let report = solve(&mut problem, &[0.0; 3], &AugLagSettings::default())?;
//! assert!(report.termination.is_converged());
//! let expected = [-2.0 / 3.0, 1.0 / 3.0, 4.0 / 3.0];
//! for (x, e) in report.x.iter().zip(expected) {
//!     assert!((x - e).abs() < 1e-7);
//! }
//! # Ok::<(), geosnap::core::solve::SolveError>(())
//! ```
//!
//! # Features
//!
//! - `gui` (default): the egui/eframe desktop application with its wgpu viewport.
//!   `cargo test --no-default-features` builds and tests everything else.

#[cfg(feature = "gui")]
pub mod app;
pub mod cli;
pub mod clock;
#[doc(inline)]
pub use geosnap_core as core;
pub mod io;
#[cfg(feature = "gui")]
pub mod render;
pub mod samples;
