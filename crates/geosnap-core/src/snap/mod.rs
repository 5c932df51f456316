//! Snapping: curve assignment and the per-primitive fit, and the session that serves a
//! drag frame by frame.
//!
//! A snap alternates assignment and fitting, as ICP does: strokes are assigned with a
//! wide gate around the dropped pose (30 % of the primitive's size, which covers the
//! error of a hand placement), the primitive is fitted, then strokes are re-assigned with
//! a tight gate (10 %) around the fitted pose and the fit is refined; a third round runs
//! only if the assignment changed. [`snap`] does one snap; [`SnapSession`] serves a drag,
//! warm-starting each frame from the last (a warm frame stops after its first fit when the
//! tight gate takes the same strokes).

mod assign;
mod bgc_start;
mod confidence;
mod context;
mod copies;
mod cut;
mod divisions;
mod holds;
pub(crate) mod initial;
mod objective;
mod pieces;
mod point;
mod region;
mod slant;
mod spread;
mod swallowed;

use glam::{DVec2, DVec3};
use thiserror::Error;

pub use assign::{
    assign, restore_assignment, stroke_samples, AssignedStroke, Assignment, CurveStrokes,
    RestoreError,
};
pub use confidence::{judge, nobody, Confidence, Evidence, Owner, Verdict};
pub use context::{Prepared, SnapContext, SnapStroke};
pub use objective::{build_problem, fit_rms, fit_terms, FitTerms, Frame, Profile};
pub use point::{guesses, snap_at, snap_at_with, PointSnap, CENTRE_REACH, DISC_LENGTH, RUNGS};
pub(crate) use spread::spread as spread_of;
pub use spread::{Dimension, Spread};

use crate::primitive::{Curve2, CurveClass, Primitive, PrimitiveKind};
use crate::solve::{
    AugLagSettings, Multipliers, SettingsError, SolveContext, SolveError, SolveReport, Solver,
    Start, Termination,
};

/// Why a primitive could not be snapped.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum SnapError {
    /// Too few strokes near the primitive to determine it.
    #[error("not enough strokes near the {kind}: {found}")]
    NotEnoughStrokes {
        /// The kind.
        kind: &'static str,
        /// What was found, in words.
        found: String,
    },
    /// The placement or the fit is not finite.
    #[error("the {0} has non-finite parameters")]
    NonFinite(&'static str),
    /// The fit ran away from the drop: its size changed by more than [`MAX_SIZE_CHANGE`]
    /// times (strokes that do not describe one such part, such as a drawing that
    /// contradicts itself).
    #[error("the {kind} fit ran away (its size changed {factor:.1}×): the strokes near it do not describe one {kind}")]
    RanAway {
        /// The kind.
        kind: &'static str,
        /// The fitted size over the dropped size.
        factor: f64,
    },
    /// The snap was cancelled.
    #[error("cancelled")]
    Cancelled,
}

/// Settings of snapping; the defaults are those documented in the module. Made by
/// [`SnapSettings::new`], which checks them.
#[derive(Clone, Debug, PartialEq)]
pub struct SnapSettings {
    wide_gate: f64,
    tight_gate: f64,
    solver: AugLagSettings,
    /// How a bent tube's radii are held in the fits (a cold snap tries both).
    profile: Profile,
}

impl SnapSettings {
    /// Settings with a first, wide assignment gate `wide_gate` and a refined one
    /// `tight_gate`, both relative to the primitive's size, and the `solver` settings of
    /// each fit.
    ///
    /// # Errors
    ///
    /// [`SettingsError::NotPositive`] for a gate that is not finite and above zero,
    /// [`SettingsError::OutOfRange`] for a tight gate wider than the wide one.
    pub fn new(
        wide_gate: f64,
        tight_gate: f64,
        solver: AugLagSettings,
    ) -> Result<Self, SettingsError> {
        for (name, value) in [("wide_gate", wide_gate), ("tight_gate", tight_gate)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(SettingsError::NotPositive { name, value });
            }
        }
        if tight_gate > wide_gate {
            return Err(SettingsError::OutOfRange {
                name: "tight_gate",
                value: tight_gate,
                range: "(0, wide_gate]",
            });
        }
        Ok(Self {
            wide_gate,
            tight_gate,
            solver,
            profile: Profile::Smooth,
        })
    }

    /// The first, wide assignment gate, relative to the primitive's size.
    pub fn wide_gate(&self) -> f64 {
        self.wide_gate
    }

    /// The refined assignment gate, relative to the primitive's size.
    pub fn tight_gate(&self) -> f64 {
        self.tight_gate
    }

    /// The solver settings of each fit.
    pub fn solver(&self) -> &AugLagSettings {
        &self.solver
    }
}

impl Default for SnapSettings {
    fn default() -> Self {
        let solver = AugLagSettings::default()
            .with_constraint_tol(1e-7)
            .and_then(|s| s.with_gradient_tol(1e-7))
            .and_then(|s| s.with_max_outer_iterations(40))
            .and_then(|s| s.with_max_evaluations(4000))
            .unwrap_or_default();
        Self {
            wide_gate: 0.3,
            tight_gate: 0.1,
            solver,
            profile: Profile::Smooth,
        }
    }
}

/// A snapped primitive: the result of a snap or of one drag frame.
#[derive(Clone, Debug, PartialEq)]
pub struct SnapResult {
    /// The fitted primitive, in model space.
    pub primitive: Primitive,
    /// The strokes assigned to each projected curve (at the fitted pose).
    pub assignment: Assignment,
    /// RMS distance of the assigned stroke samples to their curves, in sketch units.
    pub rms: f64,
    /// How the last fit ended.
    pub termination: Termination,
    /// Solver iterations and evaluations over all rounds.
    pub evaluations: u64,
    /// How much of the drawing it explains, as a length in view units: the stroke length
    /// it takes, weighted by closeness, less its visible outline where nothing is drawn.
    /// Computed for cold snaps, which are compared with other readings.
    pub explained: Option<f64>,
    /// The other readings of the drawing a cold snap found (poses whose outline differs
    /// from this one's), best first; empty for a warm drag frame.
    pub alternatives: Vec<Alternative>,
    /// How its fit held a bent tube's radii: as drawn where that fits its strokes clearly
    /// closer than smooth (see [`Profile`]); what a later fit of the part (a drag frame,
    /// the global solve) holds them to.
    pub profile: Profile,
    /// The last fit's multipliers, for a warm start.
    multipliers: Option<Multipliers>,
}

/// Another reading of the drawing that a snap found and did not choose.
#[derive(Clone, Debug, PartialEq)]
pub struct Alternative {
    /// The fitted primitive.
    pub primitive: Primitive,
    /// Its strokes per projected curve.
    pub assignment: Assignment,
    /// Its fit RMS in sketch units.
    pub rms: f64,
    /// How much of the drawing it explains (see [`SnapResult::explained`]).
    pub explained: f64,
    /// How far its outline lies from the chosen snap's, relative to the size.
    pub distance: f64,
    /// How its fit held a bent tube's radii (see [`SnapResult::profile`]).
    pub profile: Profile,
}

impl SnapResult {
    /// The snap's confidence (see [`judge`]), with `owner` telling which part placed
    /// before owns a stroke, if any, and the drop it was snapped from. A stroke supports
    /// a curve within the tight gate of the smaller of the snapped and dropped sizes.
    pub fn confidence(
        &self,
        dropped: &Primitive,
        owner: &dyn Owner,
        settings: &SnapSettings,
    ) -> Confidence {
        // A snap that grew is held to the scale it was dropped at: its own size would
        // widen the gate within which strokes count as drawing its outline.
        let scale = self.primitive.size().min(dropped.size());
        judge(self, dropped, owner, settings.tight_gate * scale)
    }

    /// This snap with its alternative number `index` chosen instead (the snap it was
    /// becomes the first alternative): for cycling through the readings a snap found.
    /// `None` when there is no such alternative.
    pub fn with_alternative(&self, index: usize) -> Option<Self> {
        let alt = self.alternatives.get(index)?;
        let mut alternatives = self.alternatives.clone();
        alternatives.remove(index);
        alternatives.insert(
            0,
            Alternative {
                primitive: self.primitive.clone(),
                assignment: self.assignment.clone(),
                rms: self.rms,
                explained: self.explained.unwrap_or(0.0),
                distance: alt.distance,
                profile: self.profile,
            },
        );
        for a in alternatives.iter_mut().skip(1) {
            a.distance = confidence::outline_distance(&alt.primitive, &a.primitive);
        }
        Some(Self {
            primitive: alt.primitive.clone(),
            assignment: alt.assignment.clone(),
            rms: alt.rms,
            termination: self.termination,
            evaluations: self.evaluations,
            explained: Some(alt.explained),
            alternatives,
            profile: alt.profile,
            multipliers: None,
        })
    }
}

/// A cold snap with how much of the drawing it explains (see [`explanation`]), for
/// choosing between the snaps of one drop. Warm drag frames are never compared, so they
/// skip the score.
struct Scored {
    result: SnapResult,
    explained: f64,
    /// The pieces the reading swallows (see [`swallowed`]), each with its distance to
    /// the reading's curves ([`swallowed::swallowed_pieces`]), for weighing it against
    /// another reading beyond one band.
    pieces: Vec<(f64, f64)>,
    /// The lines it swallows that run across it from outline to outline
    /// ([`divisions::divisions`]): where two parts read as one meet.
    divisions: Vec<Vec<DVec2>>,
    /// The gate the explanation was weighed with: a length of stroke that tells readings
    /// apart.
    gate: f64,
    /// Whether it holds a part placed before it (see [`holds`]): it reads that part and
    /// its neighbours as one.
    holds: bool,
    /// Whether it is a part placed before read again ([`repeats_placed`]).
    repeats: bool,
}

impl Scored {
    /// Whether the model contradicts it: it holds a placed part or reads one again. No
    /// designer models a part twice, or as a piece of one modelled before.
    fn reads_placed(&self) -> bool {
        self.holds || self.repeats
    }
}

impl Scored {
    /// `result` scored at the smaller of its size and the `dropped` size: a snap that
    /// grew must not widen the gate within which strokes count for it (as its confidence
    /// is judged, see [`SnapResult::confidence`]).
    fn of(
        context: &SnapContext,
        result: SnapResult,
        dropped: f64,
        settings: &SnapSettings,
    ) -> Self {
        Self::behind(context, result, &[], dropped, settings)
    }

