//! The per-primitive snapping problem min φ_p s.t. C_p, built with AD expressions in a
//! normalised frame.
//!
//! The frame: model coordinates minus the primitive's starting centre, divided by its
//! starting size, so that every tolerance and weight below is relative and a sketch
//! scaled ×10 gives the same problem (and a result ×10).
//!
//! φ_p = Σ_curves mean_samples ρ(d) + Σ_ends w_e·ρ(|end − target|) + w_r·Σ regularisers²
//!
//! - d is the exact distance of a stroke sample to its assigned projected curve
//!   (ellipse or polyline);
//! - ρ(d) = τ²·ln(1 + d²/τ²) is quadratic for small d and grows only logarithmically, so
//!   an overshoot or a stray sample cannot drag the fit (τ = 5 % of the size);
//! - end terms pull an end of an outline towards the extreme assigned sample along it,
//!   which fixes the length when no end ellipse was drawn at that end (weight 0.5); ends
//!   with an assigned ellipse, and box edges, get none, so overshoots cannot bias sizes;
//! - regularisers keep profiles and spines smooth (weight 0.01).
//!
//! A BGC's outline runs on a little past an end that an assigned end ellipse fixes, so
//! that a hand's overshoot there does not pull the end outwards (see `OutlineRun`).
//!
//! Each curve's samples are averaged so a long stroke does not outweigh a short ellipse.

use glam::{DVec2, DVec3};

use super::assign::Assignment;
use crate::ad::{Expr, Graph, Real, Vec2};
use crate::primitive::{Curve2, CurveClass, FeatureCurve, Primitive, ProjectedCurve, Shape};
use crate::solve::Problem;

/// The robust loss scale τ, relative to the primitive's size.
const TAU: f64 = 0.05;
/// Weight of an outline end without an assigned end ellipse.
const END_WEIGHT: f64 = 0.5;
/// Weight of the regularisers.
const REGULARIZER_WEIGHT: f64 = 0.01;

/// How strongly a fit holds a bent tube's radius profile smooth: the weight, inside the
/// residual, of the second differences of its radii ([`crate::primitive::Shape::profile`]).
///
/// A smooth profile is the right prior for a tube of one radius or a taper: the hand's
/// wobble along its outlines must not bend its radii (a wobble of half a percent of the
/// size is several percent of a thin tube's radius). It flattens a horn's flaring mouth,
/// though: at the smooth weight a horn whose radius grows 1.7× towards its mouth came out
/// 5 % off its drawing from its own pose. A cold snap of a bent tube therefore also fits
/// it held as drawn, and keeps that reading where it fits its strokes clearly closer (see
/// [`super::snap`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Profile {
    /// Held smooth (weight 15).
    #[default]
    Smooth,
    /// Held as its outlines draw it (weight 5: on the synthetic conditions bent tubes
    /// were recovered about as often anywhere from 2 to 8).
    Drawn,
}

impl Profile {
    /// The weight of a second difference of the radii, inside the residual.
    pub(crate) fn weight(self) -> f64 {
        match self {
            Self::Smooth => 15.0,
            Self::Drawn => 5.0,
        }
    }
}

/// The normalised frame: `normalised = (model − origin) / scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// The model point that becomes the origin.
    pub origin: DVec3,
    /// The model length that becomes 1.
    pub scale: f64,
}

impl Frame {
    /// The frame centred on `primitive` with its size as the unit.
    pub fn of(primitive: &Primitive) -> Self {
        Self {
            origin: primitive.center(),
            scale: primitive.size().max(f64::MIN_POSITIVE),
        }
    }

    /// A primitive into the frame.
    pub fn into_frame(&self, primitive: &Primitive) -> Primitive {
        primitive.transformed(-self.origin, 1.0 / self.scale)
    }

    /// A primitive out of the frame.
    pub fn out_of_frame(&self, primitive: &Primitive) -> Primitive {
        primitive
            .transformed(DVec3::ZERO, self.scale)
            .transformed(self.origin, 1.0)
    }

