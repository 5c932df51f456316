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
//! φ = ½Σcᵢ² + ½Σmin(0, gⱼ)² alone is minimised from the current point. Feasibility is
//! judged by the violation itself: the phase stops at the first point whose ‖c‖∞ is
//! within the constraint tolerance, whatever its gradient, and its gradient test is
//! relative to the size of the violation, ‖∇φ‖₂ ≤ tol·‖c‖₂ (with `tol` the gradient
//! tolerance). The problem is *infeasible* only when the phase ends with ‖c‖∞ clearly
//! above the tolerance ([`CLEARLY_INFEASIBLE`] times it: a non-zero local minimum of the
//! violation); otherwise the solve goes on from the restored point, and a solve that
//! needs more than two restorations is *stalled*.
//!
//! Gradient tests are relative to the size of the function: the solve has converged
//! when ‖∇ₓL‖∞ ≤ tol·max(1, |f(x)|), and each inner solve stops when
//! ‖∇L‖₂ ≤ min(tol·max(1, |L|), 0.1·μ·`constraint_tol`). An inner solve that stopped
//! without reaching its gradient test (the line search failed or the value stopped
//! changing) ends the solve as *stalled* when the point is feasible; otherwise the μ
//! schedule goes on.

use std::ops::ControlFlow;
use std::time::Duration;

use super::bounded_lbfgs::BoundedLbfgs;
use super::inner::{Abort, InnerFunction, InnerLimits, InnerStatus, Minimizer};
use super::lbfgs::ArgminLbfgs;
use super::report::{
    CancelFlag, Clock, Iterate, Multipliers, SolveContext, SolveObserver, SolveReport, Start,
    Termination,
};
use super::settings::{AugLagSettings, InnerSolver};
use super::{Problem, SolveError};
use crate::ad::Tape;

/// Outer iterations at the largest penalty over which the violation must fall by 1 %.
const STALL_WINDOW: usize = 3;
/// Restoration phases one solve may run before it is declared stalled.
const MAX_RESTORATIONS: usize = 2;
/// A restoration that ends with ‖c‖∞ above this many constraint tolerances finds the
/// problem infeasible; between one and this many the solve goes on.
const CLEARLY_INFEASIBLE: f64 = 10.0;

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
        if let (Some(clock), Some(limit)) = (self.clock, self.time_limit)
            && clock.elapsed() >= limit
        {
            return Err(Abort::TimeLimit);
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

/// The violation φ = ½Σcᵢ² + ½Σmin(0, gⱼ)² alone, minimised by the restoration phase.
/// Its goal is feasibility: the first evaluated point whose ‖c‖∞ is within `tolerance`
/// is kept in `feasible`, and the minimiser stops there.
struct Violation2<'p, 'b, 'c> {
    problem: &'p mut Problem,
    seeds: Vec<f64>,
    budget: &'b mut Budget<'c>,
    /// The constraint tolerance.
    tolerance: f64,
    /// The first feasible point evaluated.
    feasible: Option<Vec<f64>>,
}

