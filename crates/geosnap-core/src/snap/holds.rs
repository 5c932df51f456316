//! A reading that holds a placed part: the new part's outline encloses a part placed
//! before it and runs along that part's edges.
//!
//! Parts that touch share a few edges: a drawer's top edge is the one above's bottom
//! edge, a stacked cylinder's end ellipse is its neighbour's. A snap that reads several
//! parts as one (a chest of drawers read whole when one drawer was meant, a stack of equal
//! cylinders read as one tall cylinder) does more: the placed part lies entirely inside
//! its outline, and the reading's outline runs along the placed part's on opposite sides
//! of it (a middle drawer's two ends, a top drawer's top and ends): the placed part spans
//! the reading from one side of its outline to the other. And in 3D the placed part lies
//! inside the reading's solid at some depth ([`contains_at_some_depth`]; the drawing
//! leaves the new part's depth open): the image alone is fooled where a neighbour's image
//! encloses the placed part's (books seen nearly along their row, each image over the one
//! before it), though no depth puts the placed book inside its neighbour. No designer
//! models a part as a piece of another one they modelled before, so such a reading reads
//! the drawing against the model: a snap gives it up for a reading that holds no placed
//! part (`snap::better`), and when every reading holds one the snap is doubted, with the
//! reason naming the part it holds.
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

use glam::{DVec2, DVec3};

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
    let (Some(reading_box), Some(placed_box)) = (image_box(reading), image_box(placed)) else {
        return false;
    };
    may_hold(reading_box, placed_box, band) && holds_within(reading, placed, band)
}

/// The cheap test of [`holds`], on the images' boxes (lower and upper corners): the
/// placed part's image inside the reading's box but for a twentieth of its size (a
/// placed part need not lie exactly where the reading's hand drew it).
pub(crate) fn may_hold(reading: (DVec2, DVec2), placed: (DVec2, DVec2), band: f64) -> bool {
    let ((rlo, rhi), (plo, phi)) = (reading, placed);
    let margin = band.max(BOX_MARGIN * (rhi - rlo).length());
    plo.cmpge(rlo - margin).all() && phi.cmple(rhi + margin).all()
}

/// [`holds`] once [`may_hold`] has passed.
pub(crate) fn holds_within(reading: &Primitive, placed: &Primitive, band: f64) -> bool {
    let held = lies_in(reading, placed, band)
        .is_some_and(|(inside, along, span)| inside >= INSIDE && along >= ALONG && span >= SPAN);
    held && outline_distance(reading, placed) > DISTINCT
        && piece_at_some_depth(reading, placed, DEPTH_TOLERANCE * band)
}

/// A placed part is a piece of a reading only when it fits inside the reading's solid
/// within this many times the reading's band of the hand's noise.
const DEPTH_TOLERANCE: f64 = 2.0;

/// Whether `placed` lies inside the solid of `reading` or of its mirror image in depth
/// (which draws the same picture), within `tolerance`, at some depth (see
/// [`contains_at_some_depth`]); a bent tube, whose solid is not measured, is held as its
/// image says.
fn piece_at_some_depth(reading: &Primitive, placed: &Primitive, tolerance: f64) -> bool {
    [reading.clone(), reading.mirrored_in_depth()]
        .iter()
        .map(|r| contains_at_some_depth(r, placed, tolerance))
        .try_fold(false, |any, c| c.map(|c| any || c))
        .unwrap_or(true)
}

/// Whether `placed` lies inside the solid of `reading`, within `tolerance` (view units),
/// once `reading` is moved to some depth: a drawing in parallel projection leaves a new
/// part's depth open, so the part is tried along the line of sight. A reading that reads
/// a placed part and its neighbour as one holds it whole at the right depth; a neighbour
/// whose image merely encloses the placed part's (a book seen along the row, its image
/// over the one before it) holds it at none. `None` for a reading whose solid is not
/// measured here (a bent tube).
pub(crate) fn contains_at_some_depth(
    reading: &Primitive,
    placed: &Primitive,
    tolerance: f64,
) -> Option<bool> {
    let inside = solid(reading, tolerance)?;
    let points = placed.mesh(DEPTH_SEGMENTS).positions;
    let own = reading.mesh(DEPTH_SEGMENTS).positions;
    let z_range = |points: &[DVec3]| {
        points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.z), hi.max(p.z))
            })
    };
    let ((plo, phi), (rlo, rhi)) = (z_range(&points), z_range(&own));
    if !(plo <= phi && rlo <= rhi) {
        return Some(false);
    }
    // Moved by `dz`, the reading spans [rlo + dz, rhi + dz], which must hold [plo, phi].
    let (from, to) = (phi - rhi, plo - rlo);
    if from > to + 2.0 * tolerance {
        return Some(false);
    }
    let steps = (((to - from) / tolerance.max(f64::MIN_POSITIVE)).ceil() as usize).clamp(1, 256);
    Some((0..=steps).any(|k| {
        let dz = from + (to - from) * k as f64 / steps as f64;
        points.iter().all(|p| inside(*p - DVec3::Z * dz))
    }))
}