    /// A view-plane point into the frame.
    pub fn point(&self, p: DVec2) -> DVec2 {
        (p - self.origin.truncate()) / self.scale
    }
}

/// ρ from the squared distance: τ²·ln(1 + d²/τ²).
fn robust<T: Real>(d2: T) -> T {
    let tau2 = TAU * TAU;
    (d2 / tau2 + 1.0).ln() * tau2
}

/// The distance expression from a fixed point to a curve of expressions.
fn distance<'g>(g: &'g Graph, curve: &Curve2<Expr<'g>>, p: DVec2) -> Expr<'g> {
    match curve {
        Curve2::Ellipse { center, a, b } => {
            g.ellipse_distance(center.to_array(), a.to_array(), b.to_array(), p)
        }
        Curve2::Polyline(points) => {
            let points: Vec<[Expr<'g>; 2]> = points.iter().map(|q| q.to_array()).collect();
            g.polyline_distance(&points, p)
        }
    }
}

/// The extreme samples along a polyline's direction: the targets for its two ends.
fn end_targets(points: &[DVec2], samples: &[DVec2]) -> Option<[DVec2; 2]> {
    let (first, last) = (*points.first()?, *points.last()?);
    let dir = (last - first).normalize_or_zero();
    let key = |p: &&DVec2| (**p - first).dot(dir);
    let lo = samples.iter().min_by(|a, b| key(a).total_cmp(&key(b)))?;
    let hi = samples.iter().max_by(|a, b| key(a).total_cmp(&key(b)))?;
    Some([*lo, *hi])
}

/// How far (in sizes) past an end fixed by an end ellipse a BGC's outline runs on
/// straight along its end tangent, for the samples of a hand's overshoot.
const OUTLINE_RUN: f64 = 0.05;

/// How far (in sizes) behind an outline's current end a sample still gets its run: a
/// fit moves the end by less within one round.
const RUN_REACH: f64 = 0.2;

/// The straight run of a BGC's outline past an end that an assigned end ellipse fixes.
/// A hand overshoots an outline along its tangent there (by a few percent of the size);
/// counted against the outline's end, those samples pull it longer, which a fit pays
/// for by moving the end outwards and flattening its ellipse to keep the drawn rim: a
/// wrong tilt and length. A sample's distance is the smaller of its distance to the
/// outline and to this run ([`OUTLINE_RUN`] long: a longer run would let the outline
/// end short of its samples for free).
struct OutlineRun<'g> {
    end: Vec2<Expr<'g>>,
    /// The unit end tangent, outwards.
    dir: Vec2<Expr<'g>>,
    zero: Expr<'g>,
    /// The end and its unit outward tangent at the current pose: only samples near or
    /// past it get the run (the others are nearer the outline, and skipping them keeps
    /// a drag frame cheap).
    now: (DVec2, DVec2),
}

impl<'g> OutlineRun<'g> {
    /// The runs at the flagged ends (first, last) of outline `points` (`now` at the
    /// current pose).
    fn at_ends(
        g: &'g Graph,
        points: &[Vec2<Expr<'g>>],
        now: &[DVec2],
        ends: [bool; 2],
    ) -> Vec<Self> {
        let n = points.len();
        if n < 2 || now.len() != n {
            return Vec::new();
        }
        let run = |end: Vec2<Expr<'g>>, before: Vec2<Expr<'g>>, i: usize, j: usize| {
            let d = end - before;
            let len = (d.x.square() + d.y.square() + 1e-18).sqrt();
            Self {
                end,
                dir: Vec2::new(d.x / len, d.y / len),
                zero: g.constant(0.0),
                now: (now[i], (now[i] - now[j]).normalize_or_zero()),
            }
        };
        let mut runs = Vec::new();
        if ends[0] {
            runs.push(run(points[0], points[1], 0, 1));
        }
        if ends[1] {
            runs.push(run(points[n - 1], points[n - 2], n - 1, n - 2));
        }
        runs
    }

    /// Whether sample `p` (in the frame, where the size is 1) is near enough to the end
    /// to get the run.
    fn reaches(&self, p: DVec2) -> bool {
        (p - self.now.0).dot(self.now.1) > -RUN_REACH
    }

    /// The squared distance of `p` to the run.
    fn distance2(&self, p: DVec2) -> Expr<'g> {
        let v = Vec2::new(-self.end.x + p.x, -self.end.y + p.y);
        let along = v.dot(self.dir);
        let across = v.cross(self.dir);
        let behind = along.min(self.zero);
        let beyond = along - OUTLINE_RUN;
        let beyond = beyond - beyond.min(self.zero);
        across.square() + behind.square() + beyond.square()
    }
}

