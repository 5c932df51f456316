//! Benchmark of the augmented-Lagrangian solver.
//!
//! 1. A snapping-sized problem: three cylinders (centre, unit axis with the equality
//!    |a|² = 1, radius r ≥ 0.05 and height h ≥ 0.05; 24 variables, 3 equalities and
//!    6 inequalities) fitted to noisy 2D samples of their rim ellipses under
//!    orthographic projection along z; with the snap, a fourth equality makes cylinder 2
//!    stand on the base plane of cylinder 1 (10 constraints). Each sample is lifted into
//!    its rim's plane and contributes (|X − q| − r)², plus a depth prior per cylinder
//!    (orthographic views do not see depth). Timed: building and compiling the problem,
//!    one evaluation, a cold solve from a perturbed pose with zero multipliers, and
//!    solves over a drag (one rim's samples move a little per frame; each solve starts
//!    from the previous frame's report), with 10 samples per rim (60 in all) without and
//!    with the snap, and with 30 per rim (180 in all) with the snap.
//! 2. Every Hock–Schittkowski problem of `hock_schittkowski::all()` from its standard
//!    start, with the default inner solver (our bounded L-BFGS) and with argmin's L-BFGS.
//!
//! Run with `cargo bench --no-default-features --bench solve`; see `benches/support` for
//! the environment variables and the name filter.

#![expect(clippy::print_stdout, reason = "benchmark output")]

mod support;

use std::f64::consts::TAU;
use std::time::Duration;

use geosnap::core::ad::{Expr, Graph, ParamId, Tape, Vec3};
use geosnap::core::solve::{
    hock_schittkowski, AugLagSettings, InnerSolver, Problem, SolveReport, Solver, Start,
};
use glam::{DVec2, DVec3};
use support::{fmt_ns, timed, Bench, Rng, Stats, Table};

/// The lower bound on radius and height.
const MIN_SIZE: f64 = 0.05;
/// Standard deviation of the sample noise (the scene spans about 2 units).
const NOISE: f64 = 0.003;
/// Weight of the depth prior (`c_z` − depth hint)².
const DEPTH_WEIGHT: f64 = 1.0;
/// Frames of the simulated drag.
const FRAMES: usize = 24;
/// How far the dragged rim's samples move per frame.
const DRAG_STEP: DVec2 = DVec2::new(0.003, 0.005);
/// Variables per cylinder: centre (3), axis (3), radius, height.
const CYLINDER_VARS: usize = 8;

/// A cylinder of the scene: the bottom rim is centred at `centre`, the top rim at
/// `centre + height·axis`.
#[derive(Clone, Copy, Debug)]
struct Cylinder {
    centre: DVec3,
    axis: DVec3,
    radius: f64,
    height: f64,
}

impl Cylinder {
    fn rim_point(&self, rim: usize, t: f64) -> DVec3 {
        let (u, v) = self.axis.any_orthonormal_pair();
        let q = self.centre + self.axis * (self.height * rim as f64);
        q + self.radius * (t.cos() * u + t.sin() * v)
    }

    fn vars(&self) -> [f64; CYLINDER_VARS] {
        let (c, a) = (self.centre, self.axis);
        [c.x, c.y, c.z, a.x, a.y, a.z, self.radius, self.height]
    }

    fn from_vars(v: &[f64]) -> Self {
        Self {
            centre: DVec3::new(v[0], v[1], v[2]),
            axis: DVec3::new(v[3], v[4], v[5]),
            radius: v[6],
            height: v[7],
        }
    }
}

/// The true scene: three cylinders seen from slightly above (axes tilted towards the
/// viewer, as they are usually drawn); cylinder 2 stands on the base plane of cylinder 1,
/// which the problem states as a snap constraint.
fn truth() -> Vec<Cylinder> {
    let axis = DVec3::new(-0.15, 0.85, 0.5).normalize();
    let beside = (DVec3::X - DVec3::X.dot(axis) * axis).normalize();
    let base = DVec3::new(0.2, -0.4, 0.3);
    vec![
        Cylinder {
            centre: DVec3::new(-0.6, -0.3, 0.0),
            axis: DVec3::new(0.1, 0.9, 0.42).normalize(),
            radius: 0.25,
            height: 0.6,
        },
        Cylinder {
            centre: base,
            axis,
            radius: 0.18,
            height: 0.45,
        },
        Cylinder {
            centre: base + 0.55 * beside,
            axis,
            radius: 0.22,
            height: 0.35,
        },
    ]
}

