//! Our own L-BFGS (Liu & Nocedal 1989; two-loop recursion, Nocedal & Wright Alg. 7.4)
//! with a strong-Wolfe line search (Nocedal & Wright Alg. 3.5 and 3.6; secant and
//! quadratic interpolation in the zoom phase) that also accepts the approximate Wolfe
//! conditions of Hager & Zhang (2005). Near a minimum, differences of the function value
//! drown in round-off long before the gradient does; judging steps by the derivative
//! there lets the iterates converge to working precision instead of stopping at
//! √ε-accuracy, which is what a constraint tolerance of 1e-9 needs.
//!
//! Everything is bounded: at most [`MAX_LINE_SEARCH`] evaluations per line search and the
//! caller's iteration cap. A trial point whose value is NaN or infinite is treated as a
//! step too long (the search backtracks) rather than as a failure of the whole solve; a
//! non-finite value at the start point still aborts. Buffers are allocated once per
//! inner solve.

use std::collections::VecDeque;

use super::inner::{Abort, InnerFunction, InnerLimits, InnerOutcome, InnerStatus, Minimizer};

/// Evaluations one line search may spend.
const MAX_LINE_SEARCH: usize = 30;
/// Sufficient-decrease constant of the Wolfe conditions.
const C1: f64 = 1e-4;
/// Curvature constant of the strong Wolfe conditions (0.9 is the usual quasi-Newton
/// choice).
const C2: f64 = 0.9;
/// Relative slack of the approximate sufficient-decrease test (Hager & Zhang use 1e-6;
/// we only need to see past round-off).
const APPROX_EPS: f64 = 1e-12;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// ‖a − b‖∞.
fn s_last_norm(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0, |m: f64, (x, y)| m.max((x - y).abs()))
}

fn norm2(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// A point of the line search: step, value, directional derivative.
#[derive(Clone, Copy, Debug)]
struct Sample {
    step: f64,
    value: f64,
    slope: f64,
}

/// Our bounded L-BFGS as a [`Minimizer`].
#[derive(Debug, Default)]
pub(crate) struct BoundedLbfgs {
    s: VecDeque<Vec<f64>>,
    y: VecDeque<Vec<f64>>,
    rho: VecDeque<f64>,
}

/// The line search's result.
enum Search {
    /// Accepted; `trial`/`trial_grad` hold the point and its gradient.
    Accepted(f64),
    /// No acceptable step was found.
    Failed,
    Aborted(Abort),
}

struct LineSearch<'a> {
    function: &'a mut dyn InnerFunction,
    x: &'a [f64],
    direction: &'a [f64],
    trial: &'a mut [f64],
    trial_grad: &'a mut [f64],
    f0: f64,
    slope0: f64,
}

impl LineSearch<'_> {
    /// Evaluates at `step`; a non-finite value reads as +∞ (step too long).
    fn sample(&mut self, step: f64) -> Result<Sample, Abort> {
        for ((t, x), d) in self.trial.iter_mut().zip(self.x).zip(self.direction) {
            *t = x + step * d;
        }
        match self.function.eval(self.trial, self.trial_grad) {
            Ok(value) => Ok(Sample {
                step,
                value,
                slope: dot(self.trial_grad, self.direction),
            }),
            Err(Abort::NonFinite) => Ok(Sample {
                step,
                value: f64::INFINITY,
                slope: f64::NAN,
            }),
            Err(abort) => Err(abort),
        }
    }

    /// Sufficient decrease (Armijo), or the approximate form of Hager & Zhang:
    /// φ(α) ≤ φ(0) + ε|φ(0)|, which still holds when φ no longer decreases measurably
    /// at working precision but its derivative does.
    fn decrease_ok(&self, s: Sample) -> bool {
        s.value <= self.f0 + C1 * s.step * self.slope0
            || s.value <= self.f0 + APPROX_EPS * self.f0.abs()
    }

    /// The curvature half of the strong Wolfe conditions: |φ'(α)| ≤ −c₂φ'(0).
    fn curvature_ok(&self, s: Sample) -> bool {
        s.slope.abs() <= -C2 * self.slope0
    }

    fn accept(&self, s: Sample) -> bool {
        self.decrease_ok(s) && self.curvature_ok(s)
    }

    fn run(&mut self, first_step: f64) -> Search {
        let mut lo = Sample {
            step: 0.0,
            value: self.f0,
            slope: self.slope0,
        };
        let mut step = first_step;
        for i in 0..MAX_LINE_SEARCH {
            let s = match self.sample(step) {
                Ok(s) => s,
                Err(a) => return Search::Aborted(a),
            };
            if self.accept(s) {
                return Search::Accepted(s.value);
            }
            if !self.decrease_ok(s) || s.slope.partial_cmp(&0.0) != Some(std::cmp::Ordering::Less) {
                return self.zoom(lo, s, MAX_LINE_SEARCH - i - 1);
            }
            // Still descending with an acceptable value: expand.
            lo = s;
            step *= 4.0;
        }
        Search::Failed
    }

    /// Shrinks `[lo, hi]` (Nocedal & Wright Alg. 3.6 with the update rules of Hager &
    /// Zhang): `lo` descends (φ' < 0) with an acceptable value, `hi` either ascends
    /// (φ' ≥ 0) or has too large a value, so a Wolfe point lies between them.
    fn zoom(&mut self, mut lo: Sample, mut hi: Sample, budget: usize) -> Search {
        for _ in 0..budget {
            let width = hi.step - lo.step;
            let step = if hi.slope >= 0.0 && hi.value.is_finite() {
                // Secant on the derivative: where φ' crosses zero.
                (lo.step * hi.slope - hi.step * lo.slope) / (hi.slope - lo.slope)
            } else if hi.value.is_finite() {
                // Minimiser of the quadratic through lo (value, slope) and hi (value).
                let denom = 2.0 * (hi.value - lo.value - lo.slope * width);
                if denom > 0.0 {
                    lo.step - lo.slope * width * width / denom
                } else {
                    lo.step + 0.5 * width
                }
            } else {
                lo.step + 0.5 * width
            };
            // Safeguard: stay in the inner 80 % of the interval.
            let (a, b) = (lo.step + 0.1 * width, hi.step - 0.1 * width);
            let step = if step.is_finite() {
                step.clamp(a.min(b), a.max(b))
            } else {
                lo.step + 0.5 * width
            };
            let s = match self.sample(step) {
                Ok(s) => s,
                Err(a) => return Search::Aborted(a),
            };
            if self.accept(s) {
                return Search::Accepted(s.value);
            }
            if s.slope >= 0.0 || !self.decrease_ok(s) {
                hi = s;
            } else {
                lo = s;
            }
            if (hi.step - lo.step).abs() <= f64::EPSILON * lo.step.abs().max(hi.step.abs()) {
                break;
            }
        }
        // No Wolfe point within the budget: settle for the descending point, if any.
        if lo.step > 0.0 {
            match self.sample(lo.step) {
                Ok(s) if s.value.is_finite() => Search::Accepted(s.value),
                Ok(_) => Search::Failed,
                Err(a) => Search::Aborted(a),
            }
        } else {
            Search::Failed
        }
    }
}

