//! Drops that say where and what, not how big or which way.
//!
//! A primitive dragged off the palette and let go over a drawing, or a script step that
//! gives nothing but a kind and a point, tells the snap which part is meant by where it
//! lands, and nothing of the part's size or direction. The snap itself is built for a
//! drop a hand has sized and turned roughly (within a quarter and some degrees): its
//! gates and the starts it reads off the drawing are measured from the drop. A point
//! drop sized by some default meets a part a tenth or ten times as big, and a rod lying
//! across the page under an upright drop; measured on the generated drawings, fewer than
//! one point drop in six landed on its part.
//!
//! So the drawing sizes and turns the drop. The guesses are the drop at a ladder of
//! sizes, from the drawing's extent down by halves ([`RUNGS`]; a size whose reach holds
//! no stroke is left out), each turned along the two principal directions of the
//! strokes within its reach (a rod's outlines spread along its axis, a disc's ellipses
//! across it) unless the drop gives its direction. A cylinder or cone is also guessed
//! as a disc ([`DISC_LENGTH`] of its diameter long) along the direction across the
//! spread: a rod-shaped guess on a thin disc reads one of its ellipses as an outline. Each guess is snapped as a hand's drop
//! is, and the readings compete as the starts of one drop do (see `better`): a good fit
//! first, then what explains more of the drawing, then what swallows less. A point drop
//! says where the part's middle is, so readings centred near the point
//! ([`CENTRE_REACH`]) are chosen among first: a post read from a drop on the cap that
//! stands on it explains more of the drawing, but is not what was pointed at. The
//! winning guess stands for the drop in the snap's confidence.
//!
//! The ladder's guesses have the palette's proportions (a rod a third as wide as it is
//! long). On a table leg ten times as long as it is wide, a guess as long as the leg
//! reads its neighbours' outlines, and one as wide as the leg is far too short; on a
//! plug's prong, a plank, the same. So the drawing is also read where the point lies:
//! the region its strokes enclose round the point ([`super::region`]) has the part's
//! proportions, and gives guesses of its own, first: a round part along the region (a
//! rod) and across it (a disc), a box as a bar along it and as a slab across it, a ball
//! as wide as it. They compete with the ladder's readings as any guess does. Measured on
//! the conditions suite's point drops (10 single cases per kind and condition, 2
//! assemblies per kind and condition), the region's guesses took assembly parts from
//! 67.7 to 73.2 % (tables 48.5 → 63.9, plugs 50.0 → 58.6, valve rows
//! 60.0 → 70.0) and left single parts where they were (83.8 → 83.5 %).
//!
//! The readings are weighed at one scale, the smallest reading's. A reading is scored by
//! the strokes within a gate of its curves, and the gate grows with the size it is
//! weighed at (a hand's drop is weighed at the smaller of its own size and the
//! reading's). Each guess's reading was weighed at the smaller of its guess's size and
//! its own, so a large reading counted strokes in a wider band than a small one: a
//! cylinder spanning two of a brick's studs, its ends on their ellipses and its sides on
//! the brick's edge, explained more than the stud pointed at. At the smallest reading's
//! scale every reading is held to the same band. On the point drops
//! (10 single cases, 2 assemblies per kind and condition) assembly parts went
//! 73.2 → 77.6 % (bricks with studs 72.8 → 89.3, plugs 58.6 → 68.6, stacks
//! 84.6 → 90.4), single parts 83.5 → 83.2 %, and the good assembly parts that call
//! themselves doubtful 10.4 → 4.7 %: the rivals that had explained more only in their
//! wider band no longer stand as other readings as good.
//!
//! What the region did not give: a reading of a row of legs as one fat post still
//! explains more of the drawing than the leg pointed at, and wins. Asking the reading
//! to draw the strokes round the point (the region's boundary) turned that away, and
//! turned away as many right readings where another part's outline crosses the region
//! (a rim behind the cone that stands on it, a stack seen along its axis): it was
//! measured and left out.

use glam::DVec2;

