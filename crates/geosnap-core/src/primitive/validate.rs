//! The invariants every primitive holds, checked in one place: finite parameters, unit
//! axes and frames, positive sizes, and enough (distinct) profile and spine samples.
//!
//! Readers of files, the glTF export and the application check what they are handed with
//! [`Primitive::validate`] and report its [`PrimitiveError`].

use glam::DVec3;

use super::{Bgc, Cuboid, Primitive, Sgc};

/// How far the length of a unit vector (an axis, a frame's quaternion) may be from 1.
pub const UNIT_TOLERANCE: f64 = 1e-6;

/// Why a primitive is invalid. Fields are named as in model files (`axis`, `radius_top`,
/// `size`, `radii`, `spine`, `plane_normal`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PrimitiveError {
    /// A parameter is NaN or infinite.
    #[error("a parameter is NaN or infinite")]
    NotFinite,
    /// A direction is the zero vector.
    #[error("`{field}` has no direction")]
    NoDirection {
        /// The field.
        field: &'static str,
    },
    /// A direction is not of unit length.
    #[error("`{field}` must be a unit vector, has length {length}")]
    NotUnit {
        /// The field.
        field: &'static str,
        /// Its length.
        length: f64,
    },
    /// A size is zero or negative.
    #[error("`{field}` must be positive, got {value}")]
    NotPositive {
        /// The field.
        field: &'static str,
        /// The (first) offending value.
        value: f64,
    },
    /// A cuboid's rotation quaternion is zero.
    #[error("the rotation is zero")]
    ZeroRotation,
    /// A profile has fewer than two radii.
    #[error("`radii` must be a list of at least two radii")]
    TooFewRadii,
    /// A bent tube's spine has fewer than three points.
    #[error("`spine` must hold at least three points")]
    TooFewSpinePoints,
    /// A bent tube has not one radius per spine point.
    #[error("`radii` must have one radius per spine point")]
    RadiiPerSpinePoint {
        /// The number of radii.
        radii: usize,
        /// The number of spine points.
        points: usize,
    },
    /// Two consecutive spine points are the same.
    #[error("spine points {index} and {} coincide", .index + 1)]
    CoincidentSpinePoints {
        /// The first of the two.
        index: usize,
    },
}

/// `Ok` when `v` is a unit vector (within [`UNIT_TOLERANCE`]).
fn unit(v: DVec3, field: &'static str) -> Result<(), PrimitiveError> {
    let length = v.length();
    if length == 0.0 {
        Err(PrimitiveError::NoDirection { field })
    } else if (length - 1.0).abs() <= UNIT_TOLERANCE {
        Ok(())
    } else {
        Err(PrimitiveError::NotUnit { field, length })
    }
}

/// `Ok` when `value` is above zero.
fn positive(value: f64, field: &'static str) -> Result<(), PrimitiveError> {
    if value > 0.0 {
        Ok(())
    } else {
        Err(PrimitiveError::NotPositive { field, value })
    }
}

/// `Ok` when every radius is above zero.
fn positive_radii(radii: &[f64]) -> Result<(), PrimitiveError> {
    radii.iter().try_for_each(|r| positive(*r, "radii"))
}

impl Primitive {
    /// Checks the invariants of the primitive's kind: every parameter finite, axes of
    /// unit length (within [`UNIT_TOLERANCE`]), a unit rotation quaternion, positive
    /// lengths, radii and sizes, an SGC profile of at least two radii, and a BGC spine of
    /// at least three distinct consecutive points with one radius each.
    ///
    /// # Errors
    ///
    /// The first [`PrimitiveError`] found, fields in file order.
    pub fn validate(&self) -> Result<(), PrimitiveError> {
        let finite = match self {
            // A BGC's parameters are derived from its spine (and are not finite when
            // spine points coincide): its stored values are checked instead.
            Self::Bgc(b) => {
                b.spine.iter().all(|p| p.is_finite())
                    && b.radii.iter().all(|r| r.is_finite())
                    && b.plane_normal.is_finite()
            }
            _ => self.is_finite(),
        };
        if !finite {
            return Err(PrimitiveError::NotFinite);
        }
        match self {
            Self::Cylinder(c) => {
                unit(c.axis, "axis")?;
                positive(c.length, "length")?;
                positive(c.radius, "radius")
            }
            Self::Cone(c) => {
                unit(c.axis, "axis")?;
                positive(c.length, "length")?;
                positive(c.radius_bottom, "radius_bottom")?;
                positive(c.radius_top, "radius_top")
            }
            Self::Sphere(s) => positive(s.radius, "radius"),
            Self::Cuboid(b) => validate_cuboid(b),
            Self::Sgc(s) => validate_sgc(s),
            Self::Bgc(b) => validate_bgc(b),
        }
    }

