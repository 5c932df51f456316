//! Benchmark of the reverse-mode AD tape: a sum of 1000 squared residuals over 20
//! variables, each residual `(a·xᵢ·xⱼ + sin xₖ − t)²` with random `i, j, k`, scale `a`
//! and target `t` (fixed seed), built with `Graph::sum`.
//!
//! Measures `Tape::eval` (values only), `Tape::forward` (values and local partials),
//! `Tape::gradient` (forward and reverse sweep), the ratio gradient/value (target ≤ 3×),
//! the time per tape operation and edge, the same function written by hand in Rust (a
//! reference for the interpretive overhead of the tape), and the cost of building the
//! graph and compiling the tape. The sweeps and the references are sampled in turn, so
//! that their ratios hold on a busy machine.
//!
//! Run with `cargo bench --no-default-features --bench ad`; see `benches/support` for
//! the environment variables.

#![expect(clippy::print_stdout, reason = "benchmark output")]

mod support;

use std::hint::black_box;

use geosnap::core::ad::{Expr, Graph, Tape};
use support::{fmt_ns, timed, Bench, Rng, Stats, Table};

/// The number of variables.
const VARS: usize = 20;
/// The number of squared residuals summed.
const RESIDUALS: usize = 1000;

/// One residual `(a·xᵢ·xⱼ + sin xₖ − t)²`.
#[derive(Clone, Copy, Debug)]
struct Residual {
    i: usize,
    j: usize,
    k: usize,
    a: f64,
    target: f64,
}

/// The residuals of the benchmark (fixed seed).
fn residuals() -> Vec<Residual> {
    let mut rng = Rng::new(0x00AD_0001);
    (0..RESIDUALS)
        .map(|_| Residual {
            i: rng.index(VARS),
            j: rng.index(VARS),
            k: rng.index(VARS),
            a: rng.uniform(0.5, 2.0),
            target: rng.uniform(-1.0, 1.0),
        })
        .collect()
}

/// Builds `Σ (a·xᵢ·xⱼ + sin xₖ − t)²` on new variables of `g`.
fn build<'g>(g: &'g Graph, residuals: &[Residual]) -> Expr<'g> {
    let x = g.vars(VARS);
    g.sum(
        residuals
            .iter()
            .map(|r| (r.a * x[r.i] * x[r.j] + x[r.k].sin() - r.target).square()),
    )
}

/// The same function written by hand, for a reference: value only. Like the tape it
/// computes each `sin xₖ` once.
fn native_value(residuals: &[Residual], x: &[f64]) -> f64 {
    let sin: [f64; VARS] = std::array::from_fn(|k| x[k].sin());
    residuals
        .iter()
        .map(|r| {
            let e = r.a * x[r.i] * x[r.j] + sin[r.k] - r.target;
            e * e
        })
        .sum()
}

/// The same function written by hand: value and gradient.
fn native_gradient(residuals: &[Residual], x: &[f64], grad: &mut [f64]) -> f64 {
    let (sin, cos): ([f64; VARS], [f64; VARS]) = (
        std::array::from_fn(|k| x[k].sin()),
        std::array::from_fn(|k| x[k].cos()),
    );
    grad.fill(0.0);
    let mut f = 0.0;
    for r in residuals {
        let e = r.a * x[r.i] * x[r.j] + sin[r.k] - r.target;
        f += e * e;
        let w = 2.0 * e;
        grad[r.i] += w * r.a * x[r.j];
        grad[r.j] += w * r.a * x[r.i];
        grad[r.k] += w * cos[r.k];
    }
    f
}

