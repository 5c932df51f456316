//! The bent generalized cylinder (BGC): a tube along a planar curved spine with a radius
//! profile.
//!
//! The spine is K points P₀ … P_{K−1} (K = [`PROFILE_SAMPLES`] for a new BGC) evenly spaced
//! along a curve in a plane, so it is parameterised by construction rather than by
//! constraints. Parameters (2K + 6): the midpoint c of the middle segment P_m–P_{m+1}
//! (m = ⌊(K − 2)/2⌋; 3), the orientation quaternion q = (w, x, y, z) of the spine's frame
//! (u, v, n) (4, unit by the constraint |q|² = 1: u is the middle segment's direction, v
//! the in-plane normal, n the plane's normal), the segment length h (1), the turns
//! κ₁ … κ_{K−2} of the spine at its interior points (K − 2, radians, in the plane) and the
//! radii r₀ … r_{K−1} (K). Segment s runs along d(φ_s) = cos φ_s·u + sin φ_s·v with
//! φ_m = 0 and φ_s − φ_{s−1} = κ_s. The quaternion is normalised where it is used, so the
//! fit has no equality constraint (a regulariser keeps |q| near 1). Constraints
//! (inequalities): a positive length and radii, turns below 70° per segment, a plane
//! within 78.5° of the view plane, and each end on the side (facing the viewer or away)
//! it shows at the pose the fit starts from, unless nearly edge-on.
//!
//! The spine's tangent at a point bisects its two segments, and at an end it is the end
//! segment's direction turned back by half the next turn: exact for a circular arc, so
//! the end circles of an evenly bent tube face the right way (a first-order end tangent
//! is off by half a segment's bend, which tilts the end ellipses by up to 9°).
//!
//! Projected curves: the end ellipses (circles at P₀ and P_{K−1} whose normals are the
//! outward end tangents; feature strokes; only the near half of an end that faces away
//! from the viewer, as that is all a person draws of it, run on along its end tangents
//! as a hand overshoots it) and two contour polylines, the spine offset by
//! ± rᵢ·νᵢ with νᵢ the view-plane normal of the projected tangent (silhouette strokes;
//! exact when the spine lies in the view plane, close when it tilts moderately), through
//! the points and the arc midpoints of the segments. Feature curves `bottom` (at P₀) and
//! `top` (at P_{K−1}). Regularisers: changes of the turn along the spine (an evenly bent
//! spine, a circular arc, costs nothing) or, for a spine that bends both ways at the
//! current pose (an S: at least 14° each way), second differences of the turns (an S
//! whose bend changes sense evenly costs nothing); and, as [`Shape::profile`], second
//! differences of the radii (a smooth profile, held as strongly as the fit's
//! [`crate::snap::Profile`] says).

use glam::{DMat3, DQuat, DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::cylinder::{MAX_AXIS_Z2, MIN_SIZE_FRACTION};
use super::mesh::{orthonormal_basis, TriMesh};
use super::{
    circle_basis, circle_ellipse, quaternion_at, quaternion_columns, vec3_expr_at, Curve2,
    CurveClass, Feature, FeatureCurve, FeatureGeometry, Placement, ProjectedCurve, Shape,
    PROFILE_SAMPLES,
};
use crate::ad::{Real, Vec2, Vec3};
use crate::geom::projection::{model_direction_from_sketch, view_from_sketch};

/// Weight (inside the residual) of a change (a C) or a second difference (an S) of the
/// turns along the spine.
const TURN_SMOOTHNESS: f64 = 15.0;
/// Weight (inside the residual) of the pull of the spine's plane towards the view plane
/// when no end ellipse is assigned (see [`Shape::untilted`]).
const PLANE_PULL: f64 = 0.15;
/// The largest turn of the spine at one point (radians).
const MAX_TURN: f64 = 1.2;
/// An end circle whose normal is within this (|n_z|) of the view plane is nearly
/// edge-on: it counts as facing the viewer, and may turn either way during a fit. A
/// hand's end ellipse that flat tells little about which way it faces, so a start (or
/// an earlier round) that has such an end on the wrong side must be free to turn it.
const EDGE_ON: f64 = 0.15;

/// A bent generalized cylinder in model space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bgc {
    /// Spine points from one end to the other (at least three).
    pub spine: Vec<DVec3>,
    /// Radii at the spine points.
    pub radii: Vec<f64>,
    /// The unit normal of the spine's plane.
    pub plane_normal: DVec3,
}

