//! Automatic classification of strokes as feature or silhouette.
//!
//! A **feature** stroke is an ellipse or an elliptical arc: the outline of a circular end
//! of a cylinder, cone or generalized cylinder, seen at an angle. A **silhouette** stroke
//! is anything else: the straight or gently curving outline of a side. The user's
//! [`Stroke::class_override`] always wins ([`effective_class`], [`classify_sketch`]).
//!
//! The original system classified by PCA (σ₂/σ₁ < 0.1 means "line") and the mean
//! *algebraic* ellipse residual, then propagated hand-made labels over an endpoint graph
//! (original-system.md §2.4), which let curved silhouettes pass as ellipses and needed
//! the user to label curves first. Here the class comes from geometric evidence,
//! collected in a [`Classification`].
//!
//! [`classify_with`] judges one stroke by its shape alone; [`classify_sketch`] judges
//! every stroke of a sketch, adding two rules that look at a stroke's neighbours: a
//! shallow arc between the ends of two silhouettes is a feature (the front of a
//! cylinder's base), and an arc running alongside another at a constant distance is a
//! silhouette (one outline of a bent tube).
//!
//! Every threshold is relative (a ratio or an angle), so classification does not depend
//! on the drawing's scale, position or orientation.

use std::cell::OnceCell;
use std::f64::consts::{PI, TAU};

use glam::DVec2;

use super::parallel;
use super::preprocess::{resample_to, smooth};
use super::{Sketch, Stroke, StrokeClass, StrokeId};
use crate::geom::{fit_ellipse, fit_line, refine_ellipse_within, AngularSpan, BoxIndex, Ellipse2};

/// Thresholds for [`classify_with`] and [`classify_sketch`], all relative (ratios or
/// angles); see those functions for how each is used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClassifyOptions {
    /// Points the stroke is resampled to, uniform in arc length (at least 8). Default 64.
    pub samples: usize,
    /// Passes of the `[1, 2, 1]/4` filter over the resampled points before any test, so
    /// that the jitter of a hand-drawn (or noisy) line neither spoils the ellipse fit nor
    /// counts as turning back and forth. Default 4 (a Gaussian of about 2 % of the
    /// stroke's length, which leaves the corners of a box face clearly visible).
    pub smoothing_passes: usize,
    /// A stroke whose RMS distance to its best-fit line is below this fraction of its
    /// extent along the line is straight. Default 0.01.
    pub max_straightness: f64,
    /// The largest RMS geometric distance to the fitted ellipse, as a fraction of its
    /// mean radius `√(ab)`, for an open stroke. Default 0.04.
    pub max_residual: f64,
    /// The same for a stroke that closes on itself. Default 0.085 (a square scores 0.11,
    /// a 3:1 rectangle 0.094, hand-drawn egg-shaped or lumpy rims 0.05–0.08).
    pub max_residual_closed: f64,
    /// The largest semi-major axis, as a multiple of the diagonal of the stroke's
    /// bounding box. Default 2.0 (a 120° arc round the end of an ellipse of axis ratio
    /// 0.2 needs 1.6; a half ellipse at most 0.5).
    pub max_size_ratio: f64,
    /// The smallest parametric angular span an open stroke must cover, in radians.
    /// Default 120° (2π/3).
    pub min_span: f64,
    /// An open stroke whose endpoints are closer than this fraction of its length counts
    /// as closed. Default 0.1.
    pub closing_gap: f64,
    /// The smallest total turning angle (the sum of the exterior angles), in radians.
    /// Default 90° (π/2); a half ellipse turns 180° however flat it is.
    pub min_turning: f64,
    /// The largest turning against the overall direction, in radians, on top of 10 % of
    /// the total turning, which absorbs jitter. Default 25° (an S-curve turns its whole
    /// second half backwards).
    pub max_reverse_turning: f64,
    /// [`classify_sketch`]: the smallest total turning of an arc between two
    /// silhouettes, in radians. Default 30°.
    pub arc_min_turning: f64,
    /// [`classify_sketch`]: the smallest straightness (RMS distance to the best-fit line
    /// over the extent) of an arc between two silhouettes. Default 0.03: slightly bowed
    /// box edges between two parallel edges score 0.02–0.025, the shallowest cylinder
    /// ends 0.04 and more.
    pub arc_min_straightness: f64,
    /// [`classify_sketch`]: the largest gap between an arc's end and a silhouette's end
    /// that still counts as a junction, as a fraction of the arc's length. Default 0.15.
    pub junction_gap: f64,
    /// [`classify_sketch`]: the same gap as a fraction of the sketch's size (the diagonal
    /// of the bounding box of all strokes); the larger of the two applies, so short arcs
    /// still tolerate the imprecision of a hand-drawn junction. Default 0.02.
    pub junction_gap_sketch: f64,
    /// [`classify_sketch`]: how squarely the silhouettes must leave towards the arc's
    /// concave side: the cosine between a silhouette's direction (from its end at the
    /// junction to its point a third of the way along) and the direction opposite the
    /// arc's bulge must be at least this. Default 0.3 (within about 73°).
    pub min_departure: f64,
    /// [`classify_sketch`]: the largest angle between the two silhouettes' directions of
    /// departure, in radians: the sides of a cylinder are parallel, those of a cone
    /// converge (a menorah's cup-shaped cones leave their bottom arcs up to 70° apart),
    /// while two edges of a box leave a corner further apart still. Default 75°.
    pub max_side_angle: f64,
    /// [`classify_sketch`]: an elliptical arc with another open stroke alongside at a
    /// mean distance of at most this fraction of its length is one outline of a bent
    /// tube, a silhouette. Default 0.15.
    pub twin_max_offset: f64,
    /// [`classify_sketch`]: the largest coefficient of variation (standard deviation over
    /// mean) of that distance. Default 0.25.
    pub twin_max_variation: f64,
    /// Points the stroke is resampled to for measuring how much it turns back, fewer
    /// than [`samples`](Self::samples) so that the jitter of a hand-drawn line does not
    /// count as turning back and forth. Default 24.
    pub turning_samples: usize,
    /// The ellipse refinement stops when a step improves the RMS distance by at most
    /// this fraction of the stroke's size (its largest distance from its centroid), see
    /// [`refine_ellipse_within`]. Default 1e−5 (0.01 px on a stroke 1,000 px across), far
    /// below the residual thresholds; 0 refines to rounding, at several times the cost
    /// on short and shallow arcs (1e−4 cost two of the 960 synthetic acceptance cases).
    pub fit_tolerance: f64,
}

