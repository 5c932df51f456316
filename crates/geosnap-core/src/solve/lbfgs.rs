//! The adapter to argmin's L-BFGS with the Moré–Thuente line search: the only file of
//! the crate that names argmin, so the inner solver can be swapped.
//!
//! argmin asks for the cost and the gradient separately, and its line search runs in an
//! inner executor without an iteration cap (argmin issue #497). The adapter therefore
//! evaluates both at once and caches the last point, and every evaluation goes through
//! [`InnerFunction::eval`], which refuses to run past the solve's evaluation cap, time
//! limit or cancel flag: that is what makes every line search end.
//!
//! argmin's own stopping test reports "converged" both when the gradient is small and
//! when the cost stopped changing. The adapter runs argmin's L-BFGS steps under its own
//! test instead ([`Stopping`]): only the gradient test of [`InnerLimits::converged`]
//! (or the function's goal) is convergence; a cost that stopped changing ends the run
//! as [`InnerStatus::Stalled`].

use std::cell::RefCell;

use argmin::core::{
    CostFunction, Executor, Gradient, IterState, Solver, State, TerminationReason,
    TerminationStatus, KV,
};
use argmin::solver::linesearch::MoreThuenteLineSearch;
use argmin::solver::quasinewton::LBFGS;

use super::inner::{Abort, InnerFunction, InnerLimits, InnerOutcome, InnerStatus, Minimizer};

/// argmin's error type carries this when an evaluation aborted.
#[derive(Debug)]
struct Aborted(Abort);

impl std::fmt::Display for Aborted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "evaluation aborted: {:?}", self.0)
    }
}

impl std::error::Error for Aborted {}

/// The evaluation cache shared by argmin's cost and gradient calls.
struct Cache<'f> {
    function: &'f mut dyn InnerFunction,
    x: Vec<f64>,
    value: f64,
    grad: Vec<f64>,
    valid: bool,
    best_x: Vec<f64>,
    best_value: f64,
    abort: Option<Abort>,
}

impl Cache<'_> {
    fn at(&mut self, x: &[f64]) -> Result<(), Abort> {
        if let Some(abort) = self.abort {
            return Err(abort);
        }
        if self.valid && self.x == x {
            return Ok(());
        }
        self.valid = false;
        match self.function.eval(x, &mut self.grad) {
            Ok(value) => {
                self.x.copy_from_slice(x);
                self.value = value;
                self.valid = true;
                if value < self.best_value {
                    self.best_value = value;
                    self.best_x.copy_from_slice(x);
                }
                Ok(())
            }
            Err(abort) => {
                self.abort = Some(abort);
                Err(abort)
            }
        }
    }
}

/// The inner problem as argmin sees it.
struct ArgminProblem<'c, 'f> {
    cache: &'c RefCell<Cache<'f>>,
}

impl CostFunction for ArgminProblem<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Self::Param) -> Result<f64, argmin::core::Error> {
        let mut cache = self.cache.borrow_mut();
        cache
            .at(x)
            .map_err(|a| argmin::core::Error::new(Aborted(a)))?;
        Ok(cache.value)
    }
}

impl Gradient for ArgminProblem<'_, '_> {
    type Param = Vec<f64>;
    type Gradient = Vec<f64>;

    fn gradient(&self, x: &Self::Param) -> Result<Vec<f64>, argmin::core::Error> {
        let mut cache = self.cache.borrow_mut();
        cache
            .at(x)
            .map_err(|a| argmin::core::Error::new(Aborted(a)))?;
        Ok(cache.grad.clone())
    }
}

/// argmin's L-BFGS with the Moré–Thuente line search on our vectors.
type Lbfgs = LBFGS<MoreThuenteLineSearch<Vec<f64>, Vec<f64>, f64>, Vec<f64>, Vec<f64>, f64>;

/// argmin's iteration state for [`Lbfgs`].
type LbfgsState = IterState<Vec<f64>, Vec<f64>, (), (), (), f64>;

/// How [`Stopping`] ends a run whose cost stopped changing.
const STALLED: &str = "the cost stopped changing";

