//! Dimensions: exact sizes a user types for a part (a radius, a length), held as hard
//! constraints of the global solve, as in parametric CAD.
//!
//! A [`Dimension`] names a part, a [`Quantity`] of its kind and a value in model space
//! (sketch units, formats.md §1). [`Document::set_dimension`] sets the part's parameter
//! to the value at once, so the model shows it even before a solve; the global solve
//! (module `solve`) then keeps it as the equality `x_q − value/s = 0` in the part's
//! normalised frame (s the frame's scale: sizes map by 1/s) while it refits the part's
//! other parameters to its strokes. Dimensions are the user's word: the conflict logic
//! never switches one off, it switches off the relations that contradict them.

use serde::{Deserialize, Serialize};

use super::{Document, PrimitiveId};
use crate::primitive::{Cone, Cuboid, Cylinder, Primitive, PrimitiveKind, Sgc, Sphere};

/// A size of a primitive that can be dimensioned, in model space (sketch units).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// The radius of a cylinder or sphere.
    Radius,
    /// The radius of a cone's top end.
    RadiusTop,
    /// The radius of a cone's bottom end.
    RadiusBottom,
    /// The length along the axis of a cylinder, cone or SGC.
    Length,
    /// A cuboid's size along its local x axis (`size.x`).
    Width,
    /// A cuboid's size along its local y axis (`size.y`).
    Height,
    /// A cuboid's size along its local z axis (`size.z`).
    Depth,
}

impl Quantity {
    /// Every quantity.
    pub const ALL: [Self; 7] = [
        Self::Radius,
        Self::RadiusTop,
        Self::RadiusBottom,
        Self::Length,
        Self::Width,
        Self::Height,
        Self::Depth,
    ];

    /// The name used in files and labels (`"radius"`, `"radius_top"`, …).
    pub fn name(self) -> &'static str {
        match self {
            Self::Radius => "radius",
            Self::RadiusTop => "radius_top",
            Self::RadiusBottom => "radius_bottom",
            Self::Length => "length",
            Self::Width => "width",
            Self::Height => "height",
            Self::Depth => "depth",
        }
    }

    /// The quantities a kind has: cylinder radius and length; cone bottom and top radii
    /// and length; sphere radius; cuboid width, height and depth (its `size` along its
    /// local x, y and z axes); SGC length (its radii form a profile, not one number);
    /// none for a BGC, whose length and radii are spread along a bent spine.
    pub fn of_kind(kind: PrimitiveKind) -> &'static [Self] {
        match kind {
            PrimitiveKind::Cylinder => &[Self::Radius, Self::Length],
            PrimitiveKind::Cone => &[Self::RadiusBottom, Self::RadiusTop, Self::Length],
            PrimitiveKind::Sphere => &[Self::Radius],
            PrimitiveKind::Cuboid => &[Self::Width, Self::Height, Self::Depth],
            PrimitiveKind::Sgc => &[Self::Length],
            PrimitiveKind::Bgc => &[],
        }
    }

    /// The index of this quantity in [`Primitive::params`] of a primitive of `kind`, or
    /// `None` when the kind does not have it. Each quantity is one size parameter, which
    /// the normalised frame scales by 1/s.
    pub(crate) fn param_index(self, kind: PrimitiveKind) -> Option<usize> {
        match (kind, self) {
            (PrimitiveKind::Cylinder, Self::Length) => Some(Cylinder::LENGTH),
            (PrimitiveKind::Cylinder, Self::Radius) => Some(Cylinder::RADIUS),
            (PrimitiveKind::Cone, Self::Length) => Some(Cone::LENGTH),
            (PrimitiveKind::Cone, Self::RadiusBottom) => Some(Cone::RADIUS_BOTTOM),
            (PrimitiveKind::Cone, Self::RadiusTop) => Some(Cone::RADIUS_TOP),
            (PrimitiveKind::Sgc, Self::Length) => Some(Sgc::LENGTH),
            (PrimitiveKind::Sphere, Self::Radius) => Some(Sphere::RADIUS),
            (PrimitiveKind::Cuboid, Self::Width) => Some(Cuboid::WIDTH),
            (PrimitiveKind::Cuboid, Self::Height) => Some(Cuboid::HEIGHT),
            (PrimitiveKind::Cuboid, Self::Depth) => Some(Cuboid::DEPTH),
            _ => None,
        }
    }
}

impl std::fmt::Display for Quantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Primitive {
    /// The value of `quantity` in model space (sketch units), or `None` when this kind
    /// does not have it (see [`Quantity::of_kind`]).
    pub fn quantity(&self, quantity: Quantity) -> Option<f64> {
        let index = quantity.param_index(self.kind())?;
        self.params().get(index).copied()
    }

