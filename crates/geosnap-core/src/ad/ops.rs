//! The operations of the tape: each forward formula sits next to its local partial
//! derivatives in one `match`, so the two can be audited side by side.
//!
//! Non-smooth operations (`abs`, `min`, `max`, `hypot` at the origin) return a
//! subgradient: the derivative of one of the pieces that meet at the kink.

/// One operation of an expression graph or compiled tape.
///
/// Leaves (`Var`, `Param`, `Const`) carry no arguments; unary operations one, binary
/// operations two, and `Sum` any number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Op {
    /// The variable with this index.
    Var(u32),
    /// The parameter with this index.
    Param(u32),
    /// A constant, stored as its bit pattern so the op can be hashed.
    Const(u64),
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    /// `a²`, kept apart from `Powi(2)` because sums of squares are the common case.
    Square,
    /// `aᵏ` for an integer `k`.
    Powi(i32),
    /// `aᵖ` for a constant real `p` (stored as bits).
    Powf(u64),
    /// `aᵇ` with both operands expressions.
    Pow,
    Sqrt,
    Exp,
    Ln,
    Sin,
    Cos,
    Tan,
    /// `atan2(y, x)` with the arguments in that order.
    Atan2,
    Abs,
    Hypot,
    Min,
    Max,
    /// The n-ary sum of its arguments.
    Sum,
    /// The Euclidean distance from a point p to the ellipse E(θ) = c + A·cos θ + B·sin θ
    /// (A, B conjugate semi-diameters). Arguments: cₓ, c_y, Aₓ, A_y, Bₓ, B_y, pₓ, p_y.
    EllipseDistance,
    /// The Euclidean distance from a point p to the segment from a to b. Arguments:
    /// aₓ, a_y, bₓ, b_y, pₓ, p_y.
    SegmentDistance,
    /// The Euclidean distance from a point p to the polyline through n ≥ 2 vertices: the
    /// least of its segments' [`Op::SegmentDistance`]s, the first on a tie, with that
    /// segment's partials (see [`polyline_distance`]). Arguments: x₀, y₀, …, xₙ₋₁, yₙ₋₁,
    /// pₓ, p_y.
    PolylineDistance,
}

impl Op {
    /// Computes the value of the op from its argument values and, when `partials` is
    /// given, writes ∂value/∂argᵢ into `partials[i]`.
    ///
    /// `args` and `partials` have the op's arity. Leaves are not evaluated here.
    #[inline]
    pub(crate) fn apply(self, args: &[f64], partials: Option<&mut [f64]>) -> f64 {
        match partials {
            Some(p) => self.eval::<true>(args, p),
            None => self.eval::<false>(args, &mut []),
        }
    }