fn main() {
    let bench = Bench::from_env();
    bench.print_intro(&format!(
        "AD tape: Σ of {RESIDUALS} residuals (a·xᵢ·xⱼ + sin xₖ − t)² over {VARS} variables"
    ));

    let terms = residuals();
    let g = Graph::new();
    let f = build(&g, &terms);
    let mut tape = Tape::compile(&g, &[f]);
    let (ops, edges) = (tape.op_count(), tape.edge_count());
    println!(
        "graph: {} nodes; tape: {ops} operations, {edges} edges, {} variables",
        g.node_count(),
        tape.var_count()
    );

    let mut rng = Rng::new(0x00AD_0002);
    let x: Vec<f64> = (0..VARS).map(|_| rng.uniform(-1.5, 1.5)).collect();
    check(&mut tape, &terms, &x);
    let mut grad = vec![0.0; VARS];

    let table = Table::new(
        "Sweeps (per call; the variants are sampled in turn)",
        30,
        &[("ns/op", 7), ("ns/edge", 7), ("÷ eval", 6)],
    );
    let mut eval_median = None;
    let mut row = |name: &str, stats: &Stats| {
        let base = *eval_median.get_or_insert(stats.median);
        table.row(
            name,
            stats,
            &[
                format!("{:.2}", stats.median / ops as f64),
                format!("{:.2}", stats.median / edges as f64),
                format!("{:.2}", stats.median / base),
            ],
        );
    };
    // The five variants are sampled in turn, so that they see the same machine load.
    let mut native_grad = vec![0.0; VARS];
    let stats = bench.interleaved(5, |variant| {
        let x = black_box(&x);
        match variant {
            0 => tape.eval(x)[0],
            1 => tape.forward(x)[0],
            2 => tape.gradient(x, &mut grad),
            3 => native_value(&terms, x),
            _ => native_gradient(&terms, x, &mut native_grad),
        }
    });
    let [eval, forward, gradient, native, native_both] =
        <[Stats; 5]>::try_from(stats).expect("five variants");
    row("eval (value only)", &eval);
    row("forward (value + partials)", &forward);
    row("gradient (value + ∇)", &gradient);
    row("hand-written Rust: value", &native);
    row("hand-written Rust: value + ∇", &native_both);
    let table = Table::new("Building (per call)", 30, &[]);
    let compile = bench.each(|_| timed(|| Tape::compile(&g, &[f])).1);
    table.row("Tape::compile", &compile, &[]);
    let graph = bench.each(|_| {
        timed(|| {
            let g = Graph::new();
            let _ = build(&g, &terms);
            g
        })
        .1
    });
    table.row("build graph (Graph, ops)", &graph, &[]);

    println!();
    println!(
        "gradient / value: {:.2}× at the median, {:.2}× at p95 (target ≤ 3×); \
         gradient {} per operation, {} per edge",
        gradient.median / eval.median,
        gradient.p95 / eval.p95,
        fmt_ns(gradient.median / ops as f64),
        fmt_ns(gradient.median / edges as f64),
    );
    println!(
        "tape vs hand-written Rust: value {:.1}×, value + gradient {:.1}× slower (medians)",
        eval.median / native.median,
        gradient.median / native_both.median
    );
    println!(
        "compile: {} median for {ops} operations ({} per operation, {:.0}× one gradient)",
        fmt_ns(compile.median),
        fmt_ns(compile.median / ops as f64),
        compile.median / gradient.median
    );
}

/// Checks that the case is sane: the tape's gradient agrees with a central difference
/// and with the hand-written reference.
fn check(tape: &mut Tape, terms: &[Residual], x: &[f64]) {
    let mut grad = vec![0.0; VARS];
    let value = tape.gradient(x, &mut grad);
    let h = 1e-6;
    let mut xp = x.to_vec();
    xp[3] += h;
    let up = tape.eval(&xp)[0];
    xp[3] -= 2.0 * h;
    let down = tape.eval(&xp)[0];
    let fd = (up - down) / (2.0 * h);
    assert!(
        (fd - grad[3]).abs() <= 1e-5 * (1.0 + fd.abs()),
        "∂f/∂x₃: tape {} vs central difference {fd}",
        grad[3]
    );
    let mut native_grad = vec![0.0; VARS];
    let native = native_gradient(terms, x, &mut native_grad);
    assert!(
        (native - value).abs() <= 1e-9 * value.abs()
            && (native_value(terms, x) - value).abs() <= 1e-9 * value.abs()
            && native_grad
                .iter()
                .zip(&grad)
                .all(|(a, b)| (a - b).abs() <= 1e-9 * (1.0 + b.abs())),
        "the hand-written reference computes the same function"
    );
    println!("f(x) = {value:.6}, ‖∇f‖∞ = {:.3}", max_abs(&grad));
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}