impl BoundedLbfgs {
    /// Drops the curvature pairs: the next direction is steepest descent.
    fn forget(&mut self) {
        self.s.clear();
        self.y.clear();
        self.rho.clear();
    }

    /// The two-loop direction into `d` and its slope gᵀd; when that is not a descent
    /// direction (curvature information went stale), the pairs are dropped and the
    /// steepest-descent direction is taken instead.
    fn descent_direction(&mut self, g: &[f64], d: &mut [f64], alpha: &mut [f64]) -> f64 {
        self.direction(g, d, alpha);
        let slope = dot(g, d);
        if slope.partial_cmp(&0.0) == Some(std::cmp::Ordering::Less) {
            return slope;
        }
        self.forget();
        self.direction(g, d, alpha);
        dot(g, d)
    }

    /// Keeps the curvature pair of the step from `x` (gradient `g`) to `trial`
    /// (gradient `trial_grad`), the oldest dropped beyond `memory` pairs; skipped when
    /// sᵀy is not safely positive.
    fn remember(&mut self, x: &[f64], g: &[f64], trial: &[f64], trial_grad: &[f64], memory: usize) {
        let n = x.len();
        let mut s_new = if self.s.len() == memory {
            self.rho.pop_front();
            self.y.pop_front();
            self.s.pop_front().unwrap_or_default()
        } else {
            vec![0.0; n]
        };
        let mut y_new = vec![0.0; n];
        for i in 0..n {
            s_new[i] = trial[i] - x[i];
            y_new[i] = trial_grad[i] - g[i];
        }
        let sy = dot(&s_new, &y_new);
        if sy > f64::EPSILON * dot(&y_new, &y_new) {
            self.rho.push_back(1.0 / sy);
            self.s.push_back(s_new);
            self.y.push_back(y_new);
        }
    }

    /// d = −H·g by the two-loop recursion.
    fn direction(&self, g: &[f64], d: &mut [f64], alpha: &mut [f64]) {
        for (di, gi) in d.iter_mut().zip(g) {
            *di = -gi;
        }
        let m = self.s.len();
        for k in (0..m).rev() {
            let a = self.rho[k] * dot(&self.s[k], d);
            alpha[k] = a;
            for (di, yi) in d.iter_mut().zip(&self.y[k]) {
                *di -= a * yi;
            }
        }
        if let (Some(s), Some(y)) = (self.s.back(), self.y.back()) {
            let gamma = dot(s, y) / dot(y, y);
            for di in d.iter_mut() {
                *di *= gamma;
            }
        }
        for (k, a) in alpha.iter().enumerate().take(m) {
            let b = self.rho[k] * dot(&self.y[k], d);
            for (di, si) in d.iter_mut().zip(&self.s[k]) {
                *di += (a - b) * si;
            }
        }
    }
}