    /// [`Op::apply`] specialised at compile time: with `PARTIALS` it writes the local
    /// derivatives into `partials`, without it `partials` is not touched (it may be
    /// empty) and the derivative formulas are compiled away. Inlined into the tape's
    /// sweeps, so each op costs a jump and its arithmetic.
    #[inline(always)]
    #[expect(
        clippy::inline_always,
        reason = "inlining into the two sweeps removes the per-op call; measured in benches/ad.rs"
    )]
    #[expect(
        clippy::too_many_lines,
        reason = "one match holds every op's formula and partials side by side, by design"
    )]
    pub(crate) fn eval<const PARTIALS: bool>(self, args: &[f64], partials: &mut [f64]) -> f64 {
        // Unary and binary arguments, read once; `Sum` reads the whole slice.
        let a = args.first().copied().unwrap_or(0.0);
        let b = args.get(1).copied().unwrap_or(0.0);
        macro_rules! out {
            ($value:expr, [$($d:expr),*]) => {{
                let value = $value;
                if PARTIALS {
                    let ds = [$($d),*];
                    partials[..ds.len()].copy_from_slice(&ds);
                }
                value
            }};
        }
        match self {
            Self::Var(_) | Self::Param(_) => 0.0,
            Self::Const(bits) => f64::from_bits(bits),
            Self::Neg => out!(-a, [-1.0]),
            Self::Add => out!(a + b, [1.0, 1.0]),
            Self::Sub => out!(a - b, [1.0, -1.0]),
            Self::Mul => out!(a * b, [b, a]),
            Self::Div => {
                let v = a / b;
                out!(v, [1.0 / b, -v / b])
            }
            Self::Square => out!(a * a, [2.0 * a]),
            Self::Powi(k) => match k {
                0 => out!(1.0, [0.0]),
                1 => out!(a, [1.0]),
                _ => {
                    // k − 1 overflows only for k = i32::MIN, where powf is exact enough.
                    let below = k
                        .checked_sub(1)
                        .map_or_else(|| a.powf(f64::from(k) - 1.0), |k1| a.powi(k1));
                    out!(a.powi(k), [f64::from(k) * below])
                }
            },
            Self::Powf(bits) => {
                let p = f64::from_bits(bits);
                out!(a.powf(p), [p * a.powf(p - 1.0)])
            }
            Self::Pow => {
                let v = a.powf(b);
                // d/db aᵇ = aᵇ·ln a; at a = 0 the limit from the right is 0.
                let db = if v == 0.0 { 0.0 } else { v * a.ln() };
                out!(v, [b * a.powf(b - 1.0), db])
            }
            Self::Sqrt => {
                let s = a.sqrt();
                out!(s, [0.5 / s])
            }
            Self::Exp => {
                let e = a.exp();
                out!(e, [e])
            }
            Self::Ln => out!(a.ln(), [1.0 / a]),
            Self::Sin => out!(a.sin(), [a.cos()]),
            Self::Cos => out!(a.cos(), [-a.sin()]),
            Self::Tan => {
                let t = a.tan();
                out!(t, [1.0 + t * t])
            }
            Self::Atan2 => {
                // y = a, x = b.
                let r2 = a * a + b * b;
                let (dy, dx) = if r2 == 0.0 {
                    (0.0, 0.0)
                } else {
                    (b / r2, -a / r2)
                };
                out!(a.atan2(b), [dy, dx])
            }
            Self::Abs => {
                let s = if a > 0.0 {
                    1.0
                } else if a < 0.0 {
                    -1.0
                } else {
                    0.0
                };
                out!(a.abs(), [s])
            }
            Self::Hypot => {
                let h = a.hypot(b);
                let (da, db) = if h == 0.0 { (0.0, 0.0) } else { (a / h, b / h) };
                out!(h, [da, db])
            }
            Self::Min => {
                if a <= b {
                    out!(a, [1.0, 0.0])
                } else {
                    out!(b, [0.0, 1.0])
                }
            }
            Self::Max => {
                if a >= b {
                    out!(a, [1.0, 0.0])
                } else {
                    out!(b, [0.0, 1.0])
                }
            }
            Self::Sum => {
                if PARTIALS {
                    partials.fill(1.0);
                }
                args.iter().sum()
            }
            // Both distances are minima over a curve parameter, so by the envelope
            // theorem their gradient is the gradient of |p − q| with the closest point q
            // held at its parameter: g = (q − p)/|q − p| for q, −g for p.
            Self::EllipseDistance => {
                let (c, a_vec, b_vec, p) = (
                    [args[0], args[1]],
                    [args[2], args[3]],
                    [args[4], args[5]],
                    [args[6], args[7]],
                );
                let theta = closest_ellipse_angle(c, a_vec, b_vec, p);
                let (sin, cos) = theta.sin_cos();
                let q = [
                    c[0] + a_vec[0] * cos + b_vec[0] * sin,
                    c[1] + a_vec[1] * cos + b_vec[1] * sin,
                ];
                let d = (q[0] - p[0]).hypot(q[1] - p[1]);
                let (gx, gy) = if d > 0.0 {
                    ((q[0] - p[0]) / d, (q[1] - p[1]) / d)
                } else {
                    (0.0, 0.0)
                };
                out!(
                    d,
                    [gx, gy, gx * cos, gy * cos, gx * sin, gy * sin, -gx, -gy]
                )
            }
            Self::SegmentDistance => {
                let foot =
                    SegmentFoot::of([args[0], args[1]], [args[2], args[3]], [args[4], args[5]]);
                let d = foot.distance();
                if PARTIALS {
                    partials[..6].copy_from_slice(&foot.partials(d));
                }
                d
            }
            Self::PolylineDistance => {
                polyline_distance::<PARTIALS>(args.len(), |i| args[i], partials)
            }
        }
    }

    /// The number of arguments the op takes, or `None` for the n-ary `Sum`.
    pub(crate) fn arity(self) -> Option<usize> {
        match self {
            Self::Var(_) | Self::Param(_) | Self::Const(_) => Some(0),
            Self::Neg
            | Self::Square
            | Self::Powi(_)
            | Self::Powf(_)
            | Self::Sqrt
            | Self::Exp
            | Self::Ln
            | Self::Sin
            | Self::Cos
            | Self::Tan
            | Self::Abs => Some(1),
            Self::Add
            | Self::Sub
            | Self::Mul
            | Self::Div
            | Self::Pow
            | Self::Atan2
            | Self::Hypot
            | Self::Min
            | Self::Max => Some(2),
            Self::Sum | Self::PolylineDistance => None,
            Self::EllipseDistance => Some(8),
            Self::SegmentDistance => Some(6),
        }
    }

    /// Whether the op is a leaf of the graph.
    pub(crate) fn is_leaf(self) -> bool {
        matches!(self, Self::Var(_) | Self::Param(_) | Self::Const(_))
    }
}