    /// [`Scored::of`] for a reading whose curves marked in `hidden` (by index in its
    /// shape) run behind another part: a curve hidden there is not missed where nothing
    /// is drawn along it.
    fn behind(
        context: &SnapContext,
        mut result: SnapResult,
        hidden: &[bool],
        dropped: f64,
        settings: &SnapSettings,
    ) -> Self {
        let gate = settings.tight_gate * result.primitive.size().min(dropped);
        let band = swallow_band(&result);
        let explained = explanation(&result.primitive, &result.assignment, gate, hidden);
        result.explained = Some(explained);
        let holds = holds_placed(context, &result.primitive, band);
        let repeats = repeats_placed(context, &result.primitive, band);
        let pieces =
            swallowed::swallowed_pieces(context, &result.primitive, &result.assignment, band);
        let swallowed = swallowed::beyond(&pieces, band);
        // Only a reading that swallows something is searched for lines across it, the
        // cheaper test first: searching every reading found the same parts on the
        // conditions suite, give or take one.
        let divisions = if swallowed > 0.0 {
            divisions::divisions(
                context,
                &result.primitive,
                &result.assignment,
                (band, band + gate),
            )
        } else {
            Vec::new()
        };
        Self {
            result,
            explained,
            pieces,
            divisions,
            gate,
            holds,
            repeats,
        }
    }
}

/// The best of `candidates` (see [`better`]) with the others that read the drawing
/// differently as its alternatives, best first (good fits first, then by explanation);
/// a candidate whose outline nearly coincides with a kept one's is the same reading.
fn choose(candidates: Vec<Scored>) -> Option<SnapResult> {
    let mut best: Option<Scored> = None;
    let mut rest = Vec::with_capacity(candidates.len());
    for c in candidates {
        match best.take() {
            None => best = Some(c),
            Some(b) if better(&c, &b) => {
                rest.push(b);
                best = Some(c);
            }
            Some(b) => {
                rest.push(c);
                best = Some(b);
            }
        }
    }
    let best = best?;
    // A reading the winner divides is contradicted by the drawing (a line runs across
    // it), not a rival reading of it.
    rest.retain(|c| !divides(&best, c));
    // So is one that holds a placed part or reads one again, when the winner does
    // neither (see [`better`]): the model contradicts it, and it is neither offered nor
    // weighed as a rival.
    if !best.reads_placed() {
        rest.retain(|c| !c.reads_placed());
    }
    let mut best = best.result;
    rest.sort_by(|a, b| {
        good(&b.result)
            .cmp(&good(&a.result))
            .then(b.explained.total_cmp(&a.explained))
    });
    let mut alternatives: Vec<Alternative> = Vec::new();
    for c in rest {
        let distance = confidence::outline_distance(&best.primitive, &c.result.primitive);
        let seen = distance <= confidence::DISTINCT
            || alternatives.iter().any(|a| {
                confidence::outline_distance(&a.primitive, &c.result.primitive)
                    <= confidence::DISTINCT
            });
        if seen || !c.result.primitive.is_finite() {
            continue;
        }
        alternatives.push(Alternative {
            primitive: c.result.primitive,
            assignment: c.result.assignment,
            rms: c.result.rms,
            explained: c.explained,
            distance,
            profile: c.result.profile,
        });
        if alternatives.len() == MAX_ALTERNATIVES {
            break;
        }
    }
    best.alternatives = alternatives;
    Some(best)
}

/// The index of the candidate [`choose`] would pick.
fn leader_index(candidates: &[Scored]) -> Option<usize> {
    (0..candidates.len()).reduce(|best, i| {
        if better(&candidates[i], &candidates[best]) {
            i
        } else {
            best
        }
    })
}

/// The leader of a cold snap's `candidates` read again ([`reread_leader`]), then cut where
/// it holds lines drawn inside it ([`cut_candidates`]); a cut that leads is read again in
/// turn.
fn settle_leader(
    context: &SnapContext,
    primitive: &Primitive,
    settings: &SnapSettings,
    candidates: &mut Vec<Scored>,
    mut solve: SolveContext<'_>,
) -> Result<(), SnapError> {
    reread_leader(context, primitive, settings, candidates, solve.reborrow())?;
    if cut_candidates(context, primitive, settings, candidates, solve.reborrow())? {
        reread_leader(context, primitive, settings, candidates, solve)?;
    }
    Ok(())
}

/// Snaps the cuts of the leading candidate of a cold snap of `primitive` at the straight
/// lines drawn inside it, away from its curves (see [`cut`]: two alike parts read as
/// one), into `candidates`, each from its cut as a pose read off the drawing is (the
/// tight gate), scored as the others are. A cut that then leads is cut again, up to
/// [`cut::CUT_ROUNDS`] in all. Returns whether a cut leads.
fn cut_candidates(
    context: &SnapContext,
    primitive: &Primitive,
    settings: &SnapSettings,
    candidates: &mut Vec<Scored>,
    mut solve: SolveContext<'_>,
) -> Result<bool, SnapError> {
    let read = SnapSettings {
        wide_gate: settings.tight_gate,
        ..settings.clone()
    };
    // A cut that leads may still hold a line (a blade drawn twice over): it is cut again.
    let (first, mut from) = (candidates.len(), 0);
    for _ in 0..cut::CUT_ROUNDS {
        let Some(lead) = leader_index(candidates).filter(|i| *i >= from) else {
            break;
        };
        let leader = &candidates[lead];
        let r = &leader.result;
        // The pieces a neighbour in front hides in part are read as cut too (below).
        let (starts, behind) = cut::cuts_and_pieces(
            context,
            &r.primitive,
            &r.assignment,
            primitive,
            (swallow_band(r), leader.gate),
        );
        from = candidates.len();
        for (piece, hidden) in behind {
            if let Some(result) = as_cut(context, &piece, &hidden, settings) {
                let scored = Scored::behind(context, result, &hidden, primitive.size(), settings);
                candidates.push(scored);
            }
        }
        for start in starts {
            match snap_rounds(context, &start, &read, None, solve.reborrow()) {
                Err(SnapError::Cancelled) => return Err(SnapError::Cancelled),
                Ok(r) => candidates.push(Scored::of(context, r, primitive.size(), settings)),
                Err(_) => {}
            }
        }
    }
    Ok(leader_index(candidates).is_some_and(|i| i >= first))
}

/// A piece of a reading cut at a line drawn across it, as cut: unfitted, its strokes taken
/// at the tight gate by its curves but those marked `hidden` (by the rest of the reading
/// in front of it, see [`cut::pieces_behind`]). Fitted, such a piece is pulled out of
/// shape: the edges the rest hides, where nothing of its own is drawn, take the rest's
/// strokes. As cut, it lies where the divided reading's fit and the line put it. `None`
/// when its curves take too few strokes to make a part.
fn as_cut(
    context: &SnapContext,
    piece: &Primitive,
    hidden: &[bool],
    settings: &SnapSettings,
) -> Option<SnapResult> {
    let tight = settings.tight_gate * piece.size();
    let curves = piece.current_shape().curves;
    let seen: Vec<_> = curves
        .iter()
        .zip(hidden)
        .filter(|(_, h)| !**h)
        .map(|(c, _)| c.clone())
        .collect();
    let mut taken = assign::assign_within(context, &seen, tight, true)
        .curves
        .into_iter();
    let assignment = Assignment {
        curves: hidden
            .iter()
            .map(|h| {
                if *h {
                    Vec::new()
                } else {
                    taken.next().unwrap_or_default()
                }
            })
            .collect(),
    };
    check_enough(piece, &assignment).ok()?;
    let rms = fit_rms(piece, &assignment);
    Some(SnapResult {
        primitive: piece.clone(),
        assignment,
        rms,
        termination: Termination::Converged,
        evaluations: 0,
        explained: None,
        alternatives: Vec::new(),
        profile: settings.profile,
        multipliers: None,
    })
}

/// Reads the leading candidate of a cold snap of `primitive` again from where it ended
/// (see [`rereads`]). A reread takes the leader's place where the strokes clearly prefer
/// it ([`clearly_better`]): it is the leader's reading read better, not a rival to it
/// (kept beside it, the leader it replaced stood as an alternative explaining about as
/// much, and the snap doubted itself against its own earlier fit). Otherwise the leader
/// stays: the reread is the same reading, up to the hand's noise.
fn reread_leader(
    context: &SnapContext,
    primitive: &Primitive,
    settings: &SnapSettings,
    candidates: &mut [Scored],
    mut solve: SolveContext<'_>,
) -> Result<(), SnapError> {
    let Some(lead) = leader_index(candidates) else {
        return Ok(());
    };
    let reread = SnapSettings {
        wide_gate: settings.tight_gate,
        ..guess_settings(settings)
    };
    for start in rereads(&candidates[lead].result.primitive) {
        match snap_rounds(context, &start, &reread, None, solve.reborrow()) {
            Err(SnapError::Cancelled) => return Err(SnapError::Cancelled),
            Ok(r) => {
                let scored = Scored::of(context, r, primitive.size(), settings);
                if clearly_better(&scored, &candidates[lead]) {
                    candidates[lead] = scored;
                }
            }
            Err(_) => {}
        }
    }
    Ok(())
}

/// The poses from which the leading snap is read again, at the tight gate: the pose it
/// ended at and, for a box, the pose mirrored in depth.
///
/// A fit that starts from a rough drop takes its strokes within the wide gate, and the
/// rounds that narrow the gate may keep what it took on the way. Read afresh from where
/// it ended, its strokes are taken within the tight gate from the start. A box's mirror
/// image in depth draws the same outline with its other faces towards the viewer and
/// other edges hidden (the Necker reversal), so its strokes may read the other way; a
/// solid of revolution's mirror draws the very same curves. On the conditions suite
/// the rereads recovered 40 parts and lost none: 31 boxes (plug bodies and blades,
/// boxes with pipes, table tops), 6 cylinders, 2 generalized cylinders and a cone. A
/// bent tube's starts already read both tilts of its plane ([`bgc_start`]); a sphere is
/// read by its one outline.
fn rereads(snapped: &Primitive) -> Vec<Primitive> {
    match snapped.kind() {
        PrimitiveKind::Sphere | PrimitiveKind::Bgc => Vec::new(),
        PrimitiveKind::Cuboid => vec![snapped.clone(), snapped.mirrored_in_depth()],
        _ => vec![snapped.clone()],
    }
}

/// A snap keeps at most this many alternatives.
const MAX_ALTERNATIVES: usize = 3;

/// Checks that an assignment determines the primitive (the original's `CanSnap`, but
/// checked before every fit rather than ignored on release).
fn check_enough(primitive: &Primitive, assignment: &Assignment) -> Result<(), SnapError> {
    let shape = primitive.current_shape();
    let assigned = |class: CurveClass| {
        shape
            .curves
            .iter()
            .zip(&assignment.curves)
            .filter(|(c, a)| c.class == class && !a.is_empty())
            .count()
    };
    let (features, silhouettes, edges) = (
        assigned(CurveClass::Feature),
        assigned(CurveClass::Silhouette),
        assigned(CurveClass::Edge),
    );
    let enough = match primitive.kind() {
        PrimitiveKind::Sphere => features + silhouettes >= 1,
        PrimitiveKind::Cuboid => edges >= 3,
        PrimitiveKind::Bgc => silhouettes >= 2,
        PrimitiveKind::Cylinder | PrimitiveKind::Cone | PrimitiveKind::Sgc => {
            silhouettes >= 1 && silhouettes + features >= 2 || features >= 2
        }
    };
    if enough {
        Ok(())
    } else {
        Err(SnapError::NotEnoughStrokes {
            kind: primitive.kind().name(),
            found: format!(
                "{features} end ellipse(s), {silhouettes} outline(s), {edges} edge(s) matched"
            ),
        })
    }
}

