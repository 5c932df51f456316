//! A starting pose for a bent generalized cylinder from the strokes around its drop.
//!
//! A BGC is dropped straight and in the view plane, but the drawing shows where its spine
//! runs and how it leaves the view plane:
//! - the **medial axis** of its two outlines: every sample of an outline near the drop
//!   is paired with the nearest point of another outline that lies across
//!   the tube (roughly perpendicular to the stroke, running roughly parallel to it, at a
//!   plausible width; only the samples near the drop, so an outline that runs on into
//!   another part gives only the piece near the drop); the midpoints of the pairs trace
//!   the projected spine and their half distances the radius. A quadratic through the
//!   midpoints, in the frame of their principal direction (a C: a bend of up to about
//!   120° is a graph over its chord), or a cubic when it fits them at least twice as
//!   closely (an S), is the projected spine, from the first to the last midpoint;
//! - the **end ellipses**: each other stroke near the tube goes to the nearer end of
//!   that spine and is read as a whole ellipse (it ends near where it began; a free fit)
//!   or a front arc (its extent across the spine is the major axis); the one nearest an
//!   end moves the end to its centre; its minor/major ratio is |t_z|, the out-of-plane
//!   component of the spine's end tangent (at least 0.12, so that the start shows each
//!   end on its drawn side), its minor axis the projected end tangent; and whether it is
//!   drawn whole (the end faces the viewer, its outward normal has z > 0) or as a front
//!   arc (the end faces away) gives the sign of t_z, which the fit keeps (see
//!   [`Bgc`]'s "end keeps its side"). The spine's plane z = a·x + b·y then follows from
//!   the slopes dz/ds = t_z/√(1 − t_z²) along the two projected end tangents (least
//!   squares with a small pull towards the view plane: with one ellipse, or none, the
//!   least tilted plane that explains what is drawn). An end drawn whole in two or three
//!   strokes, none of them whole, is read whole when the strokes near it go round one
//!   ellipse together and one of them runs round an end of its major axis (see
//!   [`pieced_ellipse`]).
//!
//! A stroke's class is a prior here, not a gate: the roles are decided in the tube's
//! context. The outlines are the silhouette strokes, and any feature stroke that runs
//! with the drop over half its length (a bent outline is often classified a feature
//! arc), paired across a silhouette; the strokes that then find a partner across the
//! tube for at least half their samples are the outlines, and every other stroke may be
//! an end (an end arc drawn flat is often classified a silhouette), a feature stroke
//! before any other. A stroke need not follow one curve: one drawn down an outline, round
//! the end and back up the other outline is read in runs cut at its turns ([`turns`]),
//! its legs paired as outlines and the turn between them read as an end.
//!
//! The medial axis runs out before the ends: the outlines of a tube whose ends are
//! drawn off square (an S leaves its chord 25–60° off at both ends) stop at staggered
//! points, and a hand stops them short. A spine fitted to the medial axis alone then
//! leaves the ends nearer the chord than their ellipses are drawn, and the fit from it
//! can run away (the end arcs go unassigned, the tube swings into depth). So where an
//! end ellipse shows its minor axis (minor/major at most 0.8), a second start is read
//! with the projected spine refitted through the ends' centres and along their minor
//! axes (`ProjectedSpine::through_ends`). Both are snapped; the second stands only where
//! its snap reads the drawing clearly better (see `snap::bgc_candidates`), as a refit of the
//! same reading differs from the first by the hand's noise alone.
//!
//! The spine is lifted onto that plane and resampled evenly in 3D; the radii follow the
//! measured half-widths linearly. `None` when the strokes show no tube near the drop, and
//! for a BGC that is already bent (an earlier fit snaps from itself).

use glam::{DVec2, DVec3};

use super::assign::{stroke_samples, Assignment};
use super::context::{prepare, SnapContext};
use super::{SnapError, SnapResult, SnapSettings};
use crate::geom::{fit_ellipse, fit_line, Ellipse2};
use crate::primitive::{Bgc, Primitive};
use crate::sketch::{StrokeClass, StrokeId};
use crate::solve::SolveContext;

mod medial;
mod turns;

/// A tube's outlines pair when they are between these multiples of its dropped radius
/// apart.
const WIDTHS: (f64, f64) = (0.8, 4.0);
/// Samples of the projected spine curve before the 3D resampling.
const DENSE: usize = 200;

/// The end ellipses drawn near the ends `ends` of the projected spine (where it runs
/// along the unit `taus`, outwards or inwards), for a tube of half-width about `widths`:
/// per end (ellipse, drawn whole). Each stroke near the tube but its `outlines` is read on
/// its own, whatever its class (an end arc drawn flat is often classified a silhouette;
/// the medial axis has shown which strokes are the outlines):
/// a stroke drawn all round is a whole ellipse (a free fit; its minor axis lies along the
/// spine there); otherwise it is a front arc, whose extent across the spine is the major
/// axis (the arc's own principal direction, not the spine's estimated tangent: the ends
/// of the medial axis are its least certain part). A stroke goes to the end nearer its
/// centre, and each end keeps the nearest feature stroke, or the nearest other stroke
/// when no feature stroke is read there.
fn end_ellipses(
    context: &SnapContext,
    outlines: &[StrokeId],
    loose: &[(Vec<DVec2>, StrokeClass)],
    ends: [DVec2; 2],
    taus: [DVec2; 2],
    widths: [f64; 2],
) -> [Option<(Ellipse2, bool)>; 2] {
    // The class is the prior: a stroke classified a feature beats any other, the nearest
    // first among its peers. Per end: ((overruled, distance), ellipse, drawn whole).
    type Candidate = ((bool, f64), Ellipse2, bool);
    let mut best: [Option<Candidate>; 2] = [None, None];
    // Per end, the strokes near it, for an end drawn whole in pieces.
    let mut pieces: [Vec<&[DVec2]>; 2] = [Vec::new(), Vec::new()];
    let strokes = context
        .strokes
        .iter()
        .filter(|s| !outlines.contains(&s.id))
        .map(|s| (s.points.as_slice(), s.class))
        .chain(
            loose
                .iter()
                .map(|(points, class)| (points.as_slice(), *class)),
        );
    for (points, class) in strokes {
        if points.len() < 5 {
            continue;
        }
        let overruled = class != StrokeClass::Feature;
        let (lo, hi) = points.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let centre = (lo + hi) / 2.0;
        let side = usize::from(centre.distance(ends[1]) < centre.distance(ends[0]));
        let (at, radius) = (ends[side], widths[side]);
        let near = DVec2::new(at.x.clamp(lo.x, hi.x), at.y.clamp(lo.y, hi.y));
        if near.distance(at) > 2.0 * radius {
            continue;
        }
        pieces[side].push(points);
        let Some((fit, whole)) =
            whole_ellipse(points).or_else(|| front_arc(points, at, across_of(points, taus[side])))
        else {
            continue;
        };
        let rms = fit.rms_distance(points);
        let d = fit.center.distance(at);
        let ratio = fit.semi_major / radius;
        if rms <= 0.15 * fit.semi_major
            && d <= 2.0 * radius
            && (0.4..=2.5).contains(&ratio)
            && best[side]
                .as_ref()
                .is_none_or(|(b, _, _)| (overruled, d) < *b)
        {
            best[side] = Some(((overruled, d), fit, whole));
        }
    }
    for (side, near) in pieces.iter().enumerate() {
        if best[side].as_ref().is_some_and(|(_, _, whole)| *whole) {
            continue;
        }
        let Some(fit) = pieced_ellipse(near) else {
            continue;
        };
        let (at, radius) = (ends[side], widths[side]);
        if fit.center.distance(at) <= 2.0 * radius
            && (0.4..=2.5).contains(&(fit.semi_major / radius))
        {
            best[side] = Some(((false, fit.center.distance(at)), fit, true));
        }
    }
    best.map(|b| b.map(|(_, e, whole)| (e, whole)))
}

