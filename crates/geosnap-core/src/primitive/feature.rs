//! The feature curves of primitives that relations refer to: the ends of a solid of
//! revolution or a generalized cylinder, a sphere's outline and the faces of a box.
//!
//! A [`Feature`] is a value, not a name: names (`"top"`, `"front"`, …) are how files and
//! messages spell features, and a name means a feature only for a given kind (a box's
//! `top` is its +y face, a cylinder's `top` its top end), so reading one needs the kind
//! ([`Feature::from_name`]).

use std::fmt;

use super::PrimitiveKind;

/// An axis of a box's local frame: x is the width direction, y the height, z the depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Axis {
    /// The local x axis (width).
    X,
    /// The local y axis (height).
    Y,
    /// The local z axis (depth).
    Z,
}

impl Axis {
    /// The three axes, in order.
    pub const ALL: [Self; 3] = [Self::X, Self::Y, Self::Z];

    /// The axis's index: 0 for x, 1 for y, 2 for z.
    pub fn index(self) -> usize {
        match self {
            Self::X => 0,
            Self::Y => 1,
            Self::Z => 2,
        }
    }
}

/// A feature curve of a primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Feature {
    /// The top end circle of a cylinder, cone or generalized cylinder (where its axis
    /// points).
    Top,
    /// The bottom end circle of a cylinder, cone or generalized cylinder.
    Bottom,
    /// A sphere's outline: its great circle facing the viewer.
    Outline,
    /// A face of a box: the one whose outward normal is `axis` (`positive`) or its
    /// opposite.
    Face {
        /// The local axis the face is perpendicular to.
        axis: Axis,
        /// Whether the outward normal points along the axis (`true`) or against it.
        positive: bool,
    },
}

impl Feature {
    /// The ends of a solid of revolution or a generalized cylinder, top first.
    pub const ENDS: [Self; 2] = [Self::Top, Self::Bottom];

    /// The six faces of a box: outward normals +x, −x, +y, −y, +z, −z of its local frame.
    pub const FACES: [Self; 6] = [
        Self::face(Axis::X, true),
        Self::face(Axis::X, false),
        Self::face(Axis::Y, true),
        Self::face(Axis::Y, false),
        Self::face(Axis::Z, true),
        Self::face(Axis::Z, false),
    ];

    /// The box face perpendicular to `axis`, on its positive or negative side.
    pub const fn face(axis: Axis, positive: bool) -> Self {
        Self::Face { axis, positive }
    }

    /// The name used in files and messages: `top`, `bottom`, `outline`, and for box faces
    /// `right`, `left`, `top`, `bottom`, `front`, `back` (+x, −x, +y, −y, +z, −z). A box's
    /// +y face and a cylinder's top end share the name `top`; the kind tells them apart.
    pub fn name(self) -> &'static str {
        match self {
            Self::Top
            | Self::Face {
                axis: Axis::Y,
                positive: true,
            } => "top",
            Self::Bottom
            | Self::Face {
                axis: Axis::Y,
                positive: false,
            } => "bottom",
            Self::Outline => "outline",
            Self::Face {
                axis: Axis::X,
                positive,
            } => {
                if positive {
                    "right"
                } else {
                    "left"
                }
            }
            Self::Face {
                axis: Axis::Z,
                positive,
            } => {
                if positive {
                    "front"
                } else {
                    "back"
                }
            }
        }
    }

    /// The feature of a primitive of `kind` called `name`, if it has one.
    ///
    /// # Examples
    ///
    /// ```
    /// use geosnap_core::primitive::{Axis, Feature, PrimitiveKind};
    ///
    /// assert_eq!(Feature::from_name(PrimitiveKind::Cone, "top"), Some(Feature::Top));
    /// assert_eq!(
    ///     Feature::from_name(PrimitiveKind::Cuboid, "top"),
    ///     Some(Feature::face(Axis::Y, true))
    /// );
    /// assert_eq!(Feature::from_name(PrimitiveKind::Sphere, "top"), None);
    /// ```
    pub fn from_name(kind: PrimitiveKind, name: &str) -> Option<Self> {
        kind.features().iter().copied().find(|f| f.name() == name)
    }

    /// The direction class of the feature on its primitive: the local axis of a box
    /// face, 0 (the primitive's one axis) for any other feature.
    pub fn direction_class(self) -> usize {
        match self {
            Self::Face { axis, .. } => axis.index(),
            Self::Top | Self::Bottom | Self::Outline => 0,
        }
    }
}

impl fmt::Display for Feature {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl PrimitiveKind {
    /// The feature curves a primitive of this kind has, in the order of its
    /// [`Shape::features`](super::Shape::features).
    pub fn features(self) -> &'static [Feature] {
        match self {
            Self::Cylinder | Self::Cone | Self::Sgc | Self::Bgc => &Feature::ENDS,
            Self::Sphere => &[Feature::Outline],
            Self::Cuboid => &Feature::FACES,
        }
    }

    /// Whether a primitive of this kind has `feature`.
    pub fn has(self, feature: Feature) -> bool {
        self.features().contains(&feature)
    }
}

#[cfg(test)]
mod tests {
    use super::{Axis, Feature};
    use crate::primitive::{Placement, Primitive, PrimitiveKind};

    #[test]
    fn every_kinds_features_round_trip_through_their_names() {
        for kind in PrimitiveKind::ALL {
            assert!(!kind.features().is_empty(), "{kind:?} has features");
            for &feature in kind.features() {
                assert_eq!(
                    Feature::from_name(kind, feature.name()),
                    Some(feature),
                    "{kind:?} {feature}"
                );
                assert!(kind.has(feature), "{kind:?} has {feature}");
            }
        }
    }

    #[test]
    fn the_shape_lists_the_kinds_features_in_order() {
        for kind in PrimitiveKind::ALL {
            let p = Primitive::from_placement(kind, &Placement::at(glam::DVec2::ZERO), 40.0);
            let listed: Vec<Feature> = p
                .current_shape()
                .features
                .iter()
                .map(|f| f.feature)
                .collect();
            assert_eq!(listed, kind.features(), "{kind:?}");
        }
    }

    #[test]
    fn unknown_names_and_other_kinds_features_are_refused() {
        assert_eq!(Feature::from_name(PrimitiveKind::Cylinder, "lid"), None);
        assert_eq!(Feature::from_name(PrimitiveKind::Cylinder, "front"), None);
        assert_eq!(Feature::from_name(PrimitiveKind::Cuboid, "outline"), None);
        assert_eq!(Feature::from_name(PrimitiveKind::Sphere, "Top"), None);
        assert!(!PrimitiveKind::Sphere.has(Feature::Top));
        assert!(!PrimitiveKind::Cone.has(Feature::face(Axis::Y, true)));
    }

    #[test]
    fn box_faces_are_named_by_axis_and_side() {
        let names: Vec<&str> = Feature::FACES.iter().map(|f| f.name()).collect();
        assert_eq!(names, ["right", "left", "top", "bottom", "front", "back"]);
        for (k, face) in Feature::FACES.iter().enumerate() {
            assert_eq!(face.direction_class(), k / 2, "{face}");
        }
    }
}