impl Minimizer for BoundedLbfgs {
    fn minimize(
        &mut self,
        function: &mut dyn InnerFunction,
        x: &mut Vec<f64>,
        limits: InnerLimits,
    ) -> InnerOutcome {
        let n = x.len();
        self.forget();
        let mut g = vec![0.0; n];
        let mut f = match function.eval(x, &mut g) {
            Ok(f) => f,
            Err(abort) => {
                return InnerOutcome {
                    status: InnerStatus::Aborted(abort),
                    iterations: 0,
                }
            }
        };
        let mut d = vec![0.0; n];
        let mut alpha = vec![0.0; limits.memory];
        let mut trial = vec![0.0; n];
        let mut trial_grad = vec![0.0; n];
        let mut iterations = 0;
        let status = loop {
            if function.goal_met() || limits.converged(&*function, f, norm2(&g)) {
                break InnerStatus::Converged;
            }
            if iterations >= limits.max_iterations {
                break InnerStatus::IterationLimit;
            }
            let slope = self.descent_direction(&g, &mut d, &mut alpha);
            // Without curvature information the first step is scaled to move ~1 unit.
            let first_step = if self.s.is_empty() {
                (1.0 / d.iter().fold(0.0f64, |m, v| m.max(v.abs()))).min(1.0)
            } else {
                1.0
            };
            let mut search = LineSearch {
                function: &mut *function,
                x,
                direction: &d,
                trial: &mut trial,
                trial_grad: &mut trial_grad,
                f0: f,
                slope0: slope,
            };
            let f_new = match search.run(first_step) {
                Search::Accepted(v) => v,
                Search::Failed if !self.s.is_empty() => {
                    // Retry once along steepest descent before giving up.
                    self.forget();
                    continue;
                }
                Search::Failed => break InnerStatus::NoProgress,
                Search::Aborted(a) => break InnerStatus::Aborted(a),
            };
            iterations += 1;
            self.remember(x, &g, &trial, &trial_grad, limits.memory);
            let step_size = s_last_norm(&trial, x);
            x.copy_from_slice(&trial);
            g.copy_from_slice(&trial_grad);
            f = f_new;
            if step_size <= f64::EPSILON * x.iter().fold(1.0f64, |m, v| m.max(v.abs())) {
                // The point no longer moves at working precision.
                break if limits.converged(&*function, f, norm2(&g)) {
                    InnerStatus::Converged
                } else {
                    InnerStatus::NoProgress
                };
            }
        };
        InnerOutcome { status, iterations }
    }
}

#[cfg(test)]
mod tests {
    use super::BoundedLbfgs;
    use crate::solve::inner::{Abort, InnerFunction, InnerLimits, InnerStatus, Minimizer};

    struct Rosenbrock;
    impl InnerFunction for Rosenbrock {
        fn eval(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, Abort> {
            let (a, b) = (x[0], x[1]);
            g[0] = -2.0 * (1.0 - a) - 400.0 * a * (b - a * a);
            g[1] = 200.0 * (b - a * a);
            Ok((1.0 - a).powi(2) + 100.0 * (b - a * a).powi(2))
        }
    }

    /// `x²` for x < 1, NaN beyond: a step past 1 must be backtracked.
    struct NanWall;
    impl InnerFunction for NanWall {
        fn eval(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, Abort> {
            if x[0] > 1.0 {
                return Err(Abort::NonFinite);
            }
            g[0] = 2.0 * (x[0] - 0.9);
            Ok((x[0] - 0.9).powi(2))
        }
    }

    fn limits() -> InnerLimits {
        InnerLimits {
            gradient_tol: 1e-10,
            gradient_cap: f64::INFINITY,
            max_iterations: 500,
            memory: 8,
        }
    }

    #[test]
    fn minimises_rosenbrock() {
        let mut x = vec![-1.2, 1.0];
        let out = BoundedLbfgs::default().minimize(&mut Rosenbrock, &mut x, limits());
        assert_eq!(out.status, InnerStatus::Converged);
        assert!(
            (x[0] - 1.0).abs() < 1e-8 && (x[1] - 1.0).abs() < 1e-8,
            "{x:?}"
        );
    }

    #[test]
    fn backtracks_from_nan_trial_points() {
        let mut x = vec![-50.0];
        let out = BoundedLbfgs::default().minimize(&mut NanWall, &mut x, limits());
        assert_eq!(out.status, InnerStatus::Converged);
        assert!((x[0] - 0.9).abs() < 1e-8, "{x:?}");
    }

    #[test]
    fn respects_the_iteration_cap() {
        let mut x = vec![-1.2, 1.0];
        let mut l = limits();
        l.max_iterations = 3;
        let out = BoundedLbfgs::default().minimize(&mut Rosenbrock, &mut x, l);
        assert_eq!(out.status, InnerStatus::IterationLimit);
        assert_eq!(out.iterations, 3);
    }
}
