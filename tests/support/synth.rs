//! A synthetic-sketch renderer: it draws a ground-truth primitive the way a person would,
//! from a random orthographic view, as strokes in sketch space (y down) with classes.
//!
//! Everything is computed in model space (formats.md §1: x right, y up, z towards the
//! viewer, orthographic view along −z) and drawn at the sketch point (x, −y). The
//! renderer shares no geometry code with `geosnap_core::primitive`: contours and visible arcs
//! are derived here from the surfaces themselves, so the test that uses it is an outside
//! check of the primitives' projected curves too.
//!
//! # Views
//!
//! A canonical primitive (axis +Y, centred at the origin) is rotated the way a designer
//! would look at it: the axis (or a bent tube's chord) makes at most 65° with the view
//! plane, so at least 25° with the view direction, and at least 5° (the ends are not
//! drawn as straight lines); the in-plane direction is uniform over the full circle. A
//! box is pitched 10°–45° (either sign) and yawed 10°–80° (either sign), then rolled by
//! a uniform angle, and kept when it shows three faces clearly and no edge points nearly
//! at the viewer: 0.15 ≤ |axis_z| ≤ cos 25° for each of its axes. A bent tube's plane
//! makes at most 60° with the view plane and its end tangents at least 20° with the view
//! direction. The centre lies anywhere in a
//! 3000 × 3000 sketch at a random depth, and the size (largest extent) is log-uniform in
//! 50 … 2000 sketch units.
//!
//! # Shapes
//!
//! Cylinders of radius 0.1–0.6 × their length; cones of bottom radius 0.2–0.5 × their
//! length and top radius from [`MIN_RADIUS`] × the size to 0.8 × the bottom's (the wide
//! end on top in 30 % of the cases); SGCs with a smooth vase-like profile
//! R·(1 + g·(t − ½) + b·sin(π·(f·t + φ))), R = 0.2–0.35 × the length, |g| ≤ 0.6,
//! |b| ≤ 0.3, f = 0.8–2, sampled at its eight rings, never thinner than [`MIN_RADIUS`];
//! boxes with sides 0.35–1 × the largest; BGCs along a circular arc bent by 40°–120°
//! with a radius of about [`MIN_RADIUS`]–0.15 × the spine length tapering by up to
//! ±30 % (its ends never thinner than [`MIN_RADIUS`]).
//! Views that hide what the criteria measure are redrawn: a cone or SGC whose contours
//! would (nearly) vanish (|β| > 0.8 below), a box edge or a bent tube's plane seen too
//! obliquely.
//!
//! # What is drawn
//!
//! - Cylinder, cone, SGC: the two contour generators (silhouette), the end that faces
//!   the viewer as a whole ellipse and, of the end that faces away, only its visible front
//!   arc (feature strokes).
//! - Sphere: its outline circle, in one or two strokes (silhouette).
//! - Cuboid: its visible edges, each a straight silhouette stroke.
//! - BGC: the projected spine offset by ± the radius along its 2D normal (silhouette),
//!   and the end circles as for a cylinder (feature).
//!
//! ## Contours of a surface of revolution
//!
//! A point of the surface is p(h, θ) = m(h) + r(h)·e(θ) with e a unit vector ⟂ the unit
//! axis a. Its outward normal is ∝ e − s·a, s = dr/dh (∂_θ p × ∂_h p ∝ (a × e) × (a +
//! s·e) = e − s·a). With the basis w = (a_y, −aₓ, 0)/ρ, k = a × w (ρ = |a_xy|, so
//! k_z = −ρ) and e = α·w + β·k, the contour (normal ⟂ the view direction z) is
//! e_z = s·a_z, i.e. β = −s·a_z/ρ and α = ±√(1 − β²). A cone's generator keeps the
//! same e along its length, so its contours are straight lines; an SGC's follow the
//! local slope of its smooth profile and are drawn densely (not only through the rings).
//!
//! ## Visible part of an end that faces away
//!
//! An end circle with centre m, outward normal n (= ±a) and radius r is drawn as
//! m + r·e(θ), e(θ) = cos θ·w + sin θ·k with w = (n_y, −nₓ, 0)/ρ, k = n × w (again
//! k_z = −ρ, so e_z = −ρ·sin θ). When n_z > 0 the end disc faces the viewer and, the
//! solid being convex near its end, the whole rim is visible. Otherwise the disc is hidden
//! and a rim point is visible exactly where the side surface next to it faces the viewer:
//! (e − s·a)_z > 0, i.e. e_z > s·a_z, i.e. sin θ < β with β = −s·a_z/ρ (s and a as
//! above, with a from bottom to top). That is the arc θ ∈ (π − asin β, 2π + asin β),
//! of angle π + 2·asin β, centred on θ = 3π/2 (the rim point nearest the viewer); its
//! end points are the contour points, so the arc meets the contour lines. A cylinder
//! (β = 0) shows half its back rim; a cone narrowing towards the viewer shows more.
//!
//! # Imperfections
//!
//! Per case a [`Style`]: per-point jitter (Gaussian, σ = 0.5–1 % of the primitive's size),
//! a low-frequency wobble along each stroke's normal (two sinusoids of 0.5–2.5 cycles per
//! stroke, amplitude 0.3–1 % of the stroke's extent, at most of the primitive's size —
//! motor variability grows with the movement, so a small ellipse wobbles less than a long
//! outline — zero-mean over the stroke so it bends the stroke without moving it), over- and undershoots of up to 5 % of the size at both ends of
//! every open stroke (outlines, arcs, box edges), outlines sometimes (30 %; box edges
//! 15 %) split in two pieces with a gap of 2–6 % of their length, and closed strokes
//! that do not close: the sweep misses or overlaps by up to 0.35–0.45 rad and the radius
//! drifts by up to 3 % from start to end. Strokes are drawn in either direction.
//!
//! # Conditions
//!
//! [`scene_with`] (single primitives) and [`draw_with`] (an assembly's parts) draw the
//! wider variety of issue 16 under a [`Condition`]; [`scene`] and [`draw`] are unchanged
//! (the same seed gives the same scene as before). The conditioned renderer first
//! *records* every ideal curve the pen would draw (the same geometry as above: contours,
//! end ellipses and front arcs, box edges, a closed curve with its closure error and
//! radius drift already in its sweep), then draws the recorded curves under the
//! condition ([`Pen::render`]).
//!
//! ## Shapes
//!
//! The size (largest extent) is log-uniform in 50 … 2000 as before.
//! - Cylinders: length over radius A from a mixture: a quarter thin discs (A = 0.1–0.25,
//!   a table top of thickness 1/8 of its radius has A = 0.125), a quarter rods (A =
//!   8–20), the rest log-uniform in 0.25–8; the largest extent max(length, 2·radius) is
//!   the size.
//! - Cones: length over bottom radius log-uniform in 0.3–12, top radius 0.25–0.8 × the
//!   bottom's, the wide end on top in 30 %; redrawn while |β| > 0.8 (as above), so flat
//!   cones only appear where the view lets their contours show.
//! - Spheres as before.
//! - Boxes: the largest side 1 and the others 0.6–1 (near-cubes, 30 %), one of them
//!   1/15–1/4 log-uniform and the other 0.4–1 (slabs, 35 %), or both 1/15–1/3
//!   log-uniform (planks, 35 %), given to the box's axes in a random cyclic order.
//! - SGCs: the profile of above with mean radius R = length/A, A log-uniform in 0.6–8,
//!   never thinner than 0.35·R, scaled so that its largest extent is the size.
//! - BGCs: a planar spine parameterised by arc length u ∈ [0, 1] (speed = its length,
//!   the size) through its tangent angle θ(u) in the spine's plane: a C is a circular
//!   arc, θ = b·(u − ½), b = 40°–150°; an S bends one way then the other, θ =
//!   4·h·u·(1 − u) − θ_c (the curvature 4h·(1 − 2u) changes sign at the middle), each
//!   half bending by h = 40°–90°; θ_c turns the chord onto the canonical +Y. Its points
//!   are integrated from the tangent (Simpson's rule, 64 steps), so the
//!   [`PROFILE_SAMPLES`] samples of the truth, at even u, are evenly spaced along it as
//!   the model wants. The radius r·(1 − τ/2 + τ·u)·(1 + φ·u³) has r = 0.094–0.15 × the
//!   length, a taper |τ| ≤ 0.3 and, in half of the tubes, a flare φ = 0.3–0.8 that
//!   widens the top end like a horn. The end circles face along the end tangents, and
//!   the outlines are the projected spine offset by ± the radius along its 2D normal, as
//!   for [`Pen::tube`] (the model's own approximation of a tube's contours).
//!
//! ## Views
//!
//! [`Condition::view`]: [`Condition::NearAxial`] puts the axis 65°–80° out of the view
//! plane, [`Condition::SideOn`] 0.5°–5° (the end ellipses are nearly straight), the other
//! conditions 5°–65° (a designer's view, as above). A box's view is its designer's
//! view; near-axial, a uniformly random rotation with one axis 10°–25° from the view
//! direction (two faces seen very obliquely); side-on, one with an axis 2.9°–8.6° out of
//! the view plane (0.05 ≤ |a_z| ≤ 0.15: that face nearly edge-on, the third face a thin
//! sliver) and none within 25° of the view direction. A face exactly edge-on would leave
//! the box undetermined: the two axes perpendicular to the one in the view plane then
//! project onto one line, and any turn θ about that axis with lengths Lb·cos θ, Lc·sin θ
//! draws the same, so such views are not drawn. A tube's view is a uniformly random rotation with its plane within 60° of
//! the view plane and its end tangents at least 20° from the view direction; near-axial,
//! its plane within 75.5° of the view plane and one end tangent 12°–30° from the view
//! direction (looking into one end); side-on, its plane within 14° of the view plane
//! (both end ellipses nearly straight).
//!
//! ## Hidden lines
//!
//! With `hidden_lines` (the test draws them in half of its scenes) a designer draws what
//! is behind the solid as ordinary strokes with the same hand: the rest of a far end's
//! rim, θ ∈ (asin β, π − asin β), the complement of its visible front arc (module docs
//! above), and a box's three edges whose adjacent faces both face away. Their labels
//! start with `hidden`.
//!
//! ## How the curves are drawn
//!
//! Every recorded curve is drawn as above, except that the hand's errors scale with the
//! curve drawn rather than with the primitive (a person's errors grow with the
//! movement): the jitter's σ and the over- and undershoots are fractions of the curve's
//! extent (at most the size), so the short outlines of a thin disc are not swamped by
//! errors the size of the whole disc. Then, per condition:
//! - [`Condition::Plain`], [`Condition::NearAxial`], [`Condition::SideOn`]: the hand
//!   only.
//! - [`Condition::Missing`]: one silhouette curve (an outline, a box edge or a sphere's
//!   outline), chosen at random, has a stretch of 20–60 % of its length left out,
//!   anywhere along it (pieces shorter than 3 % of it are not drawn).
//! - [`Condition::Overshoots`]: over- and undershoots up to 15 % of each curve's extent
//!   (at most 30 % of its length), 60 % of the open curves split by a gap of 4–12 % of
//!   their length, closed curves missing or overlapping by up to 8 % of their length.
//! - [`Condition::Sketchy`]: 80 % of the curves drawn as 2–3 strokes, each with its own
//!   hand, the later ones shifted from the first by 0.3–1.2 % of the curve's extent in a
//!   random direction (at most a quarter of the part's thinnest dimension: a hand keeps
//!   the copies of one line closer than the lines it tells apart), the copies together
//!   centred on the line meant (a line gone over reads as the middle of its strokes).
//!   Half the later copies go over a stretch of the line only (40–90 % of it, anywhere
//!   along it; an end ellipse's stretch is an open arc): a hand goes back over the part
//!   of a line it doubts.
//! - [`Condition::Joined`]: a solid of revolution's or a tube's two outlines and its far
//!   end's front arc (which meets both) become one U stroke, outline + arc + outline; a
//!   box has one or two pairs of edges that meet at a corner drawn as L strokes. Joined
//!   strokes are never split, and are labelled `U: …` or `L: …` (no single class).
//! - [`Condition::Fragments`]: 70 % of the curves drawn in 3–5 pieces of about equal
//!   length (cuts ± 30 % of a piece), each joint a gap or an overlap of up to 2 % of the
//!   curve's length.
//! - [`Condition::Slanted`]: every end circle's curves (its ellipse, or its front arc and
//!   hidden rest) turned about the circle's image centre by 2°–20° either way, one angle
//!   per end: a freehand ellipse lands where it is meant and about as large, but its
//!   axes come out off (the shared lego brick's studs lean 5–20°).
//! - [`Condition::Rough`]: every curve drawn as 2–3 strokes, each with its own hand, the
//!   later ones shifted by 1.5–8 % of the curve's extent, capped and centred as under
//!   [`Condition::Sketchy`]: a quick
//!   hand that goes over its lines without meeting them (a sketchier hand than
//!   [`Condition::Sketchy`]'s).

