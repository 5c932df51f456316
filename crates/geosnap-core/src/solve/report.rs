//! What goes into a solve besides the problem (start point, and the [`SolveContext`] of
//! clock, cancel flag and observer)
//! and what comes out of it (the report and why it stopped).

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use serde::{Deserialize, Serialize};

/// Why a solve stopped. Every solve ends with one of these; none of them is a panic.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// The constraints hold within the constraint tolerance and the gradient of the
    /// Lagrangian is within the gradient tolerance (relative to max(1, |f|), see
    /// [`AugLagSettings::with_gradient_tol`](super::AugLagSettings::with_gradient_tol)).
    Converged,
    /// The cap on outer (multiplier) iterations was reached.
    MaxOuterIterations,
    /// The cap on function evaluations was reached (this also bounds every line search).
    MaxEvaluations,
    /// The wall-time cap was reached (only with a [`Clock`]).
    TimeLimit,
    /// The cancel flag was raised.
    Cancelled,
    /// The constraints cannot be satisfied from where the solve got to: minimising the
    /// violation alone ends at a local minimum where the constraints are still violated
    /// (contradictory constraints, or a region with no feasible point nearby).
    Infeasible,
    /// No more progress: the violation stopped decreasing at the largest penalty, or
    /// the inner solver could not improve a feasible point that is not yet optimal (its
    /// line search failed or the value stopped changing).
    Stalled,
    /// A value or gradient became NaN or infinite; the report holds the last finite point.
    NumericalFailure,
}

impl Termination {
    /// Whether the solve reached a solution (as opposed to stopping early).
    pub fn is_converged(self) -> bool {
        self == Self::Converged
    }

    /// A short human-readable explanation.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Converged => "converged",
            Self::MaxOuterIterations => "stopped at the outer iteration cap",
            Self::MaxEvaluations => "stopped at the evaluation cap",
            Self::TimeLimit => "stopped at the time limit",
            Self::Cancelled => "cancelled",
            Self::Infeasible => {
                "infeasible: the constraints cannot all be satisfied (the violation has a \
                 non-zero local minimum here)"
            }
            Self::Stalled => "stalled: no further progress was possible",
            Self::NumericalFailure => "numerical failure: a value became NaN or infinite",
        }
    }
}

impl fmt::Display for Termination {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.describe())
    }
}

/// Lagrange multipliers: one per equality and one (≥ 0) per inequality constraint.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Multipliers {
    /// λᵢ of the equalities cᵢ(x) = 0.
    pub equality: Vec<f64>,
    /// νⱼ ≥ 0 of the inequalities gⱼ(x) ≥ 0.
    pub inequality: Vec<f64>,
}

/// Where a solve starts: the variables and, for a warm start, the multipliers and
/// penalty of an earlier solve.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Start {
    /// The starting variables.
    pub x: Vec<f64>,
    /// Starting multipliers (zeros when `None`, the λ⁰ = 0 of the paper).
    pub multipliers: Option<Multipliers>,
    /// Starting penalty μ (the settings' μ₀ when `None`), clamped to `[μ₀, μ_max]`.
    pub penalty: Option<f64>,
}

impl Start {
    /// A cold start from `x` with zero multipliers.
    pub fn cold(x: &[f64]) -> Self {
        Self {
            x: x.to_vec(),
            multipliers: None,
            penalty: None,
        }
    }

    /// A warm start from an earlier report: its `x`, multipliers and penalty.
    pub fn warm(report: &SolveReport) -> Self {
        Self {
            x: report.x.clone(),
            multipliers: Some(report.multipliers.clone()),
            penalty: Some(report.penalty),
        }
    }
}

/// The result of a solve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolveReport {
    /// The final variables (the last finite point when the solve failed numerically).
    pub x: Vec<f64>,
    /// The objective f(x).
    pub objective: f64,
    /// ‖c(x)‖∞ over equalities |cᵢ| and inequality violations max(0, −gⱼ).
    pub max_violation: f64,
    /// ‖∇ₓ(f + Σλᵢcᵢ − Σνⱼgⱼ)‖∞ at `x` with the final multipliers.
    pub gradient_norm: f64,
    /// The constraint with the largest violation (equalities first, then inequalities),
    /// if any constraint is violated at all.
    pub worst_constraint: Option<usize>,
    /// The final multipliers, for a warm start.
    pub multipliers: Multipliers,
    /// The final penalty μ.
    pub penalty: f64,
    /// Outer (multiplier-update) iterations.
    pub outer_iterations: usize,
    /// Inner (L-BFGS) iterations over all outer iterations.
    pub inner_iterations: u64,
    /// Evaluations of value and gradient.
    pub evaluations: u64,
    /// Wall time, when a [`Clock`] was given (zero otherwise).
    pub elapsed: Duration,
    /// Why the solve stopped.
    pub termination: Termination,
}

