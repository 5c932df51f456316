//! The constrained solver end to end: the Hock–Schittkowski problems from their standard
//! start points, and every way a solve can end (infeasible, NaN, cancel, caps, time).

use std::cell::Cell;
use std::time::Duration;

use geosnap::core::ad::Graph;
use geosnap::core::solve::{
    hock_schittkowski, solve, AugLagSettings, CancelFlag, Clock, InnerSolver, Iterate, Problem,
    Solver, Start, Termination,
};

/// The problems the issue names, which must be solved by every inner solver.
const NAMED: [&str; 7] = ["HS6", "HS7", "HS8", "HS27", "HS28", "HS39", "HS42"];

fn check_hs(name: &str, settings: &AugLagSettings) -> Result<(), String> {
    let test = hock_schittkowski::by_name(name).ok_or(format!("{name} is missing"))?;
    let outcome = test.solve(settings);
    let r = &outcome.report;
    let ok = r.termination == Termination::Converged
        && outcome.objective_error() <= 1e-6
        && r.max_violation <= 1e-8;
    if ok {
        Ok(())
    } else {
        Err(format!(
            "{name}: f = {} (f* = {}), |c| = {:e}, {} after {} outer iterations",
            r.objective, test.optimum, r.max_violation, r.termination, r.outer_iterations
        ))
    }
}

#[test]
fn every_hock_schittkowski_problem_is_solved_with_the_default_settings() {
    let settings = AugLagSettings::default();
    let failures: Vec<String> = hock_schittkowski::all()
        .iter()
        .filter_map(|t| check_hs(t.name, &settings).err())
        .collect();
    assert!(failures.is_empty(), "{failures:#?}");
    assert!(
        hock_schittkowski::all().len() >= 20,
        "the set holds the named problems and more"
    );
}

