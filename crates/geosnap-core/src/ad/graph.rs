//! The expression builder: a [`Graph`] owns the nodes, an [`Expr`] is a small `Copy`
//! handle to one of them with the usual arithmetic operators.
//!
//! Nodes are hash-consed: building the same operation on the same operands twice returns
//! the same node, so a sub-expression written twice is still evaluated once. Operations
//! on constants are folded, and the identities `x + 0`, `x · 1`, `x / 1` and `−(−x)` are
//! applied while building.

use std::cell::RefCell;
use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Sub};

use rustc_hash::FxHashMap;

use super::ops::Op;

/// Index of a node inside its [`Graph`].
pub(crate) type NodeId = u32;

/// One node of the graph: an op and the range of its arguments in [`Nodes::args`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    pub(crate) op: Op,
    pub(crate) args_start: u32,
    pub(crate) args_len: u32,
}

/// The node storage of a graph, in creation order (which is a topological order:
/// a node is created after its arguments).
#[derive(Default, Debug)]
pub(crate) struct Nodes {
    #[expect(
        clippy::struct_field_names,
        reason = "the node list of the node storage"
    )]
    pub(crate) nodes: Vec<Node>,
    pub(crate) args: Vec<NodeId>,
    /// Hash-consing table from `(op, arguments)` to the node already built for them,
    /// for ops of at most two arguments (n-ary nodes are rarely repeated exactly).
    interned: FxHashMap<(Op, [NodeId; 2]), NodeId>,
    pub(crate) var_count: u32,
    pub(crate) param_names: Vec<String>,
    pub(crate) param_defaults: Vec<f64>,
}

impl Nodes {
    pub(crate) fn args_of(&self, node: &Node) -> &[NodeId] {
        let start = node.args_start as usize;
        &self.args[start..start + node.args_len as usize]
    }