/// Noisy image samples of every rim, in the order cylinder, rim (bottom, top), sample.
fn observe(scene: &[Cylinder], per_rim: usize, rng: &mut Rng) -> Vec<DVec2> {
    let mut points = Vec::with_capacity(scene.len() * 2 * per_rim);
    for cylinder in scene {
        for rim in 0..2 {
            for m in 0..per_rim {
                let t = TAU * (m as f64 + rng.uniform(-0.3, 0.3)) / per_rim as f64;
                let p = cylinder.rim_point(rim, t);
                points.push(DVec2::new(
                    p.x + NOISE * rng.normal(),
                    p.y + NOISE * rng.normal(),
                ));
            }
        }
    }
    points
}

/// The samples of drag frame `frame`: the top rim of cylinder 0 moved `frame` steps.
fn drag_frame(base: &[DVec2], per_rim: usize, frame: usize) -> Vec<DVec2> {
    let mut points = base.to_vec();
    for p in &mut points[per_rim..2 * per_rim] {
        *p += DRAG_STEP * frame as f64;
    }
    points
}

/// The start pose of a cold solve: every cylinder moved, tilted by about 8°, its radius
/// 15 % too large and its height 15 % too small.
fn perturbed(scene: &[Cylinder], rng: &mut Rng) -> Vec<f64> {
    let mut x = Vec::with_capacity(scene.len() * CYLINDER_VARS);
    for c in scene {
        let shift = DVec3::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), 0.0);
        let tilt = DVec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
        let tilt = (tilt - tilt.dot(c.axis) * c.axis).normalize() * 0.14;
        x.extend_from_slice(
            &Cylinder {
                centre: c.centre + 0.04 * shift + DVec3::new(0.0, 0.0, 0.1),
                axis: (c.axis + tilt).normalize(),
                radius: c.radius * 1.15,
                height: c.height * 0.85,
            }
            .vars(),
        );
    }
    x
}

fn point_param(k: usize, rim: usize, m: usize, coordinate: char) -> String {
    format!("cyl{k} rim{rim} p{m} {coordinate}")
}

fn depth_param(k: usize) -> String {
    format!("cyl{k} depth")
}

/// The expressions of the fitting problem.
struct Parts<'g> {
    objective: Expr<'g>,
    equalities: Vec<(String, Expr<'g>)>,
    inequalities: Vec<(String, Expr<'g>)>,
}

/// The size of a fitting problem.
#[derive(Clone, Copy, Debug)]
struct Shape {
    cylinders: usize,
    /// Samples per rim.
    per_rim: usize,
    /// Whether cylinder 2 is snapped onto the base plane of cylinder 1.
    snap: bool,
}

impl Shape {
    fn label(self) -> String {
        format!(
            "{}×2×{} pts{}",
            self.cylinders,
            self.per_rim,
            if self.snap { " + snap" } else { ", no snap" }
        )
    }
}

/// Builds the fit; the samples and depth hints are parameters.
fn build_graph(g: &Graph, shape: Shape) -> Parts<'_> {
    let Shape {
        cylinders,
        per_rim,
        snap,
    } = shape;
    let mut terms = Vec::with_capacity(cylinders * (2 * per_rim + 1));
    let mut equalities = Vec::new();
    let mut inequalities = Vec::new();
    let mut frames = Vec::new();
    for k in 0..cylinders {
        let c = Vec3::new_vars(g);
        let a = Vec3::new_vars(g);
        frames.push((c, a));
        let r = g.var();
        let h = g.var();
        for rim in 0..2 {
            let q = if rim == 0 { c } else { c + a * h };
            for m in 0..per_rim {
                let dx = g.param(&point_param(k, rim, m, 'x'), 0.0) - q.x;
                let dy = g.param(&point_param(k, rim, m, 'y'), 0.0) - q.y;
                // Lift the sample into the rim's plane a·(X − q) = 0.
                let dz = (a.x * dx + a.y * dy) / a.z;
                let distance = g.sum([dx.square(), dy.square(), dz.square()]).sqrt();
                terms.push((distance - r).square());
            }
        }
        let depth = g.param(&depth_param(k), 0.0);
        terms.push(DEPTH_WEIGHT * (c.z - depth).square());
        equalities.push((format!("cyl{k} |axis|² = 1"), a.norm_squared() - 1.0));
        inequalities.push((format!("cyl{k} radius ≥ {MIN_SIZE}"), r - MIN_SIZE));
        inequalities.push((format!("cyl{k} height ≥ {MIN_SIZE}"), h - MIN_SIZE));
    }
    if snap {
        if let [_, (c1, a1), (c2, _), ..] = frames[..] {
            // The snap: cylinder 2 stands on the base plane of cylinder 1.
            let on_plane = a1.dot(c2 - c1);
            equalities.push(("cyl2 on the base plane of cyl1".to_owned(), on_plane));
        }
    }
    Parts {
        objective: g.sum(terms),
        equalities,
        inequalities,
    }
}

