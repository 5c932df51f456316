//! Property tests of the automatic differentiation in `geosnap::core::ad`.
//!
//! The tape's gradients are checked against central finite differences of the tape's own
//! values, for every operation alone and for random programs whose instructions reuse
//! earlier values (so the graphs have shared sub-expressions). The values of the programs
//! are checked against the same programs run on plain `f64`, the Jacobian against one
//! gradient per output, and the weighted reverse sweep against the weighted sum of those
//! gradients.

use std::ops::{Add, Div, Mul, Neg, Sub};

use geosnap::core::ad::{Expr, Graph, Tape, Vec3};
use glam::DVec3;
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::TestCaseError;

/// Relative tolerance of a derivative against its central finite difference.
const FD_TOL: f64 = 1e-6;
/// Relative tolerance of a tape value against plain `f64` arithmetic, and of two
/// derivatives that differ only by the order of their floating-point additions.
const ROUNDING_TOL: f64 = 1e-12;
/// Smallest distance to a kink (`abs`, `min`, `max`, the branch cut of `atan2`).
///
/// These functions are piecewise linear or piecewise smooth, so a central difference is
/// exact as long as its step does not cross the kink.
const KINK_MARGIN: f64 = 1e-3;
/// Smallest distance to the origin for `hypot` and `atan2` (and to zero for `Vec3::norm`).
///
/// Wider than [`KINK_MARGIN`] on purpose: these functions curve like `1/r` near the origin,
/// so the truncation error of a central difference, relative to the derivative, grows
/// like `(h/r)²`; at `r = 1e-3` and `h ≈ 1e-6` that is already the whole tolerance.
const ORIGIN_MARGIN: f64 = 1e-2;
/// Largest magnitude of an intermediate value of a random program.
///
/// Products and powers of earlier values can grow without limit; for large values the
/// rounding error of the value, divided by the finite-difference step (~1e-6), and the
/// truncation error of the central difference approach the tolerance.
const VALUE_BOUND: f64 = 100.0;

/// Cases of each single-operation property.
const OP_CASES: u32 = 1024;
/// Cases of each random-program property.
const PROGRAM_CASES: u32 = 2048;

/// Whether `got` equals `want` to the relative tolerance `tol` (absolute below 1).
fn close(got: f64, want: f64, tol: f64) -> bool {
    (got - want).abs() <= tol * want.abs().max(1.0)
}

/// The central difference of output `output` of `tape` along variable `i` at `x`.
fn central_difference(tape: &mut Tape, x: &[f64], output: usize, i: usize) -> f64 {
    let h = 1e-6 * x[i].abs().max(1.0);
    let mut shifted = x.to_vec();
    shifted[i] = x[i] + h;
    let plus = tape.eval(&shifted)[output];
    shifted[i] = x[i] - h;
    let minus = tape.eval(&shifted)[output];
    // The step actually taken, after rounding x ± h.
    (plus - minus) / ((x[i] + h) - (x[i] - h))
}

/// Checks `grad`, the gradient of output `output` at `x`, against central differences.
fn check_against_fd(
    tape: &mut Tape,
    x: &[f64],
    output: usize,
    grad: &[f64],
) -> Result<(), TestCaseError> {
    for (i, &derivative) in grad.iter().enumerate() {
        let fd = central_difference(tape, x, output, i);
        prop_assert!(
            close(derivative, fd, FD_TOL),
            "output {output}, ∂/∂x{i} at {x:?}: tape {derivative}, central difference {fd}"
        );
    }
    Ok(())
}

/// Compiles `build(vars)` for `x.len()` variables, checks its value at `x` against
/// `reference(x)` and its gradient against central differences.
fn check_op(
    x: &[f64],
    reference: impl Fn(&[f64]) -> f64,
    build: impl for<'g> Fn(&[Expr<'g>]) -> Expr<'g>,
) -> Result<(), TestCaseError> {
    let g = Graph::new();
    let vars = g.vars(x.len());
    let mut tape = Tape::compile(&g, &[build(&vars)]);
    let mut grad = vec![f64::NAN; x.len()];
    let value = tape.gradient(x, &mut grad);
    let want = reference(x);
    prop_assert!(
        close(value, want, ROUNDING_TOL),
        "value at {x:?}: tape {value}, f64 {want}"
    );
    check_against_fd(&mut tape, x, 0, &grad)
}

