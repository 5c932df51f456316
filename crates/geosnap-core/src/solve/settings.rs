//! Settings of the augmented-Lagrangian solver, each checked when set.

use std::time::Duration;

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A setting was given a value outside its valid range.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum SettingsError {
    /// The value must be finite and greater than zero.
    #[error("{name} must be finite and > 0, got {value}")]
    NotPositive {
        /// The setting.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// The value lies outside the range the method needs.
    #[error("{name} must be in {range}, got {value}")]
    OutOfRange {
        /// The setting.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The valid range, as text.
        range: &'static str,
    },
}

/// Which unconstrained minimiser solves the inner problems.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InnerSolver {
    /// Our own bounded L-BFGS (`solve/bounded_lbfgs.rs`), the default: a strong-Wolfe
    /// line search that also accepts the approximate Wolfe conditions, so iterates
    /// converge to working precision; a scaled first step; backtracking from NaN trial
    /// points; and less overhead per iteration. On the Hock–Schittkowski set it needs
    /// fewer iterations and solves problems (HS77) where argmin's first unscaled step
    /// lands in another basin.
    #[default]
    Bounded,
    /// argmin's L-BFGS with its Moré–Thuente line search, behind the adapter in
    /// `solve/lbfgs.rs` (made safe by the evaluation cap, which bounds every line search).
    Argmin,
}

/// Settings of [`solve`](super::solve): the accelerated μ schedule of Shtof et al.,
/// *Geosemantic Snapping for Sketch-Based Modeling* (Eurographics 2013, optimisation
/// details: AUGMENTED-LAGRANGIAN-ACCEL), tolerances and caps.
///
/// Built from [`AugLagSettings::default`] with `with_*` methods, each of which checks its
/// value.
///
/// # Examples
///
/// ```
/// use geosnap_core::solve::AugLagSettings;
///
/// let settings = AugLagSettings::default()
///     .with_constraint_tol(1e-6)?
///     .with_max_outer_iterations(50)?;
/// assert!(AugLagSettings::default().with_penalty(0.0, 10.0).is_err());
/// # Ok::<(), geosnap_core::solve::SettingsError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "AugLagFields")]
pub struct AugLagSettings {
    mu0: f64,
    mu_max: f64,
    alpha: f64,
    beta: f64,
    constraint_tol: f64,
    gradient_tol: f64,
    max_outer_iterations: usize,
    max_inner_iterations: u64,
    max_evaluations: u64,
    time_limit: Option<Duration>,
    lbfgs_memory: usize,
    inner_solver: InnerSolver,
}

impl Default for AugLagSettings {
    /// μ₀ = 10, `μ_max` = 1000, α = 0.5, β = 2 (as Shtof et al.); ‖c‖∞ ≤ 1e-9 and
    /// ‖∇L‖∞ ≤ 1e-7 · max(1, |f|); at most 200 outer iterations, 1000 inner iterations per outer
    /// iteration and 200 000 evaluations; no time limit; L-BFGS memory 10.
    fn default() -> Self {
        Self {
            mu0: 10.0,
            mu_max: 1000.0,
            alpha: 0.5,
            beta: 2.0,
            constraint_tol: 1e-9,
            gradient_tol: 1e-7,
            max_outer_iterations: 200,
            max_inner_iterations: 1000,
            max_evaluations: 200_000,
            time_limit: None,
            lbfgs_memory: 10,
            inner_solver: InnerSolver::default(),
        }
    }
}

/// The fields of [`AugLagSettings`] as read, before they are checked: deserialising goes
/// through [`TryFrom`], which sets each one with its checking `with_*` method.
#[derive(Deserialize)]
struct AugLagFields {
    mu0: f64,
    mu_max: f64,
    alpha: f64,
    beta: f64,
    constraint_tol: f64,
    gradient_tol: f64,
    max_outer_iterations: usize,
    max_inner_iterations: u64,
    max_evaluations: u64,
    time_limit: Option<Duration>,
    lbfgs_memory: usize,
    inner_solver: InnerSolver,
}

impl TryFrom<AugLagFields> for AugLagSettings {
    type Error = SettingsError;

    fn try_from(f: AugLagFields) -> Result<Self, SettingsError> {
        let settings = Self::default()
            .with_penalty(f.mu0, f.mu_max)?
            .with_alpha(f.alpha)?
            .with_beta(f.beta)?
            .with_constraint_tol(f.constraint_tol)?
            .with_gradient_tol(f.gradient_tol)?
            .with_max_outer_iterations(f.max_outer_iterations)?
            .with_max_inner_iterations(f.max_inner_iterations)?
            .with_max_evaluations(f.max_evaluations)?
            .with_lbfgs_memory(f.lbfgs_memory)?
            .with_inner_solver(f.inner_solver);
        match f.time_limit {
            Some(limit) => settings.with_time_limit(limit),
            None => Ok(settings),
        }
    }
}

fn positive(name: &'static str, value: f64) -> Result<f64, SettingsError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(SettingsError::NotPositive { name, value })
    }
}