/// Relative change of the cost (in units of its size) below which it has stopped
/// changing: a few units in the last place.
const STALL_TOL: f64 = 4.0 * f64::EPSILON;

/// argmin's L-BFGS steps under our stopping test: the gradient test of
/// [`InnerLimits::converged`] or the function's goal end the run as converged; a cost
/// that changed by at most [`STALL_TOL`] of its size ends it with [`STALLED`].
struct Stopping<'c, 'f> {
    lbfgs: Lbfgs,
    cache: &'c RefCell<Cache<'f>>,
    limits: InnerLimits,
}

impl<'c, 'f> Solver<ArgminProblem<'c, 'f>, LbfgsState> for Stopping<'c, 'f> {
    fn name(&self) -> &'static str {
        "L-BFGS (geosnap's stopping test)"
    }

    fn init(
        &mut self,
        problem: &mut argmin::core::Problem<ArgminProblem<'c, 'f>>,
        state: LbfgsState,
    ) -> Result<(LbfgsState, Option<KV>), argmin::core::Error> {
        self.lbfgs.init(problem, state)
    }

    fn next_iter(
        &mut self,
        problem: &mut argmin::core::Problem<ArgminProblem<'c, 'f>>,
        state: LbfgsState,
    ) -> Result<(LbfgsState, Option<KV>), argmin::core::Error> {
        self.lbfgs.next_iter(problem, state)
    }

    fn terminate(&mut self, state: &LbfgsState) -> TerminationStatus {
        let cache = self.cache.borrow();
        let cost = state.get_cost();
        let gradient_norm = state.get_gradient().map_or(f64::INFINITY, |g| {
            g.iter().map(|v| v * v).sum::<f64>().sqrt()
        });
        if cache.function.goal_met() || self.limits.converged(&*cache.function, cost, gradient_norm)
        {
            return TerminationStatus::Terminated(TerminationReason::SolverConverged);
        }
        if (state.get_prev_cost() - cost).abs() <= STALL_TOL * cost.abs() {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                STALLED.to_owned(),
            ));
        }
        TerminationStatus::NotTerminated
    }
}

/// The inner status of an argmin run that ended with `reason`.
fn status_of(reason: Option<&TerminationReason>) -> InnerStatus {
    match reason {
        Some(TerminationReason::MaxItersReached) => InnerStatus::IterationLimit,
        Some(TerminationReason::SolverConverged) => InnerStatus::Converged,
        Some(TerminationReason::SolverExit(why)) if why == STALLED => InnerStatus::Stalled,
        _ => InnerStatus::NoProgress,
    }
}

/// argmin's L-BFGS (Moré–Thuente line search) as a [`Minimizer`].
#[derive(Debug, Default)]
pub(crate) struct ArgminLbfgs;

impl Minimizer for ArgminLbfgs {
    fn minimize(
        &mut self,
        function: &mut dyn InnerFunction,
        x: &mut Vec<f64>,
        limits: InnerLimits,
    ) -> InnerOutcome {
        let n = x.len();
        let cache = RefCell::new(Cache {
            function,
            x: vec![0.0; n],
            value: f64::INFINITY,
            grad: vec![0.0; n],
            valid: false,
            best_x: x.clone(),
            best_value: f64::INFINITY,
            abort: None,
        });
        // Evaluate the start first: an abort there never reaches argmin.
        if let Err(abort) = cache.borrow_mut().at(x) {
            return InnerOutcome {
                status: InnerStatus::Aborted(abort),
                iterations: 0,
            };
        }
        let solver = Stopping {
            lbfgs: LBFGS::new(MoreThuenteLineSearch::new(), limits.memory),
            cache: &cache,
            limits,
        };
        let start = x.clone();
        let run = Executor::new(ArgminProblem { cache: &cache }, solver)
            .configure(|state| state.param(start).max_iters(limits.max_iterations))
            .timer(false)
            .run();
        let (status, iterations) = match &run {
            Ok(result) => (
                status_of(result.state().get_termination_reason()),
                result.state().get_iter(),
            ),
            Err(_) => (InnerStatus::NoProgress, 0),
        };
        drop(run);
        let cache = cache.into_inner();
        x.copy_from_slice(&cache.best_x);
        // An abort inside argmin's line search ends its run without an error: the cache
        // remembers it.
        let status = cache.abort.map_or(status, InnerStatus::Aborted);
        InnerOutcome { status, iterations }
    }
}

