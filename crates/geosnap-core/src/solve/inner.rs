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

    /// The size the gradient norm is compared with at a point of value `value`: the
    /// inner solve has converged when ‖∇f‖₂ ≤ tol · scale. By default max(1, |f|), a
    /// tolerance relative to the size of the function.
    fn gradient_scale(&self, value: f64) -> f64 {
        value.abs().max(1.0)
    }

    /// Whether a point evaluated so far already meets the caller's goal, whatever its
    /// gradient (the restoration phase's feasibility); the minimiser then stops with
    /// [`InnerStatus::Converged`] at its next iteration and the caller takes the point
    /// from the function.
    fn goal_met(&self) -> bool {
        false
    }
}

/// How an inner solve ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum InnerStatus {
    /// The gradient test of [`InnerLimits::converged`] holds, or the function's goal is
    /// met ([`InnerFunction::goal_met`]). Nothing else counts as convergence.
    Converged,
    /// The iteration cap was reached.
    IterationLimit,
    /// The line search found no acceptable step: no further progress from this point.
    NoProgress,
    /// The value stopped changing (by less than a few units in its last place) while
    /// the gradient is still above the tolerance: not a stationary point, but no
    /// measurable progress either.
    Stalled,
    /// An evaluation aborted.
    Aborted(Abort),
}

impl InnerStatus {
    /// No progress is possible from the point (the line search failed or the value
    /// stopped changing), though it is not stationary.
    pub(crate) fn is_stuck(self) -> bool {
        matches!(self, Self::NoProgress | Self::Stalled)
    }
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
    /// The relative gradient tolerance: see [`InnerLimits::converged`].
    pub(crate) gradient_tol: f64,
    /// An absolute cap on the gradient norm at convergence (∞ for none).
    pub(crate) gradient_cap: f64,
    pub(crate) max_iterations: u64,
    /// L-BFGS memory.
    pub(crate) memory: usize,
}

impl InnerLimits {
    /// The gradient test: ‖∇f‖₂ ≤ min(`gradient_tol` · scale, `gradient_cap`), the scale
    /// being [`InnerFunction::gradient_scale`] of the value `value`.
    pub(crate) fn converged(
        &self,
        function: &dyn InnerFunction,
        value: f64,
        gradient_norm: f64,
    ) -> bool {
        gradient_norm <= (self.gradient_tol * function.gradient_scale(value)).min(self.gradient_cap)
    }
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

#[cfg(test)]
mod tests {
    use super::{Abort, InnerFunction, InnerLimits};

    /// f(x) = 1000 + x²: large values.
    struct Offset;
    impl InnerFunction for Offset {
        fn eval(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, Abort> {
            grad[0] = 2.0 * x[0];
            Ok(1000.0 + x[0] * x[0])
        }
    }

    #[test]
    fn the_gradient_test_is_relative_to_the_value_and_capped() {
        let limits = InnerLimits {
            gradient_tol: 1e-6,
            gradient_cap: f64::INFINITY,
            max_iterations: 1,
            memory: 1,
        };
        // |f| = 1000: 1e-4 passes relative to the value, not absolutely.
        assert!(limits.converged(&Offset, 1000.0, 1e-4));
        assert!(!limits.converged(&Offset, 1000.0, 2e-3));
        // Values below 1 count as 1.
        assert!(!limits.converged(&Offset, 1e-3, 2e-6));
        assert!(limits.converged(&Offset, -1e-3, 1e-6));
        let capped = InnerLimits {
            gradient_cap: 1e-5,
            ..limits
        };
        assert!(!capped.converged(&Offset, 1000.0, 1e-4));
    }
}