    /// The primitive with its axes, rotation and plane normal scaled to unit length where
    /// they have a direction (a BGC's zero plane normal becomes +z); a zero axis or
    /// rotation is left for [`Primitive::validate`] to refuse.
    #[must_use]
    pub fn normalized(&self) -> Self {
        let mut out = self.clone();
        match &mut out {
            Self::Cylinder(c) => c.axis = c.axis.normalize_or(c.axis),
            Self::Cone(c) => c.axis = c.axis.normalize_or(c.axis),
            Self::Sgc(s) => s.axis = s.axis.normalize_or(s.axis),
            Self::Sphere(_) => {}
            Self::Cuboid(b) => {
                let len = b.rotation.length();
                if len > 0.0 && len.is_finite() {
                    b.rotation = b.rotation.normalize();
                }
            }
            Self::Bgc(b) => {
                if b.plane_normal.is_finite() {
                    b.plane_normal = b.plane_normal.try_normalize().unwrap_or(DVec3::Z);
                }
            }
        }
        out
    }
}

fn validate_cuboid(b: &Cuboid) -> Result<(), PrimitiveError> {
    let length = b.rotation.length();
    if length == 0.0 {
        return Err(PrimitiveError::ZeroRotation);
    }
    if (length - 1.0).abs() > UNIT_TOLERANCE {
        return Err(PrimitiveError::NotUnit {
            field: "rotation",
            length,
        });
    }
    b.size
        .to_array()
        .into_iter()
        .try_for_each(|s| positive(s, "size"))
}

fn validate_sgc(s: &Sgc) -> Result<(), PrimitiveError> {
    unit(s.axis, "axis")?;
    positive(s.length, "length")?;
    if s.radii.len() < 2 {
        return Err(PrimitiveError::TooFewRadii);
    }
    positive_radii(&s.radii)
}

