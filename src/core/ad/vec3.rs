//! 3-vectors of expressions: the algebra primitives and relations are written in
//! (dot, cross, norms, normalisation).

use std::ops::{Add, Mul, Neg, Sub};

use glam::DVec3;

use super::graph::{Expr, Graph};

/// A 3-vector of expressions of one [`Graph`].
///
/// # Examples
///
/// ```
/// use geosnap::core::ad::{Graph, Tape, Vec3};
///
/// let g = Graph::new();
/// let a = Vec3::new_vars(&g);
/// let b = Vec3::constant(&g, glam::DVec3::Y);
/// // 1 − (a·b)² is zero when a is a unit vector along ±Y.
/// let parallel = 1.0 - a.normalize().dot(b).square();
/// let mut tape = Tape::compile(&g, &[parallel]);
/// assert!(tape.eval(&[0.0, -2.0, 0.0])[0].abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[must_use = "a vector expression does nothing until it is used in an output"]
pub struct Vec3<'g> {
    /// The x component.
    pub x: Expr<'g>,
    /// The y component.
    pub y: Expr<'g>,
    /// The z component.
    pub z: Expr<'g>,
}

impl<'g> Vec3<'g> {
    /// A vector from three expressions.
    pub fn new(x: Expr<'g>, y: Expr<'g>, z: Expr<'g>) -> Self {
        Self { x, y, z }
    }

    /// Three new variables of `graph`, in x, y, z order.
    pub fn new_vars(graph: &'g Graph) -> Self {
        Self::new(graph.var(), graph.var(), graph.var())
    }

    /// A constant vector.
    pub fn constant(graph: &'g Graph, v: DVec3) -> Self {
        Self::new(
            graph.constant(v.x),
            graph.constant(v.y),
            graph.constant(v.z),
        )
    }

    /// The components as an array.
    pub fn to_array(self) -> [Expr<'g>; 3] {
        [self.x, self.y, self.z]
    }

    /// The dot product `a·b`.
    pub fn dot(self, other: Self) -> Expr<'g> {
        self.x
            .graph()
            .sum([self.x * other.x, self.y * other.y, self.z * other.z])
    }

    /// The cross product `a × b`.
    pub fn cross(self, other: Self) -> Self {
        Self::new(
            self.y * other.z - self.z * other.y,
            self.z * other.x - self.x * other.z,
            self.x * other.y - self.y * other.x,
        )
    }

    /// The squared length `|a|²`.
    pub fn norm_squared(self) -> Expr<'g> {
        self.x
            .graph()
            .sum([self.x.square(), self.y.square(), self.z.square()])
    }

    /// The length `|a|` (its derivative is undefined at the zero vector, where the tape
    /// yields a non-finite value that the solver reports).
    pub fn norm(self) -> Expr<'g> {
        self.norm_squared().sqrt()
    }

    /// `a / |a|`.
    pub fn normalize(self) -> Self {
        let inv = 1.0 / self.norm();
        self * inv
    }
}

impl Add for Vec3<'_> {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        Self::new(self.x + rhs.x, self.y + rhs.y, self.z + rhs.z)
    }
}

impl Sub for Vec3<'_> {
    type Output = Self;
    fn sub(self, rhs: Self) -> Self {
        Self::new(self.x - rhs.x, self.y - rhs.y, self.z - rhs.z)
    }
}

impl Neg for Vec3<'_> {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl<'g> Mul<Expr<'g>> for Vec3<'g> {
    type Output = Self;
    fn mul(self, s: Expr<'g>) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

impl Mul<f64> for Vec3<'_> {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::Vec3;
    use crate::core::ad::{Graph, Tape};

    #[test]
    fn vector_helpers_match_glam() {
        let g = Graph::new();
        let a = Vec3::new_vars(&g);
        let b = Vec3::new_vars(&g);
        let cross = a.cross(b);
        let n = a.normalize();
        let outputs = [
            a.dot(b),
            cross.x,
            cross.y,
            cross.z,
            a.norm_squared(),
            a.norm(),
            n.x,
            n.y,
            n.z,
            (a - b + (-a) * 2.0).x,
        ];
        let mut tape = Tape::compile(&g, &outputs);
        let (va, vb) = (DVec3::new(1.0, -2.0, 0.5), DVec3::new(0.3, 0.7, -1.1));
        let got = tape.eval(&[va.x, va.y, va.z, vb.x, vb.y, vb.z]).to_vec();
        let c = va.cross(vb);
        let n = va.normalize();
        let want = [
            va.dot(vb),
            c.x,
            c.y,
            c.z,
            va.length_squared(),
            va.length(),
            n.x,
            n.y,
            n.z,
            va.x - vb.x - 2.0 * va.x,
        ];
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-12, "{g} vs {w}");
        }
    }
}
