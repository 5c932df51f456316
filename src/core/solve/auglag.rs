//! The augmented-Lagrangian outer loop with the accelerated μ schedule of Shtof,
//! Agathos, Gingold, Shamir and Cohen-Or, *Geosemantic Snapping for Sketch-Based
//! Modeling* (Eurographics 2013, optimisation details: procedure
//! AUGMENTED-LAGRANGIAN-ACCEL).
//!
//! For min f(x) s.t. cᵢ(x) = 0, gⱼ(x) ≥ 0 each outer iteration minimises
//!
//! ```text
//! L(x; λ, ν, μ) = f(x) + Σᵢ [λᵢcᵢ(x) + (μ/2)cᵢ(x)²] + Σⱼ [max(0, νⱼ − μgⱼ(x))² − νⱼ²] / (2μ)
//! ```
//!
//! with L-BFGS from the previous x (the inequality term is the Powell–Hestenes–Rockafellar
//! form, Nocedal & Wright §17.4), then updates λᵢ ← λᵢ + μcᵢ(x), νⱼ ← max(0, νⱼ − μgⱼ(x)),
//! and then, with V the violation measure below: if ΣV² < `C_max` then `C_max` ← `C_max`/μ^α,
//! else μ ← min(βμ, `μ_max`) and `C_max` ← 1/μ^α.
//!
//! The violation measure is |cᵢ| for equalities and |min(gⱼ, νⱼ/μ)| for inequalities
//! (Birgin & Martínez), which is zero exactly when gⱼ ≥ 0 and νⱼgⱼ = 0.
//!
//! Unlike the original code every solve ends: caps on outer iterations, inner iterations,
//! evaluations (which bound every line search) and time; a cancel flag; NaN detection;
//! and a restoration phase for hopeless-looking cases: when, at the largest penalty, the
//! violation has not fallen by 1 % over three outer iterations, the violation
//! ½Σcᵢ² + ½Σmin(0, gⱼ)² alone is minimised from the current point. If it cannot be
//! brought within the tolerance the problem is *infeasible* (the point is a non-zero
//! local minimum of the violation); otherwise the solve goes on from the restored point,
//! and a solve that needs more than two restorations is *stalled*.

use std::time::Duration;

use super::bounded_lbfgs::BoundedLbfgs;
use super::inner::{Abort, InnerFunction, InnerLimits, InnerStatus, Minimizer};
use super::lbfgs::ArgminLbfgs;
use super::report::{
    CancelFlag, Clock, Iterate, Multipliers, SolveObserver, SolveReport, Start, Termination,
};
use super::settings::{AugLagSettings, InnerSolver};
use super::{Problem, SolveError};
use crate::core::ad::Tape;

/// Outer iterations at the largest penalty over which the violation must fall by 1 %.
const STALL_WINDOW: usize = 3;
/// Restoration phases one solve may run before it is declared stalled.
const MAX_RESTORATIONS: usize = 2;

/// The termination an aborted evaluation leads to.
fn stop_reason(abort: Abort) -> Termination {
    match abort {
        Abort::Cancelled => Termination::Cancelled,
        Abort::TimeLimit => Termination::TimeLimit,
        Abort::EvaluationLimit => Termination::MaxEvaluations,
        Abort::NonFinite => Termination::NumericalFailure,
    }
}

/// The caps every evaluation checks first: cancel flag, time limit, evaluation count.
struct Budget<'a> {
    evaluations: u64,
    max_evaluations: u64,
    cancel: Option<&'a CancelFlag>,
    clock: Option<&'a dyn Clock>,
    time_limit: Option<Duration>,
}

impl Budget<'_> {
    /// Counts one evaluation, or says why there may be none.
    fn spend(&mut self) -> Result<(), Abort> {
        if self.cancel.is_some_and(CancelFlag::is_cancelled) {
            return Err(Abort::Cancelled);
        }
        if let (Some(clock), Some(limit)) = (self.clock, self.time_limit) {
            if clock.elapsed() >= limit {
                return Err(Abort::TimeLimit);
            }
        }
        if self.evaluations >= self.max_evaluations {
            return Err(Abort::EvaluationLimit);
        }
        self.evaluations += 1;
        Ok(())
    }
}

/// The augmented Lagrangian of a problem for fixed multipliers and penalty, as an
/// [`InnerFunction`].
struct Lagrangian<'p, 'b, 'c> {
    problem: &'p mut Problem,
    lambda: &'p [f64],
    nu: &'p [f64],
    mu: f64,
    seeds: Vec<f64>,
    budget: &'b mut Budget<'c>,
}

impl InnerFunction for Lagrangian<'_, '_, '_> {
    fn eval(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, Abort> {
        self.budget.spend()?;
        augmented(
            self.problem,
            x,
            (self.lambda, self.nu, self.mu),
            &mut self.seeds,
            grad,
        )
    }
}

/// L(x; λ, ν, μ) and its gradient (see the module docs).
fn augmented(
    problem: &mut Problem,
    x: &[f64],
    (lambda, nu, mu): (&[f64], &[f64], f64),
    seeds: &mut [f64],
    grad: &mut [f64],
) -> Result<f64, Abort> {
    let ne = lambda.len();
    let values = problem.tape.forward(x);
    let mut l = values[0];
    seeds[0] = 1.0;
    for (i, (&c, &lambda)) in values[1..=ne].iter().zip(lambda).enumerate() {
        l += lambda * c + 0.5 * mu * c * c;
        seeds[1 + i] = lambda + mu * c;
    }
    for (j, (&g, &nu)) in values[1 + ne..].iter().zip(nu).enumerate() {
        let t = (nu - mu * g).max(0.0);
        l += (t * t - nu * nu) / (2.0 * mu);
        seeds[1 + ne + j] = -t;
    }
    finish(&mut problem.tape, seeds, l, grad)
}

