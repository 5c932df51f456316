//! How tightly a drawing pins a snapped part: the spread of its dimensions that the
//! strokes' own noise leaves, read from the curvature of the fit at its minimum.
//!
//! A fit that lands on the right strokes can still be loose. A cylinder seen almost
//! along its axis shows its length only through the flatness of its end ellipses; a bent
//! tube whose end ellipses are barely drawn can tilt in depth at almost no cost; a box
//! seen square-on hides one of its sides. The fit RMS does not show any of this: the
//! strokes lie on the fitted curves whichever of the nearly equal poses is chosen.
//!
//! What does show it is how sharply the fit's objective φ rises around its minimum. If
//! each curve's strokes carry an error of standard deviation σ, and a hand's error on
//! one curve is made of about [`CURVE_MODES`] independent parts (where the curve lies,
//! its size, its tilt, its bend, however many samples the stroke has), the fitted
//! parameters scatter with covariance
//!
//! ```text
//! Cov(θ) ≈ (2σ² / m) · H⁻¹,   H = ∇²φ at the fit,
//! ```
//!
//! since φ averages each curve's squared distances (so H = 2·Σ_curves mean ∇d∇dᵀ, while
//! the noise adds 4σ²/m · mean ∇d∇dᵀ per curve to the gradient's covariance). H is
//! taken on the parameters that keep the primitive's equalities (unit axis, unit
//! quaternion), and each dimension's spread comes from its first-order change with the
//! parameters. A direction the objective does not see at all, and that changes a
//! dimension, leaves that dimension unpinned (an infinite spread); one that changes no
//! dimension (a depth the view cannot see, a quaternion's scale) is a gauge and costs
//! nothing.
//!
//! σ is the fit's RMS over the part's size, at least [`NOISE_FLOOR`]: a hand that draws
//! a curve smoothly still misplaces it by about half a percent of the part, and a perfect
//! drawing does not make every pose exact.
//!
//! The spreads are what the issue's notion of a recovered part measures: the projected
//! centre (over the size), the axis's angle, the end radii and the lengths (relative).

use glam::DVec3;
use nalgebra::{DMatrix, DVector, SymmetricEigen};

use super::assign::Assignment;
use super::objective::{build_problem, Frame, Profile};
use super::SnapSettings;
use crate::primitive::Primitive;
use crate::solve::{Problem, SolveContext, Solver, Start};

/// The independent parts of a hand's error on one drawn curve (see the module docs).
pub(crate) const CURVE_MODES: f64 = 4.0;

/// The least noise a drawn curve carries, relative to the part's size.
pub(crate) const NOISE_FLOOR: f64 = 0.005;

/// One standard deviation of a snapped part's dimensions, as the drawing's noise leaves
/// them; an infinite value is a dimension the drawing does not pin at all.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spread {
    /// The projected centre's, over the part's size.
    pub centre: f64,
    /// The axis's angle in radians: a box's worst axis, a bent tube's chord; 0 for a
    /// sphere.
    pub axis: f64,
    /// The worst radius's, relative to it; 0 for a box.
    pub radius: f64,
    /// The worst length's, relative to it: a box's sides, a bent tube's spine; 0 for a
    /// sphere.
    pub length: f64,
}

impl Spread {
    /// The spread of `dimension`.
    pub fn of(&self, dimension: Dimension) -> f64 {
        match dimension {
            Dimension::Position => self.centre,
            Dimension::Direction => self.axis,
            Dimension::Radius => self.radius,
            Dimension::Length => self.length,
        }
    }

    /// The spread as multiples of the tolerances a recovered part is held to: the centre
    /// within `centre` sizes, the axis within `axis` radians, radii and lengths within
    /// `size` (relative). Its largest entry with its dimension.
    pub fn worst(&self, centre: f64, axis: f64, size: f64) -> (f64, Dimension) {
        [
            (self.centre / centre, Dimension::Position),
            (self.axis / axis, Dimension::Direction),
            (self.radius / size, Dimension::Radius),
            (self.length / size, Dimension::Length),
        ]
        .into_iter()
        .fold((0.0, Dimension::Position), |best, x| {
            if x.0 > best.0 || x.0.is_nan() {
                x
            } else {
                best
            }
        })
    }
}

