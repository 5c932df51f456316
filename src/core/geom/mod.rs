//! Geometry: projection and camera conventions, fitting of lines, circles and ellipses
//! to points, and meshes.

pub mod projection;

mod fit;

pub use fit::{
    fit_circle, fit_ellipse, fit_line, refine_ellipse, AngularSpan, Circle2, Ellipse2, Line2,
};