use super::region::region_at;
use super::{choose, snap_from, Scored, SnapContext, SnapError, SnapResult, SnapSettings};
use crate::geom::projection::{sketch_from_view, view_from_sketch};
use crate::primitive::{Placement, Primitive, PrimitiveKind};
use crate::solve::SolveContext;

/// How many sizes the ladder tries: the drawing's extent and its halves down to 1/32.
pub const RUNGS: i32 = 6;

/// A guess reads the strokes within this share of its size of the drop point: the
/// strokes of a part of that size centred there.
const REACH: f64 = 0.6;

/// A reading is centred on the drop when its image centre lies within this share of
/// its size of the point: two and a half times the 10 % by which a hand's drop misses a
/// part's middle.
pub const CENTRE_REACH: f64 = 0.25;

/// A disc's guess is this share of its diameter long (projected).
pub const DISC_LENGTH: f64 = 0.25;

/// Two directions closer than this (radians, 10°, either way along) are one guess.
const SAME_DIRECTION: f64 = 0.175;

/// A snap of a point drop: the snapped reading and the guess (the drop sized and
/// turned by the drawing) it came from, which stands for the drop in its confidence.
#[derive(Clone, Debug, PartialEq)]
pub struct PointSnap {
    /// The snap.
    pub result: SnapResult,
    /// The guess it came from.
    pub guess: Primitive,
}

/// The guesses a drop of `kind` at `at` is snapped from (module docs): first those of
/// the region the strokes enclose round the point, when they enclose it; then the drop
/// at each rung of sizes whose reach holds strokes, largest first, along `axis` when
/// given, else along the principal directions of the strokes within reach (and up the
/// page when they are too few to say).
pub fn guesses(
    context: &SnapContext,
    kind: PrimitiveKind,
    at: DVec2,
    axis: Option<DVec2>,
) -> Vec<Primitive> {
    let Some(extent) = extent(context) else {
        return Vec::new();
    };
    // The strokes are held in view space (y up).
    let point = view_from_sketch(at);
    let mut out = region_guesses(context, kind, point, axis, extent);
    for k in 0..RUNGS {
        let size = extent * 0.5f64.powi(k);
        let near: Vec<DVec2> = context
            .strokes
            .iter()
            .filter(|s| box_distance(s.bounds, point) <= REACH * size)
            .flat_map(|s| s.points.iter().copied())
            .filter(|p| p.distance(point) <= REACH * size)
            .collect();
        if near.is_empty() {
            continue;
        }
        let directions = match (axis, kind) {
            (Some(a), _) => vec![a],
            // A sphere looks the same whichever way it is turned.
            (None, PrimitiveKind::Sphere) => vec![DVec2::new(0.0, -1.0)],
            (None, _) => principal_directions(&near)
                .into_iter()
                .map(sketch_from_view)
                .collect(),
        };
        for direction in &directions {
            let placement = Placement {
                axis: *direction,
                ..Placement::at(at)
            };
            out.push(Primitive::from_placement(kind, &placement, size));
        }
        // A round part may be a disc as well as a rod: a disc's guess along the direction
        // across the strokes' spread (a disc's ellipses spread across its axis).
        if matches!(kind, PrimitiveKind::Cylinder | PrimitiveKind::Cone)
            && let Some(direction) = directions.last()
        {
            let placement = Placement {
                axis: *direction,
                length: Some(DISC_LENGTH * size),
                radius: Some(0.5 * size),
                radius_bottom: Some(0.5 * size),
                radius_top: Some(0.3 * size),
                ..Placement::at(at)
            };
            out.push(Primitive::from_placement(kind, &placement, size));
        }
    }
    out
}

