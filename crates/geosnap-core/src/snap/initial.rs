//! Better starting poses than the dropped one, read off the drawing near it.
//!
//! A dropped primitive has a fixed tilt, but the strokes say how the part really sits,
//! and the fit converges far more reliably from there. Four readings are made:
//! - solids of revolution, from their end ellipses ([`ends`]);
//! - solids of revolution, from their two outlines ([`outlines`]);
//! - boxes, from the directions of their drawn edges ([`box_poses`]), standing also
//!   where their own edges lie on drawn lines ([`aligned`]);
//! - spheres, from the circle their outline draws near the drop ([`sphere_poses`]).
//!
use glam::{DMat3, DQuat, DVec2, DVec3};

use super::assign::{curve_bounds, ROUGHLY_STRAIGHT};
use super::context::{SnapContext, SnapStroke};
use crate::geom::{fit_circle, Circle2};
use crate::primitive::{Cuboid, Primitive, Sphere};

mod aligned;
mod ends;
mod outlines;

pub(crate) use ends::repose_from_ellipses;

/// The starting poses worth a try besides the dropped one (none when the drawing near it
/// says nothing more).
pub(crate) fn starting_poses(context: &SnapContext, primitive: &Primitive) -> Vec<Primitive> {
    match primitive {
        Primitive::Cuboid(c) => box_poses(context, c)
            .into_iter()
            .map(Primitive::Cuboid)
            .collect(),
        Primitive::Sphere(s) => sphere_poses(context, s)
            .into_iter()
            .map(Primitive::Sphere)
            .collect(),
        _ => repose_from_ellipses(context, primitive)
            .into_iter()
            .chain(outlines::outline_poses(context, primitive))
            .collect(),
    }
}

/// The longest run of fragments [`fragment_runs`] follows.
const MAX_RUN: usize = 6;

/// Runs of strokes that continue one another, as the fragments of one curve do: an end
/// of one lies within a small gap of an end of the next (at most a third of the shorter
/// one's length and half of `radius`), and the curve carries on through the joint in
/// about the same direction (within 35°). Each end joins its nearest such partner when
/// that partner's end chooses it too. Runs of one stroke are left out.
fn fragment_runs<'a>(strokes: &[&'a SnapStroke], radius: f64) -> Vec<Vec<&'a SnapStroke>> {
    let n = strokes.len();
    // Per stroke end (2·i: its start, 2·i + 1: its end): the point and the unit
    // direction leaving the stroke there.
    let end = |k: usize| {
        let points = &strokes[k / 2].points;
        let m = points.len();
        let (p, q) = if k.is_multiple_of(2) {
            (points[0], points[(m / 5).clamp(1, m - 1)])
        } else {
            (points[m - 1], points[m - 1 - (m / 5).clamp(1, m - 1)])
        };
        (p, (p - q).normalize_or_zero())
    };
    let partner = |k: usize| {
        let (p, out) = end(k);
        (0..2 * n)
            .filter(|j| j / 2 != k / 2)
            .filter_map(|j| {
                let (q, back) = end(j);
                let gap = p.distance(q);
                let shorter = strokes[k / 2].length.min(strokes[j / 2].length);
                // Leaving one stroke along `out`, the next is entered against its own
                // leaving direction.
                let continues = out.dot(-back) >= 35f64.to_radians().cos();
                (continues && gap <= (shorter / 3.0).min(radius / 2.0)).then_some((gap, j))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, j)| j)
    };
    let link: Vec<Option<usize>> = (0..2 * n)
        .map(|k| partner(k).filter(|j| partner(*j) == Some(k)))
        .collect();
    let mut used = vec![false; n];
    let mut runs = Vec::new();
    for first in 0..n {
        if used[first] {
            continue;
        }
        // Walk back to the run's first stroke (or all the way round a closed run).
        let mut at = first;
        let mut entry = 0;
        for _ in 0..n {
            match link[2 * at + entry] {
                Some(j) if j / 2 != first => {
                    at = j / 2;
                    entry = 1 - j % 2;
                }
                _ => break,
            }
        }
        // Then forward, leaving each stroke by its other end.
        let mut run = Vec::new();
        let mut exit = 1 - entry;
        while !used[at] && run.len() < MAX_RUN {
            used[at] = true;
            run.push(strokes[at]);
            match link[2 * at + exit] {
                Some(j) => {
                    at = j / 2;
                    exit = 1 - j % 2;
                }
                None => break,
            }
        }
        if run.len() >= 2 {
            runs.push(run);
        }
    }
    runs
}

/// A solid of revolution's pose as the starting poses read and change it: centre, unit
/// axis, length and end radii (bottom, top).
pub(super) struct Revolution {
    pub(super) center: DVec3,
    pub(super) axis: DVec3,
    pub(super) length: f64,
    pub(super) radii: (f64, f64),
}

impl Revolution {
    /// The pose of `primitive`, or `None` when it is not a cylinder, cone or SGC.
    pub(super) fn of(primitive: &Primitive) -> Option<Self> {
        let (center, axis, length, radii) = match primitive {
            Primitive::Cylinder(c) => (c.center, c.axis, c.length, (c.radius, c.radius)),
            Primitive::Cone(c) => (c.center, c.axis, c.length, (c.radius_bottom, c.radius_top)),
            Primitive::Sgc(s) => (
                s.center,
                s.axis,
                s.length,
                (*s.radii.first()?, *s.radii.last()?),
            ),
            _ => return None,
        };
        Some(Self {
            center,
            axis,
            length,
            radii,
        })
    }