/// The flattest end ellipse (minor over major axis) read as drawn whole in pieces:
/// flatter, the end is nearly edge-on, and which way it faces tells little (the fit may
/// turn it either way).
const PIECED_ROUNDNESS: f64 = 0.2;

/// The whole end ellipse that several strokes `pieces` draw together, if they do: a
/// hand draws a long ellipse in two or three strokes, none of which then reads as whole
/// and each of which reads as the front arc of an end facing away.
///
/// Fitted together the pieces must lie on one ellipse (RMS within 15 % of its semi-major
/// axis, minor over major at least [`PIECED_ROUNDNESS`]) and go round it (a sweep over
/// 270°), and one of them must run round an end of its major axis, where the tube's
/// outlines meet it: from one half of the ellipse into the other, curving back towards
/// the centre on both sides (within 80 % of the semi-major axis, half the semi-minor
/// axis off the major one). That last test tells an end drawn whole in pieces from the
/// front arc of an end facing away drawn with its hidden back half: a designer who draws
/// hidden lines breaks the end where the visible arc turns hidden, at the ends of the
/// major axis, and draws the two halves apart; a hand's overshoot there runs on along
/// the outline, straight past the end, not round it.
fn pieced_ellipse(pieces: &[&[DVec2]]) -> Option<Ellipse2> {
    if pieces.len() < 2 {
        return None;
    }
    let all: Vec<DVec2> = pieces.iter().flat_map(|p| p.iter().copied()).collect();
    let fit = fit_ellipse(&all)?;
    let (rms, span) = fit.rms_distance_and_span(&all);
    let (a, b) = (fit.semi_major, fit.semi_minor);
    if !(rms <= 0.15 * a && b >= PIECED_ROUNDNESS * a && span?.sweep > 1.5 * std::f64::consts::PI) {
        return None;
    }
    let (u, v) = (fit.major_axis(), fit.major_axis().perp());
    let round_a_tip = |piece: &[DVec2]| {
        [1.0, -1.0].into_iter().any(|tip: f64| {
            let half = |sign: f64| {
                piece.iter().any(|p| {
                    let d = *p - fit.center;
                    let (x, y) = (tip * d.dot(u), sign * d.dot(v));
                    (0.0..=0.8 * a).contains(&x) && y >= 0.5 * b
                })
            };
            half(1.0) && half(-1.0)
        })
    };
    pieces.iter().any(|piece| round_a_tip(piece)).then_some(fit)
}

/// The direction along the spine at a front arc: across its principal direction (the
/// arc's extent is the end circle's diameter, across the spine), signed like `tau`.
fn across_of(points: &[DVec2], tau: DVec2) -> DVec2 {
    let Some(line) = fit_line(points) else {
        return tau;
    };
    let t = line.direction.perp();
    if t.dot(tau) < 0.0 {
        -t
    } else {
        t
    }
}

/// A reading of the drawing: medial samples (midpoint, half-width), the strokes to fit
/// to (see [`Start`]), the strokes read as the tube's outlines, and the pieces of those
/// strokes that are not (the end arc of a U drawn down one outline and up the other, see
/// [`turns`]), with their strokes' classes.
type Reading = (
    Vec<(DVec2, f64)>,
    Option<Clipped>,
    Vec<StrokeId>,
    Vec<(Vec<DVec2>, StrokeClass)>,
);

/// A stroke whose samples near the drop found a partner across the tube at least this
/// often is one of the tube's outlines, whatever its class (see [`medial::paired_shares`]).
const OUTLINE_SHARE: f64 = 0.5;

/// Whether a stroke classified a feature may still be one of a tube's outlines, in the
/// context of the drop `drop` with radius about `r`: it is open (an end ellipse is drawn
/// round) and runs with the drop (its principal direction within 45° of the drop's) over
/// at least half the drop's length and one and a half tube widths. A bent outline is often
/// classified a feature arc; an end ellipse or arc runs across the tube or is shorter.
fn runs_along(points: &[DVec2], drop: [DVec2; 2], r: f64) -> bool {
    let (Some(first), Some(last), Some(line)) = (points.first(), points.last(), fit_line(points))
    else {
        return false;
    };
    let axis = (drop[1] - drop[0]).normalize_or(DVec2::Y);
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let x = (*p - line.centroid).dot(line.direction);
            (lo.min(x), hi.max(x))
        });
    let extent = hi - lo;
    first.distance(*last) > 0.4 * extent
        && line.direction.dot(axis).abs() >= std::f64::consts::FRAC_1_SQRT_2
        && extent > (3.0 * r).max(0.5 * drop[0].distance(drop[1]))
}

/// The drawing a tube is fitted to when its outlines stop at junctions (see [`Start`]).
type Clipped = (SnapContext, SnapContext, Vec<medial::Wall>);