/// [`check_op`] with one formula written once, evaluated on `f64` for the reference and
/// on `Expr` for the tape.
macro_rules! check_formula {
    ($x:expr, |$v:ident| $body:expr) => {
        check_op(&$x, |$v| $body, |$v| $body)
    };
}

/// What both `f64` and `Expr` can compute, so one program runs on either.
///
/// Methods that `f64` and `Expr` both have inherently (`sin`, `powi`, …) are forwarded;
/// the others are spelled out: `c_plus(c)` is `c + self`, and so on.
trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    fn c_plus(self, c: f64) -> Self;
    fn c_minus(self, c: f64) -> Self;
    fn c_over(self, c: f64) -> Self;
    fn square(self) -> Self;
    fn pow(self, exponent: Self) -> Self;
    fn sum3(a: Self, b: Self, c: Self) -> Self;
    fn powi(self, k: i32) -> Self;
    fn powf(self, p: f64) -> Self;
    fn sqrt(self) -> Self;
    fn exp(self) -> Self;
    fn ln(self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn tan(self) -> Self;
    fn atan2(self, x: Self) -> Self;
    fn abs(self) -> Self;
    fn hypot(self, other: Self) -> Self;
    fn min(self, other: Self) -> Self;
    fn max(self, other: Self) -> Self;
}

/// Forwards trait methods to the inherent methods of the same name.
macro_rules! forward_inherent {
    ($($name:ident($($arg:ident: $ty:ty),*)),* $(,)?) => {
        $(fn $name(self, $($arg: $ty),*) -> Self {
            Self::$name(self, $($arg),*)
        })*
    };
}

impl Scalar for f64 {
    fn c_plus(self, c: f64) -> Self {
        c + self
    }
    fn c_minus(self, c: f64) -> Self {
        c - self
    }
    fn c_over(self, c: f64) -> Self {
        c / self
    }
    fn square(self) -> Self {
        self * self
    }
    fn pow(self, exponent: Self) -> Self {
        self.powf(exponent)
    }
    fn sum3(a: Self, b: Self, c: Self) -> Self {
        a + b + c
    }
    forward_inherent!(
        powi(k: i32),
        powf(p: f64),
        sqrt(),
        exp(),
        ln(),
        sin(),
        cos(),
        tan(),
        atan2(x: Self),
        abs(),
        hypot(other: Self),
        min(other: Self),
        max(other: Self),
    );
}

impl Scalar for Expr<'_> {
    fn c_plus(self, c: f64) -> Self {
        c + self
    }
    fn c_minus(self, c: f64) -> Self {
        c - self
    }
    fn c_over(self, c: f64) -> Self {
        c / self
    }
    fn sum3(a: Self, b: Self, c: Self) -> Self {
        a.graph().sum([a, b, c])
    }
    forward_inherent!(
        square(),
        pow(exponent: Self),
        powi(k: i32),
        powf(p: f64),
        sqrt(),
        exp(),
        ln(),
        sin(),
        cos(),
        tan(),
        atan2(x: Self),
        abs(),
        hypot(other: Self),
        min(other: Self),
        max(other: Self),
    );
}

/// A uniform magnitude in `lo..hi` with a random sign.
fn away_from_zero(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo..hi, any::<bool>()).prop_map(|(m, negative)| if negative { -m } else { m })
}

/// A point `(y, x)` at a log-uniform distance in `[ORIGIN_MARGIN, 10)` from the origin.
fn polar_point() -> impl Strategy<Value = (f64, f64)> {
    (
        ORIGIN_MARGIN.log10()..1.0,
        -std::f64::consts::PI..std::f64::consts::PI,
    )
        .prop_map(|(log_r, theta)| {
            let r = 10f64.powf(log_r);
            (r * theta.sin(), r * theta.cos())
        })
}

fn dvec(v: &[f64], at: usize) -> DVec3 {
    DVec3::new(v[at], v[at + 1], v[at + 2])
}

