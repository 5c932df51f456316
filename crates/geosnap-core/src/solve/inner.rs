//! The seam between the augmented-Lagrangian outer loop and an unconstrained minimiser,
//! so that the minimiser can be swapped (argmin's L-BFGS or our bounded one).

/// Why an evaluation refused to run or to return a value; it ends the inner solve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Abort {
    Cancelled,
    TimeLimit,
    EvaluationLimit,
    NonFinite,
}

/// A smooth function to minimise: value and gradient in one call.
pub(crate) trait InnerFunction {
    /// Writes ∇f(x) into `grad` and returns f(x); an `Err` ends the inner solve.
    fn eval(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, Abort>;
}

/// How an inner solve ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum InnerStatus {
    /// The gradient norm reached the tolerance (or the value stopped changing).
    Converged,
    /// The iteration cap was reached.
    IterationLimit,
    /// The line search found no acceptable step: no further progress from this point.
    NoProgress,
    /// An evaluation aborted.
    Aborted(Abort),
}

/// What an inner solve returns besides the point it leaves in `x`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct InnerOutcome {
    pub(crate) status: InnerStatus,
    pub(crate) iterations: u64,
}

/// Limits of one inner solve.
#[derive(Clone, Copy, Debug)]
pub(crate) struct InnerLimits {
    /// Stop when ‖∇f‖₂ ≤ this.
    pub(crate) gradient_tol: f64,
    pub(crate) max_iterations: u64,
    /// L-BFGS memory.
    pub(crate) memory: usize,
}

/// An unconstrained minimiser. On return `x` holds the best point found (the start if
/// nothing better was found), whatever the status.
pub(crate) trait Minimizer {
    fn minimize(
        &mut self,
        function: &mut dyn InnerFunction,
        x: &mut Vec<f64>,
        limits: InnerLimits,
    ) -> InnerOutcome;
}