/// How far a box edge runs on past each of its corners for the stroke samples measured
/// against it, as a fraction of its length. A hand drawing a box overshoots its corners
/// (a sixth of an edge is common in a quick sketch, more in construction lines); counted
/// against the edge's end, those samples pull the corner outwards and the box grows
/// along that edge. The box's sizes need no such pull: every edge's corners lie on the
/// lines of the edges across it, and each drawn edge pins its line wherever along it the
/// stroke ends, so the sizes come from where the edges lie, not from how far the hand
/// carried them. A longer run costs more than it gains: near a corner it lets an edge
/// take the samples of the edge it meets.
const EDGE_RUN: f64 = 0.15;

/// A straight edge `points` (two corners) lengthened by [`EDGE_RUN`] at both ends.
fn edge_run<'g>(points: &[Vec2<Expr<'g>>]) -> Option<Curve2<Expr<'g>>> {
    let [a, b] = points else {
        return None;
    };
    let d = Vec2::new(b.x - a.x, b.y - a.y);
    Some(Curve2::Polyline(vec![
        Vec2::new(a.x - d.x * EDGE_RUN, a.y - d.y * EDGE_RUN),
        Vec2::new(b.x + d.x * EDGE_RUN, b.y + d.y * EDGE_RUN),
    ]))
}

/// The far end of a solid of revolution drawn as the half of its ellipse that the body
/// does not hide: a "U" under a standing can. Either half of the fitted ellipse fits such
/// a stroke, so a fit pushed along the axis (by a wide start, or by a relation in the
/// global solve) can slide the end by the ellipse's width until its hidden half lies on
/// the drawn arc: a second, wrong minimum. Whether an end is half drawn is judged where
/// the fit starts: all its samples on the side away from the other end. From then on a
/// sample that lies on the body's side of the end, past a margin of half the ellipse's
/// extent, is charged its squared depth there on top of its distance, which leaves a
/// correct fit untouched (docs/decisions.md gives what it was measured to gain).
struct FarHalf<'g> {
    /// The end ellipse's centre.
    center: Vec2<Expr<'g>>,
    /// From the other end's centre to this end's (in the view plane).
    away: Vec2<Expr<'g>>,
    /// How far a sample may lie on the body's side (frame units).
    margin: f64,
}

