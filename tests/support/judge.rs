//! How a snapped primitive is judged against its ground truth, shared by the synthetic
//! snapping tests (`synthetic_snap`, `synthetic_conditions`).
//!
//! A snap recovers the truth when, compared with it,
//! - the projected centre is within [`CENTRE_TOL`] (3 %) of the size;
//! - the axis is within [`AXIS_TOL_DEG`] (5°), up to the mirror ambiguity of an
//!   orthographic view ((x, y, z) and (x, y, −z) look the same) and up to reversal (a
//!   cone, SGC or BGC turned end for end with its radii swapped is the same solid); a
//!   BGC's axis is its chord; a box's three axes are matched up to mirror, permutation
//!   and sign, and the worst of the three angles counts;
//! - radii and lengths are within [`SIZE_TOL`] (7 %) (cylinder: radius, length; cone:
//!   both radii, length; sphere: radius; box: the three sizes, permuted as its axes; SGC:
//!   the end radii and the length; BGC: the end radii and the spine length).

use geosnap::core::primitive::{Curve2, Primitive};
use glam::{DVec2, DVec3};

use super::assemblies::{mirror, PERMUTATIONS};

/// Largest projected centre error, relative to the size.
pub(crate) const CENTRE_TOL: f64 = 0.03;
/// Largest axis error in degrees.
pub(crate) const AXIS_TOL_DEG: f64 = 5.0;
/// Largest relative error of a radius or length.
pub(crate) const SIZE_TOL: f64 = 0.07;
/// The smallest angle (degrees) between `truth` and `fit` over the mirror and, with
/// it, whether the fit is reversed (closest to −truth).
pub(crate) fn axis_error(truth: DVec3, fit: DVec3) -> (f64, bool) {
    let mut best = (f64::INFINITY, false);
    for f in [fit, mirror(fit)] {
        for (sign, reversed) in [(1.0, false), (-1.0, true)] {
            let angle = truth.angle_between(f * sign).to_degrees();
            if angle < best.0 {
                best = (angle, reversed);
            }
        }
    }
    best
}

/// |fit − truth| / truth.
pub(crate) fn rel(fit: f64, truth: f64) -> f64 {
    (fit - truth).abs() / truth.abs()
}

/// The angle (degrees) between two lines.
pub(crate) fn line_angle(a: DVec3, b: DVec3) -> f64 {
    a.dot(b).abs().min(1.0).acos().to_degrees()
}

/// The errors of one snapped primitive against the truth.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Errors {
    /// Projected centre distance / size.
    pub(crate) centre: f64,
    /// Axis angle in degrees (none for a sphere).
    pub(crate) axis: Option<f64>,
    /// Worst relative radius error (none for a box).
    pub(crate) radius: Option<f64>,
    /// Worst relative length error (a box's sizes; none for a sphere).
    pub(crate) length: Option<f64>,
    /// Whether a cylinder's, cone's or generalized cylinder's length came out longer
    /// (+1) or shorter (−1) than the truth; 0 where it is not measured (a box, a sphere).
    pub(crate) length_sign: f64,
}

impl Errors {
    /// The criteria that fail, in words.
    pub(crate) fn failures(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.centre > CENTRE_TOL {
            out.push(format!("centre {:.1} %S > 3", 100.0 * self.centre));
        }
        if let Some(a) = self.axis.filter(|a| *a > AXIS_TOL_DEG) {
            out.push(format!("axis {a:.1}° > 5"));
        }
        if let Some(r) = self.radius.filter(|r| *r > SIZE_TOL) {
            out.push(format!("radius {:.1} % > 7", 100.0 * r));
        }
        if let Some(l) = self.length.filter(|l| *l > SIZE_TOL) {
            let sign = match self.length_sign {
                s if s > 0.0 => "+",
                s if s < 0.0 => "−",
                _ => "",
            };
            out.push(format!("length {sign}{:.1} % > 7", 100.0 * l));
        }
        out
    }
}

