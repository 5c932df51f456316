//! The product, pure: geometry, numerics and the document, with no GUI, GPU, filesystem
//! or clock (time comes in through [`solve::Clock`]).
//!
//! Layers, each depending only on those before it: [`ad`] ← [`solve`] ← [`geom`] ←
//! [`sketch`].

pub mod ad;
pub mod geom;
pub mod model;
pub mod primitive;
pub mod relation;
pub mod sketch;
pub mod snap;
pub mod solve;
