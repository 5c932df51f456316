//! The adapter to argmin's L-BFGS with the Moré–Thuente line search: the only file of
//! the crate that names argmin, so the inner solver can be swapped.
//!
//! argmin asks for the cost and the gradient separately, and its line search runs in an
//! inner executor without an iteration cap (argmin issue #497). The adapter therefore
//! evaluates both at once and caches the last point, and every evaluation goes through
//! [`InnerFunction::eval`], which refuses to run past the solve's evaluation cap, time
//! limit or cancel flag: that is what makes every line search end.

use std::cell::RefCell;

use argmin::core::{CostFunction, Executor, Gradient, State, TerminationReason};
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
        let solver = LBFGS::new(MoreThuenteLineSearch::new(), limits.memory)
            .with_tolerance_grad(limits.gradient_tol);
        let Ok(solver) = solver else {
            // Only a negative tolerance is refused, which the settings rule out.
            return InnerOutcome {
                status: InnerStatus::NoProgress,
                iterations: 0,
            };
        };
        let start = x.clone();
        let run = Executor::new(ArgminProblem { cache: &cache }, solver)
            .configure(|state| state.param(start).max_iters(limits.max_iterations))
            .timer(false)
            .run();
        let (status, iterations) = match &run {
            Ok(result) => {
                let status = match result.state().get_termination_reason() {
                    Some(TerminationReason::MaxItersReached) => InnerStatus::IterationLimit,
                    Some(TerminationReason::SolverConverged) => InnerStatus::Converged,
                    _ => InnerStatus::NoProgress,
                };
                (status, result.state().get_iter())
            }
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
