//! A reading that holds a placed part: the new part's outline encloses a part placed
//! before it and runs along that part's edges.
//!
//! Parts that touch share a few edges: a drawer's top edge is the one above's bottom
//! edge, a stacked cylinder's end ellipse is its neighbour's. A snap that reads several
//! parts as one (a chest of drawers read whole when one drawer was meant, a stack of equal
//! cylinders read as one tall cylinder) does more: the placed part lies entirely inside
//! its outline, and the reading's outline runs along the placed part's on opposite sides
//! of it (a middle drawer's two ends, a top drawer's top and ends): the placed part spans
//! the reading from one side of its outline to the other. No designer models a part as a
//! piece of another one they modelled before, so such a snap reads the drawing against
//! the model: it is doubted, and the reason names the part it holds.
//!
//! What it does not catch, by design:
//! - a part drawn on the face of another (a knob on a drawer, a label on a box): it lies
//!   inside the bigger part's outline but shares none of its edges, or, set at an edge,
//!   shares them on one side only;
//! - a part dropped on a placed one again (a double): the ownership evidence names it;
//! - a sleeve round a rod: the rod lies inside but its outline runs inside the sleeve's,
//!   not along it.
//!
//! The measures are over the placed part's visible curves, sampled every half band; a
//! sample is *along* the reading when it lies within the band of one of the reading's
//! visible curves, and *inside* when it is along or inside the reading's projected
//! outline (the union of its mesh triangles). The *span* of the samples along is the
//! diagonal of their bounding box over that of all the samples.

use glam::DVec2;

use super::assign::curve_distance;
use super::confidence::{outline_distance, DISTINCT};
use super::swallowed::Outline;
use crate::primitive::{Curve2, Primitive};

/// A placed part lies in a reading when at least this much of its visible outline lies
/// along or inside the reading's: all of it, but for the hand's noise at its ends.
pub(crate) const INSIDE: f64 = 0.9;
/// A placed part runs along a reading's outline when at least this much of its own
/// outline lies along it: more than the few samples where an outline crosses the
/// reading's (a rod's outlines across a sleeve's end ellipses).
pub(crate) const ALONG: f64 = 0.1;
/// A placed part spans a reading when the samples of its outline along the reading's
/// reach across at least this much of its image (module docs): from one end to the
/// other but for its corners, where a part set at the reading's edge shares one side.
pub(crate) const SPAN: f64 = 0.6;

/// How far a placed part's image may reach out of the box round the reading's, as a
/// share of that box's diagonal, before [`lies_in`] is worth measuring.
const BOX_MARGIN: f64 = 0.05;

/// How `placed` lies in `reading`: the fractions of its visible outline inside and along
/// the reading's and the span of its samples along it (module docs), with `band` the
/// hand's noise about a curve (view units). `None` when `placed` shows no visible curve.
pub(crate) fn lies_in(
    reading: &Primitive,
    placed: &Primitive,
    band: f64,
) -> Option<(f64, f64, f64)> {
    let band = band.max(f64::MIN_POSITIVE);
    let samples = visible_samples(placed, band / 2.0);
    if samples.is_empty() {
        return None;
    }
    let shape = reading.current_shape();
    let curves: Vec<&Curve2<f64>> = shape
        .curves
        .iter()
        .filter(|c| c.visible)
        .map(|c| &c.curve)
        .collect();
    let outline = Outline::of(reading);
    let mut inside = 0usize;
    let mut along: Vec<DVec2> = Vec::new();
    for p in &samples {
        let near = curves.iter().any(|c| curve_distance(c, *p) <= band);
        if near {
            along.push(*p);
        }
        inside += usize::from(near || outline.contains(*p));
    }
    let span = diagonal(&along) / diagonal(&samples).max(f64::MIN_POSITIVE);
    let n = samples.len() as f64;
    Some((inside as f64 / n, along.len() as f64 / n, span))
}