use std::f64::consts::{PI, TAU};

use geosnap::core::geom::projection::sketch_from_view;
use geosnap::core::primitive::{
    Bgc, Cone, Cuboid, Cylinder, Primitive, PrimitiveKind, Sgc, Sphere, PROFILE_SAMPLES,
};
use geosnap::core::sketch::StrokeClass;
use glam::{DQuat, DVec2, DVec3};

/// A small deterministic pseudo-random generator (SplitMix64).
#[derive(Clone, Debug)]
pub(crate) struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Log-uniform in [lo, hi).
    pub(crate) fn log_range(&mut self, lo: f64, hi: f64) -> f64 {
        self.range(lo.ln(), hi.ln()).exp()
    }

    /// True with probability `p`.
    pub(crate) fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// ±1 with equal probability.
    pub(crate) fn sign(&mut self) -> f64 {
        if self.chance(0.5) {
            1.0
        } else {
            -1.0
        }
    }

    /// A standard normal sample (Box–Muller).
    pub(crate) fn normal(&mut self) -> f64 {
        let u = 1.0 - self.unit();
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (TAU * v).cos()
    }

    /// A uniformly distributed unit vector.
    pub(crate) fn unit_vector(&mut self) -> DVec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, TAU);
        let s = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(s * phi.cos(), s * phi.sin(), z)
    }

    /// An angle in radians, uniform between `lo` and `hi` degrees.
    pub(crate) fn degrees(&mut self, lo: f64, hi: f64) -> f64 {
        self.range(lo, hi).to_radians()
    }
}

/// How carelessly a case is drawn; lengths are fractions of the primitive's size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Style {
    /// σ of the per-point jitter.
    pub(crate) jitter: f64,
    /// Amplitude of the low-frequency wobble.
    pub(crate) wobble: f64,
    /// Largest over- (+) or undershoot (−) at an end of an open stroke.
    pub(crate) overshoot: f64,
    /// Probability that an outline is drawn in two pieces (half of it for box edges).
    pub(crate) gap_chance: f64,
    /// Largest angular miss or overlap of a closed stroke (radians).
    pub(crate) closure: f64,
    /// Largest relative radius drift from the start to the end of a closed stroke.
    pub(crate) drift: f64,
    /// Spacing of the drawn points.
    pub(crate) spacing: f64,
}

impl Style {
    /// A person's hand, with random amounts within the documented ranges.
    pub(crate) fn random(rng: &mut Rng) -> Self {
        Self {
            jitter: rng.range(0.005, 0.01),
            wobble: rng.range(0.003, 0.01),
            overshoot: 0.05,
            gap_chance: 0.3,
            closure: 0.4,
            drift: 0.03,
            spacing: 0.01,
        }
    }

    /// This hand made steadier (`factor` < 1) or shakier (> 1): every error that
    /// places a point (jitter, wobble, over- and undershoots, a closed stroke's miss
    /// and drift) scaled by `factor`; where strokes break (`gap_chance`) and how densely
    /// they are sampled stay. At 0 it draws the ideal curves, split where this hand
    /// splits them.
    pub(crate) fn steadier(self, factor: f64) -> Self {
        Self {
            jitter: self.jitter * factor,
            wobble: self.wobble * factor,
            overshoot: self.overshoot * factor,
            closure: self.closure * factor,
            drift: self.drift * factor,
            ..self
        }
    }

    /// A perfect hand: the ideal curves, for checking the renderer itself.
    pub(crate) fn perfect() -> Self {
        Self {
            jitter: 0.0,
            wobble: 0.0,
            overshoot: 0.0,
            gap_chance: 0.0,
            closure: 0.0,
            drift: 0.0,
            spacing: 0.01,
        }
    }
}

/// One drawn stroke.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SynthStroke {
    /// The points in sketch space (y down).
    pub(crate) points: Vec<DVec2>,
    /// Feature (ellipses and elliptical arcs) or silhouette (outlines, box edges).
    pub(crate) class: StrokeClass,
    /// Which curve of the ground truth it depicts (`"left"`, `"top ellipse"`, …).
    pub(crate) label: String,
}

/// A ground-truth primitive and its drawing.
#[derive(Clone, Debug)]
pub(crate) struct Scene {
    /// The primitive that was drawn.
    pub(crate) truth: Primitive,
    /// The strokes.
    pub(crate) strokes: Vec<SynthStroke>,
    /// The hand it was drawn with.
    pub(crate) style: Style,
}

/// Draws a random primitive of `kind` from a random view; the same seed gives the same
/// scene. `style` overrides the random hand (for example [`Style::perfect`]).
pub(crate) fn scene(kind: PrimitiveKind, seed: u64, style: Option<Style>) -> Scene {
    let mut rng = Rng::new(seed);
    // The random hand is drawn even when `style` overrides it, so that an override
    // changes the hand only, not the shapes and views of the cases.
    let random = Style::random(&mut rng);
    let style = style.unwrap_or(random);
    let size = rng.log_range(50.0, 2000.0);
    let center = DVec3::new(
        rng.range(0.0, 3000.0),
        -rng.range(0.0, 3000.0),
        rng.range(-size, size),
    );
    let (truth, drawing) = match kind {
        PrimitiveKind::Cylinder => cylinder(&mut rng, center, size),
        PrimitiveKind::Cone => cone(&mut rng, center, size),
        PrimitiveKind::Sphere => (
            Primitive::Sphere(Sphere {
                center,
                radius: size / 2.0,
            }),
            Drawing::Plain,
        ),
        PrimitiveKind::Cuboid => cuboid(&mut rng, center, size),
        PrimitiveKind::Sgc => sgc(&mut rng, center, size),
        PrimitiveKind::Bgc => bgc(&mut rng, center, size),
    };
    let mut pen = Pen {
        rng: &mut rng,
        style,
        size: truth.size(),
        thin: thinnest(&truth),
        strokes: Vec::new(),
        record: None,
        hidden: false,
    };
    match (&truth, drawing) {
        (Primitive::Cylinder(c), _) => {
            pen.revolution(c.center, c.axis, c.length, &|_| (c.radius, 0.0));
        }
        (Primitive::Cone(c), _) => {
            let (rb, rt) = (c.radius_bottom, c.radius_top);
            pen.revolution(c.center, c.axis, c.length, &|t| {
                (rb + (rt - rb) * t, rt - rb)
            });
        }
        (Primitive::Sphere(s), _) => pen.sphere(s.center, s.radius),
        (Primitive::Cuboid(b), _) => pen.cuboid(b),
        (Primitive::Sgc(s), Drawing::Profile(profile)) => {
            pen.revolution(s.center, s.axis, s.length, &|t| profile.at(t));
        }
        (Primitive::Bgc(b), Drawing::Arc(arc)) => pen.tube(b, &arc),
        (p, d) => unreachable!("{p:?} is drawn by {d:?}"),
    }
    let strokes = pen.strokes;
    Scene {
        truth,
        strokes,
        style,
    }
}

