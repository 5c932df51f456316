//! Starting poses of a solid of revolution read off its drawn end ellipses.
//!
//! An end circle of a solid of revolution seen at elevation φ projects (orthographically)
//! to an ellipse with minor/major = |sin φ| (the axis' z component) whose minor axis runs
//! along the projected axis, whatever the part's proportions. Every stroke near the drop,
//! and every run of fragments that continue one another end to end (an ellipse drawn in
//! three or four arcs), is fitted with an ellipse (Halíř–Flusser, refined); one it fits
//! well (RMS within 8 % of the ellipse) over a quarter of a turn or more (an arc the
//! classifier took for an outline must cover more: 2.5 rad), whose centre lies near an
//! end of the dropped primitive and whose major semi-axis is within a factor 2 of the
//! dropped radii, may draw an end.
//!
//! Two such ellipses draw the two ends when they agree as a solid's ends must: about the
//! same minor/major and orientation, their centres offset along their minor axes. Of the
//! pairs that agree, the one nearest the dropped ends (in place and radius) is taken; the
//! tilt, the image axis (the minor axes, signed by the offset), the centre (midway), the
//! length (the offset along the axis) and the radii then all come from the drawing. This
//! holds for a rod as for a thin disc, whose two large concentric ellipses a tenth of a
//! radius apart say its tilt and thickness although its outlines are too short to.
//! Without a pair, the single ellipse nearest a dropped end gives the tilt, the image
//! axis (its minor axis), the radius and, with the dropped projected length, the centre
//! on the side of the drop.
//!
//! The mirror sign of the tilt does not change the projection, so the positive one is
//! used.
//!
//! A far end is often drawn only in part: its front arc, or the arc of a stroke drawn
//! down one outline, round the end and back up the other (read in its pieces,
//! `snap/pieces.rs`). Fitted alone, five parameters from half a turn, its flatness is
//! loose, and a hand's wobble makes it disagree with the near end's. Without a pair
//! that agrees, an ellipse drawn nearly whole (5 rad of its turn or more) near one
//! dropped end gives the shape of both ends, as a solid's end circles are parallel: the
//! strokes near the other dropped end are read as arcs of that shape, scaled and moved
//! (a circle fitted in the frame where the whole ellipse is the unit circle), and the
//! best one that fits (RMS within 8 % of its size, 1.5 rad of its turn or more, its
//! centre offset along the minor axis) is the other end. Not for a squat part, whose
//! ends lie closer than a radius apart: its far end's arc is a narrow band beside the
//! whole ellipse, and a hand's error in drawing it is as large as the offset it would
//! say.

use glam::{DVec2, DVec3};

use super::{fragment_runs, sweep_round, Revolution};
use crate::geom::{fit_circle, fit_ellipse, refine_ellipse, Ellipse2};
use crate::primitive::Primitive;
use crate::sketch::{StrokeClass, StrokeId};
use crate::snap::context::{SnapContext, SnapStroke};

/// An ellipse fitted to a stroke, with its major axis the larger (`semi_major ≥
/// semi_minor`).
fn normalised(e: Ellipse2) -> Ellipse2 {
    if e.semi_minor.abs() > e.semi_major.abs() {
        Ellipse2 {
            center: e.center,
            semi_major: e.semi_minor.abs(),
            semi_minor: e.semi_major.abs(),
            angle: e.angle + std::f64::consts::FRAC_PI_2,
        }
    } else {
        Ellipse2 {
            semi_major: e.semi_major.abs(),
            semi_minor: e.semi_minor.abs(),
            ..e
        }
    }
}

/// An ellipse that a stroke, or a run of fragments, draws (see [`drawn_ellipses`]).
struct Drawn {
    /// The fitted ellipse.
    ellipse: Ellipse2,
    /// The strokes that draw it (one, or the fragments of a run in order).
    strokes: Vec<StrokeId>,
    /// Their points.
    points: Vec<DVec2>,
    /// The points' RMS distance to it.
    rms: f64,
    /// How much of its turn they cover (radians).
    sweep: f64,
}