impl<'g> FarHalf<'g> {
    /// The half-drawn end that curve `k` is, if it is one: an end ellipse (`top` or
    /// `bottom`) whose samples all lie on the side away from the other end, as the
    /// numeric shape `now` stands.
    fn of(
        curves: &[ProjectedCurve<Expr<'g>>],
        now: &[ProjectedCurve<f64>],
        k: usize,
        samples: &[DVec2],
    ) -> Option<Self> {
        let other_name = match curves[k].name.as_str() {
            "top" => "bottom",
            "bottom" => "top",
            _ => return None,
        };
        let ellipse = |c: &ProjectedCurve<f64>| match &c.curve {
            Curve2::Ellipse { center, a, b } if c.class == CurveClass::Feature => {
                Some((center.to_dvec2(), a.to_dvec2(), b.to_dvec2()))
            }
            _ => None,
        };
        let j = now.iter().position(|c| c.name == other_name)?;
        let ((c, a, b), (o, _, _)) = (ellipse(&now[k])?, ellipse(&now[j])?);
        let away = c - o;
        // An axis seen end-on has no side to speak of.
        if away.length() < 0.05 {
            return None;
        }
        let w = away.normalize();
        let extent = a.dot(w).hypot(b.dot(w));
        let margin = 0.5 * extent;
        if samples.iter().any(|p| (*p - c).dot(w) < -margin) {
            return None;
        }
        let centre_of = |curve: &ProjectedCurve<Expr<'g>>| match &curve.curve {
            Curve2::Ellipse { center, .. } => Some(*center),
            Curve2::Polyline(_) => None,
        };
        let (center, other) = (centre_of(&curves[k])?, centre_of(&curves[j])?);
        Some(Self {
            center,
            away: Vec2::new(center.x - other.x, center.y - other.y),
            margin,
        })
    }

    /// The squared depth of `p` on the body's side past the margin (0 elsewhere).
    fn behind2(&self, p: DVec2) -> Expr<'g> {
        let v = Vec2::new(-self.center.x + p.x, -self.center.y + p.y);
        let u = v.dot(self.away) / self.away.norm() + self.margin;
        let zero = u.lit(0.0);
        u.min(zero).square()
    }
}

/// The terms of one primitive's snapping problem over variables `x` of a shared graph:
/// φ_p and the internal constraints C_p. [`build_problem`] compiles them alone; the
/// global solve ([`crate::model`]) sums them over every primitive.
#[derive(Debug)]
pub struct FitTerms<'g> {
    /// φ_p.
    pub objective: Expr<'g>,
    /// The equality constraints c = 0 of the parameterisation, labelled.
    pub equalities: Vec<(&'static str, Expr<'g>)>,
    /// The inequality constraints g ≥ 0, labelled.
    pub inequalities: Vec<(&'static str, Expr<'g>)>,
    /// The named 3D feature curves over the same variables, which relations refer to.
    pub features: Vec<FeatureCurve<Expr<'g>>>,
}

/// The terms of the snapping problem of `primitive` (already in `frame`) for the strokes
/// of `assignment` (view-plane samples, converted into the frame here), over variables
/// `x` (one per parameter of `primitive`) of graph `g`; a bent tube's radii held as
/// `profile` says.
pub fn fit_terms<'g>(
    g: &'g Graph,
    x: &[Expr<'g>],
    primitive: &Primitive,
    assignment: &Assignment,
    frame: &Frame,
    profile: Profile,
) -> FitTerms<'g> {
    let shape = primitive.shape(x);
    let numeric = primitive.current_shape();
    let mut terms: Vec<Expr<'g>> = Vec::new();
    let ends_fixed = [
        end_ellipse_assigned(&shape.curves, assignment, "bottom"),
        end_ellipse_assigned(&shape.curves, assignment, "top"),
    ];
    for (k, (curve, assigned)) in shape.curves.iter().zip(&assignment.curves).enumerate() {
        let samples: Vec<DVec2> = assigned
            .iter()
            .flat_map(|a| a.samples.iter().map(|p| frame.point(*p)))
            .collect();
        if samples.is_empty() {
            continue;
        }
        let runs = outline_runs(g, primitive, curve, &numeric.curves[k], ends_fixed);
        let half = FarHalf::of(&shape.curves, &numeric.curves, k, &samples);
        terms.push(sample_term(
            g,
            primitive,
            curve,
            &runs,
            half.as_ref(),
            &samples,
        ));
        push_end_terms(curve, &numeric.curves[k], &samples, ends_fixed, &mut terms);
    }
    push_regularizer_terms(&shape, assignment, profile, &mut terms);
    FitTerms {
        objective: g.sum(terms),
        equalities: shape.equalities,
        inequalities: shape.inequalities,
        features: shape.features,
    }
}