fn evec<'g>(v: &[Expr<'g>], at: usize) -> Vec3<Expr<'g>> {
    Vec3::new(v[at], v[at + 1], v[at + 2])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(OP_CASES))]

    #[test]
    fn add(a in -10.0..10.0, b in -10.0..10.0, c in -10.0..10.0) {
        check_formula!([a, b], |v| v[0] + v[1])?;
        check_formula!([a], |v| v[0] + c)?;
        check_formula!([a], |v| c + v[0])?;
    }

    #[test]
    fn sub(a in -10.0..10.0, b in -10.0..10.0, c in -10.0..10.0) {
        check_formula!([a, b], |v| v[0] - v[1])?;
        check_formula!([a], |v| v[0] - c)?;
        check_formula!([a], |v| c - v[0])?;
    }

    #[test]
    fn mul(a in -10.0..10.0, b in -10.0..10.0, c in -10.0..10.0) {
        check_formula!([a, b], |v| v[0] * v[1])?;
        check_formula!([a], |v| v[0] * c)?;
        check_formula!([a], |v| c * v[0])?;
    }

    #[test]
    fn div(a in -10.0..10.0, b in away_from_zero(0.1, 10.0), c in away_from_zero(0.1, 10.0)) {
        check_formula!([a, b], |v| v[0] / v[1])?;
        check_formula!([a], |v| v[0] / c)?;
        check_formula!([b], |v| c / v[0])?;
    }

    #[test]
    fn neg(a in -10.0..10.0) {
        check_formula!([a], |v| -v[0])?;
    }

    #[test]
    fn square(a in -10.0..10.0) {
        check_formula!([a], |v| v[0].square())?;
    }

    #[test]
    fn powi(a in away_from_zero(0.2, 3.0)) {
        for k in [-3, -2, -1, 0, 1, 2, 3, 4, 7] {
            check_formula!([a], |v| v[0].powi(k))?;
        }
    }

    #[test]
    fn powf(a in 0.1..5.0, p in -3.0..3.0) {
        check_formula!([a], |v| v[0].powf(p))?;
    }

    #[test]
    fn pow(a in 0.1..5.0, b in -3.0..3.0) {
        check_formula!([a, b], |v| v[0].pow(v[1]))?;
    }

    #[test]
    fn sqrt(a in 0.01..100.0) {
        check_formula!([a], |v| v[0].sqrt())?;
    }

    #[test]
    fn exp(a in -10.0..10.0) {
        check_formula!([a], |v| v[0].exp())?;
    }

    #[test]
    fn ln(a in 0.01..100.0) {
        check_formula!([a], |v| v[0].ln())?;
    }

    #[test]
    fn sin_and_cos(a in -10.0..10.0) {
        check_formula!([a], |v| v[0].sin())?;
        check_formula!([a], |v| v[0].cos())?;
    }

    #[test]
    fn tan(a in -1.45..1.45, k in -2..=2) {
        // At least 0.12 from every pole kπ + π/2.
        let x = a + f64::from(k) * std::f64::consts::PI;
        check_formula!([x], |v| v[0].tan())?;
    }

    #[test]
    fn atan2((y, x) in polar_point()) {
        // Off the branch cut, the negative x axis.
        prop_assume!(x > 0.0 || y.abs() >= KINK_MARGIN);
        check_formula!([y, x], |v| v[0].atan2(v[1]))?;
    }

    #[test]
    fn abs(a in away_from_zero(KINK_MARGIN, 10.0)) {
        check_formula!([a], |v| v[0].abs())?;
    }

    #[test]
    fn hypot((a, b) in polar_point()) {
        check_formula!([a, b], |v| v[0].hypot(v[1]))?;
    }

    #[test]
    fn min_and_max(a in -10.0..10.0, d in away_from_zero(KINK_MARGIN, 10.0)) {
        let b = a + d;
        check_formula!([a, b], |v| v[0].min(v[1]))?;
        check_formula!([a, b], |v| v[0].max(v[1]))?;
        check_formula!([b, a], |v| v[0].min(v[1]))?;
        check_formula!([b, a], |v| v[0].max(v[1]))?;
    }

    /// Sums of variables (repeated ones too), scaled variables, squares and constants.
    #[test]
    fn sum(
        x in prop::array::uniform3(-10.0..10.0f64),
        terms in prop::collection::vec((0..3usize, 0..4u8, -5.0..5.0f64), 0..8),
    ) {
        check_op(
            &x,
            |v| terms.iter().map(|&(i, kind, c)| match kind {
                0 => v[i],
                1 => c * v[i],
                2 => v[i] * v[i],
                _ => c,
            }).sum(),
            |v| {
                let g = v[0].graph();
                g.sum(terms.iter().map(|&(i, kind, c)| match kind {
                    0 => v[i],
                    1 => c * v[i],
                    2 => v[i].square(),
                    _ => g.constant(c),
                }))
            },
        )?;
    }

    #[test]
    fn vec3_dot_and_cross(
        a in prop::array::uniform3(-5.0..5.0f64),
        b in prop::array::uniform3(-5.0..5.0f64),
    ) {
        let x = [a, b].concat();
        check_op(&x, |v| dvec(v, 0).dot(dvec(v, 3)), |v| evec(v, 0).dot(evec(v, 3)))?;
        check_op(&x, |v| dvec(v, 0).cross(dvec(v, 3)).x, |v| evec(v, 0).cross(evec(v, 3)).x)?;
        check_op(&x, |v| dvec(v, 0).cross(dvec(v, 3)).y, |v| evec(v, 0).cross(evec(v, 3)).y)?;
        check_op(&x, |v| dvec(v, 0).cross(dvec(v, 3)).z, |v| evec(v, 0).cross(evec(v, 3)).z)?;
    }

    #[test]
    fn vec3_norms(a in prop::array::uniform3(-5.0..5.0f64)) {
        check_op(&a, |v| dvec(v, 0).length_squared(), |v| evec(v, 0).norm_squared())?;
        prop_assume!(dvec(&a, 0).length() >= ORIGIN_MARGIN);
        check_op(&a, |v| dvec(v, 0).length(), |v| evec(v, 0).norm())?;
        check_op(&a, |v| dvec(v, 0).normalize().x, |v| evec(v, 0).normalize().x)?;
        check_op(&a, |v| dvec(v, 0).normalize().y, |v| evec(v, 0).normalize().y)?;
        check_op(&a, |v| dvec(v, 0).normalize().z, |v| evec(v, 0).normalize().z)?;
    }
}