/// One intermediate iterate, given to a [`SolveObserver`] after each outer iteration.
#[derive(Clone, Copy, Debug)]
pub struct Iterate<'a> {
    /// Outer iteration number, from 1.
    pub outer: usize,
    /// The variables.
    pub x: &'a [f64],
    /// The objective f(x).
    pub objective: f64,
    /// ‖c(x)‖∞ as in [`SolveReport::max_violation`].
    pub max_violation: f64,
    /// The Lagrangian gradient norm as in [`SolveReport::gradient_norm`].
    pub gradient_norm: f64,
    /// The penalty μ used for this iteration.
    pub penalty: f64,
    /// Inner iterations so far.
    pub inner_iterations: u64,
    /// Time so far (zero without a [`Clock`]).
    pub elapsed: Duration,
}

/// Receives the intermediate iterates of a solve (to stream them to a view, log them,
/// or record them in tests).
pub trait SolveObserver {
    /// Called after each outer iteration.
    fn iterate(&mut self, iterate: &Iterate<'_>);
}

impl SolveObserver for () {
    fn iterate(&mut self, _: &Iterate<'_>) {}
}

impl<F: FnMut(&Iterate<'_>)> SolveObserver for F {
    fn iterate(&mut self, iterate: &Iterate<'_>) {
        self(iterate);
    }
}

/// What travels with every solve besides its problem and settings: a cancel flag, a
/// clock (for the time limit and the reported time) and an observer of intermediate
/// iterates, each optional. The default has none of them.
///
/// # Examples
///
/// ```
/// use geosnap_core::solve::{CancelFlag, Iterate, SolveContext};
///
/// let cancel = CancelFlag::new();
/// let mut seen = 0;
/// let mut count = |_: &Iterate<'_>| seen += 1;
/// let mut context = SolveContext::default().with_cancel(&cancel).with_observer(&mut count);
/// // Each solve of a sequence borrows the same companions.
/// let first = context.reborrow();
/// assert!(first.cancel.is_some() && first.observer.is_some() && first.clock.is_none());
/// ```
#[derive(Default)]
pub struct SolveContext<'a> {
    /// Stops the solve when raised.
    pub cancel: Option<&'a CancelFlag>,
    /// Measures time and enforces the time cap.
    pub clock: Option<&'a dyn Clock>,
    /// Receives the intermediate iterates.
    pub observer: Option<&'a mut dyn SolveObserver>,
}

impl<'a> SolveContext<'a> {
    /// Stops the solve within one inner iteration once `flag` is raised.
    #[must_use]
    pub fn with_cancel(mut self, flag: &'a CancelFlag) -> Self {
        self.cancel = Some(flag);
        self
    }

    /// Measures time with `clock`: enforces the settings' time limit and fills
    /// [`SolveReport::elapsed`].
    #[must_use]
    pub fn with_clock(mut self, clock: &'a dyn Clock) -> Self {
        self.clock = Some(clock);
        self
    }

    /// Gives every outer iterate to `observer`.
    #[must_use]
    pub fn with_observer(mut self, observer: &'a mut dyn SolveObserver) -> Self {
        self.observer = Some(observer);
        self
    }

    /// The same companions for one solve of several, borrowed for its length.
    pub fn reborrow(&mut self) -> SolveContext<'_> {
        SolveContext {
            cancel: self.cancel,
            clock: self.clock,
            observer: self
                .observer
                .as_deref_mut()
                .map(|o| o as &mut dyn SolveObserver),
        }
    }

    /// Whether the cancel flag is raised.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.is_some_and(CancelFlag::is_cancelled)
    }
}

impl fmt::Debug for SolveContext<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SolveContext")
            .field("cancel", &self.cancel)
            .field("clock", &self.clock.is_some())
            .field("observer", &self.observer.is_some())
            .finish()
    }
}

/// A cancel flag shared between the thread that solves and the one that may cancel.
///
/// The solver looks at it before every evaluation, so a raised flag stops a running
/// solve within one inner iteration.
#[derive(Clone, Debug, Default)]
pub struct CancelFlag(Arc<AtomicBool>);

impl CancelFlag {
    /// A flag that is not raised.
    pub fn new() -> Self {
        Self::default()
    }
    /// Raises the flag.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }
    /// Whether the flag is raised.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// A source of elapsed time, injected so the core stays free of the system clock (and
/// tests can use a fake one). `geosnap::clock::MonotonicClock` is the real one.
pub trait Clock {
    /// Time elapsed since the clock started.
    fn elapsed(&self) -> Duration;
}