/// One fit of `primitive` to the strokes of `assignment`, from `start` multipliers.
///
/// # Errors
///
/// The solver's [`SolveError`] when it cannot start (a non-finite primitive).
fn fit(
    primitive: &Primitive,
    assignment: &Assignment,
    settings: &SnapSettings,
    warm: Option<&Multipliers>,
    mut solve: SolveContext<'_>,
) -> Result<(Primitive, SolveReport), SolveError> {
    let frame = Frame::of(primitive);
    let local = frame.into_frame(primitive);
    let mut problem = build_problem(&local, assignment, &frame, settings.profile);
    let start = Start {
        x: local.params(),
        multipliers: warm
            .filter(|m| {
                m.equality.len() == problem.equality_count()
                    && m.inequality.len() == problem.inequality_count()
            })
            .cloned(),
        penalty: None,
    };
    let report =
        Solver::with_context(&settings.solver, solve.reborrow()).solve(&mut problem, &start)?;
    let fitted = frame.out_of_frame(&local.with_params(&report.x));
    Ok((fitted, report))
}

/// Snaps `primitive` (as dropped) to the strokes of `context`.
///
/// # Errors
///
/// [`SnapError::NotEnoughStrokes`] when the strokes near it do not determine it,
/// [`SnapError::NonFinite`] for a non-finite placement, [`SnapError::Cancelled`].
///
/// # Examples
///
/// ```
/// use glam::{DVec2, DVec3};
/// use geosnap_core::primitive::{Cylinder, Primitive};
/// use geosnap_core::sketch::{StrokeClass, StrokeId};
/// use geosnap_core::snap::{snap, SnapContext, SnapSettings};
///
/// // Two vertical lines 20 apart and 60 long: the outline of a side-on cylinder.
/// let line = |x: f64| (0..=20).map(|i| DVec2::new(x, 100.0 + 3.0 * f64::from(i))).collect::<Vec<_>>();
/// let (a, b) = (line(40.0), line(60.0));
/// let context = SnapContext::new([
///     (StrokeId(0), a.as_slice(), StrokeClass::Silhouette),
///     (StrokeId(1), b.as_slice(), StrokeClass::Silhouette),
/// ]);
/// // Dropped a little off, a little too big.
/// let dropped = Primitive::Cylinder(Cylinder {
///     center: DVec3::new(52.0, -128.0, 0.0),
///     axis: DVec3::Y,
///     length: 70.0,
///     radius: 12.0,
/// });
/// let result = snap(&context, &dropped, &SnapSettings::default())?;
/// let Primitive::Cylinder(c) = &result.primitive else { unreachable!() };
/// assert!((c.radius - 10.0).abs() < 0.2 && (c.center.x - 50.0).abs() < 0.2);
/// assert!((c.length - 60.0).abs() < 1.0);
/// # Ok::<(), geosnap_core::snap::SnapError>(())
/// ```
pub fn snap(
    context: &SnapContext,
    primitive: &Primitive,
    settings: &SnapSettings,
) -> Result<SnapResult, SnapError> {
    snap_from(context, primitive, settings, None, SolveContext::default())
}

/// [`snap`] with a warm start and the solves' context (cancel flag, clock).
fn snap_from(
    context: &SnapContext,
    primitive: &Primitive,
    settings: &SnapSettings,
    warm: Option<&Multipliers>,
    mut solve: SolveContext<'_>,
) -> Result<SnapResult, SnapError> {
    let kind = primitive.kind().name();
    if !primitive.is_finite() {
        return Err(SnapError::NonFinite(kind));
    }
    // A BGC's fit stops at looser gradient and constraint tolerances (see
    // `bgc_start::settings`): its many parameters make the last digits expensive, and
    // they move nothing visible.
    let bgc_settings;
    let settings = if primitive.kind() == PrimitiveKind::Bgc {
        bgc_settings = bgc_start::settings(settings);
        &bgc_settings
    } else {
        settings
    };
    // A cold BGC starts from the spine and tilt its drawing shows (see `bgc_start`); the
    // straight drop is tried only when that start gives no good fit.
    if warm.is_some() {
        return snap_rounds(context, primitive, settings, warm, solve);
    }
    let mut candidates: Vec<Scored> = Vec::new();
    let mut errors: Vec<SnapError> = Vec::new();
    bgc_candidates(
        context,
        primitive,
        settings,
        &mut candidates,
        &mut errors,
        solve.reborrow(),
    )?;
    if !candidates.iter().any(|c| good(&c.result)) {
        // No good fit from the drawn spine: the straight drop and the starting poses
        // compete alone, and the drop's error is the one reported when nothing snaps.
        candidates.clear();
        errors.clear();
        // The drop itself first (its error is the one reported when nothing snaps), then
        // the drop shrunk (see `shrunk_drop`), then the starting poses the drawing itself
        // suggests (see `initial`: the tilt of drawn end ellipses, the three edge
        // directions of a drawn box); the better snap wins (see `better`).
        // A pose read off the strokes is as close to them as the drawing is exact, not as
        // a hand's drop: its first assignment already takes the tight gate, so that the
        // strokes of parts next to a thin one (a table top's legs) are not taken.
        let read = SnapSettings {
            wide_gate: settings.tight_gate,
            ..settings.clone()
        };
        let mut starts = vec![(primitive.clone(), settings.clone())];
        starts.extend(shrunk_drop(context, primitive, settings));
        starts.extend(
            initial::starting_poses(context, primitive)
                .into_iter()
                .filter(Primitive::is_finite)
                .map(|start| (start, read.clone())),
        );
        for (start, settings) in &starts {
            match snap_rounds(context, start, settings, None, solve.reborrow()) {
                Err(SnapError::Cancelled) => return Err(SnapError::Cancelled),
                Ok(r) => candidates.push(Scored::of(context, r, primitive.size(), settings)),
                Err(e) => errors.push(e),
            }
        }
    }
    settle_leader(
        context,
        primitive,
        settings,
        &mut candidates,
        solve.reborrow(),
    )?;
    match choose(candidates) {
        Some(best) if best.primitive.kind() == PrimitiveKind::Bgc => {
            drawn_profile(context, best, primitive.size(), settings, solve)
        }
        Some(best) => Ok(best),
        None => Err(errors
            .into_iter()
            .next()
            .unwrap_or(SnapError::NotEnoughStrokes {
                kind,
                found: "no strokes".to_owned(),
            })),
    }
}

/// Snaps a dropped BGC from each start its drawing suggests (see [`bgc_start`]) into
/// `candidates` (or `errors`). A variant of a reading's start stands only where the
/// strokes clearly prefer it ([`clearly_better`]) to the reading's standing snap:
/// otherwise it is the same reading, up to the hand's noise. Nothing for another kind
/// or a BGC already bent.
fn bgc_candidates(
    context: &SnapContext,
    primitive: &Primitive,
    settings: &SnapSettings,
    candidates: &mut Vec<Scored>,
    errors: &mut Vec<SnapError>,
    mut solve: SolveContext<'_>,
) -> Result<(), SnapError> {
    // The candidate standing for the reading in hand (its first start's snap, or a
    // variant's that beat it), when one does: every variant of the reading is weighed
    // against it, not against whichever start came just before.
    let mut standing: Option<usize> = None;
    for start in bgc_start::starts(context, primitive) {
        if !start.is_variant() {
            standing = None;
        }
        match bgc_start::snap_start(context, &start, settings, solve.reborrow()) {
            Err(SnapError::Cancelled) => return Err(SnapError::Cancelled),
            Ok(r) => {
                let scored = Scored::of(context, r, primitive.size(), settings);
                if standing.is_none_or(|i| clearly_better(&scored, &candidates[i])) {
                    standing = Some(candidates.len());
                    candidates.push(scored);
                }
            }
            Err(e) => errors.push(e),
        }
    }
    Ok(())
}

/// `best`, a cold snap of a bent tube fitted with a smooth profile (dropped at size
/// `dropped`), refitted with its radii held as drawn ([`Profile::Drawn`]); the refit is
/// kept where it fits its strokes clearly closer ([`DRAWN_PROFILE_RMS`]): the outlines
/// then show a shape the smooth profile flattens (a horn's mouth), not the wobble of a
/// hand, which a looser profile follows for a percent or two of RMS and some percent of
/// radius.
fn drawn_profile(
    context: &SnapContext,
    best: SnapResult,
    dropped: f64,
    settings: &SnapSettings,
    solve: SolveContext<'_>,
) -> Result<SnapResult, SnapError> {
    let drawn = SnapSettings {
        profile: Profile::Drawn,
        ..settings.clone()
    };
    match snap_rounds(context, &best.primitive, &drawn, None, solve) {
        Ok(refit) if refit.rms < DRAWN_PROFILE_RMS * best.rms => {
            let mut refit = Scored::of(context, refit, dropped, settings).result;
            refit.alternatives = best.alternatives;
            Ok(refit)
        }
        Err(SnapError::Cancelled) => Err(SnapError::Cancelled),
        _ => Ok(best),
    }
}

/// A bent tube's radii held as drawn are kept where their fit's RMS is at most this
/// fraction of the smooth fit's. Measured on the synthetic bent tubes: tubes of one
/// radius or an even taper drawn by a hand refit to 0.98–1.0 of their RMS (0.85 at
/// least), flared ones down to 0.13 (a tenth of them below 0.67); kept at 0.9 or at 0.95
/// alike, the tapers keep their 95 % and the flared ones gain the same.
const DRAWN_PROFILE_RMS: f64 = 0.9;

/// The drop shrunk by [`SHRUNK_DROP`] and the settings to snap it with, when it reads
/// other strokes than the drop does. A hand sets a part's size only roughly, and a drop
/// made too big takes its neighbours' strokes into its wide gate and can settle on a
/// reading that spans them (a table leg on the next leg). The shrunk drop sees only the
/// strokes near its middle: a guess as good as the drop, snapped with a smaller budget
/// ([`GUESS_EVALUATIONS`]), its result competing with the others (see [`better`]).
fn shrunk_drop(
    context: &SnapContext,
    primitive: &Primitive,
    settings: &SnapSettings,
) -> Option<(Primitive, SnapSettings)> {
    let shrunk = primitive
        .transformed(-primitive.center(), SHRUNK_DROP)
        .transformed(primitive.center(), 1.0);
    let reads = |p: &Primitive| {
        assign(
            context,
            &p.current_shape().curves,
            settings.wide_gate * p.size(),
        )
    };
    if reads(&shrunk).same_strokes(&reads(primitive)) {
        return None;
    }
    Some((shrunk, guess_settings(settings)))
}

