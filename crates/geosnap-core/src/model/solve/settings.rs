//! Settings of the global solve, each checked when set.

use std::time::Duration;

use crate::solve::{AugLagSettings, SettingsError};

/// L-BFGS memory of the global solve. Relations couple the parts' fits into a problem
/// whose curvature differs by orders of magnitude between directions (depths only the
/// relations fix, fits the strokes fix); a long memory models it far better than the
/// per-part snaps' 10 (docs/decisions.md has what it saves).
const LBFGS_MEMORY: usize = 100;

/// Settings of the global solve.
///
/// Built from [`GlobalSettings::default`] with `with_*` methods, each of which checks its
/// value, in the style of [`AugLagSettings`].
///
/// # Examples
///
/// ```
/// use geosnap_core::model::GlobalSettings;
///
/// let settings = GlobalSettings::default().with_soft_weight(2.0)?.with_reach(None);
/// assert_eq!((settings.soft_weight(), settings.reach()), (2.0, None));
/// assert!(GlobalSettings::default().with_violation_tol(-1.0).is_err());
/// # Ok::<(), geosnap_core::solve::SettingsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct GlobalSettings {
    solver: AugLagSettings,
    soft_weight: f64,
    violation_tol: f64,
    max_worsening: f64,
    max_conflicts: usize,
    reach: Option<usize>,
}

impl Default for GlobalSettings {
    /// The solver's defaults with ‖c‖∞ ≤ 1e-5 and ‖∇L‖∞ ≤ 1e-5 · max(1, |f|), at most 30
    /// outer iterations, 3000 evaluations and 10 s, and a long L-BFGS memory; soft
    /// weight 1, violation tolerance 1e-3, worsening 3, 8 conflicts, reach 1.
    fn default() -> Self {
        Self {
            solver: default_solver(),
            soft_weight: 1.0,
            violation_tol: 1e-3,
            max_worsening: 3.0,
            max_conflicts: 8,
            reach: Some(1),
        }
    }
}

/// The solver settings of the global solve (see [`GlobalSettings::default`]).
fn default_solver() -> AugLagSettings {
    let checked = AugLagSettings::default()
        .with_constraint_tol(1e-5)
        .and_then(|s| s.with_gradient_tol(1e-5))
        .and_then(|s| s.with_max_outer_iterations(30))
        .and_then(|s| s.with_max_evaluations(3000))
        .and_then(|s| s.with_time_limit(Duration::from_secs(10)))
        .and_then(|s| s.with_lbfgs_memory(LBFGS_MEMORY));
    match checked {
        Ok(settings) => settings,
        Err(e) => unreachable!("the global solve's default solver settings are valid: {e}"),
    }
}

fn positive(name: &'static str, value: f64) -> Result<f64, SettingsError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(SettingsError::NotPositive { name, value })
    }
}

impl GlobalSettings {
    /// The solver's settings and caps (iterations, evaluations, time).
    #[must_use]
    pub fn with_solver(mut self, solver: AugLagSettings) -> Self {
        self.solver = solver;
        self
    }

    /// The weight of a soft relation: w·‖ψ‖² is added to the objective.
    ///
    /// # Errors
    ///
    /// [`SettingsError::NotPositive`] unless finite and > 0.
    pub fn with_soft_weight(mut self, weight: f64) -> Result<Self, SettingsError> {
        self.soft_weight = positive("soft_weight", weight)?;
        Ok(self)
    }

    /// The largest ‖ψ‖∞ of a hard relation taken as satisfied after a solve.
    ///
    /// # Errors
    ///
    /// [`SettingsError::NotPositive`] unless finite and > 0.
    pub fn with_violation_tol(mut self, tol: f64) -> Result<Self, SettingsError> {
        self.violation_tol = positive("violation_tol", tol)?;
        Ok(self)
    }