fn compile(g: &Graph, parts: &Parts<'_>) -> Problem {
    let mut builder = Problem::builder(g, parts.objective);
    for (label, c) in &parts.equalities {
        builder = builder.equality(label.clone(), *c);
    }
    for (label, c) in &parts.inequalities {
        builder = builder.inequality(label.clone(), *c);
    }
    builder.build()
}

/// The compiled fit with the ids of its data parameters.
struct Fit {
    problem: Problem,
    /// (x, y) per sample, in the order of [`observe`].
    points: Vec<(ParamId, ParamId)>,
    depths: Vec<ParamId>,
}

impl Fit {
    fn new(shape: Shape) -> Self {
        let Shape {
            cylinders, per_rim, ..
        } = shape;
        let g = Graph::new();
        let parts = build_graph(&g, shape);
        let problem = compile(&g, &parts);
        let id = |name: String| {
            problem
                .param_id(&name)
                .expect("the graph has the parameter")
        };
        let mut points = Vec::new();
        for k in 0..cylinders {
            for rim in 0..2 {
                for m in 0..per_rim {
                    points.push((
                        id(point_param(k, rim, m, 'x')),
                        id(point_param(k, rim, m, 'y')),
                    ));
                }
            }
        }
        let depths = (0..cylinders).map(|k| id(depth_param(k))).collect();
        Self {
            problem,
            points,
            depths,
        }
    }

    fn load(&mut self, points: &[DVec2], scene: &[Cylinder]) {
        for (&(ix, iy), p) in self.points.iter().zip(points) {
            self.problem.set_param_id(ix, p.x);
            self.problem.set_param_id(iy, p.y);
        }
        for (&id, c) in self.depths.iter().zip(scene) {
            self.problem.set_param_id(id, c.centre.z);
        }
    }
}

/// Median and maximum of a count over reports, as `median/max`.
fn med_max(reports: &[SolveReport], count: impl Fn(&SolveReport) -> u64) -> String {
    let mut v: Vec<u64> = reports.iter().map(count).collect();
    v.sort_unstable();
    format!("{}/{}", v[v.len() / 2], v[v.len() - 1])
}

fn median_evals(reports: &[SolveReport]) -> u64 {
    let mut v: Vec<u64> = reports.iter().map(|r| r.evaluations).collect();
    v.sort_unstable();
    v[v.len() / 2]
}

/// The extra columns of a solve row: a single report, or median/max over a drag.
fn solve_columns(reports: &[SolveReport]) -> [String; 4] {
    if let [report] = reports {
        return [
            report.outer_iterations.to_string(),
            report.inner_iterations.to_string(),
            report.evaluations.to_string(),
            format!("{:?}", report.termination),
        ];
    }
    let converged = reports
        .iter()
        .filter(|r| r.termination.is_converged())
        .count();
    [
        med_max(reports, |r| r.outer_iterations as u64),
        med_max(reports, |r| r.inner_iterations),
        med_max(reports, |r| r.evaluations),
        format!("{converged}/{} Converged", reports.len()),
    ]
}

/// How far a solution is from the true scene: the largest axis angle (degrees), and the
/// largest radius and height errors.
fn pose_error(x: &[f64], scene: &[Cylinder]) -> (f64, f64, f64) {
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for (v, truth) in x.chunks_exact(CYLINDER_VARS).zip(scene) {
        let fit = Cylinder::from_vars(v);
        let angle = fit.axis.normalize().dot(truth.axis).clamp(-1.0, 1.0).acos();
        worst.0 = worst.0.max(angle.to_degrees());
        worst.1 = worst.1.max((fit.radius - truth.radius).abs());
        worst.2 = worst.2.max((fit.height - truth.height).abs());
    }
    worst
}