#[test]
fn the_named_problems_are_solved_through_argmin_too() {
    let settings = AugLagSettings::default().with_inner_solver(InnerSolver::Argmin);
    let failures: Vec<String> = NAMED
        .iter()
        .filter_map(|name| check_hs(name, &settings).err())
        .collect();
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn the_solution_is_the_published_optimum_point() {
    // HS28: x* = (0.5, −0.5, 0.5); HS39: x* = (1, 1, 0, 0).
    let r28 = hock_schittkowski::by_name("HS28")
        .unwrap()
        .solve(&AugLagSettings::default());
    for (x, e) in r28.report.x.iter().zip([0.5, -0.5, 0.5]) {
        assert!((x - e).abs() < 1e-6, "HS28 x = {:?}", r28.report.x);
    }
    let r39 = hock_schittkowski::by_name("HS39")
        .unwrap()
        .solve(&AugLagSettings::default());
    for (x, e) in r39.report.x.iter().zip([1.0, 1.0, 0.0, 0.0]) {
        assert!((x - e).abs() < 1e-4, "HS39 x = {:?}", r39.report.x);
    }
}

#[test]
fn contradictory_equalities_end_as_infeasible() {
    for inner in [InnerSolver::Bounded, InnerSolver::Argmin] {
        let g = Graph::new();
        let x = g.var();
        let mut p = Problem::builder(&g, x.square())
            .equality("x = 1", x - 1.0)
            .equality("x = 2", x - 2.0)
            .build();
        let settings = AugLagSettings::default().with_inner_solver(inner);
        let r = solve(&mut p, &[0.0], &settings).unwrap();
        assert_eq!(r.termination, Termination::Infeasible, "{inner:?}: {r:?}");
        assert!(r.outer_iterations <= 20, "promptly: {}", r.outer_iterations);
        assert!((r.x[0] - 1.5).abs() < 1e-3, "the least-violation point");
        assert!((r.max_violation - 0.5).abs() < 1e-3);
        assert!(r.termination.to_string().contains("infeasible"));
    }
}

#[test]
fn an_equality_without_real_solution_ends_as_infeasible() {
    let g = Graph::new();
    let x = g.var();
    let y = g.var();
    let mut p = Problem::builder(&g, (x - 1.0).square() + y.square())
        .equality("x² + 1 = 0", x.square() + 1.0)
        .build();
    let r = solve(&mut p, &[3.0, 1.0], &AugLagSettings::default()).unwrap();
    assert_eq!(r.termination, Termination::Infeasible, "{r:?}");
    assert!(r.outer_iterations <= 20, "promptly: {}", r.outer_iterations);
    assert_eq!(r.worst_constraint, Some(0));
    assert!((r.max_violation - 1.0).abs() < 1e-3, "x² + 1 ≥ 1");
}

#[test]
fn contradictory_inequalities_end_as_infeasible() {
    let g = Graph::new();
    let x = g.var();
    let mut p = Problem::builder(&g, x.square())
        .inequality("x ≥ 2", x - 2.0)
        .inequality("x ≤ 1", 1.0 - x)
        .build();
    let r = solve(&mut p, &[0.0], &AugLagSettings::default()).unwrap();
    assert_eq!(r.termination, Termination::Infeasible, "{r:?}");
}

#[test]
fn a_nan_objective_is_a_numerical_failure() {
    let g = Graph::new();
    let x = g.var();
    // ln of a negative number is NaN at the start point already.
    let mut p = Problem::builder(&g, (x - 5.0).ln())
        .equality("x = 1", x - 1.0)
        .build();
    let r = solve(&mut p, &[1.0], &AugLagSettings::default()).unwrap();
    assert_eq!(r.termination, Termination::NumericalFailure);
    assert_eq!(r.x, vec![1.0], "the last finite point is kept");

    // A NaN constant in the objective.
    let g = Graph::new();
    let x = g.var();
    let mut p = Problem::builder(&g, x.square() * f64::NAN).build();
    let r = solve(&mut p, &[1.0], &AugLagSettings::default()).unwrap();
    assert_eq!(r.termination, Termination::NumericalFailure);
}

#[test]
fn nan_trial_points_are_stepped_back_from() {
    // sqrt(x) is NaN for x < 0. From x = 0.8 the first step (one unit along −∇f) lands
    // at x = −0.2; the bounded line search backs off instead of failing. The minimiser
    // solves 1 − 0.5/√x + 0.1 = 0: x = (0.5/1.1)².
    let g = Graph::new();
    let x = g.var();
    let mut p = Problem::builder(&g, (x.sqrt() - 0.5).square() + 0.1 * x).build();
    let r = solve(&mut p, &[0.8], &AugLagSettings::default()).unwrap();
    assert_eq!(r.termination, Termination::Converged, "{r:?}");
    assert!((r.x[0] - 0.25 / 1.21).abs() < 1e-9, "{r:?}");
}

#[test]
fn bad_start_points_are_errors_not_panics() {
    let g = Graph::new();
    let x = g.var();
    let mut p = Problem::builder(&g, x.square()).build();
    let settings = AugLagSettings::default();
    assert!(solve(&mut p, &[], &settings).is_err());
    assert!(solve(&mut p, &[f64::NAN], &settings).is_err());
    let start = Start {
        x: vec![1.0],
        multipliers: Some(geosnap::core::solve::Multipliers {
            equality: vec![1.0],
            inequality: vec![],
        }),
        penalty: None,
    };
    let err = Solver::new(&settings).solve(&mut p, &start).unwrap_err();
    assert!(err.to_string().contains("multipliers"), "{err}");
}

/// A Rosenbrock-like valley in many variables on a sphere: hundreds of inner iterations.
fn long_problem(g: &Graph) -> Problem {
    let x = g.vars(40);
    let f = g.sum(
        x.windows(2)
            .map(|w| 100.0 * (w[1] - w[0].square()).square() + (1.0 - w[0]).square()),
    );
    let sphere = g.sum(x.iter().map(|v| v.square())) - 30.0;
    Problem::builder(g, f).equality("sphere", sphere).build()
}

#[test]
fn cancelling_stops_within_one_inner_iteration() {
    for inner in [InnerSolver::Bounded, InnerSolver::Argmin] {
        let g = Graph::new();
        let mut p = long_problem(&g);
        // A time limit makes the solver read the clock before every evaluation.
        let settings = AugLagSettings::default()
            .with_inner_solver(inner)
            .with_time_limit(Duration::from_hours(1))
            .unwrap();
        let cancel = CancelFlag::new();
        // Raise the flag from inside the solve: after the clock has been read 50 times
        // (once per evaluation), as a UI thread would at some arbitrary moment.
        let clock = RaiseAfter {
            calls: Cell::new(0),
            after: 50,
            flag: cancel.clone(),
        };
        let r = Solver::new(&settings)
            .cancel(&cancel)
            .clock(&clock)
            .solve(&mut p, &Start::cold(&[-1.0; 40]))
            .unwrap();
        assert_eq!(r.termination, Termination::Cancelled, "{inner:?}");
        // The flag is seen at the very next evaluation.
        assert_eq!(r.evaluations, 50, "{inner:?}");
        assert!(r.x.iter().all(|v| v.is_finite()));
    }
}

/// A clock that raises a cancel flag on its n-th reading; time stands still.
struct RaiseAfter {
    calls: Cell<u32>,
    after: u32,
    flag: CancelFlag,
}

impl Clock for RaiseAfter {
    fn elapsed(&self) -> Duration {
        self.calls.set(self.calls.get() + 1);
        if self.calls.get() >= self.after {
            self.flag.cancel();
        }
        Duration::ZERO
    }
}

/// A fake clock that advances 1 ms per reading.
struct Ticking(Cell<u64>);

impl Clock for Ticking {
    fn elapsed(&self) -> Duration {
        self.0.set(self.0.get() + 1);
        Duration::from_millis(self.0.get())
    }
}

#[test]
fn the_time_limit_ends_a_solve() {
    let g = Graph::new();
    let mut p = long_problem(&g);
    let settings = AugLagSettings::default()
        .with_time_limit(Duration::from_millis(100))
        .unwrap();
    let clock = Ticking(Cell::new(0));
    let r = Solver::new(&settings)
        .clock(&clock)
        .solve(&mut p, &Start::cold(&[-1.0; 40]))
        .unwrap();
    assert_eq!(r.termination, Termination::TimeLimit);
    assert!(r.elapsed >= Duration::from_millis(100));
    assert!(r.evaluations < 100, "one clock reading per evaluation");
}

#[test]
fn the_caps_end_a_solve() {
    let g = Graph::new();
    let mut p = long_problem(&g);
    let start = [-1.0; 40];
    let capped = AugLagSettings::default().with_max_evaluations(30).unwrap();
    let r = solve(&mut p, &start, &capped).unwrap();
    assert_eq!(r.termination, Termination::MaxEvaluations);
    assert!(r.evaluations <= 30);

    let argmin = capped.with_inner_solver(InnerSolver::Argmin);
    let r = solve(&mut p, &start, &argmin).unwrap();
    assert_eq!(r.termination, Termination::MaxEvaluations);
    assert!(r.evaluations <= 30, "argmin's line search is bounded too");

    let one_outer = AugLagSettings::default()
        .with_max_outer_iterations(1)
        .unwrap()
        .with_max_inner_iterations(5)
        .unwrap();
    let r = solve(&mut p, &start, &one_outer).unwrap();
    assert_eq!(r.termination, Termination::MaxOuterIterations);
    assert_eq!(r.outer_iterations, 1);
    assert!(r.inner_iterations <= 5);
}

#[test]
fn a_hard_problem_always_ends_within_the_caps() {
    // Many random starts of problems with awkward geometry: every solve must end with
    // some termination, and quickly (no hang of the original code's kind).
    let mut seed = 7u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % 2000) as f64 / 100.0 - 10.0
    };
    let settings = AugLagSettings::default()
        .with_max_evaluations(20_000)
        .unwrap();
    for _ in 0..200 {
        let g = Graph::new();
        let x = g.var();
        let y = g.var();
        let f = (x * y).sin() + (x - y).abs() + x.powi(4) / 100.0;
        let mut p = Problem::builder(&g, f)
            .equality("curve", x.square() - y.powi(3) - 1.0)
            .inequality("disk", 25.0 - x.square() - y.square())
            .build();
        let r = solve(&mut p, &[next(), next()], &settings).unwrap();
        assert!(r.evaluations <= 20_000);
        assert!(r.x.iter().all(|v| v.is_finite()));
    }
}