impl Default for ClassifyOptions {
    fn default() -> Self {
        Self {
            samples: 64,
            smoothing_passes: 4,
            max_straightness: 0.01,
            max_residual: 0.04,
            max_residual_closed: 0.085,
            max_size_ratio: 2.0,
            min_span: TAU / 3.0,
            closing_gap: 0.1,
            min_turning: PI / 2.0,
            max_reverse_turning: 25f64.to_radians(),
            arc_min_turning: 30f64.to_radians(),
            arc_min_straightness: 0.03,
            junction_gap: 0.15,
            junction_gap_sketch: 0.02,
            min_departure: 0.3,
            max_side_angle: 75f64.to_radians(),
            twin_max_offset: 0.15,
            twin_max_variation: 0.25,
            turning_samples: 24,
            fit_tolerance: 1e-5,
        }
    }
}

/// Why a stroke got its class: the test that decided it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ClassReason {
    /// The user chose the class ([`Stroke::class_override`]).
    Override,
    /// Fewer than two distinct finite points (or zero length): a silhouette by default.
    TooFewPoints,
    /// The stroke is straight.
    Straight,
    /// No ellipse could be fitted (for example the points are collinear).
    NoEllipse,
    /// The fitted ellipse is too far from the points.
    PoorFit,
    /// The fitted ellipse is much larger than the stroke (a gently curved line).
    EllipseTooLarge,
    /// The stroke covers too small an arc of its ellipse.
    ShortArc,
    /// The stroke turns too little in total.
    LittleTurning,
    /// The stroke turns back against its overall direction (an inflection or zigzag).
    Inflection,
    /// Every shape test passed: an ellipse or elliptical arc.
    Ellipse,
    /// A shallow elliptical arc joining the ends of two silhouettes that leave towards
    /// its concave side ([`classify_sketch`] only).
    ArcBetweenSilhouettes,
    /// An open arc running alongside another open stroke at a nearly constant distance:
    /// the two outlines of a bent tube ([`classify_sketch`] only).
    ParallelOutline,
    /// An open arc hanging from both ends of a closed ellipse, but of another shape: the
    /// outline of a bowl or dome under its rim ([`classify_sketch`] only).
    OutlineUnderRim,
}

/// The evidence behind a stroke's class; a measured value is `None` when the test that
/// needs it was not reached or not possible.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Classification {
    /// The stroke classified.
    pub id: StrokeId,
    /// The class: feature for [`ClassReason::Ellipse`] and
    /// [`ClassReason::ArcBetweenSilhouettes`], the user's choice for
    /// [`ClassReason::Override`], silhouette otherwise.
    pub class: StrokeClass,
    /// The test that decided it.
    pub reason: ClassReason,
    /// RMS distance to the best-fit line over the extent along it.
    pub straightness: Option<f64>,
    /// The fitted ellipse (algebraic fit refined on geometric distance).
    pub ellipse: Option<Ellipse2>,
    /// RMS geometric distance to the ellipse over its mean radius `√(ab)`.
    pub relative_residual: Option<f64>,
    /// Semi-major axis over the diagonal of the stroke's bounding box.
    pub size_ratio: Option<f64>,
    /// The arc of the ellipse the stroke covers ([`Ellipse2::angular_span`]).
    pub span: Option<AngularSpan>,
    /// Whether the stroke is closed or its endpoints nearly meet.
    pub closes: bool,
    /// The sum of the signed exterior angles along the stroke resampled to
    /// [`ClassifyOptions::samples`] points, in radians (positive counter-clockwise in a
    /// y-up frame, i.e. clockwise on screen).
    pub turning: f64,
    /// The turning against the overall direction, in radians: `(Σ|θᵢ| − |Σθᵢ|)/2` over
    /// the exterior angles θᵢ of the stroke resampled to the coarser
    /// [`ClassifyOptions::turning_samples`] points.
    pub reverse_turning: f64,
}

/// The inferred class of `stroke` from its shape alone, with the default options
/// (ignoring any override; see [`effective_class`]).
///
/// # Examples
///
/// ```
/// use geosnap_core::sketch::{classify, Stroke, StrokeClass, StrokeId};
/// use glam::DVec2;
///
/// let ellipse: Vec<DVec2> = (0..40)
///     .map(|i| {
///         let t = std::f64::consts::TAU * f64::from(i) / 40.0;
///         DVec2::new(100.0 * t.cos(), 30.0 * t.sin())
///     })
///     .collect();
/// let stroke = Stroke { id: StrokeId(0), points: ellipse, closed: true, class_override: None };
/// assert_eq!(classify(&stroke), StrokeClass::Feature);
/// ```
pub fn classify(stroke: &Stroke) -> StrokeClass {
    classify_with(stroke, &ClassifyOptions::default()).class
}

/// The class that counts for one stroke on its own: the user's override if there is
/// one, otherwise [`classify`]. Prefer [`classify_sketch`] for a whole sketch, which also
/// recognises shallow arcs between silhouettes.
pub fn effective_class(stroke: &Stroke) -> StrokeClass {
    stroke.class_override.unwrap_or_else(|| classify(stroke))
}

/// Classifies `stroke` from its shape alone (ignoring any override) and reports the
/// evidence.
///
/// The tests, in order:
///
/// 1. the stroke is resampled to [`ClassifyOptions::samples`] points uniform in arc
///    length, so densely and sparsely sampled parts weigh the same, and lightly smoothed
///    ([`ClassifyOptions::smoothing_passes`]);
/// 2. **straight** strokes (RMS distance to the best line below
///    [`ClassifyOptions::max_straightness`] of their extent) are silhouettes;
/// 3. the stroke must **turn consistently**: in total at least
///    [`ClassifyOptions::min_turning`] ([`ClassReason::LittleTurning`]), with little
///    turning against that direction (an inflection, as in an S-curve, or a zigzag,
///    [`ClassReason::Inflection`]), see [`ClassifyOptions::max_reverse_turning`];
/// 4. an ellipse is fitted ([`fit_ellipse`], then [`refine_ellipse`](crate::geom::refine_ellipse) to within
///    [`ClassifyOptions::fit_tolerance`]) and must fit
///    **well**: RMS geometric distance at most [`ClassifyOptions::max_residual`] of the
///    ellipse's mean radius `√(ab)` ([`ClassifyOptions::max_residual_closed`] for a stroke
///    that closes on itself, because hand-drawn loops wobble more; quadrilaterals score
///    0.09 or more);
/// 5. the ellipse must not be absurdly **large** for the stroke (semi-major axis at most
///    [`ClassifyOptions::max_size_ratio`] times the diagonal of the stroke's bounding
///    box): a gently curved line is always fitted well by some huge, flat ellipse;
/// 6. the stroke must **cover** enough of the ellipse (a parametric angular span of at
///    least [`ClassifyOptions::min_span`]), unless it closes on itself.
///
/// The tests that need no ellipse come first because the fit is by far the costliest
/// step (a geometric refinement, [`refine_ellipse`](crate::geom::refine_ellipse)): a stroke they settle is reported
/// without the ellipse evidence (`None`), since the fit would not change its class.
/// The class is that of every test passing, whatever their order.
///
/// Every threshold is relative (a ratio or an angle), so the class does not depend on the
/// stroke's scale, position or orientation.
pub fn classify_with(stroke: &Stroke, options: &ClassifyOptions) -> Classification {
    analyse(stroke, options).classification
}