/// Whether the end ellipse named `name` (`"bottom"` or `"top"`) among `curves` has
/// strokes assigned in `assignment`.
fn end_ellipse_assigned(
    curves: &[ProjectedCurve<Expr<'_>>],
    assignment: &Assignment,
    name: &str,
) -> bool {
    curves
        .iter()
        .zip(&assignment.curves)
        .any(|(c, a)| c.name == name && c.class == CurveClass::Feature && !a.is_empty())
}

/// The runs of a BGC's outline `curve` past its ends (first, last) that an assigned end
/// ellipse fixes, as flagged in `ends_fixed` (see [`OutlineRun`]); `now` is the same
/// curve at the current pose. None for other curves and kinds.
fn outline_runs<'g>(
    g: &'g Graph,
    primitive: &Primitive,
    curve: &ProjectedCurve<Expr<'g>>,
    now: &ProjectedCurve<f64>,
    ends_fixed: [bool; 2],
) -> Vec<OutlineRun<'g>> {
    match (primitive, curve.class, &curve.curve) {
        (Primitive::Bgc(_), CurveClass::Silhouette, Curve2::Polyline(points)) => {
            let now: Vec<DVec2> = match &now.curve {
                Curve2::Polyline(now) => now.iter().map(|p| p.to_dvec2()).collect(),
                Curve2::Ellipse { .. } => Vec::new(),
            };
            OutlineRun::at_ends(g, points, &now, ends_fixed)
        }
        _ => Vec::new(),
    }
}

/// The mean robust distance of `samples` (in the frame) to `curve`: a box edge is
/// measured lengthened past its corners (see [`EDGE_RUN`]), a sample near an outline's
/// `runs` takes the nearer of the outline and the run, and a half-drawn end adds the
/// sample's depth on the body's side (see [`FarHalf`]).
fn sample_term<'g>(
    g: &'g Graph,
    primitive: &Primitive,
    curve: &ProjectedCurve<Expr<'g>>,
    runs: &[OutlineRun<'g>],
    half: Option<&FarHalf<'g>>,
    samples: &[DVec2],
) -> Expr<'g> {
    let measured = match (primitive, &curve.curve) {
        (Primitive::Cuboid(_), Curve2::Polyline(points)) => edge_run(points),
        _ => None,
    };
    let measured = measured.as_ref().unwrap_or(&curve.curve);
    let per_sample: Vec<Expr<'g>> = samples
        .iter()
        .map(|p| {
            let d2 = distance(g, measured, *p).square();
            let d2 = runs
                .iter()
                .filter(|run| run.reaches(*p))
                .fold(d2, |d2, run| d2.min(run.distance2(*p)));
            let d2 = half.map_or(d2, |h| d2 + h.behind2(*p));
            robust(d2)
        })
        .collect();
    g.sum(per_sample) * (1.0 / samples.len() as f64)
}

/// Pushes onto `terms` the pulls of an outline's ends (first, last) towards the extreme
/// `samples` along it, for the ends not flagged in `ends_fixed`; `now` is the same curve
/// at the current pose. Only an outline end with nothing else to fix it is pulled to the
/// drawn extreme: an assigned end ellipse fixes it better, and box edges fix each other
/// at the corners; a pull there would let overshoots bias the sizes.
fn push_end_terms<'g>(
    curve: &ProjectedCurve<Expr<'g>>,
    now: &ProjectedCurve<f64>,
    samples: &[DVec2],
    ends_fixed: [bool; 2],
    terms: &mut Vec<Expr<'g>>,
) {
    let (Curve2::Polyline(points), Curve2::Polyline(now)) = (&curve.curve, &now.curve) else {
        return;
    };
    let now: Vec<DVec2> = now.iter().map(|p| p.to_dvec2()).collect();
    let Some(targets) = end_targets(&now, samples) else {
        return;
    };
    let ends = [points[0], points[points.len() - 1]];
    for ((end, target), fixed) in ends.iter().zip(targets).zip(ends_fixed) {
        if curve.class != CurveClass::Silhouette || fixed {
            continue;
        }
        let d2 = (end.x - target.x).square() + (end.y - target.y).square();
        terms.push(robust(d2) * END_WEIGHT);
    }
}