/// The index m of the middle segment P_m–P_{m+1} of a K-point spine.
fn middle(k: usize) -> usize {
    (k - 2) / 2
}

/// The spine of parameters `x` (layout in the module docs) for K = `k`: its points, its
/// unit tangents at the points, the arc midpoints of its segments with their tangents,
/// and the plane's normal.
struct Spine<T> {
    points: Vec<Vec3<T>>,
    tangents: Vec<Vec3<T>>,
    midpoints: Vec<Vec3<T>>,
    mid_tangents: Vec<Vec3<T>>,
    normal: Vec3<T>,
}

fn spine<T: Real>(k: usize, x: &[T]) -> Spine<T> {
    let c = vec3_expr_at(x, Bgc::CENTER);
    // The quaternion is normalised here (its scale is free, fixed by a regulariser), so
    // the fit has no equality constraint to satisfy.
    let q = quaternion_at(x, Bgc::ROTATION);
    let norm = (q[0].square() + q[1].square() + q[2].square() + q[3].square()).sqrt();
    let [u, v, n] = quaternion_columns(q.map(|v| v / norm));
    let h = x[Bgc::SEGMENT];
    let kappa = &x[Bgc::turns(k)];
    let m = middle(k);
    let zero = h.lit(0.0);
    // Segment directions φ_s: φ_m = 0, φ_s − φ_{s−1} = κ_s (κ_s is kappa[s − 1]).
    let mut phi = vec![zero; k - 1];
    for s in m + 1..k - 1 {
        phi[s] = phi[s - 1] + kappa[s - 1];
    }
    for s in (0..m).rev() {
        phi[s] = phi[s + 1] - kappa[s];
    }
    let dir = |angle: T| u * angle.cos() + v * angle.sin();
    let d: Vec<Vec3<T>> = phi.iter().map(|a| dir(*a)).collect();
    let mut points = vec![c; k];
    points[m] = c - u * (h * 0.5);
    points[m + 1] = c + u * (h * 0.5);
    for s in m + 1..k - 1 {
        points[s + 1] = points[s] + d[s] * h;
    }
    for s in (0..m).rev() {
        points[s] = points[s + 1] - d[s] * h;
    }
    // Tangent angles at the points: bisectors inside, half a turn back at the ends.
    let mut psi = Vec::with_capacity(k);
    psi.push(phi[0] - kappa[0] * 0.5);
    for i in 1..k - 1 {
        psi.push((phi[i - 1] + phi[i]) * 0.5);
    }
    psi.push(phi[k - 2] + kappa[k - 3] * 0.5);
    let tangents = psi.iter().map(|a| dir(*a)).collect();
    // The arc through P_s and P_{s+1} turning by θ = ψ_{s+1} − ψ_s bulges away from its
    // centre by (h/2)·tan(θ/4) at its midpoint, where its tangent is d(φ_s).
    let mut midpoints = Vec::with_capacity(k - 1);
    for s in 0..k - 1 {
        let theta = psi[s + 1] - psi[s];
        let quarter = theta * 0.25;
        let sag = h * 0.5 * quarter.sin() / quarter.cos();
        let left = u * (-phi[s].sin()) + v * phi[s].cos();
        midpoints.push((points[s] + points[s + 1]) * h.lit(0.5) - left * sag);
    }
    Spine {
        points,
        tangents,
        midpoints,
        mid_tangents: d,
        normal: n,
    }
}