/// What a kind needs beyond its parameters to be drawn exactly.
#[derive(Clone, Debug)]
enum Drawing {
    /// Nothing beyond the parameters.
    Plain,
    /// The smooth radius profile of an SGC.
    Profile(Profile),
    /// The circular-arc spine of a BGC.
    Arc(Arc),
    /// The C or S spine of a BGC of the wider variety.
    Spine(SpineCurve),
}

/// A smooth SGC profile r(t) = R·(1 + g·(t − ½) + b·sin(π·(f·t + φ))), t from bottom (0)
/// to top (1).
#[derive(Clone, Copy, Debug)]
struct Profile {
    r: f64,
    g: f64,
    b: f64,
    f: f64,
    phi: f64,
}

impl Profile {
    /// The radius and dr/dt at t.
    fn at(&self, t: f64) -> (f64, f64) {
        let angle = PI * (self.f * t + self.phi);
        (
            self.r * (1.0 + self.g * (t - 0.5) + self.b * angle.sin()),
            self.r * (self.g + self.b * PI * self.f * angle.cos()),
        )
    }
}

/// A BGC's spine: a circular arc of length `length` bending by `bend` radians, with
/// radii varying linearly from `r0` to `r1`, rotated by `rotation` and moved so that
/// the mean of its [`PROFILE_SAMPLES`] samples is `center`.
#[derive(Clone, Copy, Debug)]
struct Arc {
    length: f64,
    bend: f64,
    r0: f64,
    r1: f64,
    rotation: DQuat,
    /// Translation applied after the rotation.
    offset: DVec3,
}

impl Arc {
    /// The spine point at u ∈ [0, 1] before the translation, in canonical orientation:
    /// the chord runs along +Y and the arc bulges towards +X.
    fn canonical(&self, u: f64) -> DVec3 {
        let rho = self.length / self.bend;
        let alpha = self.bend * (u - 0.5);
        DVec3::new(
            rho * (alpha.cos() - (self.bend / 2.0).cos()),
            rho * alpha.sin(),
            0.0,
        )
    }

    /// The spine point at u.
    fn point(&self, u: f64) -> DVec3 {
        self.rotation * self.canonical(u) + self.offset
    }

    /// The unit tangent at u (towards increasing u).
    fn tangent(&self, u: f64) -> DVec3 {
        let alpha = self.bend * (u - 0.5);
        self.rotation * DVec3::new(-alpha.sin(), alpha.cos(), 0.0)
    }

    /// The radius at u.
    fn radius(&self, u: f64) -> f64 {
        self.r0 + (self.r1 - self.r0) * u
    }
}

/// The smallest radius drawn, as a fraction of the primitive's size. The hand's wobble
/// (up to 1 % of the size, low frequency, so it does not average out) leaves a radius
/// uncertain by about half a percent of the size; a radius must be about 8 % of the size
/// for the drawing to determine it within the test's 7 %.
pub(crate) const MIN_RADIUS: f64 = 0.08;

/// A unit axis making `elevation` (signed) with the view plane, in-plane direction `psi`.
fn axis_at(elevation: f64, psi: f64) -> DVec3 {
    DVec3::new(
        elevation.cos() * psi.cos(),
        elevation.cos() * psi.sin(),
        elevation.sin(),
    )
}

/// A designer's view of an axis: 5°–65° out of the view plane, either way, any direction.
fn axis_view(rng: &mut Rng) -> DVec3 {
    let elevation = rng.degrees(5.0, 65.0) * rng.sign();
    axis_at(elevation, rng.range(0.0, TAU))
}

/// β = −s·a_z/ρ of the module docs: where a contour sits on a ring of slope `s`.
fn contour_beta(axis: DVec3, slope: f64) -> f64 {
    let rho = axis.truncate().length().max(1e-12);
    -slope * axis.z / rho
}

fn cylinder(rng: &mut Rng, center: DVec3, size: f64) -> (Primitive, Drawing) {
    let radius = size * rng.range(0.1, 0.6);
    let axis = axis_view(rng);
    let p = Primitive::Cylinder(Cylinder {
        center,
        axis,
        length: size,
        radius,
    });
    (p, Drawing::Plain)
}

fn cone(rng: &mut Rng, center: DVec3, size: f64) -> (Primitive, Drawing) {
    loop {
        let mut rb = size * rng.range(0.2, 0.5);
        let mut rt = rng.range(MIN_RADIUS * size, 0.8 * rb);
        if rng.chance(0.3) {
            std::mem::swap(&mut rb, &mut rt);
        }
        let axis = axis_view(rng);
        // Views whose contours are clearly there (|β| ≤ 0.8): a designer does not draw
        // a cone from nearly down its axis.
        if contour_beta(axis, (rt - rb) / size).abs() <= 0.8 {
            let p = Primitive::Cone(Cone {
                center,
                axis,
                length: size,
                radius_bottom: rb,
                radius_top: rt,
            });
            return (p, Drawing::Plain);
        }
    }
}

fn sgc(rng: &mut Rng, center: DVec3, size: f64) -> (Primitive, Drawing) {
    loop {
        let profile = Profile {
            r: size * rng.range(0.2, 0.35),
            g: rng.range(-0.6, 0.6),
            b: rng.range(-0.3, 0.3),
            f: rng.range(0.8, 2.0),
            phi: rng.range(0.0, 1.0),
        };
        let axis = axis_view(rng);
        let ok = (0..=50).all(|i| {
            let (r, dr) = profile.at(f64::from(i) / 50.0);
            r >= MIN_RADIUS * size && contour_beta(axis, dr / size).abs() <= 0.8
        });
        if ok {
            let k = PROFILE_SAMPLES;
            let radii = (0..k)
                .map(|i| profile.at(i as f64 / (k - 1) as f64).0)
                .collect();
            let p = Primitive::Sgc(Sgc {
                center,
                axis,
                length: size,
                radii,
            });
            return (p, Drawing::Profile(profile));
        }
    }
}

fn cuboid(rng: &mut Rng, center: DVec3, size: f64) -> (Primitive, Drawing) {
    loop {
        let pitch = rng.degrees(10.0, 45.0) * rng.sign();
        let yaw = rng.degrees(10.0, 80.0) * rng.sign();
        let roll = rng.range(0.0, TAU);
        let rotation = DQuat::from_rotation_z(roll)
            * DQuat::from_rotation_x(pitch)
            * DQuat::from_rotation_y(yaw);
        let mut extents = DVec3::new(
            rng.range(0.35, 1.0),
            rng.range(0.35, 1.0),
            rng.range(0.35, 1.0),
        );
        extents *= size / extents.max_element();
        let b = Cuboid {
            center,
            rotation,
            size: extents,
        };
        // Three faces in view, and no edge pointing nearly at the viewer (the same 25°
        // as for an axis).
        let max_z = 25f64.to_radians().cos();
        if b.axes().iter().all(|a| (0.15..=max_z).contains(&a.z.abs())) {
            return (Primitive::Cuboid(b), Drawing::Plain);
        }
    }
}

fn bgc(rng: &mut Rng, center: DVec3, size: f64) -> (Primitive, Drawing) {
    loop {
        let length = size;
        let bend = rng.degrees(40.0, 120.0);
        let r = length * rng.range(MIN_RADIUS / 0.85, 0.15);
        let taper = rng.range(-0.3, 0.3);
        let chord = axis_view(rng);
        let rotation =
            DQuat::from_rotation_arc(DVec3::Y, chord) * DQuat::from_rotation_y(rng.range(0.0, TAU));
        let mut arc = Arc {
            length,
            bend,
            r0: r * (1.0 - taper / 2.0),
            r1: r * (1.0 + taper / 2.0),
            rotation,
            offset: DVec3::ZERO,
        };
        let plane_normal = rotation * DVec3::Z;
        let ends_ok = [0.0, 1.0]
            .iter()
            .all(|u| arc.tangent(*u).z.abs() <= 20f64.to_radians().cos());
        if plane_normal.z.abs() < 0.5 || !ends_ok {
            continue;
        }
        let k = PROFILE_SAMPLES;
        let us: Vec<f64> = (0..k).map(|i| i as f64 / (k - 1) as f64).collect();
        let mean = us.iter().map(|u| arc.point(*u)).sum::<DVec3>() / k as f64;
        arc.offset = center - mean;
        let spine = us.iter().map(|u| arc.point(*u)).collect();
        let radii = us.iter().map(|u| arc.radius(*u)).collect();
        let p = Primitive::Bgc(Bgc {
            spine,
            radii,
            plane_normal,
        });
        return (p, Drawing::Arc(arc));
    }
}

/// The view-plane point of the circle (centre m, unit normal n, radius r) at angle θ,
/// with the basis w = (n_y, −nₓ, 0)/ρ, k = n × w of the module docs.
fn circle_point(m: DVec3, n: DVec3, r: f64, theta: f64) -> DVec2 {
    let w = DVec3::new(n.y, -n.x, 0.0)
        .try_normalize()
        .unwrap_or(DVec3::X);
    let k = n.cross(w);
    (m + (w * theta.cos() + k * theta.sin()) * r).truncate()
}

/// The point at arc length `s` along a polyline with cumulative lengths `cum`,
/// extrapolated along the end segments beyond its ends.
fn point_at(points: &[DVec2], cum: &[f64], s: f64) -> DVec2 {
    let n = points.len();
    let total = cum[n - 1];
    if s <= 0.0 {
        let dir = (points[1] - points[0]).normalize_or_zero();
        return points[0] + dir * s;
    }
    if s >= total {
        let dir = (points[n - 1] - points[n - 2]).normalize_or_zero();
        return points[n - 1] + dir * (s - total);
    }
    let i = cum.partition_point(|c| *c <= s).clamp(1, n - 1);
    let seg = cum[i] - cum[i - 1];
    let t = if seg > 0.0 {
        (s - cum[i - 1]) / seg
    } else {
        0.0
    };
    points[i - 1].lerp(points[i], t)
}