#[test]
fn inequalities_are_active_or_inactive_as_they_should_be() {
    let g = Graph::new();
    let x = g.var();
    let y = g.var();
    let f = (x - 2.0).square() + (y - 2.0).square();
    // Active: x ≤ 1 binds; inactive: y ≥ −5 does not.
    let mut p = Problem::builder(&g, f)
        .inequality("x ≤ 1", 1.0 - x)
        .inequality("y ≥ −5", y + 5.0)
        .build();
    let r = solve(&mut p, &[0.0, 0.0], &AugLagSettings::default()).unwrap();
    assert_eq!(r.termination, Termination::Converged, "{r:?}");
    assert!(
        (r.x[0] - 1.0).abs() < 1e-8 && (r.x[1] - 2.0).abs() < 1e-8,
        "{r:?}"
    );
    assert!(
        (r.multipliers.inequality[0] - 2.0).abs() < 1e-6,
        "ν = 2 for the active one"
    );
    assert!(
        r.multipliers.inequality[1].abs() < 1e-12,
        "ν = 0 for the inactive one"
    );
}

#[test]
fn positive_sizes_stay_positive() {
    // Fit a radius to data that would want it negative: the inequality r ≥ 0.01 holds.
    let g = Graph::new();
    let r = g.var();
    let f = (r + 3.0).square();
    let mut p = Problem::builder(&g, f)
        .inequality("r ≥ 0.01", r - 0.01)
        .build();
    let report = solve(&mut p, &[1.0], &AugLagSettings::default()).unwrap();
    assert!(report.termination.is_converged());
    assert!(report.x[0] >= 0.01 - 1e-9, "{report:?}");
}

