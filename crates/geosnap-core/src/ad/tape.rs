//! The compiled tape: the nodes that the chosen outputs depend on, in topological order,
//! with one flat array of argument indices and one of local partial derivatives.
//!
//! Layout of the slots: first every variable of the graph (slot `i` is variable `i`,
//! used or not, so gradients come out in variable order), then every parameter, then the
//! constants and operations the outputs need. Evaluation is a forward sweep over the
//! operations; the gradient of any weighted sum of the outputs is one reverse sweep that
//! adds `adjoint × partial` along every edge. Nothing is allocated per evaluation.

use super::graph::Graph;
use super::ops::Op;

/// Identifies a parameter of a compiled [`Tape`]; see [`Tape::param_id`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ParamId(pub(crate) u32);

/// What the last sweep left in the buffers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Swept {
    Nothing,
    Values,
    ValuesAndPartials,
}

/// A compiled set of expressions (the outputs), evaluated many times for different
/// variables and parameters.
///
/// # Examples
///
/// Value and gradient of one output, then the Jacobian of two:
///
/// ```
/// use geosnap_core::ad::{Graph, Tape};
///
/// let g = Graph::new();
/// let x = g.var();
/// let y = g.var();
/// let target = g.param("target", 0.0);
/// let residual = (x - target).square() + y.square();
/// let mut tape = Tape::compile(&g, &[residual, x * y]);
///
/// let id = tape.param_id("target").unwrap();
/// tape.set_param(id, 3.0);
/// let mut grad = [0.0; 2];
/// let f = tape.gradient(&[1.0, 2.0], &mut grad);
/// assert_eq!(f, 8.0);
/// assert_eq!(grad, [-4.0, 4.0]);
///
/// let mut jacobian = [0.0; 4];
/// tape.jacobian(&[1.0, 2.0], &mut jacobian);
/// assert_eq!(jacobian, [-4.0, 4.0, 2.0, 1.0]);
/// ```
#[derive(Clone, Debug)]
pub struct Tape {
    ops: Vec<Op>,
    /// `args_start[k]..args_start[k + 1]` indexes the arguments and partials of the k-th
    /// operation (slot `first_op + k`).
    args_start: Vec<u32>,
    args: Vec<u32>,
    partials: Vec<f64>,
    values: Vec<f64>,
    adjoints: Vec<f64>,
    var_count: usize,
    param_names: Vec<String>,
    /// The slot of each output.
    outputs: Vec<u32>,
    /// Output values of the last sweep.
    output_values: Vec<f64>,
    /// Index of the first slot that is computed (after variables, parameters, constants).
    first_op: usize,
    swept: Swept,
}