/// One instruction of a random [`Program`]: what it computes from its operands `a`, `b`,
/// `c` (earlier values; unary steps read `a` only). Steps that could leave their domain or
/// blow up are wrapped so that any finite operands are safe.
#[derive(Clone, Copy, Debug)]
enum Step {
    Add,
    Sub,
    Mul,
    Neg,
    Square,
    /// `a · k`.
    Scale(f64),
    /// `k + a`.
    Shift(f64),
    /// `k − a`.
    Reflect(f64),
    /// `a / k`, with `|k| ≥ 0.5`.
    DivBy(f64),
    /// `k / (1 + a²)`.
    Bump(f64),
    /// `a / (1 + b²)`.
    Div,
    /// `aᵏ` for `k ≥ 0`, `(1 + a²)ᵏ` for `k < 0`.
    Powi(i32),
    /// `(1 + a²)ᵖ`.
    Powf(f64),
    /// `(1 + a²)ᵇ`.
    Pow,
    /// `√(1 + a²)`.
    Sqrt,
    /// `exp(sin(a) / 2)`.
    Exp,
    /// `ln(1 + a²)`.
    Ln,
    Sin,
    Cos,
    /// `tan(sin(a) / 2)`.
    Tan,
    /// `atan2(a, b)`.
    Atan2,
    Abs,
    Hypot,
    Min,
    Max,
    /// `Graph::sum([a, b, c])`.
    Sum,
}

impl Step {
    fn apply<S: Scalar>(self, a: S, b: S, c: S) -> S {
        let one_plus_square = |v: S| v.square().c_plus(1.0);
        match self {
            Self::Add => a + b,
            Self::Sub => a - b,
            Self::Mul => a * b,
            Self::Neg => -a,
            Self::Square => a.square(),
            Self::Scale(k) => a * k,
            Self::Shift(k) => a.c_plus(k),
            Self::Reflect(k) => a.c_minus(k),
            Self::DivBy(k) => a / k,
            Self::Bump(k) => one_plus_square(a).c_over(k),
            Self::Div => a / one_plus_square(b),
            Self::Powi(k) if k >= 0 => a.powi(k),
            Self::Powi(k) => one_plus_square(a).powi(k),
            Self::Powf(p) => one_plus_square(a).powf(p),
            Self::Pow => one_plus_square(a).pow(b),
            Self::Sqrt => one_plus_square(a).sqrt(),
            Self::Exp => (a.sin() * 0.5).exp(),
            Self::Ln => one_plus_square(a).ln(),
            Self::Sin => a.sin(),
            Self::Cos => a.cos(),
            Self::Tan => (a.sin() * 0.5).tan(),
            Self::Atan2 => a.atan2(b),
            Self::Abs => a.abs(),
            Self::Hypot => a.hypot(b),
            Self::Min => a.min(b),
            Self::Max => a.max(b),
            Self::Sum => S::sum3(a, b, c),
        }
    }

