//! Reverse-mode automatic differentiation: an expression builder and a compiled tape.
//!
//! Build expressions once in a [`Graph`] through [`Expr`] handles (operators `+ − × ÷`,
//! negation, powers, `sqrt`, `exp`, `ln`, trigonometry, `atan2`, `abs`, `hypot`,
//! `min`/`max`, n-ary [`Graph::sum`], and the [`Vec3`] helpers), then compile the outputs
//! you need into a [`Tape`] and evaluate it as often as you like:
//!
//! - [`Tape::eval`]: the output values (one forward sweep);
//! - [`Tape::gradient`]: value and gradient of the first output (forward + reverse);
//! - [`Tape::forward`] then [`Tape::reverse`]: the gradient of any weighted sum of the
//!   outputs, which is how the solver gets ∇ of a Lagrangian from one tape holding the
//!   objective and the constraints;
//! - [`Tape::jacobian`]: every output's gradient.
//!
//! Nomenclature: a *node* is one operation of the graph, a *slot* its place on the tape,
//! an *edge* one argument of an operation (with its local partial derivative), a
//! *parameter* an input that is not differentiated (multipliers, weights, targets).
//!
//! Shared sub-expressions are evaluated once: a handle used twice is one node, and equal
//! operations on equal operands are merged while building (hash-consing). Evaluations
//! allocate nothing: the tape keeps its value, partial and adjoint buffers.
//!
//! Cost: a forward sweep is one pass over the operations, a reverse sweep one pass over
//! the edges, independent of the number of variables (reverse mode).

mod graph;
mod ops;
mod real;
mod tape;
mod vec3;

pub use graph::{Expr, Graph};
pub use real::Real;
pub use tape::{ParamId, Tape};

/// The distance from `p` to the ellipse c + a·cos θ + b·sin θ, and the θ of the closest
/// point: the plain-number twin of [`Graph::ellipse_distance`].
pub fn ellipse_distance(
    c: glam::DVec2,
    a: glam::DVec2,
    b: glam::DVec2,
    p: glam::DVec2,
) -> (f64, f64) {
    let theta = ops::closest_ellipse_angle(c.to_array(), a.to_array(), b.to_array(), p.to_array());
    let q = c + a * theta.cos() + b * theta.sin();
    (q.distance(p), theta)
}

pub use vec3::{Vec2, Vec3};