#[test]
fn the_observer_sees_every_outer_iterate_and_warm_starts_save_work() {
    let test = hock_schittkowski::by_name("HS40").unwrap();
    let mut p = test.compile();
    let settings = AugLagSettings::default();
    let mut seen: Vec<(usize, f64)> = Vec::new();
    let mut record = |it: &Iterate<'_>| seen.push((it.outer, it.max_violation));
    let cold = Solver::new(&settings)
        .observer(&mut record)
        .solve(&mut p, &Start::cold(test.start))
        .unwrap();
    assert_eq!(seen.len(), cold.outer_iterations);
    assert!(seen.iter().enumerate().all(|(i, (k, _))| *k == i + 1));
    assert!(seen.last().unwrap().1 <= 1e-8);

    let warm = Solver::new(&settings)
        .solve(&mut p, &Start::warm(&cold))
        .unwrap();
    assert!(warm.termination.is_converged());
    assert!(
        warm.evaluations < cold.evaluations / 4,
        "warm {} vs cold {} evaluations",
        warm.evaluations,
        cold.evaluations
    );
}

#[test]
fn parameters_change_the_problem_without_recompiling() {
    let g = Graph::new();
    let x = g.var();
    let target = g.param("target", 0.0);
    let mut p = Problem::builder(&g, (x - target).square())
        .inequality("x ≤ 10", 10.0 - x)
        .build();
    let settings = AugLagSettings::default();
    for t in [1.0, 4.0, 12.0] {
        assert!(p.set_param("target", t));
        let r = solve(&mut p, &[0.0], &settings).unwrap();
        assert!((r.x[0] - t.min(10.0)).abs() < 1e-7, "target {t}: {r:?}");
    }
}

#[test]
fn reports_serialise() {
    let r = hock_schittkowski::by_name("HS28")
        .unwrap()
        .solve(&AugLagSettings::default())
        .report;
    let json = serde_json::to_string(&r).unwrap();
    assert!(json.contains("\"termination\":\"converged\""), "{json}");
    let back: geosnap::core::solve::SolveReport = serde_json::from_str(&json).unwrap();
    assert_eq!(back, r);
}