/// Medial samples (midpoint, half-width) of the tube dropped from `first` to `last` with
/// radius about `r` (see [`medial`]): the outlines near the drop (see the module docs)
/// are paired within `reach` of its centre, the pairs grouped into chains, the chains cut
/// at their junctions, and the piece nearest the drop kept with its continuations. With
/// them, the drawing with the tube's outlines clipped where they stop at a junction
/// (`None` when none does), so that its fit does not run on along them into the part
/// beyond, and the strokes read as the outlines.
fn medial_axis(context: &SnapContext, drop: [DVec2; 2], reach: f64, r: f64) -> Vec<Reading> {
    let center = (drop[0] + drop[1]) / 2.0;
    let indices: Vec<usize> = (0..context.strokes.len())
        .filter(|i| {
            let s = &context.strokes[*i];
            // The bounds first: a stroke whose bounds lie beyond `reach` has no point
            // within it.
            let (lo, hi) = s.bounds;
            s.points.len() >= 2
                && center.clamp(lo, hi).distance(center) <= reach
                && s.points.iter().any(|p| p.distance(center) <= reach)
                && (s.class == StrokeClass::Silhouette || runs_along(&s.points, drop, r))
        })
        .collect();
    let Outlines {
        runs,
        samples,
        ids: outline_ids,
        loose,
    } = outlines_near(context, &indices, center, reach, r);
    let all: Vec<(DVec2, f64)> = samples.iter().map(|m| (m.at, m.half)).collect();
    let chains = medial::chains(samples);
    let pieces = medial::cut_at_junctions(&chains, drop);
    let tube = medial::tube_of(&pieces, drop);
    if tube.stops.is_empty() {
        // No junction: every pair near the drop is read together (a hand's outline that
        // breaks up or wanders off its partner for a stretch breaks the chains).
        return vec![(all, None, outline_ids, loose)];
    }
    let mut clipped = context.clone();
    // The stops on each stroke, at arc lengths along the whole stroke.
    let stops: Vec<medial::Stop> = tube
        .stops
        .iter()
        .map(|s| medial::Stop {
            stroke: runs[s.stroke].0,
            inside: s.inside + runs[s.stroke].2,
            ..*s
        })
        .collect();
    for index in &indices {
        let mine: Vec<&medial::Stop> = stops.iter().filter(|s| s.stroke == *index).collect();
        if mine.is_empty() {
            continue;
        }
        let stroke = &mut clipped.strokes[*index];
        if let Some(points) = medial::clipped(&stroke.points, &mine)
            && let Some(s) = prepare(stroke.id, points, stroke.class)
        {
            *stroke = s;
        }
    }
    // Other strokes drawn on across the part the tube meets (an outline drawn in two
    // strokes, the second running on past the junction) stop there too.
    let own: Vec<usize> = stops.iter().map(|s| s.stroke).collect();
    for (i, stroke) in clipped.strokes.iter_mut().enumerate() {
        if own.contains(&i) || stroke.class != StrokeClass::Silhouette {
            continue;
        }
        for wall in &tube.walls {
            if let Some(points) = medial::trimmed(&stroke.points, wall) {
                match prepare(stroke.id, points, stroke.class) {
                    Some(s) => *stroke = s,
                    // Nothing left on the tube's side: the stroke is the other part's.
                    None => stroke.points.clear(),
                }
            }
        }
    }
    // The parts the tube meets at its junctions cross it: their outlines are none of
    // its own (nor its end ellipses).
    let across: Vec<_> = tube
        .across
        .iter()
        .map(|k| context.strokes[runs[*k].0].id)
        .collect();
    clipped
        .strokes
        .retain(|s| !across.contains(&s.id) && s.points.len() >= 2);
    let clipped = SnapContext::of(clipped.strokes);
    let mut whole = context.clone();
    whole.strokes.retain(|s| !across.contains(&s.id));
    whole.pieces.retain(|s| !across.contains(&s.id));
    vec![(
        tube.samples,
        Some((clipped, whole, tube.walls)),
        outline_ids,
        loose,
    )]
}

/// The outlines a tube's medial axis is read from (see [`outlines_near`]).
struct Outlines {
    /// The strokes' runs (see [`turns`]): per run, the stroke's index, its points and
    /// the arc length along the stroke where it starts.
    runs: Vec<(usize, std::ops::Range<usize>, f64)>,
    /// The medial samples; their pairs index `runs`.
    samples: Vec<medial::Medial>,
    /// The strokes read as the tube's outlines.
    ids: Vec<StrokeId>,
    /// The runs of those strokes that are not outlines (a U's end), with their class.
    loose: Vec<(Vec<DVec2>, StrokeClass)>,
}

/// The medial samples of the strokes `indices` near `center` for a tube of radius about
/// `r`, the strokes that are its outlines and the pieces of them that are not.
fn outlines_near(
    context: &SnapContext,
    indices: &[usize],
    center: DVec2,
    reach: f64,
    r: f64,
) -> Outlines {
    // Each stroke in runs cut at its sharp turns (see `turns`): a U drawn down one
    // outline, round the end and up the other pairs with itself, and its end is read.
    // Per run: the stroke's index, its points, and the arc length where it starts.
    let runs: Vec<(usize, std::ops::Range<usize>, f64)> = indices
        .iter()
        .flat_map(|i| {
            let points = &context.strokes[*i].points;
            turns::u_runs(points, r, WIDTHS)
                .into_iter()
                .map(move |range| {
                    let offset = points[..=range.start]
                        .windows(2)
                        .map(|w| w[0].distance(w[1]))
                        .sum::<f64>();
                    (*i, range, offset)
                })
        })
        .collect();
    let outlines: Vec<&[DVec2]> = runs
        .iter()
        .map(|(i, range, _)| &context.strokes[*i].points[range.clone()])
        .collect();
    let mut samples = medial::medial_samples(&outlines, center, reach, r, WIDTHS);
    // A feature stroke is overruled as an outline only across a silhouette: two features
    // side by side are more likely the halves of one end ellipse than a tube.
    let silhouette = |k: usize| context.strokes[runs[k].0].class == StrokeClass::Silhouette;
    samples.retain(|m| silhouette(m.pair.0) || silhouette(m.pair.1));
    let shares = medial::paired_shares(&outlines, center, reach, &samples);
    let mut ids: Vec<StrokeId> = Vec::new();
    for ((i, _, _), share) in runs.iter().zip(&shares) {
        let id = context.strokes[*i].id;
        if *share >= OUTLINE_SHARE && !ids.contains(&id) {
            ids.push(id);
        }
    }
    let split = |i: usize| runs.iter().filter(|(j, ..)| *j == i).count() > 1;
    let loose: Vec<(Vec<DVec2>, StrokeClass)> = runs
        .iter()
        .zip(&shares)
        .filter(|((i, ..), share)| {
            **share < OUTLINE_SHARE && split(*i) && ids.contains(&context.strokes[*i].id)
        })
        .map(|((i, range, _), _)| {
            let stroke = &context.strokes[*i];
            (stroke.points[range.clone()].to_vec(), stroke.class)
        })
        .collect();
    Outlines {
        runs,
        samples,
        ids,
        loose,
    }
}

/// A whole ellipse (a free fit) to a stroke drawn all round it: (ellipse, true), or
/// `None` when the stroke is no whole ellipse. A stroke drawn round ends near where it
/// began (a hand misses or overlaps by a little), a front arc ends a diameter away from
/// its start; a free fit to a front arc often finds a larger, flatter ellipse that the
/// arc wraps most of the way round, so its sweep does not tell.
fn whole_ellipse(points: &[DVec2]) -> Option<(Ellipse2, bool)> {
    let (first, last) = (*points.first()?, *points.last()?);
    let (lo, hi) = points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    if first.distance(last) > 0.4 * lo.distance(hi) {
        return None;
    }
    let fit = fit_ellipse(points)?;
    let sweep = fit.angular_span(points).map_or(0.0, |s| s.sweep);
    (sweep > 1.5 * std::f64::consts::PI && fit.semi_minor.is_finite()).then_some((fit, true))
}

