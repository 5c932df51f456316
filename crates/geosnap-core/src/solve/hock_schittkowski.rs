//! Equality-constrained problems of the Hock–Schittkowski collection (W. Hock and
//! K. Schittkowski, *Test Examples for Nonlinear Programming Codes*, 1981), written from
//! the published definitions with their standard start points and optimal values.
//!
//! They check the solver on a machine (`geosnap selftest`), in the tests and in the
//! benchmarks.
//!
//! # Examples
//!
//! ```
//! use geosnap_core::solve::hock_schittkowski::{self, Outcome};
//! use geosnap_core::solve::AugLagSettings;
//!
//! let hs28 = hock_schittkowski::by_name("HS28").unwrap();
//! let outcome: Outcome = hs28.solve(&AugLagSettings::default());
//! assert!(outcome.objective_error() <= 1e-6);
//! ```

use std::f64::consts::{PI, SQRT_2};

use super::{solve, AugLagSettings, Problem, SolveReport};
use crate::ad::{Expr, Graph};

/// The objective and equality constraints of a test problem, built on its variables.
pub type Parts<'g> = (Expr<'g>, Vec<Expr<'g>>);

/// One test problem.
#[derive(Clone, Copy, Debug)]
pub struct TestProblem {
    /// Its number in the collection, as `HSn`.
    pub name: &'static str,
    /// The standard start point (its length is the number of variables).
    pub start: &'static [f64],
    /// The optimal objective value f*.
    pub optimum: f64,
    /// Builds the objective and the equality constraints on the variables.
    pub build: for<'g> fn(&'g Graph, &[Expr<'g>]) -> Parts<'g>,
}

/// A solved test problem.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The problem.
    pub problem: TestProblem,
    /// The solver's report.
    pub report: SolveReport,
}

impl Outcome {
    /// |f − f*| / max(1, |f*|).
    pub fn objective_error(&self) -> f64 {
        (self.report.objective - self.problem.optimum).abs() / self.problem.optimum.abs().max(1.0)
    }
}

impl TestProblem {
    /// Compiles the problem.
    pub fn compile(&self) -> Problem {
        let g = Graph::new();
        let x = g.vars(self.start.len());
        let (objective, equalities) = (self.build)(&g, &x);
        Problem::new(&g, objective, &equalities, &[])
    }

    /// Solves the problem from its standard start point.
    ///
    /// # Panics
    ///
    /// Never for the problems of this module (their start points fit).
    pub fn solve(&self, settings: &AugLagSettings) -> Outcome {
        let mut problem = self.compile();
        let report = solve(&mut problem, self.start, settings)
            .expect("the standard start point fits the problem");
        Outcome {
            problem: *self,
            report,
        }
    }
}

/// The problem called `name` (such as `"HS28"`), if this module has it.
pub fn by_name(name: &str) -> Option<TestProblem> {
    all()
        .into_iter()
        .find(|p| p.name.eq_ignore_ascii_case(name))
}

