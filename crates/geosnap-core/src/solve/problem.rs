//! A constrained problem compiled once: min f(x) s.t. cᵢ(x) = 0, gⱼ(x) ≥ 0.

use crate::ad::{Expr, Graph, ParamId, Tape};

/// A compiled constrained problem: the objective, the equality constraints cᵢ(x) = 0 and
/// the inequality constraints gⱼ(x) ≥ 0, as outputs of one [`Tape`] (in that order), with
/// a label per constraint for diagnostics.
///
/// The variables are those of the [`Graph`] the expressions were built in, in creation
/// order. Parameters of the graph can be changed between solves with
/// [`Problem::set_param`] without recompiling.
///
/// # Examples
///
/// ```
/// use geosnap_core::ad::Graph;
/// use geosnap_core::solve::Problem;
///
/// let g = Graph::new();
/// let x = g.var();
/// let y = g.var();
/// let problem = Problem::builder(&g, x.square() + y.square())
///     .equality("on the line", x + y - 1.0)
///     .inequality("x ≥ 0.2", x - 0.2)
///     .build();
/// assert_eq!((problem.var_count(), problem.equality_count()), (2, 1));
/// ```
#[derive(Clone, Debug)]
pub struct Problem {
    pub(crate) tape: Tape,
    equality_count: usize,
    inequality_count: usize,
    labels: Vec<String>,
}