fn solve_once(problem: &mut Problem, settings: &AugLagSettings, start: &Start) -> SolveReport {
    Solver::new(settings)
        .solve(problem, start)
        .expect("the start fits the problem")
}

/// One cylinder-fit case: the scene, its samples over the drag, and reference solves.
struct Case {
    label: String,
    scene: Vec<Cylinder>,
    shape: Shape,
    /// The samples of each drag frame.
    frames: Vec<Vec<DVec2>>,
    /// The perturbed start pose of the cold solve.
    x0: Vec<f64>,
    fit: Fit,
    settings: AugLagSettings,
    /// Frame 0 cold from `x0`, then each frame warm from the previous report.
    chain: Vec<SolveReport>,
    /// Each frame from 1 on, started at the previous report's x with zero multipliers.
    x_only: Vec<SolveReport>,
}

impl Case {
    /// Builds the case with `per_rim` samples per rim and solves the drag once.
    fn new(shape: Shape) -> Self {
        let per_rim = shape.per_rim;
        let scene = truth();
        // The settings snapping uses: tolerances 1e-7 in the normalised frame, caps.
        let settings = geosnap::core::snap::SnapSettings::default()
            .solver()
            .clone();
        let mut rng = Rng::new(0x5_0001 + per_rim as u64);
        let base = observe(&scene, per_rim, &mut rng);
        let frames: Vec<Vec<DVec2>> = (0..FRAMES).map(|f| drag_frame(&base, per_rim, f)).collect();
        let x0 = perturbed(&scene, &mut rng);
        let mut fit = Fit::new(shape);
        fit.load(&frames[0], &scene);
        let mut chain = vec![solve_once(&mut fit.problem, &settings, &Start::cold(&x0))];
        let mut x_only = Vec::new();
        for frame in &frames[1..] {
            fit.load(frame, &scene);
            let previous = chain.last().expect("the chain starts with the cold solve");
            let from_x = Start::cold(&previous.x);
            x_only.push(solve_once(&mut fit.problem, &settings, &from_x));
            let next = solve_once(&mut fit.problem, &settings, &Start::warm(previous));
            chain.push(next);
        }
        Self {
            label: shape.label(),
            scene,
            shape,
            frames,
            x0,
            fit,
            settings,
            chain,
            x_only,
        }
    }

    /// Prints the size of the problem and how well the solves fit the true scene.
    fn describe(&self, tape: &Tape) {
        let cold = &self.chain[0];
        let last = self.chain.last().expect("the chain is not empty");
        let p = &self.fit.problem;
        let (angle, dr, dh) = pose_error(&cold.x, &self.scene);
        println!();
        println!(
            "Cylinder fit {}: {} variables, {} equalities, {} inequalities, {} samples, \
             {} parameters; {} tape operations, {} edges",
            self.label,
            p.var_count(),
            p.equality_count(),
            p.inequality_count(),
            self.fit.points.len(),
            self.fit.points.len() * 2 + self.fit.depths.len(),
            tape.op_count(),
            tape.edge_count()
        );
        println!(
            "  cold solve: f = {:.3e}, ‖c‖∞ = {:.1e}, ‖∇L‖∞ = {:.1e}; vs truth: axis \
             {angle:.2}°, radius {dr:.4}, height {dh:.4}",
            cold.objective, cold.max_violation, cold.gradient_norm
        );
        println!(
            "  after the drag ({} frames, {:.3} moved): f = {:.3e}, height of cylinder 0 \
             {:.4} (was {:.4})",
            FRAMES - 1,
            (DRAG_STEP * (FRAMES - 1) as f64).length(),
            last.objective,
            last.x[7],
            cold.x[7]
        );
    }

    /// Times the cold solve of frame 0 from the perturbed pose.
    fn time_cold(&mut self) -> Duration {
        self.fit.load(&self.frames[0], &self.scene);
        let start = Start::cold(&self.x0);
        let solver = Solver::new(&self.settings);
        timed(|| solver.solve(&mut self.fit.problem, &start)).1
    }