/// The guesses the region around the drop (see [`super::region`]) gives a drop of
/// `kind` at view point `point`: the part in the region's proportions, a round part
/// along the region (a rod) and across it (a disc seen edge-on, or a disc's top ellipse
/// seen from above) unless the drop gives its axis. None where the point is not
/// enclosed by strokes.
fn region_guesses(
    context: &SnapContext,
    kind: PrimitiveKind,
    point: DVec2,
    axis: Option<DVec2>,
    extent: f64,
) -> Vec<Primitive> {
    let Some(region) = region_at(context, point, extent) else {
        return Vec::new();
    };
    let (a, b) = (region.half_major, region.half_minor);
    if !(a > 0.0 && b > 0.0) {
        return Vec::new();
    }
    let at = sketch_from_view(region.centre);
    // Each guess: its image axis (view space), its projected length and its radius.
    let mut shapes = vec![(region.major, 2.0 * a, b), (region.minor(), 2.0 * b, a)];
    if let Some(given) = axis {
        let given = view_from_sketch(given).normalize_or(DVec2::Y);
        let along = given.dot(region.major).abs();
        let across = given.dot(region.minor()).abs();
        shapes = vec![(
            given,
            2.0 * (a * along + b * across),
            a * across + b * along,
        )];
    }
    let placement = |direction: DVec2, length: f64, radius: f64| Placement {
        axis: sketch_from_view(direction),
        length: Some(length),
        radius: Some(radius),
        radius_bottom: Some(radius),
        radius_top: Some(0.5 * radius),
        ..Placement::at(at)
    };
    match kind {
        PrimitiveKind::Sphere => {
            let placement = Placement {
                radius: Some(a),
                ..Placement::at(at)
            };
            vec![Primitive::from_placement(kind, &placement, 2.0 * a)]
        }
        // A bar along the region (a prong, a plank: its up along the region) and a slab
        // across it (a table top whose top face the drop lands on: its up across).
        PrimitiveKind::Cuboid => [
            (region.major, [2.0 * b, 2.0 * a, 2.0 * b]),
            (region.minor(), [2.0 * a, b, 2.0 * a]),
        ]
        .into_iter()
        .take(if axis.is_some() { 1 } else { 2 })
        .map(|(up, size)| {
            let up = axis.map_or(up, |g| view_from_sketch(g).normalize_or(DVec2::Y));
            let placement = Placement {
                axis: sketch_from_view(up),
                size: Some(size),
                ..Placement::at(at)
            };
            Primitive::from_placement(kind, &placement, 2.0 * a)
        })
        .collect(),
        PrimitiveKind::Sgc | PrimitiveKind::Bgc => shapes
            .into_iter()
            .take(1)
            .map(|(d, l, r)| Primitive::from_placement(kind, &placement(d, l, r), l.max(2.0 * r)))
            .collect(),
        PrimitiveKind::Cylinder | PrimitiveKind::Cone => shapes
            .into_iter()
            .map(|(d, l, r)| Primitive::from_placement(kind, &placement(d, l, r), l.max(2.0 * r)))
            .collect(),
    }
}