    /// Whether the operand values `a`, `b` are far enough from the step's kink or
    /// singularity for central differences (always true for smooth steps).
    fn is_smooth_at(self, a: f64, b: f64) -> bool {
        match self {
            Self::Abs => a.abs() >= KINK_MARGIN,
            Self::Min | Self::Max => (a - b).abs() >= KINK_MARGIN,
            Self::Hypot => a.hypot(b) >= ORIGIN_MARGIN,
            // The branch cut is the negative x axis (x = b, y = a).
            Self::Atan2 => a.hypot(b) >= ORIGIN_MARGIN && (b > 0.0 || a.abs() >= KINK_MARGIN),
            _ => true,
        }
    }
}

fn step() -> impl Strategy<Value = Step> {
    let k = || -2.0..2.0f64;
    prop_oneof![
        Just(Step::Add),
        Just(Step::Sub),
        Just(Step::Mul),
        Just(Step::Neg),
        Just(Step::Square),
        k().prop_map(Step::Scale),
        k().prop_map(Step::Shift),
        k().prop_map(Step::Reflect),
        away_from_zero(0.5, 2.0).prop_map(Step::DivBy),
        k().prop_map(Step::Bump),
        Just(Step::Div),
        (-3..=4i32).prop_map(Step::Powi),
        (-2.5..2.5f64).prop_map(Step::Powf),
        Just(Step::Pow),
        Just(Step::Sqrt),
        Just(Step::Exp),
        Just(Step::Ln),
        Just(Step::Sin),
        Just(Step::Cos),
        Just(Step::Tan),
        Just(Step::Atan2),
        Just(Step::Abs),
        Just(Step::Hypot),
        Just(Step::Min),
        Just(Step::Max),
        Just(Step::Sum),
    ]
}

/// A step and the indices of its operands among the values built before it.
#[derive(Clone, Copy, Debug)]
struct Instruction {
    step: Step,
    operands: [usize; 3],
}

/// A straight-line program: values `0..vars` are the variables, the next `params` values
/// the parameters `p0`, `p1`, …, and each instruction appends one value.
#[derive(Clone, Debug)]
struct Program {
    vars: usize,
    params: usize,
    instructions: Vec<Instruction>,
}

impl Program {
    fn inputs(&self) -> usize {
        self.vars + self.params
    }

    fn value_count(&self) -> usize {
        self.inputs() + self.instructions.len()
    }

    /// Runs the program on the inputs and returns every value, inputs first.
    fn run<S: Scalar>(&self, inputs: Vec<S>) -> Vec<S> {
        let mut values = inputs;
        for instruction in &self.instructions {
            let [a, b, c] = instruction.operands.map(|i| values[i]);
            values.push(instruction.step.apply(a, b, c));
        }
        values
    }

    /// The plain `f64` oracle: every value at `x` with the parameters `params`.
    fn eval(&self, x: &[f64], params: &[f64]) -> Vec<f64> {
        self.run([x, params].concat())
    }

    /// Every value as an expression of `g`, the parameters defaulting to `params`.
    fn build<'g>(&self, g: &'g Graph, params: &[f64]) -> Vec<Expr<'g>> {
        let mut inputs = g.vars(self.vars);
        inputs.extend(
            params
                .iter()
                .enumerate()
                .map(|(k, &value)| g.param(&param_name(k), value)),
        );
        self.run(inputs)
    }

    /// Whether the oracle values are moderate and no kink argument is near its kink.
    fn is_well_conditioned(&self, values: &[f64]) -> bool {
        values
            .iter()
            .all(|v| v.is_finite() && v.abs() <= VALUE_BOUND)
            && self.instructions.iter().all(|instruction| {
                let [a, b, _] = instruction.operands;
                instruction.step.is_smooth_at(values[a], values[b])
            })
    }
}

fn param_name(k: usize) -> String {
    format!("p{k}")
}

