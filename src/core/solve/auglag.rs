//! The augmented-Lagrangian outer loop with the accelerated μ schedule of seed 002
//! (procedure AUGMENTED-LAGRANGIAN-ACCEL).
//!
//! For min f(x) s.t. cᵢ(x) = 0, gⱼ(x) ≥ 0 each outer iteration minimises
//!
//! ```text
//! L(x; λ, ν, μ) = f(x) + Σᵢ [λᵢcᵢ(x) + (μ/2)cᵢ(x)²] + Σⱼ [max(0, νⱼ − μgⱼ(x))² − νⱼ²] / (2μ)
//! ```
//!
//! with L-BFGS from the previous x (the inequality term is the Powell–Hestenes–Rockafellar
//! form, Nocedal & Wright §17.4), then updates λᵢ ← λᵢ + μcᵢ(x), νⱼ ← max(0, νⱼ − μgⱼ(x)),
//! and then, with V the violation measure below: if ΣV² < C_max then C_max ← C_max/μ^α,
//! else μ ← min(βμ, μ_max) and C_max ← 1/μ^α.
//!
//! The violation measure is |cᵢ| for equalities and |min(gⱼ, νⱼ/μ)| for inequalities
//! (Birgin & Martínez), which is zero exactly when gⱼ ≥ 0 and νⱼgⱼ = 0.
//!
//! Unlike the original code every solve ends: caps on outer iterations, inner iterations,
//! evaluations (which bound every line search) and time; a cancel flag; NaN detection;
//! and two tests for hopeless cases. *Infeasible*: at the largest penalty the point is a
//! stationary point of the violation ½‖c‖² with the constraints still violated, measured
//! scale-free as ‖Σcᵢ∇cᵢ‖ ≤ 10⁻⁶·Σ|cᵢ|‖∇cᵢ‖. *Stalled*: at the largest penalty the
//! violation has not fallen by 1 % over five outer iterations.

use std::time::Duration;

use super::bounded_lbfgs::BoundedLbfgs;
use super::inner::{Abort, InnerFunction, InnerLimits, InnerStatus, Minimizer};
use super::lbfgs::ArgminLbfgs;
use super::report::{
    CancelFlag, Clock, Iterate, Multipliers, SolveObserver, SolveReport, Start, Termination,
};
use super::settings::{AugLagSettings, InnerSolver};
use super::{Problem, SolveError};

/// Outer iterations at the largest penalty over which the violation must fall by 1 %.
const STALL_WINDOW: usize = 5;
/// The relative size of ‖Jᵀc‖ below which a violated point counts as a stationary
/// point of the violation.
const INFEASIBLE_RATIO: f64 = 1e-6;

/// The augmented Lagrangian of a problem for fixed multipliers and penalty, as an
/// [`InnerFunction`], with the solve's caps checked before every evaluation.
struct Lagrangian<'a> {
    problem: &'a mut Problem,
    lambda: &'a [f64],
    nu: &'a [f64],
    mu: f64,
    seeds: Vec<f64>,
    evaluations: &'a mut u64,
    max_evaluations: u64,
    cancel: Option<&'a CancelFlag>,
    clock: Option<&'a dyn Clock>,
    time_limit: Option<Duration>,
}

impl InnerFunction for Lagrangian<'_> {
    fn eval(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, Abort> {
        if self.cancel.is_some_and(CancelFlag::is_cancelled) {
            return Err(Abort::Cancelled);
        }
        if let (Some(clock), Some(limit)) = (self.clock, self.time_limit) {
            if clock.elapsed() >= limit {
                return Err(Abort::TimeLimit);
            }
        }
        if *self.evaluations >= self.max_evaluations {
            return Err(Abort::EvaluationLimit);
        }
        *self.evaluations += 1;
        let values = self.problem.tape.forward(x);
        let ne = self.lambda.len();
        let mu = self.mu;
        let mut l = values[0];
        self.seeds[0] = 1.0;
        for (i, (&c, &lambda)) in values[1..=ne].iter().zip(self.lambda).enumerate() {
            l += lambda * c + 0.5 * mu * c * c;
            self.seeds[1 + i] = lambda + mu * c;
        }
        for (j, (&g, &nu)) in values[1 + ne..].iter().zip(self.nu).enumerate() {
            let t = (nu - mu * g).max(0.0);
            l += (t * t - nu * nu) / (2.0 * mu);
            self.seeds[1 + ne + j] = -t;
        }
        if !l.is_finite() {
            return Err(Abort::NonFinite);
        }
        self.problem.tape.reverse(&self.seeds, grad);
        if grad.iter().any(|g| !g.is_finite()) {
            return Err(Abort::NonFinite);
        }
        Ok(l)
    }
}

/// Constraint state at a point: violation, complementarity-aware measure and the worst.
struct Violation {
    /// ‖c‖∞ with inequality violations max(0, −g).
    max: f64,
    /// The index of the largest violation, when there is one.
    worst: Option<usize>,
    /// max of the measure V (|c|, |min(g, ν/μ)|).
    measure_max: f64,
    /// ΣV².
    measure_sq: f64,
}