impl InnerFunction for Violation2<'_, '_, '_> {
    fn eval(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, Abort> {
        self.budget.spend()?;
        let ne = self.problem.equality_count();
        let values = self.problem.tape.forward(x);
        let mut v = 0.0;
        let mut max = 0.0f64;
        self.seeds[0] = 0.0;
        for (k, &c) in values[1..].iter().enumerate() {
            let r = if k < ne { c } else { c.min(0.0) };
            v += 0.5 * r * r;
            max = max.max(r.abs());
            self.seeds[1 + k] = r;
        }
        let v = finish(&mut self.problem.tape, &self.seeds, v, grad)?;
        if self.feasible.is_none() && max <= self.tolerance {
            self.feasible = Some(x.to_vec());
        }
        Ok(v)
    }

    /// ‖c‖₂ = √(2φ): the gradient Jᵀc is judged against the violation it comes from.
    fn gradient_scale(&self, value: f64) -> f64 {
        (2.0 * value.max(0.0)).sqrt()
    }

    fn goal_met(&self) -> bool {
        self.feasible.is_some()
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

/// Runs the solve to its end; see the module docs and [`AugLag`].
pub(crate) fn run(
    problem: &mut Problem,
    start: &Start,
    settings: &AugLagSettings,
    context: SolveContext<'_>,
) -> Result<SolveReport, SolveError> {
    let mut state = AugLag::new(problem, start, settings, context)?;
    let termination = loop {
        if let ControlFlow::Break(termination) = state.step() {
            break termination;
        }
    };
    Ok(state.report(termination))
}

/// The checked start multipliers: zeros when none are given, inequality ones clamped to
/// ν ≥ 0.
fn start_multipliers(start: &Start, ne: usize, ni: usize) -> Result<Multipliers, SolveError> {
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
    Ok(multipliers)
}

/// A solve in progress: everything the outer loop carries from one iteration to the
/// next. [`AugLag::step`] runs one outer iteration and says whether the solve goes on;
/// [`AugLag::report`] ends it.
pub(crate) struct AugLag<'p, 'c> {
    problem: &'p mut Problem,
    settings: &'p AugLagSettings,
    observer: Option<&'c mut dyn SolveObserver>,
    budget: Budget<'c>,
    minimizer: Box<dyn Minimizer>,
    /// The number of equality constraints.
    ne: usize,
    multipliers: Multipliers,
    /// The penalty μ.
    mu: f64,
    /// The violation target `C_max`.
    c_max: f64,
    x: Vec<f64>,
    grad: Vec<f64>,
    seeds: Vec<f64>,
    inner_iterations: u64,
    outer: usize,
    /// Violations at the largest penalty, for the stall test.
    history: Vec<f64>,
    restorations: usize,
}

impl<'p, 'c> AugLag<'p, 'c> {
    /// A solve of `problem` from `start`, before its first outer iteration.
    pub(crate) fn new(
        problem: &'p mut Problem,
        start: &Start,
        settings: &'p AugLagSettings,
        context: SolveContext<'c>,
    ) -> Result<Self, SolveError> {
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
        let multipliers = start_multipliers(start, ne, ni)?;
        let mu = start
            .penalty
            .filter(|m| m.is_finite())
            .map_or(settings.mu0(), |m| {
                m.clamp(settings.mu0(), settings.mu_max())
            });
        let minimizer: Box<dyn Minimizer> = match settings.inner_solver() {
            InnerSolver::Argmin => Box::new(ArgminLbfgs),
            InnerSolver::Bounded => Box::new(BoundedLbfgs::default()),
        };
        Ok(Self {
            problem,
            settings,
            observer: context.observer,
            budget: Budget {
                evaluations: 0,
                max_evaluations: settings.max_evaluations(),
                cancel: context.cancel,
                clock: context.clock,
                time_limit: settings.time_limit(),
            },
            minimizer,
            ne,
            multipliers,
            mu,
            c_max: 1.0 / mu.powf(settings.alpha()),
            x: start.x.clone(),
            grad: vec![0.0; n],
            seeds: vec![0.0; 1 + ne + ni],
            inner_iterations: 0,
            outer: 0,
            history: Vec::new(),
            restorations: 0,
        })
    }

    /// Time since the clock started (zero without a clock).
    fn elapsed(&self) -> Duration {
        self.budget.clock.map_or(Duration::ZERO, Clock::elapsed)
    }

    /// One outer iteration: the inner solve, the multiplier updates, the convergence
    /// tests, the μ schedule and, when the violation stopped falling at the largest
    /// penalty, the restoration phase. `Break` says why the solve ends.
    pub(crate) fn step(&mut self) -> ControlFlow<Termination> {
        let settings = self.settings;
        let ne = self.ne;
        let ni = self.multipliers.inequality.len();
        if self.outer >= settings.max_outer_iterations() {
            return ControlFlow::Break(Termination::MaxOuterIterations);
        }
        self.outer += 1;
        // The inner tolerance is relative to |L|, but must also resolve the constraints:
        // moving cᵢ by the constraint tolerance changes ∇L by about μ·tol·|∇cᵢ|, so it is
        // capped at a tenth of that.
        let limits = InnerLimits {
            gradient_tol: settings.gradient_tol(),
            gradient_cap: 0.1 * self.mu * settings.constraint_tol(),
            max_iterations: settings.max_inner_iterations(),
            memory: settings.lbfgs_memory(),
        };
        let mut lagrangian = Lagrangian {
            problem: &mut *self.problem,
            lambda: &self.multipliers.equality,
            nu: &self.multipliers.inequality,
            mu: self.mu,
            seeds: vec![0.0; 1 + ne + ni],
            budget: &mut self.budget,
        };
        let outcome = self
            .minimizer
            .minimize(&mut lagrangian, &mut self.x, limits);
        self.inner_iterations += outcome.iterations;
        if let InnerStatus::Aborted(abort) = outcome.status {
            return ControlFlow::Break(stop_reason(abort));
        }
        let v = self.update_multipliers()?;

        let feasible = v.measure_max <= settings.constraint_tol();
        let stationary = v.gradient_norm <= settings.gradient_tol() * v.objective.abs().max(1.0);
        if feasible && stationary {
            return ControlFlow::Break(Termination::Converged);
        }
        if feasible && outcome.status.is_stuck() {
            // The inner solve cannot improve a feasible point (its line search failed or
            // its value stopped changing): the gradient norm is at the round-off floor
            // of this problem.
            return ControlFlow::Break(Termination::Stalled);
        }

        // The accelerated μ schedule (lines 10–15).
        if v.measure_sq < self.c_max {
            self.c_max /= self.mu.powf(settings.alpha());
        } else {
            self.mu = (self.mu * settings.beta()).min(settings.mu_max());
            self.c_max = 1.0 / self.mu.powf(settings.alpha());
        }

        // At the largest penalty, a violation that stopped falling calls for the
        // restoration phase, which tells an infeasible problem from a slow one.
        if feasible || self.mu < settings.mu_max() {
            self.history.clear();
            return ControlFlow::Continue(());
        }
        self.history.push(v.max);
        let history = &self.history;
        let stalled = history.len() > STALL_WINDOW
            && v.max > 0.99 * history[history.len() - 1 - STALL_WINDOW];
        if !stalled {
            return ControlFlow::Continue(());
        }
        if self.restorations == MAX_RESTORATIONS {
            return ControlFlow::Break(Termination::Stalled);
        }
        self.restore()
    }

    /// Re-evaluates at the accepted point, updates the multipliers (line 8 of the paper's
    /// procedure, and its PHR analogue) and shows the iterate to the observer; the
    /// violation before the update, with the gradient norm.
    fn update_multipliers(&mut self) -> ControlFlow<Termination, Measured> {
        let ne = self.ne;
        let mu = self.mu;
        // Re-evaluate at the accepted point (outside the budget): its gradient is ∇ₓ of
        // the Lagrangian with the updated multipliers, and the tape holds c(x).
        let parts = (
            &self.multipliers.equality[..],
            &self.multipliers.inequality[..],
            mu,
        );
        if augmented(
            self.problem,
            &self.x,
            parts,
            &mut self.seeds,
            &mut self.grad,
        )
        .is_err()
        {
            return ControlFlow::Break(Termination::NumericalFailure);
        }
        let values = self.problem.tape.output_values().to_vec();
        let gradient_norm = self.grad.iter().fold(0.0f64, |m, g| m.max(g.abs()));

        for (lambda, c) in self.multipliers.equality.iter_mut().zip(&values[1..=ne]) {
            *lambda += mu * c;
        }
        let nu_old = self.multipliers.inequality.clone();
        for (nu, g) in self
            .multipliers
            .inequality
            .iter_mut()
            .zip(&values[1 + ne..])
        {
            *nu = (*nu - mu * g).max(0.0);
        }
        let v = violation(&values[1..], ne, &nu_old, mu);
        let elapsed = self.elapsed();
        if let Some(observer) = self.observer.as_deref_mut() {
            observer.iterate(&Iterate {
                outer: self.outer,
                x: &self.x,
                objective: values[0],
                max_violation: v.max,
                gradient_norm,
                penalty: mu,
                inner_iterations: self.inner_iterations,
                elapsed,
            });
        }
        ControlFlow::Continue(Measured {
            objective: values[0],
            max: v.max,
            measure_max: v.measure_max,
            measure_sq: v.measure_sq,
            gradient_norm,
        })
    }

    /// The restoration phase: minimises the violation alone from the current point
    /// until it is within the constraint tolerance (see the module docs).
    /// `Break(Infeasible)` when it ends clearly violated (a local minimum of the violation
    /// that is not zero); otherwise the solve goes on from the restored point.
    fn restore(&mut self) -> ControlFlow<Termination> {
        let ne = self.ne;
        let ni = self.multipliers.inequality.len();
        let tolerance = self.settings.constraint_tol();
        self.restorations += 1;
        self.history.clear();
        let limits = InnerLimits {
            gradient_tol: self.settings.gradient_tol(),
            gradient_cap: f64::INFINITY,
            max_iterations: self.settings.max_inner_iterations(),
            memory: self.settings.lbfgs_memory(),
        };
        let mut phase = Violation2 {
            problem: &mut *self.problem,
            seeds: vec![0.0; 1 + ne + ni],
            budget: &mut self.budget,
            tolerance,
            feasible: None,
        };
        let restored = self.minimizer.minimize(&mut phase, &mut self.x, limits);
        let feasible = phase.feasible.take();
        self.inner_iterations += restored.iterations;
        if let Some(point) = feasible {
            self.x = point;
            return ControlFlow::Continue(());
        }
        if let InnerStatus::Aborted(abort) = restored.status {
            return ControlFlow::Break(stop_reason(abort));
        }
        let values = self.problem.tape.eval(&self.x).to_vec();
        let after = violation(&values[1..], ne, &self.multipliers.inequality, self.mu).max;
        if after > CLEARLY_INFEASIBLE * tolerance {
            return ControlFlow::Break(Termination::Infeasible);
        }
        ControlFlow::Continue(())
    }

    /// Ends the solve with `termination`: the report at the current point.
    pub(crate) fn report(mut self, termination: Termination) -> SolveReport {
        let ne = self.ne;
        // The final point's values (the tape may hold a line-search trial point).
        let values = self.problem.tape.forward(&self.x).to_vec();
        let v = violation(&values[1..], ne, &self.multipliers.inequality, self.mu);
        let gradient_norm = lagrangian_gradient(self.problem, &self.multipliers, &mut self.grad);
        let elapsed = self.elapsed();
        SolveReport {
            objective: values[0],
            max_violation: v.max,
            gradient_norm,
            worst_constraint: v.worst,
            x: self.x,
            multipliers: self.multipliers,
            penalty: self.mu,
            outer_iterations: self.outer,
            inner_iterations: self.inner_iterations,
            evaluations: self.budget.evaluations,
            elapsed,
            termination,
        }
    }
}

/// What an outer iteration measured at its point, before the multiplier update.
struct Measured {
    /// f(x).
    objective: f64,
    /// ‖c‖∞ with inequality violations max(0, −g).
    max: f64,
    /// max of the measure V.
    measure_max: f64,
    /// ΣV².
    measure_sq: f64,
    /// ‖∇ₓL‖∞.
    gradient_norm: f64,
}

/// ‖∇f + Σλᵢ∇cᵢ − Σνⱼ∇gⱼ‖∞ after a forward sweep at the point.
fn lagrangian_gradient(problem: &mut Problem, m: &Multipliers, grad: &mut [f64]) -> f64 {
    let mut seeds = vec![1.0];
    seeds.extend(&m.equality);
    seeds.extend(m.inequality.iter().map(|nu| -nu));
    problem.tape.reverse(&seeds, grad);
    grad.iter().fold(0.0, |acc: f64, g| acc.max(g.abs()))
}

#[cfg(test)]
mod tests {
    use std::ops::ControlFlow;

    use super::{run, AugLag};
    use crate::ad::Graph;
    use crate::solve::{AugLagSettings, Iterate, Problem, SolveContext, Start};

    /// The closest point to (2, 1) on the unit circle in the upper half-plane.
    fn problem(g: &Graph) -> Problem {
        let x = g.var();
        let y = g.var();
        Problem::builder(g, (x - 2.0).square() + (y - 1.0).square())
            .equality("on the circle", x.square() + y.square() - 1.0)
            .inequality("upper half", y)
            .build()
    }

    #[test]
    fn stepping_by_hand_gives_the_report_of_run() {
        let settings = AugLagSettings::default();
        let start = Start::cold(&[0.0, 1.0]);
        let g = Graph::new();
        let mut seen = Vec::new();
        let mut record = |i: &Iterate<'_>| seen.push(i.x.to_vec());
        let context = SolveContext::default().with_observer(&mut record);
        let whole = run(&mut problem(&g), &start, &settings, context).expect("valid start");

        let mut stepped = Vec::new();
        let mut record = |i: &Iterate<'_>| stepped.push(i.x.to_vec());
        let context = SolveContext::default().with_observer(&mut record);
        let g = Graph::new();
        let mut p = problem(&g);
        let mut state = AugLag::new(&mut p, &start, &settings, context).expect("valid start");
        let mut steps = 0;
        let termination = loop {
            steps += 1;
            match state.step() {
                ControlFlow::Continue(()) => {}
                ControlFlow::Break(t) => break t,
            }
        };
        let by_hand = state.report(termination);
        assert_eq!(by_hand, whole, "bit for bit the same report");
        assert!(by_hand.termination.is_converged());
        assert_eq!(steps, whole.outer_iterations);
        assert_eq!(stepped, seen, "the observer sees the same iterates");
    }
}