/// Segments of the meshes [`contains_at_some_depth`] measures.
const DEPTH_SEGMENTS: usize = 12;

/// The test of a solid of revolution about `axis` through `center`, of `length`, whose
/// radius at a fraction `f` of the way from the bottom is `radius(f)`, grown by `t`.
fn revolved<'a>(
    center: DVec3,
    axis: DVec3,
    length: f64,
    t: f64,
    radius: impl Fn(f64) -> f64 + 'a,
) -> Box<dyn Fn(DVec3) -> bool + 'a> {
    Box::new(move |p: DVec3| {
        let d = p - center;
        let h = d.dot(axis);
        let f = ((h + length / 2.0) / length.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        h.abs() <= length / 2.0 + t && (d - axis * h).length() <= radius(f) + t
    })
}

/// The test whether a point lies inside `primitive`'s solid grown by `tolerance`; `None`
/// for a bent tube.
fn solid(primitive: &Primitive, tolerance: f64) -> Option<Box<dyn Fn(DVec3) -> bool + '_>> {
    let t = tolerance;
    Some(match primitive {
        Primitive::Sphere(s) => {
            let (c, r) = (s.center, s.radius);
            Box::new(move |p: DVec3| p.distance(c) <= r + t)
        }
        Primitive::Cuboid(b) => {
            let (c, turn, half) = (b.center, b.rotation.inverse(), b.size / 2.0 + t);
            Box::new(move |p: DVec3| (turn * (p - c)).abs().cmple(half).all())
        }
        Primitive::Cylinder(c) => revolved(c.center, c.axis, c.length, t, move |_| c.radius),
        Primitive::Cone(c) => revolved(c.center, c.axis, c.length, t, move |f| {
            c.radius_bottom + (c.radius_top - c.radius_bottom) * f
        }),
        Primitive::Sgc(s) => revolved(s.center, s.axis, s.length, t, move |f| {
            let n = s.radii.len();
            if n == 0 {
                return 0.0;
            }
            let x = f * (n - 1) as f64;
            let i = (x.floor() as usize).min(n.saturating_sub(2));
            let j = (i + 1).min(n - 1);
            s.radii[i] + (s.radii[j] - s.radii[i]) * (x - i as f64)
        }),
        Primitive::Bgc(_) => return None,
    })
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
pub(crate) fn image_box(primitive: &Primitive) -> Option<(DVec2, DVec2)> {
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

    #[test]
    fn a_chest_read_whole_holds_its_drawers_at_any_depth_and_in_its_mirror_image() {
        let (whole, drawers) = chest();
        // The drawing leaves the reading's depth open, and its mirror image in depth
        // draws the same picture.
        for reading in [
            whole.transformed(DVec3::Z * 400.0, 1.0),
            whole.mirrored_in_depth(),
        ] {
            for (i, drawer) in drawers.iter().enumerate() {
                assert!(holds(&reading, drawer, 1.5), "drawer {i}");
            }
        }
    }

    /// A rod running into depth behind a thin panel: the panel's image encloses the rod's
    /// and runs along its outlines on both sides, yet the rod is deeper than the panel and
    /// no depth puts it inside: it is no piece of the panel.
    #[test]
    fn a_rod_deeper_than_a_panel_whose_image_encloses_it_is_no_piece_of_it() {
        let axis = DVec3::new(0.0, 0.5, 0.75f64.sqrt());
        let rod = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis,
            length: 100.0,
            radius: 10.0,
        });
        // The rod's image: 20 wide, 50 + 20 long along y (its ends' ellipses).
        let panel = Primitive::Cuboid(Cuboid {
            center: DVec3::new(0.0, 0.0, 200.0),
            rotation: DQuat::IDENTITY,
            size: DVec3::new(20.0, 72.0, 5.0),
        });
        let (inside, along, span) = lies_in(&panel, &rod, 1.5).expect("the rod shows");
        assert!(
            inside >= INSIDE && along >= ALONG && span >= SPAN,
            "the image alone holds it: {inside} {along} {span}"
        );
        assert_eq!(contains_at_some_depth(&panel, &rod, 3.0), Some(false));
        assert!(!holds(&panel, &rod, 1.5));
        // A panel as deep as the rod holds it.
        let deep = Primitive::Cuboid(Cuboid {
            center: DVec3::new(0.0, 0.0, 200.0),
            rotation: DQuat::IDENTITY,
            size: DVec3::new(20.0, 72.0, 100.0),
        });
        assert!(holds(&deep, &rod, 1.5));
    }
}