    /// `primitive` (of the kind [`Revolution::of`] reads) moved to this pose. An SGC keeps
    /// its drawn profile's shape between the new end radii; a cylinder takes their mean.
    pub(super) fn applied_to(&self, primitive: &Primitive) -> Option<Primitive> {
        let (rb, rt) = self.radii;
        Some(match primitive {
            Primitive::Cylinder(c) => {
                let mut c = c.clone();
                c.center = self.center;
                c.axis = self.axis;
                c.length = self.length;
                c.radius = f64::midpoint(rb, rt);
                Primitive::Cylinder(c)
            }
            Primitive::Cone(c) => {
                let mut c = c.clone();
                c.center = self.center;
                c.axis = self.axis;
                c.length = self.length;
                c.radius_bottom = rb;
                c.radius_top = rt;
                Primitive::Cone(c)
            }
            Primitive::Sgc(s) => {
                let (r_bottom, r_top) = (*s.radii.first()?, *s.radii.last()?);
                let mut s = s.clone();
                s.center = self.center;
                s.axis = self.axis;
                s.length = self.length;
                let k = s.radii.len().max(2) - 1;
                for (i, r) in s.radii.iter_mut().enumerate() {
                    let t = i as f64 / k as f64;
                    *r *= (rb * (1.0 - t) + rt * t) / (r_bottom * (1.0 - t) + r_top * t);
                }
                Primitive::Sgc(s)
            }
            _ => return None,
        })
    }
}

/// The circles a sphere's outline may draw near a drop: a centre within half the dropped
/// radius of the dropped centre and a radius within a factor 1.6 of the dropped one, as
/// a hand's rough drop misses by less.
const SPHERE_REACH: f64 = 0.5;

/// The sweep (radians) of `points` round `center`: the full turn less the widest gap
/// between their directions.
fn sweep_round(points: &[DVec2], center: DVec2) -> f64 {
    let mut angles: Vec<f64> = points
        .iter()
        .map(|p| {
            let d = *p - center;
            d.y.atan2(d.x)
        })
        .collect();
    angles.sort_by(f64::total_cmp);
    let (Some(first), Some(last)) = (angles.first(), angles.last()) else {
        return 0.0;
    };
    let wrap = first + std::f64::consts::TAU - last;
    let widest = angles.windows(2).map(|w| w[1] - w[0]).fold(wrap, f64::max);
    std::f64::consts::TAU - widest
}

/// Starting poses for a sphere, read off the circles drawn near its drop. A sphere's
/// outline is a circle whatever the view, and the hand draws it as one or a few arcs;
/// a rough drop (off by a tenth of the size, a quarter too big or small) may meet other
/// circles first: the ends of tubes joined to a ball, a neighbour's outline. So every
/// stroke near the drop, and every run of fragments ([`fragment_runs`]), that a circle
/// fits closely (RMS within 8 % of its radius, as for an end ellipse) over a fifth of a
/// turn or more proposes a circle; each circle is scored by how much of its length the
/// nearby strokes draw (samples within a tenth of the radius of it), and the best drawn
/// one is the start. A
/// start read off the drawing lands on the same outline from any drop near it.
fn sphere_poses(context: &SnapContext, dropped: &Sphere) -> Vec<Sphere> {
    let (c0, r0) = (dropped.center.truncate(), dropped.radius);
    if !(r0 > 0.0) {
        return Vec::new();
    }
    let reach = SPHERE_REACH * r0;
    let nearby: Vec<&SnapStroke> = context
        .strokes
        .iter()
        .chain(&context.pieces)
        .filter(|stroke| {
            let (lo, hi) = stroke.bounds;
            let closest = DVec2::new(c0.x.clamp(lo.x, hi.x), c0.y.clamp(lo.y, hi.y));
            stroke.points.len() >= 3 && closest.distance(c0) <= reach + 1.6 * r0
        })
        .collect();
    let mut circles: Vec<Circle2> = Vec::new();
    let mut propose = |run: &[&SnapStroke]| {
        let points: Vec<DVec2> = run.iter().flat_map(|s| s.points.iter().copied()).collect();
        let Some(circle) = fit_circle(&points) else {
            return;
        };
        let fits = circle.rms_residual <= 0.08 * circle.radius
            && circle.center.distance(c0) <= reach
            && (r0 / 1.6..=r0 * 1.6).contains(&circle.radius)
            && sweep_round(&points, circle.center) >= 0.2 * std::f64::consts::TAU;
        if fits {
            circles.push(circle);
        }
    };
    for stroke in &nearby {
        propose(std::slice::from_ref(stroke));
    }
    for run in fragment_runs(&nearby, 1.6 * r0) {
        for len in 2..=run.len() {
            for window in run.windows(len) {
                propose(window);
            }
        }
    }
    // How much of a circle the nearby strokes draw: the share of its directions (in 96
    // sectors) that a stroke sample near it covers.
    let drawn = |circle: &Circle2| {
        let mut covered = [false; 96];
        for p in nearby.iter().flat_map(|s| &s.points) {
            if circle.distance(*p) <= 0.1 * circle.radius {
                let d = *p - circle.center;
                let a = d.y.atan2(d.x) + std::f64::consts::PI;
                let k = ((a / std::f64::consts::TAU * 96.0) as usize).min(95);
                covered[k] = true;
            }
        }
        covered.iter().filter(|c| **c).count() as f64 / 96.0
    };
    circles
        .iter()
        .map(|c| (drawn(c), c))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c)| Sphere {
            center: DVec3::new(c.center.x, c.center.y, dropped.center.z),
            radius: c.radius,
        })
        .into_iter()
        .collect()
}

