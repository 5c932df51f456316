//! The constrained solver: min f(x) s.t. cᵢ(x) = 0, gⱼ(x) ≥ 0, by the augmented
//! Lagrangian method with the accelerated μ schedule of Shtof et al. (*Geosemantic
//! Snapping for Sketch-Based Modeling*, Eurographics 2013, optimisation details) and
//! L-BFGS inner solves.
//!
//! Write the objective and constraints with [`ad`](crate::ad) expressions, compile
//! them into a [`Problem`], and call [`solve`] (or [`Solver`] for a cancel flag, a clock,
//! an observer and warm starts). Every solve ends, and its [`SolveReport`] says why
//! ([`Termination`]).
//!
//! # Examples
//!
//! The closest point to (2, 1) on the unit circle, in the upper half-plane x₂ ≥ 0:
//!
//! ```
//! use geosnap_core::ad::Graph;
//! use geosnap_core::solve::{solve, AugLagSettings, Problem, Termination};
//!
//! let g = Graph::new();
//! let x = g.var();
//! let y = g.var();
//! let f = (x - 2.0).square() + (y - 1.0).square();
//! let mut problem = Problem::builder(&g, f)
//!     .equality("on the circle", x.square() + y.square() - 1.0)
//!     .inequality("upper half", y)
//!     .build();
//! let report = solve(&mut problem, &[0.0, 1.0], &AugLagSettings::default())?;
//! assert_eq!(report.termination, Termination::Converged);
//! let r = 5f64.sqrt();
//! assert!((report.x[0] - 2.0 / r).abs() < 1e-7 && (report.x[1] - 1.0 / r).abs() < 1e-7);
//! assert!(report.max_violation <= 1e-9);
//! # Ok::<(), geosnap_core::solve::SolveError>(())
//! ```

mod auglag;
mod bounded_lbfgs;
mod inner;
mod lbfgs;
mod problem;
mod report;
mod settings;

pub mod hock_schittkowski;

use thiserror::Error;

pub use problem::{Problem, ProblemBuilder};
pub use report::{
    CancelFlag, Clock, Iterate, Multipliers, SolveContext, SolveObserver, SolveReport, Start,
    Termination,
};
pub use settings::{AugLagSettings, InnerSolver, SettingsError};

/// A solve that could not start because its inputs are inconsistent. Problems that
/// arise while solving (NaN, infeasibility, caps) are not errors: they end the solve with
/// a [`Termination`].
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum SolveError {
    /// The start point does not have one value per variable.
    #[error("the start point has {got} values but the problem has {expected} variables")]
    StartLength {
        /// The number of variables.
        expected: usize,
        /// The number of values given.
        got: usize,
    },
    /// The start point holds NaN or ∞.
    #[error("start value {index} is not finite")]
    NonFiniteStart {
        /// The first non-finite entry.
        index: usize,
    },
    /// The warm-start multipliers do not match the constraints.
    #[error("warm-start multipliers must number {equalities} equalities and {inequalities} inequalities")]
    MultiplierLength {
        /// The number of equality constraints.
        equalities: usize,
        /// The number of inequality constraints.
        inequalities: usize,
    },
    /// The warm-start multipliers hold NaN or ∞.
    #[error("warm-start multipliers are not finite")]
    NonFiniteMultipliers,
}

/// A solve with its optional companions, a [`SolveContext`]: a cancel flag, a clock (for
/// the time limit and the reported time) and an observer of intermediate iterates.
///
/// # Examples
///
/// ```
/// use geosnap_core::ad::Graph;
/// use geosnap_core::solve::{AugLagSettings, CancelFlag, Iterate, Problem, Solver, Start};
///
/// let g = Graph::new();
/// let x = g.var();
/// let mut problem = Problem::builder(&g, (x - 3.0).square()).equality("x = 1", x - 1.0).build();
/// let settings = AugLagSettings::default();
/// let cancel = CancelFlag::new();
/// let mut seen = 0;
/// let mut count = |_: &Iterate<'_>| seen += 1;
/// let report = Solver::new(&settings)
///     .cancel(&cancel)
///     .observer(&mut count)
///     .solve(&mut problem, &Start::cold(&[0.0]))?;
/// assert!(report.termination.is_converged());
/// assert!(seen >= 1);
/// // Warm start from the report: converges at once.
/// let again = Solver::new(&settings).solve(&mut problem, &Start::warm(&report))?;
/// assert_eq!(again.outer_iterations, 1);
/// # Ok::<(), geosnap_core::solve::SolveError>(())
/// ```
pub struct Solver<'a> {
    settings: &'a AugLagSettings,
    context: SolveContext<'a>,
}

impl std::fmt::Debug for Solver<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Solver")
            .field("settings", self.settings)
            .field("context", &self.context)
            .finish()
    }
}

impl<'a> Solver<'a> {
    /// A solver with these settings and no companions.
    pub fn new(settings: &'a AugLagSettings) -> Self {
        Self::with_context(settings, SolveContext::default())
    }

    /// A solver with these settings and companions.
    pub fn with_context(settings: &'a AugLagSettings, context: SolveContext<'a>) -> Self {
        Self { settings, context }
    }

    /// Stops the solve within one inner iteration once `flag` is raised.
    #[must_use]
    pub fn cancel(mut self, flag: &'a CancelFlag) -> Self {
        self.context = self.context.with_cancel(flag);
        self
    }

    /// Measures time with `clock`: enforces the settings' time limit and fills
    /// [`SolveReport::elapsed`].
    #[must_use]
    pub fn clock(mut self, clock: &'a dyn Clock) -> Self {
        self.context = self.context.with_clock(clock);
        self
    }

    /// Gives every outer iterate to `observer`.
    #[must_use]
    pub fn observer(mut self, observer: &'a mut dyn SolveObserver) -> Self {
        self.context = self.context.with_observer(observer);
        self
    }

    /// Solves `problem` from `start`.
    ///
    /// # Errors
    ///
    /// [`SolveError`] when the start point or multipliers do not fit the problem or are
    /// not finite. Everything that happens during the solve is reported through
    /// [`SolveReport::termination`] instead.
    pub fn solve(self, problem: &mut Problem, start: &Start) -> Result<SolveReport, SolveError> {
        auglag::run(problem, start, self.settings, self.context)
    }
}

/// Solves `problem` from `x0` (zero multipliers) with `settings`; see [`Solver`] for
/// warm starts, cancellation, time limits and observers.
///
/// # Errors
///
/// [`SolveError`] when `x0` does not have one finite value per variable.
pub fn solve(
    problem: &mut Problem,
    x0: &[f64],
    settings: &AugLagSettings,
) -> Result<SolveReport, SolveError> {
    Solver::new(settings).solve(problem, &Start::cold(x0))
}