/// A program of up to `max_instructions` instructions over 3–5 variables and 1–2
/// parameters.
fn program(max_instructions: usize) -> impl Strategy<Value = Program> {
    (3..=5usize, 1..=2usize).prop_flat_map(move |(vars, params)| {
        prop::collection::vec(
            (step(), prop::array::uniform3(any::<Index>())),
            1..=max_instructions,
        )
        .prop_map(move |raw| Program {
            vars,
            params,
            instructions: raw
                .into_iter()
                .enumerate()
                .map(|(i, (step, operands))| Instruction {
                    step,
                    // Any value built so far: an input or an earlier instruction.
                    operands: operands.map(|o| o.index(vars + params + i)),
                })
                .collect(),
        })
    })
}

/// A program, a point, parameter values for compiling and others to switch to.
#[derive(Clone, Debug)]
struct Case {
    program: Program,
    x: Vec<f64>,
    params: Vec<f64>,
    new_params: Vec<f64>,
}

impl Case {
    /// Whether the program is well conditioned at `x` with both parameter sets.
    fn is_well_conditioned(&self) -> bool {
        [&self.params, &self.new_params].iter().all(|params| {
            self.program
                .is_well_conditioned(&self.program.eval(&self.x, params))
        })
    }
}

fn case(max_instructions: usize) -> impl Strategy<Value = Case> {
    program(max_instructions).prop_flat_map(|program| {
        let input = || prop::collection::vec(-2.0..2.0f64, program.params);
        (
            prop::collection::vec(-2.0..2.0f64, program.vars),
            input(),
            input(),
            Just(program),
        )
            .prop_map(|(x, params, new_params, program)| Case {
                program,
                x,
                params,
                new_params,
            })
    })
}

/// A case, 2–4 of its values as outputs and one seed per output.
fn case_with_outputs() -> impl Strategy<Value = (Case, Vec<usize>, Vec<f64>)> {
    (
        case(10),
        prop::collection::vec((any::<Index>(), -2.0..2.0f64), 2..=4),
    )
        .prop_map(|(case, picks)| {
            let values = case.program.value_count();
            let (outputs, seeds) = picks.into_iter().map(|(i, s)| (i.index(values), s)).unzip();
            (case, outputs, seeds)
        })
}