/// Strokes closer in direction than this (radians) belong to one edge direction.
const SAME_DIRECTION: f64 = 0.14;

/// One drawn edge line of a box direction: its extent along the direction (not a
/// stroke's length: a hand's jitter makes a polyline longer than the edge it draws) and
/// bounds. A line is one straight stroke, or several that continue one another on the
/// same line ([`drawn_lines`]): an edge drawn in fragments, or sketched twice over.
#[derive(Clone, Copy)]
struct Edge {
    extent: f64,
    bounds: (DVec2, DVec2),
}

/// A straight stroke seen along a unit direction `d`: its mean offset across `d`, its
/// interval along `d` and its bounds.
struct OnLine {
    offset: f64,
    along: (f64, f64),
    bounds: (DVec2, DVec2),
}

/// A gap along an edge line up to this share of the longer of the two pieces it
/// separates is a break in the hand's line, not the end of the edge.
const LINE_GAP: f64 = 0.25;

/// Strokes whose mean offsets across the direction differ by at most this share of the
/// direction's longest stroke lie on one line.
const LINE_OFFSET: f64 = 0.03;

/// The edge lines that straight strokes of one direction `d` draw: strokes on one line
/// (offsets within [`LINE_OFFSET`] of the longest stroke) whose intervals along it
/// overlap or leave a gap of at most [`LINE_GAP`] of the longer piece join into one line.
/// A hand draws a long edge in fragments, or twice over; the edge is the line they draw
/// together, whatever the drawing's scale.
fn drawn_lines(strokes: &[&SnapStroke], d: DVec2) -> Vec<Edge> {
    let n = d.perp();
    let mut lines: Vec<OnLine> = strokes
        .iter()
        .map(|s| {
            let (lo, hi) =
                s.points
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                        let t = p.dot(d);
                        (lo.min(t), hi.max(t))
                    });
            let offset = s.points.iter().map(|p| p.dot(n)).sum::<f64>() / s.points.len() as f64;
            OnLine {
                offset,
                along: (lo, hi),
                bounds: s.bounds,
            }
        })
        .collect();
    let longest = lines
        .iter()
        .map(|l| l.along.1 - l.along.0)
        .fold(0.0, f64::max);
    let tolerance = LINE_OFFSET * longest;
    // Join pairs until none joins: a handful of strokes per direction, so the quadratic
    // passes cost nothing.
    let mut joined = true;
    while joined {
        joined = false;
        'pairs: for i in 0..lines.len() {
            for j in i + 1..lines.len() {
                let (a, b) = (&lines[i], &lines[j]);
                if (a.offset - b.offset).abs() > tolerance {
                    continue;
                }
                let gap = a.along.0.max(b.along.0) - a.along.1.min(b.along.1);
                let piece = (a.along.1 - a.along.0).max(b.along.1 - b.along.0);
                if gap > LINE_GAP * piece {
                    continue;
                }
                let (wa, wb) = (a.along.1 - a.along.0, b.along.1 - b.along.0);
                let weight = (wa + wb).max(f64::MIN_POSITIVE);
                let merged = OnLine {
                    offset: (a.offset * wa + b.offset * wb) / weight,
                    along: (a.along.0.min(b.along.0), a.along.1.max(b.along.1)),
                    bounds: (a.bounds.0.min(b.bounds.0), a.bounds.1.max(b.bounds.1)),
                };
                lines[i] = merged;
                lines.swap_remove(j);
                joined = true;
                break 'pairs;
            }
        }
    }
    lines
        .into_iter()
        .map(|l| Edge {
            extent: l.along.1 - l.along.0,
            bounds: l.bounds,
        })
        .collect()
}

/// The three edge directions of a drawn box: groups of straight strokes by direction
/// (mod π), strongest (longest in total) first; each is (unit direction, its edge lines
/// from [`drawn_lines`]). A group takes the strokes within `absorb` times
/// [`SAME_DIRECTION`] of its strongest direction.
fn edge_directions(strokes: &[&SnapStroke], absorb: f64) -> Option<[(DVec2, Vec<Edge>); 3]> {
    // Directions as doubled angles, so that d and −d agree.
    let angle = |s: &SnapStroke| s.direction.y.atan2(s.direction.x);
    let gap = |a: f64, b: f64| {
        let d = (a - b).rem_euclid(std::f64::consts::PI);
        d.min(std::f64::consts::PI - d)
    };
    let mut left: Vec<&SnapStroke> = strokes.to_vec();
    let mut groups = Vec::with_capacity(3);
    for _ in 0..3 {
        let support = |a: f64| -> f64 {
            left.iter()
                .filter(|s| gap(angle(s), a) <= SAME_DIRECTION)
                .map(|s| s.length)
                .sum()
        };
        let seed = left
            .iter()
            .map(|s| angle(s))
            .max_by(|a, b| support(*a).total_cmp(&support(*b)))?;
        let (members, rest): (Vec<&SnapStroke>, Vec<&SnapStroke>) = left
            .iter()
            .partition(|s| gap(angle(s), seed) <= absorb * SAME_DIRECTION);
        // The length-weighted mean direction, on doubled angles.
        let doubled = members.iter().fold(DVec2::ZERO, |acc, s| {
            let a = 2.0 * angle(s);
            acc + DVec2::new(a.cos(), a.sin()) * s.length
        });
        let a = doubled.y.atan2(doubled.x) / 2.0;
        let direction = DVec2::new(a.cos(), a.sin());
        groups.push((direction, drawn_lines(&members, direction)));
        left = rest;
    }
    groups.try_into().ok()
}