/// `settings` with the smaller evaluation budget of a guess ([`GUESS_EVALUATIONS`]).
fn guess_settings(settings: &SnapSettings) -> SnapSettings {
    SnapSettings {
        solver: settings
            .solver
            .clone()
            .with_max_evaluations(GUESS_EVALUATIONS)
            .unwrap_or_else(|_| settings.solver.clone()),
        ..settings.clone()
    }
}

/// The factor by which a cold drop is also shrunk before it is snapped (see
/// [`snap_from`]): a hand sets a part's size to within about a quarter. Only a smaller
/// guess is tried: a larger one reads more of the neighbours' strokes, and its wins
/// were as often a part swallowing its neighbours (a goblet's bowl taking its stem and
/// foot) as the part meant.
const SHRUNK_DROP: f64 = 0.8;

/// The evaluation budget of each fit from a shrunk drop: a converging snap takes 50–200
/// in all its rounds, and a guess that neither converges nor runs away must not cost a
/// drag frame tens of milliseconds (1,000 found the same parts).
const GUESS_EVALUATIONS: u64 = 400;

/// A snap may change the dropped size by at most this factor either way; beyond it the
/// fit has run away (see [`SnapError::RanAway`]).
pub const MAX_SIZE_CHANGE: f64 = 4.0;

/// A fit RMS above this fraction of the size is a failed fit, whatever it explains.
const GOOD_FIT: f64 = 0.05;

/// Whether snap `a` is better than snap `b` of the same drop: a good fit (RMS within
/// [`GOOD_FIT`] of the size) beats a bad one; between two good or two bad fits, a
/// reading divided by a line drawn across it loses to its piece on one side of the line
/// ([`divides`]), and otherwise the one that explains more of the drawing wins (see
/// [`explanation`]). Two that explain about as much (within a quarter of the size) tie:
/// one fitting at under [`SWALLOW_TIE_RMS`] of the other's RMS wins, then the one that
/// swallows clearly less of the drawing (by more than the explanation's gate, see
/// [`swallowed`]; both weighed beyond the wider of their two bands, see
/// [`swallowed::swallowed_pieces`]), then the closer one. A fit that
/// takes more strokes by bending itself out of shape loses to one that explains fewer
/// strokes well.
///
/// Before the explanations, a reading that holds a part placed before it (see
/// [`holds`]: the placed part is a piece of it, in the image and at some depth) or reads
/// one again ([`repeats_placed`]) gives way to one that does neither: no designer models
/// a part as a piece of one placed before, or twice. Two drawers of a chest read as one box explain more than the drawer meant
/// (the other's outline too); with the other drawer placed, the pair is read against the
/// model. On the conditions suite (10 cases and 2 assemblies per kind and condition,
/// the parts before each placed where they lie) rows of drawers went from 17 to 24 of 76
/// parts, the other kinds as before.
///
/// Each reading's band grows with its RMS ([`swallow_band`]). Weighed each within its
/// own band, a looser reading swallowed less for fitting worse: a brick read with one
/// of its studs' strokes on an edge (RMS 2.7 % of its size against 1.8 %) left its
/// studs' near strokes inside its wider band and won, for 2 of 10 hand drops on the
/// shared legobrick sketch. Weighed beyond one band, the shared sketches' parts stable
/// under perturbed drops went from 47 to 49 of 62 (the brick and a stud); the
/// conditions suite at 10 cases and 2 assemblies per kind and condition lost one part
/// of 1519 (a box's overshoots, a tee's rough drop lost; a bent tube drawn sketchily
/// gained).
///
/// A tie went to the closer fit alone before what a reading swallows was weighed: an arm
/// of a menorah read on through its stem to the other arm's inner end, whose whole drawn
/// ellipse fits more closely than its own end's arc, won over its own reading (RMS 1.21
/// against 1.41, explanations 674 and 657), leaving its own drawn end inside it. On the
/// conditions suite weighing what each swallows took assembly parts from 86.2 to 86.6 %
/// recovered (menorahs 78.1 → 79.4 %, handles 90.8 → 92.0 %).
fn better(a: &Scored, b: &Scored) -> bool {
    better_by(a, b, 1.0)
}

/// Whether `a` reads the drawing clearly better than `b`: as [`better`], but a closer
/// fit wins a tie only with an RMS under [`CLEARLY_CLOSER`] of `b`'s.
fn clearly_better(a: &Scored, b: &Scored) -> bool {
    better_by(a, b, CLEARLY_CLOSER)
}

/// [`better`] with a closer fit winning a tie only with an RMS under `closer` × `b`'s.
fn better_by(a: &Scored, b: &Scored, closer: f64) -> bool {
    let (ra, rb) = (&a.result, &b.result);
    match (good(ra), good(rb)) {
        (true, false) => true,
        (false, true) => false,
        _ if divides(a, b) => true,
        _ if divides(b, a) => false,
        // No designer models a part as a piece of one placed before, or twice.
        _ if a.reads_placed() != b.reads_placed() => b.reads_placed(),
        _ => {
            // Explanations within a quarter of the size apart are a tie.
            let margin = 0.25 * ra.primitive.size().max(rb.primitive.size());
            if a.explained > b.explained + margin {
                return true;
            }
            if a.explained < b.explained - margin {
                return false;
            }
            // A tie: a reading that fits at a fraction of the other's RMS sits on its
            // strokes where the other does not; otherwise the reading that swallows
            // clearly less of the drawing wins, then the closer fit.
            if ra.rms < SWALLOW_TIE_RMS * rb.rms {
                return true;
            }
            if rb.rms < SWALLOW_TIE_RMS * ra.rms {
                return false;
            }
            // Weighed beyond one band: the looser fit's own band is the wider.
            let clear = a.gate.max(b.gate);
            let band = swallow_band(ra).max(swallow_band(rb));
            let (sa, sb) = (
                swallowed::beyond(&a.pieces, band),
                swallowed::beyond(&b.pieces, band),
            );
            if (sa - sb).abs() > clear {
                return sa < sb;
            }
            ra.rms < closer * rb.rms
        }
    }
}

/// Whether `reading` holds one of the parts placed before it (see [`holds`]), with
/// `band` the hand's noise about a curve.
fn holds_placed(context: &SnapContext, reading: &Primitive, band: f64) -> bool {
    if context.placed.is_empty() {
        return false;
    }
    let Some(image) = holds::image_box(reading) else {
        return false;
    };
    context.placed.iter().any(|p| {
        holds::may_hold(image, p.image, band) && holds::holds_within(reading, &p.primitive, band)
    })
}

/// Whether `reading` is one of the parts placed before it read again: its visible outline
/// within [`confidence::DISTINCT`] of that part's ([`confidence::outline_distance`]; a
/// pose and its mirror image in depth draw the same picture), with `band` the hand's
/// noise about a curve. A drop between two drawers, the first placed, is meant for the
/// second; two parts on one set of strokes are a double the model does not want.
fn repeats_placed(context: &SnapContext, reading: &Primitive, band: f64) -> bool {
    if context.placed.is_empty() {
        return false;
    }
    let Some(image) = holds::image_box(reading) else {
        return false;
    };
    context.placed.iter().any(|p| {
        holds::may_hold(image, p.image, band)
            && holds::may_hold(p.image, image, band)
            && confidence::outline_distance(reading, &p.primitive) <= confidence::DISTINCT
    })
}

/// Whether `a` is `b` divided where the drawing divides it: `b` holds a line across it
/// from outline to outline ([`divisions::divisions`]); `a` is smaller as drawn (its
/// visible curves are shorter in all), takes that line as its outline (its visible curves
/// run along it within its gate on average), runs along `b`'s outline elsewhere
/// ([`WITHIN_DIVIDED`]), fits about as closely ([`DIVIDED_RMS`]) and holds fewer such
/// lines (a row of four drawers read as two is nearer the drawer meant than four). A
/// designer draws no edge across a part's face: two drawers of a chest, read as one box,
/// explain more of the drawing than either drawer (the other's outline too), yet the
/// line between them says they are two. Such a division decides before the explanations
/// are weighed ([`better`]).
fn divides(a: &Scored, b: &Scored) -> bool {
    if a.divisions.len() >= b.divisions.len()
        || a.result.rms > DIVIDED_RMS * b.result.rms.max(STEADY * b.result.primitive.size())
    {
        return false;
    }
    let curves = cut::visible_curves(&a.result.primitive);
    // Smaller as drawn: a drawer cut off a chest keeps the chest's width (its size).
    let drawn = |curves: &[Curve2<f64>]| curves.iter().map(assign::curve_length).sum::<f64>();
    if drawn(&curves) >= drawn(&cut::visible_curves(&b.result.primitive)) {
        return false;
    }
    let takes = b.divisions.iter().any(|line| {
        let points = cut::spread_along(line, cut::LINE_POINTS);
        cut::along(&curves, &points) <= a.gate
    });
    takes && within(&curves, b, a.gate) >= WITHIN_DIVIDED
}

/// The share of the length of `curves` (a reading's visible curves) that runs within
/// `gate` of `b`'s curves or of the lines across it: 1 for a piece of `b` cut off at
/// those lines, little for another part's reading that happens to take one of them.
fn within(curves: &[Curve2<f64>], b: &Scored, gate: f64) -> f64 {
    let outline: Vec<Curve2<f64>> = b
        .result
        .primitive
        .current_shape()
        .curves
        .into_iter()
        .map(|c| c.curve)
        .collect();
    let (mut near, mut all) = (0usize, 0usize);
    for curve in curves {
        for p in curve.points(WITHIN_POINTS) {
            all += 1;
            let on_b = outline.iter().any(|c| assign::curve_distance(c, p) <= gate);
            let on_line = || {
                b.divisions.iter().any(|line| {
                    line.windows(2)
                        .any(|w| crate::geom::segment_distance(w[0], w[1], p) <= gate)
                })
            };
            if on_b || on_line() {
                near += 1;
            }
        }
    }
    near as f64 / all.max(1) as f64
}

/// A reading divides another ([`divides`]) only when it fits its strokes about as
/// closely: at most this many times the other's RMS (a hand's noise moves a refit by a
/// few percent; another part's reading that takes a line across, a handle's rod cut at
/// the body's outline drawn through it, fits two to six times worse).
const DIVIDED_RMS: f64 = 1.5;

/// The RMS, as a share of the size, below which two fits are alike however their RMS
/// compare: a steady hand's noise (a ruler-drawn line fits at nearly nothing).
const STEADY: f64 = 0.005;