impl Tape {
    /// Compiles `outputs` (expressions of `graph`) into a tape.
    ///
    /// Only the nodes the outputs depend on are kept; every variable and parameter of the
    /// graph keeps a slot. Parameters start at the default given in [`Graph::param`].
    ///
    /// # Panics
    ///
    /// If an output belongs to another graph (a programming error).
    pub fn compile(graph: &Graph, outputs: &[super::Expr<'_>]) -> Self {
        let nodes = graph.inner.borrow();
        let n_nodes = nodes.nodes.len();
        for out in outputs {
            assert!(
                std::ptr::eq(out.graph, graph),
                "an output of Tape::compile belongs to another graph"
            );
        }
        // Mark what the outputs need, walking backwards (creation order is topological).
        let mut needed = vec![false; n_nodes];
        for out in outputs {
            needed[out.id as usize] = true;
        }
        for id in (0..n_nodes).rev() {
            if needed[id] {
                let node = nodes.nodes[id];
                for &arg in nodes.args_of(&node) {
                    needed[arg as usize] = true;
                }
            }
        }

        let var_count = nodes.var_count as usize;
        let param_count = nodes.param_names.len();
        let mut ops: Vec<Op> = (0..var_count as u32).map(Op::Var).collect();
        ops.extend((0..param_count as u32).map(Op::Param));
        let mut values = vec![0.0; var_count];
        values.extend_from_slice(&nodes.param_defaults);
        let mut slot_of: Vec<u32> = vec![u32::MAX; n_nodes];

        // Leaves first: variables and parameters have fixed slots, constants follow.
        for (id, node) in nodes.nodes.iter().enumerate() {
            match node.op {
                Op::Var(i) => {
                    slot_of[id] = i;
                }
                Op::Param(i) => {
                    slot_of[id] = var_count as u32 + i;
                }
                Op::Const(bits) if needed[id] => {
                    slot_of[id] = ops.len() as u32;
                    ops.push(node.op);
                    values.push(f64::from_bits(bits));
                }
                _ => {}
            }
        }
        let first_op = ops.len();
        let mut args_start = vec![0u32];
        let mut args = Vec::new();
        for (id, node) in nodes.nodes.iter().enumerate() {
            if !needed[id] || node.op.is_leaf() {
                continue;
            }
            slot_of[id] = ops.len() as u32;
            ops.push(node.op);
            values.push(0.0);
            args.extend(nodes.args_of(node).iter().map(|&a| slot_of[a as usize]));
            args_start.push(args.len() as u32);
        }
        let outputs: Vec<u32> = outputs.iter().map(|o| slot_of[o.id as usize]).collect();
        let slots = ops.len();
        Self {
            partials: vec![0.0; args.len()],
            adjoints: vec![0.0; slots],
            output_values: vec![0.0; outputs.len()],
            ops,
            args_start,
            args,
            values,
            var_count,
            param_names: nodes.param_names.clone(),
            outputs,
            first_op,
            swept: Swept::Nothing,
        }
    }

    /// The number of variables (the length of every `x` and gradient slice).
    pub fn var_count(&self) -> usize {
        self.var_count
    }

    /// The number of outputs.
    pub fn output_count(&self) -> usize {
        self.outputs.len()
    }

    /// The number of computed nodes (operations) on the tape.
    pub fn op_count(&self) -> usize {
        self.ops.len() - self.first_op
    }

    /// The number of edges (argument links), the other half of the sweep cost.
    pub fn edge_count(&self) -> usize {
        self.args.len()
    }

    /// The id of the parameter called `name`, if the graph had one.
    pub fn param_id(&self, name: &str) -> Option<ParamId> {
        self.param_names
            .iter()
            .position(|n| n == name)
            .map(|i| ParamId(i as u32))
    }

    /// The names of the parameters, in [`ParamId`] order.
    pub fn param_names(&self) -> &[String] {
        &self.param_names
    }

    /// Sets a parameter for the following evaluations.
    pub fn set_param(&mut self, id: ParamId, value: f64) {
        self.values[self.var_count + id.0 as usize] = value;
        self.swept = Swept::Nothing;
    }

    /// The current value of a parameter.
    pub fn param(&self, id: ParamId) -> f64 {
        self.values[self.var_count + id.0 as usize]
    }

    fn load(&mut self, x: &[f64]) {
        assert_eq!(
            x.len(),
            self.var_count,
            "the tape has {} variables but x has {} values",
            self.var_count,
            x.len()
        );
        self.values[..self.var_count].copy_from_slice(x);
    }

    /// One forward sweep; with `PARTIALS` it also records the local derivatives.
    fn sweep<const PARTIALS: bool>(&mut self) {
        let mut scratch = [0.0f64; 8];
        let (computed, inputs) = (self.first_op, &self.args_start);
        for (k, op) in self.ops[computed..].iter().enumerate() {
            let (start, end) = (inputs[k] as usize, inputs[k + 1] as usize);
            let args = &self.args[start..end];
            let value = match *op {
                // Sums read their arguments straight from the value array.
                Op::Sum => {
                    if PARTIALS {
                        self.partials[start..end].fill(1.0);
                    }
                    args.iter().map(|&a| self.values[a as usize]).sum()
                }
                // So does a polyline's distance, which has as many as its vertices.
                Op::PolylineDistance => {
                    let values = &self.values;
                    super::ops::polyline_distance::<PARTIALS>(
                        args.len(),
                        |i| values[args[i] as usize],
                        &mut self.partials[start..end],
                    )
                }
                op => {
                    for (s, &a) in scratch.iter_mut().zip(args) {
                        *s = self.values[a as usize];
                    }
                    op.eval::<PARTIALS>(&scratch[..args.len()], &mut self.partials[start..end])
                }
            };
            self.values[computed + k] = value;
        }
        for (out, &slot) in self.output_values.iter_mut().zip(&self.outputs) {
            *out = self.values[slot as usize];
        }
        self.swept = if PARTIALS {
            Swept::ValuesAndPartials
        } else {
            Swept::Values
        };
    }

    /// Evaluates every output at `x` (values only, the cheapest sweep).
    ///
    /// # Panics
    ///
    /// If `x.len()` is not [`Tape::var_count`].
    pub fn eval(&mut self, x: &[f64]) -> &[f64] {
        self.load(x);
        self.sweep::<false>();
        &self.output_values
    }

    /// Evaluates every output at `x` and records the local derivatives, ready for
    /// [`Tape::reverse`]. Returns the output values.
    ///
    /// # Panics
    ///
    /// If `x.len()` is not [`Tape::var_count`].
    pub fn forward(&mut self, x: &[f64]) -> &[f64] {
        self.load(x);
        self.sweep::<true>();
        &self.output_values
    }

    /// The output values of the last sweep.
    pub fn output_values(&self) -> &[f64] {
        &self.output_values
    }

    /// One reverse sweep after [`Tape::forward`]: writes into `grad` the gradient of
    /// `Σₖ seeds[k] · outputₖ` with respect to the variables.
    ///
    /// This is how a Lagrangian `f + Σ wᵢ cᵢ` gets its gradient from one tape holding `f`
    /// and the `cᵢ` as outputs: the weights are computed from the forward values.
    ///
    /// # Panics
    ///
    /// If [`Tape::forward`] did not run since the last change of variables or parameters,
    /// or if the slice lengths are wrong.
    pub fn reverse(&mut self, seeds: &[f64], grad: &mut [f64]) {
        assert_eq!(
            self.swept,
            Swept::ValuesAndPartials,
            "Tape::reverse needs Tape::forward first"
        );
        assert_eq!(seeds.len(), self.outputs.len(), "one seed per output");
        assert_eq!(
            grad.len(),
            self.var_count,
            "one gradient entry per variable"
        );
        self.adjoints.fill(0.0);
        for (&slot, &seed) in self.outputs.iter().zip(seeds) {
            self.adjoints[slot as usize] += seed;
        }
        self.reverse_from_adjoints(grad);
    }

    /// Value and gradient of output 0 at `x`.
    ///
    /// # Panics
    ///
    /// If the tape has no output or the slice lengths are wrong.
    pub fn gradient(&mut self, x: &[f64], grad: &mut [f64]) -> f64 {
        assert!(!self.outputs.is_empty(), "the tape has no output");
        self.forward(x);
        // A one-hot seed without allocating: the other outputs get weight 0.
        self.adjoints.fill(0.0);
        self.adjoints[self.outputs[0] as usize] = 1.0;
        self.reverse_from_adjoints(grad);
        self.output_values[0]
    }

    /// The Jacobian of all outputs at `x`, row-major (`outputs × variables`), one reverse
    /// sweep per output.
    ///
    /// # Panics
    ///
    /// If `jacobian.len()` is not `output_count · var_count` or `x` has the wrong length.
    pub fn jacobian(&mut self, x: &[f64], jacobian: &mut [f64]) {
        let n = self.var_count;
        assert_eq!(
            jacobian.len(),
            self.outputs.len() * n,
            "the Jacobian has one row of var_count entries per output"
        );
        self.forward(x);
        for (row, k) in jacobian
            .chunks_exact_mut(n.max(1))
            .zip(0..self.outputs.len())
        {
            self.adjoints.fill(0.0);
            self.adjoints[self.outputs[k] as usize] = 1.0;
            self.reverse_from_adjoints(&mut row[..n]);
        }
    }

    /// The reverse sweep proper, from adjoints already seeded.
    fn reverse_from_adjoints(&mut self, grad: &mut [f64]) {
        for slot in (self.first_op..self.ops.len()).rev() {
            let adjoint = self.adjoints[slot];
            if adjoint == 0.0 {
                continue;
            }
            let start = self.args_start[slot - self.first_op] as usize;
            let end = self.args_start[slot - self.first_op + 1] as usize;
            for e in start..end {
                self.adjoints[self.args[e] as usize] += adjoint * self.partials[e];
            }
        }
        grad.copy_from_slice(&self.adjoints[..self.var_count]);
    }
}

#[cfg(test)]
mod tests {
    use super::Tape;
    use crate::ad::Graph;