/// The orientations (mirror pair) of a box whose axes project along the unit directions
/// `d`: the 3D axes (dᵢ, wᵢ) are orthogonal when dᵢ·dⱼ + wᵢwⱼ = 0 for each pair, which
/// fixes w₁² = −(d₁·d₂)(d₁·d₃)/(d₂·d₃) and the others from it; `None` when the directions
/// cannot come from a box or an axis would lie within 8° of the view.
fn box_axes(d: [DVec2; 3]) -> Option<[[DVec3; 3]; 2]> {
    let (d12, d13, d23) = (d[0].dot(d[1]), d[0].dot(d[2]), d[1].dot(d[2]));
    if d12.abs().min(d13.abs()).min(d23.abs()) < 1e-3 {
        return None;
    }
    let w1_sq = -d12 * d13 / d23;
    if !(w1_sq > 0.0) {
        return None;
    }
    let w1 = w1_sq.sqrt();
    let w = [w1, -d12 / w1, -d13 / w1];
    // An axis within 8° of the view (|w| > cot 8° ≈ 7.1) is not seen well enough.
    if w.iter().any(|w| w.abs() > 7.1) {
        return None;
    }
    let axes = |sign: f64| [0, 1, 2].map(|i| DVec3::new(d[i].x, d[i].y, sign * w[i]).normalize());
    Some([axes(1.0), axes(-1.0)])
}

/// The sizes of a box with `axes` (labelled as the dropped box's by `perm`: its axis `j`
/// draws as edge direction `perm[j]`) and its image centre, read off the edges of each
/// direction: the longest stroke of a direction gives the size along that axis, and the
/// middle of the strokes' bounds the centre (a box's outline is symmetric about its
/// centre). A stroke more than twice as long as the dropped box's edge of that direction
/// draws something else that runs the same way (a table's leg under a thin top runs
/// along the top's thickness) and does not count, unless no stroke of the direction is
/// that short (then all count). `None` when no stroke counts.
fn sizes_and_centre(
    groups: &[(DVec2, Vec<Edge>); 3],
    axes: &[DVec3; 3],
    perm: [usize; 3],
    dropped: &Cuboid,
) -> Option<(DVec3, DVec2)> {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    let size = [0, 1, 2].map(|j| {
        let shrink = axes[perm[j]].truncate().length().max(1e-3);
        let expected = dropped.size[j] * shrink;
        let edges = &groups[perm[j]].1;
        let counted: Vec<&Edge> = edges
            .iter()
            .filter(|e| e.extent <= 2.0 * expected)
            .collect();
        // Without a stroke as short, the drop's labels did not match (its edge of that
        // direction is another one): all count.
        let counted = if counted.is_empty() {
            edges.iter().collect()
        } else {
            counted
        };
        let mut longest: f64 = 0.0;
        for edge in counted {
            longest = longest.max(edge.extent);
            lo = lo.min(edge.bounds.0);
            hi = hi.max(edge.bounds.1);
        }
        longest / shrink
    });
    lo.cmple(hi)
        .all()
        .then(|| (DVec3::from_array(size), (lo + hi) / 2.0))
}

/// The strokes that `keep` accepts lying wholly within the image bounds of `dropped`'s
/// curves grown by `margin` on every side: the strokes a start read off the drawing
/// near a drop may use.
pub(super) fn strokes_near<'a>(
    context: &'a SnapContext,
    dropped: &Primitive,
    margin: f64,
    keep: impl Fn(&SnapStroke) -> bool,
) -> Vec<&'a SnapStroke> {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for c in &dropped.current_shape().curves {
        let (clo, chi) = curve_bounds(&c.curve);
        lo = lo.min(clo);
        hi = hi.max(chi);
    }
    let (lo, hi) = (lo - DVec2::splat(margin), hi + DVec2::splat(margin));
    let inside = |p: &DVec2| p.x >= lo.x && p.y >= lo.y && p.x <= hi.x && p.y <= hi.y;
    // Whole strokes, and the pieces of those drawn round a turn (`pieces.rs`).
    context
        .strokes
        .iter()
        .chain(&context.pieces)
        .filter(|s| keep(s) && s.points.iter().all(inside))
        .collect()
}

