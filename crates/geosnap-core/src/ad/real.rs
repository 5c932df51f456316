//! [`Real`]: the scalar operations shared by `f64` and [`Expr`], so that a geometric
//! formula is written once and used both for plain evaluation (drawing, assignment) and
//! for building differentiable expressions (fitting).

use std::ops::{Add, Div, Mul, Neg, Sub};

use super::graph::Expr;

/// A real scalar: `f64`, or an [`Expr`] of a [`Graph`](super::Graph).
///
/// # Examples
///
/// ```
/// use geosnap_core::ad::{Graph, Real, Tape};
///
/// fn hypotenuse<T: Real>(a: T, b: T) -> T {
///     (a * a + b * b).sqrt()
/// }
/// assert_eq!(hypotenuse(3.0, 4.0), 5.0);
/// let g = Graph::new();
/// let (a, b) = (g.var(), g.var());
/// let mut tape = Tape::compile(&g, &[hypotenuse(a, b)]);
/// assert_eq!(tape.eval(&[3.0, 4.0])[0], 5.0);
/// ```
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    /// A constant of the same kind as `self` (for an [`Expr`], in the same graph).
    #[must_use]
    fn lit(self, value: f64) -> Self;
    /// `√self`.
    #[must_use]
    fn sqrt(self) -> Self;
    /// The natural logarithm.
    #[must_use]
    fn ln(self) -> Self;
    /// `self²`.
    #[must_use]
    fn square(self) -> Self;
    /// The sine.
    #[must_use]
    fn sin(self) -> Self;
    /// The cosine.
    #[must_use]
    fn cos(self) -> Self;
    /// `|self|`.
    #[must_use]
    fn abs(self) -> Self;
    /// The smaller of the two.
    #[must_use]
    fn min(self, other: Self) -> Self;
    /// The larger of the two.
    #[must_use]
    fn max(self, other: Self) -> Self;
    /// `√(self² + other²)`.
    #[must_use]
    fn hypot(self, other: Self) -> Self;
    /// `atan2(self, x)`.
    #[must_use]
    fn atan2(self, x: Self) -> Self;
}

impl Real for f64 {
    fn lit(self, value: f64) -> Self {
        value
    }
    fn ln(self) -> Self {
        Self::ln(self)
    }
    fn sqrt(self) -> Self {
        Self::sqrt(self)
    }
    fn square(self) -> Self {
        self * self
    }
    fn sin(self) -> Self {
        Self::sin(self)
    }
    fn cos(self) -> Self {
        Self::cos(self)
    }
    fn abs(self) -> Self {
        Self::abs(self)
    }
    fn min(self, other: Self) -> Self {
        Self::min(self, other)
    }
    fn max(self, other: Self) -> Self {
        Self::max(self, other)
    }
    fn hypot(self, other: Self) -> Self {
        Self::hypot(self, other)
    }
    fn atan2(self, x: Self) -> Self {
        Self::atan2(self, x)
    }
}

impl Real for Expr<'_> {
    fn lit(self, value: f64) -> Self {
        self.graph().constant(value)
    }
    fn ln(self) -> Self {
        Self::ln(self)
    }
    fn sqrt(self) -> Self {
        Self::sqrt(self)
    }
    fn square(self) -> Self {
        Self::square(self)
    }
    fn sin(self) -> Self {
        Self::sin(self)
    }
    fn cos(self) -> Self {
        Self::cos(self)
    }
    fn abs(self) -> Self {
        Self::abs(self)
    }
    fn min(self, other: Self) -> Self {
        Self::min(self, other)
    }
    fn max(self, other: Self) -> Self {
        Self::max(self, other)
    }
    fn hypot(self, other: Self) -> Self {
        Self::hypot(self, other)
    }
    fn atan2(self, x: Self) -> Self {
        Self::atan2(self, x)
    }
}