/// The two contour polylines (left, right): the spine's points and arc midpoints offset
/// by ± the radius along the view-plane normal of their projected tangents.
fn contours<T: Real>(s: &Spine<T>, radii: &[T]) -> (Vec<Vec2<T>>, Vec<Vec2<T>>) {
    let k = s.points.len();
    let normal2 = |t: Vec3<T>| {
        let len = (t.x.square() + t.y.square() + 1e-18).sqrt();
        Vec2::new(-t.y / len, t.x / len)
    };
    let mut left = Vec::with_capacity(2 * k - 1);
    let mut right = Vec::with_capacity(2 * k - 1);
    for i in 0..k {
        if i > 0 {
            let nu = normal2(s.mid_tangents[i - 1]);
            let r = (radii[i - 1] + radii[i]) * 0.5;
            let at = s.midpoints[i - 1].xy();
            left.push(at + nu * r);
            right.push(at - nu * r);
        }
        let nu = normal2(s.tangents[i]);
        let at = s.points[i].xy();
        left.push(at + nu * radii[i]);
        right.push(at - nu * radii[i]);
    }
    (left, right)
}

/// Segments of the near half of an end circle that faces away from the viewer.
const HALF_SEGMENTS: usize = 8;
/// How far (in radii) the near half of an end facing away runs on along its tangents at
/// both ends: a hand overshoots a front arc along its tangent there (by up to about half
/// a radius), where the hidden rim turns back sharply for a flat ellipse.
const OVERSHOOT: f64 = 0.5;

/// The projected curve of an end circle: the whole ellipse when it faces the viewer
/// (`facing`), else its near half, the rim points c + r·(w·cos θ + k·sin θ) of
/// [`circle_basis`] with sin θ ≤ 0 (k_z < 0, so those are nearer the viewer), as a
/// polyline, run on along its end tangents (both ±k there, away from the near side) by
/// [`OVERSHOOT`] radii.
fn end_curve<T: Real>(center: Vec3<T>, normal: Vec3<T>, radius: T, facing: bool) -> Curve2<T> {
    if facing {
        return circle_ellipse(center, normal, radius);
    }
    let (w, k) = circle_basis(normal);
    let c = center.xy();
    let on = k.xy() * (radius * OVERSHOOT);
    let mut points = Vec::with_capacity(HALF_SEGMENTS + 3);
    for i in 0..=HALF_SEGMENTS {
        let theta = std::f64::consts::PI * (1.0 + i as f64 / HALF_SEGMENTS as f64);
        points.push(c + (w.xy().scale(theta.cos()) + k.xy().scale(theta.sin())) * radius);
    }
    let (first, last) = (points[0], points[HALF_SEGMENTS]);
    points.insert(0, first + on);
    points.push(last + on);
    Curve2::Polyline(points)
}