fn at_least_one<T: Into<u64> + Copy>(name: &'static str, value: T) -> Result<T, SettingsError> {
    if value.into() >= 1 {
        Ok(value)
    } else {
        Err(SettingsError::OutOfRange {
            name,
            value: value.into() as f64,
            range: "[1, ∞)",
        })
    }
}

impl AugLagSettings {
    /// The penalty schedule's start μ₀ and cap `μ_max` (`0 < μ₀ ≤ μ_max`).
    ///
    /// # Errors
    ///
    /// [`SettingsError`] if either is not finite and positive, or `μ₀ > μ_max`.
    pub fn with_penalty(mut self, mu0: f64, mu_max: f64) -> Result<Self, SettingsError> {
        self.mu0 = positive("mu0", mu0)?;
        self.mu_max = positive("mu_max", mu_max)?;
        if mu0 > mu_max {
            return Err(SettingsError::OutOfRange {
                name: "mu0",
                value: mu0,
                range: "(0, mu_max]",
            });
        }
        Ok(self)
    }

    /// The exponent α of the violation target `C_max = 1/μ^α` (in `(0, 10]`).
    ///
    /// # Errors
    ///
    /// [`SettingsError`] outside `(0, 10]`.
    pub fn with_alpha(mut self, alpha: f64) -> Result<Self, SettingsError> {
        self.alpha = positive("alpha", alpha)?;
        if alpha > 10.0 {
            return Err(SettingsError::OutOfRange {
                name: "alpha",
                value: alpha,
                range: "(0, 10]",
            });
        }
        Ok(self)
    }

    /// The growth factor β of μ when the violation did not drop enough (`β > 1`).
    ///
    /// # Errors
    ///
    /// [`SettingsError`] unless finite and > 1.
    pub fn with_beta(mut self, beta: f64) -> Result<Self, SettingsError> {
        if !(beta.is_finite() && beta > 1.0) {
            return Err(SettingsError::OutOfRange {
                name: "beta",
                value: beta,
                range: "(1, ∞)",
            });
        }
        self.beta = beta;
        Ok(self)
    }

    /// Convergence needs every equality |cᵢ| and inequality violation ≤ `tol`.
    ///
    /// # Errors
    ///
    /// [`SettingsError::NotPositive`] unless finite and > 0.
    pub fn with_constraint_tol(mut self, tol: f64) -> Result<Self, SettingsError> {
        self.constraint_tol = positive("constraint_tol", tol)?;
        Ok(self)
    }

    /// Convergence needs ‖∇ₓL‖∞ ≤ `tol` · max(1, |f(x)|): the gradient of the
    /// Lagrangian, relative to the objective once |f| exceeds 1 (absolute below). Each
    /// inner solve likewise stops at ‖∇L‖₂ ≤ `tol` · max(1, |L|), capped at a tenth of
    /// μ · `constraint_tol` so that it resolves the constraints; the restoration phase
    /// measures its gradient against the violation instead, ‖∇φ‖₂ ≤ `tol` · ‖c‖₂.
    ///
    /// # Errors
    ///
    /// [`SettingsError::NotPositive`] unless finite and > 0.
    pub fn with_gradient_tol(mut self, tol: f64) -> Result<Self, SettingsError> {
        self.gradient_tol = positive("gradient_tol", tol)?;
        Ok(self)
    }

    /// The cap on outer (multiplier-update) iterations.
    ///
    /// # Errors
    ///
    /// [`SettingsError::OutOfRange`] for 0.
    pub fn with_max_outer_iterations(mut self, n: usize) -> Result<Self, SettingsError> {
        self.max_outer_iterations = at_least_one("max_outer_iterations", n as u64)? as usize;
        Ok(self)
    }

    /// The cap on L-BFGS iterations within one outer iteration.
    ///
    /// # Errors
    ///
    /// [`SettingsError::OutOfRange`] for 0.
    pub fn with_max_inner_iterations(mut self, n: u64) -> Result<Self, SettingsError> {
        self.max_inner_iterations = at_least_one("max_inner_iterations", n)?;
        Ok(self)
    }

    /// The cap on value-and-gradient evaluations over the whole solve, which also bounds
    /// every line search.
    ///
    /// # Errors
    ///
    /// [`SettingsError::OutOfRange`] for 0.
    pub fn with_max_evaluations(mut self, n: u64) -> Result<Self, SettingsError> {
        self.max_evaluations = at_least_one("max_evaluations", n)?;
        Ok(self)
    }

    /// The wall-time cap (enforced when the solve is given a [`Clock`](super::Clock)).
    ///
    /// # Errors
    ///
    /// [`SettingsError::NotPositive`] for a zero duration.
    pub fn with_time_limit(mut self, limit: Duration) -> Result<Self, SettingsError> {
        if limit.is_zero() {
            return Err(SettingsError::NotPositive {
                name: "time_limit",
                value: 0.0,
            });
        }
        self.time_limit = Some(limit);
        Ok(self)
    }