/// Classifies every stroke of `sketch`, in order: overrides win
/// ([`ClassReason::Override`], with the shape evidence still reported), then the shape
/// tests of [`classify_with`], then two context rules.
///
/// The context rules. A hand-drawn elliptical arc is often too shallow to pass the
/// shape tests alone: the front half of a cylinder's base is drawn as a flat
/// "U" between the two side outlines, indistinguishable in shape from a gently curved
/// side. So an open stroke that fits an ellipse well, turns consistently by at least
/// [`ClassifyOptions::arc_min_turning`] and is visibly bowed
/// ([`ClassifyOptions::arc_min_straightness`]) becomes a feature
/// ([`ClassReason::ArcBetweenSilhouettes`]) when each of its ends meets the end of a
/// different silhouette (within [`ClassifyOptions::junction_gap`] of the arc's length or
/// [`ClassifyOptions::junction_gap_sketch`] of the sketch's size)
/// and both silhouettes leave towards the arc's concave side in nearly the same
/// direction ([`ClassifyOptions::min_departure`], [`ClassifyOptions::max_side_angle`]),
/// as the sides of a cylinder, cone or tube leave its end. Two edges of a box leave a
/// corner too far apart to pass, and neither a stroke that closes on itself nor one that
/// is itself such a shallow arc counts as a silhouette here, so two shallow arcs cannot
/// vouch for each other.
///
/// Conversely, an elliptical arc that runs alongside another open stroke at a nearly
/// constant, small distance is one of the two outlines of a bent tube (the arms of a
/// menorah): a silhouette ([`ClassReason::ParallelOutline`], see
/// [`ClassifyOptions::twin_max_offset`]).
///
/// All distances are relative to the strokes' lengths or the sketch's size.
pub fn classify_sketch(sketch: &Sketch, options: &ClassifyOptions) -> Vec<Classification> {
    classify_among(sketch, options, true)
}

/// [`classify_sketch`], the neighbour rules looking at the strokes an index of their
/// bounds finds near (`indexed`) or at every stroke (the same result, slowly).
fn classify_among(
    sketch: &Sketch,
    options: &ClassifyOptions,
    indexed: bool,
) -> Vec<Classification> {
    // Each stroke on its own first, the costly part (the ellipse fits), in parallel.
    let analyses: Vec<Analysis> = parallel::map(&sketch.strokes, |stroke| {
        let mut a = analyse(stroke, options);
        if let Some(class) = stroke.class_override {
            a.classification.class = class;
            a.classification.reason = ClassReason::Override;
        }
        a
    });
    let candidates = Candidates::new(&analyses, options);
    // The neighbour rules look only at the strokes whose bounds come near enough.
    let near = Neighbours {
        all: &analyses,
        boxes: indexed.then(|| BoxIndex::new(analyses.iter().map(|a| bounds(&a.points)))),
    };
    let size = sketch.bounds().map_or(0.0, |(lo, hi)| (hi - lo).length());
    let sketch_gap = options.junction_gap_sketch * if size.is_finite() { size } else { 0.0 };
    // The arcs whose ends meet two silhouettes at all, in parallel: the arcs the rule
    // below may make features are among them (an anchor is a silhouette that may anchor
    // some arc), and the ellipses of the shallowest of them are fitted before it asks.
    let may_be: Vec<usize> = (0..analyses.len())
        .filter(|&i| candidates.may_be(i))
        .collect();
    let joining: Vec<usize> = {
        let joins = parallel::map(&may_be, |&i| {
            joins_two_silhouettes(
                &analyses[i],
                &near,
                |j| may_anchor(&analyses, j),
                sketch_gap,
                options,
            )
        });
        may_be
            .into_iter()
            .zip(joins)
            .filter_map(|(i, joins)| joins.then_some(i))
            .collect()
    };
    candidates.fit_joining(&joining);
    let mut out: Vec<Classification> = analyses.iter().map(|a| a.classification).collect();
    for &i in &joining {
        let a = &analyses[i];
        // The junctions first: they are cheaper than the ellipse an arc may still need.
        let anchors_it = |j| candidates.anchors(j, a.length);
        if joins_two_silhouettes(a, &near, anchors_it, sketch_gap, options) && candidates.is(i) {
            out[i].class = StrokeClass::Feature;
            out[i].reason = ClassReason::ArcBetweenSilhouettes;
            if let Some(fit) = candidates.fits[i].get() {
                fit.report(&mut out[i]);
            }
        }
    }
    // Elliptical arcs that are outlines after all, each on its own, in parallel.
    let outlines = parallel::map(&analyses, |a| {
        let c = &a.classification;
        let arc = c.reason == ClassReason::Ellipse && !c.closes;
        if arc && hangs_from_a_rim(a, &near, sketch_gap) {
            Some(ClassReason::OutlineUnderRim)
        } else if arc && has_parallel_twin(a, &near, options) {
            Some(ClassReason::ParallelOutline)
        } else {
            None
        }
    });
    for (c, reason) in out.iter_mut().zip(outlines) {
        if let Some(reason) = reason {
            c.class = StrokeClass::Silhouette;
            c.reason = reason;
        }
    }
    out
}

/// The shallow arcs of a sketch the neighbour rule of [`classify_sketch`] may make
/// features, and the silhouettes they may join, with the ellipses of the shallowest
/// arcs fitted only when a rule asks (see [`Candidacy::IfItFits`]): the answers are
/// those of fitting every stroke, at a fraction of the cost on a large drawing.
struct Candidates<'a> {
    all: &'a [Analysis],
    options: &'a ClassifyOptions,
    candidacy: Vec<Candidacy>,
    /// The ellipses fitted on demand, per stroke.
    fits: Vec<OnceCell<EllipseFit>>,
}

impl<'a> Candidates<'a> {
    fn new(all: &'a [Analysis], options: &'a ClassifyOptions) -> Self {
        Self {
            all,
            options,
            candidacy: all.iter().map(|a| arc_candidacy(a, options)).collect(),
            fits: all.iter().map(|_| OnceCell::new()).collect(),
        }
    }

    /// Whether stroke `i` may be a shallow arc (it is unless its ellipse fits badly).
    fn may_be(&self, i: usize) -> bool {
        self.candidacy.get(i).is_some_and(|&c| c != Candidacy::No)
    }

    /// Whether stroke `i` is a shallow arc, fitting its ellipse if need be.
    fn is(&self, i: usize) -> bool {
        match self.candidacy.get(i) {
            Some(Candidacy::Yes) => true,
            Some(Candidacy::IfItFits) => self.fits[i]
                .get_or_init(|| EllipseFit::of(&self.all[i].points, self.options))
                .fits_open(self.options),
            _ => false,
        }
    }