/// Snaps a drop of `kind` at sketch point `at` that gives no size (and no direction when
/// `axis` is `None`) to the strokes of `context`: every guess of [`guesses`] is snapped
/// and the best reading kept, the others its alternatives.
///
/// # Errors
///
/// [`SnapError::NotEnoughStrokes`] when no stroke lies near `at` or no guess snaps (the
/// largest guess's error), [`SnapError::NonFinite`] for a non-finite point or axis,
/// [`SnapError::Cancelled`].
///
/// # Examples
///
/// ```
/// use glam::DVec2;
/// use geosnap_core::primitive::{Primitive, PrimitiveKind};
/// use geosnap_core::sketch::{StrokeClass, StrokeId};
/// use geosnap_core::snap::{snap_at, SnapContext, SnapSettings};
///
/// // A cylinder lying across the page: two lines 20 apart and 120 long, and the arc
/// // of each end.
/// let line = |y: f64| (0..=24).map(|i| DVec2::new(100.0 + 5.0 * f64::from(i), y)).collect::<Vec<_>>();
/// let end = |x: f64| {
///     (0..=16)
///         .map(|i| {
///             let t = std::f64::consts::PI * f64::from(i) / 16.0 - std::f64::consts::FRAC_PI_2;
///             DVec2::new(x + 6.0 * t.cos(), 110.0 + 10.0 * t.sin())
///         })
///         .collect::<Vec<_>>()
/// };
/// let strokes = [line(100.0), line(120.0), end(100.0), end(220.0)];
/// let classes = [StrokeClass::Silhouette, StrokeClass::Silhouette, StrokeClass::Feature, StrokeClass::Feature];
/// let context = SnapContext::new(
///     strokes.iter().zip(classes).enumerate().map(|(i, (s, c))| (StrokeId(i as u32), s.as_slice(), c)),
/// );
/// // Dropped in its middle, with no size and no direction.
/// let snapped = snap_at(&context, PrimitiveKind::Cylinder, DVec2::new(158.0, 112.0), None, &SnapSettings::default())?;
/// let Primitive::Cylinder(c) = &snapped.result.primitive else { unreachable!() };
/// let image_axis = c.axis.truncate().normalize();
/// assert!(image_axis.x.abs() > 0.99, "it lies across the page: {image_axis:?}");
/// let projected = c.length * c.axis.truncate().length();
/// assert!((c.radius - 10.0).abs() < 1.0 && (projected - 120.0).abs() < 12.0);
/// # Ok::<(), geosnap_core::snap::SnapError>(())
/// ```
pub fn snap_at(
    context: &SnapContext,
    kind: PrimitiveKind,
    at: DVec2,
    axis: Option<DVec2>,
    settings: &SnapSettings,
) -> Result<PointSnap, SnapError> {
    snap_at_with(context, kind, at, axis, settings, SolveContext::default())
}

/// [`snap_at`] with the solves' context (cancel flag, clock).
///
/// # Errors
///
/// As [`snap_at`].
pub fn snap_at_with(
    context: &SnapContext,
    kind: PrimitiveKind,
    at: DVec2,
    axis: Option<DVec2>,
    settings: &SnapSettings,
    mut solve: SolveContext<'_>,
) -> Result<PointSnap, SnapError> {
    if !at.is_finite() || axis.is_some_and(|a| !a.is_finite() || a.length() == 0.0) {
        return Err(SnapError::NonFinite(kind.name()));
    }
    let mut snapped: Vec<(SnapResult, Primitive)> = Vec::new();
    let mut first_error = None;
    for guess in guesses(context, kind, at, axis) {
        match snap_from(context, &guess, settings, None, solve.reborrow()) {
            Err(SnapError::Cancelled) => return Err(SnapError::Cancelled),
            Err(e) => {
                first_error.get_or_insert(e);
            }
            Ok(r) => snapped.push((r, guess)),
        }
    }
    // Every reading is weighed at one scale, the smallest reading's (module docs): at its
    // own size, a reading spanning several parts would count their strokes in a wider
    // band than the part pointed at counts its own.
    let scale = snapped
        .iter()
        .map(|(r, _)| r.primitive.size())
        .filter(|s| s.is_finite() && *s > 0.0)
        .fold(f64::INFINITY, f64::min);
    let mut candidates: Vec<(Scored, Primitive)> = snapped
        .into_iter()
        .map(|(r, guess)| (Scored::of(context, r, scale, settings), guess))
        .collect();
    // The drop points at the part's middle: readings centred near it are the ones meant
    // (a post read from a drop on the cap standing on it explains more, and is not
    // pointed at); the others compete only when no reading is.
    let centred = |s: &Scored| {
        let c = s.result.primitive.center().truncate();
        c.distance(view_from_sketch(at)) <= CENTRE_REACH * s.result.primitive.size()
    };
    if candidates.iter().any(|(s, _)| centred(s)) {
        candidates.retain(|(s, _)| centred(s));
    }
    let guesses: Vec<(Primitive, Primitive)> = candidates
        .iter()
        .map(|(s, g)| (s.result.primitive.clone(), g.clone()))
        .collect();
    let Some(result) = choose(candidates.into_iter().map(|(s, _)| s).collect()) else {
        return Err(first_error.unwrap_or(SnapError::NotEnoughStrokes {
            kind: kind.name(),
            found: "no strokes near the drop".to_owned(),
        }));
    };
    let guess = guesses
        .into_iter()
        .find(|(p, _)| *p == result.primitive)
        .map_or_else(|| result.primitive.clone(), |(_, g)| g);
    Ok(PointSnap { result, guess })
}