/// The dimensions a spread is reported for, each a few numbers of a primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// The projected centre.
    Position,
    /// The axis (a box's axes, a bent tube's chord).
    Direction,
    /// The end radii (a sphere's radius).
    Radius,
    /// The lengths (a box's sides, a bent tube's spine).
    Length,
}

impl Dimension {
    /// The dimension in words.
    pub fn name(self) -> &'static str {
        match self {
            Self::Position => "position",
            Self::Direction => "direction",
            Self::Radius => "radius",
            Self::Length => "length",
        }
    }
}

/// The measured numbers of `p`: for each, its dimension, its value's scale (a relative
/// spread divides by it; 1 for a centre or a direction component) and the value. A
/// direction gives its three components, each of a group that counts as one.
fn measures(p: &Primitive) -> Vec<(Dimension, usize, f64, f64)> {
    let mut out = Vec::new();
    let mut group = 0usize;
    let mut push_group =
        |out: &mut Vec<(Dimension, usize, f64, f64)>, d: Dimension, values: &[(f64, f64)]| {
            for (scale, value) in values {
                out.push((d, group, *scale, *value));
            }
            group += 1;
        };
    let centre = p.center().truncate();
    push_group(
        &mut out,
        Dimension::Position,
        &[(1.0, centre.x), (1.0, centre.y)],
    );
    let dir = |v: DVec3| [(1.0, v.x), (1.0, v.y), (1.0, v.z)];
    let rel = |v: f64| (v.abs().max(f64::MIN_POSITIVE), v);
    match p {
        Primitive::Cylinder(c) => {
            push_group(&mut out, Dimension::Direction, &dir(c.axis));
            push_group(&mut out, Dimension::Radius, &[rel(c.radius)]);
            push_group(&mut out, Dimension::Length, &[rel(c.length)]);
        }
        Primitive::Cone(c) => {
            push_group(&mut out, Dimension::Direction, &dir(c.axis));
            push_group(&mut out, Dimension::Radius, &[rel(c.radius_bottom)]);
            push_group(&mut out, Dimension::Radius, &[rel(c.radius_top)]);
            push_group(&mut out, Dimension::Length, &[rel(c.length)]);
        }
        Primitive::Sphere(s) => push_group(&mut out, Dimension::Radius, &[rel(s.radius)]),
        Primitive::Cuboid(b) => {
            for (axis, side) in b.axes().into_iter().zip(b.size.to_array()) {
                push_group(&mut out, Dimension::Direction, &dir(axis));
                push_group(&mut out, Dimension::Length, &[rel(side)]);
            }
        }
        Primitive::Sgc(s) => {
            push_group(&mut out, Dimension::Direction, &dir(s.axis));
            push_group(&mut out, Dimension::Radius, &[rel(s.radii[0])]);
            push_group(
                &mut out,
                Dimension::Radius,
                &[rel(s.radii[s.radii.len() - 1])],
            );
            push_group(&mut out, Dimension::Length, &[rel(s.length)]);
        }
        Primitive::Bgc(b) => {
            let chord = (b.spine[b.spine.len() - 1] - b.spine[0]).normalize_or_zero();
            push_group(&mut out, Dimension::Direction, &dir(chord));
            push_group(&mut out, Dimension::Radius, &[rel(b.radii[0])]);
            push_group(
                &mut out,
                Dimension::Radius,
                &[rel(b.radii[b.radii.len() - 1])],
            );
            push_group(&mut out, Dimension::Length, &[rel(b.spine_length())]);
        }
    }
    out
}

/// A central-difference step for a parameter of value `x` (the frame's unit is the
/// part's size, so parameters are of order 1).
fn step(x: f64) -> f64 {
    1e-5 * x.abs().max(1.0)
}