    /// Whether stroke `j` may anchor an arc of length `arc_length`.
    ///
    /// The silhouettes an arc may join are open (a loop has no end to leave from). A
    /// shallow arc may anchor only an arc less than half its length (the curved sides of
    /// a cup and the small arc of its bottom), or two of them (the two sides of a curved
    /// horn, say) would vouch for each other. A longer stroke anchors the arc whatever
    /// it is, which spares its fit.
    fn anchors(&self, j: usize, arc_length: f64) -> bool {
        self.may_anchor(j) && (arc_length <= self.all[j].length / 2.0 || !self.is(j))
    }

    /// Whether stroke `j` may anchor some arc (see [`may_anchor`]).
    fn may_anchor(&self, j: usize) -> bool {
        may_anchor(self.all, j)
    }

    /// Fits, in parallel, the ellipses of the arcs of [`Candidacy::IfItFits`] among
    /// `joining`, the arcs whose ends meet silhouettes as the neighbour rule wants (any
    /// silhouette that may anchor some arc), before it asks for them one by one: every
    /// arc the rule will ask about is among them.
    fn fit_joining(&self, joining: &[usize]) {
        let wanted: Vec<usize> = joining
            .iter()
            .copied()
            .filter(|&i| self.candidacy[i] == Candidacy::IfItFits)
            .collect();
        let fits = parallel::map(&wanted, |&i| {
            EllipseFit::of(&self.all[i].points, self.options)
        });
        for (i, fit) in wanted.into_iter().zip(fits) {
            // Only this pass has filled any of them.
            let _ = self.fits[i].set(fit);
        }
    }
}

/// Whether stroke `j` of `all` may anchor some arc: an open silhouette.
fn may_anchor(all: &[Analysis], j: usize) -> bool {
    all.get(j).is_some_and(|a| {
        let c = &a.classification;
        c.class == StrokeClass::Silhouette && !c.closes
    })
}

/// The strokes of a sketch as the neighbour rules see them, with an index of their
/// bounds: a rule looks only at the strokes whose bounds come within its reach, which
/// are the only ones its tests can pass (so the result is that of a scan over all).
struct Neighbours<'a> {
    all: &'a [Analysis],
    /// The index of the strokes' bounds (`None`: every stroke is near).
    boxes: Option<BoxIndex>,
}

impl Neighbours<'_> {
    /// The strokes whose bounds come within `distance` of the box `lo`–`hi` along each
    /// axis (with no index, all), in sketch order.
    fn near(
        &self,
        lo: DVec2,
        hi: DVec2,
        distance: f64,
    ) -> impl Iterator<Item = (usize, &Analysis)> {
        let indices = match &self.boxes {
            Some(boxes) => boxes.near(lo, hi, distance),
            None => (0..self.all.len()).collect(),
        };
        indices
            .into_iter()
            .filter_map(|i| self.all.get(i).map(|a| (i, a)))
    }
}

/// Whether both ends of the open elliptical arc `arc` lie on one closed ellipse (within
/// `gap`, or 5 % of the arc's length), while the arc's own ellipse is of another shape
/// (its minor semi-axis half as large again or more): a bowl's outline hangs from the
/// ends of its rim, whereas the drawn half of a disc's hidden rim has the shape of the
/// rim above it.
fn hangs_from_a_rim(arc: &Analysis, near: &Neighbours<'_>, gap: f64) -> bool {
    let (Some(&start), Some(&end), Some(own)) = (
        arc.points.first(),
        arc.points.last(),
        arc.classification.ellipse.as_ref(),
    ) else {
        return false;
    };
    let gap = gap.max(0.05 * arc.length);
    // A rim within `gap` of the arc's start has its bounds within `gap` of it.
    near.near(start, start, gap).any(|(_, rim)| {
        let c = &rim.classification;
        let Some(shape) = c.ellipse.as_ref() else {
            return false;
        };
        c.id != arc.classification.id
            && c.closes
            && c.reason == ClassReason::Ellipse
            && rim.points.len() >= 3
            && polyline_distance(&rim.points, start).0 <= gap
            && polyline_distance(&rim.points, end).0 <= gap
            && own.semi_minor.min(own.semi_major) >= 1.5 * shape.semi_minor.min(shape.semi_major)
    })
}

/// Whether another open stroke of similar length (half to twice) runs alongside the
/// middle 70 % of `arc` at a nearly constant distance: small against the arc's length (at
/// most [`ClassifyOptions::twin_max_offset`] of it, at least 1 %, since a retraced line
/// is not a tube), with a coefficient of variation of at most
/// [`ClassifyOptions::twin_max_variation`], and always closest to the twin's inside, not
/// its ends. The back and front halves of one ellipse do not pass: they touch at their
/// ends and are furthest apart in the middle.
fn has_parallel_twin(arc: &Analysis, near: &Neighbours<'_>, options: &ClassifyOptions) -> bool {
    let n = arc.points.len();
    if n < 8 || !(arc.length > 0.0) {
        return false;
    }
    let middle = &arc.points[n * 3 / 20..n - n * 3 / 20];
    let max_offset = options.twin_max_offset * arc.length;
    let (lo, hi) = bounds(middle);
    // The cheap rejection below, by the index: only the strokes whose bounds come
    // within `max_offset` of the middle's along each axis can pass it.
    near.near(lo, hi, max_offset).any(|(_, other)| {
        if other.classification.id == arc.classification.id
            || other.classification.closes
            || other.points.len() < 3
            || !(other.length >= 0.5 * arc.length && other.length <= 2.0 * arc.length)
        {
            return false;
        }
        // Cheap rejection: the bounding boxes are further apart than the largest offset.
        let (other_lo, other_hi) = bounds(&other.points);
        let gap = (other_lo - hi).max(lo - other_hi).max(DVec2::ZERO);
        if gap.length() > max_offset {
            return false;
        }
        let mut distances = Vec::with_capacity(middle.len());
        for &p in middle {
            let (distance, at_end) = polyline_distance(&other.points, p);
            if at_end {
                return false;
            }
            distances.push(distance);
        }
        let count = distances.len() as f64;
        let mean = distances.iter().sum::<f64>() / count;
        let variance = distances.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / count;
        mean >= 0.01 * arc.length
            && mean <= max_offset
            && variance.sqrt() <= options.twin_max_variation * mean
    })
}