fn violation(values: &[f64], ne: usize, nu: &[f64], mu: f64) -> Violation {
    let mut v = Violation {
        max: 0.0,
        worst: None,
        measure_max: 0.0,
        measure_sq: 0.0,
    };
    for (k, &value) in values.iter().enumerate() {
        let (plain, measure) = if k < ne {
            (value.abs(), value.abs())
        } else {
            ((-value).max(0.0), value.min(nu[k - ne] / mu).abs())
        };
        if plain > v.max {
            v.max = plain;
            v.worst = Some(k);
        }
        v.measure_max = v.measure_max.max(measure);
        v.measure_sq += measure * measure;
    }
    v
}

/// Runs the solve; see the module docs.
#[expect(
    clippy::too_many_lines,
    reason = "the outer loop reads best as one piece, in the order of the paper's pseudocode"
)]
pub(crate) fn run(
    problem: &mut Problem,
    start: &Start,
    settings: &AugLagSettings,
    cancel: Option<&CancelFlag>,
    clock: Option<&dyn Clock>,
    observer: &mut dyn SolveObserver,
) -> Result<SolveReport, SolveError> {
    let n = problem.var_count();
    let ne = problem.equality_count();
    let ni = problem.inequality_count();
    if start.x.len() != n {
        return Err(SolveError::StartLength {
            expected: n,
            got: start.x.len(),
        });
    }
    if let Some(i) = start.x.iter().position(|v| !v.is_finite()) {
        return Err(SolveError::NonFiniteStart { index: i });
    }
    let mut multipliers = start.multipliers.clone().unwrap_or_else(|| Multipliers {
        equality: vec![0.0; ne],
        inequality: vec![0.0; ni],
    });
    if multipliers.equality.len() != ne || multipliers.inequality.len() != ni {
        return Err(SolveError::MultiplierLength {
            equalities: ne,
            inequalities: ni,
        });
    }
    if multipliers
        .equality
        .iter()
        .chain(&multipliers.inequality)
        .any(|m| !m.is_finite())
    {
        return Err(SolveError::NonFiniteMultipliers);
    }
    for nu in &mut multipliers.inequality {
        *nu = nu.max(0.0);
    }
    let elapsed = || clock.map_or(Duration::ZERO, Clock::elapsed);

    let mut mu = start
        .penalty
        .filter(|m| m.is_finite())
        .map_or(settings.mu0(), |m| {
            m.clamp(settings.mu0(), settings.mu_max())
        });
    let mut c_max = 1.0 / mu.powf(settings.alpha());
    let mut x = start.x.clone();
    let mut grad = vec![0.0; n];
    let mut evaluations = 0u64;
    let mut inner_iterations = 0u64;
    let mut outer = 0usize;
    let mut minimizer: Box<dyn Minimizer> = match settings.inner_solver() {
        InnerSolver::Argmin => Box::new(ArgminLbfgs),
        InnerSolver::Bounded => Box::new(BoundedLbfgs::default()),
    };
    // The inner gradient tolerance starts loose and tightens by 10× per outer iteration.
    let mut inner_tol: Option<f64> = None;
    let mut history: Vec<f64> = Vec::new();
    let mut infeasible_strikes = 0;

    let termination = loop {
        if outer >= settings.max_outer_iterations() {
            break Termination::MaxOuterIterations;
        }
        outer += 1;
        // The inner tolerance must also resolve the constraints: moving cᵢ by the
        // constraint tolerance changes ∇L by about μ·tol·|∇cᵢ|, so ask for a tenth of that.
        let tol = inner_tol
            .get_or_insert(settings.gradient_tol())
            .min(0.1 * mu * settings.constraint_tol());
        let mut lagrangian = Lagrangian {
            problem: &mut *problem,
            lambda: &multipliers.equality,
            nu: &multipliers.inequality,
            mu,
            seeds: vec![0.0; 1 + ne + ni],
            evaluations: &mut evaluations,
            max_evaluations: settings.max_evaluations(),
            cancel,
            clock,
            time_limit: settings.time_limit(),
        };
        let outcome = minimizer.minimize(
            &mut lagrangian,
            &mut x,
            InnerLimits {
                gradient_tol: tol,
                max_iterations: settings.max_inner_iterations(),
                memory: settings.lbfgs_memory(),
            },
        );
        inner_iterations += outcome.iterations;
        if let InnerStatus::Aborted(abort) = outcome.status {
            break match abort {
                Abort::Cancelled => Termination::Cancelled,
                Abort::TimeLimit => Termination::TimeLimit,
                Abort::EvaluationLimit => Termination::MaxEvaluations,
                Abort::NonFinite => Termination::NumericalFailure,
            };
        }
        // Re-evaluate at the accepted point: its gradient is ∇ₓ of the Lagrangian with
        // the updated multipliers, and the tape then holds c(x) and its partials.
        // This evaluation is not counted against the cap, so it cannot fail on it.
        lagrangian.max_evaluations = u64::MAX;
        if lagrangian.eval(&x, &mut grad).is_err() {
            break Termination::NumericalFailure;
        }
        let values = problem.tape.output_values().to_vec();
        let gradient_norm = grad.iter().fold(0.0f64, |m, g| m.max(g.abs()));

        // Multiplier updates (line 8 of the paper's procedure, and its PHR analogue).
        for (lambda, c) in multipliers.equality.iter_mut().zip(&values[1..=ne]) {
            *lambda += mu * c;
        }
        let nu_old = multipliers.inequality.clone();
        for (nu, g) in multipliers.inequality.iter_mut().zip(&values[1 + ne..]) {
            *nu = (*nu - mu * g).max(0.0);
        }
        let v = violation(&values[1..], ne, &nu_old, mu);
        observer.iterate(&Iterate {
            outer,
            x: &x,
            objective: values[0],
            max_violation: v.max,
            gradient_norm,
            penalty: mu,
            inner_iterations,
            elapsed: elapsed(),
        });

        let feasible = v.measure_max <= settings.constraint_tol();
        let stationary = gradient_norm <= settings.gradient_tol();
        if feasible && stationary {
            break Termination::Converged;
        }
        if feasible && outcome.status == InnerStatus::NoProgress && tol <= settings.gradient_tol() {
            // The line search cannot improve a feasible point at the tightest tolerance:
            // the gradient norm is at the round-off floor of this problem.
            break Termination::Stalled;
        }

        // The accelerated μ schedule (lines 10–15).
        if v.measure_sq < c_max {
            c_max /= mu.powf(settings.alpha());
        } else {
            mu = (mu * settings.beta()).min(settings.mu_max());
            c_max = 1.0 / mu.powf(settings.alpha());
        }
        inner_tol = Some((tol * 0.1).max(settings.gradient_tol()));

        if !feasible && mu >= settings.mu_max() {
            if violation_is_stationary(problem, &values[1..], ne) {
                infeasible_strikes += 1;
                if infeasible_strikes >= 2 {
                    break Termination::Infeasible;
                }
            } else {
                infeasible_strikes = 0;
            }
            history.push(v.measure_max);
            if history.len() > STALL_WINDOW {
                let old = history[history.len() - 1 - STALL_WINDOW];
                if v.measure_max > 0.99 * old {
                    break Termination::Stalled;
                }
            }
        }
    };

    // The final point's values (the tape may hold a line-search trial point).
    let values = problem.tape.forward(&x).to_vec();
    let v = violation(&values[1..], ne, &multipliers.inequality, mu);
    let gradient_norm = lagrangian_gradient(problem, &multipliers, &mut grad);
    Ok(SolveReport {
        objective: values[0],
        max_violation: v.max,
        gradient_norm,
        worst_constraint: v.worst,
        x,
        multipliers,
        penalty: mu,
        outer_iterations: outer,
        inner_iterations,
        evaluations,
        elapsed: elapsed(),
        termination,
    })
}