/// Checks every value of a tape compiled from all the values of `program` (last value
/// first) against the oracle, and the gradient of the last value against central
/// differences.
fn check_program_at(
    tape: &mut Tape,
    program: &Program,
    x: &[f64],
    params: &[f64],
) -> Result<(), TestCaseError> {
    let mut want = program.eval(x, params);
    want.reverse();
    let mut grad = vec![f64::NAN; x.len()];
    let value = tape.gradient(x, &mut grad);
    prop_assert!(
        close(value, want[0], ROUNDING_TOL),
        "last value: tape {value}, f64 {}",
        want[0]
    );
    let got = tape.eval(x).to_vec();
    for (k, (&got, &want)) in got.iter().zip(&want).enumerate() {
        prop_assert!(
            close(got, want, ROUNDING_TOL),
            "value {k} from the end: tape {got}, f64 {want}"
        );
    }
    check_against_fd(tape, x, 0, &grad)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(PROGRAM_CASES))]

    /// Values against the `f64` oracle and gradients against central differences, then
    /// the same after changing the parameters of the compiled tape.
    #[test]
    fn random_programs(case in case(12)) {
        prop_assume!(case.is_well_conditioned());
        let Case { program, x, params, new_params } = case;
        let g = Graph::new();
        let mut values = program.build(&g, &params);
        values.reverse();
        let mut tape = Tape::compile(&g, &values);
        check_program_at(&mut tape, &program, &x, &params)?;

        for (k, &value) in new_params.iter().enumerate() {
            let id = tape
                .param_id(&param_name(k))
                .ok_or_else(|| TestCaseError::fail(format!("parameter {k} is not on the tape")))?;
            tape.set_param(id, value);
            prop_assert_eq!(tape.param(id).to_bits(), value.to_bits());
        }
        check_program_at(&mut tape, &program, &x, &new_params)?;
    }

    /// Each Jacobian row is the gradient of its output compiled alone, and matches
    /// central differences.
    #[test]
    fn jacobian_rows_are_gradients((case, outputs, _seeds) in case_with_outputs()) {
        prop_assume!(case.is_well_conditioned());
        let Case { program, x, params, .. } = case;
        let n = x.len();
        let g = Graph::new();
        let values = program.build(&g, &params);
        let outputs: Vec<Expr<'_>> = outputs.iter().map(|&i| values[i]).collect();
        let mut tape = Tape::compile(&g, &outputs);
        let mut jacobian = vec![f64::NAN; outputs.len() * n];
        tape.jacobian(&x, &mut jacobian);

        for (k, (row, &output)) in jacobian.chunks_exact(n).zip(&outputs).enumerate() {
            let mut alone = Tape::compile(&g, &[output]);
            let mut grad = vec![f64::NAN; n];
            alone.gradient(&x, &mut grad);
            for (i, (&j, &d)) in row.iter().zip(&grad).enumerate() {
                prop_assert!(
                    close(j, d, ROUNDING_TOL),
                    "row {k}, column {i}: Jacobian {j}, gradient alone {d}"
                );
            }
            check_against_fd(&mut tape, &x, k, row)?;
        }
    }

    /// `forward` then `reverse(seeds)` is `Σ seeds[k] · ∇ output k`.
    #[test]
    fn weighted_reverse_sweep((case, outputs, seeds) in case_with_outputs()) {
        prop_assume!(case.is_well_conditioned());
        let Case { program, x, params, .. } = case;
        let n = x.len();
        let g = Graph::new();
        let values = program.build(&g, &params);
        let outputs: Vec<Expr<'_>> = outputs.iter().map(|&i| values[i]).collect();
        let mut tape = Tape::compile(&g, &outputs);
        let mut jacobian = vec![f64::NAN; outputs.len() * n];
        tape.jacobian(&x, &mut jacobian);
        let evaluated = tape.eval(&x).to_vec();

        let forward = tape.forward(&x).to_vec();
        prop_assert_eq!(&forward, &evaluated, "forward and eval give the same values");
        let mut grad = vec![f64::NAN; n];
        tape.reverse(&seeds, &mut grad);
        for (i, &got) in grad.iter().enumerate() {
            let terms = jacobian.chunks_exact(n).zip(&seeds).map(|(row, s)| s * row[i]);
            let want: f64 = terms.clone().sum();
            // Rounding relative to the terms: they may cancel.
            let scale: f64 = terms.map(f64::abs).sum();
            prop_assert!(
                (got - want).abs() <= ROUNDING_TOL * scale.max(1.0),
                "∂/∂x{i}: reverse sweep {got}, Σ seeds · Jacobian column {want}"
            );
        }
    }
}

/// A sub-expression used many times, or built twice, is one node of the graph and is
/// evaluated once on the tape.
#[test]
fn shared_subexpression_is_evaluated_once() {
    let g = Graph::new();
    let x = g.var();
    let y = g.var();
    let s = (x * y).sin();
    let nodes = g.node_count();
    assert_eq!(
        (x * y).sin(),
        s,
        "building (x·y).sin() twice gives one node"
    );
    assert_eq!(g.node_count(), nodes, "building it again adds no node");

    // f = s² + cos s + eˢ + 3s + s + s², with s² built twice.
    let f = g.sum([s * s, s.cos(), s.exp(), s * 3.0, s]) + (x * y).sin().square();
    let mut tape = Tape::compile(&g, &[f]);
    // x·y, sin, s·s, cos, exp, s·3, sum, square, + (the constant 3 is not an operation).
    assert_eq!(tape.op_count(), 9, "every use of s reads the same slot");

    let (vx, vy) = (0.7, -1.3);
    let mut grad = [f64::NAN; 2];
    let value = tape.gradient(&[vx, vy], &mut grad);
    let vs = (vx * vy).sin();
    let want = 2.0 * vs * vs + vs.cos() + vs.exp() + 4.0 * vs;
    assert!(
        close(value, want, ROUNDING_TOL),
        "value {value}, want {want}"
    );
    // df/ds = 4s − sin s + eˢ + 4, ds/dx = y cos(xy), ds/dy = x cos(xy).
    let df_ds = 4.0 * vs - vs.sin() + vs.exp() + 4.0;
    let want = [df_ds * vy * (vx * vy).cos(), df_ds * vx * (vx * vy).cos()];
    for (got, want) in grad.iter().zip(want) {
        assert!(
            close(*got, want, ROUNDING_TOL),
            "gradient {got}, want {want}"
        );
    }
}
