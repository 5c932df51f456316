//! Strokes and sketches: the 2D input that primitives snap to.
//!
//! Nomenclature: a *stroke* is one polyline the designer drew (or one subpath of an
//! imported SVG), in *sketch space*: the SVG viewBox's user units, x to the right,
//! y **down** (formats.md §1). Each stroke has a *class*: a **feature** stroke is an
//! ellipse or elliptical arc (the outline of a circular end) or a box edge, a
//! **silhouette** stroke an outline of a side. The class is inferred automatically and
//! may be overridden per stroke.
//!
//! Neighbours: [`preprocess`](fn@preprocess) cleans and resamples strokes,
//! [`classify_sketch`] infers each stroke's class from an ellipse fit
//! ([`crate::geom::fit_ellipse`]) and its junctions with other strokes, and
//! [`StrokeIndex`] finds the strokes near a point for the curve assigner.

mod classify;
mod index;
mod parallel;
mod preprocess;
mod stroke;

pub use classify::{
    classify, classify_sketch, classify_with, effective_class, ClassReason, Classification,
    ClassifyOptions,
};
pub use index::StrokeIndex;
pub use preprocess::{
    preprocess, preprocess_report, MergedStroke, PreprocessOptions, Preprocessed,
};
pub use stroke::{Sketch, Stroke, StrokeClass, StrokeId};