/// Compares `fit` with `truth` as the module docs say.
pub(crate) fn evaluate(truth: &Primitive, fit: &Primitive) -> Errors {
    let size = truth.size();
    let centre = truth.center().truncate().distance(fit.center().truncate()) / size;
    let mut e = Errors {
        centre,
        ..Errors::default()
    };
    match (truth, fit) {
        (Primitive::Cylinder(t), Primitive::Cylinder(f)) => {
            e.axis = Some(axis_error(t.axis, f.axis).0);
            e.radius = Some(rel(f.radius, t.radius));
            e.length = Some(rel(f.length, t.length));
            e.length_sign = (f.length - t.length).signum();
        }
        (Primitive::Cone(t), Primitive::Cone(f)) => {
            let (angle, reversed) = axis_error(t.axis, f.axis);
            let (rb, rt) = if reversed {
                (f.radius_top, f.radius_bottom)
            } else {
                (f.radius_bottom, f.radius_top)
            };
            e.axis = Some(angle);
            e.radius = Some(rel(rb, t.radius_bottom).max(rel(rt, t.radius_top)));
            e.length = Some(rel(f.length, t.length));
            e.length_sign = (f.length - t.length).signum();
        }
        (Primitive::Sphere(t), Primitive::Sphere(f)) => {
            e.radius = Some(rel(f.radius, t.radius));
        }
        (Primitive::Cuboid(t), Primitive::Cuboid(f)) => {
            let (ta, fa) = (t.axes(), f.axes());
            let mut best = (f64::INFINITY, 0.0);
            for m in [false, true] {
                for p in PERMUTATIONS {
                    let fit_axis = |i: usize| if m { mirror(fa[i]) } else { fa[i] };
                    let angle = (0..3)
                        .map(|i| line_angle(fit_axis(i), ta[p[i]]))
                        .fold(0.0, f64::max);
                    if angle < best.0 {
                        let sizes = (0..3)
                            .map(|i| rel(f.size[i], t.size[p[i]]))
                            .fold(0.0, f64::max);
                        best = (angle, sizes);
                    }
                }
            }
            e.axis = Some(best.0);
            e.length = Some(best.1);
        }
        (Primitive::Sgc(t), Primitive::Sgc(f)) => {
            let (angle, reversed) = axis_error(t.axis, f.axis);
            let (k, kf) = (t.radii.len() - 1, f.radii.len() - 1);
            let (r0, r1) = if reversed {
                (f.radii[kf], f.radii[0])
            } else {
                (f.radii[0], f.radii[kf])
            };
            e.axis = Some(angle);
            e.radius = Some(rel(r0, t.radii[0]).max(rel(r1, t.radii[k])));
            e.length = Some(rel(f.length, t.length));
            e.length_sign = (f.length - t.length).signum();
        }
        (Primitive::Bgc(t), Primitive::Bgc(f)) => {
            let chord = |s: &[DVec3]| (s[s.len() - 1] - s[0]).normalize_or_zero();
            let (angle, reversed) = axis_error(chord(&t.spine), chord(&f.spine));
            let (k, kf) = (t.radii.len() - 1, f.radii.len() - 1);
            let (r0, r1) = if reversed {
                (f.radii[kf], f.radii[0])
            } else {
                (f.radii[0], f.radii[kf])
            };
            e.axis = Some(angle);
            e.radius = Some(rel(r0, t.radii[0]).max(rel(r1, t.radii[k])));
            e.length = Some(rel(f.spine_length(), t.spine_length()));
            e.length_sign = (f.spine_length() - t.spine_length()).signum();
        }
        (t, f) => panic!("a {:?} snapped to a {:?}", t.kind(), f.kind()),
    }
    e
}