/// Pushes onto `terms` the weighted squares of `shape`'s regularisers, of its profile's
/// second differences (held as `profile` says), and of its pull towards the least tilted
/// pose when fewer than two end ellipses have strokes in `assignment` (`Shape::untilted`).
fn push_regularizer_terms<'g>(
    shape: &Shape<Expr<'g>>,
    assignment: &Assignment,
    profile: Profile,
    terms: &mut Vec<Expr<'g>>,
) {
    for r in &shape.regularizers {
        terms.push(r.square() * REGULARIZER_WEIGHT);
    }
    let held = profile.weight();
    for r in &shape.profile {
        terms.push((*r * held).square() * REGULARIZER_WEIGHT);
    }
    let ends_drawn = shape
        .curves
        .iter()
        .zip(&assignment.curves)
        .filter(|(c, a)| c.class == CurveClass::Feature && !a.is_empty())
        .count();
    if ends_drawn < 2 {
        for r in &shape.untilted {
            terms.push(r.square() * REGULARIZER_WEIGHT);
        }
    }
}

/// Builds the snapping problem of `primitive` (already in `frame`) for the strokes of
/// `assignment` (view-plane samples, converted into the frame here), a bent tube's radii
/// held as `profile` says.
pub fn build_problem(
    primitive: &Primitive,
    assignment: &Assignment,
    frame: &Frame,
    profile: Profile,
) -> Problem {
    let g = Graph::new();
    let x = g.vars(primitive.params().len());
    let terms = fit_terms(&g, &x, primitive, assignment, frame, profile);
    let mut builder = Problem::builder(&g, terms.objective);
    for (label, c) in terms.equalities {
        builder = builder.equality(label, c);
    }
    for (label, c) in terms.inequalities {
        builder = builder.inequality(label, c);
    }
    builder.build()
}