/// The ellipses that the strokes and pieces `nearby` ([`ellipse_strokes`]) draw (module
/// docs): a centre within `reach` of `near`, a major semi-axis in `radii` (the smallest and largest allowed). Besides
/// single strokes, runs of fragments ([`fragment_runs`]) are read together: a hand
/// often draws an ellipse in three or four arcs, none of which says its shape alone.
fn drawn_ellipses(
    nearby: &[&SnapStroke],
    near: DVec2,
    reach: f64,
    radii: (f64, f64),
) -> Vec<Drawn> {
    let mut out = Vec::new();
    let mut read = |run: &[&SnapStroke]| {
        let points: Vec<DVec2> = run.iter().flat_map(|s| s.points.iter().copied()).collect();
        if points.len() < 5 {
            return;
        }
        let Some(fit) = fit_ellipse(&points) else {
            return;
        };
        let fit = normalised(refine_ellipse(&fit, &points));
        if fit.center.distance(near) > reach || !(radii.0..=radii.1).contains(&fit.semi_major) {
            return;
        }
        // Only strokes the ellipse really fits (RMS within 8 % of its size) and that
        // cover a good part of it tell the tilt; an arc classified as an outline must
        // cover more of the turn, as an outline bent by the hand may fit a short arc.
        let min_sweep = if run.iter().all(|s| s.class == StrokeClass::Feature) {
            1.5
        } else {
            2.5
        };
        let (rms, span) = fit.rms_distance_and_span(&points);
        let covered = span.map_or(0.0, |s| s.sweep);
        if rms <= 0.08 * fit.semi_major && covered >= min_sweep {
            out.push(Drawn {
                ellipse: fit,
                strokes: run.iter().map(|s| s.id).collect(),
                points,
                rms,
                sweep: covered,
            });
        }
    };
    for stroke in nearby {
        read(std::slice::from_ref(stroke));
    }
    for run in fragment_runs(nearby, radii.1) {
        // Every stretch of two or more consecutive fragments: a run may carry on from an
        // end arc into the outline it meets.
        for len in 2..=run.len() {
            for window in run.windows(len) {
                read(window);
            }
        }
    }
    out
}

/// The strokes and pieces of strokes that may draw an ellipse with its centre within
/// `reach` of `near` and a major semi-axis up to `largest`.
fn ellipse_strokes(
    context: &SnapContext,
    near: DVec2,
    reach: f64,
    largest: f64,
) -> Vec<&SnapStroke> {
    context
        .strokes
        .iter()
        .chain(&context.pieces)
        .filter(|stroke| {
            let (lo, hi) = stroke.bounds;
            let closest = DVec2::new(near.x.clamp(lo.x, hi.x), near.y.clamp(lo.y, hi.y));
            stroke.points.len() >= 3 && closest.distance(near) <= reach + 2.0 * largest
        })
        .collect()
}

/// Whether two readings draw one ellipse between them (pieces of one end, or one end
/// drawn twice) rather than two: they share a stroke, or one ellipse fits both about as
/// well (RMS within 1.5 × the worse of their own) as each fits its own.
fn one_ellipse(a: &Drawn, b: &Drawn) -> bool {
    if a.strokes.iter().any(|s| b.strokes.contains(s)) {
        return true;
    }
    let points: Vec<DVec2> = a.points.iter().chain(&b.points).copied().collect();
    fit_ellipse(&points).is_some_and(|e| {
        let e = refine_ellipse(&e, &points);
        e.rms_distance(&points) <= 1.5 * a.rms.max(b.rms)
    })
}