    fn assert_close(got: &[f64], want: &[f64]) {
        assert_eq!(got.len(), want.len(), "lengths differ");
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g - w).abs() <= 1e-14 * w.abs().max(1.0),
                "{got:?} vs {want:?}"
            );
        }
    }

    #[test]
    fn shared_subexpression_is_one_slot() {
        let g = Graph::new();
        let x = g.var();
        let s = x.sin();
        let f = s * s + s;
        let tape = Tape::compile(&g, &[f]);
        // x, sin, mul, add.
        assert_eq!(tape.op_count(), 3, "sin x is computed once");
    }

    #[test]
    fn unused_nodes_are_not_compiled_and_unused_vars_get_zero_gradient() {
        let g = Graph::new();
        let x = g.var();
        let y = g.var();
        let _unused = (y.exp() * 4.0).sin();
        let mut tape = Tape::compile(&g, &[x.square()]);
        assert_eq!(tape.op_count(), 1, "only the square");
        let mut grad = [1.0; 2];
        let f = tape.gradient(&[3.0, 7.0], &mut grad);
        assert!((f - 9.0).abs() < 1e-15);
        assert_close(&grad, &[6.0, 0.0]);
    }

    #[test]
    fn weighted_reverse_sweep_is_the_gradient_of_the_weighted_sum() {
        let g = Graph::new();
        let x = g.var();
        let y = g.var();
        let f = x * y;
        let c = x.square() - y;
        let mut tape = Tape::compile(&g, &[f, c]);
        let values = tape.forward(&[2.0, 3.0]).to_vec();
        assert_close(&values, &[6.0, 1.0]);
        let mut grad = [0.0; 2];
        tape.reverse(&[1.0, 0.5], &mut grad);
        // ∇(xy + ½(x² − y)) = (y + x, x − ½).
        assert_close(&grad, &[5.0, 1.5]);
    }

    #[test]
    fn a_constant_output_has_zero_gradient() {
        let g = Graph::new();
        let _x = g.var();
        let mut tape = Tape::compile(&g, &[g.constant(4.0)]);
        let mut grad = [1.0];
        assert!((tape.gradient(&[1.0], &mut grad) - 4.0).abs() < 1e-15);
        assert_close(&grad, &[0.0]);
    }

    #[test]
    fn params_change_without_recompiling() {
        let g = Graph::new();
        let x = g.var();
        let w = g.param("w", 2.0);
        let mut tape = Tape::compile(&g, &[w * x]);
        assert!((tape.eval(&[3.0])[0] - 6.0).abs() < 1e-15);
        let id = tape.param_id("w").unwrap();
        tape.set_param(id, -1.0);
        let mut grad = [0.0];
        assert!((tape.gradient(&[3.0], &mut grad) + 3.0).abs() < 1e-15);
        assert_close(&grad, &[-1.0]);
        assert!(tape.param_id("nope").is_none());
    }
}