/// A reading divides another ([`divides`]) only when at least this share of its outline
/// runs along the other's outline or the lines across it: a drawer cut off its chest
/// keeps the chest's outline but where the chest's neighbours hide it.
const WITHIN_DIVIDED: f64 = 0.7;

/// Points per curve at which [`within`] measures.
const WITHIN_POINTS: usize = 24;

/// The band round a reading's curves that what it swallows leaves to the hand's noise
/// ([`SWALLOW_BAND_RMS`], [`SWALLOW_BAND_SIZE`]).
fn swallow_band(result: &SnapResult) -> f64 {
    (SWALLOW_BAND_RMS * result.rms).max(SWALLOW_BAND_SIZE * result.primitive.size())
}

/// A reading's curves keep a band of this many times its fit's RMS (the hand's noise
/// it sees) free of what it swallows (see [`swallowed`]) …
const SWALLOW_BAND_RMS: f64 = 3.0;
/// … and of at least this fraction of its size.
const SWALLOW_BAND_SIZE: f64 = 0.01;
/// Of two readings that explain about as much, one whose RMS is under this fraction of
/// the other's fits clearly closer, whatever they swallow.
const SWALLOW_TIE_RMS: f64 = 0.5;

/// A second reading's RMS at most this fraction of the first's is clearly closer (as
/// for [`DRAWN_PROFILE_RMS`]): a hand's noise moves a refit of the same reading by a few
/// percent.
const CLEARLY_CLOSER: f64 = 0.9;

/// Whether a snap's RMS is within [`GOOD_FIT`] of its size.
fn good(r: &SnapResult) -> bool {
    r.rms <= GOOD_FIT * r.primitive.size()
}

/// How much of the drawing a snapped primitive explains, as a length in view units: the
/// length of the stroke samples it takes, each piece weighted by how close it runs to its
/// curve (1 on it, 0 at `gate`), with a stretch of a curve that several strokes draw
/// counted once (by the closest), less the length of its visible curves that its
/// strokes leave undrawn, each point by how far its nearest stroke runs (nothing when a
/// stroke passes through it, wholly at `gate` or beyond).
///
/// The two halves weigh distance alike. A stroke counts for a reading by how close it
/// runs, and a curve counts as drawn by the same measure: a stroke near the gate's edge
/// is barely the reading's, and the curve it runs along is barely drawn. Counted drawn
/// wherever a stroke came within the gate, a reading laid a fraction of the gate beside
/// its strokes lacked nothing: an end set past its drawn ellipse, where overshooting
/// outlines still run, cost nothing. On the conditions suite weighing both alike took
/// assembly parts from 85.8 to 86.3 % recovered (9 of the 20 parts it recovered were
/// drawn with overshoots; 1 was lost).
///
/// A sketchy hand draws a line two or three times; counted once a stroke, whatever it
/// drew thrice weighed three times, and a reading that took a neighbour's triple-drawn
/// ellipse outweighed one that took its own end's triple-drawn arc by two ellipses'
/// length. On the conditions suite counting each stretch once took assembly parts from
/// 84.8 to 86.1 % recovered.
///
/// Both halves matter in a cluttered drawing. Counting strokes alone favours a pose
/// that grows to reach its neighbours' strokes: a table top stretched over its legs, or
/// a brick read as the other box of its hexagonal outline (the Necker reversal), whose
/// inner edges then run where nothing is drawn. A designer draws every visible edge, so
/// a visible curve without strokes is evidence against the pose, as much as a stroke it
/// takes is evidence for it.
fn explanation(primitive: &Primitive, assignment: &Assignment, gate: f64, hidden: &[bool]) -> f64 {
    let gate = gate.max(f64::MIN_POSITIVE);
    let shape = primitive.current_shape();
    let mut taken = 0.0;
    let mut missing = 0.0;
    for (k, (curve, strokes)) in shape.curves.iter().zip(&assignment.curves).enumerate() {
        // Each piece of stroke counts by how close it runs: fully on the curve, nothing
        // at the gate.
        let closeness = |p: DVec2| (1.0 - assign::curve_distance(&curve.curve, p) / gate).max(0.0);
        let points = resampled(&curve.curve.points(96), gate / 2.0);
        let step = assign::curve_length(&curve.curve) / points.len().max(1) as f64;
        // A line drawn over several times (a sketchy hand's 2–3 strokes) is drawn once:
        // where strokes overlap along the curve, only the closest counts.
        let closed = matches!(curve.curve, Curve2::Ellipse { .. });
        taken += strokes
            .iter()
            .map(|s| {
                s.samples
                    .windows(2)
                    .map(|w| w[0].distance(w[1]) * closeness(w[0].midpoint(w[1])))
                    .sum::<f64>()
            })
            .sum::<f64>()
            - step * overdrawn(&points, strokes, &closeness, closed);
        if !curve.visible || hidden.get(k).is_some_and(|h| *h) {
            continue;
        }
        let unsupported: f64 = points
            .iter()
            .map(|p| {
                let nearest = strokes
                    .iter()
                    .flat_map(|s| s.samples.windows(2))
                    .map(|w| crate::geom::segment_distance(w[0], w[1], *p))
                    .fold(f64::INFINITY, f64::min);
                (nearest / gate).min(1.0)
            })
            .sum();
        missing += step * unsupported;
    }
    taken - missing
}

/// How many of a curve's `points` its `strokes` draw more than once: over each point,
/// the closeness of every stroke that covers it but the closest one's, summed. A piece
/// between two samples of a stroke covers the points between the curve points nearest
/// to its ends (the shorter way round a `closed` curve), by its `closeness` to the curve.
fn overdrawn(
    points: &[DVec2],
    strokes: &[AssignedStroke],
    closeness: &dyn Fn(DVec2) -> f64,
    closed: bool,
) -> f64 {
    let n = points.len();
    if n == 0 || strokes.len() < 2 {
        return 0.0;
    }
    let nearest = |p: DVec2| crate::geom::nearest_index(points, p);
    let (mut sum, mut best) = (vec![0.0_f64; n], vec![0.0_f64; n]);
    for s in strokes {
        let mut own = vec![0.0_f64; n];
        for w in s.samples.windows(2) {
            let weight = closeness(w[0].midpoint(w[1]));
            let (i, j) = (nearest(w[0]), nearest(w[1]));
            let (lo, hi) = (i.min(j), i.max(j));
            if closed && hi - lo > n / 2 {
                (hi..n)
                    .chain(0..=lo)
                    .for_each(|k| own[k] = own[k].max(weight));
            } else {
                (lo..=hi).for_each(|k| own[k] = own[k].max(weight));
            }
        }
        for k in 0..n {
            sum[k] += own[k];
            best[k] = best[k].max(own[k]);
        }
    }
    sum.iter().zip(&best).map(|(s, b)| s - b).sum()
}

/// Points along a polyline no farther apart than `step` (each segment split evenly; the
/// coverage count of [`explanation`] needs no uniform arc length).
fn resampled(points: &[DVec2], step: f64) -> Vec<DVec2> {
    let mut out = Vec::with_capacity(points.len());
    for w in points.windows(2) {
        // At most 64 points a segment: a degenerate fit (a curve huge against its
        // size) must not ask for gigabytes.
        let n = (w[0].distance(w[1]) / step).ceil().clamp(1.0, 64.0) as usize;
        out.extend((0..n).map(|k| w[0].lerp(w[1], k as f64 / n as f64)));
    }
    out.extend(points.last().copied());
    out
}

/// The assignment and fitting rounds of a snap from `primitive`.
fn snap_rounds(
    context: &SnapContext,
    primitive: &Primitive,
    settings: &SnapSettings,
    warm: Option<&Multipliers>,
    mut solve: SolveContext<'_>,
) -> Result<SnapResult, SnapError> {
    let kind = primitive.kind().name();
    let wide = settings.wide_gate * primitive.size();
    let mut assignment = assign(context, &primitive.current_shape().curves, wide);
    check_enough(primitive, &assignment)?;
    let mut current = primitive.clone();
    let mut multipliers = warm.cloned();
    let mut evaluations = 0;
    let mut termination = Termination::Converged;
    for round in 0..3 {
        // From the second round, each end ellipse's strokes are fitted turned about its
        // centre by the hand's slant against the fitted pose (see [`slant`]).
        let turned = (round > 0).then(|| slant::deslanted(&current, &assignment));
        // The solver refuses only a non-finite start.
        let (fitted, report) = fit(
            &current,
            turned.as_ref().unwrap_or(&assignment),
            settings,
            multipliers.as_ref(),
            solve.reborrow(),
        )
        .map_err(|_| SnapError::NonFinite(kind))?;
        evaluations += report.evaluations;
        termination = report.termination;
        if termination == Termination::Cancelled {
            return Err(SnapError::Cancelled);
        }
        if fitted.is_finite() {
            current = fitted;
            multipliers = Some(report.multipliers);
        }
        // A fit a little out of range may come back once the tight gate drops the
        // strokes it reached for (a box read as the other box of its outline went ×5.8
        // and back to ×1.4); one that left it by its square has run away: stop here.
        let factor = current.size() / primitive.size();
        let hopeless = MAX_SIZE_CHANGE * MAX_SIZE_CHANGE;
        if !(1.0 / hopeless..=hopeless).contains(&factor) {
            return Err(SnapError::RanAway { kind, factor });
        }
        let tight = settings.tight_gate * current.size();
        let next = assign::assign_within(context, &current.current_shape().curves, tight, true);
        let changed = !next.same_strokes(&assignment);
        if check_enough(&current, &next).is_err() {
            // The tight gate lost strokes the fit needs: keep the wider assignment.
            break;
        }
        assignment = next;
        // A warm-started drag frame starts next to its answer: when the tight gate takes
        // the same strokes, a second fit would only polish the preview.
        if (round >= 1 || warm.is_some()) && !changed {
            break;
        }
    }
    if !current.is_finite() {
        return Err(SnapError::NonFinite(kind));
    }
    let factor = current.size() / primitive.size();
    if !(1.0 / MAX_SIZE_CHANGE..=MAX_SIZE_CHANGE).contains(&factor) {
        return Err(SnapError::RanAway { kind, factor });
    }
    let rms = fit_rms(&current, &assignment);
    Ok(SnapResult {
        primitive: current,
        assignment,
        rms,
        termination,
        evaluations,
        explained: None,
        alternatives: Vec::new(),
        profile: settings.profile,
        multipliers,
    })
}

/// Snapping while a primitive is dragged: each [`SnapSession::update`] takes the
/// primitive where the cursor put it and returns the snapped preview, warm-started from
/// the previous frame.
///
/// Threading is the caller's: run updates off the UI thread, keep the newest request and
/// raise the [`CancelFlag`](crate::solve::CancelFlag) of a running update (in its
/// [`SolveContext`]) when a newer one arrives.
#[derive(Clone, Debug)]
pub struct SnapSession {
    context: SnapContext,
    settings: SnapSettings,
    last: Option<LastFrame>,
    /// The direction the last point drop gave (see [`SnapSession::update_at`]); `None`
    /// when the last frame was not a point drop's.
    point_axis: Option<Aim>,
}