/// Starting poses of a dropped box from the straight strokes around it: the three edge
/// directions give its orientation up to the mirror of the view (both are returned), and
/// the strokes of each direction its sizes and centre (see `sizes_and_centre`). The axes
/// are labelled and signed as the dropped box's nearest ones, so its width stays its
/// width.
pub(crate) fn box_poses(context: &SnapContext, dropped: &Cuboid) -> Vec<Cuboid> {
    let strokes = strokes_near(
        context,
        &Primitive::Cuboid(dropped.clone()),
        0.3 * dropped.size.max_element(),
        |s| s.straightness <= ROUGHLY_STRAIGHT,
    );
    // A group first takes every stroke within twice the direction tolerance, so that a
    // hand's shaky edges stay together; seen side on, two of a box's axes can draw
    // within that of each other, and only the tighter grouping tells them apart. Both
    // groupings give their poses; the fit and the explanation choose.
    let mut poses = Vec::new();
    let mut seen: Vec<[DVec2; 3]> = Vec::new();
    for absorb in ABSORB {
        let Some(groups) = edge_directions(&strokes, absorb) else {
            continue;
        };
        let directions = [0, 1, 2].map(|i| groups[i].0);
        let same =
            |d: &[DVec2; 3]| (0..3).all(|i| d[i].dot(directions[i]).abs() > SAME_DIRECTION.cos());
        if seen.iter().any(same) {
            continue;
        }
        seen.push(directions);
        poses.extend(poses_from_groups(&strokes, &groups, dropped));
    }
    poses
}

/// How widely a direction group takes strokes, in [`SAME_DIRECTION`]s: the groupings
/// [`box_poses`] reads.
const ABSORB: [f64; 2] = [2.0, 1.0];

/// The poses of a box (labelled as the dropped box) whose edges draw the direction
/// groups `groups` (see [`box_poses`]).
fn poses_from_groups(
    strokes: &[&SnapStroke],
    groups: &[(DVec2, Vec<Edge>); 3],
    dropped: &Cuboid,
) -> Vec<Cuboid> {
    let Some(orientations) = box_axes([0, 1, 2].map(|i| groups[i].0)) else {
        return Vec::new();
    };
    let dropped_axes = dropped.axes();
    orientations
        .iter()
        .filter_map(|axes| {
            // The labelling (a permutation with signs) nearest to the dropped axes.
            let perms = [
                [0, 1, 2],
                [0, 2, 1],
                [1, 0, 2],
                [1, 2, 0],
                [2, 0, 1],
                [2, 1, 0],
            ];
            let perm = perms.into_iter().max_by(|p, q| {
                let fit = |p: &[usize; 3]| -> f64 {
                    (0..3).map(|j| dropped_axes[j].dot(axes[p[j]]).abs()).sum()
                };
                fit(p).total_cmp(&fit(q))
            })?;
            let mut new_axes = [0, 1, 2].map(|j| {
                let a = axes[perm[j]];
                if a.dot(dropped_axes[j]) < 0.0 {
                    -a
                } else {
                    a
                }
            });
            // A box is its own mirror image: make the frame right-handed by turning the
            // axis least like the dropped one.
            if new_axes[0].cross(new_axes[1]).dot(new_axes[2]) < 0.0 {
                let worst = (0..3).min_by(|i, j| {
                    let fit = |k: &usize| new_axes[*k].dot(dropped_axes[*k]);
                    fit(i).total_cmp(&fit(j))
                })?;
                new_axes[worst] = -new_axes[worst];
            }
            let (size, centre) = sizes_and_centre(groups, axes, perm, dropped)?;
            let rotation =
                DQuat::from_mat3(&DMat3::from_cols(new_axes[0], new_axes[1], new_axes[2]))
                    .normalize();
            let read = Cuboid {
                center: DVec3::new(centre.x, centre.y, dropped.center.z),
                rotation,
                size,
            };
            // The strokes' bounds take in whatever else runs the box's ways nearby (a
            // pipe's outlines): the same box at the drop's centre is tried too, when the
            // two differ by more than a tenth of the box.
            let at_drop = Cuboid {
                center: dropped.center,
                ..read.clone()
            };
            let apart = read.center.truncate().distance(dropped.center.truncate());
            let mut poses = if apart > 0.1 * read.size.max_element() {
                vec![read.clone(), at_drop]
            } else {
                vec![read.clone()]
            };
            // Next to parts drawn the same way, the bounds' middle may fall between two of
            // them: the box also stands where its own edges lie on drawn lines.
            let tried: Vec<DVec2> = poses.iter().map(|p| p.center.truncate()).collect();
            if let Some(centre) =
                aligned::aligned_centre(strokes, &read, dropped.center.truncate(), &tried)
            {
                let new = poses
                    .iter()
                    .all(|p| p.center.truncate().distance(centre) > 0.02 * read.size.max_element());
                if new {
                    poses.push(Cuboid {
                        center: DVec3::new(centre.x, centre.y, dropped.center.z),
                        ..read
                    });
                }
            }
            Some(poses)
        })
        .flatten()
        .collect()
}

#[cfg(test)]
pub(super) mod tests {
    use glam::{DQuat, DVec2, DVec3};

    use super::{box_poses, fragment_runs, starting_poses};
    use crate::primitive::{Cuboid, Curve2, Primitive, Sphere};
    use crate::sketch::{StrokeClass, StrokeId};
    use crate::snap::context::SnapStroke;
    use crate::snap::SnapContext;

    /// The visible edges of `truth` as straight strokes (sketch space, y down).
    pub(in crate::snap) fn drawn(truth: &Cuboid) -> SnapContext {
        drawn_past_corners(truth, 0.0)
    }