/// The signed angle from `a` to `b` in the plane (u, v), wrapped into (−π, π].
fn turn(a: DVec3, b: DVec3, u: DVec3, v: DVec3) -> f64 {
    let angle = |d: DVec3| d.dot(v).atan2(d.dot(u));
    let t = angle(b) - angle(a);
    (t + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

/// How far (radians) a spine must bend each way, in all, to be an S rather than a C
/// with a little noise in its turns.
const S_BEND: f64 = 0.25;

/// Whether turns `kappa` bend the spine both ways, each by at least [`S_BEND`] in all.
fn is_s_bend(kappa: &[f64]) -> bool {
    let left: f64 = kappa.iter().filter(|t| **t > 0.0).sum();
    let right: f64 = -kappa.iter().filter(|t| **t < 0.0).sum::<f64>();
    left >= S_BEND && right >= S_BEND
}

impl Bgc {
    /// Index of the middle segment's midpoint (3 values) in the parameter vector.
    pub const CENTER: usize = 0;
    /// Index of the spine frame's quaternion w; x, y and z follow (4 values).
    pub const ROTATION: usize = 3;
    /// Index of the segment length.
    pub const SEGMENT: usize = 7;
    /// Index of the first turn; the K − 2 turns of a K-point spine follow.
    pub const TURNS: usize = 8;

    /// The indices of the turns of a spine of `k` points.
    pub fn turns(k: usize) -> std::ops::Range<usize> {
        Self::TURNS..Self::TURNS + k - 2
    }

    /// The indices of the radii of a spine of `k` points (after the turns).
    pub fn radii(k: usize) -> std::ops::Range<usize> {
        Self::TURNS + k - 2..Self::TURNS + 2 * k - 2
    }

    pub(crate) fn from_placement(p: &Placement, default_size: f64) -> Self {
        let v = view_from_sketch(p.at);
        let center = DVec3::new(v.x, v.y, 0.0);
        let axis = model_direction_from_sketch(p.axis).unwrap_or(DVec3::Y);
        let length = p.length.unwrap_or(default_size).abs().max(1e-9);
        let r = p.radius.unwrap_or(default_size * 0.15).abs().max(1e-9);
        let k = PROFILE_SAMPLES;
        let spine = (0..k)
            .map(|i| center + axis * (length * (i as f64 / (k - 1) as f64 - 0.5)))
            .collect();
        Self {
            spine,
            radii: vec![r; k],
            plane_normal: DVec3::Z,
        }
    }

    /// A BGC through the given spine points (for example a medial axis found in the
    /// strokes) with a constant radius. The points should be evenly spaced along a
    /// planar curve; `Bgc::params` takes their plane and mean spacing.
    pub fn through(spine: Vec<DVec3>, radius: f64) -> Self {
        let radii = vec![radius; spine.len()];
        let mut b = Self {
            spine,
            radii,
            plane_normal: DVec3::Z,
        };
        b.plane_normal = b.spine_plane_normal();
        b
    }

    /// The normal of the spine's plane: `plane_normal` when the spine lies in it, else
    /// the plane the spine's bends span (`plane_normal` made ⟂ to a straight spine).
    fn spine_plane_normal(&self) -> DVec3 {
        let n = self.plane_normal.normalize_or(DVec3::Z);
        let p = &self.spine;
        let length = self.spine_length().max(f64::MIN_POSITIVE);
        let off_plane = p
            .iter()
            .map(|q| (*q - p[0]).dot(n).abs())
            .fold(0.0, f64::max);
        if off_plane <= 1e-9 * length {
            return n;
        }
        let bends: DVec3 = p.windows(3).map(|w| (w[1] - w[0]).cross(w[2] - w[1])).sum();
        if bends.length() > 1e-9 * length * length {
            let b = bends.normalize();
            return if b.dot(n) < 0.0 { -b } else { b };
        }
        let chord = (p[p.len() - 1] - p[0]).normalize_or(DVec3::Y);
        (n - chord * n.dot(chord)).normalize_or(orthonormal_basis(chord).0)
    }

    pub(crate) fn params(&self) -> Vec<f64> {
        let k = self.spine.len();
        let p = &self.spine;
        let m = middle(k);
        let n = self.spine_plane_normal();
        let c = (p[m] + p[m + 1]) / 2.0;
        let mid = p[m + 1] - p[m];
        let u = (mid - n * mid.dot(n)).normalize_or(orthonormal_basis(n).0);
        let v = n.cross(u);
        let q = DQuat::from_mat3(&DMat3::from_cols(u, v, n)).normalize();
        let h = self.spine_length() / (k - 1) as f64;
        let mut x = vec![c.x, c.y, c.z, q.w, q.x, q.y, q.z, h];
        for i in 1..k - 1 {
            x.push(turn(p[i] - p[i - 1], p[i + 1] - p[i], u, v));
        }
        x.extend_from_slice(&self.radii);
        x
    }

    pub(crate) fn with_params(&self, x: &[f64]) -> Self {
        let k = self.spine.len();
        let [w, qx, qy, qz] = quaternion_at(x, Self::ROTATION);
        let len = (w * w + DVec3::new(qx, qy, qz).length_squared()).sqrt();
        let mut y = x.to_vec();
        if len > 0.0 && len.is_finite() {
            for value in &mut y[Self::ROTATION..Self::ROTATION + 4] {
                *value /= len;
            }
        }
        let s = spine(k, &y);
        Self {
            spine: s.points.iter().map(|p| p.to_dvec3()).collect(),
            radii: x[Self::radii(k)].to_vec(),
            plane_normal: s.normal.to_dvec3().normalize_or(self.plane_normal),
        }
    }

    /// The spine's length.
    pub fn spine_length(&self) -> f64 {
        self.spine.windows(2).map(|w| w[0].distance(w[1])).sum()
    }

    pub(crate) fn center(&self) -> DVec3 {
        self.spine.iter().copied().sum::<DVec3>() / self.spine.len().max(1) as f64
    }

    pub(crate) fn size(&self) -> f64 {
        let widest = self.radii.iter().fold(0.0f64, |m, r| m.max(*r));
        self.spine_length().max(2.0 * widest)
    }

    pub(crate) fn transformed(&self, offset: DVec3, factor: f64) -> Self {
        Self {
            spine: self.spine.iter().map(|p| (*p + offset) * factor).collect(),
            radii: self.radii.iter().map(|r| r * factor).collect(),
            plane_normal: self.plane_normal,
        }
    }

    pub(crate) fn shape<T: Real>(&self, x: &[T]) -> Shape<T> {
        let k = self.spine.len();
        let s = spine(k, x);
        let h = x[Self::SEGMENT];
        let kappa = &x[Self::turns(k)];
        let radii = &x[Self::radii(k)];
        let (left, right) = contours(&s, radii);
        // An end circle facing away from the viewer shows only its near half (as drawn):
        // which way each end faces is taken at the current numeric pose; an end almost
        // edge-on (|n_z| < [`EDGE_ON`]) counts as facing, a coin toss which half is in front.
        let params = self.params();
        let now = {
            let t = spine(k, &params).tangents;
            [-t[0].z, t[k - 1].z]
        };
        let facing = now.map(|z| z > 0.0 || z.abs() < EDGE_ON);
        let bottom_normal = -s.tangents[0];
        let top_normal = s.tangents[k - 1];
        let (p0, p1) = (s.points[0], s.points[k - 1]);
        let curve = ProjectedCurve::shown;
        let min = self.size() * MIN_SIZE_FRACTION;
        let equalities = Vec::new();
        let inequalities = Self::inequalities(k, &s, h, kappa, radii, min, now);
        let regularizers = Self::regularizers(x, kappa, is_s_bend(&params[Self::turns(k)]));
        Shape {
            curves: vec![
                curve(
                    "top",
                    CurveClass::Feature,
                    end_curve(p1, top_normal, radii[k - 1], facing[1]),
                ),
                curve(
                    "bottom",
                    CurveClass::Feature,
                    end_curve(p0, bottom_normal, radii[0], facing[0]),
                ),
                curve("left", CurveClass::Silhouette, Curve2::Polyline(left)),
                curve("right", CurveClass::Silhouette, Curve2::Polyline(right)),
            ],
            features: vec![
                FeatureCurve {
                    feature: Feature::Top,
                    geometry: FeatureGeometry::Circle {
                        center: p1,
                        normal: top_normal,
                        radius: radii[k - 1],
                    },
                },
                FeatureCurve {
                    feature: Feature::Bottom,
                    geometry: FeatureGeometry::Circle {
                        center: p0,
                        normal: bottom_normal,
                        radius: radii[0],
                    },
                },
            ],
            equalities,
            inequalities,
            regularizers,
            profile: radii.windows(3).map(|w| w[0] - w[1] * 2.0 + w[2]).collect(),
            // The spine's plane leans out of the view (1 − n_z²) only as far as its end
            // ellipses say: a drawn bend is as well a circular arc seen aslant, which the
            // turn smoothness prefers.
            untilted: vec![(h.lit(1.0) - s.normal.z.square()) * PLANE_PULL],
        }
    }

    /// The shape's inequality constraints, each with its name: a positive length and
    /// positive radii (at least `min`), the spine's plane not edge-on, moderate turns, and
    /// each end keeping the side it shows at the current pose (`now`: each end's outward
    /// z at the current parameters). `k` is the number of spine points, `h` the segment
    /// length, `kappa` the turns.
    fn inequalities<T: Real>(
        k: usize,
        s: &Spine<T>,
        h: T,
        kappa: &[T],
        radii: &[T],
        min: f64,
        now: [f64; 2],
    ) -> Vec<(&'static str, T)> {
        // The spine's plane within 78.5° of the view plane (as an axis of a solid of
        // revolution within 11.5° of the view direction, [`MAX_AXIS_Z2`]): a plane seen
        // edge-on shows the length of nothing, and a fit could run away along it.
        let mut inequalities = vec![
            ("positive length", h * (k - 1) as f64 - min),
            (
                "plane not edge-on",
                s.normal.z.square() - (1.0 - MAX_AXIS_Z2),
            ),
        ];
        inequalities.extend(radii.iter().map(|r| ("positive radius", *r - min)));
        inequalities.extend(
            kappa
                .iter()
                .map(|t| ("moderate turn", -t.square() + MAX_TURN * MAX_TURN)),
        );
        // An end keeps the side it shows at the current pose (unless nearly edge-on): a
        // full ellipse explains a drawn front arc as well as the half that is drawn, so
        // without this a fit may turn an end facing away round to face the viewer (or
        // back), and the tilt of the tube with it.
        let outward_z = [-s.tangents[0].z, s.tangents[k - 1].z];
        for (z, now) in outward_z.into_iter().zip(now) {
            let g = if now.abs() < EDGE_ON {
                h.lit(1.0)
            } else if now > 0.0 {
                z
            } else {
                -z
            };
            inequalities.push(("end keeps its side", g));
        }
        inequalities
    }

    /// The shape's regularizers: smooth turns (`kappa`; for an S bend, when `s_bend`,
    /// evenly changing ones) and a unit rotation quaternion in the parameters `x` (the
    /// smooth radius profile is [`Shape::profile`]).
    fn regularizers<T: Real>(x: &[T], kappa: &[T], s_bend: bool) -> Vec<T> {
        // A spine that bends one way (a C) at the current pose is smoothed towards even
        // turns, a circular arc; one that bends both ways (an S) towards turns that
        // change evenly along it (even turns would straighten it into a C).
        let mut regularizers: Vec<T> = if s_bend {
            kappa
                .windows(3)
                .map(|w| (w[0] - w[1] * 2.0 + w[2]) * TURN_SMOOTHNESS)
                .collect()
        } else {
            kappa
                .windows(2)
                .map(|w| (w[1] - w[0]) * TURN_SMOOTHNESS)
                .collect()
        };
        let q = quaternion_at(x, Self::ROTATION);
        regularizers.push(q[0].square() + q[1].square() + q[2].square() + q[3].square() - 1.0);
        regularizers
    }

    pub(crate) fn mesh(&self, segments: usize) -> TriMesh {
        let k = self.spine.len();
        // Rotation-minimising frames: carry u along the spine by projecting it.
        let tangent = |i: usize| {
            let (lo, hi) = (i.saturating_sub(1), (i + 1).min(k - 1));
            (self.spine[hi] - self.spine[lo]).normalize_or(DVec3::Y)
        };
        let (mut u, _) = orthonormal_basis(tangent(0));
        let mut rings = Vec::with_capacity(k);
        let mut normals = Vec::with_capacity(k);
        for i in 0..k {
            let t = tangent(i);
            u = (u - t * u.dot(t)).normalize_or(orthonormal_basis(t).0);
            let v = t.cross(u);
            let mut ring = Vec::with_capacity(segments);
            let mut ring_normals = Vec::with_capacity(segments);
            for j in 0..segments {
                let angle = std::f64::consts::TAU * j as f64 / segments as f64;
                let e = u * angle.cos() + v * angle.sin();
                ring.push(self.spine[i] + e * self.radii[i]);
                ring_normals.push(e);
            }
            rings.push(ring);
            normals.push(ring_normals);
        }
        TriMesh::tube(&self.spine, &rings, &normals)
    }

    /// The spine projected to the view plane.
    pub fn projected_spine(&self) -> Vec<DVec2> {
        self.spine.iter().map(|p| DVec2::new(p.x, p.y)).collect()
    }
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::Bgc;
    use crate::primitive::{Placement, Primitive, PrimitiveKind};

    #[test]
    fn a_straight_placement_satisfies_its_constraints() {
        let mut place = Placement::at(DVec2::new(10.0, 20.0));
        place.length = Some(70.0);
        place.radius = Some(5.0);
        let p = Primitive::from_placement(PrimitiveKind::Bgc, &place, 30.0);
        let back = p.with_params(&p.params());
        let (Primitive::Bgc(a), Primitive::Bgc(b)) = (&p, &back) else {
            panic!("a bgc")
        };
        assert!(a
            .spine
            .iter()
            .zip(&b.spine)
            .all(|(x, y)| x.distance(*y) < 1e-9));
        assert_eq!(a.radii, b.radii);
        let shape = p.current_shape();
        assert!(shape.equalities.iter().all(|(_, c)| c.abs() < 1e-9));
        assert!(shape.inequalities.iter().all(|(_, g)| *g > 0.0));
        let Primitive::Bgc(b) = &p else {
            panic!("a bgc")
        };
        assert!((b.spine_length() - 70.0).abs() < 1e-9);
        let v = p.mesh(256).volume();
        let exact = std::f64::consts::PI * 25.0 * 70.0;
        assert!((v - exact).abs() < 1e-2 * exact, "{v} vs {exact}");
    }

    #[test]
    fn a_quarter_torus_mesh_is_closed() {
        let spine: Vec<DVec3> = (0..8)
            .map(|i| {
                let t = std::f64::consts::FRAC_PI_2 * f64::from(i) / 7.0;
                DVec3::new(10.0 * t.cos(), 10.0 * t.sin(), 0.0)
            })
            .collect();
        let tube = Bgc::through(spine, 1.0);
        let v = tube.mesh(64).volume();
        // Pappus: π r² · (π/2 · R), up to the polygonal spine.
        let exact = std::f64::consts::PI * std::f64::consts::FRAC_PI_2 * 10.0;
        assert!((v - exact).abs() < 0.05 * exact, "{v} vs {exact}");
    }

    /// A planar spine of `k` points a unit apart whose turns are `turn(i)` at point i.
    fn spine_with_turns(k: usize, turn: impl Fn(usize) -> f64) -> Vec<DVec3> {
        let mut points = vec![DVec3::ZERO, DVec3::Y];
        let mut angle = 0.0f64;
        for i in 1..k - 1 {
            angle += turn(i);
            let last = points[i];
            points.push(last + DVec3::new(-angle.sin(), angle.cos(), 0.0));
        }
        points
    }

    #[test]
    fn an_evenly_changing_s_and_an_even_c_cost_no_smoothness() {
        // Turns from +0.3 to −0.3 rad, changing evenly (an S), and even turns (a C).
        let s = spine_with_turns(8, |i| 0.3 - 0.6 * (i - 1) as f64 / 5.0);
        let c = spine_with_turns(8, |_| 0.25);
        for (name, spine) in [("S", s), ("C", c)] {
            let p = Primitive::Bgc(Bgc::through(spine, 0.2));
            let shape = p.current_shape();
            let worst = shape
                .regularizers
                .iter()
                .fold(0.0f64, |m, r| m.max(r.abs()));
            assert!(worst < 1e-9, "the {name} costs {worst}");
        }
        assert!(super::is_s_bend(&[0.3, 0.18, 0.06, -0.06, -0.18, -0.3]));
        assert!(!super::is_s_bend(&[0.25, 0.25, 0.25, 0.02, -0.02, 0.25]));
    }
}