    fn constant_value(&self, id: NodeId) -> Option<f64> {
        match self.nodes[id as usize].op {
            Op::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    /// Adds a node (or finds the equal node already built) and returns its id.
    fn intern(&mut self, op: Op, args: &[NodeId]) -> NodeId {
        debug_assert!(
            op.arity().is_none_or(|a| a == args.len()),
            "{op:?} takes {:?} arguments, got {}",
            op.arity(),
            args.len()
        );
        // Fold operations whose arguments are all constants.
        if !op.is_leaf()
            && !args.is_empty()
            && args.iter().all(|&a| self.constant_value(a).is_some())
        {
            let values: Vec<f64> = args
                .iter()
                .filter_map(|&a| self.constant_value(a))
                .collect();
            let value = op.apply(&values, None);
            return self.intern(Op::Const(value.to_bits()), &[]);
        }
        if let Some(simpler) = self.simplify(op, args) {
            return simpler;
        }
        let key = match *args {
            [] => Some((op, [u32::MAX; 2])),
            [a] => Some((op, [a, u32::MAX])),
            [a, b] => Some((op, [a, b])),
            _ => None,
        };
        if let Some(&id) = key.as_ref().and_then(|k| self.interned.get(k)) {
            return id;
        }
        let id = u32::try_from(self.nodes.len()).expect("an expression graph holds < 2³² nodes");
        self.nodes.push(Node {
            op,
            args_start: self.args.len() as u32,
            args_len: args.len() as u32,
        });
        self.args.extend_from_slice(args);
        if let Some(key) = key {
            self.interned.insert(key, id);
        }
        id
    }

    /// Algebraic identities that return an existing node instead of a new one.
    fn simplify(&self, op: Op, args: &[NodeId]) -> Option<NodeId> {
        let is = |id: NodeId, v: f64| self.constant_value(id) == Some(v);
        match (op, args) {
            (Op::Add | Op::Sub, &[a, b]) if is(b, 0.0) => Some(a),
            (Op::Mul | Op::Div, &[a, b]) if is(b, 1.0) => Some(a),
            (Op::Add, &[a, b]) if is(a, 0.0) => Some(b),
            (Op::Mul, &[a, b]) if is(a, 1.0) => Some(b),
            (Op::Powi(1) | Op::Sum, &[a]) => Some(a),
            (Op::Neg, &[a]) => match self.nodes[a as usize].op {
                Op::Neg => Some(self.args[self.nodes[a as usize].args_start as usize]),
                _ => None,
            },
            _ => None,
        }
    }
}

/// A builder of expressions: variables, parameters, constants and the operations on them.
///
/// Build expressions through [`Expr`] handles, then compile the ones you need with
/// [`Tape::compile`](super::Tape::compile). The graph uses interior mutability so that
/// handles can be combined with plain operators; it is not meant to be shared across
/// threads while building (build on the thread that will solve).
///
/// # Examples
///
/// ```
/// use geosnap_core::ad::{Graph, Tape};
///
/// let g = Graph::new();
/// let x = g.var();
/// let y = g.var();
/// let f = (x * y).sin() + x.square();
/// let mut tape = Tape::compile(&g, &[f]);
/// let mut grad = [0.0; 2];
/// let value = tape.gradient(&[1.0, 2.0], &mut grad);
/// assert!((value - (2.0f64.sin() + 1.0)).abs() < 1e-12);
/// assert!((grad[0] - (2.0 * 2.0f64.cos() + 2.0)).abs() < 1e-12);
/// ```
#[derive(Default)]
pub struct Graph {
    pub(crate) inner: RefCell<Nodes>,
}

impl fmt::Debug for Graph {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let inner = self.inner.borrow();
        f.debug_struct("Graph")
            .field("nodes", &inner.nodes.len())
            .field("vars", &inner.var_count)
            .field("params", &inner.param_names)
            .finish()
    }
}

impl Graph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    fn node(&self, op: Op, args: &[NodeId]) -> Expr<'_> {
        let id = self.inner.borrow_mut().intern(op, args);
        Expr { graph: self, id }
    }

    /// A new variable; variables are numbered 0, 1, 2, … in creation order, and that index
    /// is their position in the `x` slices given to a [`Tape`](super::Tape).
    pub fn var(&self) -> Expr<'_> {
        let index = {
            let mut inner = self.inner.borrow_mut();
            let index = inner.var_count;
            inner.var_count += 1;
            index
        };
        self.node(Op::Var(index), &[])
    }

    /// `n` new variables.
    pub fn vars(&self, n: usize) -> Vec<Expr<'_>> {
        (0..n).map(|_| self.var()).collect()
    }

    /// The number of variables created so far.
    pub fn var_count(&self) -> usize {
        self.inner.borrow().var_count as usize
    }

    /// The named parameter `name`, created with the value `default` if it does not exist
    /// yet (an existing parameter keeps its first default).
    ///
    /// Parameters are inputs of the compiled tape that change between evaluations without
    /// recompiling, such as multipliers, weights and targets; set them with
    /// [`Tape::set_param`](super::Tape::set_param).
    pub fn param(&self, name: &str, default: f64) -> Expr<'_> {
        let index = {
            let mut inner = self.inner.borrow_mut();
            if let Some(i) = inner.param_names.iter().position(|n| n == name) {
                i as u32
            } else {
                inner.param_names.push(name.to_owned());
                inner.param_defaults.push(default);
                (inner.param_names.len() - 1) as u32
            }
        };
        self.node(Op::Param(index), &[])
    }

    /// A constant.
    pub fn constant(&self, value: f64) -> Expr<'_> {
        self.node(Op::Const(value.to_bits()), &[])
    }

    /// The sum of any number of expressions (0 for none), stored as one n-ary node.
    ///
    /// Prefer this over folding with `+` for long sums: one node with n edges instead of
    /// n − 1 binary nodes.
    pub fn sum<'g, I>(&'g self, terms: I) -> Expr<'g>
    where
        I: IntoIterator<Item = Expr<'g>>,
    {
        // Collect first: building the terms may add nodes to this graph.
        let terms: Vec<Expr<'g>> = terms.into_iter().collect();
        let mut ids = Vec::with_capacity(terms.len() + 1);
        let mut constant = 0.0;
        let inner = self.inner.borrow();
        for term in terms {
            debug_assert!(std::ptr::eq(term.graph, self), "mixing graphs");
            match inner.constant_value(term.id) {
                Some(c) => constant += c,
                None => ids.push(term.id),
            }
        }
        drop(inner);
        if constant != 0.0 || ids.is_empty() {
            let c = self.constant(constant);
            ids.push(c.id);
        }
        self.node(Op::Sum, &ids)
    }

    /// The distance from the fixed point `p` to the ellipse c + A·cos θ + B·sin θ (A, B
    /// conjugate semi-diameters; a flat ellipse is a segment), as one node whose gradient
    /// follows the closest point (envelope theorem). Arguments are `[x, y]` pairs.
    pub fn ellipse_distance<'g>(
        &'g self,
        center: [Expr<'g>; 2],
        a: [Expr<'g>; 2],
        b: [Expr<'g>; 2],
        p: glam::DVec2,
    ) -> Expr<'g> {
        let (px, py) = (self.constant(p.x), self.constant(p.y));
        let ids = [center[0], center[1], a[0], a[1], b[0], b[1], px, py].map(|e| e.id);
        self.node(Op::EllipseDistance, &ids)
    }

    /// The distance from the fixed point `p` to the segment from `a` to `b`, as one node.
    pub fn segment_distance<'g>(
        &'g self,
        a: [Expr<'g>; 2],
        b: [Expr<'g>; 2],
        p: glam::DVec2,
    ) -> Expr<'g> {
        let (px, py) = (self.constant(p.x), self.constant(p.y));
        let ids = [a[0], a[1], b[0], b[1], px, py].map(|e| e.id);
        self.node(Op::SegmentDistance, &ids)
    }

    /// The distance from the fixed point `p` to the polyline through `points`, as one
    /// node (a segment's node for two points, the constant 0 for fewer): the least of
    /// its segments' distances ([`Graph::segment_distance`]), with the gradient of the
    /// nearest segment's, the first on a tie. Its value and gradient are those of folding
    /// the segments' distances with [`Expr::min`] from first to last, with one node
    /// instead of 2n − 3, and the square root of most segments spared.
    pub fn polyline_distance<'g>(&'g self, points: &[[Expr<'g>; 2]], p: glam::DVec2) -> Expr<'g> {
        match points {
            [] | [_] => self.constant(0.0),
            [a, b] => self.segment_distance(*a, *b, p),
            _ => {
                let (px, py) = (self.constant(p.x), self.constant(p.y));
                let ids: Vec<NodeId> = points
                    .iter()
                    .flat_map(|q| [q[0].id, q[1].id])
                    .chain([px.id, py.id])
                    .collect();
                self.node(Op::PolylineDistance, &ids)
            }
        }
    }

    /// The number of nodes built so far (after sharing and folding).
    pub fn node_count(&self) -> usize {
        self.inner.borrow().nodes.len()
    }
}

/// A handle to one node of a [`Graph`]: cheap to copy, combined with `+ − × ÷` and the
/// methods below into new nodes of the same graph.
#[derive(Clone, Copy)]
#[must_use = "an expression does nothing until it is used in an output"]
pub struct Expr<'g> {
    pub(crate) graph: &'g Graph,
    pub(crate) id: NodeId,
}

impl fmt::Debug for Expr<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let inner = self.graph.inner.borrow();
        write!(
            f,
            "Expr#{}({:?})",
            self.id, inner.nodes[self.id as usize].op
        )
    }
}