/// The axis with image direction `dir` and out-of-plane component `z` (|z| < 1).
fn tilted(dir: DVec2, z: f64) -> DVec3 {
    let xy = dir.normalize_or(DVec2::Y) * (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(xy.x, xy.y, z)
}

/// Minor over major of an ellipse, clamped below 0.95 (a rounder end says little of the
/// image axis, and a tilt of 1 none of its length).
fn roundness(e: &Ellipse2) -> f64 {
    (e.semi_minor / e.semi_major.max(f64::MIN_POSITIVE)).clamp(0.0, 0.95)
}

/// Ellipses rounder than this do not tell the image axis by their minor axes.
const ROUND: f64 = 0.9;

/// Whether ellipses `b` and `t` can draw the two ends of one solid of revolution (module
/// docs): the same roundness within 0.2, major axes within 20° (unless both are nearly
/// round), and centres offset along the minor axes (across them by at most a quarter of
/// the major semi-axis).
fn ends_agree(b: &Ellipse2, t: &Ellipse2) -> bool {
    let (rb, rt) = (roundness(b), roundness(t));
    if (rb - rt).abs() > 0.2 {
        return false;
    }
    let round = rb.min(rt) >= ROUND;
    if !round && b.major_axis().perp_dot(t.major_axis()).abs() > 20f64.to_radians().sin() {
        return false;
    }
    let across = (t.center - b.center).dot(b.major_axis()).abs();
    round || across <= 0.25 * b.semi_major.max(t.semi_major)
}

/// What the drawn ends say of a solid of revolution: its image axis (unit, signed
/// bottom to top), tilt, image centre, projected length and end radii.
struct Reading {
    dir: DVec2,
    z: f64,
    center: DVec2,
    projected: f64,
    radii: (f64, f64),
}

/// The drawn ends' reading (module docs), or `None` when no ellipse near the drop
/// draws an end. `ends` are the dropped ends' image centres (bottom, top), `radii` their
/// radii, `image_dir` the dropped image axis and `projected` its projected length.
fn read_ends(
    context: &SnapContext,
    ends: (DVec2, DVec2),
    radii: (f64, f64),
    image_dir: DVec2,
    projected: f64,
    gate: f64,
) -> Option<Reading> {
    let mid = ends.0.midpoint(ends.1);
    let reach = gate + ends.0.distance(ends.1) / 2.0;
    let allowed = (0.5 * radii.0.min(radii.1), 2.0 * radii.0.max(radii.1));
    let nearby = ellipse_strokes(context, mid, reach, allowed.1);
    let drawn = drawn_ellipses(&nearby, mid, reach, allowed);
    let ellipses: Vec<&Ellipse2> = drawn.iter().map(|d| &d.ellipse).collect();
    if let Some((i, j)) = end_pair(&drawn, &ellipses, ends, radii, gate) {
        return Some(pair_reading(ellipses[i], ellipses[j], image_dir, gate));
    }
    if let Some((b, t)) = similar_pair(&drawn, &nearby, ends, radii, gate) {
        return Some(pair_reading(&b, &t, image_dir, gate));
    }
    // One end drawn: the nearest ellipse to either dropped end.
    let (e, top) = ellipses
        .iter()
        .flat_map(|e| {
            [
                end_cost(e, ends.0, radii.0, gate).map(|c| (c, e, false)),
                end_cost(e, ends.1, radii.1, gate).map(|c| (c, e, true)),
            ]
        })
        .flatten()
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, e, top)| (e, top))?;
    Some(one_end_reading(e, top, ends, radii, image_dir, projected))
}

/// A drawn ellipse that shows most of its turn says the shape of both ends: a solid of
/// revolution's end circles are parallel, so in a parallel view their ellipses have the
/// same flatness and orientation. Its other end, drawn only in part (a front arc, or the
/// arc of a stroke drawn round the end), says little of its shape alone but fits that
/// shape, scaled and moved: in the frame where the whole ellipse is a unit circle it is
/// an arc of a circle. The pair (bottom, top) of the whole ellipse nearest a dropped end
/// and the arc that fits its shape best at the other, or `None`.
fn similar_pair(
    drawn: &[Drawn],
    nearby: &[&SnapStroke],
    ends: (DVec2, DVec2),
    radii: (f64, f64),
    gate: f64,
) -> Option<(Ellipse2, Ellipse2)> {
    let mut best: Option<(f64, Ellipse2, Ellipse2, bool)> = None;
    for whole in drawn.iter().filter(|d| d.sweep >= WHOLE) {
        let e = &whole.ellipse;
        // The arcs of its shape that the other strokes draw, apart enough from it (a
        // squat part's ends lie closer than a radius apart: its far end's arc is a
        // narrow band beside the whole ellipse, and a hand's error in drawing it is as
        // large as the offset it would say).
        let arcs: Vec<Ellipse2> = nearby
            .iter()
            .filter(|s| !whole.strokes.contains(&s.id))
            .filter_map(|s| similar_arc(e, &s.points))
            .filter(|other| {
                let across = (other.center - e.center).dot(e.major_axis()).abs();
                let larger = e.semi_major.max(other.semi_major);
                across <= 0.25 * larger && other.center.distance(e.center) >= larger
            })
            .collect();
        for top in [false, true] {
            let (at, r, other_at, other_r) = if top {
                (ends.1, radii.1, ends.0, radii.0)
            } else {
                (ends.0, radii.0, ends.1, radii.1)
            };
            let Some(cost) = end_cost(e, at, r, gate) else {
                continue;
            };
            for other in &arcs {
                let Some(other_cost) = end_cost(other, other_at, other_r, gate) else {
                    continue;
                };
                if best.as_ref().is_none_or(|b| cost + other_cost < b.0) {
                    best = Some((cost + other_cost, *e, *other, top));
                }
            }
        }
    }
    best.map(|(_, e, other, top)| if top { (other, e) } else { (e, other) })
}