#[test]
fn the_penalty_follows_the_accelerated_schedule() {
    // Contradictory constraints never get below C_max: μ doubles up to μ_max (β = 2).
    let g = Graph::new();
    let x = g.var();
    let mut p = Problem::builder(&g, x.square())
        .equality("x = 1", x - 1.0)
        .equality("x = 2", x - 2.0)
        .build();
    let settings = AugLagSettings::default();
    let mut penalties = Vec::new();
    let mut record = |it: &Iterate<'_>| penalties.push(it.penalty);
    Solver::new(&settings)
        .observer(&mut record)
        .solve(&mut p, &Start::cold(&[0.0]))
        .unwrap();
    assert_eq!(
        penalties[..8],
        [10.0, 20.0, 40.0, 80.0, 160.0, 320.0, 640.0, 1000.0],
        "{penalties:?}"
    );

    // A well-posed problem whose violation falls fast keeps μ₀ all the way.
    let mut p = hock_schittkowski::by_name("HS28").unwrap().compile();
    let mut penalties = Vec::new();
    let mut record = |it: &Iterate<'_>| penalties.push(it.penalty);
    Solver::new(&settings)
        .observer(&mut record)
        .solve(&mut p, &Start::cold(&[-4.0, 1.0, 1.0]))
        .unwrap();
    assert!(
        penalties.iter().all(|&m| (m - 10.0).abs() < 1e-12),
        "{penalties:?}"
    );

    // Other settings are honoured: β = 3 from μ₀ = 1.
    let settings = AugLagSettings::default()
        .with_penalty(1.0, 100.0)
        .unwrap()
        .with_beta(3.0)
        .unwrap();
    let g = Graph::new();
    let x = g.var();
    let mut p = Problem::builder(&g, x.square())
        .equality("x = 1", x - 1.0)
        .equality("x = 2", x - 2.0)
        .build();
    let mut penalties = Vec::new();
    let mut record = |it: &Iterate<'_>| penalties.push(it.penalty);
    Solver::new(&settings)
        .observer(&mut record)
        .solve(&mut p, &Start::cold(&[0.0]))
        .unwrap();
    // Each step either keeps μ (the violation fell below C_max) or multiplies it by β,
    // up to μ_max.
    assert!((penalties[0] - 1.0).abs() < 1e-12, "{penalties:?}");
    for w in penalties.windows(2) {
        let kept = (w[1] - w[0]).abs() < 1e-12;
        let grown = (w[1] - (3.0 * w[0]).min(100.0)).abs() < 1e-12;
        assert!(kept || grown, "{penalties:?}");
    }
    assert!(
        (penalties.last().unwrap() - 100.0).abs() < 1e-12,
        "{penalties:?}"
    );
}

#[test]
fn restoration_judges_feasibility_by_the_violation() {
    // HS61 through argmin once went through a restoration that called its feasible,
    // nearly solved point infeasible.
    let settings = AugLagSettings::default().with_inner_solver(InnerSolver::Argmin);
    check_hs("HS61", &settings).unwrap();
    let hs61 = hock_schittkowski::by_name("HS61").unwrap().solve(&settings);
    for (x, e) in hs61
        .report
        .x
        .iter()
        .zip([5.326_770_157, -2.118_998_639, 3.210_464_239])
    {
        assert!((x - e).abs() < 1e-6, "HS61 x = {:?}", hs61.report.x);
    }
    // A problem without a feasible point is still infeasible, through either solver.
    for inner in [InnerSolver::Bounded, InnerSolver::Argmin] {
        let g = Graph::new();
        let x = g.var();
        let y = g.var();
        let mut p = Problem::builder(&g, (x - 1.0).square() + y.square())
            .equality("on the circle", x.square() + y.square() - 1.0)
            .equality("far out", x - 3.0)
            .build();
        let settings = AugLagSettings::default().with_inner_solver(inner);
        let r = solve(&mut p, &[0.5, 0.5], &settings).unwrap();
        assert_eq!(r.termination, Termination::Infeasible, "{inner:?}: {r:?}");
    }
}