impl PartialEq for Expr<'_> {
    /// Two handles are equal when they name the same node of the same graph (hash-consing
    /// makes structurally equal expressions the same node in most cases).
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self.graph, other.graph) && self.id == other.id
    }
}

impl<'g> Expr<'g> {
    /// The graph this expression belongs to.
    pub fn graph(self) -> &'g Graph {
        self.graph
    }

    fn unary(self, op: Op) -> Self {
        self.graph.node(op, &[self.id])
    }

    fn binary(self, op: Op, other: Self) -> Self {
        assert!(
            std::ptr::eq(self.graph, other.graph),
            "expressions from different graphs cannot be combined"
        );
        self.graph.node(op, &[self.id, other.id])
    }

    fn lift(self, value: f64) -> Self {
        self.graph.constant(value)
    }

    /// The value if this expression is a constant.
    pub fn as_constant(self) -> Option<f64> {
        self.graph.inner.borrow().constant_value(self.id)
    }

    /// `self²`.
    pub fn square(self) -> Self {
        self.unary(Op::Square)
    }
    /// `selfᵏ` for an integer `k`.
    pub fn powi(self, k: i32) -> Self {
        match k {
            2 => self.square(),
            _ => self.unary(Op::Powi(k)),
        }
    }
    /// `selfᵖ` for a real constant `p` (NaN for negative bases and non-integer `p`).
    pub fn powf(self, p: f64) -> Self {
        self.unary(Op::Powf(p.to_bits()))
    }
    /// `selfᵉ` with an expression exponent (defined for positive bases).
    pub fn pow(self, exponent: Self) -> Self {
        self.binary(Op::Pow, exponent)
    }
    /// `√self`.
    pub fn sqrt(self) -> Self {
        self.unary(Op::Sqrt)
    }
    /// `e^self`.
    pub fn exp(self) -> Self {
        self.unary(Op::Exp)
    }
    /// The natural logarithm.
    pub fn ln(self) -> Self {
        self.unary(Op::Ln)
    }
    /// The sine (radians).
    pub fn sin(self) -> Self {
        self.unary(Op::Sin)
    }
    /// The cosine (radians).
    pub fn cos(self) -> Self {
        self.unary(Op::Cos)
    }
    /// The tangent (radians).
    pub fn tan(self) -> Self {
        self.unary(Op::Tan)
    }
    /// `atan2(self, x)`: the angle of the point `(x, self)`, in `(−π, π]`.
    pub fn atan2(self, x: Self) -> Self {
        self.binary(Op::Atan2, x)
    }
    /// `|self|`, with subgradient 0 at 0.
    pub fn abs(self) -> Self {
        self.unary(Op::Abs)
    }
    /// `√(self² + other²)` without overflow; subgradient 0 at the origin.
    pub fn hypot(self, other: Self) -> Self {
        self.binary(Op::Hypot, other)
    }
    /// The smaller of the two; on a tie the derivative follows `self`.
    pub fn min(self, other: Self) -> Self {
        self.binary(Op::Min, other)
    }
    /// The larger of the two; on a tie the derivative follows `self`.
    pub fn max(self, other: Self) -> Self {
        self.binary(Op::Max, other)
    }
}