/// A drawn ellipse shows most of its turn (radians) when it covers this much of it.
const WHOLE: f64 = 5.0;

/// The ellipse of `shape`'s flatness and orientation that `points` draw an arc of, when
/// they fit it (RMS within 8 % of its size) over at least 1.5 radians of its turn.
fn similar_arc(shape: &Ellipse2, points: &[DVec2]) -> Option<Ellipse2> {
    let (u, v) = (shape.major_axis(), shape.minor_axis());
    let (a, b) = (
        shape.semi_major,
        shape.semi_minor.max(1e-9 * shape.semi_major),
    );
    let to_unit = |p: &DVec2| DVec2::new(p.dot(u) / a, p.dot(v) / b);
    let local: Vec<DVec2> = points.iter().map(to_unit).collect();
    let circle = fit_circle(&local)?;
    if sweep_round(&local, circle.center) < 1.5 {
        return None;
    }
    let c = circle.center;
    let similar = Ellipse2 {
        center: u * (c.x * a) + v * (c.y * b),
        semi_major: a * circle.radius,
        semi_minor: b * circle.radius,
        angle: shape.angle,
    };
    (similar.rms_distance(points) <= 0.08 * similar.semi_major).then_some(similar)
}

/// How far an ellipse is from drawing an end at `at` with radius `r`: its centre's
/// distance in gates plus its radius' in log ratio; `None` beyond a gate, where it does
/// not draw that end.
fn end_cost(e: &Ellipse2, at: DVec2, r: f64, gate: f64) -> Option<f64> {
    let d = e.center.distance(at) / gate;
    (d <= 1.0).then(|| d + (e.semi_major / r).ln().abs())
}

/// The indices among `ellipses` (the ellipses of `drawn`) of the bottom and top end
/// ellipses that agree as the two ends of one solid and lie nearest the dropped ends
/// (`ends`, with `radii`) by [`end_cost`], or `None` when no two do.
fn end_pair(
    drawn: &[Drawn],
    ellipses: &[&Ellipse2],
    ends: (DVec2, DVec2),
    radii: (f64, f64),
    gate: f64,
) -> Option<(usize, usize)> {
    let mut pair: Option<(f64, usize, usize)> = None;
    for (i, b) in ellipses.iter().enumerate() {
        for (j, t) in ellipses.iter().enumerate() {
            if i == j || !ends_agree(b, t) {
                continue;
            }
            let (Some(cb), Some(ct)) = (
                end_cost(b, ends.0, radii.0, gate),
                end_cost(t, ends.1, radii.1, gate),
            ) else {
                continue;
            };
            if pair.is_none_or(|(c, _, _)| cb + ct < c) && !one_ellipse(&drawn[i], &drawn[j]) {
                pair = Some((cb + ct, i, j));
            }
        }
    }
    pair.map(|(_, i, j)| (i, j))
}

/// The reading of two drawn end ellipses, bottom `b` and top `t`: tilt from the rounder,
/// image axis from their minor axes, the centre between them and the projected length
/// along the axis. `image_dir` is the dropped image axis.
fn pair_reading(b: &Ellipse2, t: &Ellipse2, image_dir: DVec2, gate: f64) -> Reading {
    let z = roundness(b).max(roundness(t));
    let offset = t.center - b.center;
    // The image axis: the minor axes (sign-aligned), unless the ends are too round to
    // tell, then the offset, then the drop's.
    let along = |d: DVec2, like: DVec2| if d.dot(like) < 0.0 { -d } else { d };
    let reference = if offset.length() > 1e-9 * gate {
        offset
    } else {
        image_dir
    };
    let dir = if z < ROUND {
        (along(b.minor_axis(), reference) + along(t.minor_axis(), reference))
            .normalize_or(image_dir)
    } else {
        reference.normalize_or(image_dir)
    };
    Reading {
        dir,
        z,
        center: b.center.midpoint(t.center),
        projected: offset.dot(dir).abs(),
        radii: (b.semi_major, t.semi_major),
    }
}