/// Whether two primitives are the same up to rounding (a BGC moved by an offset and
/// back does not give the same bits).
fn same_shape(a: &Primitive, b: &Primitive) -> bool {
    let tolerance = 1e-9 * a.size().max(b.size());
    let (x, y) = (a.params(), b.params());
    a.kind() == b.kind()
        && x.len() == y.len()
        && x.iter().zip(&y).all(|(p, q)| (p - q).abs() <= tolerance)
}

/// The direction a point drop gave, `None` for one the drawing turns.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Aim(Option<DVec2>);

/// What a drag frame leaves for the next one.
#[derive(Clone, Debug)]
struct LastFrame {
    /// The primitive where the cursor put it.
    dragged: Primitive,
    /// The strokes the wide gate took around it.
    near: Assignment,
    /// The snapped preview.
    result: SnapResult,
}

impl SnapSession {
    /// A session over the strokes of `context`.
    pub fn new(context: SnapContext, settings: SnapSettings) -> Self {
        Self {
            context,
            settings,
            last: None,
            point_axis: None,
        }
    }

    /// The snapped preview of `dragged` (the primitive where the cursor put it).
    ///
    /// The preview is a function of the strokes around the cursor: when `dragged` only
    /// moved since the last frame and the wide gate around it takes the strokes it took
    /// last frame, the fit is warm-started from the last snapped primitive and its
    /// multipliers (it only confirms the preview, which stays on its drawing). Otherwise
    /// (other strokes under the cursor, a new kind, size or axis) the snap starts cold
    /// from `dragged`, so a preview dragged off its drawing lets go of it.
    ///
    /// # Errors
    ///
    /// As [`snap`]; a failed frame leaves the session's warm start untouched.
    pub fn update(
        &mut self,
        dragged: &Primitive,
        solve: SolveContext<'_>,
    ) -> Result<SnapResult, SnapError> {
        if !dragged.is_finite() {
            return Err(SnapError::NonFinite(dragged.kind().name()));
        }
        let near = self.near(dragged);
        self.update_near(dragged, near, solve)
    }

    /// The strokes the wide gate takes around `dragged`.
    fn near(&self, dragged: &Primitive) -> Assignment {
        let wide = self.settings.wide_gate * dragged.size();
        assign(&self.context, &dragged.current_shape().curves, wide)
    }

    /// [`SnapSession::update`] of `dragged` (finite) with the strokes `near` it.
    fn update_near(
        &mut self,
        dragged: &Primitive,
        near: Assignment,
        mut solve: SolveContext<'_>,
    ) -> Result<SnapResult, SnapError> {
        let warm = self.last.as_ref().filter(|last| {
            let offset = dragged.center() - last.dragged.center();
            same_shape(&last.dragged.transformed(offset, 1.0), dragged)
                && near.same_strokes(&last.near)
        });
        let result = match warm {
            // A warm frame holds a bent tube's radii as its cold snap chose to.
            Some(last) => snap_from(
                &self.context,
                &last.result.primitive,
                &SnapSettings {
                    profile: last.result.profile,
                    ..self.settings.clone()
                },
                last.result.multipliers.as_ref(),
                solve.reborrow(),
            )
            .or_else(|_| snap_from(&self.context, dragged, &self.settings, None, solve)),
            None => snap_from(&self.context, dragged, &self.settings, None, solve),
        }?;
        self.last = Some(LastFrame {
            dragged: dragged.clone(),
            near,
            result: result.clone(),
        });
        self.point_axis = None;
        Ok(result)
    }

    /// The snapped preview of a drop of `kind` at sketch point `at` that gives no size
    /// (and no direction when `axis` is `None`): the palette's drag before the wheel
    /// sized or turned it (see [`snap_at`]). While the cursor moves over the same strokes
    /// the last frame's guess, moved to the cursor, is refined warm as
    /// [`SnapSession::update`] refines a drag; over other strokes the drawing is read
    /// afresh, every guess snapped cold.
    ///
    /// # Errors
    ///
    /// As [`snap_at`].
    pub fn update_at(
        &mut self,
        kind: PrimitiveKind,
        at: DVec2,
        axis: Option<DVec2>,
        mut solve: SolveContext<'_>,
    ) -> Result<PointSnap, SnapError> {
        if !at.is_finite() {
            return Err(SnapError::NonFinite(kind.name()));
        }
        let moved = self.last.as_ref().and_then(|last| {
            let guess = &last.dragged;
            let point = crate::geom::projection::view_from_sketch(at);
            let offset = DVec3::new(point.x, point.y, guess.center().z) - guess.center();
            let moved = guess.transformed(offset, 1.0);
            let same_drop = guess.kind() == kind && self.point_axis == Some(Aim(axis));
            let near = self.near(&moved);
            (same_drop && near.same_strokes(&last.near)).then_some((moved, near))
        });
        if let Some((moved, near)) = moved {
            let result = self.update_near(&moved, near, solve)?;
            self.point_axis = Some(Aim(axis));
            return Ok(PointSnap {
                result,
                guess: moved,
            });
        }
        let snapped = snap_at_with(
            &self.context,
            kind,
            at,
            axis,
            &self.settings,
            solve.reborrow(),
        );
        let snapped = match snapped {
            Ok(s) => s,
            Err(e) => {
                self.reset();
                return Err(e);
            }
        };
        self.last = Some(LastFrame {
            dragged: snapped.guess.clone(),
            near: self.near(&snapped.guess),
            result: snapped.result.clone(),
        });
        self.point_axis = Some(Aim(axis));
        Ok(snapped)
    }

    /// Forgets the previous frame (the next update starts cold).
    pub fn reset(&mut self) {
        self.last = None;
        self.point_axis = None;
    }