fn cumulative(points: &[DVec2]) -> Vec<f64> {
    let mut cum = Vec::with_capacity(points.len());
    let mut s = 0.0;
    cum.push(0.0);
    for w in points.windows(2) {
        s += w[0].distance(w[1]);
        cum.push(s);
    }
    cum
}

/// The hand that draws: it turns ideal view-plane curves into strokes.
struct Pen<'a> {
    rng: &'a mut Rng,
    style: Style,
    size: f64,
    /// The part's thinnest dimension (a tube's or a disc's width, a slab's thickness):
    /// a hand keeps the copies of one line closer together than the lines it means to
    /// tell apart ([`Pen::render`]).
    thin: f64,
    strokes: Vec<SynthStroke>,
    /// When set, the curves are recorded here as ideals instead of being drawn: the
    /// conditioned renderer ([`Pen::render`]) draws them afterwards.
    record: Option<Vec<Ideal>>,
    /// Whether hidden lines are recorded too (only with `record`).
    hidden: bool,
}

impl Pen<'_> {
    /// A random over- (+) or undershoot (−) length.
    fn overshoot(&mut self) -> f64 {
        self.rng.range(-1.0, 1.0) * self.style.overshoot * self.size
    }

    /// The ideal polyline from arc length `s0` to `s1` (beyond its ends along the end
    /// tangents), resampled evenly, wobbled and jittered.
    fn humanize(&mut self, ideal: &[DVec2], s0: f64, s1: f64) -> Vec<DVec2> {
        self.humanize_with(ideal, s0, s1, self.size)
    }

    /// [`Pen::humanize`] with the jitter's σ a fraction of `scale` rather than of the
    /// primitive's size (the conditioned renderer scales it with the curve drawn).
    fn humanize_with(&mut self, ideal: &[DVec2], s0: f64, s1: f64, scale: f64) -> Vec<DVec2> {
        let cum = cumulative(ideal);
        let spacing = self.style.spacing * self.size;
        let n = (((s1 - s0) / spacing).ceil() as usize).max(12) + 1;
        let base: Vec<DVec2> = (0..n)
            .map(|i| point_at(ideal, &cum, s0 + (s1 - s0) * i as f64 / (n - 1) as f64))
            .collect();
        // Low-frequency wobble along the normal, zero-mean over the stroke.
        // A hand's drift grows with the movement (motor variability is proportional to
        // its amplitude): a small end ellipse wobbles less than a long outline.
        let (lo, hi) = base.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let extent = (hi - lo).max_element().min(self.size);
        let amplitude = self.style.wobble * extent;
        let waves: Vec<(f64, f64, f64)> = (0..2)
            .map(|_| {
                (
                    self.rng.range(0.5, 2.5),
                    self.rng.range(0.0, TAU),
                    self.rng.range(0.3, 1.0),
                )
            })
            .collect();
        let norm: f64 = waves.iter().map(|w| w.2).sum();
        let offsets: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / (n - 1) as f64;
                waves
                    .iter()
                    .map(|(f, phase, c)| c * (TAU * f * t + phase).sin())
                    .sum::<f64>()
                    * amplitude
                    / norm
            })
            .collect();
        let mean = offsets.iter().sum::<f64>() / n as f64;
        let sigma = self.style.jitter * scale;
        (0..n)
            .map(|i| {
                let (lo, hi) = (i.saturating_sub(1), (i + 1).min(n - 1));
                let normal = (base[hi] - base[lo]).perp().normalize_or_zero();
                let jitter = DVec2::new(self.rng.normal(), self.rng.normal()) * sigma;
                base[i] + normal * (offsets[i] - mean) + jitter
            })
            .collect()
    }

    /// Emits a stroke (view-plane points), in a random drawing direction.
    fn emit(&mut self, mut points: Vec<DVec2>, class: StrokeClass, label: String) {
        if self.rng.chance(0.5) {
            points.reverse();
        }
        let points = points.into_iter().map(sketch_from_view).collect();
        self.strokes.push(SynthStroke {
            points,
            class,
            label,
        });
    }

    /// An open curve with over- or undershoots at both ends, sometimes in two pieces
    /// (with probability `gap_chance` × `gap_factor`).
    fn open(&mut self, ideal: &[DVec2], class: StrokeClass, label: &str, gap_factor: f64) {
        if let Some(record) = &mut self.record {
            record.push(Ideal {
                points: ideal.to_vec(),
                closed: false,
                class,
                label: label.to_owned(),
                gap_factor,
                pivot: None,
            });
            return;
        }
        let total = *cumulative(ideal).last().unwrap_or(&0.0);
        let limit = 0.3 * total;
        let s0 = -self.overshoot().clamp(-limit, limit);
        let s1 = total + self.overshoot().clamp(-limit, limit);
        let points = self.humanize(ideal, s0, s1);
        if self.rng.chance(self.style.gap_chance * gap_factor) {
            let n = points.len();
            let at = self.rng.range(0.3, 0.7);
            let gap = self.rng.range(0.02, 0.06);
            let keep = |i: usize, before: bool| {
                let t = i as f64 / (n - 1) as f64;
                if before {
                    t < at - gap / 2.0
                } else {
                    t > at + gap / 2.0
                }
            };
            let first: Vec<DVec2> = (0..n)
                .filter(|i| keep(*i, true))
                .map(|i| points[i])
                .collect();
            let second: Vec<DVec2> = (0..n)
                .filter(|i| keep(*i, false))
                .map(|i| points[i])
                .collect();
            self.emit(first, class, format!("{label} (1/2)"));
            self.emit(second, class, format!("{label} (2/2)"));
        } else {
            self.emit(points, class, label.to_owned());
        }
    }

    /// A closed curve `f(θ)` drawn from a random start over 2π ± the closure error, its
    /// radius drifting (`f` takes θ and a radius factor).
    fn closed(
        &mut self,
        f: &dyn Fn(f64, f64) -> DVec2,
        theta0: f64,
        sweep: f64,
        class: StrokeClass,
        label: String,
    ) {
        let drift = self.rng.range(-1.0, 1.0) * self.style.drift;
        let dense: Vec<DVec2> = (0..=720)
            .map(|i| {
                let t = f64::from(i) / 720.0;
                f(theta0 + sweep * t, 1.0 + drift * t)
            })
            .collect();
        if let Some(record) = &mut self.record {
            record.push(Ideal {
                points: dense,
                closed: true,
                class,
                label,
                gap_factor: 0.0,
                pivot: None,
            });
            return;
        }
        let total = *cumulative(&dense).last().unwrap_or(&0.0);
        let points = self.humanize(&dense, 0.0, total);
        self.emit(points, class, label);
    }

    /// One end circle (centre m, outward normal n, radius r) of a surface of revolution
    /// with axis `axis` (bottom to top) and slope `slope` at that end: whole when it faces
    /// the viewer, else its visible front arc (module docs).
    fn end(&mut self, m: DVec3, n: DVec3, axis: DVec3, r: f64, slope: f64, name: &str) {
        let recorded = self.record.as_ref().map_or(0, Vec::len);
        self.end_curves(m, n, axis, r, slope, name);
        if let Some(record) = &mut self.record {
            for ideal in &mut record[recorded..] {
                ideal.pivot = Some(m.truncate());
            }
        }
    }

    /// The curves of [`Pen::end`].
    fn end_curves(&mut self, m: DVec3, n: DVec3, axis: DVec3, r: f64, slope: f64, name: &str) {
        if n.z > 0.0 {
            let theta0 = self.rng.range(0.0, TAU);
            let sweep = TAU + self.rng.range(-1.0, 1.0) * self.style.closure;
            self.closed(
                &|theta, factor| circle_point(m, n, r * factor, theta),
                theta0,
                sweep,
                StrokeClass::Feature,
                format!("{name} ellipse"),
            );
        } else {
            let beta = contour_beta(axis, slope).clamp(-1.0, 1.0);
            let (start, end) = (PI - beta.asin(), TAU + beta.asin());
            let dense: Vec<DVec2> = (0..=360)
                .map(|i| circle_point(m, n, r, start + (end - start) * f64::from(i) / 360.0))
                .collect();
            self.open(&dense, StrokeClass::Feature, &format!("{name} arc"), 0.0);
            if self.hidden {
                // The rest of the rim, behind the solid: θ ∈ (asin β, π − asin β).
                let (start, end) = (beta.asin(), PI - beta.asin());
                let dense: Vec<DVec2> = (0..=360)
                    .map(|i| circle_point(m, n, r, start + (end - start) * f64::from(i) / 360.0))
                    .collect();
                self.open(
                    &dense,
                    StrokeClass::Feature,
                    &format!("hidden {name} arc"),
                    0.0,
                );
            }
        }
    }

    /// A cylinder, cone or SGC: centre c, unit axis a, length l and profile t ↦ (r, dr/dt).
    fn revolution(&mut self, c: DVec3, a: DVec3, l: f64, profile: &dyn Fn(f64) -> (f64, f64)) {
        let w = DVec3::new(a.y, -a.x, 0.0).normalize();
        let k = a.cross(w);
        for (side, name) in [(1.0, "right"), (-1.0, "left")] {
            let dense: Vec<DVec2> = (0..=200)
                .map(|i| {
                    let t = f64::from(i) / 200.0;
                    let (r, dr) = profile(t);
                    let beta = contour_beta(a, dr / l);
                    let alpha = (1.0 - beta * beta).max(0.0).sqrt();
                    let e = w * (side * alpha) + k * beta;
                    (c + a * (l * (t - 0.5)) + e * r).truncate()
                })
                .collect();
            self.open(&dense, StrokeClass::Silhouette, name, 1.0);
        }
        let (r0, dr0) = profile(0.0);
        let (r1, dr1) = profile(1.0);
        self.end(c - a * (l / 2.0), -a, a, r0, dr0 / l, "bottom");
        self.end(c + a * (l / 2.0), a, a, r1, dr1 / l, "top");
    }

    /// A sphere's outline circle, in one stroke or two.
    fn sphere(&mut self, c: DVec3, r: f64) {
        let center = c.truncate();
        let circle =
            move |theta: f64, factor: f64| center + DVec2::from_angle(theta) * (r * factor);
        let theta0 = self.rng.range(0.0, TAU);
        let err = self.style.closure;
        if self.rng.chance(0.5) {
            let sweep = TAU + self.rng.range(-1.0, 1.0) * err;
            self.closed(
                &circle,
                theta0,
                sweep,
                StrokeClass::Silhouette,
                "outline".to_owned(),
            );
        } else {
            let split = theta0 + PI + self.rng.range(-0.3, 0.3);
            let first = split - theta0 + self.rng.range(-0.5, 0.5) * err;
            let second_start = split + self.rng.range(-0.5, 0.5) * err;
            let second = theta0 + TAU - second_start + self.rng.range(-0.5, 0.5) * err;
            self.closed(
                &circle,
                theta0,
                first,
                StrokeClass::Silhouette,
                "outline (1/2)".to_owned(),
            );
            self.closed(
                &circle,
                second_start,
                second,
                StrokeClass::Silhouette,
                "outline (2/2)".to_owned(),
            );
        }
    }

    /// A box's visible edges: those with an adjacent face whose outward normal has z > 0.
    fn cuboid(&mut self, b: &Cuboid) {
        let axes = b.axes();
        let half = b.size * 0.5;
        for along in 0..3 {
            let (i, j) = ((along + 1) % 3, (along + 2) % 3);
            for (si, sj) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let visible = axes[i].z * si > 0.0 || axes[j].z * sj > 0.0;
                if !visible && !self.hidden {
                    continue;
                }
                let mid = b.center + axes[i] * (half[i] * si) + axes[j] * (half[j] * sj);
                let d = axes[along] * half[along];
                let ideal = [(mid - d).truncate(), (mid + d).truncate()];
                let hidden = if visible { "" } else { "hidden " };
                let label = format!("{hidden}edge ∥{} ({si:+},{sj:+})", ["x", "y", "z"][along]);
                self.open(&ideal, StrokeClass::Silhouette, &label, 0.5);
            }
        }
    }

    /// A bent tube: the projected spine offset by ± the radius along its 2D normal, and
    /// the end circles.
    fn tube(&mut self, b: &Bgc, arc: &Arc) {
        for (side, name) in [(1.0, "left"), (-1.0, "right")] {
            let dense: Vec<DVec2> = (0..=200)
                .map(|i| {
                    let u = f64::from(i) / 200.0;
                    let t = arc.tangent(u).truncate();
                    let nu = DVec2::new(-t.y, t.x).normalize();
                    arc.point(u).truncate() + nu * (side * arc.radius(u))
                })
                .collect();
            self.open(&dense, StrokeClass::Silhouette, name, 1.0);
        }
        let slope = (arc.r1 - arc.r0) / arc.length;
        let k = b.spine.len();
        let (t0, t1) = (arc.tangent(0.0), arc.tangent(1.0));
        self.end(arc.point(0.0), -t0, t0, b.radii[0], slope, "bottom");
        self.end(arc.point(1.0), t1, t1, b.radii[k - 1], slope, "top");
    }
}