/// ‖∇f + Σλᵢ∇cᵢ − Σνⱼ∇gⱼ‖∞ after a forward sweep at the point.
fn lagrangian_gradient(problem: &mut Problem, m: &Multipliers, grad: &mut [f64]) -> f64 {
    let mut seeds = vec![1.0];
    seeds.extend(&m.equality);
    seeds.extend(m.inequality.iter().map(|nu| -nu));
    problem.tape.reverse(&seeds, grad);
    grad.iter().fold(0.0, |acc: f64, g| acc.max(g.abs()))
}

/// Whether the point (after a forward sweep there) is a stationary point of the
/// violation ½Σcᵢ² + ½Σmin(0, gⱼ)² while violated; see the module docs.
fn violation_is_stationary(problem: &mut Problem, constraints: &[f64], ne: usize) -> bool {
    let n = problem.var_count();
    let residual: Vec<f64> = constraints
        .iter()
        .enumerate()
        .map(|(k, &c)| if k < ne { c } else { c.min(0.0) })
        .collect();
    let mut seeds = vec![0.0];
    seeds.extend(&residual);
    let mut direction = vec![0.0; n];
    problem.tape.reverse(&seeds, &mut direction);
    let combined = direction.iter().map(|d| d * d).sum::<f64>().sqrt();
    // Σ|rₖ|·‖∇cₖ‖, one reverse sweep per violated constraint.
    let mut bound = 0.0;
    let mut row = vec![0.0; n];
    for (k, &r) in residual.iter().enumerate() {
        if r == 0.0 {
            continue;
        }
        seeds.fill(0.0);
        seeds[1 + k] = 1.0;
        problem.tape.reverse(&seeds, &mut row);
        bound += r.abs() * row.iter().map(|d| d * d).sum::<f64>().sqrt();
    }
    combined <= INFEASIBLE_RATIO * bound || bound == 0.0
}