/// The half ellipse with its minor axis along `tau` that a front arc draws: it runs from
/// one end of the major axis to the other, so the major axis is the arc's extent across
/// the spine, and q − q₀ = c·√(1 − (p − p₀)²/A²) is fitted linearly for q₀ and c = ±B.
/// (ellipse, false).
fn front_arc(points: &[DVec2], at: DVec2, tau: DVec2) -> Option<(Ellipse2, bool)> {
    let across = tau.perp();
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let x = (*p - at).dot(across);
            (lo.min(x), hi.max(x))
        });
    let (x0, semi) = (f64::midpoint(lo, hi), (hi - lo) / 2.0);
    if !(semi > 0.0) {
        return None;
    }
    let rows: Vec<DVec2> = points
        .iter()
        .map(|p| {
            let d = *p - at;
            let x = (d.dot(across) - x0) / semi;
            DVec2::new((1.0 - x * x).max(0.0).sqrt(), d.dot(tau))
        })
        .collect();
    let (y0, c) = linear(&rows)?;
    let fit = Ellipse2 {
        center: at + across * x0 + tau * y0,
        semi_major: semi,
        semi_minor: c.abs(),
        angle: across.y.atan2(across.x),
    };
    (fit.semi_minor > 0.0).then_some((fit, false))
}

/// A starting BGC read off the drawing, and the drawing to fit it to: `None` for the
/// whole drawing, or the drawing with the tube's outlines clipped where they stop at a
/// junction (see [`medial`]) and the one to name its strokes in.
pub(crate) struct Start {
    /// The starting pose.
    pose: Primitive,
    /// The strokes to fit it to, when not all of the drawing's: the tube's outlines
    /// clipped at its junctions, the drawing without the outlines of the parts it meets
    /// there (whose strokes the result names), and the far sides of those junctions.
    context: Option<Clipped>,
    /// Whether this is the start before it with its spine drawn through the drawn ends
    /// (see `ProjectedSpine::through_ends`): the same reading, told apart only where the
    /// strokes clearly prefer it (see `snap::bgc_candidates`).
    variant: bool,
}

impl Start {
    /// Whether this start is a variant of the one before it (see [`Start::variant`]).
    pub(crate) fn is_variant(&self) -> bool {
        self.variant
    }
}

/// The starting BGCs for the dropped `primitive`, best first, each variant after the
/// start it varies, or none (see the module docs).
pub(crate) fn starts(context: &SnapContext, primitive: &Primitive) -> Vec<Start> {
    starting_poses(context, primitive).unwrap_or_default()
}

fn starting_poses(context: &SnapContext, primitive: &Primitive) -> Option<Vec<Start>> {
    let Primitive::Bgc(dropped) = primitive else {
        return None;
    };
    let k = dropped.spine.len();
    // Only a straight drop (as the palette or a script places one) is replaced: a bent
    // BGC, such as an earlier fit, snaps from itself.
    let straight = is_straight(dropped);
    if !straight {
        return None;
    }
    let first = dropped.spine.first()?.truncate();
    let last = dropped.spine.last()?.truncate();
    let length = first.distance(last);
    let r = dropped.radii.iter().sum::<f64>() / k as f64;
    if !(length > 0.0 && r > 0.0) {
        return None;
    }
    let readings = medial_axis(context, [first, last], length + 3.0 * r, r);
    let mut starts: Vec<Start> = Vec::new();
    for (medial, clipped, outlines, loose) in readings {
        let poses = pose_from(context, dropped, &medial, &outlines, &loose).unwrap_or_default();
        for (i, pose) in poses.into_iter().enumerate() {
            starts.push(Start {
                pose,
                context: clipped.clone(),
                variant: i > 0,
            });
        }
    }
    Some(starts)
}

/// The starting BGCs for `dropped` from the medial samples `medial` of its outlines (see
/// the module docs): the spine through the medial axis, then, where the drawn ends
/// show their tangents, the spine through them as well.
fn pose_from(
    context: &SnapContext,
    dropped: &Bgc,
    medial: &[(DVec2, f64)],
    outlines: &[StrokeId],
    loose: &[(Vec<DVec2>, StrokeClass)],
) -> Option<Vec<Primitive>> {
    let k = dropped.spine.len();
    let first = dropped.spine.first()?.truncate();
    let last = dropped.spine.last()?.truncate();
    let axis = (last - first).normalize_or(DVec2::Y);
    let length = first.distance(last);
    let r = dropped.radii.iter().sum::<f64>() / k as f64;
    if medial.len() < 8 {
        return None;
    }
    let points: Vec<DVec2> = medial.iter().map(|(p, _)| *p).collect();
    let (projected, local) = ProjectedSpine::fit(&points, axis)?;
    let span = local
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.x), hi.max(p.x))
        });
    let (x0, x1) = span;
    let curve = |x: f64| projected.at(x);
    let slope_dir = |x: f64| projected.tangent(x);
    // Radius profile: half-width linear in x.
    let widths: Vec<DVec2> = local
        .iter()
        .zip(medial)
        .map(|(p, (_, w))| DVec2::new(p.x, *w))
        .collect();
    let (w0, w1) = linear(&widths)?;
    let width = |x: f64| (w0 + w1 * x).max(0.2 * r);
    // End ellipses move the ends and tell the tilt.
    let [bottom, top] = end_ellipses(
        context,
        outlines,
        loose,
        [curve(x0), curve(x1)],
        [slope_dir(x0), slope_dir(x1)],
        [width(x0), width(x1)],
    );
    // The spine through the medial axis alone, and through the drawn ends as well (see
    // `ProjectedSpine::through_ends`: the medial axis runs out before the ends, most of
    // all where they are drawn off square): the snaps of both compete.
    let ends = [bottom.as_ref(), top.as_ref()];
    let depth = dropped.spine.iter().map(|q| q.z).sum::<f64>() / k as f64;
    let through = projected.through_ends(&local, ends);
    let mut poses = Vec::new();
    for spine in [Some(&projected), through.as_ref()].into_iter().flatten() {
        let to_x = |p: DVec2| spine.x_of(p);
        let (mut x0, mut x1) = span;
        if let Some((e, _)) = &bottom {
            x0 = to_x(e.center);
        }
        if let Some((e, _)) = &top {
            x1 = to_x(e.center);
        }
        if !(x1 - x0 > 0.1 * length) {
            continue;
        }
        let rows = tilt_rows(
            bottom.as_ref(),
            top.as_ref(),
            [spine.tangent(x0), spine.tangent(x1)],
        );
        let tilt = plane_tilt(&rows);
        let points = spine.lifted((x0, x1), depth, tilt, k);
        let mut radii: Vec<f64> = points.iter().map(|p| width(to_x(p.truncate()))).collect();
        if let Some((e, _)) = &bottom {
            radii[0] = f64::midpoint(radii[0], e.semi_major);
        }
        if let Some((e, _)) = &top {
            radii[k - 1] = f64::midpoint(radii[k - 1], e.semi_major);
        }
        let mut bgc = Bgc::through(points, r);
        bgc.radii = radii;
        bgc.plane_normal = DVec3::new(-tilt.x, -tilt.y, 1.0).normalize();
        let pose = Primitive::Bgc(bgc);
        if pose.is_finite() {
            poses.push(pose);
        }
    }
    Some(poses)
}