/// Draws a given cylinder, cone, sphere or box with `style` (an assembly's parts, placed
/// by the caller in one view), as [`scene`] draws its random primitives. SGCs and BGCs
/// need the smooth profile or spine they were made from and are not drawn here.
pub(crate) fn draw(truth: &Primitive, style: Style, rng: &mut Rng) -> Vec<SynthStroke> {
    let mut pen = Pen {
        rng,
        style,
        size: truth.size(),
        thin: thinnest(truth),
        strokes: Vec::new(),
        record: None,
        hidden: false,
    };
    match truth {
        Primitive::Cylinder(c) => {
            pen.revolution(c.center, c.axis, c.length, &|_| (c.radius, 0.0));
        }
        Primitive::Cone(c) => {
            let (rb, rt) = (c.radius_bottom, c.radius_top);
            pen.revolution(c.center, c.axis, c.length, &|t| {
                (rb + (rt - rb) * t, rt - rb)
            });
        }
        Primitive::Sphere(s) => pen.sphere(s.center, s.radius),
        Primitive::Cuboid(b) => pen.cuboid(b),
        Primitive::Sgc(_) | Primitive::Bgc(_) => {
            panic!("draw() takes cylinders, cones, spheres and boxes")
        }
    }
    pen.strokes
}

/// A drawing condition of [`scene_with`] and [`draw_with`] (module docs, "Conditions").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum Condition {
    /// The wider shapes from a designer's view, drawn with the usual hand.
    Plain,
    /// Views nearly along the axis (65°–80° out of the view plane).
    NearAxial,
    /// Views from the side (the axis 0.5°–5° out of the view plane).
    SideOn,
    /// 20–60 % of one silhouette left out.
    Missing,
    /// Large over- and undershoots and gaps.
    Overshoots,
    /// Lines drawn as 2–3 overlapping strokes.
    Sketchy,
    /// Strokes joined across corners: U (outline, end arc, outline) and L (two box edges).
    Joined,
    /// Lines drawn in several short pieces.
    Fragments,
    /// End ellipses drawn turned 2°–20° about their centres, as a hand slants them.
    Slanted,
    /// Every line drawn as 2–3 strokes 1.5–8 % of its extent apart: a quick, rough hand.
    Rough,
}

impl Condition {
    /// Every condition.
    pub(crate) const ALL: [Self; 10] = [
        Self::Plain,
        Self::NearAxial,
        Self::SideOn,
        Self::Missing,
        Self::Overshoots,
        Self::Sketchy,
        Self::Joined,
        Self::Fragments,
        Self::Slanted,
        Self::Rough,
    ];

    /// A short name.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Plain => "plain",
            Self::NearAxial => "near-axial",
            Self::SideOn => "side-on",
            Self::Missing => "missing",
            Self::Overshoots => "overshoots",
            Self::Sketchy => "sketchy",
            Self::Joined => "joined",
            Self::Fragments => "fragments",
            Self::Slanted => "slanted",
            Self::Rough => "rough",
        }
    }

    /// The condition named `name` ([`Condition::name`]).
    pub(crate) fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }

    /// The range of views the condition draws from.
    pub(crate) fn view(self) -> ViewRange {
        match self {
            Self::NearAxial => ViewRange::NearAxial,
            Self::SideOn => ViewRange::SideOn,
            _ => ViewRange::Designer,
        }
    }
}

/// Which views a conditioned scene is drawn from (module docs, "Conditions").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ViewRange {
    /// A designer's view, as [`scene`] draws.
    Designer,
    /// Looking nearly along the axis.
    NearAxial,
    /// Looking at the side, the axis nearly in the view plane.
    SideOn,
}

/// An ideal curve recorded by the conditioned renderer before it is drawn.
#[derive(Clone, Debug)]
struct Ideal {
    /// The view-plane polyline (dense).
    points: Vec<DVec2>,
    /// Whether it is a closed curve (its sweep and drift already include the hand's
    /// closure error).
    closed: bool,
    /// The class it is drawn as.
    class: StrokeClass,
    /// The curve it depicts.
    label: String,
    /// Scales the chance of a gap, as in [`Pen::open`].
    gap_factor: f64,
    /// The image centre of the end circle it draws, when it draws one (turned about it
    /// under [`Condition::Slanted`]).
    pivot: Option<DVec2>,
}

impl Ideal {
    fn hidden(&self) -> bool {
        self.label.starts_with("hidden")
    }
}

/// The share of a line's later copies that go over a stretch of it only.
const PARTIAL_COPIES: f64 = 0.5;

/// How one stroke of an ideal is drawn: under which condition, shifted by how much (a
/// copy of a line gone over again), over which stretch of it (fractions of its length).
#[derive(Clone, Copy)]
struct Hand {
    condition: Condition,
    shift: DVec2,
    stretch: (f64, f64),
}

/// A unit axis `elevation_deg` (a range, either sign) out of the view plane, any
/// in-plane direction.
fn axis_in(rng: &mut Rng, view: ViewRange) -> DVec3 {
    let (lo, hi) = match view {
        ViewRange::Designer => (5.0, 65.0),
        ViewRange::NearAxial => (65.0, 80.0),
        ViewRange::SideOn => (0.5, 5.0),
    };
    let elevation = rng.degrees(lo, hi) * rng.sign();
    axis_at(elevation, rng.range(0.0, TAU))
}

/// A uniformly random rotation (a normalised 4D Gaussian).
pub(crate) fn random_rotation(rng: &mut Rng) -> DQuat {
    loop {
        let q = DQuat::from_xyzw(rng.normal(), rng.normal(), rng.normal(), rng.normal());
        if q.length() > 1e-3 {
            return q.normalize();
        }
    }
}

/// A length over radius ratio: a quarter thin discs (0.1–0.25), a quarter rods (8–20),
/// the rest log-uniform in between.
fn aspect(rng: &mut Rng) -> f64 {
    let u = rng.unit();
    if u < 0.25 {
        rng.log_range(0.1, 0.25)
    } else if u < 0.5 {
        rng.log_range(8.0, 20.0)
    } else {
        rng.log_range(0.25, 8.0)
    }
}

fn wide_cylinder(rng: &mut Rng, center: DVec3, size: f64, view: ViewRange) -> Primitive {
    let a = aspect(rng);
    let (length, radius) = if a >= 2.0 {
        (size, size / a)
    } else {
        (a * size / 2.0, size / 2.0)
    };
    Primitive::Cylinder(Cylinder {
        center,
        axis: axis_in(rng, view),
        length,
        radius,
    })
}