    /// The same primitive with `quantity` set to `value` (model space), everything else
    /// unchanged to the bit; `None` when this kind does not have the quantity or `value`
    /// is not a finite positive number.
    #[must_use]
    pub fn with_quantity(&self, quantity: Quantity, value: f64) -> Option<Self> {
        if !(value.is_finite() && value > 0.0) {
            return None;
        }
        let mut out = self.clone();
        let field = match (&mut out, quantity) {
            (Self::Cylinder(c), Quantity::Radius) => &mut c.radius,
            (Self::Cylinder(c), Quantity::Length) => &mut c.length,
            (Self::Cone(c), Quantity::RadiusBottom) => &mut c.radius_bottom,
            (Self::Cone(c), Quantity::RadiusTop) => &mut c.radius_top,
            (Self::Cone(c), Quantity::Length) => &mut c.length,
            (Self::Sphere(s), Quantity::Radius) => &mut s.radius,
            (Self::Cuboid(b), Quantity::Width) => &mut b.size.x,
            (Self::Cuboid(b), Quantity::Height) => &mut b.size.y,
            (Self::Cuboid(b), Quantity::Depth) => &mut b.size.z,
            (Self::Sgc(s), Quantity::Length) => &mut s.length,
            _ => return None,
        };
        *field = value;
        debug_assert!(
            out.quantity(quantity) == Some(value),
            "with_quantity and param_index agree"
        );
        Some(out)
    }
}

/// An exact size the user typed for a part: a hard constraint of the global solve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Dimension {
    /// The part.
    pub primitive: PrimitiveId,
    /// Which of its sizes.
    pub quantity: Quantity,
    /// The value, in model space (sketch units), finite and positive.
    pub value: f64,
}

/// Why a dimension was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DimensionError {
    /// The document has no such part.
    #[error("there is no primitive {}", id.0)]
    NoPrimitive {
        /// The id asked for.
        id: PrimitiveId,
    },
    /// The part's kind does not have the quantity.
    #[error("a {} has no {quantity}", kind.name())]
    NotOfKind {
        /// The quantity asked for.
        quantity: Quantity,
        /// The part's kind.
        kind: PrimitiveKind,
    },
    /// The value is not a finite positive number.
    #[error("a {quantity} must be a finite positive number, not {value}")]
    InvalidValue {
        /// The quantity.
        quantity: Quantity,
        /// The value refused.
        value: f64,
    },
}

impl Document {
    /// The dimensions, in the order they were first set.
    pub fn dimensions(&self) -> &[Dimension] {
        &self.dimensions
    }

    /// The dimensions of part `id`.
    pub fn dimensions_of(&self, id: PrimitiveId) -> impl Iterator<Item = &Dimension> {
        self.dimensions.iter().filter(move |d| d.primitive == id)
    }

    /// Dimensions part `id`'s `quantity` to `value` (model space): the part's parameter
    /// is set at once, and every later global solve holds it exactly (see the module
    /// docs). A dimension of the same part and quantity is replaced. Call
    /// [`Document::solve`] with the part as changed to refit its other parameters.
    ///
    /// # Errors
    ///
    /// [`DimensionError::NoPrimitive`], [`DimensionError::NotOfKind`] when the part's
    /// kind has no such quantity ([`Quantity::of_kind`]), and
    /// [`DimensionError::InvalidValue`] for a non-finite or non-positive value; the
    /// document is then unchanged.
    pub fn set_dimension(
        &mut self,
        id: PrimitiveId,
        quantity: Quantity,
        value: f64,
    ) -> Result<(), DimensionError> {
        let placed = self
            .primitives
            .get_mut(&id)
            .ok_or(DimensionError::NoPrimitive { id })?;
        let kind = placed.primitive.kind();
        if quantity.param_index(kind).is_none() {
            return Err(DimensionError::NotOfKind { quantity, kind });
        }
        let primitive = placed
            .primitive
            .with_quantity(quantity, value)
            .ok_or(DimensionError::InvalidValue { quantity, value })?;
        placed.primitive = primitive;
        let dimension = Dimension {
            primitive: id,
            quantity,
            value,
        };
        match self
            .dimensions
            .iter_mut()
            .find(|d| d.primitive == id && d.quantity == quantity)
        {
            Some(existing) => *existing = dimension,
            None => self.dimensions.push(dimension),
        }
        Ok(())
    }

    /// Removes the dimension of part `id`'s `quantity`; whether there was one. The part
    /// keeps its current size, now free to change in later solves.
    pub fn remove_dimension(&mut self, id: PrimitiveId, quantity: Quantity) -> bool {
        let before = self.dimensions.len();
        self.dimensions
            .retain(|d| !(d.primitive == id && d.quantity == quantity));
        self.dimensions.len() != before
    }
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use super::{DimensionError, Quantity};
    use crate::model::{Document, Fit, Placed, PrimitiveId};
    use crate::primitive::{Cone, Cuboid, Cylinder, Primitive, PrimitiveKind, Sphere};