/// The larger extent of the drawing's strokes, `None` without strokes.
fn extent(context: &SnapContext) -> Option<f64> {
    let (lo, hi) = context.strokes.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), s| (lo.min(s.bounds.0), hi.max(s.bounds.1)),
    );
    let extent = (hi - lo).max_element();
    (extent.is_finite() && extent > 0.0).then_some(extent)
}

/// The distance from `p` to the box `bounds` (0 inside).
fn box_distance(bounds: (DVec2, DVec2), p: DVec2) -> f64 {
    (bounds.0 - p).max(p - bounds.1).max(DVec2::ZERO).length()
}

/// The two principal directions (major, then minor) of `points`' spread (view space, y
/// up), each pointing up; up alone when fewer than three points or no spread say it.
fn principal_directions(points: &[DVec2]) -> Vec<DVec2> {
    let up = DVec2::Y;
    if points.len() < 3 {
        return vec![up];
    }
    let mean = points.iter().sum::<DVec2>() / points.len() as f64;
    let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
    for p in points {
        let d = *p - mean;
        xx += d.x * d.x;
        xy += d.x * d.y;
        yy += d.y * d.y;
    }
    if xx + yy <= 0.0 {
        return vec![up];
    }
    let major = DVec2::from_angle(0.5 * (2.0 * xy).atan2(xx - yy));
    let upward = |d: DVec2| if d.dot(up) < 0.0 { -d } else { d };
    let mut out: Vec<DVec2> = Vec::with_capacity(2);
    for d in [major, major.perp()] {
        let d = upward(d);
        if out.iter().all(|o| o.dot(d).abs() < SAME_DIRECTION.cos()) {
            out.push(d);
        }
    }
    out
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::sketch::{StrokeClass, StrokeId};

    /// A context of `strokes` (sketch space), every one an outline.
    pub(in crate::snap) fn context(strokes: &[Vec<DVec2>]) -> SnapContext {
        SnapContext::new(
            strokes
                .iter()
                .enumerate()
                .map(|(i, s)| (StrokeId(i as u32), s.as_slice(), StrokeClass::Silhouette)),
        )
    }

    fn circle(c: DVec2, r: f64) -> Vec<DVec2> {
        (0..=48)
            .map(|i| c + DVec2::from_angle(std::f64::consts::TAU * f64::from(i) / 48.0) * r)
            .collect()
    }

    #[test]
    fn a_ball_far_bigger_than_any_default_is_found_from_its_middle() {
        // A ball 600 across alone on the page; a point drop in its middle has no
        // stroke within a palette-sized reach.
        let ctx = context(&[circle(DVec2::new(500.0, 500.0), 300.0)]);
        let snapped = snap_at(
            &ctx,
            PrimitiveKind::Sphere,
            DVec2::new(520.0, 470.0),
            None,
            &SnapSettings::default(),
        )
        .expect("the ball snaps");
        let Primitive::Sphere(s) = &snapped.result.primitive else {
            panic!("a sphere");
        };
        assert!((s.radius - 300.0).abs() < 6.0, "radius {}", s.radius);
        assert!(s.center.truncate().distance(DVec2::new(500.0, -500.0)) < 6.0);
    }

    #[test]
    fn a_small_ball_beside_a_big_one_is_found_where_it_is_dropped() {
        let ctx = context(&[
            circle(DVec2::new(500.0, 500.0), 300.0),
            circle(DVec2::new(900.0, 500.0), 30.0),
        ]);
        let snapped = snap_at(
            &ctx,
            PrimitiveKind::Sphere,
            DVec2::new(905.0, 495.0),
            None,
            &SnapSettings::default(),
        )
        .expect("the small ball snaps");
        let Primitive::Sphere(s) = &snapped.result.primitive else {
            panic!("a sphere");
        };
        assert!((s.radius - 30.0).abs() < 2.0, "radius {}", s.radius);
    }

    /// The visible curves of `truth` as strokes (sketch space).
    fn drawn(truth: &Primitive) -> Vec<Vec<DVec2>> {
        truth
            .current_shape()
            .curves
            .iter()
            .filter(|c| c.visible)
            .map(|c| {
                c.curve
                    .points(48)
                    .into_iter()
                    .map(sketch_from_view)
                    .collect()
            })
            .collect()
    }

    #[test]
    fn thin_parts_are_found_in_their_own_proportions() {
        let at = DVec2::new(400.0, 300.0);
        let plank = Placement {
            axis: DVec2::new(1.0, -0.4),
            size: Some([30.0, 300.0, 12.0]),
            ..Placement::at(at)
        };
        let rod = Placement {
            axis: DVec2::new(1.0, -0.4),
            length: Some(320.0),
            radius: Some(10.0),
            ..Placement::at(at)
        };
        for (kind, placement) in [
            (PrimitiveKind::Cuboid, plank),
            (PrimitiveKind::Cylinder, rod),
        ] {
            let truth = Primitive::from_placement(kind, &placement, 100.0);
            let ctx = context(&drawn(&truth));
            let snapped = snap_at(
                &ctx,
                kind,
                at + DVec2::new(3.0, 2.0),
                None,
                &SnapSettings::default(),
            )
            .expect("it snaps");
            let got = &snapped.result.primitive;
            assert!(
                got.center().distance(truth.center()) < 0.03 * truth.size()
                    && (got.size() / truth.size() - 1.0).abs() < 0.07,
                "{kind:?}: {got:?} for {truth:?}"
            );
        }
    }

    #[test]
    fn guesses_follow_the_strokes_direction_unless_the_drop_gives_one() {
        // Two long lines across the page.
        let line = |y: f64| -> Vec<DVec2> {
            (0..=40)
                .map(|i| DVec2::new(10.0 * f64::from(i), y))
                .collect()
        };
        let ctx = context(&[line(100.0), line(140.0)]);
        let at = DVec2::new(200.0, 120.0);
        let free = guesses(&ctx, PrimitiveKind::Cylinder, at, None);
        assert!(free.iter().any(|g| match g {
            Primitive::Cylinder(c) => c.axis.truncate().normalize().x.abs() > 0.99,
            _ => false,
        }));
        let aimed = guesses(
            &ctx,
            PrimitiveKind::Cylinder,
            at,
            Some(DVec2::new(0.0, -1.0)),
        );
        assert!(!aimed.is_empty());
        assert!(aimed.iter().all(|g| match g {
            Primitive::Cylinder(c) => c.axis.truncate().normalize().y > 0.99,
            _ => false,
        }));
    }

    #[test]
    fn no_strokes_near_is_a_clear_error_and_bad_points_are_refused() {
        let ctx = context(&[circle(DVec2::new(500.0, 500.0), 30.0)]);
        let settings = SnapSettings::default();
        // Far beyond the drawing: every rung's reach is empty.
        let far = snap_at(
            &ctx,
            PrimitiveKind::Cone,
            DVec2::new(9000.0, 9000.0),
            None,
            &settings,
        );
        assert!(
            matches!(far, Err(SnapError::NotEnoughStrokes { .. })),
            "{far:?}"
        );
        let nan = snap_at(
            &ctx,
            PrimitiveKind::Cone,
            DVec2::new(f64::NAN, 0.0),
            None,
            &settings,
        );
        assert!(matches!(nan, Err(SnapError::NonFinite(_))));
        let zero = snap_at(
            &ctx,
            PrimitiveKind::Cone,
            DVec2::new(500.0, 500.0),
            Some(DVec2::ZERO),
            &settings,
        );
        assert!(matches!(zero, Err(SnapError::NonFinite(_))));
        let empty = context(&[]);
        assert!(snap_at(&empty, PrimitiveKind::Sphere, DVec2::ZERO, None, &settings).is_err());
    }
}