/// The violation ½Σcᵢ² + ½Σmin(0, gⱼ)² alone, minimised by the restoration phase.
struct Violation2<'p, 'b, 'c> {
    problem: &'p mut Problem,
    seeds: Vec<f64>,
    budget: &'b mut Budget<'c>,
}

impl InnerFunction for Violation2<'_, '_, '_> {
    fn eval(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, Abort> {
        self.budget.spend()?;
        let ne = self.problem.equality_count();
        let values = self.problem.tape.forward(x);
        let mut v = 0.0;
        self.seeds[0] = 0.0;
        for (k, &c) in values[1..].iter().enumerate() {
            let r = if k < ne { c } else { c.min(0.0) };
            v += 0.5 * r * r;
            self.seeds[1 + k] = r;
        }
        finish(&mut self.problem.tape, &self.seeds, v, grad)
    }
}

/// The reverse sweep and the finiteness checks shared by the inner functions.
fn finish(tape: &mut Tape, seeds: &[f64], value: f64, grad: &mut [f64]) -> Result<f64, Abort> {
    if !value.is_finite() {
        return Err(Abort::NonFinite);
    }
    tape.reverse(seeds, grad);
    if grad.iter().any(|g| !g.is_finite()) {
        return Err(Abort::NonFinite);
    }
    Ok(value)
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
    let mut seeds = vec![0.0; 1 + ne + ni];
    let mut budget = Budget {
        evaluations: 0,
        max_evaluations: settings.max_evaluations(),
        cancel,
        clock,
        time_limit: settings.time_limit(),
    };
    let mut inner_iterations = 0u64;
    let mut outer = 0usize;
    let mut minimizer: Box<dyn Minimizer> = match settings.inner_solver() {
        InnerSolver::Argmin => Box::new(ArgminLbfgs),
        InnerSolver::Bounded => Box::new(BoundedLbfgs::default()),
    };
    // Violations at the largest penalty, for the stall test.
    let mut history: Vec<f64> = Vec::new();
    let mut restorations = 0;

    let termination = loop {
        if outer >= settings.max_outer_iterations() {
            break Termination::MaxOuterIterations;
        }
        outer += 1;
        // The inner tolerance must also resolve the constraints: moving cᵢ by the
        // constraint tolerance changes ∇L by about μ·tol·|∇cᵢ|, so ask for a tenth of that.
        let limits = InnerLimits {
            gradient_tol: settings
                .gradient_tol()
                .min(0.1 * mu * settings.constraint_tol()),
            max_iterations: settings.max_inner_iterations(),
            memory: settings.lbfgs_memory(),
        };
        let mut lagrangian = Lagrangian {
            problem: &mut *problem,
            lambda: &multipliers.equality,
            nu: &multipliers.inequality,
            mu,
            seeds: vec![0.0; 1 + ne + ni],
            budget: &mut budget,
        };
        let outcome = minimizer.minimize(&mut lagrangian, &mut x, limits);
        inner_iterations += outcome.iterations;
        if let InnerStatus::Aborted(abort) = outcome.status {
            break stop_reason(abort);
        }
        // Re-evaluate at the accepted point (outside the budget): its gradient is ∇ₓ of
        // the Lagrangian with the updated multipliers, and the tape holds c(x).
        let parts = (&multipliers.equality[..], &multipliers.inequality[..], mu);
        if augmented(problem, &x, parts, &mut seeds, &mut grad).is_err() {
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
        if feasible && outcome.status == InnerStatus::NoProgress {
            // The line search cannot improve a feasible point: the gradient norm is at
            // the round-off floor of this problem.
            break Termination::Stalled;
        }

        // The accelerated μ schedule (lines 10–15).
        if v.measure_sq < c_max {
            c_max /= mu.powf(settings.alpha());
        } else {
            mu = (mu * settings.beta()).min(settings.mu_max());
            c_max = 1.0 / mu.powf(settings.alpha());
        }

        // At the largest penalty, a violation that stopped falling calls for the
        // restoration phase, which tells an infeasible problem from a slow one.
        if feasible || mu < settings.mu_max() {
            history.clear();
            continue;
        }
        history.push(v.max);
        let stalled = history.len() > STALL_WINDOW
            && v.max > 0.99 * history[history.len() - 1 - STALL_WINDOW];
        if !stalled {
            continue;
        }
        if restorations == MAX_RESTORATIONS {
            break Termination::Stalled;
        }
        restorations += 1;
        history.clear();
        let mut phase = Violation2 {
            problem: &mut *problem,
            seeds: vec![0.0; 1 + ne + ni],
            budget: &mut budget,
        };
        let restored = minimizer.minimize(&mut phase, &mut x, limits);
        inner_iterations += restored.iterations;
        if let InnerStatus::Aborted(abort) = restored.status {
            break stop_reason(abort);
        }
        let values = problem.tape.eval(&x).to_vec();
        let after = violation(&values[1..], ne, &multipliers.inequality, mu).max;
        if after > settings.constraint_tol() {
            // Even minimising the violation alone leaves it violated: a (local)
            // minimum of the violation that is not zero.
            break Termination::Infeasible;
        }
        // Feasible after all: go on from the restored point.
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
        evaluations: budget.evaluations,
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