/// The projected spine of a BGC in its principal frame: a cubic
/// y = c₀ + c₁·x + c₂·x² + c₃·x³, x along `dir` from `origin` and y along `normal`.
struct ProjectedSpine {
    origin: DVec2,
    dir: DVec2,
    normal: DVec2,
    coef: [f64; 4],
}

impl ProjectedSpine {
    /// The projected spine through the medial points `points`, in the frame of their
    /// principal line (its direction signed like `axis`), with the points in that frame;
    /// `None` when no line or curve fits them.
    fn fit(points: &[DVec2], axis: DVec2) -> Option<(Self, Vec<DVec2>)> {
        let line = fit_line(points)?;
        let mut dir = line.direction;
        if dir.dot(axis) < 0.0 {
            dir = -dir;
        }
        let normal = dir.perp();
        let origin = line.centroid;
        let local: Vec<DVec2> = points
            .iter()
            .map(|p| DVec2::new((*p - origin).dot(dir), (*p - origin).dot(normal)))
            .collect();
        let coef = spine_curve(&local)?;
        let spine = Self {
            origin,
            dir,
            normal,
            coef,
        };
        Some((spine, local))
    }

    /// The spine refitted to the medial points `local` (in its frame) and to the drawn
    /// end ellipses `ends` (bottom, top): a cubic by weighted least squares that runs
    /// through each end's centre and leaves it along the end's minor axis, where the
    /// ellipse is flat enough to show it (minor/major at most 0.8) and the axis lies
    /// within 75° of the frame's direction (the cubic is a graph over it). Each end's
    /// rows weigh as much as all the medial points together. `None` where no end shows
    /// its direction: the refit would be the medial spine again.
    fn through_ends(&self, local: &[DVec2], ends: [Option<&(Ellipse2, bool)>; 2]) -> Option<Self> {
        let to_local = |p: DVec2| {
            DVec2::new(
                (p - self.origin).dot(self.dir),
                (p - self.origin).dot(self.normal),
            )
        };
        let centres: Vec<DVec2> = ends
            .iter()
            .flatten()
            .map(|(e, _)| to_local(e.center))
            .collect();
        let scale = local
            .iter()
            .chain(&centres)
            .fold(0.0f64, |m, p| m.max(p.x.abs()))
            .max(1e-300);
        let at = |x: f64| {
            let x = x / scale;
            [1.0, x, x * x, x * x * x]
        };
        let mut rows: Vec<([f64; 4], f64, f64)> =
            local.iter().map(|p| (at(p.x), p.y, 1.0)).collect();
        let weight = (local.len() as f64).sqrt();
        let mut any = false;
        for ((e, _), c) in ends.into_iter().flatten().zip(&centres) {
            rows.push((at(c.x), c.y, weight));
            if e.semi_minor <= 0.8 * e.semi_major {
                let m = e.minor_axis();
                let (along, across) = (m.dot(self.dir), m.dot(self.normal));
                if along.abs() >= 0.25 {
                    // dy/dx in units of length (× scale): Σ k·C_k·X^(k−1).
                    let x = c.x / scale;
                    rows.push((
                        [0.0, 1.0, 2.0 * x, 3.0 * x * x],
                        across / along * scale,
                        weight,
                    ));
                    any = true;
                }
            }
        }
        if !any {
            return None;
        }
        let mut coef = weighted_cubic(&rows)?;
        let mut power = 1.0;
        for ck in &mut coef {
            *ck /= power;
            power *= scale;
        }
        Some(Self { coef, ..*self })
    }

    /// The image point of the spine at `x`.
    fn at(&self, x: f64) -> DVec2 {
        let (origin, dir, normal, coef) = (self.origin, self.dir, self.normal, self.coef);
        origin + dir * x + normal * (coef[0] + x * (coef[1] + x * (coef[2] + x * coef[3])))
    }

    /// The unit image tangent of the spine at `x`.
    fn tangent(&self, x: f64) -> DVec2 {
        let (dir, normal, coef) = (self.dir, self.normal, self.coef);
        (dir + normal * (coef[1] + x * (2.0 * coef[2] + 3.0 * x * coef[3]))).normalize()
    }

    /// The frame's x of the image point `p`.
    fn x_of(&self, p: DVec2) -> f64 {
        (p - self.origin).dot(self.dir)
    }

    /// The spine between `x0` and `x1` (`span`) lifted onto the plane through its middle at
    /// `depth` with depth gradient `tilt`, resampled evenly in 3D to `k` points.
    fn lifted(&self, span: (f64, f64), depth: f64, tilt: DVec2, k: usize) -> Vec<DVec3> {
        let (x0, x1) = span;
        let mid = self.at(f64::midpoint(x0, x1));
        // Lift onto the plane, then resample evenly in 3D.
        let lifted: Vec<DVec3> = (0..=DENSE)
            .map(|i| {
                let p = self.at(x0 + (x1 - x0) * i as f64 / DENSE as f64);
                DVec3::new(p.x, p.y, depth + tilt.dot(p - mid))
            })
            .collect();
        resample(&lifted, k)
    }
}

/// Snaps a starting pose: fitted to its own strokes (see [`Start`]), then assigned the
/// drawing's strokes as they are (whole or in pieces, but for the outlines of the parts
/// it meets at its junctions) at the tight gate, so that the result names them, unless
/// that loses strokes the fit needs.
pub(crate) fn snap_start(
    context: &SnapContext,
    start: &Start,
    settings: &SnapSettings,
    solve: SolveContext<'_>,
) -> Result<SnapResult, SnapError> {
    let Some((clipped, whole, walls)) = &start.context else {
        return super::snap_rounds(context, &start.pose, settings, None, solve);
    };
    let mut result = super::snap_rounds(clipped, &start.pose, settings, None, solve)?;
    let tight = settings.tight_gate * result.primitive.size();
    let curves = result.primitive.current_shape().curves;
    let mut named = super::assign::assign_within(whole, &curves, tight, true);
    within_walls(&mut named, whole, walls);
    if super::check_enough(&result.primitive, &named).is_ok() {
        result.rms = super::fit_rms(&result.primitive, &named);
        result.assignment = named;
    }
    Ok(result)
}

/// Drops from `assignment` the stroke samples beyond the junctions' `walls` (an outline
/// drawn on across the part the tube meets is the tube's only up to the junction): a
/// stroke taken whole becomes a piece of it.
fn within_walls(assignment: &mut Assignment, context: &SnapContext, walls: &[medial::Wall]) {
    for curve in &mut assignment.curves {
        for taken in curve.iter_mut() {
            let Some(stroke) = context.strokes.iter().find(|s| s.id == taken.stroke) else {
                continue;
            };
            let samples = stroke_samples(stroke);
            let indices: Vec<usize> = taken
                .part
                .clone()
                .unwrap_or_else(|| (0..samples.len()).collect());
            let kept: Vec<usize> = indices
                .iter()
                .copied()
                .filter(|i| {
                    samples
                        .get(*i)
                        .is_some_and(|p| !walls.iter().any(|w| w.beyond(*p)))
                })
                .collect();
            if kept.len() < indices.len() {
                taken.samples = kept.iter().map(|i| samples[*i]).collect();
                taken.part = Some(kept);
            }
        }
        curve.retain(|taken| taken.samples.len() >= 2);
    }
}