#[cfg(test)]
mod tests {
    use std::cell::RefCell;

    use argmin::core::{IterState, Solver, State, TerminationReason, TerminationStatus};
    use argmin::solver::linesearch::MoreThuenteLineSearch;
    use argmin::solver::quasinewton::LBFGS;

    use super::{status_of, ArgminLbfgs, Cache, LbfgsState, Stopping, STALLED};
    use crate::solve::inner::{Abort, InnerFunction, InnerLimits, InnerStatus, Minimizer};

    /// f(x) = 10²⁰ + x with its gradient judged absolutely: steps shorter than 10⁴ do
    /// not change the value, yet the gradient is 1 everywhere.
    struct Plateau;
    impl InnerFunction for Plateau {
        fn eval(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, Abort> {
            grad[0] = 1.0;
            Ok(1e20 + x[0])
        }
        fn gradient_scale(&self, _: f64) -> f64 {
            1.0
        }
    }

    /// (x − 3)².
    struct Bowl;
    impl InnerFunction for Bowl {
        fn eval(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, Abort> {
            grad[0] = 2.0 * (x[0] - 3.0);
            Ok((x[0] - 3.0).powi(2))
        }
    }

    fn limits() -> InnerLimits {
        InnerLimits {
            gradient_tol: 1e-10,
            gradient_cap: f64::INFINITY,
            max_iterations: 200,
            memory: 5,
        }
    }

    /// The stopping test at a state of cost `prev` then `cost` and gradient `gradient`.
    fn verdict(prev: f64, cost: f64, gradient: f64) -> TerminationStatus {
        let mut function = Plateau;
        let cache = RefCell::new(Cache {
            function: &mut function,
            x: vec![0.0],
            value: 0.0,
            grad: vec![0.0],
            valid: false,
            best_x: vec![0.0],
            best_value: f64::INFINITY,
            abort: None,
        });
        let mut stopping = Stopping {
            lbfgs: LBFGS::new(MoreThuenteLineSearch::new(), 5),
            cache: &cache,
            limits: limits(),
        };
        let state: LbfgsState = IterState::new()
            .param(vec![0.0])
            .gradient(vec![gradient])
            .cost(prev)
            .cost(cost);
        stopping.terminate(&state)
    }

    #[test]
    fn only_the_gradient_test_is_convergence() {
        let converged = TerminationStatus::Terminated(TerminationReason::SolverConverged);
        let stalled =
            TerminationStatus::Terminated(TerminationReason::SolverExit(STALLED.to_owned()));
        assert_eq!(verdict(5.0, 4.0, 1e-12), converged);
        assert_eq!(verdict(5.0, 5.0, 1e-12), converged, "small gradient wins");
        assert_eq!(verdict(5.0, 5.0, 1.0), stalled, "same cost, large gradient");
        assert_eq!(verdict(5.0, 5.0 * (1.0 + f64::EPSILON), 1.0), stalled);
        assert_eq!(verdict(5.0, 4.9, 1.0), TerminationStatus::NotTerminated);
        assert_eq!(
            status_of(Some(&TerminationReason::SolverExit(STALLED.to_owned()))),
            InnerStatus::Stalled
        );
        assert_eq!(
            status_of(Some(&TerminationReason::SolverConverged)),
            InnerStatus::Converged
        );
    }

    #[test]
    fn a_stationary_point_is_convergence() {
        let mut x = vec![-4.0];
        let out = ArgminLbfgs.minimize(&mut Bowl, &mut x, limits());
        assert_eq!(out.status, InnerStatus::Converged);
        assert!((x[0] - 3.0).abs() < 1e-9, "{x:?}");
    }
}