    fn placed(primitive: Primitive) -> Placed {
        Placed {
            primitive,
            fit: Fit::default(),
        }
    }

    fn samples() -> Vec<Primitive> {
        vec![
            Primitive::Cylinder(Cylinder {
                center: DVec3::new(1.0, 2.0, 3.0),
                axis: DVec3::Y,
                length: 10.0,
                radius: 2.0,
            }),
            Primitive::Cone(Cone {
                center: DVec3::ZERO,
                axis: DVec3::X,
                length: 8.0,
                radius_bottom: 3.0,
                radius_top: 1.0,
            }),
            Primitive::Sphere(Sphere {
                center: DVec3::ZERO,
                radius: 4.0,
            }),
            Primitive::Cuboid(Cuboid {
                center: DVec3::ONE,
                rotation: DQuat::from_rotation_y(0.3),
                size: DVec3::new(5.0, 6.0, 7.0),
            }),
        ]
    }

    #[test]
    fn every_quantity_of_a_kind_reads_and_writes_its_own_parameter() {
        for p in samples() {
            for &q in Quantity::of_kind(p.kind()) {
                let before = p.quantity(q).expect("the kind has it");
                let changed = p.with_quantity(q, before + 1.5).expect("settable");
                assert!((changed.quantity(q).expect("still there") - before - 1.5).abs() < 1e-12);
                // Only that parameter moved.
                let moved = p
                    .params()
                    .iter()
                    .zip(changed.params())
                    .filter(|(a, b)| (**a - *b).abs() > 1e-12)
                    .count();
                assert_eq!(moved, 1, "{:?} {q}", p.kind());
            }
            for q in Quantity::ALL {
                if !Quantity::of_kind(p.kind()).contains(&q) {
                    assert_eq!(p.quantity(q), None);
                    assert_eq!(p.with_quantity(q, 1.0), None);
                }
            }
        }
        let Primitive::Cuboid(b) = &samples()[3] else {
            unreachable!("the fourth sample is a box")
        };
        let cuboid = Primitive::Cuboid(b.clone());
        assert_eq!(cuboid.quantity(Quantity::Width), Some(5.0));
        assert_eq!(cuboid.quantity(Quantity::Height), Some(6.0));
        assert_eq!(cuboid.quantity(Quantity::Depth), Some(7.0));
        assert!(Quantity::of_kind(PrimitiveKind::Bgc).is_empty());
    }

    #[test]
    fn names_match_the_serde_names() {
        for q in Quantity::ALL {
            assert_eq!(
                serde_json::to_value(q).expect("serialises"),
                serde_json::Value::String(q.name().to_owned())
            );
        }
    }

    #[test]
    fn bad_dimensions_are_refused_and_leave_the_document_alone() {
        let mut doc = Document::new();
        let a = doc.add(placed(samples()[0].clone()));
        let before = doc.clone();
        assert_eq!(
            doc.set_dimension(PrimitiveId(9), Quantity::Radius, 1.0),
            Err(DimensionError::NoPrimitive { id: PrimitiveId(9) })
        );
        assert_eq!(
            doc.set_dimension(a, Quantity::Width, 1.0),
            Err(DimensionError::NotOfKind {
                quantity: Quantity::Width,
                kind: PrimitiveKind::Cylinder
            })
        );
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let error = doc
                .set_dimension(a, Quantity::Radius, bad)
                .expect_err("refused");
            assert!(matches!(error, DimensionError::InvalidValue { .. }));
            assert!(error.to_string().contains("radius"), "{error}");
        }
        assert_eq!(doc, before);
    }

    #[test]
    fn a_dimension_applies_at_once_replaces_its_like_and_goes_with_its_part() {
        let mut doc = Document::new();
        let a = doc.add(placed(samples()[0].clone()));
        let b = doc.add(placed(samples()[2].clone()));
        doc.set_dimension(a, Quantity::Radius, 3.0).expect("valid");
        doc.set_dimension(a, Quantity::Length, 12.0).expect("valid");
        doc.set_dimension(a, Quantity::Radius, 2.5).expect("valid");
        doc.set_dimension(b, Quantity::Radius, 1.0).expect("valid");
        let radius = |doc: &Document| {
            doc.get(a)
                .and_then(|p| p.primitive.quantity(Quantity::Radius))
        };
        assert_eq!(radius(&doc), Some(2.5));
        assert_eq!(doc.dimensions().len(), 3);
        assert_eq!(doc.dimensions_of(a).count(), 2);
        assert!(doc.remove_dimension(a, Quantity::Length));
        assert!(!doc.remove_dimension(a, Quantity::Length));
        assert!(doc.remove(a).is_some());
        assert_eq!(doc.dimensions().len(), 1);
        assert_eq!(doc.dimensions()[0].primitive, b);
    }
}