/// The gradient tolerance of a BGC's fit, in the normalised frame (objective values are
/// squared fractions of the size, below 1, where the solver's relative tolerance is an
/// absolute one).
const GRADIENT_TOL: f64 = 3e-4;

/// The constraint tolerance of a BGC's fit: its constraints are bounds that keep it
/// sane (a positive radius, a moderate turn), met to a millionth of its size.
const CONSTRAINT_TOL: f64 = 1e-4;

/// The settings of a BGC's snap: `settings` with the solver's gradient tolerance no
/// tighter than [`GRADIENT_TOL`].
pub(crate) fn settings(settings: &SnapSettings) -> SnapSettings {
    let mut s = settings.clone();
    if s.solver.gradient_tol() < GRADIENT_TOL
        && let Ok(solver) = s.solver.clone().with_gradient_tol(GRADIENT_TOL)
    {
        s.solver = solver;
    }
    if s.solver.constraint_tol() < CONSTRAINT_TOL
        && let Ok(solver) = s.solver.clone().with_constraint_tol(CONSTRAINT_TOL)
    {
        s.solver = solver;
    }
    s
}

/// `k` points evenly spaced by arc length along a polyline of at least two points.
fn resample(points: &[DVec3], k: usize) -> Vec<DVec3> {
    let mut cumulative = vec![0.0];
    for w in points.windows(2) {
        cumulative.push(cumulative[cumulative.len() - 1] + w[0].distance(w[1]));
    }
    let n = points.len() - 1;
    let total = cumulative[n];
    (0..k)
        .map(|i| {
            let s = total * i as f64 / (k - 1) as f64;
            let j = cumulative.partition_point(|c| *c < s).clamp(1, n);
            let seg = cumulative[j] - cumulative[j - 1];
            let t = if seg > 0.0 {
                (s - cumulative[j - 1]) / seg
            } else {
                0.0
            };
            points[j - 1].lerp(points[j], t)
        })
        .collect()
}

/// Whether a BGC's spine is a straight line (as dropped).
fn is_straight(b: &Bgc) -> bool {
    let (first, last) = (b.spine[0], b.spine[b.spine.len() - 1]);
    let chord = (last - first).normalize_or_zero();
    b.spine.iter().all(|p| {
        let d = *p - first;
        (d - chord * d.dot(chord)).length() <= 1e-9 * b.spine_length()
    })
}

/// The rows (projected end tangent, dz/ds) of [`plane_tilt`] from the end ellipses,
/// with `along` the projected spine's directions at its two ends (bottom to top).
fn tilt_rows(
    bottom: Option<&(Ellipse2, bool)>,
    top: Option<&(Ellipse2, bool)>,
    along: [DVec2; 2],
) -> Vec<(DVec2, f64)> {
    // Slopes dz/ds along the projected end tangents (bottom to top).
    let slope = |e: &Ellipse2, outward_up: bool| {
        let z = (e.semi_minor / e.semi_major).clamp(0.12, 0.94);
        let g = z / (1.0 - z * z).sqrt();
        if outward_up {
            g
        } else {
            -g
        }
    };
    // The projected end tangent: the ellipse's minor axis, unless it is nearly a circle.
    let end_dir = |e: &Ellipse2, along: DVec2| {
        let m = e.minor_axis();
        if e.semi_minor > 0.8 * e.semi_major {
            along
        } else if m.dot(along) < 0.0 {
            -m
        } else {
            m
        }
    };
    let mut rows: Vec<(DVec2, f64)> = Vec::new();
    if let Some((e, whole)) = bottom {
        // The bottom's outward normal is −t₀: whole (faces the viewer) means t₀.z < 0.
        rows.push((end_dir(e, along[0]), slope(e, !*whole)));
    }
    if let Some((e, whole)) = top {
        rows.push((end_dir(e, along[1]), slope(e, *whole)));
    }
    rows
}

/// The plane's gradient (a, b) with (a, b)·τᵢ = gᵢ for rows (τᵢ, gᵢ), least squares with
/// a small pull towards zero.
fn plane_tilt(rows: &[(DVec2, f64)]) -> DVec2 {
    let lambda = 0.05;
    let (mut m00, mut m01, mut m11, mut v0, mut v1) = (lambda, 0.0, lambda, 0.0, 0.0);
    for (t, g) in rows {
        m00 += t.x * t.x;
        m01 += t.x * t.y;
        m11 += t.y * t.y;
        v0 += t.x * g;
        v1 += t.y * g;
    }
    let det = m00 * m11 - m01 * m01;
    let tilt = DVec2::new(m11 * v0 - m01 * v1, m00 * v1 - m01 * v0) / det;
    // At most 70° out of the view plane.
    let limit = 70f64.to_radians().tan();
    if tilt.length() > limit {
        tilt * (limit / tilt.length())
    } else {
        tilt
    }
}

/// The projected spine over its chord: a quadratic (a C), or a cubic when that fits the
/// medial samples at least twice as closely (an S: it bends one way, then the other); a
/// cubic's freedom would otherwise bend a C's noisy ends.
fn spine_curve(points: &[DVec2]) -> Option<[f64; 4]> {
    let rss = |c: &[f64; 4]| {
        points
            .iter()
            .map(|p| (p.y - (c[0] + p.x * (c[1] + p.x * (c[2] + p.x * c[3])))).powi(2))
            .sum::<f64>()
    };
    let three = polynomial::<4>(points)?;
    let two = polynomial::<3>(points).map(|c| [c[0], c[1], c[2], 0.0]);
    match two {
        Some(two) if rss(&three) >= 0.5 * rss(&two) => Some(two),
        _ => Some(three),
    }
}

/// Least-squares y = c₀ + c₁·x + … + c_{N−1}·x^{N−1} (x rescaled to [−1, 1] for the
/// normal equations' conditioning).
fn polynomial<const N: usize>(points: &[DVec2]) -> Option<[f64; N]> {
    let scale = points
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()))
        .max(1e-300);
    let mut a = [[0.0; N]; N];
    let mut b = [0.0; N];
    for p in points {
        let x = p.x / scale;
        let mut row = [1.0; N];
        for k in 1..N {
            row[k] = row[k - 1] * x;
        }
        for i in 0..N {
            for j in 0..N {
                a[i][j] += row[i] * row[j];
            }
            b[i] += row[i] * p.y;
        }
    }
    let mut c = solve(a, b)?;
    let mut power = 1.0;
    for ck in &mut c {
        *ck /= power;
        power *= scale;
    }
    Some(c)
}

/// Weighted least squares over rows (basis values for c₀ … c₃ at a point, target,
/// weight), solved with x rescaled for conditioning.
fn weighted_cubic(rows: &[([f64; 4], f64, f64)]) -> Option<[f64; 4]> {
    let mut a = [[0.0; 4]; 4];
    let mut b = [0.0; 4];
    for (row, y, w) in rows {
        let w2 = w * w;
        for i in 0..4 {
            for j in 0..4 {
                a[i][j] += w2 * row[i] * row[j];
            }
            b[i] += w2 * row[i] * y;
        }
    }
    solve(a, b)
}