/// The distance from `p` to an open polyline, and whether the closest point is one of
/// its two endpoints.
fn polyline_distance(points: &[DVec2], p: DVec2) -> (f64, bool) {
    let last = points.len().saturating_sub(2);
    let mut best = (f64::INFINITY, false);
    for (i, w) in points.windows(2).enumerate() {
        let d = w[1] - w[0];
        let len2 = d.length_squared();
        let t = if len2 > 0.0 {
            ((p - w[0]).dot(d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let distance = p.distance(w[0] + t * d);
        if distance < best.0 {
            let at_end = (i == 0 && t <= 0.0) || (i == last && t >= 1.0);
            best = (distance, at_end);
        }
    }
    best
}

/// A stroke's classification with the resampled points the context rule needs.
struct Analysis {
    classification: Classification,
    /// The stroke resampled uniformly in arc length (empty for too few points).
    points: Vec<DVec2>,
    /// The stroke's length.
    length: f64,
}

fn analyse(stroke: &Stroke, options: &ClassifyOptions) -> Analysis {
    let mut report = Classification {
        id: stroke.id,
        class: StrokeClass::Silhouette,
        reason: ClassReason::TooFewPoints,
        straightness: None,
        ellipse: None,
        relative_residual: None,
        size_ratio: None,
        span: None,
        closes: false,
        turning: 0.0,
        reverse_turning: 0.0,
    };
    let finite: Vec<DVec2> = stroke
        .points
        .iter()
        .copied()
        .filter(|p| p.is_finite())
        .collect();
    let length = polyline_length(&finite, stroke.closed);
    let Some(mut points) = resample_to(&finite, stroke.closed, options.samples.max(8)) else {
        return Analysis {
            classification: report,
            points: Vec::new(),
            length,
        };
    };
    for _ in 0..options.smoothing_passes {
        points = smooth(&points, stroke.closed);
    }
    report.closes = stroke.closed
        || match (finite.first(), finite.last()) {
            (Some(a), Some(b)) => a.distance(*b) <= options.closing_gap * length,
            _ => false,
        };
    // The total turning at full resolution, which catches the sharp ends of a flat half
    // ellipse; the turning back at a coarser one, which ignores jitter.
    report.turning = turning(&points, stroke.closed).0;
    let coarse = resample_to(&points, stroke.closed, options.turning_samples.max(4));
    let (net, absolute) = coarse.map_or((0.0, 0.0), |c| turning(&c, stroke.closed));
    report.reverse_turning = 0.5 * (absolute - net.abs()).max(0.0);
    shape_tests(&mut report, &points, options);
    Analysis {
        classification: report,
        points,
        length,
    }
}

/// Tests 2–6 of [`classify_with`] on the resampled points; fills in `report`.
fn shape_tests(report: &mut Classification, points: &[DVec2], options: &ClassifyOptions) {
    let Some(line) = fit_line(points) else {
        return;
    };
    let straightness = line.rms_residual / line.length().max(f64::MIN_POSITIVE);
    report.straightness = Some(straightness);
    report.reason = if straightness < options.max_straightness {
        ClassReason::Straight
    } else if report.turning.abs() < options.min_turning {
        ClassReason::LittleTurning
    } else if reverses(report, options) {
        ClassReason::Inflection
    } else {
        let fit = EllipseFit::of(points, options);
        fit.report(report);
        fit.reason(report.closes, options)
    };
    if report.reason == ClassReason::Ellipse {
        report.class = StrokeClass::Feature;
    }
}

/// The ellipse evidence of a stroke: the fitted ellipse and the measures the shape tests
/// take of it (`None` when no ellipse could be fitted).
#[derive(Clone, Copy, Debug)]
struct EllipseFit(Option<(Ellipse2, f64, f64, Option<AngularSpan>)>);

impl EllipseFit {
    /// Fits the resampled `points`: the algebraic fit refined on geometric distance, with
    /// its relative residual, size ratio and span.
    fn of(points: &[DVec2], options: &ClassifyOptions) -> Self {
        Self(
            fit_ellipse(points)
                .map(|e| refine_ellipse_within(&e, points, options.fit_tolerance))
                .map(|ellipse| {
                    let mean_radius = (ellipse.semi_major * ellipse.semi_minor).sqrt();
                    let (rms, span) = ellipse.rms_distance_and_span(points);
                    let relative_residual = rms / mean_radius;
                    let (lo, hi) = bounds(points);
                    let size_ratio = ellipse.semi_major / (hi - lo).length().max(f64::MIN_POSITIVE);
                    (ellipse, relative_residual, size_ratio, span)
                }),
        )
    }

    /// Writes the evidence into `report`.
    fn report(&self, report: &mut Classification) {
        if let Some((ellipse, relative_residual, size_ratio, span)) = self.0 {
            report.ellipse = Some(ellipse);
            report.relative_residual = Some(relative_residual);
            report.size_ratio = Some(size_ratio);
            report.span = span;
        }
    }

    /// Whether the ellipse fits an open stroke well ([`ClassifyOptions::max_residual`]).
    fn fits_open(&self, options: &ClassifyOptions) -> bool {
        self.0
            .is_some_and(|(_, residual, _, _)| residual <= options.max_residual)
    }

    /// The verdict of tests 4–6 of [`classify_with`].
    fn reason(&self, closes: bool, options: &ClassifyOptions) -> ClassReason {
        let Some((_, relative_residual, size_ratio, span)) = self.0 else {
            return ClassReason::NoEllipse;
        };
        let max_residual = if closes {
            options.max_residual_closed
        } else {
            options.max_residual
        };
        if !(relative_residual <= max_residual) {
            ClassReason::PoorFit
        } else if !(size_ratio <= options.max_size_ratio) {
            ClassReason::EllipseTooLarge
        } else if !closes && span.is_none_or(|s| s.sweep < options.min_span) {
            ClassReason::ShortArc
        } else {
            ClassReason::Ellipse
        }
    }
}

fn reverses(report: &Classification, options: &ClassifyOptions) -> bool {
    report.reverse_turning > options.max_reverse_turning + 0.1 * report.turning.abs()
}

/// Whether a stroke is a shallow arc the neighbour rule of [`classify_sketch`] may make a
/// feature: an open silhouette that fails the shape tests only for being shallow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Candidacy {
    /// It is not.
    No,
    /// It is: it fits an ellipse well and turns consistently, if not much.
    Yes,
    /// It is if it fits an ellipse well: it turns too little to be an ellipse, so its
    /// ellipse was not fitted, and is fitted only when a neighbour rule asks.
    IfItFits,
}

/// The [`Candidacy`] of a stroke: open, not overridden, turning consistently by at
/// least [`ClassifyOptions::arc_min_turning`], visibly bowed, and fitting an ellipse well
/// without passing the other tests (too large, too short an arc, or too little turning).
fn arc_candidacy(a: &Analysis, options: &ClassifyOptions) -> Candidacy {
    let c = &a.classification;
    let shallow = !c.closes
        && c.turning.abs() >= options.arc_min_turning
        && c.straightness
            .is_some_and(|s| s >= options.arc_min_straightness)
        && !reverses(c, options);
    match c.reason {
        // A poor fit of an open stroke is reported before these.
        ClassReason::EllipseTooLarge | ClassReason::ShortArc if shallow => Candidacy::Yes,
        ClassReason::LittleTurning if shallow => Candidacy::IfItFits,
        _ => Candidacy::No,
    }
}

/// Whether each end of the arc `arc` meets an end of a different anchor silhouette, and
/// both leave towards the arc's concave side (`anchors_it` says which strokes may anchor
/// it; it is asked last, as it may need a stroke's ellipse).
fn joins_two_silhouettes(
    arc: &Analysis,
    near: &Neighbours<'_>,
    anchors_it: impl Fn(usize) -> bool,
    sketch_gap: f64,
    options: &ClassifyOptions,
) -> bool {
    let (Some(&start), Some(&end)) = (arc.points.first(), arc.points.last()) else {
        return false;
    };
    // The bulge: the side of the chord the arc lies on, on average.
    let normal = (end - start).perp().normalize_or_zero();
    let side: f64 = arc.points.iter().map(|&p| (p - start).dot(normal)).sum();
    if normal == DVec2::ZERO || side == 0.0 {
        return false;
    }
    let concave = -normal * side.signum();
    let gap = (options.junction_gap * arc.length).max(sketch_gap);
    // For each end of the arc, the anchors meeting it there and leaving concavely, with
    // their directions of departure.
    // An anchor's end within `gap` of `at` lies in its bounds.
    let meeting = |at: DVec2| -> Vec<(usize, StrokeId, DVec2)> {
        near.near(at, at, gap)
            .filter_map(|(j, other)| {
                let n = other.points.len();
                if n < 2 || other.classification.id == arc.classification.id {
                    return None;
                }
                let third = (n - 1) / 3;
                let leaving = [(0, third), (n - 1, n - 1 - third)]
                    .into_iter()
                    .map(|(e, f)| {
                        (
                            other.points[e],
                            (other.points[f] - other.points[e]).normalize_or_zero(),
                        )
                    })
                    .find(|&(end, leaving)| {
                        end.distance(at) <= gap && leaving.dot(concave) >= options.min_departure
                    })?;
                Some((j, other.classification.id, leaving.1))
            })
            .collect()
    };
    let (at_start, at_end) = (meeting(start), meeting(end));
    let min_cos = options.max_side_angle.cos();
    at_start.iter().any(|&(j, a, da)| {
        at_end
            .iter()
            .any(|&(k, b, db)| a != b && da.dot(db) >= min_cos && anchors_it(j) && anchors_it(k))
    })
}

fn polyline_length(points: &[DVec2], closed: bool) -> f64 {
    let open: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
    match (closed, points.first(), points.last()) {
        (true, Some(a), Some(b)) => open + a.distance(*b),
        _ => open,
    }
}

fn bounds(points: &[DVec2]) -> (DVec2, DVec2) {
    let first = points.first().copied().unwrap_or(DVec2::ZERO);
    points
        .iter()
        .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)))
}