macro_rules! binary_operator {
    ($trait:ident, $method:ident, $op:expr) => {
        impl<'g> $trait for Expr<'g> {
            type Output = Expr<'g>;
            fn $method(self, rhs: Self) -> Self::Output {
                self.binary($op, rhs)
            }
        }
        impl<'g> $trait<f64> for Expr<'g> {
            type Output = Expr<'g>;
            fn $method(self, rhs: f64) -> Self::Output {
                self.binary($op, self.lift(rhs))
            }
        }
        impl<'g> $trait<Expr<'g>> for f64 {
            type Output = Expr<'g>;
            fn $method(self, rhs: Expr<'g>) -> Self::Output {
                rhs.lift(self).binary($op, rhs)
            }
        }
    };
}

binary_operator!(Add, add, Op::Add);
binary_operator!(Sub, sub, Op::Sub);
binary_operator!(Mul, mul, Op::Mul);
binary_operator!(Div, div, Op::Div);

impl Neg for Expr<'_> {
    type Output = Self;
    fn neg(self) -> Self::Output {
        self.unary(Op::Neg)
    }
}

#[cfg(test)]
mod tests {
    use super::Graph;

    #[test]
    fn equal_subexpressions_share_one_node() {
        let g = Graph::new();
        let x = g.var();
        let y = g.var();
        let a = (x * y).sin();
        let before = g.node_count();
        let b = (x * y).sin();
        assert_eq!(a, b, "hash-consing returns the same node");
        assert_eq!(g.node_count(), before, "no node was added");
    }

    #[test]
    fn constants_fold_and_identities_apply() {
        let g = Graph::new();
        let x = g.var();
        let c = g.constant(2.0) * 3.0 + 1.0;
        assert_eq!(c.as_constant(), Some(7.0));
        assert_eq!(x + 0.0, x, "x + 0 is x");
        assert_eq!(1.0 * x, x, "1·x is x");
        assert_eq!(-(-x), x, "−(−x) is x");
        assert_eq!(g.sum([x]), x, "a sum of one term is the term");
        assert_eq!(g.sum([]).as_constant(), Some(0.0));
    }

    #[test]
    fn params_are_named_once() {
        let g = Graph::new();
        let a = g.param("lambda", 1.0);
        let b = g.param("lambda", 5.0);
        assert_eq!(a, b, "the same name gives the same parameter");
        assert_ne!(a, g.param("mu", 1.0));
    }
}