    /// The largest ratio of a part's RMS after the solve to its RMS after its own snap
    /// (at least 1).
    ///
    /// # Errors
    ///
    /// [`SettingsError::OutOfRange`] unless finite and ≥ 1.
    pub fn with_max_worsening(mut self, ratio: f64) -> Result<Self, SettingsError> {
        if !(ratio.is_finite() && ratio >= 1.0) {
            return Err(SettingsError::OutOfRange {
                name: "max_worsening",
                value: ratio,
                range: "[1, ∞)",
            });
        }
        self.max_worsening = ratio;
        Ok(self)
    }

    /// The most rounds of switching a relation off and solving again (0: a broken solve is
    /// put back at once). Contradictions found before solving cost no round.
    #[must_use]
    pub fn with_max_conflicts(mut self, n: usize) -> Self {
        self.max_conflicts = n;
        self
    }

    /// How far a change reaches, in relations; `None` frees the whole component.
    #[must_use]
    pub fn with_reach(mut self, reach: Option<usize>) -> Self {
        self.reach = reach;
        self
    }

    /// The solver's settings and caps (iterations, evaluations, time).
    pub fn solver(&self) -> &AugLagSettings {
        &self.solver
    }

    /// Weight of a soft relation: w·‖ψ‖² is added to the objective (default 1, which
    /// weighs a 1 % residual like a 1 %-of-size fit error of one curve).
    pub fn soft_weight(&self) -> f64 {
        self.soft_weight
    }

    /// Largest ‖ψ‖∞ of a hard relation taken as satisfied after a solve (default 1e-3:
    /// 0.06° for a direction, 0.1 % of the features' size for a position; the solver
    /// itself aims at 1e-5).
    pub fn violation_tol(&self) -> f64 {
        self.violation_tol
    }

    /// Largest ratio of a part's RMS after the solve to its RMS after its own snap
    /// (default 3).
    pub fn max_worsening(&self) -> f64 {
        self.max_worsening
    }

    /// The most rounds of switching relations off and solving again (default 8).
    pub fn max_conflicts(&self) -> usize {
        self.max_conflicts
    }

    /// How far a change reaches, in relations (default 1): a solve after a change frees
    /// the changed parts and those related to them, and holds the rest of their
    /// component where it is (its relations hold already, and those reaching the freed
    /// parts are kept as constraints). `None` frees the whole component. A release then
    /// costs about the same whatever the size of the model.
    pub fn reach(&self) -> Option<usize> {
        self.reach
    }
}

#[cfg(test)]
mod tests {
    use super::GlobalSettings;
    use crate::solve::SettingsError;

    #[test]
    fn every_checked_setting_rejects_bad_values() {
        let s = GlobalSettings::default();
        assert!(s.clone().with_soft_weight(0.0).is_err());
        assert!(s.clone().with_soft_weight(f64::NAN).is_err());
        assert!(s.clone().with_violation_tol(-1e-3).is_err());
        assert!(s.clone().with_violation_tol(f64::INFINITY).is_err());
        assert!(s.clone().with_max_worsening(0.5).is_err());
        let err = s.clone().with_max_worsening(f64::NAN).unwrap_err();
        assert!(matches!(
            err,
            SettingsError::OutOfRange {
                name: "max_worsening",
                ..
            }
        ));
        let t = s
            .with_soft_weight(2.0)
            .and_then(|t| t.with_violation_tol(1e-4))
            .and_then(|t| t.with_max_worsening(5.0))
            .expect("valid values")
            .with_max_conflicts(3)
            .with_reach(None);
        assert_eq!(
            (
                t.soft_weight(),
                t.violation_tol(),
                t.max_worsening(),
                t.max_conflicts(),
                t.reach()
            ),
            (2.0, 1e-4, 5.0, 3, None)
        );
    }

    #[test]
    fn the_default_solver_settings_are_the_global_solves() {
        let s = GlobalSettings::default();
        let solver = s.solver();
        assert_eq!(
            (
                solver.constraint_tol(),
                solver.max_outer_iterations(),
                solver.max_evaluations()
            ),
            (1e-5, 30, 3000)
        );
    }
}