    /// Times the solve of drag frame `1 + i mod (FRAMES − 1)`: warm from the previous
    /// frame's report, or (with `warm` false) from its x with zero multipliers.
    fn time_frame(&mut self, i: usize, warm: bool) -> Duration {
        let f = 1 + i % (FRAMES - 1);
        self.fit.load(&self.frames[f], &self.scene);
        let start = if warm {
            Start::warm(&self.chain[f - 1])
        } else {
            Start::cold(&self.chain[f - 1].x)
        };
        let solver = Solver::new(&self.settings);
        timed(|| solver.solve(&mut self.fit.problem, &start)).1
    }
}

fn blank() -> [String; 4] {
    Default::default()
}

/// Building, evaluating, cold and warm solves of the cylinder fit with `per_rim`
/// samples per rim.
fn snapping(bench: &Bench, shape: Shape) {
    let mut case = Case::new(shape);
    let mut tape = fit_tape(&case.scene, shape, &case.frames[0]);
    case.describe(&tape);
    let label = case.label.clone();
    let table = Table::new(
        &format!("Cylinder fit {label} (drag rows: median/max over the frames)"),
        40,
        &[
            ("outer", 5),
            ("inner", 7),
            ("evals", 7),
            ("termination", 18),
        ],
    );
    if bench.wants(&format!("build {label}")) {
        let total = bench.each(|_| timed(|| Fit::new(shape)).1);
        table.row("build: graph + compile + param ids", &total, &blank());
        let g = Graph::new();
        let parts = build_graph(&g, case.shape);
        let compiled = bench.each(|_| timed(|| compile(&g, &parts)).1);
        table.row("build: compile only (Problem::build)", &compiled, &blank());
    }
    if !bench.wants(&format!("solve {label}")) {
        return;
    }
    // What the solver does per evaluation: forward, then one reverse sweep seeded with
    // the Lagrangian's weights.
    let seeds: Vec<f64> = (0..tape.output_count())
        .map(|k| 1.0 / (1.0 + k as f64))
        .collect();
    let mut grad = vec![0.0; tape.var_count()];
    let x = case.chain[0].x.clone();
    // The four variants are sampled in turn, so that they see the same machine load.
    let stats = bench.each_interleaved(4, |variant, i| match variant {
        0 => {
            timed(|| {
                tape.forward(&x);
                tape.reverse(&seeds, &mut grad);
                grad[0]
            })
            .1
        }
        1 => case.time_cold(),
        v => case.time_frame(i, v == 2),
    });
    let [eval, cold, warm, from_x] = <[Stats; 4]>::try_from(stats).expect("four variants");
    table.row("one evaluation: forward + reverse", &eval, &blank());
    let columns = solve_columns(&case.chain[..1]);
    table.row("cold: perturbed pose, zero multipliers", &cold, &columns);
    let columns = solve_columns(&case.chain[1..]);
    table.row("drag frame: Start::warm(previous)", &warm, &columns);
    let columns = solve_columns(&case.x_only);
    table.row(
        "drag frame: previous x, zero multipliers",
        &from_x,
        &columns,
    );
    targets(&label, &cold, &warm);
    let cold_evals = case.chain[0].evaluations as f64;
    let drag_evals = median_evals(&case.chain[1..]) as f64;
    println!(
        "  {label}: evaluations alone (count × one evaluation's median): cold {cold_evals} × \
         {} = {} ({:.0} % of the cold median), drag frame {drag_evals} × {} = {} ({:.0} % \
         of the warm median)",
        fmt_ns(eval.median),
        fmt_ns(cold_evals * eval.median),
        100.0 * cold_evals * eval.median / cold.median,
        fmt_ns(eval.median),
        fmt_ns(drag_evals * eval.median),
        100.0 * drag_evals * eval.median / warm.median,
    );
}

/// The fit's outputs (objective, equalities, inequalities) compiled into a bare tape with
/// the samples of `points` loaded: the problem does not expose its tape, and this one
/// times one evaluation of the kind the solver makes.
fn fit_tape(scene: &[Cylinder], shape: Shape, points: &[DVec2]) -> Tape {
    let per_rim = shape.per_rim;
    let g = Graph::new();
    let parts = build_graph(&g, shape);
    let mut outputs = vec![parts.objective];
    outputs.extend(
        parts
            .equalities
            .iter()
            .chain(&parts.inequalities)
            .map(|(_, e)| *e),
    );
    let mut tape = Tape::compile(&g, &outputs);
    let mut set = |name: String, value: f64| {
        let id = tape.param_id(&name).expect("the graph has the parameter");
        tape.set_param(id, value);
    };
    let mut p = points.iter();
    for (k, cylinder) in scene.iter().enumerate() {
        for rim in 0..2 {
            for m in 0..per_rim {
                let point = p.next().expect("one sample per rim point");
                set(point_param(k, rim, m, 'x'), point.x);
                set(point_param(k, rim, m, 'y'), point.y);
            }
        }
        set(depth_param(k), cylinder.centre.z);
    }
    tape
}

