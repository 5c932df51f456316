//! Small vectors over any [`Real`] scalar: the algebra primitives and relations are
//! written in (dot, cross, norms, normalisation), once for `f64` and [`Expr`].

use std::ops::{Add, Mul, Neg, Sub};

use glam::{DVec2, DVec3};

use super::graph::{Expr, Graph};
use super::real::Real;

/// A 3-vector of scalars (`f64` or [`Expr`]).
///
/// # Examples
///
/// ```
/// use geosnap_core::ad::{Graph, Tape, Vec3};
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
#[must_use = "a vector does nothing until it is used"]
pub struct Vec3<T> {
    /// The x component.
    pub x: T,
    /// The y component.
    pub y: T,
    /// The z component.
    pub z: T,
}

/// A 2-vector of scalars (`f64` or [`Expr`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[must_use = "a vector does nothing until it is used"]
pub struct Vec2<T> {
    /// The x component.
    pub x: T,
    /// The y component.
    pub y: T,
}

impl<'g> Vec3<Expr<'g>> {
    /// Three new variables of `graph`, in x, y, z order.
    pub fn new_vars(graph: &'g Graph) -> Self {
        Self::new(graph.var(), graph.var(), graph.var())
    }

    /// A constant vector in `graph`.
    pub fn constant(graph: &'g Graph, v: DVec3) -> Self {
        Self::new(
            graph.constant(v.x),
            graph.constant(v.y),
            graph.constant(v.z),
        )
    }
}

impl Vec3<f64> {
    /// From a glam vector.
    pub fn from_dvec3(v: DVec3) -> Self {
        Self::new(v.x, v.y, v.z)
    }

    /// To a glam vector.
    pub fn to_dvec3(self) -> DVec3 {
        DVec3::new(self.x, self.y, self.z)
    }
}

impl<T: Real> Vec3<T> {
    /// A vector from three scalars.
    pub fn new(x: T, y: T, z: T) -> Self {
        Self { x, y, z }
    }

    /// A constant vector of the same kind as `like` (for expressions, in its graph).
    pub fn lit(like: T, v: DVec3) -> Self {
        Self::new(like.lit(v.x), like.lit(v.y), like.lit(v.z))
    }

    /// The components as an array.
    pub fn to_array(self) -> [T; 3] {
        [self.x, self.y, self.z]
    }

    /// The dot product `a·b`.
    pub fn dot(self, other: Self) -> T {
        self.x * other.x + self.y * other.y + self.z * other.z
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
    pub fn norm_squared(self) -> T {
        self.dot(self)
    }

    /// The length `|a|` (its derivative is undefined at the zero vector, where the tape
    /// yields a non-finite value that the solver reports).
    pub fn norm(self) -> T {
        self.norm_squared().sqrt()
    }

    /// `a / |a|`.
    pub fn normalize(self) -> Self {
        let n = self.norm();
        Self::new(self.x / n, self.y / n, self.z / n)
    }

    /// The projection onto the view plane: (x, y), dropping depth z (formats.md §1).
    pub fn xy(self) -> Vec2<T> {
        Vec2::new(self.x, self.y)
    }
}

impl<T: Real> Vec2<T> {
    /// A vector from two scalars.
    pub fn new(x: T, y: T) -> Self {
        Self { x, y }
    }

    /// A constant vector of the same kind as `like`.
    pub fn lit(like: T, v: DVec2) -> Self {
        Self::new(like.lit(v.x), like.lit(v.y))
    }

    /// The components as an array.
    pub fn to_array(self) -> [T; 2] {
        [self.x, self.y]
    }

    /// The dot product.
    pub fn dot(self, other: Self) -> T {
        self.x * other.x + self.y * other.y
    }

    /// The z component of the 3D cross product (the 2D "perp dot").
    pub fn cross(self, other: Self) -> T {
        self.x * other.y - self.y * other.x
    }

    /// The length.
    pub fn norm(self) -> T {
        self.x.hypot(self.y)
    }

    /// The vector turned by +90°.
    pub fn perp(self) -> Self {
        Self::new(-self.y, self.x)
    }
}

impl Vec2<f64> {
    /// To a glam vector.
    pub fn to_dvec2(self) -> DVec2 {
        DVec2::new(self.x, self.y)
    }
}

macro_rules! vector_ops {
    ($name:ident { $($c:ident),* }) => {
        impl<T: Real> Add for $name<T> {
            type Output = Self;
            fn add(self, rhs: Self) -> Self {
                Self { $($c: self.$c + rhs.$c),* }
            }
        }
        impl<T: Real> Sub for $name<T> {
            type Output = Self;
            fn sub(self, rhs: Self) -> Self {
                Self { $($c: self.$c - rhs.$c),* }
            }
        }
        impl<T: Real> Neg for $name<T> {
            type Output = Self;
            fn neg(self) -> Self {
                Self { $($c: -self.$c),* }
            }
        }
        impl<T: Real> Mul<T> for $name<T> {
            type Output = Self;
            fn mul(self, s: T) -> Self {
                Self { $($c: self.$c * s),* }
            }
        }
        impl<T: Real> $name<T> {
            /// The vector times a constant.
            pub fn scale(self, s: f64) -> Self {
                Self { $($c: self.$c * s),* }
            }
        }
    };
}

vector_ops!(Vec3 { x, y, z });
vector_ops!(Vec2 { x, y });

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::Vec3;
    use crate::ad::{Graph, Tape};

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
            (a - b + (-a).scale(2.0)).x,
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

    #[test]
    fn the_same_formula_serves_f64_and_expressions() {
        let a = Vec3::from_dvec3(DVec3::new(1.0, 2.0, 2.0));
        assert!((a.norm() - 3.0).abs() < 1e-15);
        assert!((a.normalize().to_dvec3() - DVec3::new(1.0, 2.0, 2.0) / 3.0).length() < 1e-15);
        assert!((a.xy().perp().to_dvec2() - glam::DVec2::new(-2.0, 1.0)).length() < 1e-15);
    }
}