/// The reading of one drawn end ellipse `e` (the top end when `top`): tilt and image axis
/// from it, the dropped projected length, the centre on the drop's side of the end, and
/// the dropped end radii scaled to its radius. `ends`, `radii`, `image_dir` and
/// `projected` are the drop's as in [`read_ends`].
fn one_end_reading(
    e: &Ellipse2,
    top: bool,
    ends: (DVec2, DVec2),
    radii: (f64, f64),
    image_dir: DVec2,
    projected: f64,
) -> Reading {
    let z = roundness(e);
    let dir = if z < ROUND {
        let m = e.minor_axis();
        if m.dot(image_dir) < 0.0 {
            -m
        } else {
            m
        }
    } else {
        image_dir.normalize_or(DVec2::Y)
    };
    // The drop's projected length at the drawn tilt; the centre on the drop's side of
    // the end.
    let drop_centre = ends.0.midpoint(ends.1);
    let side = if (drop_centre - e.center).dot(dir) < 0.0 {
        -1.0
    } else {
        1.0
    };
    let scale = e.semi_major / if top { radii.1 } else { radii.0 };
    Reading {
        dir,
        z,
        center: e.center + dir * (side * projected / 2.0),
        projected,
        radii: (radii.0 * scale, radii.1 * scale),
    }
}