/// Every problem of this module, in collection order.
#[expect(
    clippy::too_many_lines,
    reason = "a table of problems, one short entry each"
)]
pub fn all() -> Vec<TestProblem> {
    vec![
        TestProblem {
            name: "HS6",
            start: &[-1.2, 1.0],
            optimum: 0.0,
            build: |_, x| ((1.0 - x[0]).square(), vec![10.0 * (x[1] - x[0].square())]),
        },
        TestProblem {
            name: "HS7",
            start: &[2.0, 2.0],
            optimum: -1.732_050_807_568_877_2,
            build: |_, x| {
                (
                    (1.0 + x[0].square()).ln() - x[1],
                    vec![(1.0 + x[0].square()).square() + x[1].square() - 4.0],
                )
            },
        },
        TestProblem {
            name: "HS8",
            start: &[2.0, 1.0],
            optimum: -1.0,
            build: |g, x| {
                (
                    g.constant(-1.0),
                    vec![x[0].square() + x[1].square() - 25.0, x[0] * x[1] - 9.0],
                )
            },
        },
        TestProblem {
            name: "HS9",
            start: &[0.0, 0.0],
            optimum: -0.5,
            build: |_, x| {
                (
                    (PI * x[0] / 12.0).sin() * (PI * x[1] / 16.0).cos(),
                    vec![4.0 * x[0] - 3.0 * x[1]],
                )
            },
        },
        TestProblem {
            name: "HS26",
            start: &[-2.6, 2.0, 2.0],
            optimum: 0.0,
            build: |_, x| {
                (
                    (x[0] - x[1]).square() + (x[1] - x[2]).powi(4),
                    vec![(1.0 + x[1].square()) * x[0] + x[2].powi(4) - 3.0],
                )
            },
        },
        TestProblem {
            name: "HS27",
            start: &[2.0, 2.0, 2.0],
            optimum: 0.04,
            build: |_, x| {
                (
                    0.01 * (x[0] - 1.0).square() + (x[1] - x[0].square()).square(),
                    vec![x[0] + x[2].square() + 1.0],
                )
            },
        },
        TestProblem {
            name: "HS28",
            start: &[-4.0, 1.0, 1.0],
            optimum: 0.0,
            build: |_, x| {
                (
                    (x[0] + x[1]).square() + (x[1] + x[2]).square(),
                    vec![x[0] + 2.0 * x[1] + 3.0 * x[2] - 1.0],
                )
            },
        },
        TestProblem {
            name: "HS39",
            start: &[2.0, 2.0, 2.0, 2.0],
            optimum: -1.0,
            build: |_, x| {
                (
                    -x[0],
                    vec![
                        x[1] - x[0].powi(3) - x[2].square(),
                        x[0].square() - x[1] - x[3].square(),
                    ],
                )
            },
        },
        TestProblem {
            name: "HS40",
            start: &[0.8, 0.8, 0.8, 0.8],
            optimum: -0.25,
            build: |_, x| {
                (
                    -(x[0] * x[1] * x[2] * x[3]),
                    vec![
                        x[0].powi(3) + x[1].square() - 1.0,
                        x[0].square() * x[3] - x[2],
                        x[3].square() - x[1],
                    ],
                )
            },
        },
        TestProblem {
            name: "HS42",
            start: &[1.0, 1.0, 1.0, 1.0],
            optimum: 28.0 - 10.0 * SQRT_2,
            build: |g, x| {
                (
                    g.sum([
                        (x[0] - 1.0).square(),
                        (x[1] - 2.0).square(),
                        (x[2] - 3.0).square(),
                        (x[3] - 4.0).square(),
                    ]),
                    vec![x[0] - 2.0, x[2].square() + x[3].square() - 2.0],
                )
            },
        },
        TestProblem {
            name: "HS46",
            start: &[SQRT_2 / 2.0, 1.75, 0.5, 2.0, 2.0],
            optimum: 0.0,
            build: |g, x| {
                (
                    g.sum([
                        (x[0] - x[1]).square(),
                        (x[2] - 1.0).square(),
                        (x[3] - 1.0).powi(4),
                        (x[4] - 1.0).powi(6),
                    ]),
                    vec![
                        x[0].square() * x[3] + (x[3] - x[4]).sin() - 1.0,
                        x[1] + x[2].powi(4) * x[3].square() - 2.0,
                    ],
                )
            },
        },
        TestProblem {
            name: "HS47",
            start: &[2.0, SQRT_2, -1.0, 2.0 - SQRT_2, 0.5],
            optimum: 0.0,
            build: |g, x| {
                (
                    g.sum([
                        (x[0] - x[1]).square(),
                        (x[1] - x[2]).powi(3),
                        (x[2] - x[3]).powi(4),
                        (x[3] - x[4]).powi(4),
                    ]),
                    vec![
                        x[0] + x[1].square() + x[2].powi(3) - 3.0,
                        x[1] - x[2].square() + x[3] - 1.0,
                        x[0] * x[4] - 1.0,
                    ],
                )
            },
        },
        TestProblem {
            name: "HS48",
            start: &[3.0, 5.0, -3.0, 2.0, -2.0],
            optimum: 0.0,
            build: |g, x| {
                (
                    g.sum([
                        (x[0] - 1.0).square(),
                        (x[1] - x[2]).square(),
                        (x[3] - x[4]).square(),
                    ]),
                    vec![
                        g.sum(x.iter().copied()) - 5.0,
                        x[2] - 2.0 * (x[3] + x[4]) + 3.0,
                    ],
                )
            },
        },
        TestProblem {
            name: "HS49",
            start: &[10.0, 7.0, 2.0, -3.0, 0.8],
            optimum: 0.0,
            build: |g, x| {
                (
                    g.sum([
                        (x[0] - x[1]).square(),
                        (x[2] - 1.0).square(),
                        (x[3] - 1.0).powi(4),
                        (x[4] - 1.0).powi(6),
                    ]),
                    vec![
                        x[0] + x[1] + x[2] + 4.0 * x[3] - 7.0,
                        x[2] + 5.0 * x[4] - 6.0,
                    ],
                )
            },
        },
        TestProblem {
            name: "HS50",
            start: &[35.0, -31.0, 11.0, 5.0, -5.0],
            optimum: 0.0,
            build: |g, x| {
                (
                    g.sum([
                        (x[0] - x[1]).square(),
                        (x[1] - x[2]).square(),
                        (x[2] - x[3]).powi(4),
                        (x[3] - x[4]).square(),
                    ]),
                    vec![
                        x[0] + 2.0 * x[1] + 3.0 * x[2] - 6.0,
                        x[1] + 2.0 * x[2] + 3.0 * x[3] - 6.0,
                        x[2] + 2.0 * x[3] + 3.0 * x[4] - 6.0,
                    ],
                )
            },
        },
        TestProblem {
            name: "HS51",
            start: &[2.5, 0.5, 2.0, -1.0, 0.5],
            optimum: 0.0,
            build: |g, x| {
                (
                    g.sum([
                        (x[0] - x[1]).square(),
                        (x[1] + x[2] - 2.0).square(),
                        (x[3] - 1.0).square(),
                        (x[4] - 1.0).square(),
                    ]),
                    vec![
                        x[0] + 3.0 * x[1] - 4.0,
                        x[2] + x[3] - 2.0 * x[4],
                        x[1] - x[4],
                    ],
                )
            },
        },
        TestProblem {
            name: "HS52",
            start: &[2.0, 2.0, 2.0, 2.0, 2.0],
            optimum: 1859.0 / 349.0,
            build: |g, x| {
                (
                    g.sum([
                        (4.0 * x[0] - x[1]).square(),
                        (x[1] + x[2] - 2.0).square(),
                        (x[3] - 1.0).square(),
                        (x[4] - 1.0).square(),
                    ]),
                    vec![x[0] + 3.0 * x[1], x[2] + x[3] - 2.0 * x[4], x[1] - x[4]],
                )
            },
        },
        TestProblem {
            name: "HS61",
            start: &[0.0, 0.0, 0.0],
            optimum: -143.646_142_2,
            build: |g, x| {
                (
                    g.sum([
                        4.0 * x[0].square() + 2.0 * x[1].square() + 2.0 * x[2].square(),
                        -33.0 * x[0] + 16.0 * x[1] - 24.0 * x[2],
                    ]),
                    vec![
                        3.0 * x[0] - 2.0 * x[1].square() - 7.0,
                        4.0 * x[0] - x[2].square() - 11.0,
                    ],
                )
            },
        },
        TestProblem {
            name: "HS77",
            start: &[2.0, 2.0, 2.0, 2.0, 2.0],
            optimum: 0.241_505_128_5,
            build: |g, x| {
                (
                    g.sum([
                        (x[0] - 1.0).square(),
                        (x[0] - x[1]).square(),
                        (x[2] - 1.0).square(),
                        (x[3] - 1.0).powi(4),
                        (x[4] - 1.0).powi(6),
                    ]),
                    vec![
                        x[0].square() * x[3] + (x[3] - x[4]).sin() - 2.0 * SQRT_2,
                        x[1] + x[2].powi(4) * x[3].square() - 8.0 - SQRT_2,
                    ],
                )
            },
        },
        TestProblem {
            name: "HS78",
            start: &[-2.0, 1.5, 2.0, -1.0, -1.0],
            optimum: -2.919_700_415,
            build: |g, x| {
                (
                    x[0] * x[1] * x[2] * x[3] * x[4],
                    vec![
                        g.sum(x.iter().map(|v| v.square())) - 10.0,
                        x[1] * x[2] - 5.0 * x[3] * x[4],
                        x[0].powi(3) + x[1].powi(3) + 1.0,
                    ],
                )
            },
        },
        TestProblem {
            name: "HS79",
            start: &[2.0, 2.0, 2.0, 2.0, 2.0],
            optimum: 0.078_776_821_1,
            build: |g, x| {
                (
                    g.sum([
                        (x[0] - 1.0).square(),
                        (x[0] - x[1]).square(),
                        (x[1] - x[2]).square(),
                        (x[2] - x[3]).powi(4),
                        (x[3] - x[4]).powi(4),
                    ]),
                    vec![
                        x[0] + x[1].square() + x[2].powi(3) - 2.0 - 3.0 * SQRT_2,
                        x[1] - x[2].square() + x[3] + 2.0 - 2.0 * SQRT_2,
                        x[0] * x[4] - 2.0,
                    ],
                )
            },
        },
    ]
}