/// Least-squares y = c₀ + c₁·x.
fn linear(points: &[DVec2]) -> Option<(f64, f64)> {
    let n = points.len() as f64;
    let mean = points.iter().copied().sum::<DVec2>() / n;
    let sxx: f64 = points.iter().map(|p| (p.x - mean.x).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.x - mean.x) * (p.y - mean.y)).sum();
    let c1 = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    Some((mean.y - c1 * mean.x, c1)).filter(|(a, b)| a.is_finite() && b.is_finite())
}

/// Solves a small linear system by Gaussian elimination with partial pivoting.
fn solve<const N: usize>(mut a: [[f64; N]; N], mut b: [f64; N]) -> Option<[f64; N]> {
    let scale = a
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    for col in 0..N {
        let pivot = (col..N).max_by(|i, j| a[*i][col].abs().total_cmp(&a[*j][col].abs()))?;
        if !(a[pivot][col].abs() > 1e-12 * scale) {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let pivot_row = a[col];
        for row in col + 1..N {
            let f = a[row][col] / pivot_row[col];
            for (value, p) in a[row].iter_mut().zip(&pivot_row).skip(col) {
                *value -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; N];
    for row in (0..N).rev() {
        let tail: f64 = (row + 1..N).map(|j| a[row][j] * x[j]).sum();
        x[row] = (b[row] - tail) / a[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A C-shaped tube of radius 10 round (0, 0): its spine runs on the circle of radius
    /// 100 from −50° to 50°; per stroke (points, drawn as an outline). The outlines are
    /// the arcs of radius 90 and 110; the bottom end is drawn as a front arc, the top end
    /// as a whole ellipse, both 10 across and 4 along the spine (the tube leaves the view
    /// plane there).
    fn c_tube() -> Vec<(Vec<DVec2>, bool)> {
        let arc = |radius: f64| -> Vec<DVec2> {
            (0..=50)
                .map(|i| {
                    let a = (-50.0 + 2.0 * f64::from(i)).to_radians();
                    DVec2::new(radius * a.cos(), radius * a.sin())
                })
                .collect()
        };
        let end = |degrees: f64, whole: bool| -> Vec<DVec2> {
            let a = f64::to_radians(degrees);
            let (centre, across) = (
                DVec2::new(100.0 * a.cos(), 100.0 * a.sin()),
                DVec2::new(a.cos(), a.sin()),
            );
            let along = across.perp();
            let sweep = if whole {
                std::f64::consts::TAU
            } else {
                std::f64::consts::PI
            };
            (0..=24)
                .map(|i| {
                    let t = sweep * f64::from(i) / 24.0;
                    centre + across * 10.0 * t.cos() - along * 4.0 * t.sin()
                })
                .collect()
        };
        vec![
            (arc(90.0), true),
            (arc(110.0), true),
            (end(-50.0, false), false),
            (end(50.0, true), false),
        ]
    }

    /// The start for a straight drop along the tube's chord, radius 9, in a drawing of
    /// `strokes` with the given classes.
    fn start_of(strokes: &[(Vec<DVec2>, bool)], classes: &[StrokeClass]) -> Option<Bgc> {
        let context = SnapContext::new(
            strokes
                .iter()
                .zip(classes)
                .enumerate()
                .map(|(i, ((points, _), class))| (StrokeId(i as u32), points.as_slice(), *class)),
        );
        let a = 50f64.to_radians();
        let (first, last) = (
            DVec3::new(100.0 * a.cos(), -100.0 * a.sin(), 0.0),
            DVec3::new(100.0 * a.cos(), 100.0 * a.sin(), 0.0),
        );
        let spine = (0..8)
            .map(|i| first.lerp(last, f64::from(i) / 7.0))
            .collect();
        let dropped = Primitive::Bgc(Bgc::through(spine, 9.0));
        let start = starts(&context, &dropped).into_iter().next()?;
        match start.pose {
            Primitive::Bgc(b) => Some(b),
            _ => None,
        }
    }

    /// The larger out-of-view-plane component of the start's spine direction at its ends.
    fn end_tilt(b: &Bgc) -> f64 {
        let k = b.spine.len();
        let bottom = (b.spine[1] - b.spine[0]).normalize().z.abs();
        bottom.max((b.spine[k - 1] - b.spine[k - 2]).normalize().z.abs())
    }

    #[test]
    fn a_bent_tube_starts_from_its_drawn_outlines_and_ends() {
        use StrokeClass::{Feature, Silhouette};
        let b = start_of(&c_tube(), &[Silhouette, Silhouette, Feature, Feature])
            .expect("a start from the drawn tube");
        // The spine bends through the arc of radius 100, and it leaves the view plane at
        // its ends as their ellipses show (minor/major 0.4).
        let mid = b.spine[3].truncate().midpoint(b.spine[4].truncate());
        assert!((mid.length() - 100.0).abs() < 5.0, "middle at {mid}");
        assert!(end_tilt(&b) > 0.25, "end tilt {}", end_tilt(&b));
    }

    #[test]
    fn an_end_arc_classified_as_an_outline_is_still_read_as_the_end() {
        use StrokeClass::Silhouette;
        // Only one end is drawn, so only its arc can tilt the tube.
        let mut strokes = c_tube();
        strokes.truncate(3);
        let misread = start_of(&strokes, &[Silhouette; 3]).expect("a start from the drawn tube");
        assert!(
            end_tilt(&misread) > 0.25,
            "end tilt {}: the end arc was not read",
            end_tilt(&misread)
        );
        // Without its arc, the tube shows no tilt: the arc is what was read.
        strokes.truncate(2);
        let without = start_of(&strokes, &[Silhouette; 2]).expect("a start");
        assert!(end_tilt(&without) < 0.1, "end tilt {}", end_tilt(&without));
    }

    /// The arc of the top end of [`c_tube`] from parameter `from` to `to` (radians; 0 to
    /// π is its front half, π to 2π its back half).
    fn top_end_arc(from: f64, to: f64) -> Vec<DVec2> {
        let a = 50f64.to_radians();
        let (centre, across) = (
            DVec2::new(100.0 * a.cos(), 100.0 * a.sin()),
            DVec2::new(a.cos(), a.sin()),
        );
        let along = across.perp();
        (0..=16)
            .map(|i| {
                let t = from + (to - from) * f64::from(i) / 16.0;
                centre + across * 10.0 * t.cos() - along * 4.0 * t.sin()
            })
            .collect()
    }

    /// Whether the start's top end faces the viewer: its outward normal points out of
    /// the page. The view flips the sketch's y, so the top end (drawn at +50°) is the
    /// spine's first point, and its outward normal runs from the second to the first.
    fn top_faces_the_viewer(b: &Bgc) -> bool {
        (b.spine[0] - b.spine[1]).z > 0.0
    }

    #[test]
    fn an_end_drawn_whole_in_pieces_faces_the_viewer_as_one_drawn_whole() {
        use StrokeClass::{Feature, Silhouette};
        let classes = [Silhouette, Silhouette, Feature, Feature, Feature, Feature];
        let whole = start_of(&c_tube(), &classes[..4]).expect("a start");
        assert!(top_faces_the_viewer(&whole));
        // The top ellipse in three strokes with small gaps: each piece alone reads as the
        // front arc of an end facing away.
        let mut pieced = c_tube();
        pieced.truncate(3);
        for (from, to) in [(0.3, 2.3), (2.4, 4.4), (4.5, 6.2)] {
            pieced.push((top_end_arc(from, to), false));
        }
        let b = start_of(&pieced, &classes).expect("a start");
        assert!(
            top_faces_the_viewer(&b),
            "the pieces were not read as one ellipse"
        );
        // The front half of an end facing away and its hidden back half, drawn apart
        // where the visible arc turns hidden (the ends of the major axis), overshooting
        // a little as a hand does: the end still faces away.
        let mut hidden = c_tube();
        hidden.truncate(3);
        hidden.push((top_end_arc(-0.2, std::f64::consts::PI + 0.2), false));
        hidden.push((
            top_end_arc(std::f64::consts::PI, std::f64::consts::TAU),
            false,
        ));
        let b = start_of(&hidden, &classes[..5]).expect("a start");
        assert!(
            !top_faces_the_viewer(&b),
            "a hidden back half turned the end round"
        );
    }

    #[test]
    fn a_bent_outline_classified_as_a_feature_still_pairs_with_its_partner() {
        use StrokeClass::{Feature, Silhouette};
        let b = start_of(&c_tube(), &[Feature, Silhouette, Feature, Feature])
            .expect("the inner outline is overruled as an outline in the tube's context");
        let mid = b.spine[3].truncate().midpoint(b.spine[4].truncate());
        assert!((mid.length() - 100.0).abs() < 5.0, "middle at {mid}");
        // Two features side by side are not a tube on their own.
        assert!(start_of(&c_tube(), &[Feature, Feature, Feature, Feature]).is_none());
    }

    /// An S-shaped tube of radius 10 in the view plane, 300 long, whose spine turns by
    /// 60° one way and back (the tangent angle 4·60°·u·(1 − u) from its chord's, so
    /// both ends leave it 40° off the chord): its outlines (silhouettes, stopping a
    /// radius short of the ends, as a hand does), its ends drawn nearly edge-on
    /// (minor/major 0.15; the bottom whole, the top as its front arc; features), and the
    /// spine's two ends and end tangents (bottom, top), in sketch coordinates.
    fn s_tube() -> DrawnTube {
        let n: u32 = 120;
        let theta = |u: f64| 4.0 * 60f64.to_radians() * u * (1.0 - u);
        let mut spine = vec![DVec2::ZERO];
        for i in 0..n {
            let u = (f64::from(i) + 0.5) / f64::from(n);
            let last = *spine.last().unwrap_or(&DVec2::ZERO);
            spine.push(last + DVec2::from_angle(theta(u)) * (300.0 / f64::from(n)));
        }
        // Turn the chord onto +y.
        let chord = spine[spine.len() - 1] - spine[0];
        let turn = DVec2::from_angle(DVec2::Y.to_angle() - chord.to_angle());
        let spine: Vec<DVec2> = spine.iter().map(|p| turn.rotate(*p)).collect();
        let n = n as usize;
        let tangent = |i: usize| (spine[(i + 1).min(n)] - spine[i.saturating_sub(1)]).normalize();
        let outline = |side: f64| -> Vec<DVec2> {
            (n / 25..=n - n / 25)
                .map(|i| spine[i] + tangent(i).perp() * 10.0 * side)
                .collect()
        };
        let end = |i: usize, sweep: f64| -> Vec<DVec2> {
            let (across, along) = (tangent(i).perp(), tangent(i));
            (0..=24)
                .map(|j| {
                    let t = sweep * f64::from(j) / 24.0;
                    spine[i] + across * 10.0 * t.cos() + along * 1.5 * t.sin()
                })
                .collect()
        };
        let strokes = vec![
            (outline(1.0), StrokeClass::Silhouette),
            (outline(-1.0), StrokeClass::Silhouette),
            (end(0, std::f64::consts::TAU), StrokeClass::Feature),
            (end(n, -std::f64::consts::PI), StrokeClass::Feature),
        ];
        DrawnTube {
            strokes,
            ends: [spine[0], spine[n]],
            tangents: [tangent(0), tangent(n)],
        }
    }

    /// A drawn tube: its strokes with their classes, and its spine's ends and end
    /// tangents (bottom, top).
    struct DrawnTube {
        strokes: Vec<(Vec<DVec2>, StrokeClass)>,
        ends: [DVec2; 2],
        tangents: [DVec2; 2],
    }

    /// The image angle between lines along `a` and `b`, in degrees.
    fn line_angle(a: DVec2, b: DVec2) -> f64 {
        let turn = a.angle_to(b).abs();
        turn.min(std::f64::consts::PI - turn).to_degrees()
    }

    /// The projected tangent of a start's spine at its first (`last` false) or last end:
    /// the end segment turned back by half the next turn, as the model takes it.
    fn end_direction(b: &Bgc, last: bool) -> DVec2 {
        let p: Vec<DVec2> = if last {
            b.spine.iter().rev().map(|q| q.truncate()).collect()
        } else {
            b.spine.iter().map(|q| q.truncate()).collect()
        };
        let (d0, d1) = (p[1] - p[0], p[2] - p[1]);
        DVec2::from_angle(d0.to_angle() - d0.angle_to(d1) / 2.0)
    }

    #[test]
    fn a_bent_tube_leaves_its_ends_along_their_drawn_ellipses() {
        let DrawnTube {
            strokes,
            ends,
            tangents,
        } = s_tube();
        // The context takes sketch points and the view flips their y.
        let flip = |p: DVec2| DVec2::new(p.x, -p.y);
        let (ends, tangents) = (ends.map(flip), tangents.map(flip));
        let context = SnapContext::new(
            strokes
                .iter()
                .enumerate()
                .map(|(i, (points, class))| (StrokeId(i as u32), points.as_slice(), *class)),
        );
        let spine = (0..8)
            .map(|i| ends[0].lerp(ends[1], f64::from(i) / 7.0).extend(0.0))
            .collect();
        let dropped = Primitive::Bgc(Bgc::through(spine, 9.0));
        let errors: Vec<[f64; 2]> = starts(&context, &dropped)
            .iter()
            .filter_map(|s| match &s.pose {
                Primitive::Bgc(b) => Some([
                    line_angle(end_direction(b, false), tangents[0]),
                    line_angle(end_direction(b, true), tangents[1]),
                ]),
                _ => None,
            })
            .collect();
        // The medial axis runs out before the ends, so a spine fitted to it alone leaves
        // them 8° closer to the chord than drawn; one start leaves them as their
        // ellipses are drawn.
        assert!(
            errors.iter().any(|e| e[0] < 5.0 && e[1] < 5.0),
            "end tangents off by {errors:?} (degrees)"
        );
    }
}