/// The closest point q = a + t·(b − a) of a segment to a point p, as
/// [`Op::SegmentDistance`] and [`Op::PolylineDistance`] compute it.
#[derive(Clone, Copy, Debug)]
struct SegmentFoot {
    /// The fraction along the segment.
    t: f64,
    /// q − p.
    dx: f64,
    dy: f64,
}

impl SegmentFoot {
    #[inline(always)]
    #[expect(
        clippy::inline_always,
        reason = "the innermost step of the tape's distance ops, called per segment"
    )]
    fn of([ax, ay]: [f64; 2], [bx, by]: [f64; 2], [px, py]: [f64; 2]) -> Self {
        let (ux, uy) = (bx - ax, by - ay);
        let len2 = ux * ux + uy * uy;
        let t = if len2 > 0.0 {
            (((px - ax) * ux + (py - ay) * uy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (qx, qy) = (ax + t * ux, ay + t * uy);
        Self {
            t,
            dx: qx - px,
            dy: qy - py,
        }
    }

    /// |q − p|², as a sum of two squares (within a few units in the last place).
    fn square(&self) -> f64 {
        self.dx * self.dx + self.dy * self.dy
    }

    /// |q − p|.
    fn distance(&self) -> f64 {
        self.dx.hypot(self.dy)
    }

    /// The partials of the distance `d` (= [`SegmentFoot::distance`]) with respect to
    /// aₓ, a_y, bₓ, b_y, pₓ, p_y.
    fn partials(&self, d: f64) -> [f64; 6] {
        let t = self.t;
        let (gx, gy) = if d > 0.0 {
            (self.dx / d, self.dy / d)
        } else {
            (0.0, 0.0)
        };
        [(1.0 - t) * gx, (1.0 - t) * gy, t * gx, t * gy, -gx, -gy]
    }
}

/// How much larger than the least squared distance a segment's squared distance may be
/// and its distance still be computed by [`polyline_distance`]: far more than the
/// rounding of a sum of two squares (a few units in the last place), so that a segment
/// ruled out is farther than the nearest one by more than the rounding of `hypot`.
const RULED_OUT: f64 = 1e-9;

/// Below this squared distance no segment is ruled out (the squares may underflow).
const TINY_SQUARE: f64 = 1e-300;

/// At most this many segments may be within [`RULED_OUT`] of the nearest one in
/// [`polyline_distance`] (ties at the vertices they share, mostly) before it falls back
/// to the plain fold.
const NEAREST: usize = 4;

/// [`Op::PolylineDistance`] of `n` arguments read through `arg`: exactly (value and
/// partials) what folding the [`Op::SegmentDistance`]s of the segments with [`Op::Min`],
/// first to last, gives (the first segment wins a tie; a NaN distance wins over the ones
/// before it), without the square root of most segments.
///
/// A segment whose squared distance `dx² + dy²` (of the same foot whose `hypot` the
/// fold takes) exceeds the least one by more than [`RULED_OUT`] cannot be the nearest,
/// nor tie with it once rounded, so only the segments within that margin of the least
/// square are folded, in order. A non-finite square (an overflow, a NaN), or more than
/// [`NEAREST`] segments within the margin, and every segment is folded as by the ops.
#[inline]
pub(crate) fn polyline_distance<const PARTIALS: bool>(
    n: usize,
    arg: impl Fn(usize) -> f64,
    partials: &mut [f64],
) -> f64 {
    if PARTIALS {
        partials.fill(0.0);
    }
    let vertices = n.saturating_sub(2) / 2;
    if vertices < 2 {
        return 0.0;
    }
    let p = [arg(n - 2), arg(n - 1)];
    let vertex = |i: usize| [arg(2 * i), arg(2 * i + 1)];
    let limit = |least: f64| least * (1.0 + RULED_OUT) + TINY_SQUARE;
    // The segments within the margin of the least square so far, in order:
    // (segment, foot, square).
    let none = (0, SegmentFoot::of([0.0; 2], [0.0; 2], [0.0; 2]), 0.0);
    let mut nearest = [none; NEAREST];
    let mut count = 0;
    let mut least = f64::INFINITY;
    let mut plain = false;
    let mut a = vertex(0);
    for i in 0..vertices - 1 {
        let b = vertex(i + 1);
        let foot = SegmentFoot::of(a, b, p);
        a = b;
        let square = foot.square();
        if !square.is_finite() {
            plain = true;
            break;
        }
        if square > limit(least) {
            continue;
        }
        if square < least {
            least = square;
            let mut kept = 0;
            for k in 0..count {
                if nearest[k].2 <= limit(least) {
                    nearest[kept] = nearest[k];
                    kept += 1;
                }
            }
            count = kept;
        }
        if count == NEAREST {
            plain = true;
            break;
        }
        nearest[count] = (i, foot, square);
        count += 1;
    }
    // The fold's running minimum: (distance, segment, its foot).
    let mut best: Option<(f64, usize, SegmentFoot)> = None;
    let mut fold = |i: usize, foot: SegmentFoot| {
        let d = foot.distance();
        // `Op::Min`: the running minimum stays unless it is ≤ the new distance.
        if best.is_none_or(|(m, ..)| !(m <= d)) {
            best = Some((d, i, foot));
        }
    };
    if plain {
        for i in 0..vertices - 1 {
            fold(i, SegmentFoot::of(vertex(i), vertex(i + 1), p));
        }
    } else {
        for &(i, foot, _) in &nearest[..count] {
            fold(i, foot);
        }
    }
    let Some((d, i, foot)) = best else {
        return 0.0;
    };
    if PARTIALS {
        let [dax, day, dbx, dby, dpx, dpy] = foot.partials(d);
        partials[2 * i..2 * i + 4].copy_from_slice(&[dax, day, dbx, dby]);
        partials[n - 2] = dpx;
        partials[n - 1] = dpy;
    }
    d
}

/// The parameter θ of the point of E(θ) = c + A·cos θ + B·sin θ closest to p: the best
/// of 32 evenly spaced angles, refined by safeguarded Newton steps on |E(θ) − p|².
pub(crate) fn closest_ellipse_angle(c: [f64; 2], a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> f64 {
    const SCAN: usize = 32;
    let d = [c[0] - p[0], c[1] - p[1]];
    // Squared distance at the angle with this (sin, cos).
    let h = |s: f64, co: f64| {
        let e = [d[0] + a[0] * co + b[0] * s, d[1] + a[1] * co + b[1] * s];
        e[0] * e[0] + e[1] * e[1]
    };
    // The scan turns (cos, sin) by a fixed rotation rather than calling sin_cos 32 times
    // (the rounding over 32 turns is far below what a starting point needs).
    let (step_sin, step_cos) = (std::f64::consts::TAU / SCAN as f64).sin_cos();
    let (mut s, mut co) = (0.0f64, 1.0f64);
    let mut best = 0.0;
    let mut best_h = f64::INFINITY;
    for k in 0..SCAN {
        let v = h(s, co);
        if v < best_h {
            best_h = v;
            best = std::f64::consts::TAU * k as f64 / SCAN as f64;
        }
        (s, co) = (s * step_cos + co * step_sin, co * step_cos - s * step_sin);
    }
    let max_step = std::f64::consts::PI / SCAN as f64;
    let (mut s, mut co) = best.sin_cos();
    for _ in 0..30 {
        let e = [d[0] + a[0] * co + b[0] * s, d[1] + a[1] * co + b[1] * s];
        let e1 = [-a[0] * s + b[0] * co, -a[1] * s + b[1] * co];
        let e2 = [-a[0] * co - b[0] * s, -a[1] * co - b[1] * s];
        let g = e[0] * e1[0] + e[1] * e1[1];
        let curvature = e1[0] * e1[0] + e1[1] * e1[1] + e[0] * e2[0] + e[1] * e2[1];
        let step = if curvature > 0.0 {
            (-g / curvature).clamp(-max_step, max_step)
        } else {
            -g.signum() * max_step * 0.5
        };
        // Accept only steps that do not increase the distance (the function is not convex).
        let candidate = best + step;
        let (cs, cc) = candidate.sin_cos();
        let v = h(cs, cc);
        if v <= best_h {
            best = candidate;
            best_h = v;
            (s, co) = (cs, cc);
        } else {
            break;
        }
        if step.abs() < 1e-13 {
            break;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::Op;

    /// Central difference of one argument of an op.
    fn central_difference(op: Op, args: &[f64], i: usize) -> f64 {
        let h = 1e-6 * args[i].abs().max(1.0);
        let mut plus = args.to_vec();
        let mut minus = args.to_vec();
        plus[i] += h;
        minus[i] -= h;
        (op.apply(&plus, None) - op.apply(&minus, None)) / (2.0 * h)
    }

    #[test]
    fn partials_match_central_differences_at_smooth_points() {
        let cases: Vec<(Op, Vec<f64>)> = vec![
            (Op::Neg, vec![0.7]),
            (Op::Add, vec![0.7, -1.3]),
            (Op::Sub, vec![0.7, -1.3]),
            (Op::Mul, vec![0.7, -1.3]),
            (Op::Div, vec![0.7, -1.3]),
            (Op::Square, vec![-1.3]),
            (Op::Powi(3), vec![-1.3]),
            (Op::Powi(-2), vec![1.3]),
            (Op::Powf(2.5_f64.to_bits()), vec![1.3]),
            (Op::Pow, vec![1.3, 0.4]),
            (Op::Sqrt, vec![1.3]),
            (Op::Exp, vec![0.3]),
            (Op::Ln, vec![1.3]),
            (Op::Sin, vec![0.3]),
            (Op::Cos, vec![0.3]),
            (Op::Tan, vec![0.3]),
            (Op::Atan2, vec![0.3, -0.8]),
            (Op::Abs, vec![-0.3]),
            (Op::Hypot, vec![0.3, -0.8]),
            (Op::Min, vec![0.3, -0.8]),
            (Op::Max, vec![0.3, -0.8]),
            (Op::Sum, vec![0.3, -0.8, 2.0, 4.0]),
            (
                Op::EllipseDistance,
                vec![0.1, -0.2, 2.0, 0.5, -0.3, 0.8, 3.0, 1.5],
            ),
            (
                Op::EllipseDistance,
                vec![0.0, 0.0, 2.0, 0.0, 0.0, 1.0, 0.3, 0.2],
            ),
            (Op::SegmentDistance, vec![0.0, 0.0, 2.0, 1.0, 0.7, 1.9]),
            (Op::SegmentDistance, vec![0.0, 0.0, 2.0, 1.0, 3.7, 1.9]),
        ];
        for (op, args) in cases {
            let mut partials = vec![0.0; args.len()];
            op.apply(&args, Some(&mut partials));
            for (i, d) in partials.iter().enumerate() {
                let fd = central_difference(op, &args, i);
                assert!(
                    (d - fd).abs() <= 1e-6 * fd.abs().max(1.0),
                    "{op:?} arg {i}: tape {d}, finite difference {fd}"
                );
            }
        }
    }

    #[test]
    fn ellipse_distance_is_the_true_distance() {
        // Axis-aligned ellipse with semi-axes 3 and 1: the point (0, 3) is 2 from (0, 1);
        // a point inside, (2.9, 0), is 0.1 from (3, 0).
        let e = |px: f64, py: f64| {
            Op::EllipseDistance.apply(&[0.0, 0.0, 3.0, 0.0, 0.0, 1.0, px, py], None)
        };
        assert!((e(0.0, 3.0) - 2.0).abs() < 1e-12);
        assert!((e(2.9, 0.0) - 0.1).abs() < 1e-12);
        // A degenerate (flat) ellipse is the segment from (−3, 0) to (3, 0).
        let flat = Op::EllipseDistance.apply(&[0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 1.0, 2.0], None);
        assert!((flat - 2.0).abs() < 1e-9, "{flat}");
        let seg = Op::SegmentDistance.apply(&[0.0, 0.0, 2.0, 0.0, 3.0, 4.0], None);
        assert!((seg - 17f64.sqrt()).abs() < 1e-12);
    }

    /// A small deterministic generator of numbers in [0, 1).
    fn noise(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Value and gradient of the distance from `p` to the polyline of `vertices` (as
    /// variables), one node or the segments folded with `min` (`fused`).
    fn polyline_distance(vertices: &[[f64; 2]], p: [f64; 2], fused: bool) -> (f64, Vec<f64>) {
        use crate::ad::{Graph, Tape};
        let g = Graph::new();
        let x: Vec<f64> = vertices.iter().flatten().copied().collect();
        let vars = g.vars(x.len());
        let points: Vec<[_; 2]> = vars.chunks(2).map(|c| [c[0], c[1]]).collect();
        let p = glam::DVec2::from_array(p);
        let d = if fused {
            g.polyline_distance(&points, p)
        } else {
            points
                .windows(2)
                .map(|w| g.segment_distance(w[0], w[1], p))
                .reduce(crate::ad::Expr::min)
                .unwrap_or_else(|| g.constant(0.0))
        };
        // Through a square, as the snapping objective uses it.
        let mut tape = Tape::compile(&g, &[d.square() * 0.5 + d]);
        let mut grad = vec![0.0; x.len()];
        let value = tape.gradient(&x, &mut grad);
        (value, grad)
    }

    #[test]
    fn a_polyline_distance_is_the_fold_of_its_segments_to_the_bit() {
        let mut seed = 19;
        let bits = |(v, g): (f64, Vec<f64>)| {
            (
                v.to_bits(),
                g.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
            )
        };
        let mut cases: Vec<(Vec<[f64; 2]>, [f64; 2])> = Vec::new();
        for n in [2, 3, 5, 17] {
            for _ in 0..300 {
                let mut at = [0.0, 0.0];
                let vertices: Vec<[f64; 2]> = (0..n)
                    .map(|_| {
                        at = [
                            at[0] + noise(&mut seed) - 0.2,
                            at[1] + noise(&mut seed) - 0.5,
                        ];
                        at
                    })
                    .collect();
                let p = [
                    noise(&mut seed) * n as f64 - 1.0,
                    noise(&mut seed) * 2.0 - 1.0,
                ];
                cases.push((vertices, p));
            }
        }
        // Ties: a point as far from two segments (symmetric), on a vertex, on a segment,
        // repeated vertices, a closed outline, and non-finite vertices.
        let square = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]];
        for p in [
            [0.5, 0.5],
            [1.0, 0.0],
            [0.5, 0.0],
            [2.0, 2.0],
            [0.5, 0.25],
            [-1.0, -1.0],
        ] {
            cases.push((square.clone(), p));
        }
        cases.push((
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [2.0, 0.0]],
            [1.0, 1.0],
        ));
        cases.push((vec![[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]], [0.0, 0.0]));
        cases.push((vec![[0.0, 0.0], [1e200, 0.0], [2.0, 1.0]], [1.0, 3.0]));
        cases.push((
            vec![[0.0, 0.0], [1.0, f64::NAN], [2.0, 1.0], [3.0, 0.0]],
            [1.0, 3.0],
        ));
        cases.push((
            vec![[0.0, 0.0], [1.0, 0.0], [2.0, f64::INFINITY]],
            [1.0, 3.0],
        ));
        cases.push((
            vec![[1e-170, 0.0], [0.0, 1e-170], [-1e-170, 0.0]],
            [0.0, 0.0],
        ));
        // Many segments as near: a hexagon round the point, a stroke retraced five times.
        let hexagon: Vec<[f64; 2]> = (0..=6)
            .map(|k| {
                let a = std::f64::consts::TAU * f64::from(k) / 6.0;
                [a.cos(), a.sin()]
            })
            .collect();
        cases.push((hexagon, [0.0, 0.0]));
        let retraced: Vec<[f64; 2]> = (0..11).map(|k| [f64::from(k % 2), 0.0]).collect();
        cases.push((retraced.clone(), [0.5, 1.0]));
        cases.push((retraced, [2.0, 1.0]));
        // A long polyline, with a NaN far along it.
        let mut long: Vec<[f64; 2]> = (0..40).map(|i| [f64::from(i), 0.0]).collect();
        cases.push((long.clone(), [36.5, 1.0]));
        long[35][1] = f64::NAN;
        cases.push((long.clone(), [36.5, 1.0]));
        cases.push((long, [3.5, 1.0]));
        for (vertices, p) in &cases {
            let fused = polyline_distance(vertices, *p, true);
            let folded = polyline_distance(vertices, *p, false);
            assert_eq!(bits(fused), bits(folded), "{vertices:?} from {p:?}");
        }
    }

    #[test]
    fn extreme_integer_powers_do_not_overflow() {
        let mut p = [0.0];
        let v = Op::Powi(i32::MIN).apply(&[1.0], Some(&mut p));
        assert!((v - 1.0).abs() < f64::EPSILON, "1^k = 1");
        assert!(
            (p[0] - f64::from(i32::MIN)).abs() < 1.0,
            "d/da a^k at 1 is k"
        );
    }

    #[test]
    fn kinks_return_a_subgradient() {
        let mut p = [9.0; 2];
        assert!(Op::Abs.apply(&[0.0], Some(&mut p[..1])).abs() < f64::EPSILON);
        assert!(p[0].abs() < f64::EPSILON, "abs'(0) is 0, a subgradient");
        Op::Hypot.apply(&[0.0, 0.0], Some(&mut p));
        assert!(p.iter().all(|d| d.abs() < f64::EPSILON), "hypot at origin");
        Op::Min.apply(&[1.0, 1.0], Some(&mut p));
        assert!(
            (p[0] + p[1] - 1.0).abs() < f64::EPSILON,
            "min tie picks one side"
        );
    }
}