    /// The number of correction pairs L-BFGS keeps (1 to 100).
    ///
    /// # Errors
    ///
    /// [`SettingsError::OutOfRange`] outside 1 to 100.
    pub fn with_lbfgs_memory(mut self, m: usize) -> Result<Self, SettingsError> {
        if !(1..=100).contains(&m) {
            return Err(SettingsError::OutOfRange {
                name: "lbfgs_memory",
                value: m as f64,
                range: "[1, 100]",
            });
        }
        self.lbfgs_memory = m;
        Ok(self)
    }

    /// The inner unconstrained minimiser.
    #[must_use]
    pub fn with_inner_solver(mut self, inner: InnerSolver) -> Self {
        self.inner_solver = inner;
        self
    }

    /// μ₀.
    pub fn mu0(&self) -> f64 {
        self.mu0
    }
    /// `μ_max`.
    pub fn mu_max(&self) -> f64 {
        self.mu_max
    }
    /// α.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
    /// β.
    pub fn beta(&self) -> f64 {
        self.beta
    }
    /// The constraint tolerance.
    pub fn constraint_tol(&self) -> f64 {
        self.constraint_tol
    }
    /// The gradient tolerance (relative to max(1, |f|); see
    /// [`with_gradient_tol`](Self::with_gradient_tol)).
    pub fn gradient_tol(&self) -> f64 {
        self.gradient_tol
    }
    /// The outer iteration cap.
    pub fn max_outer_iterations(&self) -> usize {
        self.max_outer_iterations
    }
    /// The inner iteration cap per outer iteration.
    pub fn max_inner_iterations(&self) -> u64 {
        self.max_inner_iterations
    }
    /// The evaluation cap.
    pub fn max_evaluations(&self) -> u64 {
        self.max_evaluations
    }
    /// The time limit.
    pub fn time_limit(&self) -> Option<Duration> {
        self.time_limit
    }
    /// The L-BFGS memory.
    pub fn lbfgs_memory(&self) -> usize {
        self.lbfgs_memory
    }
    /// The inner solver.
    pub fn inner_solver(&self) -> InnerSolver {
        self.inner_solver
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::{AugLagSettings, SettingsError};

    #[test]
    fn every_setting_rejects_bad_values() {
        let s = AugLagSettings::default();
        assert!(s.clone().with_penalty(f64::NAN, 10.0).is_err());
        assert!(s.clone().with_penalty(100.0, 10.0).is_err());
        assert!(s.clone().with_alpha(0.0).is_err());
        assert!(s.clone().with_alpha(11.0).is_err());
        assert!(s.clone().with_beta(1.0).is_err());
        assert!(s.clone().with_beta(f64::INFINITY).is_err());
        assert!(s.clone().with_constraint_tol(-1.0).is_err());
        assert!(s.clone().with_gradient_tol(0.0).is_err());
        assert!(s.clone().with_max_outer_iterations(0).is_err());
        assert!(s.clone().with_max_inner_iterations(0).is_err());
        assert!(s.clone().with_max_evaluations(0).is_err());
        assert!(s.clone().with_time_limit(Duration::ZERO).is_err());
        assert!(s.clone().with_lbfgs_memory(0).is_err());
        let err = s.with_constraint_tol(f64::NAN).unwrap_err();
        assert!(matches!(
            err,
            SettingsError::NotPositive {
                name: "constraint_tol",
                ..
            }
        ));
        assert!(err.to_string().contains("constraint_tol"), "{err}");
    }

    #[test]
    fn settings_read_from_json_are_checked() {
        let good = AugLagSettings::default()
            .with_time_limit(Duration::from_secs(3))
            .unwrap();
        let json = serde_json::to_value(&good).unwrap();
        let back: AugLagSettings = serde_json::from_value(json.clone()).unwrap();
        assert_eq!(back, good, "a valid file round-trips");
        for (field, bad) in [
            ("constraint_tol", serde_json::json!(-1.0)),
            ("beta", serde_json::json!(0.5)),
            ("mu0", serde_json::json!(1e9)),
            ("lbfgs_memory", serde_json::json!(0)),
            ("time_limit", serde_json::json!({ "secs": 0, "nanos": 0 })),
        ] {
            let mut value = json.clone();
            value[field] = bad;
            let err = serde_json::from_value::<AugLagSettings>(value).unwrap_err();
            assert!(err.to_string().contains(field), "{field}: {err}");
        }
    }

    #[test]
    fn defaults_are_the_papers() {
        let s = AugLagSettings::default();
        assert_eq!(
            (s.mu0(), s.mu_max(), s.alpha(), s.beta()),
            (10.0, 1000.0, 0.5, 2.0)
        );
        let t = s.with_penalty(1.0, 1e4).unwrap().with_beta(3.0).unwrap();
        assert_eq!((t.mu0(), t.mu_max(), t.beta()), (1.0, 1e4, 3.0));
    }
}