    /// `truth`'s visible edges as strokes, each carried `past` of its length beyond both
    /// corners (a hand's overshoot).
    pub(in crate::snap) fn drawn_past_corners(truth: &Cuboid, past: f64) -> SnapContext {
        let shape = Primitive::Cuboid(truth.clone()).current_shape();
        let strokes: Vec<Vec<DVec2>> = shape
            .curves
            .iter()
            .filter(|c| c.visible)
            .filter_map(|c| match &c.curve {
                Curve2::Polyline(p) => {
                    let (a, b) = (p[0].to_dvec2(), p[1].to_dvec2());
                    let (a, b) = (a - (b - a) * past, b + (b - a) * past);
                    Some(
                        (0..=20)
                            .map(|i| {
                                let q = a.lerp(b, f64::from(i) / 20.0);
                                DVec2::new(q.x, -q.y)
                            })
                            .collect(),
                    )
                }
                Curve2::Ellipse { .. } => None,
            })
            .collect();
        SnapContext::new(
            strokes
                .iter()
                .enumerate()
                .map(|(i, s)| (StrokeId(i as u32), s.as_slice(), StrokeClass::Silhouette)),
        )
    }

    /// A box turned so that its three visible faces show.
    pub(in crate::snap) fn turned_box() -> Cuboid {
        Cuboid {
            center: DVec3::new(400.0, -300.0, 0.0),
            rotation: DQuat::from_rotation_y(0.7) * DQuat::from_rotation_x(0.45),
            size: DVec3::new(200.0, 120.0, 90.0),
        }
    }

    /// A box dropped on [`turned_box`] upright, in the palette's default orientation and
    /// size, a little off its centre.
    fn palette_drop() -> Cuboid {
        Cuboid {
            center: DVec3::new(420.0, -280.0, 0.0),
            rotation: DQuat::from_rotation_x(20f64.to_radians())
                * DQuat::from_rotation_y(-30f64.to_radians()),
            size: DVec3::new(150.0, 150.0, 150.0),
        }
    }

    #[test]
    fn a_drawn_box_gives_its_orientation_and_sizes() {
        let truth = turned_box();
        let dropped = palette_drop();
        let poses = box_poses(&drawn(&truth), &dropped);
        // The pose and its mirror image, each also at the drop's centre (the drop is more
        // than a tenth of the box from the drawn centre).
        assert_eq!(poses.len(), 4, "{poses:#?}");
        let truth_axes = truth.axes();
        // Some pose has the true axes (up to order and sign, and the view's mirror) and
        // sizes, and the true centre.
        let mirror = |v: DVec3| DVec3::new(v.x, v.y, -v.z);
        let found = poses.iter().any(|pose| {
            let axes = pose.axes();
            (0..3).all(|i| {
                (0..3).any(|j| {
                    let same = |a: DVec3| a.dot(truth_axes[j]).abs() > 0.9998;
                    (same(axes[i]) || same(mirror(axes[i])))
                        && (pose.size[i] - truth.size[j]).abs() < 0.01 * truth.size[j]
                })
            })
        });
        assert!(found, "{poses:#?}");
        let at = |centre: DVec3| {
            poses
                .iter()
                .filter(|pose| pose.center.truncate().distance(centre.truncate()) < 1e-6)
                .count()
        };
        assert_eq!((at(truth.center), at(dropped.center)), (2, 2), "{poses:#?}");
    }