fn wide_cone(rng: &mut Rng, center: DVec3, size: f64, view: ViewRange) -> Primitive {
    loop {
        let a = rng.log_range(0.3, 12.0);
        let (length, mut rb) = if a >= 2.0 {
            (size, size / a)
        } else {
            (a * size / 2.0, size / 2.0)
        };
        let mut rt = rb * rng.range(0.25, 0.8);
        if rng.chance(0.3) {
            std::mem::swap(&mut rb, &mut rt);
        }
        let axis = axis_in(rng, view);
        if contour_beta(axis, (rt - rb) / length).abs() <= 0.8 {
            return Primitive::Cone(Cone {
                center,
                axis,
                length,
                radius_bottom: rb,
                radius_top: rt,
            });
        }
    }
}

fn wide_sgc(rng: &mut Rng, center: DVec3, size: f64, view: ViewRange) -> (Primitive, Profile) {
    loop {
        // Built for length 1, then scaled so that its largest extent is `size`.
        let mean = 1.0 / rng.log_range(0.6, 8.0);
        let profile = Profile {
            r: mean,
            g: rng.range(-0.6, 0.6),
            b: rng.range(-0.3, 0.3),
            f: rng.range(0.8, 2.0),
            phi: rng.range(0.0, 1.0),
        };
        let axis = axis_in(rng, view);
        let ok = (0..=50).all(|i| {
            let (r, dr) = profile.at(f64::from(i) / 50.0);
            r >= 0.35 * mean && contour_beta(axis, dr).abs() <= 0.8
        });
        if !ok {
            continue;
        }
        let widest = (0..=50)
            .map(|i| profile.at(f64::from(i) / 50.0).0)
            .fold(0.0, f64::max);
        let scale = size / (2.0 * widest).max(1.0);
        let profile = Profile {
            r: profile.r * scale,
            ..profile
        };
        let k = PROFILE_SAMPLES;
        let radii = (0..k)
            .map(|i| profile.at(i as f64 / (k - 1) as f64).0)
            .collect();
        let p = Primitive::Sgc(Sgc {
            center,
            axis,
            length: scale,
            radii,
        });
        return (p, profile);
    }
}

fn wide_cuboid(rng: &mut Rng, center: DVec3, size: f64, view: ViewRange) -> Primitive {
    let u = rng.unit();
    let mut sides = if u < 0.3 {
        [1.0, rng.range(0.6, 1.0), rng.range(0.6, 1.0)]
    } else if u < 0.65 {
        [1.0, rng.log_range(1.0 / 15.0, 0.25), rng.range(0.4, 1.0)]
    } else {
        [
            1.0,
            rng.log_range(1.0 / 15.0, 1.0 / 3.0),
            rng.log_range(1.0 / 15.0, 1.0 / 3.0),
        ]
    };
    // Which box axis gets which side.
    let shift = (rng.next_u64() % 3) as usize;
    sides.rotate_left(shift);
    let extents = DVec3::from_array(sides) * size;
    let max_z = 25f64.to_radians().cos();
    loop {
        let rotation = match view {
            ViewRange::Designer => {
                let pitch = rng.degrees(10.0, 45.0) * rng.sign();
                let yaw = rng.degrees(10.0, 80.0) * rng.sign();
                let roll = rng.range(0.0, TAU);
                DQuat::from_rotation_z(roll)
                    * DQuat::from_rotation_x(pitch)
                    * DQuat::from_rotation_y(yaw)
            }
            _ => random_rotation(rng),
        };
        let b = Cuboid {
            center,
            rotation,
            size: extents,
        };
        let z = b.axes().map(|a| a.z.abs());
        let (lo, hi) = (
            z.iter().copied().fold(1.0, f64::min),
            z.iter().copied().fold(0.0, f64::max),
        );
        let ok = match view {
            ViewRange::Designer => lo >= 0.15 && hi <= max_z,
            ViewRange::NearAxial => (max_z..=10f64.to_radians().cos()).contains(&hi),
            ViewRange::SideOn => (0.05..=0.15).contains(&lo) && hi <= max_z,
        };
        if ok {
            return Primitive::Cuboid(b);
        }
    }
}

/// A BGC's planar spine of any shape (module docs, "Conditions"), parameterised by arc
/// length: u ∈ [0, 1] runs at speed `length`.
#[derive(Clone, Copy, Debug)]
struct SpineCurve {
    length: f64,
    /// An S (two bends of opposite sense) rather than a C (one circular arc).
    s_shape: bool,
    /// The C's total bend, or each half's bend of the S (radians).
    bend: f64,
    /// The tangent angle that turns the chord onto +Y.
    chord_angle: f64,
    /// The mean radius, its linear taper (r·(1 − taper/2 + taper·u)) and its flare
    /// (× (1 + flare·u³)).
    r: f64,
    taper: f64,
    flare: f64,
    rotation: DQuat,
    offset: DVec3,
}

impl SpineCurve {
    /// The tangent angle at u in the canonical plane (0 is +Y, positive towards −X).
    fn theta(&self, u: f64) -> f64 {
        let raw = if self.s_shape {
            4.0 * self.bend * u * (1.0 - u)
        } else {
            self.bend * (u - 0.5)
        };
        raw - self.chord_angle
    }

    /// The canonical (unrotated) point at u, by Simpson's rule over the tangent.
    fn canonical(&self, u: f64) -> DVec3 {
        let steps = 64;
        let h = u / f64::from(steps);
        let t = |v: f64| {
            let a = self.theta(v);
            DVec3::new(-a.sin(), a.cos(), 0.0)
        };
        let mut sum = t(0.0) + t(u);
        for i in 1..steps {
            let w = if i % 2 == 1 { 4.0 } else { 2.0 };
            sum += t(h * f64::from(i)) * w;
        }
        sum * (h / 3.0 * self.length)
    }

    fn point(&self, u: f64) -> DVec3 {
        self.rotation * self.canonical(u) + self.offset
    }

    fn tangent(&self, u: f64) -> DVec3 {
        let a = self.theta(u);
        self.rotation * DVec3::new(-a.sin(), a.cos(), 0.0)
    }

    fn radius(&self, u: f64) -> f64 {
        self.r * (1.0 - self.taper / 2.0 + self.taper * u) * (1.0 + self.flare * u.powi(3))
    }

    /// dr/ds (per unit of arc length) at u.
    fn slope(&self, u: f64) -> f64 {
        let lin = 1.0 - self.taper / 2.0 + self.taper * u;
        let fl = 1.0 + self.flare * u.powi(3);
        self.r * (self.taper * fl + lin * 3.0 * self.flare * u.powi(2)) / self.length
    }
}

fn wide_bgc(rng: &mut Rng, center: DVec3, size: f64, view: ViewRange) -> (Primitive, SpineCurve) {
    loop {
        let s_shape = rng.chance(0.5);
        let bend = if s_shape {
            rng.degrees(40.0, 90.0)
        } else {
            rng.degrees(40.0, 150.0)
        };
        let mut spine = SpineCurve {
            length: size,
            s_shape,
            bend,
            chord_angle: 0.0,
            r: size * rng.range(MIN_RADIUS / 0.85, 0.15),
            taper: rng.range(-0.3, 0.3),
            flare: if rng.chance(0.5) {
                rng.range(0.3, 0.8)
            } else {
                0.0
            },
            rotation: random_rotation(rng),
            offset: DVec3::ZERO,
        };
        let chord = spine.canonical(1.0);
        spine.chord_angle = (-chord.x).atan2(chord.y);
        let normal = spine.rotation * DVec3::Z;
        let ends = [spine.tangent(0.0).z.abs(), spine.tangent(1.0).z.abs()];
        let steepest = ends[0].max(ends[1]);
        let ok = match view {
            ViewRange::Designer => normal.z.abs() >= 0.5 && steepest <= 20f64.to_radians().cos(),
            ViewRange::NearAxial => {
                normal.z.abs() >= 0.25
                    && (30f64.to_radians().cos()..=12f64.to_radians().cos()).contains(&steepest)
            }
            ViewRange::SideOn => normal.z.abs() >= 0.97,
        };
        if !ok {
            continue;
        }
        let k = PROFILE_SAMPLES;
        let us: Vec<f64> = (0..k).map(|i| i as f64 / (k - 1) as f64).collect();
        let mean = us.iter().map(|u| spine.point(*u)).sum::<DVec3>() / k as f64;
        spine.offset = center - mean;
        let p = Primitive::Bgc(Bgc {
            spine: us.iter().map(|u| spine.point(*u)).collect(),
            radii: us.iter().map(|u| spine.radius(*u)).collect(),
            plane_normal: normal,
        });
        return (p, spine);
    }
}

/// Draws a random primitive of `kind` of the wider variety under `condition`, with hidden
/// lines when `hidden_lines` (module docs, "Conditions"); the same arguments give the
/// same scene. `style` overrides the random hand, as for [`scene`].
pub(crate) fn scene_with(
    kind: PrimitiveKind,
    seed: u64,
    condition: Condition,
    hidden_lines: bool,
    style: Option<Style>,
) -> Scene {
    scene_with_hand(kind, seed, condition, hidden_lines, style, 1.0)
}

/// [`scene_with`] with the random hand's errors scaled by `hand` ([`Style::steadier`]):
/// the same shape, view and condition, drawn by a steadier or shakier hand.
pub(crate) fn scene_with_hand(
    kind: PrimitiveKind,
    seed: u64,
    condition: Condition,
    hidden_lines: bool,
    style: Option<Style>,
    hand: f64,
) -> Scene {
    let mut rng = Rng::new(seed);
    let random = Style::random(&mut rng).steadier(hand);
    let style = style.unwrap_or(random);
    let size = rng.log_range(50.0, 2000.0);
    let center = DVec3::new(
        rng.range(0.0, 3000.0),
        -rng.range(0.0, 3000.0),
        rng.range(-size, size),
    );
    let view = condition.view();
    let (truth, drawing) = match kind {
        PrimitiveKind::Cylinder => (wide_cylinder(&mut rng, center, size, view), Drawing::Plain),
        PrimitiveKind::Cone => (wide_cone(&mut rng, center, size, view), Drawing::Plain),
        PrimitiveKind::Sphere => (
            Primitive::Sphere(Sphere {
                center,
                radius: size / 2.0,
            }),
            Drawing::Plain,
        ),
        PrimitiveKind::Cuboid => (wide_cuboid(&mut rng, center, size, view), Drawing::Plain),
        PrimitiveKind::Sgc => {
            let (p, profile) = wide_sgc(&mut rng, center, size, view);
            (p, Drawing::Profile(profile))
        }
        PrimitiveKind::Bgc => {
            let (p, spine) = wide_bgc(&mut rng, center, size, view);
            (p, Drawing::Spine(spine))
        }
    };
    let strokes = conditioned(&truth, &drawing, style, &mut rng, condition, hidden_lines);
    Scene {
        truth,
        strokes,
        style,
    }
}