/// The diagonal of the bounding box of `points` (0 for none).
fn diagonal(points: &[DVec2]) -> f64 {
    let Some(first) = points.first() else {
        return 0.0;
    };
    let (lo, hi) = points
        .iter()
        .fold((*first, *first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    (hi - lo).length()
}

/// Whether `reading` holds `placed` (module docs), with `band` the hand's noise about a
/// curve. A reading whose outline lies within [`DISTINCT`] of the placed part's is that
/// part again, which the ownership evidence judges.
pub(crate) fn holds(reading: &Primitive, placed: &Primitive, band: f64) -> bool {
    let (Some((rlo, rhi)), Some((plo, phi))) = (image_box(reading), image_box(placed)) else {
        return false;
    };
    // The cheap test first: the placed part's image inside the reading's box but for a
    // twentieth of its size (a placed part need not lie exactly where the reading's
    // hand drew it).
    let margin = band.max(BOX_MARGIN * (rhi - rlo).length());
    if !(plo.cmpge(rlo - margin).all() && phi.cmple(rhi + margin).all()) {
        return false;
    }
    let held = lies_in(reading, placed, band)
        .is_some_and(|(inside, along, span)| inside >= INSIDE && along >= ALONG && span >= SPAN);
    held && outline_distance(reading, placed) > DISTINCT
}

/// The samples of `primitive`'s visible curves, about `step` apart.
fn visible_samples(primitive: &Primitive, step: f64) -> Vec<DVec2> {
    primitive
        .current_shape()
        .curves
        .iter()
        .filter(|c| c.visible)
        .flat_map(|c| curve_samples(&c.curve, step))
        .filter(|p| p.is_finite())
        .collect()
}

/// The samples of `curve`, about `step` apart, each point once (an ellipse's point list
/// closes on itself).
pub(crate) fn curve_samples(curve: &Curve2<f64>, step: f64) -> Vec<DVec2> {
    let points = curve.points(64);
    let points = match curve {
        Curve2::Ellipse { .. } => &points[..points.len().saturating_sub(1)],
        Curve2::Polyline(_) => &points[..],
    };
    super::resampled(points, step)
}

/// The box round `primitive`'s projected curves (`None` when it has none finite).
fn image_box(primitive: &Primitive) -> Option<(DVec2, DVec2)> {
    let shape = primitive.current_shape();
    let mut points = shape
        .curves
        .iter()
        .flat_map(|c| c.curve.points(24))
        .filter(|p| p.is_finite());
    let first = points.next()?;
    Some(points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitive::{Cuboid, Cylinder};
    use glam::{DQuat, DVec3};

    /// A box of `size` at `center`, turned so that three faces face the viewer.
    fn cuboid(center: DVec3, size: DVec3) -> Primitive {
        let turn = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.6);
        Primitive::Cuboid(Cuboid {
            center,
            rotation: turn,
            size,
        })
    }

    /// Three drawers in a chest, 90 wide, 30 high and 60 deep each, the chest's `up`
    /// axis along the boxes' second.
    fn chest() -> (Primitive, [Primitive; 3]) {
        let turn = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.6);
        let up = turn * DVec3::Y;
        let size = DVec3::new(90.0, 30.0, 60.0);
        let drawer = |i: f64| cuboid(up * 30.0 * i, size);
        (
            cuboid(DVec3::ZERO, DVec3::new(90.0, 90.0, 60.0)),
            [drawer(1.0), drawer(0.0), drawer(-1.0)],
        )
    }

    #[test]
    fn a_chest_read_whole_holds_each_of_its_drawers() {
        let (whole, drawers) = chest();
        for (i, drawer) in drawers.iter().enumerate() {
            assert!(
                holds(&whole, drawer, 1.5),
                "drawer {i}: {:?}",
                lies_in(&whole, drawer, 1.5)
            );
        }
    }

    #[test]
    fn a_drawer_does_not_hold_its_neighbour_nor_itself() {
        let (_, [top, middle, bottom]) = chest();
        assert!(!holds(&middle, &top, 1.5));
        assert!(!holds(&middle, &bottom, 1.5));
        assert!(!holds(&middle, &middle, 1.5));
    }

    #[test]
    fn a_knob_on_a_drawers_face_is_inside_it_but_not_held() {
        let (_, [top, ..]) = chest();
        let Primitive::Cuboid(b) = &top else {
            unreachable!()
        };
        let [x, _, z] = b.axes();
        // A knob standing out of the middle of the face that faces the viewer.
        let front = if z.z > 0.0 { z } else { -z };
        let knob = Primitive::Cylinder(Cylinder {
            center: b.center + front * 34.0 + x * 5.0,
            axis: front,
            length: 8.0,
            radius: 5.0,
        });
        let (inside, along, span) = lies_in(&top, &knob, 1.5).expect("the knob shows");
        assert!(inside >= INSIDE, "inside {inside}");
        assert!(along < ALONG || span < SPAN, "along {along}, span {span}");
        assert!(!holds(&top, &knob, 1.5));
    }

    #[test]
    fn a_stack_of_equal_cylinders_read_as_one_holds_the_lower_but_a_sleeve_holds_no_rod() {
        let axis = DVec3::new(0.0, 1.0, 0.4).normalize();
        let cylinder = |at: f64, length: f64, radius: f64| {
            Primitive::Cylinder(Cylinder {
                center: axis * at,
                axis,
                length,
                radius,
            })
        };
        let lower = cylinder(-20.0, 40.0, 20.0);
        let stack = cylinder(0.0, 80.0, 20.0);
        assert!(
            holds(&stack, &lower, 1.5),
            "{:?}",
            lies_in(&stack, &lower, 1.5)
        );
        let rod = cylinder(0.0, 60.0, 6.0);
        let sleeve = cylinder(0.0, 60.0, 20.0);
        assert!(
            !holds(&sleeve, &rod, 1.5),
            "{:?}",
            lies_in(&sleeve, &rod, 1.5)
        );
    }
}