    /// The poses' sizes for `truth`, read off `context` with `dropped`: per pose, each
    /// true size's relative error on the pose axis along it (the worst of the three).
    fn worst_size_error(poses: &[Cuboid], truth: &Cuboid) -> f64 {
        let mirror = |v: DVec3| DVec3::new(v.x, v.y, -v.z);
        let truth_axes = truth.axes();
        poses
            .iter()
            .map(|pose| {
                let axes = pose.axes();
                (0..3)
                    .map(|j| {
                        (0..3)
                            .filter(|i| {
                                let same = |a: DVec3| a.dot(truth_axes[j]).abs() > 0.999;
                                same(axes[*i]) || same(mirror(axes[*i]))
                            })
                            .map(|i| (pose.size[i] - truth.size[j]).abs() / truth.size[j])
                            .fold(f64::INFINITY, f64::min)
                    })
                    .fold(0.0, f64::max)
            })
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn a_box_drawn_in_fragments_or_twice_over_gives_its_sizes() {
        let truth = turned_box();
        let dropped = palette_drop();
        let whole = drawn(&truth);
        // Each edge in three pieces: a gap of 3 % of the edge, then an overlap of 2 %.
        // And each edge drawn twice, the second stroke shifted by 0.5 % of the box across
        // and covering 55 % of the edge from either end.
        let mut fragments = Vec::new();
        let mut sketchy = Vec::new();
        for stroke in &whole.strokes {
            let (a, b) = (stroke.points[0], stroke.points[stroke.points.len() - 1]);
            let piece = |from: f64, to: f64| -> Vec<DVec2> {
                (0..=10)
                    .map(|i| a.lerp(b, from + (to - from) * f64::from(i) / 10.0))
                    .collect()
            };
            fragments.extend([piece(0.0, 0.32), piece(0.35, 0.68), piece(0.66, 1.0)]);
            let shift = (b - a).perp().normalize() * 1.0;
            sketchy.push(piece(0.0, 0.55));
            sketchy.push(piece(0.45, 1.0).into_iter().map(|p| p + shift).collect());
        }
        for strokes in [fragments, sketchy] {
            assert_sizes_read(&strokes, &dropped, &truth);
        }
    }

    #[test]
    fn a_box_beside_a_twin_whose_edges_run_on_in_line_keeps_its_sizes() {
        // A row of two boxes a twentieth of a width apart: the neighbour's edges continue
        // this box's edges along the row, across a small gap.
        let truth = turned_box();
        let gap = 1.05 * truth.size.x;
        let twin = Cuboid {
            center: truth.center + truth.axes()[0] * gap,
            ..truth.clone()
        };
        let (a, b) = (drawn(&truth), drawn(&twin));
        let strokes: Vec<Vec<DVec2>> = a
            .strokes
            .iter()
            .chain(&b.strokes)
            .map(|s| s.points.clone())
            .collect();
        assert_sizes_read(&strokes, &palette_drop(), &truth);
    }

    /// Asserts that some box pose read off `strokes` (in the view plane, y up) for
    /// `dropped` has the sizes of `truth` within 2 %.
    fn assert_sizes_read(strokes: &[Vec<DVec2>], dropped: &Cuboid, truth: &Cuboid) {
        // `SnapContext::new` takes sketch space (y down).
        let sketch: Vec<Vec<DVec2>> = strokes
            .iter()
            .map(|s| s.iter().map(|p| DVec2::new(p.x, -p.y)).collect())
            .collect();
        let context = SnapContext::new(
            sketch
                .iter()
                .enumerate()
                .map(|(i, s)| (StrokeId(i as u32), s.as_slice(), StrokeClass::Silhouette)),
        );
        let poses = box_poses(&context, dropped);
        let error = worst_size_error(&poses, truth);
        assert!(
            error < 0.02,
            "sizes off by {:.1} %: {poses:#?}",
            100.0 * error
        );
    }

    #[test]
    fn a_box_seen_side_on_with_two_axes_drawn_alike_gives_its_orientation() {
        // Two of its axes draw 15° apart, within one direction group's wide reach.
        let axes = [
            DVec3::new(-0.118, 0.676, -0.728),
            DVec3::new(-0.945, -0.302, -0.127),
            DVec3::new(-0.306, 0.672, 0.674),
        ]
        .map(DVec3::normalize);
        let truth = Cuboid {
            center: DVec3::new(1676.0, -1396.0, 0.0),
            rotation: DQuat::from_mat3(&glam::DMat3::from_cols(
                axes[0],
                axes[1],
                axes[0].cross(axes[1]),
            ))
            .normalize(),
            size: DVec3::new(1100.0, 850.0, 920.0),
        };
        let dropped = Cuboid {
            center: DVec3::new(1630.0, -1450.0, 0.0),
            rotation: DQuat::from_mat3(&glam::DMat3::from_cols(
                DVec3::new(0.099, -0.877, 0.470).normalize(),
                DVec3::new(0.896, 0.285, 0.342).normalize(),
                DVec3::new(0.099, -0.877, 0.470)
                    .normalize()
                    .cross(DVec3::new(0.896, 0.285, 0.342).normalize()),
            ))
            .normalize(),
            size: DVec3::new(830.0, 644.0, 1076.0),
        };
        let mirror = |v: DVec3| DVec3::new(v.x, v.y, -v.z);
        let poses = box_poses(&drawn(&truth), &dropped);
        let truth_axes = truth.axes();
        let found = poses.iter().any(|pose| {
            pose.axes().iter().all(|a| {
                truth_axes.iter().any(|t| {
                    let near = |v: DVec3| v.dot(*t).abs() > 2f64.to_radians().cos();
                    near(*a) || near(mirror(*a))
                })
            })
        });
        assert!(found, "no pose has the true axes: {poses:#?}");
    }

    #[test]
    fn too_few_edge_directions_give_no_pose() {
        // Only two directions: a rectangle seen head-on says nothing of the depth.
        let line = |a: DVec2, b: DVec2| -> Vec<DVec2> {
            (0..=10).map(|i| a.lerp(b, f64::from(i) / 10.0)).collect()
        };
        let strokes = [
            line(DVec2::new(0.0, 0.0), DVec2::new(100.0, 0.0)),
            line(DVec2::new(0.0, 50.0), DVec2::new(100.0, 50.0)),
            line(DVec2::new(0.0, 0.0), DVec2::new(0.0, 50.0)),
            line(DVec2::new(100.0, 0.0), DVec2::new(100.0, 50.0)),
        ];
        let context = SnapContext::new(
            strokes
                .iter()
                .enumerate()
                .map(|(i, s)| (StrokeId(i as u32), s.as_slice(), StrokeClass::Silhouette)),
        );
        let dropped = Cuboid {
            center: DVec3::new(50.0, -25.0, 0.0),
            rotation: DQuat::IDENTITY,
            size: DVec3::new(100.0, 50.0, 50.0),
        };
        assert!(box_poses(&context, &dropped).is_empty());
    }

    /// A circle of `radius` about `centre` square to `axis`, from angle `from` to `to`
    /// (radians), as a stroke in sketch space (y down).
    pub(in crate::snap) fn rim(
        centre: DVec3,
        axis: DVec3,
        radius: f64,
        from: f64,
        to: f64,
    ) -> Vec<DVec2> {
        let u = axis.any_orthonormal_vector();
        let v = axis.cross(u);
        (0..=48)
            .map(|i| {
                let t = from + (to - from) * f64::from(i) / 48.0;
                let p = centre + radius * (t.cos() * u + t.sin() * v);
                DVec2::new(p.x, -p.y)
            })
            .collect()
    }

    /// `strokes` (sketch space, y down) as a context, all of `class`.
    pub(in crate::snap) fn strokes_of(strokes: &[Vec<DVec2>], class: StrokeClass) -> SnapContext {
        SnapContext::new(
            strokes
                .iter()
                .enumerate()
                .map(|(i, s)| (StrokeId(i as u32), s.as_slice(), class)),
        )
    }

    #[test]
    fn fragments_that_continue_one_another_form_one_run() {
        let tau = std::f64::consts::TAU;
        let centre = DVec3::new(0.0, 0.0, 0.0);
        let axis = DVec3::Z;
        // Three arcs of one circle with small gaps, given out of order, and a stroke
        // across the circle's middle that meets none of them end to end.
        let mut strokes: Vec<Vec<DVec2>> = [2, 0, 1]
            .iter()
            .map(|k| {
                let a = tau / 3.0 * f64::from(*k);
                rim(centre, axis, 100.0, a + 0.03, a + tau / 3.0 - 0.03)
            })
            .collect();
        strokes.push(vec![
            DVec2::new(-50.0, 0.0),
            DVec2::new(50.0, 0.0),
            DVec2::new(60.0, 1.0),
        ]);
        let context = strokes_of(&strokes, StrokeClass::Feature);
        let all: Vec<&SnapStroke> = context.strokes.iter().collect();
        let runs = fragment_runs(&all, 100.0);
        assert_eq!(runs.len(), 1, "{}", runs.len());
        let mut ids: Vec<u32> = runs[0].iter().map(|s| s.id.0).collect();
        ids.sort_unstable();
        assert_eq!(ids, vec![0, 1, 2]);
    }

    #[test]
    fn a_sphere_starts_from_the_circle_drawn_round_a_rough_drop() {
        // A ball drawn as two arcs, a tube's end ellipse on its rim and a stroke across
        // it; dropped a quarter too big and off by a tenth of its size.
        let arc = |c: DVec2, r: f64, from: f64, to: f64| -> Vec<DVec2> {
            (0..=40)
                .map(|i| c + r * DVec2::from_angle(from + (to - from) * f64::from(i) / 40.0))
                .collect()
        };
        let ball = DVec2::new(300.0, -200.0);
        let strokes = [
            arc(ball, 100.0, 0.3, 3.0),
            arc(ball, 100.0, 3.3, 6.0),
            arc(
                ball + DVec2::new(95.0, 0.0),
                30.0,
                0.0,
                std::f64::consts::TAU,
            ),
            vec![ball - DVec2::new(60.0, 10.0), ball + DVec2::new(40.0, 30.0)],
        ];
        // Strokes are given in sketch space (y down).
        let strokes: Vec<Vec<DVec2>> = strokes
            .iter()
            .map(|s| s.iter().map(|p| DVec2::new(p.x, -p.y)).collect())
            .collect();
        let context = strokes_of(&strokes, StrokeClass::Feature);
        let dropped = Sphere {
            center: DVec3::new(ball.x + 15.0, ball.y - 12.0, 0.0),
            radius: 125.0,
        };
        let poses = starting_poses(&context, &Primitive::Sphere(dropped));
        let [Primitive::Sphere(s)] = poses.as_slice() else {
            panic!("{poses:?}");
        };
        assert!(s.center.truncate().distance(ball) < 1.0, "{s:?}");
        assert!((s.radius - 100.0).abs() < 1.0, "{s:?}");
    }

    #[test]
    fn a_long_stroke_along_a_slabs_thin_edges_is_not_its_thickness() {
        let mut truth = turned_box();
        truth.size = DVec3::new(200.0, 16.0, 150.0);
        let mut context = drawn(&truth);
        // Two table legs under the slab, along its thin axis, five times as long as it is
        // thick.
        let [x, y, z] = truth.axes();
        let legs: Vec<Vec<DVec2>> = [-1.0, 1.0]
            .iter()
            .map(|side| {
                let top = truth.center + x * (side * 60.0) - y * 8.0 + z * 40.0;
                (0..=20)
                    .map(|i| {
                        let p = top - y * (80.0 * f64::from(i) / 20.0);
                        DVec2::new(p.x, -p.y)
                    })
                    .collect()
            })
            .collect();
        let extra = SnapContext::new(legs.iter().enumerate().map(|(i, s)| {
            (
                StrokeId(100 + i as u32),
                s.as_slice(),
                StrokeClass::Silhouette,
            )
        }));
        context.strokes.extend(extra.strokes);
        context.pieces.extend(extra.pieces);
        let dropped = Cuboid {
            center: truth.center + DVec3::new(10.0, -8.0, 0.0),
            size: DVec3::new(230.0, 20.0, 120.0),
            ..truth.clone()
        };
        let poses = box_poses(&context, &dropped);
        assert!(!poses.is_empty());
        for pose in &poses {
            assert!(
                (pose.size.y - truth.size.y).abs() < 0.05 * truth.size.y,
                "{pose:?}"
            );
        }
    }
}