fn validate_bgc(b: &Bgc) -> Result<(), PrimitiveError> {
    if b.spine.len() < 3 {
        return Err(PrimitiveError::TooFewSpinePoints);
    }
    if b.radii.len() != b.spine.len() {
        return Err(PrimitiveError::RadiiPerSpinePoint {
            radii: b.radii.len(),
            points: b.spine.len(),
        });
    }
    positive_radii(&b.radii)?;
    unit(b.plane_normal, "plane_normal")?;
    if let Some(index) = b.spine.windows(2).position(|w| w[0] == w[1]) {
        return Err(PrimitiveError::CoincidentSpinePoints { index });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use super::PrimitiveError;
    use crate::primitive::{Bgc, Cone, Cuboid, Cylinder, Primitive, Sgc, Sphere};

    fn cylinder() -> Cylinder {
        Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::Y,
            length: 4.0,
            radius: 1.0,
        }
    }

    fn cone() -> Cone {
        Cone {
            center: DVec3::ZERO,
            axis: DVec3::Y,
            length: 4.0,
            radius_bottom: 2.0,
            radius_top: 1.0,
        }
    }

    fn sphere() -> Sphere {
        Sphere {
            center: DVec3::ZERO,
            radius: 1.0,
        }
    }

    fn cuboid() -> Cuboid {
        Cuboid {
            center: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
            size: DVec3::new(1.0, 2.0, 3.0),
        }
    }

    fn sgc() -> Sgc {
        Sgc {
            center: DVec3::ZERO,
            axis: DVec3::Y,
            length: 4.0,
            radii: vec![1.0, 1.5, 1.0],
        }
    }

    fn bgc() -> Bgc {
        Bgc::through(vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.5, 0.0)], 0.3)
    }

    #[test]
    fn every_kind_is_valid_as_made() {
        for p in [
            Primitive::Cylinder(cylinder()),
            Primitive::Cone(cone()),
            Primitive::Sphere(sphere()),
            Primitive::Cuboid(cuboid()),
            Primitive::Sgc(sgc()),
            Primitive::Bgc(bgc()),
        ] {
            assert_eq!(p.validate(), Ok(()), "{:?}", p.kind());
        }
    }

    #[test]
    fn every_kind_refuses_nan() {
        let nan = f64::NAN;
        let mut b = bgc();
        b.spine[1].y = nan;
        for p in [
            Primitive::Cylinder(Cylinder {
                length: nan,
                ..cylinder()
            }),
            Primitive::Cone(Cone {
                center: DVec3::new(0.0, nan, 0.0),
                ..cone()
            }),
            Primitive::Sphere(Sphere {
                radius: nan,
                ..sphere()
            }),
            Primitive::Cuboid(Cuboid {
                size: DVec3::new(1.0, nan, 1.0),
                ..cuboid()
            }),
            Primitive::Sgc(Sgc {
                radii: vec![1.0, nan],
                ..sgc()
            }),
            Primitive::Bgc(b),
        ] {
            assert_eq!(
                p.validate(),
                Err(PrimitiveError::NotFinite),
                "{:?}",
                p.kind()
            );
        }
    }

    #[test]
    fn axes_and_frames_must_be_unit() {
        let long = DVec3::new(0.0, 2.0, 0.0);
        let not_unit = |field| PrimitiveError::NotUnit { field, length: 2.0 };
        for (p, error) in [
            (
                Primitive::Cylinder(Cylinder {
                    axis: long,
                    ..cylinder()
                }),
                not_unit("axis"),
            ),
            (
                Primitive::Cone(Cone {
                    axis: long,
                    ..cone()
                }),
                not_unit("axis"),
            ),
            (
                Primitive::Sgc(Sgc {
                    axis: long,
                    ..sgc()
                }),
                not_unit("axis"),
            ),
            (
                Primitive::Bgc(Bgc {
                    plane_normal: long,
                    ..bgc()
                }),
                not_unit("plane_normal"),
            ),
            (
                Primitive::Cuboid(Cuboid {
                    rotation: DQuat::from_xyzw(0.0, 0.0, 0.0, 2.0),
                    ..cuboid()
                }),
                not_unit("rotation"),
            ),
            (
                Primitive::Cylinder(Cylinder {
                    axis: DVec3::ZERO,
                    ..cylinder()
                }),
                PrimitiveError::NoDirection { field: "axis" },
            ),
            (
                Primitive::Cuboid(Cuboid {
                    rotation: DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
                    ..cuboid()
                }),
                PrimitiveError::ZeroRotation,
            ),
        ] {
            assert_eq!(p.validate(), Err(error.clone()), "{:?}", p.kind());
            if !matches!(
                error,
                PrimitiveError::NoDirection { .. } | PrimitiveError::ZeroRotation
            ) {
                assert_eq!(p.normalized().validate(), Ok(()), "{:?}", p.kind());
            }
        }
    }

    #[test]
    fn sizes_must_be_positive() {
        let not_positive = |field, value| PrimitiveError::NotPositive { field, value };
        let mut b = bgc();
        b.radii[2] = -1.0;
        for (p, error) in [
            (
                Primitive::Cylinder(Cylinder {
                    radius: 0.0,
                    ..cylinder()
                }),
                not_positive("radius", 0.0),
            ),
            (
                Primitive::Cone(Cone {
                    radius_top: -1.0,
                    ..cone()
                }),
                not_positive("radius_top", -1.0),
            ),
            (
                Primitive::Sphere(Sphere {
                    radius: -2.0,
                    ..sphere()
                }),
                not_positive("radius", -2.0),
            ),
            (
                Primitive::Cuboid(Cuboid {
                    size: DVec3::new(1.0, 0.0, 1.0),
                    ..cuboid()
                }),
                not_positive("size", 0.0),
            ),
            (
                Primitive::Sgc(Sgc {
                    length: 0.0,
                    ..sgc()
                }),
                not_positive("length", 0.0),
            ),
            (Primitive::Bgc(b), not_positive("radii", -1.0)),
        ] {
            assert_eq!(p.validate(), Err(error), "{:?}", p.kind());
        }
        let text = not_positive("radius", -2.0).to_string();
        assert_eq!(text, "`radius` must be positive, got -2", "the message");
    }

    #[test]
    fn profiles_and_spines_need_enough_distinct_samples() {
        let short = Primitive::Sgc(Sgc {
            radii: vec![1.0],
            ..sgc()
        });
        assert_eq!(
            short.validate(),
            Err(PrimitiveError::TooFewRadii),
            "one radius"
        );
        let mut b = bgc();
        b.spine.pop();
        b.radii.pop();
        assert_eq!(
            Primitive::Bgc(b).validate(),
            Err(PrimitiveError::TooFewSpinePoints),
            "two points"
        );
        let mut b = bgc();
        b.radii.pop();
        assert_eq!(
            Primitive::Bgc(b).validate(),
            Err(PrimitiveError::RadiiPerSpinePoint {
                radii: 2,
                points: 3
            }),
            "a radius missing"
        );
        let mut b = bgc();
        b.spine[2] = b.spine[1];
        let error = Primitive::Bgc(b).validate().unwrap_err();
        assert_eq!(
            error,
            PrimitiveError::CoincidentSpinePoints { index: 1 },
            "a twin point"
        );
        assert_eq!(
            error.to_string(),
            "spine points 1 and 2 coincide",
            "the message"
        );
    }
}
