//! Typing a part's position and orientation in the properties panel.
//!
//! Position is the part's centre (model space, in the document's unit). Orientation is
//! what the kind has: the axis of a cylinder, cone or profile as its tilt from straight
//! up (+Y) and its heading about +Y (0° towards the viewer, +Z; 90° to the right, +X);
//! a box's turns about Y, then X, then Z. A sphere has none; a bent tube is moved and
//! turned as a whole only through its position here.
//!
//! A part typed into place is placed there exactly: it leaves its strokes (it is then
//! "placed freely", as an Alt + drop places it), keeps its relations and dimensions, and
//! the model is solved so that its relations hold again.

use glam::{DQuat, DVec3, EulerRot};

use crate::core::model::{Document, Fit, Placed, PrimitiveId};
use crate::core::primitive::Primitive;

/// The angles a part's orientation is typed as, in degrees, with their names.
pub(crate) fn angles(primitive: &Primitive) -> Vec<(&'static str, f64)> {
    match primitive {
        Primitive::Cylinder(c) => axis_angles(c.axis),
        Primitive::Cone(c) => axis_angles(c.axis),
        Primitive::Sgc(s) => axis_angles(s.axis),
        Primitive::Cuboid(b) => {
            let (y, x, z) = b.rotation.to_euler(EulerRot::YXZ);
            vec![
                ("turn about Y", y.to_degrees()),
                ("turn about X", x.to_degrees()),
                ("turn about Z", z.to_degrees()),
            ]
        }
        Primitive::Sphere(_) | Primitive::Bgc(_) => Vec::new(),
    }
}

fn axis_angles(axis: DVec3) -> Vec<(&'static str, f64)> {
    let axis = axis.normalize_or(DVec3::Y);
    vec![
        ("tilt from up", axis.y.clamp(-1.0, 1.0).acos().to_degrees()),
        ("heading", axis.x.atan2(axis.z).to_degrees()),
    ]
}

/// `primitive` with its orientation angles (as [`angles`] lists them, degrees) set to
/// `degrees`; `None` when the kind has no such angles or a value is not finite.
pub(crate) fn with_angles(primitive: &Primitive, degrees: &[f64]) -> Option<Primitive> {
    if degrees.iter().any(|d| !d.is_finite()) {
        return None;
    }
    let axis = || {
        let (tilt, heading) = (degrees.first()?.to_radians(), degrees.get(1)?.to_radians());
        Some(DVec3::new(
            tilt.sin() * heading.sin(),
            tilt.cos(),
            tilt.sin() * heading.cos(),
        ))
    };
    Some(match primitive.clone() {
        Primitive::Cylinder(mut c) => {
            c.axis = axis()?;
            Primitive::Cylinder(c)
        }
        Primitive::Cone(mut c) => {
            c.axis = axis()?;
            Primitive::Cone(c)
        }
        Primitive::Sgc(mut s) => {
            s.axis = axis()?;
            Primitive::Sgc(s)
        }
        Primitive::Cuboid(mut b) => {
            let [y, x, z] =
                [degrees.first()?, degrees.get(1)?, degrees.get(2)?].map(|d| d.to_radians());
            b.rotation = DQuat::from_euler(EulerRot::YXZ, y, x, z).normalize();
            Primitive::Cuboid(b)
        }
        Primitive::Sphere(_) | Primitive::Bgc(_) => return None,
    })
}

/// `primitive` moved so that its centre is at `center`.
pub(crate) fn with_center(primitive: &Primitive, center: DVec3) -> Primitive {
    primitive.transformed(center - primitive.center(), 1.0)
}

/// The model with part `id` placed as `primitive`, exactly and unsnapped, its relations
/// and dimensions kept (not yet solved); `None` when there is no such part.
pub(crate) fn placed_exactly(
    document: &Document,
    id: PrimitiveId,
    primitive: Primitive,
) -> Option<Document> {
    document.get(id)?;
    let mut changed = document.clone();
    let relations: Vec<_> = changed
        .relations()
        .iter()
        .filter(|r| r.members.contains(&id))
        .cloned()
        .collect();
    let dimensions: Vec<_> = changed.dimensions_of(id).copied().collect();
    // Removing forgets its snap (its strokes would pull it back) with its relations and
    // dimensions, which are then put back on the part as typed.
    changed.remove(id);
    changed.insert(
        id,
        Placed {
            primitive,
            fit: Fit::default(),
        },
    );
    for relation in relations {
        // Each was valid on this part before, and the part keeps its kind.
        let _ = changed.add_relation(relation);
    }
    for d in dimensions {
        let _ = changed.set_dimension(id, d.quantity, d.value);
    }
    Some(changed)
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use super::{angles, placed_exactly, with_angles, with_center};
    use crate::core::model::{Document, Fit, Placed};
    use crate::core::primitive::{Cuboid, Cylinder, Primitive};

    #[test]
    fn typed_angles_read_back_as_typed() {
        let can = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::Y,
            length: 10.0,
            radius: 2.0,
        });
        let turned = with_angles(&can, &[30.0, 90.0]).expect("a cylinder has an axis");
        let read: Vec<f64> = angles(&turned).into_iter().map(|(_, a)| a).collect();
        assert!(
            (read[0] - 30.0).abs() < 1e-9 && (read[1] - 90.0).abs() < 1e-9,
            "{read:?}"
        );
        let Primitive::Cylinder(c) = &turned else {
            panic!("a cylinder");
        };
        assert!(
            c.axis.x > 0.0 && (c.axis.length() - 1.0).abs() < 1e-12,
            "tilted to +X"
        );

        let block = Primitive::Cuboid(Cuboid {
            center: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
            size: DVec3::ONE,
        });
        let turned = with_angles(&block, &[20.0, -10.0, 5.0]).expect("a box turns");
        let read: Vec<f64> = angles(&turned).into_iter().map(|(_, a)| a).collect();
        for (r, want) in read.iter().zip([20.0, -10.0, 5.0]) {
            assert!((r - want).abs() < 1e-9, "{read:?}");
        }
        assert!(with_angles(&block, &[f64::NAN, 0.0, 0.0]).is_none());
    }

    #[test]
    fn a_part_typed_into_place_keeps_its_id_and_leaves_its_strokes() {
        let mut document = Document::new();
        let ball = |x: f64| Placed {
            primitive: Primitive::Sphere(crate::core::primitive::Sphere {
                center: DVec3::new(x, 0.0, 0.0),
                radius: 1.0,
            }),
            fit: Fit {
                strokes: vec![crate::core::sketch::StrokeId(3)],
                ..Fit::default()
            },
        };
        let id = document.add(ball(0.0));
        let moved = with_center(&document.get(id).expect("placed").primitive, DVec3::X * 5.0);
        let changed = placed_exactly(&document, id, moved).expect("the part exists");
        let placed = changed.get(id).expect("the same id");
        assert!((placed.primitive.center() - DVec3::X * 5.0).length() < 1e-12);
        assert!(placed.fit.strokes.is_empty(), "placed freely");
    }
}