/// A short description of a primitive's parameters.
pub(crate) fn describe(p: &Primitive) -> String {
    let v = |d: DVec3| format!("({:.1}, {:.1}, {:.1})", d.x, d.y, d.z);
    let a = |d: DVec3| format!("({:.3}, {:.3}, {:.3})", d.x, d.y, d.z);
    let list = |r: &[f64]| {
        r.iter()
            .map(|x| format!("{x:.1}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    match p {
        Primitive::Cylinder(c) => format!(
            "centre {} axis {} length {:.1} radius {:.1}",
            v(c.center),
            a(c.axis),
            c.length,
            c.radius
        ),
        Primitive::Cone(c) => format!(
            "centre {} axis {} length {:.1} radii {:.1} → {:.1}",
            v(c.center),
            a(c.axis),
            c.length,
            c.radius_bottom,
            c.radius_top
        ),
        Primitive::Sphere(s) => format!("centre {} radius {:.1}", v(s.center), s.radius),
        Primitive::Cuboid(b) => {
            let [x, y, z] = b.axes();
            format!(
                "centre {} axes {} {} {} size {}",
                v(b.center),
                a(x),
                a(y),
                a(z),
                v(b.size)
            )
        }
        Primitive::Sgc(s) => format!(
            "centre {} axis {} length {:.1} radii [{}]",
            v(s.center),
            a(s.axis),
            s.length,
            list(&s.radii)
        ),
        Primitive::Bgc(b) => {
            let k = b.spine.len();
            let chord = (b.spine[k - 1] - b.spine[0]).normalize_or_zero();
            let bottom = (b.spine[0] - b.spine[1]).normalize_or_zero();
            let top = (b.spine[k - 1] - b.spine[k - 2]).normalize_or_zero();
            format!(
                "centre {} chord {} spine length {:.1} plane normal {} end normals z {:.2}, {:.2} radii [{}]",
                v(p.center()),
                a(chord),
                b.spine_length(),
                a(b.plane_normal),
                bottom.z,
                top.z,
                list(&b.radii)
            )
        }
    }
}

/// The distance from `p` to a numeric curve (ellipses by dense sampling).
pub(crate) fn distance_to(curve: &Curve2<f64>, p: DVec2) -> f64 {
    let segment = |a: DVec2, b: DVec2| {
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        (a + ab * t).distance(p)
    };
    match curve {
        Curve2::Ellipse { .. } => curve
            .points(1024)
            .windows(2)
            .map(|w| segment(w[0], w[1]))
            .fold(f64::INFINITY, f64::min),
        Curve2::Polyline(points) => points
            .windows(2)
            .map(|w| segment(w[0].to_dvec2(), w[1].to_dvec2()))
            .fold(f64::INFINITY, f64::min),
    }
}

/// A failure whose projected curves lie within this of the truth's (relative to the
/// size, see [`picture_difference`]) draws the truth's picture: the drawing cannot tell
/// the two apart, so what fails is what it leaves open (a bent tube's depth), not the
/// reading of the strokes.
pub(crate) const SAME_PICTURE: f64 = 0.01;

/// How far apart the pictures of `truth` and `fit` are: the 90th percentile of the
/// distances from the samples of either's projected curves (all of them, hidden or not)
/// to the other's curves, the larger of the two directions, over the truth's size.
/// Curves are compared as one set each, so a reversed reading of the same picture
/// differs by nothing.
pub(crate) fn picture_difference(truth: &Primitive, fit: &Primitive) -> f64 {
    let curves = |p: &Primitive| -> Vec<Vec<DVec2>> {
        p.current_shape()
            .curves
            .iter()
            .map(|c| densified(&c.curve.points(64), 4))
            .collect()
    };
    let (a, b) = (curves(truth), curves(fit));
    let one_way = |from: &[Vec<DVec2>], to: &[Vec<DVec2>]| {
        let mut d: Vec<f64> = from
            .iter()
            .flatten()
            .map(|p| {
                to.iter()
                    .flat_map(|c| c.windows(2))
                    .map(|w| segment_distance(*p, w[0], w[1]))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        if d.is_empty() {
            return f64::INFINITY;
        }
        d.sort_by(f64::total_cmp);
        d[(d.len() * 9) / 10]
    };
    one_way(&a, &b).max(one_way(&b, &a)) / truth.size()
}

/// `points` with `n − 1` more points evenly between each two.
fn densified(points: &[DVec2], n: usize) -> Vec<DVec2> {
    let mut out = Vec::with_capacity(points.len() * n);
    for w in points.windows(2) {
        out.extend((0..n).map(|k| w[0].lerp(w[1], k as f64 / n as f64)));
    }
    out.extend(points.last());
    out
}

/// The distance from `p` to the segment `a`–`b`.
fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}