/// The dropped primitive re-posed from its drawn end ellipses, or `None` when it is not
/// a solid of revolution or no end ellipse is drawn near it.
pub(crate) fn repose_from_ellipses(
    context: &SnapContext,
    primitive: &Primitive,
) -> Option<Primitive> {
    let dropped = Revolution::of(primitive)?;
    let gate = 0.3 * primitive.size();
    let half = dropped.axis * (dropped.length / 2.0);
    let ends = (
        (dropped.center - half).truncate(),
        (dropped.center + half).truncate(),
    );
    let image_dir = dropped.axis.truncate();
    let reading = read_ends(
        context,
        ends,
        dropped.radii,
        image_dir,
        dropped.length * image_dir.length(),
        gate,
    )?;
    Revolution {
        center: DVec3::new(reading.center.x, reading.center.y, dropped.center.z),
        axis: tilted(reading.dir, reading.z),
        length: reading.projected / (1.0 - reading.z * reading.z).max(1e-6).sqrt(),
        radii: reading.radii,
    }
    .applied_to(primitive)
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::{normalised, repose_from_ellipses, roundness, similar_arc};
    use crate::geom::{fit_ellipse, refine_ellipse, Ellipse2};
    use crate::primitive::{Cylinder, Primitive};
    use crate::sketch::{StrokeClass, StrokeId};
    use crate::snap::initial::tests::{rim, strokes_of};
    use crate::snap::SnapContext;

    /// A table top: radius 200, a tenth as thick, tilted 37° out of the view plane.
    fn disc() -> Cylinder {
        Cylinder {
            center: DVec3::new(500.0, -400.0, 0.0),
            axis: DVec3::new(0.48, 0.64, 0.6),
            length: 20.0,
            radius: 200.0,
        }
    }

    /// The disc dropped as a hand would: in the palette's tilt, turned, smaller, off.
    fn dropped_disc() -> Primitive {
        Primitive::Cylinder(Cylinder {
            center: DVec3::new(515.0, -390.0, 0.0),
            axis: DVec3::new(0.35, 0.87, 0.342).normalize(),
            length: 30.0,
            radius: 160.0,
        })
    }

    #[test]
    fn two_concentric_large_ellipses_make_a_disc() {
        let truth = disc();
        let half = truth.axis * (truth.length / 2.0);
        let tau = std::f64::consts::TAU;
        let context = strokes_of(
            &[
                rim(truth.center + half, truth.axis, truth.radius, 0.0, tau),
                rim(
                    truth.center - half,
                    truth.axis,
                    truth.radius,
                    0.0,
                    tau / 2.0,
                ),
            ],
            StrokeClass::Feature,
        );
        let Some(Primitive::Cylinder(c)) = repose_from_ellipses(&context, &dropped_disc()) else {
            panic!("no pose");
        };
        let mirror = DVec3::new(c.axis.x, c.axis.y, -c.axis.z);
        let angle = c
            .axis
            .dot(truth.axis)
            .abs()
            .max(mirror.dot(truth.axis).abs())
            .min(1.0)
            .acos();
        assert!(angle.to_degrees() < 0.5, "{c:?}");
        assert!(
            (c.length - truth.length).abs() < 0.02 * truth.length,
            "{c:?}"
        );
        assert!(
            (c.radius - truth.radius).abs() < 0.01 * truth.radius,
            "{c:?}"
        );
        assert!(c.center.truncate().distance(truth.center.truncate()) < 0.5);
    }

    /// A rod whose near end is drawn whole and whose outlines and far end are one U
    /// stroke (down one outline, round the far end's front arc, back up the other),
    /// the arc drawn by a wobbling hand so that, fitted alone, it is a flatter ellipse
    /// than the near end's: the U's pieces give the far end, read in the near end's
    /// shape, and with it the rod's length, which a drop a quarter short does not.
    #[test]
    fn a_far_end_drawn_round_in_a_u_stroke_gives_the_length() {
        let truth = Cylinder {
            center: DVec3::new(300.0, -300.0, 0.0),
            axis: DVec3::new(0.3, 0.8, 0.52).normalize(),
            length: 240.0,
            radius: 50.0,
        };
        let (a, r) = (truth.axis, truth.radius);
        let w = DVec3::new(a.y, -a.x, 0.0).normalize();
        let k = a.cross(w);
        let (top, bottom) = (
            truth.center + a * (truth.length / 2.0),
            truth.center - a * (truth.length / 2.0),
        );
        let sketch = |p: DVec3| DVec2::new(p.x, -p.y);
        let at = |c: DVec3, t: f64| c + r * (t.cos() * w + t.sin() * k);
        let near: Vec<DVec2> = (0..=64)
            .map(|i| sketch(at(top, std::f64::consts::TAU * f64::from(i) / 64.0)))
            .collect();
        // Round the far end on the side away from the near one.
        let turn = if k.truncate().dot(a.truncate()) > 0.0 {
            -std::f64::consts::PI
        } else {
            std::f64::consts::PI
        };
        let line =
            |p: DVec3, q: DVec3| (0..40).map(move |i| sketch(p.lerp(q, f64::from(i) / 40.0)));
        let mut u: Vec<DVec2> = line(at(top, 0.0), at(bottom, 0.0)).collect();
        u.extend((0..=30).map(|i| {
            let t = turn * f64::from(i) / 30.0;
            let p = at(bottom, t);
            let wobble = 0.04 * r * (2.0 * t).sin().abs();
            sketch(p + (p - bottom).normalize() * wobble)
        }));
        u.extend(line(at(bottom, turn), at(top, turn)).skip(1));
        let context = SnapContext::new([
            (StrokeId(0), near.as_slice(), StrokeClass::Feature),
            (StrokeId(1), u.as_slice(), StrokeClass::Silhouette),
        ]);
        let dropped = Primitive::Cylinder(Cylinder {
            center: truth.center + DVec3::new(8.0, 20.0, 0.0),
            axis: DVec3::new(0.35, 0.87, 0.342).normalize(),
            length: 180.0,
            radius: 45.0,
        });
        let Some(Primitive::Cylinder(c)) = repose_from_ellipses(&context, &dropped) else {
            panic!("no pose");
        };
        assert!(
            (c.length - truth.length).abs() < 0.05 * truth.length,
            "{c:?}"
        );
        assert!(
            c.center.truncate().distance(truth.center.truncate()) < 0.03 * truth.length,
            "{c:?}"
        );
    }

    /// A far end drawn only over a third of its turn, by a hand that wobbles: fitted
    /// alone, five parameters from a short arc, its flatness is anyone's guess; read in
    /// the shape of the near end (centre and scale), it is the end drawn.
    #[test]
    fn a_short_arc_is_read_in_the_shape_of_the_whole_end() {
        let near = Ellipse2 {
            center: DVec2::new(100.0, 50.0),
            semi_major: 60.0,
            semi_minor: 24.0,
            angle: 0.3,
        };
        let far = Ellipse2 {
            center: near.center + near.minor_axis() * -150.0,
            semi_major: 48.0,
            semi_minor: 19.2,
            ..near
        };
        let arc: Vec<DVec2> = (0..=40)
            .map(|i| {
                let t = 3.6 + 2.1 * f64::from(i) / 40.0;
                let p = far.point_at(t);
                p + (p - far.center).normalize() * (1.2 * (9.0 * t).sin())
            })
            .collect();
        let free = normalised(refine_ellipse(&fit_ellipse(&arc).expect("a fit"), &arc));
        let similar = similar_arc(&near, &arc).expect("the arc fits the near end's shape");
        assert!(
            similar.center.distance(far.center) < 0.03 * far.semi_major,
            "{similar:?}"
        );
        assert!(
            (similar.semi_major / far.semi_major - 1.0).abs() < 0.03,
            "{similar:?}"
        );
        assert!(
            (roundness(&free) - roundness(&near)).abs() > 0.2,
            "alone, the arc reads as another shape: {free:?}"
        );
    }

    #[test]
    fn two_halves_of_one_ellipse_are_one_end() {
        // Only the near end is drawn, in two strokes: they are not the disc's two ends
        // (which would make it a disc of no thickness).
        let truth = disc();
        let near = truth.center + truth.axis * (truth.length / 2.0);
        let pi = std::f64::consts::PI;
        let context = strokes_of(
            &[
                rim(near, truth.axis, truth.radius, 0.0, pi),
                rim(near, truth.axis, truth.radius, pi, 2.0 * pi),
            ],
            StrokeClass::Feature,
        );
        let Some(Primitive::Cylinder(c)) = repose_from_ellipses(&context, &dropped_disc()) else {
            panic!("no pose");
        };
        // The tilt and image axis are the drawn end's; the length is the drop's.
        assert!((c.axis.z.abs() - truth.axis.z).abs() < 0.01, "{c:?}");
        let dir = c.axis.truncate().normalize();
        assert!(
            dir.dot(truth.axis.truncate().normalize()).abs() > 0.9999,
            "{c:?}"
        );
        assert!(c.length > 20.0, "{c:?}");
    }

    #[test]
    fn ends_drawn_in_fragments_are_read_together() {
        // A rod whose top is drawn in five short arcs and whose bottom's half in three,
        // with small gaps: no arc alone sweeps enough of a turn to tell the tilt.
        let truth = Cylinder {
            center: DVec3::new(300.0, -300.0, 0.0),
            axis: DVec3::new(0.3, 0.8, 0.52).normalize(),
            length: 150.0,
            radius: 60.0,
        };
        let half = truth.axis * (truth.length / 2.0);
        let tau = std::f64::consts::TAU;
        let arcs = |centre: DVec3, from: f64, to: f64, n: usize| {
            (0..n)
                .map(|k| {
                    let step = (to - from) / n as f64;
                    let a = from + step * k as f64;
                    rim(centre, truth.axis, truth.radius, a + 0.04, a + step - 0.04)
                })
                .collect::<Vec<_>>()
        };
        let mut strokes = arcs(truth.center + half, 0.0, tau, 5);
        strokes.extend(arcs(truth.center - half, 0.0, tau / 2.0, 3));
        let context = strokes_of(&strokes, StrokeClass::Feature);
        let dropped = Primitive::Cylinder(Cylinder {
            center: DVec3::new(310.0, -290.0, 0.0),
            axis: DVec3::new(0.35, 0.87, 0.342).normalize(),
            length: 120.0,
            radius: 50.0,
        });
        let Some(Primitive::Cylinder(c)) = repose_from_ellipses(&context, &dropped) else {
            panic!("no pose");
        };
        assert!((c.axis.z.abs() - truth.axis.z).abs() < 0.02, "{c:?}");
        assert!(
            (c.length - truth.length).abs() < 0.05 * truth.length,
            "{c:?}"
        );
        assert!(
            (c.radius - truth.radius).abs() < 0.03 * truth.radius,
            "{c:?}"
        );
        assert!(
            c.center.truncate().distance(truth.center.truncate()) < 3.0,
            "{c:?}"
        );
    }
}