/// The spread of `primitive`'s dimensions, fitted to `assignment` at RMS `rms` (view
/// units), as the module docs say, with how far its own strokes would still move it
/// added in quadrature; `None` when the fit's curvature is not finite or the settling
/// fit fails.
pub(crate) fn spread(
    primitive: &Primitive,
    assignment: &Assignment,
    rms: f64,
    profile: Profile,
) -> Option<Spread> {
    let frame = Frame::of(primitive);
    let local = frame.into_frame(primitive);
    let mut problem = build_problem(&local, assignment, &frame, profile);
    let pose = local.params();
    if pose.is_empty() || !pose.iter().all(|v| v.is_finite()) {
        return None;
    }
    let at_pose = feasible_directions(&mut problem, &pose);
    let x0 = settled(&mut problem, primitive, &pose, &at_pose)?;
    let basis = if x0 == pose {
        at_pose
    } else {
        feasible_directions(&mut problem, &x0)
    };
    let settled_pose = local.with_params(&x0);
    let hessian = hessian(&mut problem, &x0)?;
    let eigen = SymmetricEigen::new(basis.transpose() * &hessian * &basis);
    let largest = eigen.eigenvalues.iter().copied().fold(0.0, f64::max);
    if largest <= 0.0 || !largest.is_finite() {
        return None;
    }
    let base = measures(&settled_pose);
    let gradients = measure_gradients(&local, &x0, base.len())?;
    let moved = measures(&local);
    let sigma = (rms / primitive.size().max(f64::MIN_POSITIVE)).max(NOISE_FLOOR);
    let scale = 2.0 * sigma * sigma / CURVE_MODES;
    let mut variances: Vec<f64> = Vec::with_capacity(base.len());
    for (k, measure) in base.iter().enumerate() {
        let g = basis.transpose() * gradients.row(k).transpose();
        let norm = g.norm();
        let mut variance = 0.0;
        for (i, lambda) in eigen.eigenvalues.iter().enumerate() {
            let along = g.dot(&eigen.eigenvectors.column(i));
            if along.abs() <= 1e-6 * norm {
                continue;
            }
            variance += if *lambda > 1e-10 * largest {
                scale * along * along / lambda
            } else {
                f64::INFINITY
            };
        }
        let offset = moved.get(k).map_or(0.0, |m| m.3 - measure.3);
        variances.push((variance + offset * offset) / (measure.2 * measure.2));
    }
    Some(gather(&base, &variances))
}

/// The parameters at the minimum of `problem` nearest `pose`: `pose` itself when the
/// fit already stopped there (its slope along `basis`, the feasible directions at
/// `pose`, is flat), else those of one more fit from it. A snap's last
/// assignment can hold other strokes than its last fit did (a bent tube is fitted to
/// its strokes clipped at junctions and named with the drawing's whole strokes), and
/// the curvature tells the spread only at a minimum.
fn settled(
    problem: &mut Problem,
    primitive: &Primitive,
    pose: &[f64],
    basis: &DMatrix<f64>,
) -> Option<Vec<f64>> {
    let mut slope = vec![0.0; pose.len()];
    problem.gradient(pose, &mut slope);
    if (basis.transpose() * DVector::from(slope)).norm() <= STATIONARY {
        return Some(pose.to_vec());
    }
    let defaults = SnapSettings::default();
    let settings = match primitive {
        Primitive::Bgc(_) => super::bgc_start::settings(&defaults),
        _ => defaults,
    };
    let start = Start {
        x: pose.to_vec(),
        multipliers: None,
        penalty: None,
    };
    let report = Solver::with_context(settings.solver(), SolveContext::default())
        .solve(problem, &start)
        .ok()?;
    report.x.iter().all(|v| v.is_finite()).then_some(report.x)
}

