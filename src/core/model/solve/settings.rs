//! Settings of the global solve.

use std::time::Duration;

use crate::core::solve::AugLagSettings;

/// L-BFGS memory of the global solve. Relations couple the parts' fits into a problem
/// whose curvature differs by orders of magnitude between directions (depths only the
/// relations fix, fits the strokes fix); a long memory models it far better than the
/// per-part snaps' 10: on the shared sketches it cuts evaluations 3–10×.
const LBFGS_MEMORY: usize = 100;

/// Settings of the global solve.
#[derive(Clone, Debug, PartialEq)]
pub struct GlobalSettings {
    /// The solver's settings and caps (iterations, evaluations, time).
    pub solver: AugLagSettings,
    /// Weight of a soft relation: w·‖ψ‖² is added to the objective (default 1, which
    /// weighs a 1 % residual like a 1 %-of-size fit error of one curve).
    pub soft_weight: f64,
    /// Largest ‖ψ‖∞ of a hard relation taken as satisfied after a solve (default 1e-3:
    /// 0.06° for a direction, 0.1 % of the features' size for a position; the solver
    /// itself aims at 1e-5).
    pub violation_tol: f64,
    /// Largest ratio of a part's RMS after the solve to its RMS after its own snap
    /// (default 3).
    pub max_worsening: f64,
    /// Most relations switched off per solve (default 8).
    pub max_conflicts: usize,
    /// How far a change reaches, in relations (default 1): a solve after a change frees
    /// the changed parts and those related to them, and holds the rest of their
    /// component where it is (its relations hold already, and those reaching the freed
    /// parts are kept as constraints). `None` frees the whole component. A release then
    /// costs about the same whatever the size of the model.
    pub reach: Option<usize>,
}

impl Default for GlobalSettings {
    fn default() -> Self {
        let solver = AugLagSettings::default()
            .with_constraint_tol(1e-5)
            .and_then(|s| s.with_gradient_tol(1e-5))
            .and_then(|s| s.with_max_outer_iterations(30))
            .and_then(|s| s.with_max_evaluations(3000))
            .and_then(|s| s.with_time_limit(Duration::from_secs(10)))
            .and_then(|s| s.with_lbfgs_memory(LBFGS_MEMORY))
            .unwrap_or_default();
        Self {
            solver,
            soft_weight: 1.0,
            violation_tol: 1e-3,
            max_worsening: 3.0,
            max_conflicts: 8,
            reach: Some(1),
        }
    }
}