/// The RMS distance (view-plane units) of the assigned samples to their curves.
pub fn fit_rms(primitive: &Primitive, assignment: &Assignment) -> f64 {
    let shape = primitive.current_shape();
    let mut sum = 0.0;
    let mut count = 0usize;
    for (curve, assigned) in shape.curves.iter().zip(&assignment.curves) {
        for p in assigned.iter().flat_map(|a| &a.samples) {
            sum += super::assign::curve_distance(&curve.curve, *p).powi(2);
            count += 1;
        }
    }
    if count == 0 {
        0.0
    } else {
        (sum / count as f64).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::FarHalf;
    use crate::ad::{Graph, Tape};
    use crate::primitive::{Curve2, Cylinder, Primitive};

    /// A can standing towards the viewer, in its own frame.
    fn can() -> Primitive {
        Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.25, 0.85, 0.45).normalize(),
            length: 1.0,
            radius: 0.2,
        })
    }

    /// Points of the ellipse `name` of `p`, all of them or only those on the side away
    /// from the other end.
    fn drawn(p: &Primitive, name: &str, half: bool) -> Vec<DVec2> {
        let shape = p.current_shape();
        let centre = |n: &str| {
            shape.curves.iter().find_map(|c| match &c.curve {
                Curve2::Ellipse { center, .. } if c.name == n => Some(center.to_dvec2()),
                _ => None,
            })
        };
        let other = if name == "top" { "bottom" } else { "top" };
        let (c, o) = (
            centre(name).expect("an end"),
            centre(other).expect("an end"),
        );
        let curve = shape
            .curves
            .iter()
            .find(|c| c.name == name)
            .expect("an end");
        curve
            .curve
            .points(48)
            .into_iter()
            .filter(|p| !half || (*p - c).dot(c - o) >= 0.0)
            .collect()
    }

    #[test]
    fn a_tubes_tilt_is_pulled_to_the_view_plane_only_without_both_ends_drawn() {
        use crate::primitive::{Bgc, CurveClass};
        use crate::sketch::StrokeId;
        use crate::snap::{AssignedStroke, Assignment};
        // A bent tube in a plane leaning 40° out of the view.
        let lean = 40f64.to_radians();
        let spine: Vec<DVec3> = (0..8)
            .map(|i| {
                let t = f64::from(i) / 7.0;
                let (x, y) = (t, 0.3 * (std::f64::consts::PI * t).sin());
                DVec3::new(x, y * lean.cos(), y * lean.sin())
            })
            .collect();
        let p = Primitive::Bgc(Bgc::through(spine, 0.05));
        let now = p.current_shape().curves;
        // Every curve of `class` takes samples of itself: a perfect drawing of it.
        let drawing = |class: CurveClass| Assignment {
            curves: now
                .iter()
                .map(|c| {
                    if c.class == class {
                        vec![AssignedStroke {
                            stroke: StrokeId(0),
                            samples: c.curve.points(16),
                            mean_distance: 0.0,
                            part: None,
                        }]
                    } else {
                        Vec::new()
                    }
                })
                .collect(),
        };
        let frame = super::Frame {
            origin: DVec3::ZERO,
            scale: 1.0,
        };
        let value = |assignment: &Assignment| {
            let g = Graph::new();
            let x = g.vars(p.params().len());
            let terms = super::fit_terms(&g, &x, &p, assignment, &frame, super::Profile::Smooth);
            Tape::compile(&g, &[terms.objective]).eval(&p.params())[0]
        };
        let ends = value(&drawing(CurveClass::Feature));
        let outlines = value(&drawing(CurveClass::Silhouette));
        // The pull: (1 − n_z²)·0.15, squared, with the regularisers' weight 0.01.
        let pull = (lean.sin().powi(2) * 0.15).powi(2) * 0.01;
        assert!(
            (outlines - ends - pull).abs() < 0.1 * pull,
            "{outlines} against {ends} (pull {pull})"
        );
    }

    #[test]
    fn a_far_end_drawn_as_a_u_charges_samples_on_the_bodys_side() {
        let p = can();
        let g = Graph::new();
        let x = g.vars(p.params().len());
        let shape = p.shape(&x);
        let now = p.current_shape().curves;
        let k = |name: &str| now.iter().position(|c| c.name == name).expect("an end");
        // The U under the can is a half-drawn end; a whole ellipse is not.
        let u = drawn(&p, "bottom", true);
        let half = FarHalf::of(&shape.curves, &now, k("bottom"), &u).expect("a U");
        assert!(FarHalf::of(
            &shape.curves,
            &now,
            k("bottom"),
            &drawn(&p, "bottom", false)
        )
        .is_none());
        assert!(FarHalf::of(&shape.curves, &now, k("top"), &drawn(&p, "top", false)).is_none());
        // Nothing for the drawn arc itself; on the body's side, the squared depth past
        // the margin.
        let params = p.params();
        let value = |p: DVec2| Tape::compile(&g, &[half.behind2(p)]).eval(&params)[0];
        assert!(u.iter().all(|s| value(*s) == 0.0));
        let centre = |name: &str| match &now[k(name)].curve {
            Curve2::Ellipse { center, .. } => center.to_dvec2(),
            Curve2::Polyline(_) => unreachable!("an ellipse"),
        };
        let c = centre("bottom");
        let towards_body = (centre("top") - c).normalize();
        let (near, far) = (
            value(c + towards_body * (half.margin + 0.01)),
            value(c + towards_body * (half.margin + 0.1)),
        );
        assert!(far > near && near > 0.0, "{near} then {far}");
    }
}