/// The Hessian of `problem`'s objective at `x`, by central differences of its exact
/// gradient, symmetrised; `None` when not finite.
fn hessian(problem: &mut Problem, x0: &[f64]) -> Option<DMatrix<f64>> {
    let n = x0.len();
    let mut hessian = DMatrix::<f64>::zeros(n, n);
    let (mut plus, mut minus) = (vec![0.0; n], vec![0.0; n]);
    let mut x = x0.to_vec();
    for j in 0..n {
        let h = step(x0[j]);
        x[j] = x0[j] + h;
        problem.gradient(&x, &mut plus);
        x[j] = x0[j] - h;
        problem.gradient(&x, &mut minus);
        x[j] = x0[j];
        for i in 0..n {
            hessian[(i, j)] = (plus[i] - minus[i]) / (2.0 * h);
        }
    }
    let hessian = (&hessian + hessian.transpose()) * 0.5;
    hessian.iter().all(|v| v.is_finite()).then_some(hessian)
}

/// The gradient (rows) of each of the `count` measured numbers of `local` with
/// parameters `x0`, by central differences through the parameters.
fn measure_gradients(local: &Primitive, x0: &[f64], count: usize) -> Option<DMatrix<f64>> {
    let n = x0.len();
    let mut gradients = DMatrix::<f64>::zeros(count, n);
    let mut x = x0.to_vec();
    for j in 0..n {
        let h = step(x0[j]);
        x[j] = x0[j] + h;
        let up = measures(&local.with_params(&x));
        x[j] = x0[j] - h;
        let down = measures(&local.with_params(&x));
        x[j] = x0[j];
        if up.len() != count || down.len() != count {
            return None;
        }
        for (k, (u, d)) in up.iter().zip(&down).enumerate() {
            gradients[(k, j)] = (u.3 - d.3) / (2.0 * h);
        }
    }
    Some(gradients)
}

/// The spread per dimension from each measured number's variance: a group's variances
/// add (a direction's three components give its angle), and the worst group counts.
fn gather(base: &[(Dimension, usize, f64, f64)], variances: &[f64]) -> Spread {
    let mut groups: Vec<(Dimension, f64)> = Vec::new();
    let mut last = None;
    for ((dimension, group, _, _), variance) in base.iter().zip(variances) {
        if last == Some(*group) {
            if let Some(g) = groups.last_mut() {
                g.1 += variance;
            }
        } else {
            groups.push((*dimension, *variance));
            last = Some(*group);
        }
    }
    let worst = |d: Dimension| {
        groups
            .iter()
            .filter(|g| g.0 == d)
            .map(|g| g.1.sqrt())
            .fold(0.0, f64::max)
    };
    Spread {
        centre: worst(Dimension::Position),
        axis: worst(Dimension::Direction),
        radius: worst(Dimension::Radius),
        length: worst(Dimension::Length),
    }
}

/// The largest gradient (in the frame, along the feasible directions) of a fit that is
/// at its minimum: solves stop at 1e-7 relative, and a fit far above that stopped short.
const STATIONARY: f64 = 1e-3;

/// An inequality (g ≥ 0, in the frame's units) at most this far from its bound holds the
/// fit there.
const ACTIVE: f64 = 1e-4;