/// `(Σθᵢ, Σ|θᵢ|)` over the exterior angles θᵢ of the polyline: at every interior vertex
/// of an open one, at every vertex of a closed one.
fn turning(points: &[DVec2], closed: bool) -> (f64, f64) {
    let n = points.len();
    if n < 3 {
        return (0.0, 0.0);
    }
    let vertices = if closed { 0..n } else { 1..n - 1 };
    let (mut total, mut absolute) = (0.0, 0.0);
    for i in vertices {
        let a = points[i] - points[(i + n - 1) % n];
        let b = points[(i + 1) % n] - points[i];
        let angle = a.perp_dot(b).atan2(a.dot(b));
        total += angle;
        absolute += angle.abs();
    }
    (total, absolute)
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{PI, TAU};

    use glam::DVec2;

    use super::{
        classify, classify_among, classify_sketch, classify_with, effective_class, ClassReason,
        ClassifyOptions,
    };
    use crate::sketch::{Sketch, Stroke, StrokeClass, StrokeId};

    fn stroke(points: Vec<DVec2>, closed: bool) -> Stroke {
        Stroke {
            id: StrokeId(0),
            points,
            closed,
            class_override: None,
        }
    }

    /// Points of the ellipse with centre c, semi-axes (a, b), rotated by `angle`, for
    /// parameters from `from` to `to`.
    fn ellipse(c: DVec2, a: f64, b: f64, angle: f64, from: f64, to: f64, n: usize) -> Vec<DVec2> {
        let u = DVec2::from_angle(angle);
        (0..n)
            .map(|i| {
                let t = from + (to - from) * i as f64 / (n - 1) as f64;
                c + a * t.cos() * u + b * t.sin() * u.perp()
            })
            .collect()
    }

    fn assert_class(points: Vec<DVec2>, closed: bool, want: StrokeClass) {
        let s = stroke(points, closed);
        let report = classify_with(&s, &ClassifyOptions::default());
        assert_eq!(report.class, want, "{report:#?}");
        assert_eq!(classify(&s), want);
    }

    #[test]
    fn ellipses_and_arcs_are_features() {
        let c = DVec2::new(500.0, 300.0);
        // Full ellipse, closed and open with a small gap.
        assert_class(
            ellipse(c, 200.0, 60.0, 0.1, 0.0, TAU * 0.98, 80),
            true,
            StrokeClass::Feature,
        );
        assert_class(
            ellipse(c, 200.0, 60.0, 0.1, 0.0, TAU * 0.95, 80),
            false,
            StrokeClass::Feature,
        );
        // Half ellipse (the front of a cylinder's base), flat and round.
        assert_class(
            ellipse(c, 200.0, 60.0, 0.0, 0.0, PI, 50),
            false,
            StrokeClass::Feature,
        );
        assert_class(
            ellipse(c, 200.0, 50.0, 0.0, 0.0, PI, 50),
            false,
            StrokeClass::Feature,
        );
        assert_class(
            ellipse(c, 80.0, 70.0, 1.0, 0.0, PI, 50),
            false,
            StrokeClass::Feature,
        );
        // A 130° arc of a fairly round ellipse.
        assert_class(
            ellipse(c, 100.0, 70.0, 0.3, 1.0, 1.0 + 130f64.to_radians(), 40),
            false,
            StrokeClass::Feature,
        );
    }

    #[test]
    fn wobbly_hand_drawn_ellipse_is_a_feature() {
        // Jitter of about 1 % of the major axis and a slightly overlapping end.
        let points: Vec<DVec2> = ellipse(DVec2::ZERO, 150.0, 50.0, -0.4, 0.2, 0.2 + TAU * 1.04, 90)
            .into_iter()
            .enumerate()
            .map(|(i, p)| {
                let i = i as f64;
                p + DVec2::new(1.5 * (i * 1.7).sin(), 1.5 * (i * 2.3).cos())
            })
            .collect();
        assert_class(points, false, StrokeClass::Feature);
    }

    #[test]
    fn lines_and_curves_are_silhouettes() {
        // Straight line.
        let line: Vec<DVec2> = (0..30)
            .map(|i| DVec2::new(f64::from(i) * 10.0, f64::from(i) * 3.0))
            .collect();
        let report = classify_with(&stroke(line.clone(), false), &ClassifyOptions::default());
        assert_eq!(report.reason, ClassReason::Straight, "{report:#?}");
        // A slightly curved silhouette: a 30° arc of a circle.
        assert_class(
            ellipse(
                DVec2::ZERO,
                1000.0,
                1000.0,
                0.0,
                1.0,
                1.0 + 30f64.to_radians(),
                40,
            ),
            false,
            StrokeClass::Silhouette,
        );
        // A gently bulging side (a sine hump), as on a vase or a goblet's bowl.
        let hump: Vec<DVec2> = (0..50)
            .map(|i| {
                let t = f64::from(i) / 49.0;
                DVec2::new(40.0 * (PI * t).sin(), 400.0 * t)
            })
            .collect();
        assert_class(hump, false, StrokeClass::Silhouette);
        // S-curve: two opposite half circles.
        let mut s_curve = ellipse(DVec2::new(0.0, 0.0), 50.0, 50.0, 0.0, PI, 0.0, 30);
        s_curve.extend(
            ellipse(DVec2::new(100.0, 0.0), 50.0, 50.0, 0.0, PI, TAU, 30)
                .into_iter()
                .skip(1),
        );
        let report = classify_with(&stroke(s_curve, false), &ClassifyOptions::default());
        assert_eq!(report.class, StrokeClass::Silhouette, "{report:#?}");
        // Zigzag.
        let zigzag: Vec<DVec2> = (0..20)
            .map(|i| DVec2::new(f64::from(i) * 10.0, if i % 2 == 0 { 0.0 } else { 25.0 }))
            .collect();
        assert_class(zigzag, false, StrokeClass::Silhouette);
        // A square drawn as one closed stroke (a box face).
        let square = vec![
            DVec2::ZERO,
            DVec2::new(100.0, 0.0),
            DVec2::new(100.0, 100.0),
            DVec2::new(0.0, 100.0),
        ];
        assert_class(square, true, StrokeClass::Silhouette);
    }

    #[test]
    fn degenerate_strokes_are_silhouettes() {
        let two = vec![DVec2::ZERO, DVec2::new(5.0, 1.0)];
        assert_class(two, false, StrokeClass::Silhouette);
        let report = classify_with(
            &stroke(vec![DVec2::ONE], false),
            &ClassifyOptions::default(),
        );
        assert_eq!(report.reason, ClassReason::TooFewPoints);
        let report = classify_with(
            &stroke(vec![DVec2::ONE; 4], true),
            &ClassifyOptions::default(),
        );
        assert_eq!(report.reason, ClassReason::TooFewPoints);
        let report = classify_with(&stroke(vec![], false), &ClassifyOptions::default());
        assert_eq!(report.class, StrokeClass::Silhouette);
        let nan = vec![
            DVec2::NAN,
            DVec2::ZERO,
            DVec2::X,
            DVec2::new(f64::INFINITY, 0.0),
        ];
        assert_eq!(classify(&stroke(nan, false)), StrokeClass::Silhouette);
    }

    #[test]
    fn override_wins() {
        let mut s = stroke(ellipse(DVec2::ZERO, 10.0, 5.0, 0.0, 0.0, TAU, 40), true);
        assert_eq!(effective_class(&s), StrokeClass::Feature);
        s.class_override = Some(StrokeClass::Silhouette);
        assert_eq!(effective_class(&s), StrokeClass::Silhouette);
        let sketch = Sketch {
            strokes: vec![s.clone()],
            view_box: None,
        };
        let report = classify_sketch(&sketch, &ClassifyOptions::default());
        assert_eq!(report[0].reason, ClassReason::Override);
        assert_eq!(report[0].class, StrokeClass::Silhouette);
        assert!(
            report[0].ellipse.is_some(),
            "the evidence is still reported"
        );
        // classify itself ignores the override.
        assert_eq!(classify(&s), StrokeClass::Feature);
    }

    /// A cylinder drawn as two vertical sides and a shallow bottom arc (70° of a circle:
    /// too short an arc for the shape tests alone), the sides starting `gap` above the
    /// arc's ends.
    fn cylinder_bottom(sides_up: bool, gap: f64) -> Sketch {
        let arc = ellipse(
            DVec2::ZERO,
            100.0,
            100.0,
            0.0,
            55f64.to_radians(),
            125f64.to_radians(),
            30,
        );
        let (a, b) = (arc[0], arc[arc.len() - 1]);
        // The arc bulges towards +y; the sides leave towards −y (its concave side) or +y.
        let dir = if sides_up { -1.0 } else { 1.0 };
        let side = |p: DVec2| {
            vec![
                p + DVec2::new(0.0, dir * gap),
                p + DVec2::new(0.0, dir * (gap + 150.0)),
            ]
        };
        let mut strokes = vec![
            stroke(arc, false),
            stroke(side(a), false),
            stroke(side(b), false),
        ];
        for (i, s) in strokes.iter_mut().enumerate() {
            s.id = StrokeId(i as u32 + 10);
        }
        Sketch {
            strokes,
            view_box: None,
        }
    }

    #[test]
    fn shallow_arc_between_silhouettes_is_a_feature() {
        let options = ClassifyOptions::default();
        let sketch = cylinder_bottom(true, 3.0);
        let alone = classify_with(&sketch.strokes[0], &options);
        assert_eq!(alone.class, StrokeClass::Silhouette, "{alone:#?}");
        let report = classify_sketch(&sketch, &options);
        assert_eq!(
            report[0].reason,
            ClassReason::ArcBetweenSilhouettes,
            "{:#?}",
            report[0]
        );
        assert_eq!(report[0].class, StrokeClass::Feature);
        assert_eq!(report[0].id, StrokeId(10));
        assert_eq!(report[1].reason, ClassReason::Straight);
        // Sides leaving towards the bulge: not the end of a cylinder.
        let report = classify_sketch(&cylinder_bottom(false, 3.0), &options);
        assert_eq!(report[0].class, StrokeClass::Silhouette, "{:#?}", report[0]);
        // Sides too far from the arc's ends.
        let report = classify_sketch(&cylinder_bottom(true, 80.0), &options);
        assert_eq!(report[0].class, StrokeClass::Silhouette, "{:#?}", report[0]);
        // One side overridden as a feature: only one silhouette meets the arc.
        let mut sketch = cylinder_bottom(true, 3.0);
        sketch.strokes[2].class_override = Some(StrokeClass::Feature);
        let report = classify_sketch(&sketch, &options);
        assert_eq!(report[0].class, StrokeClass::Silhouette, "{:#?}", report[0]);
    }

    #[test]
    fn the_index_of_neighbours_changes_no_class() {
        // Copies of the scenes of the neighbour rules (a cylinder's bottom arc between
        // its sides, a bowl under its rim, a bent tube's two outlines) on a grid, with
        // arcs, ellipses and lines scattered among them.
        let mut seed = 5u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut strokes: Vec<Stroke> = Vec::new();
        for k in 0..12 {
            let at = DVec2::new(f64::from(k % 4) * 450.0, f64::from(k / 4) * 450.0);
            let mut scene = cylinder_bottom(k % 2 == 0, 3.0).strokes;
            for s in &mut scene {
                s.points
                    .iter_mut()
                    .for_each(|p| *p += at + DVec2::new(0.0, 250.0));
            }
            scene.push(stroke(ellipse(at, 100.0, 30.0, 0.0, 0.0, TAU, 64), true));
            scene.push(stroke(ellipse(at, 100.0, 120.0, 0.0, PI, TAU, 64), false));
            scene.push(stroke(ellipse(at, 200.0, 120.0, 0.0, 0.0, PI, 60), false));
            scene.push(stroke(ellipse(at, 170.0, 90.0, 0.0, 0.0, PI, 60), false));
            for _ in 0..10 {
                let c = at + DVec2::new(next(), next()) * 400.0 - 200.0;
                let (a, b, angle) = (10.0 + 80.0 * next(), 10.0 + 80.0 * next(), 6.0 * next());
                let from = 6.0 * next();
                let sweep = if next() < 0.3 {
                    TAU
                } else {
                    0.5 + 2.5 * next()
                };
                scene.push(stroke(
                    ellipse(c, a, b, angle, from, from + sweep, 24),
                    false,
                ));
                scene.push(stroke(vec![c, c + DVec2::from_angle(angle) * a], false));
            }
            strokes.extend(scene);
        }
        for (i, s) in strokes.iter_mut().enumerate() {
            s.id = StrokeId(i as u32);
        }
        let sketch = Sketch {
            strokes,
            view_box: None,
        };
        let options = ClassifyOptions::default();
        let indexed = classify_among(&sketch, &options, true);
        assert_eq!(indexed, classify_among(&sketch, &options, false));
        for reason in [
            ClassReason::ArcBetweenSilhouettes,
            ClassReason::OutlineUnderRim,
            ClassReason::ParallelOutline,
        ] {
            assert!(
                indexed.iter().any(|c| c.reason == reason),
                "the scenes exercise {reason:?}"
            );
        }
    }

    #[test]
    fn sides_leaving_a_corner_apart_do_not_make_an_arc() {
        // The same shallow arc, but the sides leave its ends 40° either side of
        // vertical (80° apart), as two edges of a box would.
        let mut sketch = cylinder_bottom(true, 3.0);
        for (k, sign) in [(1, -1.0), (2, 1.0)] {
            let start = sketch.strokes[k].points[0];
            let dir = DVec2::new(sign * 40f64.to_radians().sin(), -40f64.to_radians().cos());
            sketch.strokes[k].points = vec![start, start + 150.0 * dir];
        }
        let report = classify_sketch(&sketch, &ClassifyOptions::default());
        assert_eq!(report[0].class, StrokeClass::Silhouette, "{:#?}", report[0]);
    }

    #[test]
    fn a_bowls_outline_under_its_rim_is_a_silhouette() {
        // A closed rim ellipse (100 × 30); under it, hanging from its ends, a U of
        // another shape (100 × 120: a bowl), or the same shape 10 lower (a disc's rim).
        let rim = ellipse(DVec2::ZERO, 100.0, 30.0, 0.0, 0.0, TAU, 64);
        let bowl = ellipse(DVec2::ZERO, 100.0, 120.0, 0.0, PI, TAU, 64);
        let disc = ellipse(DVec2::new(0.0, -10.0), 100.0, 30.0, 0.0, PI, TAU, 64);
        let sketch = |under: Vec<DVec2>| Sketch {
            strokes: vec![stroke(rim.clone(), true), {
                let mut s = stroke(under, false);
                s.id = StrokeId(1);
                s
            }],
            view_box: None,
        };
        let options = ClassifyOptions::default();
        let report = classify_sketch(&sketch(bowl), &options);
        assert_eq!(report[0].class, StrokeClass::Feature, "{:#?}", report[0]);
        assert_eq!(
            report[1].reason,
            ClassReason::OutlineUnderRim,
            "{:#?}",
            report[1]
        );
        assert_eq!(report[1].class, StrokeClass::Silhouette);
        let report = classify_sketch(&sketch(disc), &options);
        assert_eq!(report[1].class, StrokeClass::Feature, "{:#?}", report[1]);
    }

    #[test]
    fn the_two_outlines_of_a_bent_tube_are_silhouettes() {
        // Two concentric half ellipses 15 % apart (a bent tube), and a lone one.
        let outer = ellipse(DVec2::ZERO, 200.0, 120.0, 0.0, 0.0, PI, 60);
        let inner = ellipse(DVec2::ZERO, 170.0, 90.0, 0.0, 0.0, PI, 60);
        let lone = ellipse(DVec2::new(1000.0, 0.0), 200.0, 120.0, 0.0, 0.0, PI, 60);
        let mut sketch = Sketch {
            strokes: vec![
                stroke(outer, false),
                stroke(inner, false),
                stroke(lone, false),
            ],
            view_box: None,
        };
        for (i, s) in sketch.strokes.iter_mut().enumerate() {
            s.id = StrokeId(i as u32);
        }
        let report = classify_sketch(&sketch, &ClassifyOptions::default());
        assert_eq!(
            report[0].reason,
            ClassReason::ParallelOutline,
            "{:#?}",
            report[0]
        );
        assert_eq!(
            report[1].reason,
            ClassReason::ParallelOutline,
            "{:#?}",
            report[1]
        );
        assert_eq!(report[2].reason, ClassReason::Ellipse, "{:#?}", report[2]);
        // The back and front halves of one ellipse are not a tube.
        let front = ellipse(DVec2::ZERO, 200.0, 80.0, 0.0, 0.0, PI, 60);
        let back = ellipse(DVec2::ZERO, 200.0, 80.0, 0.0, PI, TAU, 60);
        let halves = Sketch {
            strokes: vec![stroke(front, false), stroke(back, false)],
            view_box: None,
        };
        let report = classify_sketch(&halves, &ClassifyOptions::default());
        assert!(
            report.iter().all(|c| c.class == StrokeClass::Feature),
            "{report:#?}"
        );
    }

    #[test]
    fn invariant_under_similarity_transforms() {
        let points = ellipse(
            DVec2::new(3.0, 4.0),
            20.0,
            9.0,
            0.7,
            0.5,
            0.5 + 200f64.to_radians(),
            40,
        );
        let base = classify_with(&stroke(points.clone(), false), &ClassifyOptions::default());
        for (scale, rotation, shift) in [
            (1e-3, 0.0, DVec2::ZERO),
            (1e4, 2.0, DVec2::new(1e5, -3e4)),
            (1.0, -1.0, DVec2::X),
        ] {
            let r = DVec2::from_angle(rotation);
            let moved: Vec<DVec2> = points
                .iter()
                .map(|&p| r.rotate(p) * scale + shift)
                .collect();
            let report = classify_with(&stroke(moved, false), &ClassifyOptions::default());
            assert_eq!(report.class, base.class);
            assert!(
                (report.relative_residual.unwrap() - base.relative_residual.unwrap()).abs() < 1e-6
            );
            assert!((report.turning - base.turning).abs() < 1e-9);
        }
    }
}