/// The figures against the targets (median cold solve ≤ 1 ms, warm ≤ 200 µs).
fn targets(label: &str, cold: &Stats, warm: &Stats) {
    for (what, s, target_us) in [
        ("cold solve", cold, 1000.0),
        ("warm drag frame", warm, 200.0),
    ] {
        let verdict = if s.median <= target_us * 1e3 {
            "met".to_owned()
        } else {
            format!("MISSED by {:.1}×", s.median / (target_us * 1e3))
        };
        println!(
            "  {label}: {what} median {}, p95 {} (target median ≤ {}: {verdict})",
            fmt_ns(s.median),
            fmt_ns(s.p95),
            fmt_ns(target_us * 1e3)
        );
    }
}

/// Every Hock–Schittkowski problem with both inner solvers.
fn hock_schittkowski_table(bench: &Bench) {
    let bounded = AugLagSettings::default();
    let argmin = AugLagSettings::default().with_inner_solver(InnerSolver::Argmin);
    let table = Table::new(
        "Hock–Schittkowski problems, standard start, default settings (bounded = our \
         bounded L-BFGS, the default; argmin = InnerSolver::Argmin)",
        14,
        &[
            ("outer", 5),
            ("inner", 6),
            ("evals", 6),
            ("|f−f*|", 8),
            ("termination", 18),
        ],
    );
    let mut totals = [(0.0, 0usize, 0u64, 0usize); 2];
    let solvers = [("bounded", &bounded), ("argmin", &argmin)];
    for p in hock_schittkowski::all() {
        if !bench.wants(p.name) {
            continue;
        }
        let start = Start::cold(p.start);
        let mut problems = [p.compile(), p.compile()];
        let reports: Vec<SolveReport> = problems
            .iter_mut()
            .zip(solvers)
            .map(|(problem, (_, settings))| solve_once(problem, settings, &start))
            .collect();
        // Both solvers' samples are taken in turn, so that they see the same load.
        let stats = bench.each_interleaved(2, |v, _| {
            let solver = Solver::new(solvers[v].1);
            timed(|| solver.solve(&mut problems[v], &start)).1
        });
        for (which, (stats, report)) in stats.iter().zip(&reports).enumerate() {
            let error = (report.objective - p.optimum).abs() / p.optimum.abs().max(1.0);
            let total = &mut totals[which];
            total.0 += stats.median;
            total.1 += report.outer_iterations;
            total.2 += report.inner_iterations;
            total.3 += usize::from(report.termination.is_converged() && error <= 1e-6);
            table.row(
                &format!("{} {}", p.name, solvers[which].0),
                stats,
                &[
                    report.outer_iterations.to_string(),
                    report.inner_iterations.to_string(),
                    report.evaluations.to_string(),
                    format!("{error:.1e}"),
                    format!("{:?}", report.termination),
                ],
            );
        }
    }
    println!();
    for (solver, (median, outer, inner, solved)) in ["bounded", "argmin"].iter().zip(totals) {
        if outer == 0 {
            continue; // filtered out
        }
        println!(
            "  {solver:<8} sum of medians {}, {outer} outer and {inner} inner iterations in \
             all, {solved} converged with |f−f*| ≤ 1e-6",
            fmt_ns(median)
        );
    }
}

fn main() {
    let bench = Bench::from_env();
    bench.print_intro(
        "Solver benchmarks (augmented Lagrangian; snapping fits with the snapping settings, \
         Hock–Schittkowski with the defaults)",
    );
    for (per_rim, snap) in [(10, false), (10, true), (30, true)] {
        snapping(
            &bench,
            Shape {
                cylinders: truth().len(),
                per_rim,
                snap,
            },
        );
    }
    hock_schittkowski_table(&bench);
}