/// An orthonormal basis (columns) of the parameter directions that keep the problem's
/// equalities and its active inequalities to first order (a fit held at a bound, a bent
/// tube's turn at its limit, cannot move past it): the null space of their Jacobian at
/// `x`, or every direction when there are none.
fn feasible_directions(problem: &mut Problem, x: &[f64]) -> DMatrix<f64> {
    let n = x.len();
    let equalities = problem.equality_count();
    let values = problem.constraints(x);
    let active: Vec<usize> = (0..values.len())
        .filter(|&k| k < equalities || values[k] <= ACTIVE)
        .collect();
    if active.is_empty() {
        return DMatrix::identity(n, n);
    }
    let all = problem.constraint_jacobian(x);
    let mut jacobian = DMatrix::<f64>::zeros(active.len(), n);
    for (row, &k) in active.iter().enumerate() {
        for j in 0..n {
            jacobian[(row, j)] = all[k * n + j];
        }
    }
    let normal = jacobian.transpose() * &jacobian;
    let eigen = SymmetricEigen::new(normal);
    let largest = eigen.eigenvalues.iter().copied().fold(0.0, f64::max);
    let keep: Vec<usize> = (0..n)
        .filter(|&i| eigen.eigenvalues[i] <= 1e-12 * largest.max(f64::MIN_POSITIVE))
        .collect();
    let mut basis = DMatrix::<f64>::zeros(n, keep.len());
    for (c, &i) in keep.iter().enumerate() {
        basis.set_column(c, &DVector::from(eigen.eigenvectors.column(i)));
    }
    basis
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::{spread, Profile};
    use crate::primitive::{Cylinder, Primitive};
    use crate::sketch::{StrokeClass, StrokeId};
    use crate::snap::{snap, SnapContext, SnapSettings};

    /// The drawn curves of `truth` (outlines and both end ellipses, sampled densely), as
    /// a context.
    fn drawing_of(truth: &Primitive) -> SnapContext {
        let shape = truth.current_shape();
        let strokes: Vec<(Vec<DVec2>, StrokeClass)> = shape
            .curves
            .iter()
            .filter(|c| c.visible)
            .map(|c| {
                let class = match c.class {
                    crate::primitive::CurveClass::Silhouette => StrokeClass::Silhouette,
                    _ => StrokeClass::Feature,
                };
                // The view plane's y runs up, the sketch's down.
                let points = c
                    .curve
                    .points(64)
                    .iter()
                    .map(|p| DVec2::new(p.x, -p.y))
                    .collect();
                (points, class)
            })
            .collect();
        SnapContext::new(
            strokes
                .iter()
                .enumerate()
                .map(|(i, (p, c))| (StrokeId(i as u32), p.as_slice(), *c)),
        )
    }

    fn can(axis: DVec3) -> Primitive {
        Primitive::Cylinder(Cylinder {
            center: DVec3::new(200.0, -200.0, 0.0),
            axis: axis.normalize(),
            length: 120.0,
            radius: 30.0,
        })
    }

    #[test]
    fn a_can_seen_along_its_axis_has_a_loose_length_and_one_seen_from_the_side_does_not() {
        let settings = SnapSettings::default();
        let mut lengths = Vec::new();
        for axis in [DVec3::new(0.0, 1.0, 0.4), DVec3::new(0.0, 0.2, 1.0)] {
            let truth = can(axis);
            let result = snap(&drawing_of(&truth), &truth, &settings).expect("it snaps");
            let s = spread(
                &result.primitive,
                &result.assignment,
                result.rms,
                Profile::Smooth,
            )
            .expect("finite");
            assert!(s.centre < 0.01 && s.radius < 0.02, "{s:?}");
            lengths.push(s.length);
        }
        assert!(lengths[0] < 0.03, "side view: {lengths:?}");
        assert!(lengths[1] > 3.0 * lengths[0], "end view: {lengths:?}");
    }

    #[test]
    fn a_pose_its_own_strokes_would_move_is_as_loose_as_the_move() {
        let settings = SnapSettings::default();
        let truth = can(DVec3::new(0.0, 1.0, 0.4));
        let result = snap(&drawing_of(&truth), &truth, &settings).expect("it snaps");
        let Primitive::Cylinder(fitted) = &result.primitive else {
            unreachable!("a cylinder snaps to a cylinder")
        };
        let wider = Primitive::Cylinder(Cylinder {
            radius: 1.3 * fitted.radius,
            ..*fitted
        });
        let at_rest = spread(
            &result.primitive,
            &result.assignment,
            result.rms,
            Profile::Smooth,
        )
        .expect("finite");
        let moved =
            spread(&wider, &result.assignment, result.rms, Profile::Smooth).expect("finite");
        assert!(at_rest.radius < 0.02, "{at_rest:?}");
        // Its strokes settle it 30 % narrower: the spread holds that move.
        assert!((moved.radius - 0.3).abs() < 0.05, "{moved:?}");
    }
}