/// A bent tube that ends at a post drawn across it (as a candlestick's arms meet its
/// stem): a random tube of the wider variety from a designer's view, drawn plainly, whose
/// outlines run on past its bottom end across a post (two parallel outlines through that
/// end, across the tube there, as wide as the tube), and whose bottom end ellipse the post
/// hides. The truth is the tube alone; the same seed gives the same scene.
pub(crate) fn bgc_across_post(seed: u64) -> Scene {
    let mut scene = scene_with(PrimitiveKind::Bgc, seed, Condition::Plain, false, None);
    let Primitive::Bgc(b) = &scene.truth else {
        unreachable!("scene_with draws the kind asked for");
    };
    let sketch = |v: DVec2| sketch_from_view(v);
    let end = b.spine[0].truncate();
    let along = (b.spine[0].truncate() - b.spine[1].truncate()).normalize();
    let across = along.perp();
    let r = b.radii[0];
    scene.strokes.retain(|s| !s.label.contains("bottom"));
    // The outlines run on past the end, to the post's far side.
    for stroke in &mut scene.strokes {
        if stroke.class != StrokeClass::Silhouette || stroke.points.len() < 2 {
            continue;
        }
        let first = view_point(stroke.points[0]);
        let last = view_point(stroke.points[stroke.points.len() - 1]);
        let near_first = first.distance(end) <= 1.5 * r;
        let near_last = last.distance(end) <= 1.5 * r;
        if !(near_first || near_last) {
            continue;
        }
        let from = if near_last { last } else { first };
        let run: Vec<DVec2> = (1..=10)
            .map(|i| sketch(from + along * (2.0 * r * f64::from(i) / 10.0)))
            .collect();
        if near_last {
            stroke.points.extend(run);
        } else {
            let mut points: Vec<DVec2> = run.into_iter().rev().collect();
            points.append(&mut stroke.points);
            stroke.points = points;
        }
    }
    // The post: two outlines across the tube's end, a little over three tube lengths long.
    let reach = 1.6 * b.spine_length();
    for (side, label) in [(1.0, "post left"), (-1.0, "post right")] {
        let points = (0..=40)
            .map(|i| {
                let s = reach * (f64::from(i) / 20.0 - 1.0);
                sketch(end + along * (side * r) + across * s)
            })
            .collect();
        scene.strokes.push(SynthStroke {
            points,
            class: StrokeClass::Silhouette,
            label: label.to_owned(),
        });
    }
    scene
}

/// The view-plane point of a sketch point.
fn view_point(p: DVec2) -> DVec2 {
    DVec2::new(p.x, -p.y)
}

/// Draws a given cylinder, cone, sphere or box under `condition`, with hidden lines when
/// `hidden_lines` (an assembly's parts), as [`scene_with`] draws its primitives.
pub(crate) fn draw_with(
    truth: &Primitive,
    style: Style,
    rng: &mut Rng,
    condition: Condition,
    hidden_lines: bool,
) -> Vec<SynthStroke> {
    assert!(
        !matches!(truth, Primitive::Sgc(_) | Primitive::Bgc(_)),
        "draw_with() takes cylinders, cones, spheres and boxes"
    );
    conditioned(truth, &Drawing::Plain, style, rng, condition, hidden_lines)
}

/// Records the curves of `truth` and draws them under `condition`.
fn conditioned(
    truth: &Primitive,
    drawing: &Drawing,
    style: Style,
    rng: &mut Rng,
    condition: Condition,
    hidden_lines: bool,
) -> Vec<SynthStroke> {
    let mut pen = Pen {
        rng,
        style,
        size: truth.size(),
        thin: thinnest(truth),
        strokes: Vec::new(),
        record: Some(Vec::new()),
        hidden: hidden_lines,
    };
    match (truth, drawing) {
        (Primitive::Cylinder(c), _) => {
            pen.revolution(c.center, c.axis, c.length, &|_| (c.radius, 0.0));
        }
        (Primitive::Cone(c), _) => {
            let (rb, rt) = (c.radius_bottom, c.radius_top);
            pen.revolution(c.center, c.axis, c.length, &|t| {
                (rb + (rt - rb) * t, rt - rb)
            });
        }
        (Primitive::Sphere(s), _) => pen.sphere(s.center, s.radius),
        (Primitive::Cuboid(b), _) => pen.cuboid(b),
        (Primitive::Sgc(s), Drawing::Profile(profile)) => {
            pen.revolution(s.center, s.axis, s.length, &|t| profile.at(t));
        }
        (Primitive::Bgc(_), Drawing::Spine(spine)) => pen.spine_tube(spine),
        (p, d) => unreachable!("{p:?} is drawn by {d:?}"),
    }
    pen.render(condition);
    pen.strokes
}

/// The thinnest dimension of `truth`: a sphere's diameter, the smaller of a solid of
/// revolution's length and widest diameter, a box's smallest side, a bent tube's
/// narrowest diameter.
fn thinnest(truth: &Primitive) -> f64 {
    match truth {
        Primitive::Cylinder(c) => c.length.min(2.0 * c.radius),
        Primitive::Cone(c) => c.length.min(2.0 * c.radius_bottom.max(c.radius_top)),
        Primitive::Sphere(s) => 2.0 * s.radius,
        Primitive::Cuboid(b) => b.size.min_element(),
        Primitive::Sgc(s) => s
            .length
            .min(2.0 * s.radii.iter().copied().fold(0.0, f64::max)),
        Primitive::Bgc(b) => 2.0 * b.radii.iter().copied().fold(f64::INFINITY, f64::min),
    }
}

/// The largest extent of a polyline's bounding box.
fn extent(points: &[DVec2]) -> f64 {
    let (lo, hi) = points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    (hi - lo).max_element().max(0.0)
}

/// `a` then `b`, with `a` turned so that it ends at the end of `b` it is nearest to and
/// `b` turned to start there.
fn chain(a: &[DVec2], b: &[DVec2]) -> Vec<DVec2> {
    let (Some(a0), Some(a1), Some(b0), Some(b1)) = (a.first(), a.last(), b.first(), b.last())
    else {
        return a.iter().chain(b).copied().collect();
    };
    // The pairing of ends that are nearest: (a's end at the joint, b's end at the joint).
    let pairs = [(a1, b0), (a1, b1), (a0, b0), (a0, b1)];
    let best = (0..4)
        .min_by(|i, j| {
            let d = |k: usize| pairs[k].0.distance(*pairs[k].1);
            d(*i).total_cmp(&d(*j))
        })
        .unwrap_or(0);
    let mut first = a.to_vec();
    let mut second = b.to_vec();
    if best >= 2 {
        first.reverse();
    }
    if best % 2 == 1 {
        second.reverse();
    }
    first.extend(second);
    first
}