/// Collects the parts of a [`Problem`]; see [`Problem::builder`].
#[derive(Debug)]
pub struct ProblemBuilder<'g> {
    graph: &'g Graph,
    objective: Expr<'g>,
    equalities: Vec<(String, Expr<'g>)>,
    inequalities: Vec<(String, Expr<'g>)>,
}

impl<'g> ProblemBuilder<'g> {
    /// Adds the equality constraint `c(x) = 0`.
    #[must_use]
    pub fn equality(mut self, label: impl Into<String>, c: Expr<'g>) -> Self {
        self.equalities.push((label.into(), c));
        self
    }

    /// Adds the inequality constraint `g(x) ≥ 0`.
    #[must_use]
    pub fn inequality(mut self, label: impl Into<String>, g: Expr<'g>) -> Self {
        self.inequalities.push((label.into(), g));
        self
    }

    /// Compiles the problem.
    pub fn build(self) -> Problem {
        let mut outputs = vec![self.objective];
        outputs.extend(self.equalities.iter().map(|(_, e)| *e));
        outputs.extend(self.inequalities.iter().map(|(_, e)| *e));
        let labels = self
            .equalities
            .iter()
            .chain(&self.inequalities)
            .map(|(l, _)| l.clone())
            .collect();
        Problem {
            tape: Tape::compile(self.graph, &outputs),
            equality_count: self.equalities.len(),
            inequality_count: self.inequalities.len(),
            labels,
        }
    }
}

impl Problem {
    /// Starts a problem with objective `objective`; add constraints, then
    /// [`build`](ProblemBuilder::build).
    pub fn builder<'g>(graph: &'g Graph, objective: Expr<'g>) -> ProblemBuilder<'g> {
        ProblemBuilder {
            graph,
            objective,
            equalities: Vec::new(),
            inequalities: Vec::new(),
        }
    }

    /// A problem from unlabelled equalities and inequalities (labelled `c0, c1, …` and
    /// `g0, g1, …`).
    pub fn new<'g>(
        graph: &'g Graph,
        objective: Expr<'g>,
        equalities: &[Expr<'g>],
        inequalities: &[Expr<'g>],
    ) -> Self {
        let mut builder = Self::builder(graph, objective);
        for (i, c) in equalities.iter().enumerate() {
            builder = builder.equality(format!("c{i}"), *c);
        }
        for (j, g) in inequalities.iter().enumerate() {
            builder = builder.inequality(format!("g{j}"), *g);
        }
        builder.build()
    }

    /// The number of variables.
    pub fn var_count(&self) -> usize {
        self.tape.var_count()
    }

    /// The number of equality constraints.
    pub fn equality_count(&self) -> usize {
        self.equality_count
    }

    /// The number of inequality constraints.
    pub fn inequality_count(&self) -> usize {
        self.inequality_count
    }

    /// The label of constraint `k` (equalities first, then inequalities), as used by
    /// [`SolveReport::worst_constraint`](super::SolveReport::worst_constraint).
    pub fn constraint_label(&self, k: usize) -> Option<&str> {
        self.labels.get(k).map(String::as_str)
    }

    /// Sets the graph parameter `name` for the following solves; returns `false` if the
    /// graph has no such parameter.
    pub fn set_param(&mut self, name: &str, value: f64) -> bool {
        match self.tape.param_id(name) {
            Some(id) => {
                self.tape.set_param(id, value);
                true
            }
            None => false,
        }
    }

    /// The id of a parameter, for repeated [`Problem::set_param_id`] calls.
    pub fn param_id(&self, name: &str) -> Option<ParamId> {
        self.tape.param_id(name)
    }

    /// Sets a parameter by id.
    pub fn set_param_id(&mut self, id: ParamId, value: f64) {
        self.tape.set_param(id, value);
    }

    /// The objective value at `x`.
    ///
    /// # Panics
    ///
    /// If `x` does not have [`Problem::var_count`] entries.
    pub fn objective(&mut self, x: &[f64]) -> f64 {
        self.tape.eval(x)[0]
    }

    /// The objective value at `x`, with its gradient written into `grad`.
    ///
    /// # Panics
    ///
    /// If `x` or `grad` does not have [`Problem::var_count`] entries.
    pub fn gradient(&mut self, x: &[f64], grad: &mut [f64]) -> f64 {
        self.tape.gradient(x, grad)
    }

    /// The constraint values at `x`: equalities, then inequalities.
    ///
    /// # Panics
    ///
    /// If `x` does not have [`Problem::var_count`] entries.
    pub fn constraints(&mut self, x: &[f64]) -> Vec<f64> {
        self.tape.eval(x)[1..].to_vec()
    }

    /// The Jacobian of the constraints at `x`, row-major (constraints × variables):
    /// for diagnostics such as finding redundant or conflicting constraints.
    ///
    /// # Panics
    ///
    /// If `x` does not have [`Problem::var_count`] entries.
    pub fn constraint_jacobian(&mut self, x: &[f64]) -> Vec<f64> {
        let n = self.var_count();
        let mut all = vec![0.0; self.tape.output_count() * n];
        self.tape.jacobian(x, &mut all);
        all.split_off(n)
    }
}

#[cfg(test)]
mod tests {
    use super::Problem;
    use crate::ad::Graph;

    #[test]
    fn constraint_jacobian_and_labels() {
        let g = Graph::new();
        let x = g.var();
        let y = g.var();
        let w = g.param("w", 2.0);
        let mut p = Problem::builder(&g, x * y)
            .equality("sum", x + w * y)
            .inequality("x pos", x)
            .build();
        assert_eq!(p.constraint_label(0), Some("sum"));
        assert_eq!(p.constraint_label(1), Some("x pos"));
        assert_eq!(p.constraint_label(2), None);
        assert_eq!(p.constraint_jacobian(&[1.0, 1.0]), vec![1.0, 2.0, 1.0, 0.0]);
        assert!(p.set_param("w", 5.0));
        assert!(!p.set_param("nope", 5.0));
        assert_eq!(p.constraints(&[1.0, 1.0]), vec![6.0, 1.0]);
        assert!((p.objective(&[2.0, 3.0]) - 6.0).abs() < 1e-15);
        let mut grad = [0.0; 2];
        assert!((p.gradient(&[2.0, 3.0], &mut grad) - 6.0).abs() < 1e-15);
        assert!(
            (grad[0] - 3.0).abs() < 1e-15 && (grad[1] - 2.0).abs() < 1e-15,
            "{grad:?}"
        );
    }
}