    /// The strokes of the session.
    pub fn context(&self) -> &SnapContext {
        &self.context
    }
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec2, DVec3};

    use super::assign::curve_length;
    use super::{assign, explanation, initial, SnapContext, SnapSession, SnapSettings};
    use crate::primitive::{Bgc, Cuboid, Curve2, Cylinder, Primitive};
    use crate::sketch::{StrokeClass, StrokeId};
    use crate::solve::SolveContext;

    /// A good snap of a cylinder of size 100 that explains `explained`, swallows
    /// `swallowed` and fits at `rms`, scored with a gate of 10.
    fn scored(explained: f64, swallowed: f64, rms: f64) -> super::Scored {
        let primitive = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::Y,
            length: 100.0,
            radius: 10.0,
        });
        super::Scored {
            result: super::SnapResult {
                primitive,
                assignment: super::Assignment::default(),
                rms,
                termination: crate::solve::Termination::Converged,
                evaluations: 0,
                explained: Some(explained),
                alternatives: Vec::new(),
                profile: super::Profile::Smooth,
                multipliers: None,
            },
            explained,
            pieces: vec![(swallowed, f64::INFINITY)],
            divisions: Vec::new(),
            gate: 10.0,
            holds: false,
            repeats: false,
        }
    }

    #[test]
    fn a_reading_that_holds_a_placed_part_gives_way_to_one_that_holds_none() {
        // Two drawers read as one box explain far more than the drawer meant, but the
        // pair holds the drawer placed before.
        let mut pair = scored(1400.0, 0.0, 1.0);
        pair.holds = true;
        let drawer = scored(700.0, 0.0, 1.2);
        assert!(super::better(&drawer, &pair));
        assert!(!super::better(&pair, &drawer));
        // With nothing placed, the reading that explains more wins.
        pair.holds = false;
        assert!(super::better(&pair, &drawer));
    }

    /// A reading of `primitive` that takes no stroke, at an RMS of 1.
    fn bare_reading(primitive: Primitive) -> super::SnapResult {
        super::SnapResult {
            primitive,
            assignment: super::Assignment::default(),
            rms: 1.0,
            termination: crate::solve::Termination::Converged,
            evaluations: 0,
            explained: None,
            alternatives: Vec::new(),
            profile: super::Profile::Smooth,
            multipliers: None,
        }
    }

    #[test]
    fn a_reading_holds_a_part_only_once_that_part_is_placed() {
        use crate::primitive::Cuboid;
        use glam::DQuat;
        let turn = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.6);
        let cuboid = |center: DVec3, size: DVec3| {
            Primitive::Cuboid(Cuboid {
                center,
                rotation: turn,
                size,
            })
        };
        let up = turn * DVec3::Y;
        let chest = cuboid(DVec3::new(300.0, -300.0, 0.0), DVec3::new(90.0, 60.0, 60.0));
        let drawer = cuboid(chest.center() + up * 15.0, DVec3::new(90.0, 30.0, 60.0));
        let result = bare_reading(chest);
        let settings = SnapSettings::default();
        let alone = drawn_parts(std::slice::from_ref(&drawer));
        let free = super::Scored::of(&alone, result.clone(), 90.0, &settings);
        assert!(!free.holds);
        let placed = alone.with_placed([drawer]);
        let held = super::Scored::of(&placed, result, 90.0, &settings);
        assert!(held.holds);
    }

    #[test]
    fn a_reading_of_a_placed_part_again_gives_way_to_one_of_another_part() {
        // The drawer placed before, read again, explains a little more than the drawer
        // beside it that the drop meant.
        let mut again = scored(760.0, 0.0, 1.0);
        again.repeats = true;
        let other = scored(700.0, 0.0, 1.1);
        assert!(super::better(&other, &again));
        assert!(!super::better(&again, &other));
        // Between a reading that holds a placed part and one that repeats one, the
        // model contradicts both: what they explain decides.
        let mut pair = scored(1400.0, 0.0, 1.0);
        pair.holds = true;
        assert!(super::better(&pair, &again));
    }

    #[test]
    fn a_reading_repeats_a_placed_part_seen_the_same_but_not_its_neighbour() {
        use crate::primitive::Cuboid;
        use glam::DQuat;
        let turn = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.6);
        let up = turn * DVec3::Y;
        let drawer = |center: DVec3| {
            Primitive::Cuboid(Cuboid {
                center,
                rotation: turn,
                size: DVec3::new(90.0, 30.0, 60.0),
            })
        };
        let placed = drawer(DVec3::new(300.0, -300.0, 0.0));
        let below = drawer(placed.center() - up * 30.0);
        let settings = SnapSettings::default();
        let context = drawn_parts(&[placed.clone(), below.clone()]);
        let model = context.clone().with_placed([placed.clone()]);
        let scored = |context: &SnapContext, p: &Primitive| {
            super::Scored::of(context, bare_reading(p.clone()), 90.0, &settings)
        };
        assert!(scored(&model, &placed).repeats);
        assert!(scored(&model, &placed.mirrored_in_depth()).repeats);
        assert!(
            !scored(&model, &below).repeats,
            "the neighbour is another part"
        );
        assert!(!scored(&context, &placed).repeats, "nothing placed");
    }

    #[test]
    fn of_two_readings_that_explain_as_much_the_one_swallowing_less_wins() {
        // An arm read on through its stem to the other arm's end: it explains a little
        // more, fits a little closer, and leaves its own drawn end inside it.
        let through = scored(674.0, 60.0, 1.21);
        let own = scored(657.0, 0.0, 1.41);
        assert!(super::better(&own, &through));
        assert!(!super::better(&through, &own));
        // What they swallow differs by less than the gate: the closer fit wins.
        let close = scored(674.0, 8.0, 1.21);
        assert!(super::better(&close, &own));
        // A fit at under half the other's RMS wins whatever it swallows.
        let tight = scored(674.0, 60.0, 0.6);
        assert!(super::better(&tight, &own));
        // Explaining clearly more still wins first.
        let more = scored(800.0, 60.0, 1.41);
        assert!(super::better(&more, &own));
    }

    #[test]
    fn what_two_readings_swallow_is_weighed_beyond_one_band() {
        // A close fit (RMS 1.0, band 3) leaves a piece 5 from its curves inside its
        // outline; a looser fit of the same drop (RMS 1.8, band 5.4) has that piece
        // within its own band and swallows 10 elsewhere.
        let mut close = scored(674.0, 0.0, 1.0);
        close.pieces = vec![(60.0, 5.0)];
        let mut loose = scored(674.0, 0.0, 1.8);
        loose.pieces = vec![(10.0, 8.0)];
        // Beyond the looser band the close fit swallows nothing, the loose one 10 (not
        // clearly more than the gate of 10): the closer fit wins the tie.
        assert!(super::better(&close, &loose));
        assert!(!super::better(&loose, &close));
        // A piece beyond both bands still counts against the close fit.
        close.pieces.push((40.0, 9.0));
        assert!(super::better(&loose, &close));
    }

    /// A horn: a C-shaped tube whose radius grows slowly along most of it and fast at
    /// its mouth (radii 30 → 50 over eight spine points), its plane turned 20° out of the
    /// view plane.
    fn horn() -> Bgc {
        let tilt = 20f64.to_radians();
        let spine = (0..8)
            .map(|i| {
                let a = (-60.0 + 120.0 * f64::from(i) / 7.0).to_radians();
                let (x, y) = (300.0 * a.cos(), 300.0 * a.sin());
                DVec3::new(x * tilt.cos(), y, x * tilt.sin())
            })
            .collect();
        let mut horn = Bgc::through(spine, 30.0);
        horn.radii = vec![30.0, 30.3, 31.0, 32.2, 34.4, 37.9, 43.0, 50.2];
        horn
    }

    /// The visible curves of `part` as strokes, as a careful hand draws them: its ends
    /// as ellipses, its outlines as lines.
    fn drawn_with_ends(part: &Primitive) -> SnapContext {
        drawn(std::slice::from_ref(part), |curve| match curve {
            Curve2::Ellipse { .. } => StrokeClass::Feature,
            Curve2::Polyline(_) => StrokeClass::Silhouette,
        })
    }

    /// The visible curves of `parts` as strokes, as a careful hand draws them, each
    /// given the class `class` says.
    fn drawn(parts: &[Primitive], class: impl Fn(&Curve2<f64>) -> StrokeClass) -> SnapContext {
        let strokes: Vec<(Vec<DVec2>, StrokeClass)> = parts
            .iter()
            .flat_map(|p| p.current_shape().curves)
            .filter(|c| c.visible)
            .map(|c| {
                let points = c.curve.points(64).into_iter();
                let points = points.map(|q| DVec2::new(q.x, -q.y)).collect();
                (points, class(&c.curve))
            })
            .collect();
        SnapContext::new(
            strokes
                .iter()
                .enumerate()
                .map(|(i, (p, class))| (StrokeId(i as u32), p.as_slice(), *class)),
        )
    }

    #[test]
    fn a_flared_tube_keeps_the_flare_it_is_drawn_with() {
        let truth = horn();
        let context = drawn_with_ends(&Primitive::Bgc(truth.clone()));
        // Dropped on its spine at one radius, and snapped from its own pose.
        let dropped = Bgc::through(truth.spine.clone(), 38.0);
        let flare_kept = |p: &Primitive| {
            let Primitive::Bgc(fit) = p else {
                panic!("a bent tube snaps to a bent tube");
            };
            let worst = fit
                .radii
                .iter()
                .zip(&truth.radii)
                .map(|(r, t)| (r - t).abs() / t)
                .fold(0.0, f64::max);
            // A profile smoothed harder than the drawing shows it flattens the mouth.
            assert!(
                worst < 0.025,
                "radii {:.1?} for {:.1?}",
                fit.radii,
                truth.radii
            );
        };
        for start in [dropped, truth.clone()] {
            let result = super::snap(&context, &Primitive::Bgc(start), &SnapSettings::default())
                .expect("the horn snaps");
            assert_eq!(result.profile, super::Profile::Drawn);
            flare_kept(&result.primitive);
        }
    }

    #[test]
    fn a_flared_tube_keeps_its_flare_in_the_global_solve() {
        use crate::model::{Companions, Document, Fit, GlobalSettings, Placed, Relation};
        use crate::primitive::Feature;
        use crate::relation::{Mode, RelationKind};
        let truth = horn();
        let context = drawn_with_ends(&Primitive::Bgc(truth.clone()));
        let result = super::snap(
            &context,
            &Primitive::Bgc(truth.clone()),
            &SnapSettings::default(),
        )
        .expect("the horn snaps");
        let Primitive::Bgc(snapped) = &result.primitive else {
            panic!("a bent tube snaps to a bent tube");
        };
        // A post along the horn's narrow end, held to it: the solve frees the horn and
        // fits it to its strokes again.
        let end = snapped.spine[0];
        let along = (snapped.spine[0] - snapped.spine[1]).normalize();
        let mut doc = Document::new();
        let horn = doc.add_snapped(&result);
        let post = doc.add(Placed {
            primitive: Primitive::Cylinder(Cylinder {
                center: end + along * 60.0,
                axis: (along + DVec3::new(0.0, 0.05, 0.0)).normalize(),
                length: 100.0,
                radius: 30.0,
            }),
            fit: Fit::default(),
        });
        doc.add_relation(Relation {
            kind: RelationKind::Parallel,
            members: vec![horn, post],
            features: vec![Some(Feature::Bottom), Some(Feature::Top)],
            mode: Mode::Hard,
            inferred: None,
        })
        .expect("a valid relation");
        doc.solve(None, &GlobalSettings::default(), Companions::default());
        let Primitive::Bgc(solved) = &doc.get(horn).expect("placed").primitive else {
            panic!("still a bent tube");
        };
        // Held smooth, the solve would flatten the mouth the snap followed.
        let mouth = |b: &Bgc| b.radii[7] / b.radii[4];
        assert!(
            (mouth(solved) - mouth(&truth)).abs() < 0.03 * mouth(&truth),
            "radii {:.1?} for {:.1?}",
            solved.radii,
            truth.radii
        );
    }

    #[test]
    fn a_box_with_its_hidden_edges_drawn_keeps_its_sizes() {
        // A visible edge that takes a hidden one's stroke pulls the box off its drawing.
        let (truth, context) = assign::tests::plank_with_its_hidden_edges();
        let Primitive::Cuboid(t) = &truth else {
            unreachable!()
        };
        let dropped = Primitive::Cuboid(Cuboid {
            center: t.center + DVec3::new(6.0, -4.0, 0.0),
            size: t.size * 1.1,
            ..t.clone()
        });
        for start in [&truth, &dropped] {
            let result = super::snap(&context, start, &SnapSettings::default()).expect("a snap");
            let Primitive::Cuboid(b) = &result.primitive else {
                panic!("a box snapped to {:?}", result.primitive)
            };
            let mut sizes = b.size.to_array();
            sizes.sort_by(f64::total_cmp);
            let mut want = t.size.to_array();
            want.sort_by(f64::total_cmp);
            for (got, expected) in sizes.iter().zip(&want) {
                assert!(
                    (got / expected - 1.0).abs() < 0.02,
                    "sizes {sizes:?} for {want:?}"
                );
            }
        }
    }

    #[test]
    fn bad_gates_are_refused() {
        use crate::solve::{AugLagSettings, SettingsError};
        let solver = AugLagSettings::default();
        assert!(
            SnapSettings::new(0.3, 0.1, solver.clone()).is_ok(),
            "the defaults"
        );
        for (wide, tight, name) in [
            (f64::NAN, 0.1, "wide_gate"),
            (0.3, 0.0, "tight_gate"),
            (-0.3, 0.1, "wide_gate"),
            (0.3, f64::INFINITY, "tight_gate"),
        ] {
            let error = SnapSettings::new(wide, tight, solver.clone()).unwrap_err();
            assert!(
                matches!(error, SettingsError::NotPositive { name: n, .. } if n == name),
                "{error}"
            );
        }
        let error = SnapSettings::new(0.1, 0.3, solver).unwrap_err();
        assert!(
            matches!(
                error,
                SettingsError::OutOfRange {
                    name: "tight_gate",
                    ..
                }
            ),
            "{error}"
        );
    }

    #[test]
    fn a_fit_from_a_non_finite_primitive_is_an_error() {
        let nan = Primitive::Cylinder(Cylinder {
            center: DVec3::new(f64::NAN, 0.0, 0.0),
            axis: DVec3::Y,
            length: 4.0,
            radius: 1.0,
        });
        let assignment = super::Assignment::default();
        let settings = SnapSettings::default();
        assert!(
            super::fit(&nan, &assignment, &settings, None, SolveContext::default()).is_err(),
            "the solver's error is passed on"
        );
    }

    #[test]
    fn a_pose_with_visible_edges_where_nothing_is_drawn_explains_less() {
        let truth = initial::tests::turned_box();
        let context = initial::tests::drawn(&truth);
        let score = |p: &Cuboid| {
            let p = Primitive::Cuboid(p.clone());
            let gate = 0.1 * p.size();
            let a = assign(&context, &p.current_shape().curves, gate);
            (a.stroke_ids().len(), explanation(&p, &a, gate, &[]))
        };
        // Stretched along its first axis, away from the drawn far end: its near edges
        // still take strokes, but its far end stands where nothing is drawn.
        let mut long = truth.clone();
        long.size.x *= 1.6;
        long.center += truth.axes()[0] * 0.3 * truth.size.x;
        let ((n_true, e_true), (n_long, e_long)) = (score(&truth), score(&long));
        assert_eq!(n_true, 9, "every visible edge takes its stroke");
        assert!(
            n_long >= 5,
            "the stretched box still takes strokes: {n_long}"
        );
        assert!(
            e_true > e_long + 0.25 * truth.size.max_element(),
            "the drawn box explains {e_true:.0}, the stretched one {e_long:.0}"
        );
        // The drawn box's explanation is about its drawn edges' length.
        let drawn: f64 = Primitive::Cuboid(truth.clone())
            .current_shape()
            .curves
            .iter()
            .filter(|c| c.visible)
            .map(|c| curve_length(&c.curve))
            .sum();
        assert!(
            (e_true - drawn).abs() < 0.05 * drawn,
            "{e_true:.0} against {drawn:.0}"
        );
    }

    #[test]
    fn a_line_drawn_three_times_explains_what_it_does_drawn_once() {
        // A cylinder's outlines and ends drawn once, then each drawn three times by a
        // sketchy hand (the copies half a percent of the size apart): it explains the
        // same drawing.
        let truth = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.2, 0.9, 0.39).normalize(),
            length: 300.0,
            radius: 60.0,
        });
        let explained = |copies: u32| {
            let parts: Vec<Primitive> = (0..copies)
                .map(|k| truth.transformed(DVec3::new(0.8, -0.4, 0.0) * f64::from(k), 1.0))
                .collect();
            let context = drawn(&parts, |c| match c {
                Curve2::Ellipse { .. } => StrokeClass::Feature,
                Curve2::Polyline(_) => StrokeClass::Silhouette,
            });
            let gate = 0.1 * truth.size();
            let a = assign(&context, &truth.current_shape().curves, gate);
            assert_eq!(
                a.stroke_ids().len(),
                context.strokes.len(),
                "every copy is taken: {a:?}"
            );
            explanation(&truth, &a, gate, &[])
        };
        let (once, thrice) = (explained(1), explained(3));
        assert!(
            (thrice - once).abs() < 0.1 * once,
            "drawn once {once:.0}, three times {thrice:.0}"
        );
    }

    #[test]
    fn a_stroke_near_the_gates_edge_draws_its_curve_only_as_far_as_it_runs_close() {
        // A cylinder seen from the side, drawn on its curves and drawn shifted sideways
        // by half the gate: its outlines' strokes then run half the gate off them (its
        // ends, flat ellipses across the shift, stay on theirs). Half the gate off, an
        // outline's stroke is half its own and the outline half drawn: the two halves
        // cancel, and the outlines explain nothing. Counted drawn wherever a stroke came
        // within the gate, they kept half their length.
        let part = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::Y,
            length: 300.0,
            radius: 60.0,
        });
        let gate = 0.1 * part.size();
        let explained = |shift: f64| {
            let moved = part.transformed(DVec3::new(shift, 0.0, 0.0), 1.0);
            let context = drawn(&[moved], |c| match c {
                Curve2::Ellipse { .. } => StrokeClass::Feature,
                Curve2::Polyline(_) => StrokeClass::Silhouette,
            });
            let a = assign(&context, &part.current_shape().curves, 2.0 * gate);
            assert_eq!(a.stroke_ids().len(), context.strokes.len(), "{a:?}");
            explanation(&part, &a, gate, &[])
        };
        let outlines: f64 = part
            .current_shape()
            .curves
            .iter()
            .filter(|c| c.visible && matches!(c.curve, Curve2::Polyline(_)))
            .map(|c| curve_length(&c.curve))
            .sum();
        let (on, off) = (explained(0.0), explained(0.5 * gate));
        assert!(
            on - off > 0.9 * outlines,
            "drawn on its curves {on:.0}, half the gate off {off:.0}, outlines {outlines:.0}"
        );
    }

    /// The visible curves of `parts` as strokes, as a careful hand draws them.
    fn drawn_parts(parts: &[Primitive]) -> SnapContext {
        drawn(parts, |_| StrokeClass::Silhouette)
    }

    #[test]
    fn a_drop_made_too_big_next_to_a_neighbour_still_lands_on_its_part() {
        // Two legs side by side, a leg's width apart, leaning a little towards the viewer.
        let leg = |x: f64| {
            Primitive::Cylinder(Cylinder {
                center: DVec3::new(x, -160.0, 0.0),
                axis: DVec3::new(0.0, 0.96, 0.28).normalize(),
                length: 150.0,
                radius: 12.0,
            })
        };
        let (meant, neighbour) = (leg(100.0), leg(148.0));
        let context = drawn_parts(&[meant.clone(), neighbour]);
        // Dropped over the meant leg a quarter too big and upright, off towards the
        // neighbour by a tenth of its size: its wide gate takes the neighbour's
        // outline too.
        let dropped = Primitive::Cylinder(Cylinder {
            center: DVec3::new(112.0, -165.0, 0.0),
            axis: DVec3::Y,
            length: 190.0,
            radius: 16.0,
        });
        let result = super::snap(&context, &dropped, &SnapSettings::default()).expect("it snaps");
        let Primitive::Cylinder(c) = &result.primitive else {
            unreachable!()
        };
        assert!(
            (c.center.x - 100.0).abs() < 3.0 && (c.radius - 12.0).abs() < 1.0,
            "landed on {c:?}"
        );
    }

    #[test]
    fn a_box_dropped_beside_a_twin_blade_gets_a_start_on_the_blade_nearest_the_drop() {
        // A plug's two thin blades side by side, a blade and a half apart, turned to show
        // their three faces.
        let rotation = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(-0.6);
        let blade = |x: f64| Cuboid {
            center: rotation * DVec3::new(x, 0.0, 0.0) + DVec3::new(300.0, -300.0, 0.0),
            rotation,
            size: DVec3::new(24.0, 200.0, 6.0),
        };
        let row = [blade(0.0), blade(36.0)];
        let context = drawn_parts(&row.clone().map(Primitive::Cuboid));
        // Dropped off the first blade towards the other, turned by 8° and a fifth too
        // big: the edges near it span both blades, and the middle of their bounds falls
        // between them.
        let meant = &row[0];
        let dropped = Cuboid {
            center: meant.center + rotation * DVec3::new(12.0, 6.0, 0.0),
            rotation: DQuat::from_rotation_z(0.14) * rotation,
            size: meant.size * 1.2,
        };
        let starts = initial::box_poses(&context, &dropped);
        let on_blade = |c: &Cuboid| c.center.truncate().distance(meant.center.truncate()) < 4.0;
        assert!(starts.iter().any(on_blade), "{starts:?}");
    }

    /// Two vertical lines 20 apart and 60 long: the outline of a side-on cylinder.
    fn outline() -> SnapContext {
        let line = |x: f64| {
            (0..=20)
                .map(|i| DVec2::new(x, 100.0 + 3.0 * f64::from(i)))
                .collect::<Vec<_>>()
        };
        let (a, b) = (line(40.0), line(60.0));
        SnapContext::new([
            (StrokeId(0), a.as_slice(), StrokeClass::Silhouette),
            (StrokeId(1), b.as_slice(), StrokeClass::Silhouette),
        ])
    }

    fn dragged(x: f64) -> Primitive {
        Primitive::Cylinder(Cylinder {
            center: DVec3::new(x, -128.0, 0.0),
            axis: DVec3::Y,
            length: 70.0,
            radius: 12.0,
        })
    }

    #[test]
    fn a_box_drawn_with_overshooting_edges_keeps_its_sizes() {
        // Every visible edge carried a tenth of its length past both corners, as a quick
        // hand does: the sizes come from where the edges lie, not from how far they run.
        let truth = initial::tests::turned_box();
        let context = initial::tests::drawn_past_corners(&truth, 0.1);
        let result = super::snap(
            &context,
            &Primitive::Cuboid(truth.clone()),
            &SnapSettings::default(),
        )
        .expect("it snaps");
        let Primitive::Cuboid(b) = &result.primitive else {
            panic!("not a box");
        };
        // Sizes are compared as a set (a box's axes may come back in another order);
        // counted against the corners, the overshoots made it about 1 % too big.
        let mut got = b.size.to_array();
        let mut want = truth.size.to_array();
        got.sort_by(f64::total_cmp);
        want.sort_by(f64::total_cmp);
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() < 0.003 * w, "sizes {got:?} for {want:?}");
        }
    }

    #[test]
    fn choosing_an_alternative_swaps_it_with_the_snap() {
        let context = outline();
        let result =
            super::snap(&context, &dragged(52.0), &SnapSettings::default()).expect("it snaps");
        assert!(
            result.with_alternative(0).is_none(),
            "{:?}",
            result.alternatives
        );
        let other = dragged(80.0);
        let mut with = result.clone();
        with.alternatives.push(super::Alternative {
            primitive: other.clone(),
            assignment: result.assignment.clone(),
            rms: 3.0,
            explained: 10.0,
            distance: 0.4,
            profile: super::Profile::Smooth,
        });
        let swapped = with.with_alternative(0).expect("one alternative");
        assert_eq!(swapped.primitive, other);
        assert!((swapped.rms - 3.0).abs() < 1e-12);
        assert_eq!(swapped.alternatives.len(), 1);
        assert_eq!(swapped.alternatives[0].primitive, result.primitive);
        let back = swapped.with_alternative(0).expect("and back");
        assert_eq!(back.primitive, result.primitive);
    }

    #[test]
    fn a_preview_stays_on_its_strokes_while_the_cursor_stays_over_them() {
        let mut session = SnapSession::new(outline(), SnapSettings::default());
        let first = session
            .update(&dragged(52.0), SolveContext::default())
            .expect("it snaps");
        assert_eq!(first.assignment.stroke_ids(), [StrokeId(0), StrokeId(1)]);
        for k in 1..20 {
            let x = 52.0 + 2.0 * (f64::from(k) * 0.7).sin();
            let frame = session
                .update(&dragged(x), SolveContext::default())
                .expect("it stays snapped");
            assert!(
                frame.primitive.center().distance(first.primitive.center()) < 1e-3,
                "frame {k} moved the snapped preview"
            );
            assert!(frame.evaluations <= 5, "frame {k}: {}", frame.evaluations);
        }
    }

    #[test]
    fn a_preview_dragged_off_its_strokes_lets_go_and_snaps_again_on_the_way_back() {
        let mut session = SnapSession::new(outline(), SnapSettings::default());
        assert!(session
            .update(&dragged(52.0), SolveContext::default())
            .is_ok());
        let mut x = 52.0;
        while x < 300.0 {
            x += 3.0;
            let frame = session.update(&dragged(x), SolveContext::default());
            assert!(
                x <= 150.0 || frame.is_err(),
                "still snapped at x = {x}: {frame:?}"
            );
        }
        while x > 52.0 {
            x -= 3.0;
            let _ = session.update(&dragged(x), SolveContext::default());
        }
        let back = session
            .update(&dragged(52.0), SolveContext::default())
            .expect("snapped again");
        assert!((back.primitive.center().x - 50.0).abs() < 0.5);
    }
}