impl Pen<'_> {
    /// A bent tube along any spine: the outlines and the end circles as [`Pen::tube`]
    /// draws them.
    fn spine_tube(&mut self, spine: &SpineCurve) {
        for (side, name) in [(1.0, "left"), (-1.0, "right")] {
            let dense: Vec<DVec2> = (0..=200)
                .map(|i| {
                    let u = f64::from(i) / 200.0;
                    let t = spine.tangent(u).truncate();
                    let nu = DVec2::new(-t.y, t.x).normalize_or_zero();
                    spine.point(u).truncate() + nu * (side * spine.radius(u))
                })
                .collect();
            self.open(&dense, StrokeClass::Silhouette, name, 1.0);
        }
        let (t0, t1) = (spine.tangent(0.0), spine.tangent(1.0));
        let (r0, r1) = (spine.radius(0.0), spine.radius(1.0));
        self.end(spine.point(0.0), -t0, t0, r0, spine.slope(0.0), "bottom");
        self.end(spine.point(1.0), t1, t1, r1, spine.slope(1.0), "top");
    }

    /// Draws the recorded ideals under `condition` (module docs, "Conditions").
    fn render(&mut self, condition: Condition) {
        let mut ideals = self.record.take().unwrap_or_default();
        if condition == Condition::Slanted {
            self.slant(&mut ideals);
        }
        if condition == Condition::Joined {
            ideals = self.join(ideals);
        }
        let missing = if condition == Condition::Missing {
            let candidates: Vec<usize> = (0..ideals.len())
                .filter(|i| ideals[*i].class == StrokeClass::Silhouette && !ideals[*i].hidden())
                .collect();
            let pick = (self.rng.next_u64() % candidates.len().max(1) as u64) as usize;
            candidates.get(pick).copied()
        } else {
            None
        };
        for (i, ideal) in ideals.iter().enumerate() {
            let scale = extent(&ideal.points).min(self.size);
            if missing == Some(i) {
                self.draw_missing(ideal, scale);
                continue;
            }
            let copies = match condition {
                Condition::Sketchy if self.rng.chance(0.8) => {
                    2 + (self.rng.next_u64() % 2) as usize
                }
                Condition::Rough => 2 + (self.rng.next_u64() % 2) as usize,
                _ => 1,
            };
            let apart = if condition == Condition::Rough {
                (0.015, 0.08)
            } else {
                (0.003, 0.012)
            };
            // The later copies lie apart from the first by a fraction of the curve's
            // extent (at most a quarter of the part's thinnest dimension), and the
            // copies together are centred on the line meant: what a hand goes over
            // several times reads as the middle of its strokes.
            let mut shifts: Vec<DVec2> = (0..copies)
                .map(|copy| {
                    if copy == 0 {
                        DVec2::ZERO
                    } else {
                        let apart = (self.rng.range(apart.0, apart.1) * scale).min(self.thin / 4.0);
                        DVec2::from_angle(self.rng.range(0.0, TAU)) * apart
                    }
                })
                .collect();
            let mean = shifts.iter().copied().sum::<DVec2>() / copies as f64;
            for s in &mut shifts {
                *s -= mean;
            }
            for (copy, shift) in shifts.into_iter().enumerate() {
                // Half the later copies go over a stretch of the line only (40–90 % of
                // it, anywhere along it): a hand goes back over the part it doubts.
                let stretch = if copies > 1 {
                    let (partial, f) = (self.rng.chance(PARTIAL_COPIES), self.rng.range(0.4, 0.9));
                    let a = self.rng.range(0.0, 1.0 - f);
                    if copy > 0 && partial {
                        (a, a + f)
                    } else {
                        (0.0, 1.0)
                    }
                } else {
                    (0.0, 1.0)
                };
                let label = match (copies > 1, stretch == (0.0, 1.0)) {
                    (false, _) => ideal.label.clone(),
                    (true, true) => format!("{} (copy {}/{copies})", ideal.label, copy + 1),
                    (true, false) => format!(
                        "{} (copy {}/{copies}, {:.0} % of it)",
                        ideal.label,
                        copy + 1,
                        100.0 * (stretch.1 - stretch.0)
                    ),
                };
                let hand = Hand {
                    condition,
                    shift,
                    stretch,
                };
                self.draw_ideal(ideal, &label, scale, hand);
            }
        }
    }

    /// Turns every end circle's curves about its centre by 2°–20° either way, one angle
    /// per end (its front and hidden arcs alike).
    fn slant(&mut self, ideals: &mut [Ideal]) {
        let mut turns: Vec<(DVec2, f64)> = Vec::new();
        for ideal in ideals.iter_mut() {
            let Some(pivot) = ideal.pivot else {
                continue;
            };
            let turn = if let Some((_, turn)) = turns.iter().find(|(p, _)| *p == pivot) {
                *turn
            } else {
                let turn = self.rng.degrees(2.0, 20.0) * self.rng.sign();
                turns.push((pivot, turn));
                turn
            };
            let rotation = DVec2::from_angle(turn);
            for p in &mut ideal.points {
                *p = pivot + rotation.rotate(*p - pivot);
            }
        }
    }

    /// Joins strokes across corners: the outlines of a solid of revolution or a tube and
    /// its far end's front arc into one U stroke; one or two pairs of box edges that meet
    /// at a corner into L strokes.
    fn join(&mut self, ideals: Vec<Ideal>) -> Vec<Ideal> {
        let find = |pred: &dyn Fn(&Ideal) -> bool| ideals.iter().position(pred);
        let left = find(&|i| i.label == "left");
        let right = find(&|i| i.label == "right");
        let arc = find(&|i| !i.closed && i.class == StrokeClass::Feature && !i.hidden());
        if let (Some(l), Some(r), Some(a)) = (left, right, arc) {
            let u = chain(
                &chain(&ideals[l].points, &ideals[a].points),
                &ideals[r].points,
            );
            let joined = Ideal {
                points: u,
                closed: false,
                class: StrokeClass::Silhouette,
                label: format!("U: left + {} + right", ideals[a].label),
                gap_factor: 0.0,
                pivot: None,
            };
            let mut out: Vec<Ideal> = ideals
                .into_iter()
                .enumerate()
                .filter(|(k, _)| ![l, r, a].contains(k))
                .map(|(_, i)| i)
                .collect();
            out.push(joined);
            return out;
        }
        // Box edges: pairs sharing a corner, taken in a random order, at most two.
        let edges: Vec<usize> = (0..ideals.len())
            .filter(|k| ideals[*k].label.starts_with("edge"))
            .collect();
        let tol = 1e-6 * self.size;
        let mut pairs = Vec::new();
        for (x, a) in edges.iter().enumerate() {
            for b in &edges[x + 1..] {
                let (pa, pb) = (&ideals[*a].points, &ideals[*b].points);
                let meet = [pa[0], pa[pa.len() - 1]].iter().any(|p| {
                    [pb[0], pb[pb.len() - 1]]
                        .iter()
                        .any(|q| p.distance(*q) < tol)
                });
                if meet {
                    pairs.push((*a, *b));
                }
            }
        }
        let mut used: Vec<usize> = Vec::new();
        let mut joined = Vec::new();
        let wanted = 1 + (self.rng.next_u64() % 2) as usize;
        while joined.len() < wanted && !pairs.is_empty() {
            let (a, b) = pairs.swap_remove((self.rng.next_u64() % pairs.len() as u64) as usize);
            if used.contains(&a) || used.contains(&b) {
                continue;
            }
            used.extend([a, b]);
            joined.push(Ideal {
                points: chain(&ideals[a].points, &ideals[b].points),
                closed: false,
                class: StrokeClass::Silhouette,
                label: format!("L: {} + {}", ideals[a].label, ideals[b].label),
                gap_factor: 0.0,
                pivot: None,
            });
        }
        let mut out: Vec<Ideal> = ideals
            .into_iter()
            .enumerate()
            .filter(|(k, _)| !used.contains(k))
            .map(|(_, i)| i)
            .collect();
        out.extend(joined);
        out
    }

    /// One drawing of an ideal: over- and undershoots and gaps (larger under
    /// [`Condition::Overshoots`]), in pieces under [`Condition::Fragments`], moved by
    /// `shift` (a sketchy copy).
    fn draw_ideal(&mut self, ideal: &Ideal, label: &str, scale: f64, hand: Hand) {
        let Hand {
            condition,
            shift,
            stretch,
        } = hand;
        let total = *cumulative(&ideal.points).last().unwrap_or(&0.0);
        if total <= 0.0 {
            return;
        }
        let heavy = condition == Condition::Overshoots;
        let (s0, s1) = if ideal.closed {
            let extra = if heavy {
                self.rng.range(-0.08, 0.08) * total
            } else {
                0.0
            };
            (0.0, total + extra)
        } else {
            let reach = if heavy { 0.15 } else { self.style.overshoot } * scale;
            let limit = 0.3 * total;
            let a = (self.rng.range(-1.0, 1.0) * reach).clamp(-limit, limit);
            let b = (self.rng.range(-1.0, 1.0) * reach).clamp(-limit, limit);
            (-a, total + b)
        };
        let mut pieces = vec![(s0, s1)];
        if condition == Condition::Fragments && self.rng.chance(0.7) {
            let n = 3 + (self.rng.next_u64() % 3) as usize;
            let mut cuts: Vec<f64> = (1..n)
                .map(|k| {
                    let even = k as f64 / n as f64;
                    s0 + (s1 - s0) * (even + self.rng.range(-0.3, 0.3) / n as f64)
                })
                .collect();
            cuts.sort_by(f64::total_cmp);
            let mut bounds = vec![s0];
            bounds.extend(cuts);
            bounds.push(s1);
            pieces = bounds
                .windows(2)
                .map(|w| {
                    // Each joint a small gap or overlap, up to 2 % of the curve.
                    let d0 = self.rng.range(-0.02, 0.02) * total;
                    let d1 = self.rng.range(-0.02, 0.02) * total;
                    (w[0] + d0, w[1] - d1)
                })
                .collect();
            if let Some(first) = pieces.first_mut() {
                first.0 = s0;
            }
            if let Some(last) = pieces.last_mut() {
                last.1 = s1;
            }
        } else if !ideal.closed {
            let (chance, lo, hi) = if heavy {
                (0.6, 0.04, 0.12)
            } else {
                (self.style.gap_chance * ideal.gap_factor, 0.02, 0.06)
            };
            if self.rng.chance(chance) {
                let at = s0 + (s1 - s0) * self.rng.range(0.3, 0.7);
                let gap = self.rng.range(lo, hi) * total;
                pieces = vec![(s0, at - gap / 2.0), (at + gap / 2.0, s1)];
            }
        }
        if stretch != (0.0, 1.0) {
            // A stretch of the line, gone over once more: it starts and stops where the
            // hand does (drawn after the same draws as a whole copy, so that the rest of
            // the drawing does not change with it).
            pieces = vec![(stretch.0 * total, stretch.1 * total)];
        }
        let n = pieces.len();
        for (k, (a, b)) in pieces.into_iter().enumerate() {
            if b - a <= 0.0 {
                continue;
            }
            let points: Vec<DVec2> = self
                .humanize_with(&ideal.points, a, b, scale)
                .into_iter()
                .map(|p| p + shift)
                .collect();
            let name = if n > 1 {
                format!("{label} ({}/{n})", k + 1)
            } else {
                label.to_owned()
            };
            self.emit(points, ideal.class, name);
        }
    }

    /// An ideal with 20–60 % of its length left out, anywhere along it.
    fn draw_missing(&mut self, ideal: &Ideal, scale: f64) {
        let total = *cumulative(&ideal.points).last().unwrap_or(&0.0);
        let f = self.rng.range(0.2, 0.6);
        let a = self.rng.range(0.0, 1.0 - f);
        let (cut0, cut1) = (a * total, (a + f) * total);
        let mut n = 0;
        for (s0, s1) in [(0.0, cut0), (cut1, total)] {
            if s1 - s0 < 0.03 * total {
                continue;
            }
            n += 1;
            let points = self.humanize_with(&ideal.points, s0, s1, scale);
            self.emit(
                points,
                ideal.class,
                format!("{} (part {n}, {:.0} % missing)", ideal.label, 100.0 * f),
            );
        }
    }
}
