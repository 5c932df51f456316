//! The global solve (problem 2 of the optimisation details of Shtof, Agathos, Gingold,
//! Shamir and Cohen-Or, *Geosemantic Snapping for Sketch-Based Modeling*, Eurographics
//! 2013): min Σφ_p s.t. every C_p and every hard ψ_g, with soft relations as weighted
//! terms of the objective, from x_start = (the current primitives: the previous solution
//! and the new part's snap).
//!
//! **Frames.** Each primitive keeps the variables of its own snapping problem, in its own
//! normalised frame (centre at the origin, size 1, see [`Frame`]), so φ_p is exactly the
//! per-primitive objective and every part is equally well scaled, whatever their sizes.
//! Relations need one frame for all: a feature's position maps to the common frame by the
//! constant affine map x ↦ (x·s_p + o_p − O)/S (radii and half extents by s_p/S, normals
//! unchanged), where O is the parts' mean centre and S their median size. The residuals
//! are scale-free, so S only keeps numbers near 1.
//!
//! **Components and reach.** φ is a sum over parts and each relation couples its members
//! only, so the problem splits into the connected components of the relation graph. Only
//! the components holding a changed part are solved; the others are at their optimum
//! already. Within them, a change frees the parts within [`GlobalSettings::reach`]
//! relations of it (default 1: the released part and the parts it was related to) and
//! holds the others, whose relations hold already, as constants; `reach: None` (and
//! `solve(None, ..)`, as `geosnap solve` does) frees everything.
//!
//! A solve that comes out broken with parts held blames a relation with the parts still
//! held; it does not free the rest of the component first. A change is settled where it
//! was made, as a parametric CAD sketcher reports the constraint that conflicts rather
//! than moving the whole sketch: the rest of the model, settled by earlier releases,
//! stays where the user saw it, and a release costs about the same whatever the size of
//! the model. (Freeing the whole component first, as this solve did before, made a
//! conflicting release of a 50-part model take 10–30 s, one full solve per relation
//! blamed, and found no more of the synthetic assemblies' designed relations.)
//!
//! **Conflicts.** A solve is *broken* when the hard relations cannot be met (‖ψ‖∞ above
//! [`GlobalSettings::violation_tol`] at the caps) or a part's fit gets much worse than its
//! own snap (RMS more than [`GlobalSettings::max_worsening`] times, with a floor of
//! [`WORSENING_FLOOR`] of its size so that near-perfect snaps are not held to noise). The
//! relation responsible is then switched off and the component solved again from the
//! same start:
//! - when infeasible, the hard relation with the largest residual;
//! - when a fit got worse, among the hard relations of the parts that got worse, the one
//!   pulling hardest: the largest Σ|λ| (its multipliers are the forces it exerts against
//!   the fits).
//!
//! **Dimensions.** A size the user typed for a free part ([`super::Dimension`]) is the
//! hard equality x_q − value/s_p = 0 on that parameter in the part's frame, labelled
//! `cylinder 3: radius = 12.5`. A part with dimensions is solved even without relations,
//! so that its other parameters are refitted to its strokes with the size held. The
//! conflict logic never blames a dimension: when the hard relations contradict one, a
//! relation is switched off; and a dimensioned part's fit is not checked for worsening,
//! since the user's size may rightly pull it off its strokes.
//!
//! After [`GlobalSettings::max_conflicts`] rounds a still broken component is put back
//! as it was: the user is never left with a broken model.

use std::collections::BTreeSet;
use std::time::Duration;

use glam::DVec3;

use super::{Document, PrimitiveId, Quantity, Relation, RelationId};
use crate::core::ad::{Expr, Graph, Vec3};
use crate::core::primitive::{FeatureCurve, FeatureGeometry, Primitive};
use crate::core::relation::{residuals, Member, Mode};
use crate::core::snap::{fit_rms, fit_terms, Assignment, Frame};
use crate::core::solve::{
    AugLagSettings, CancelFlag, Clock, Multipliers, Problem, SolveObserver, SolveReport, Solver,
    Start, Termination,
};

/// A part's fit may worsen freely up to this fraction of its size (RMS), whatever its own
/// snap achieved.
pub const WORSENING_FLOOR: f64 = 0.005;

/// Weight of a part without strokes (loaded without its sketch) on staying where it is,
/// per squared parameter change in its frame.
const ANCHOR_WEIGHT: f64 = 1.0;

/// Weight of a fitted part on staying where the solve found it, per squared parameter
/// change in its frame (a proximal term).
///
/// Strokes do not always determine every parameter: a leg whose ends are hidden shows
/// its outline, which fixes its projected length but not how far it tilts out of the
/// view, and without this term the solve drifts along that valley (a synthetic table's
/// hidden leg came out four times too long, turned almost end-on). The weight is small
/// against the fit: moving a parameter by 5 % of the part's size costs what a 0.05 %
/// error of one curve's fit does (φ_p is about the squared error in the frame), so
/// relations and strokes still decide wherever they can.
const PROXIMAL_WEIGHT: f64 = 1e-4;

/// L-BFGS memory of the global solve. Relations couple the parts' fits into a problem
/// whose curvature differs by orders of magnitude between directions (depths only the
/// relations fix, fits the strokes fix); a long memory models it far better than the
/// per-part snaps' 10: on the shared sketches it cuts evaluations 3–10×.
const LBFGS_MEMORY: usize = 100;

/// Samples per stroke and curve the global solve fits (evenly thinned from the snap's
/// up to 32). φ_p averages over samples, so thinning keeps its minimum where it was
/// while each evaluation gets cheaper; the reported fits use every sample.
const SOLVE_SAMPLES: usize = 12;

/// The assignment with each stroke's samples evenly thinned to at most `n` (end points
/// kept, as the outline ends are pulled to the extreme samples).
fn thinned(assignment: &Assignment, n: usize) -> Assignment {
    let n = n.max(2);
    Assignment {
        curves: assignment
            .curves
            .iter()
            .map(|strokes| {
                strokes
                    .iter()
                    .map(|a| {
                        let m = a.samples.len();
                        let mut out = a.clone();
                        if m > n {
                            out.samples =
                                (0..n).map(|i| a.samples[i * (m - 1) / (n - 1)]).collect();
                        }
                        out
                    })
                    .collect()
            })
            .collect(),
    }
}

/// Settings of the global solve.
#[derive(Clone, Debug, PartialEq)]
pub struct GlobalSettings {
    /// The solver's settings and caps (iterations, evaluations, time).
    pub solver: AugLagSettings,
    /// Weight of a soft relation: w·‖ψ‖² is added to the objective (default 1, which
    /// weighs a 1 % residual like a 1 %-of-size fit error of one curve).
    pub soft_weight: f64,
    /// Largest ‖ψ‖∞ of a hard relation taken as satisfied after a solve (default 1e-3:
    /// 0.06° for a direction, 0.1 % of the features' size for a position; the solver
    /// itself aims at 1e-5).
    pub violation_tol: f64,
    /// Largest ratio of a part's RMS after the solve to its RMS after its own snap
    /// (default 3).
    pub max_worsening: f64,
    /// Most relations switched off per solve (default 8).
    pub max_conflicts: usize,
    /// How far a change reaches, in relations (default 1): a solve after a change frees
    /// the changed parts and those related to them, and holds the rest of their
    /// component where it is (its relations hold already, and those reaching the freed
    /// parts are kept as constraints). `None` frees the whole component. A release then
    /// costs about the same whatever the size of the model.
    pub reach: Option<usize>,
}

impl Default for GlobalSettings {
    fn default() -> Self {
        let solver = AugLagSettings::default()
            .with_constraint_tol(1e-5)
            .and_then(|s| s.with_gradient_tol(1e-5))
            .and_then(|s| s.with_max_outer_iterations(30))
            .and_then(|s| s.with_max_evaluations(3000))
            .and_then(|s| s.with_time_limit(Duration::from_secs(10)))
            .and_then(|s| s.with_lbfgs_memory(LBFGS_MEMORY))
            .unwrap_or_default();
        Self {
            solver,
            soft_weight: 1.0,
            violation_tol: 1e-3,
            max_worsening: 3.0,
            max_conflicts: 8,
            reach: Some(1),
        }
    }
}

/// A relation switched off because it conflicted, with the reason in words.
#[derive(Clone, Debug, PartialEq)]
pub struct Conflict {
    /// The relation.
    pub relation: RelationId,
    /// A message naming it and saying why.
    pub message: String,
}

/// What a global solve did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GlobalOutcome {
    /// The parts solved (those of the components holding a changed part, within
    /// [`GlobalSettings::reach`] of it).
    pub solved: Vec<PrimitiveId>,
    /// Hard and soft relations taken into account.
    pub relations: usize,
    /// Relations switched off, in order.
    pub conflicts: Vec<Conflict>,
    /// The last solve's report (`None` when nothing needed solving: no relations and no
    /// dimensions).
    pub report: Option<SolveReport>,
    /// Solves run (1 plus one per conflict).
    pub solves: usize,
    /// Whether the result was refused and the parts put back as they were.
    pub reverted: bool,
}

/// Where the solver stands, for a status bar or a log: the companions of a solve.
#[derive(Default)]
pub struct Companions<'a> {
    /// Stops the solve when raised.
    pub cancel: Option<&'a CancelFlag>,
    /// Measures time and enforces the time cap.
    pub clock: Option<&'a dyn Clock>,
    /// Receives the intermediate iterates.
    pub observer: Option<&'a mut dyn SolveObserver>,
}

impl std::fmt::Debug for Companions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Companions")
            .field("cancel", &self.cancel)
            .field("clock", &self.clock.is_some())
            .field("observer", &self.observer.is_some())
            .finish()
    }
}

/// A clock that starts when it is made, over another clock: the solver reads time from
/// its own start.
struct Since<'a> {
    clock: &'a dyn Clock,
    start: Duration,
}

impl Clock for Since<'_> {
    fn elapsed(&self) -> Duration {
        self.clock.elapsed().saturating_sub(self.start)
    }
}

/// One part of a solve: the primitive, its strokes and its snap's RMS.
struct Part<'d> {
    id: PrimitiveId,
    primitive: &'d Primitive,
    assignment: Option<&'d Assignment>,
    own_rms: Option<f64>,
    frame: Frame,
    local: Primitive,
    /// Its variables' range in the solve's x (empty when held).
    start: usize,
    len: usize,
    /// Whether it is held where it is (beyond the reach of the change).
    held: bool,
    /// Its dimensions (quantity, value in model space), held exactly.
    dimensions: Vec<(Quantity, f64)>,
}

/// The compiled problem of a set of parts and relations, with where each relation's
/// equations are.
struct Compiled {
    problem: Problem,
    /// (relation index, range of its equalities among the problem's equalities).
    hard: Vec<(usize, std::ops::Range<usize>)>,
}

/// A feature mapped from a part's frame into the common frame (see the module docs).
fn to_common<'g>(f: &FeatureCurve<Expr<'g>>, scale: f64, offset: DVec3) -> FeatureCurve<Expr<'g>> {
    let point = |v: Vec3<Expr<'g>>| {
        Vec3::new(
            v.x * scale + offset.x,
            v.y * scale + offset.y,
            v.z * scale + offset.z,
        )
    };
    let geometry = match &f.geometry {
        FeatureGeometry::Circle {
            center,
            normal,
            radius,
        } => FeatureGeometry::Circle {
            center: point(*center),
            normal: *normal,
            radius: *radius * scale,
        },
        FeatureGeometry::Rectangle {
            center,
            normal,
            half_extents,
        } => FeatureGeometry::Rectangle {
            center: point(*center),
            normal: *normal,
            half_extents: half_extents.map(|(axis, h)| (axis, h * scale)),
        },
    };
    FeatureCurve {
        feature: f.feature,
        geometry,
    }
}

/// The equalities holding a free part's dimensions, in its frame: sizes map by 1/s.
fn dimension_equalities<'g>(
    part: &Part<'_>,
    name: &str,
    x: &[Expr<'g>],
) -> Vec<(String, Expr<'g>)> {
    part.dimensions
        .iter()
        .filter_map(|(quantity, target)| {
            let v = quantity
                .param_index(part.primitive.kind())
                .and_then(|i| x.get(i))?;
            Some((
                format!("{name}: {quantity} = {target}"),
                *v - *target / part.frame.scale,
            ))
        })
        .collect()
}

/// Builds the global problem of `parts` with the `relations` (index, relation) whose
/// members are all among them.
fn compile(
    parts: &[Part<'_>],
    relations: &[(usize, &Relation)],
    settings: &GlobalSettings,
) -> Compiled {
    let g = Graph::new();
    let origin = parts.iter().map(|p| p.frame.origin).sum::<DVec3>() / parts.len() as f64;
    let mut sizes: Vec<f64> = parts.iter().map(|p| p.frame.scale).collect();
    sizes.sort_by(f64::total_cmp);
    let unit = sizes[sizes.len() / 2];
    let mut objective = Vec::new();
    let mut equalities: Vec<(String, Expr<'_>)> = Vec::new();
    let mut inequalities: Vec<(String, Expr<'_>)> = Vec::new();
    let mut features = Vec::with_capacity(parts.len());
    for part in parts {
        let scale = part.frame.scale / unit;
        let offset = (part.frame.origin - origin) / unit;
        if part.held {
            // Held where it is: its features are constants.
            let x: Vec<Expr<'_>> = part.local.params().iter().map(|v| g.constant(*v)).collect();
            let shape = part.local.shape(&x);
            features.push(
                shape
                    .features
                    .iter()
                    .map(|f| to_common(f, scale, offset))
                    .collect::<Vec<_>>(),
            );
            continue;
        }
        let x = g.vars(part.len);
        let name = format!("{} {}", part.primitive.kind().name(), part.id.0);
        // The squared distance from where the part stands.
        let now = part.local.params();
        let moved = g.sum(x.iter().zip(&now).map(|(v, n)| (*v - *n).square()));
        let (value, eqs, ineqs, feats) = if let Some(assignment) = part.assignment {
            let assignment = thinned(assignment, SOLVE_SAMPLES);
            let t = fit_terms(&g, &x, &part.local, &assignment, &part.frame);
            let value = t.objective + moved * PROXIMAL_WEIGHT;
            (value, t.equalities, t.inequalities, t.features)
        } else {
            let shape = part.local.shape(&x);
            let (eqs, ineqs) = (shape.equalities, shape.inequalities);
            (moved * ANCHOR_WEIGHT, eqs, ineqs, shape.features)
        };
        objective.push(value);
        equalities.extend(eqs.into_iter().map(|(l, e)| (format!("{name}: {l}"), e)));
        // The user's dimensions come before the relations, so the relations' ranges
        // below are unaffected, and `blame` never sees them.
        equalities.extend(dimension_equalities(part, &name, &x));
        inequalities.extend(ineqs.into_iter().map(|(l, e)| (format!("{name}: {l}"), e)));
        features.push(
            feats
                .iter()
                .map(|f| to_common(f, scale, offset))
                .collect::<Vec<_>>(),
        );
    }
    let mut hard = Vec::new();
    let mut soft = Vec::new();
    for (index, relation) in relations {
        let members: Option<Vec<Member<'_, Expr<'_>>>> = relation
            .members
            .iter()
            .enumerate()
            .map(|(k, id)| {
                let i = parts.iter().position(|p| p.id == *id)?;
                Some(Member {
                    features: &features[i],
                    feature: relation.features.get(k).copied().flatten(),
                })
            })
            .collect();
        let Some(members) = members else { continue };
        let Ok(psi) = residuals(relation.kind, &members) else {
            continue;
        };
        match relation.mode {
            Mode::Hard => {
                let first = equalities.len();
                let label = describe(*index, relation);
                equalities.extend(psi.into_iter().map(|e| (label.clone(), e)));
                hard.push((*index, first..equalities.len()));
            }
            Mode::Soft => soft.extend(psi.into_iter().map(|e| e.square() * settings.soft_weight)),
            Mode::Off => {}
        }
    }
    objective.extend(soft);
    let total = g.sum(objective);
    let mut builder = Problem::builder(&g, total);
    for (label, e) in equalities {
        builder = builder.equality(label, e);
    }
    for (label, e) in inequalities {
        builder = builder.inequality(label, e);
    }
    Compiled {
        problem: builder.build(),
        hard,
    }
}

/// A relation in words: `relation 3 (coaxial: cylinder 0 top, cone 2 bottom)`.
fn describe(index: usize, relation: &Relation) -> String {
    let members: Vec<String> = relation
        .members
        .iter()
        .enumerate()
        .map(
            |(k, id)| match relation.features.get(k).copied().flatten() {
                Some(f) => format!("#{} {f}", id.0),
                None => format!("#{}", id.0),
            },
        )
        .collect();
    format!(
        "relation {index} ({} of {})",
        relation.kind.name(),
        members.join(", ")
    )
}

/// Whether a relation takes part in solves.
fn active(relation: &Relation) -> bool {
    relation.mode != Mode::Off
}

/// The parts within `reach` relations of `changed` (active relations only).
fn neighbourhood(
    document: &Document,
    changed: &[PrimitiveId],
    reach: usize,
) -> BTreeSet<PrimitiveId> {
    let mut near: BTreeSet<PrimitiveId> = changed.iter().copied().collect();
    for _ in 0..reach {
        let mut next = near.clone();
        for r in document.relations.iter().filter(|r| active(r)) {
            if r.members.iter().any(|m| near.contains(m)) {
                next.extend(r.members.iter().copied());
            }
        }
        if next.len() == near.len() {
            break;
        }
        near = next;
    }
    near
}

/// The parts of `ids` beyond `reach` relations of `changed`.
fn held_beyond(
    document: &Document,
    ids: &BTreeSet<PrimitiveId>,
    changed: &[PrimitiveId],
    reach: usize,
) -> BTreeSet<PrimitiveId> {
    let near = neighbourhood(document, changed, reach);
    ids.difference(&near).copied().collect()
}

/// The parts connected to `changed` through active relations.
fn component(document: &Document, changed: &[PrimitiveId]) -> BTreeSet<PrimitiveId> {
    let mut reached: BTreeSet<PrimitiveId> = changed
        .iter()
        .copied()
        .filter(|id| document.get(*id).is_some())
        .collect();
    loop {
        let before = reached.len();
        for r in document.relations.iter().filter(|r| active(r)) {
            if r.members.iter().any(|m| reached.contains(m)) {
                reached.extend(r.members.iter().copied());
            }
        }
        if reached.len() == before {
            return reached;
        }
    }
}

impl Document {
    /// Solves the components of the model holding the `changed` parts (every part when
    /// `changed` is `None`) with their relations, switching off conflicting relations (see
    /// the module docs), and stores the solved primitives with their new fits.
    ///
    /// # Examples
    ///
    /// ```
    /// use glam::DVec3;
    /// use geosnap::core::model::{Companions, Document, Fit, GlobalSettings, Placed, Relation};
    /// use geosnap::core::primitive::{Cylinder, Feature, Primitive};
    /// use geosnap::core::relation::{Mode, RelationKind};
    ///
    /// let tilted = |x: f64, axis: DVec3| Placed {
    ///     primitive: Primitive::Cylinder(Cylinder {
    ///         center: DVec3::new(x, 0.0, 0.0),
    ///         axis: axis.normalize(),
    ///         length: 10.0,
    ///         radius: 2.0,
    ///     }),
    ///     fit: Fit::default(),
    /// };
    /// let mut doc = Document::new();
    /// let a = doc.add(tilted(0.0, DVec3::Y));
    /// let b = doc.add(tilted(8.0, DVec3::new(0.1, 1.0, 0.0)));
    /// doc.add_relation(Relation {
    ///     kind: RelationKind::Parallel,
    ///     members: vec![a, b],
    ///     features: vec![Some(Feature::Top), Some(Feature::Top)],
    ///     mode: Mode::Hard,
    /// })?;
    /// let outcome = doc.solve(None, &GlobalSettings::default(), Companions::default());
    /// assert!(outcome.conflicts.is_empty());
    /// let axis = |id| match &doc.get(id).unwrap().primitive {
    ///     Primitive::Cylinder(c) => c.axis,
    ///     _ => unreachable!(),
    /// };
    /// assert!(axis(a).cross(axis(b)).length() < 1e-4);
    /// # Ok::<(), anyhow::Error>(())
    /// ```
    #[expect(
        clippy::too_many_lines,
        reason = "one loop of solve, blame and retry reads best whole"
    )]
    pub fn solve(
        &mut self,
        changed: Option<&[PrimitiveId]>,
        settings: &GlobalSettings,
        mut companions: Companions<'_>,
    ) -> GlobalOutcome {
        let all: Vec<PrimitiveId> = self.primitives.keys().copied().collect();
        let mut ids = component(self, changed.unwrap_or(&all));
        let mut held = match (changed, settings.reach) {
            (Some(changed), Some(reach)) => held_beyond(self, &ids, changed, reach),
            _ => BTreeSet::new(),
        };
        let mut outcome = GlobalOutcome {
            solved: ids.difference(&held).copied().collect(),
            ..GlobalOutcome::default()
        };
        if ids.is_empty() {
            return outcome;
        }
        loop {
            let relations = self.relations_between(&ids, &held);
            outcome.relations = relations.len();
            if relations.is_empty() {
                // Unrelated parts are at their own snaps' optimum already, unless the
                // user dimensioned them: those are refitted with their dimensions held.
                ids = self.dimensioned(&ids, &held);
                if ids.is_empty() {
                    return outcome;
                }
                held.clear();
                outcome.solved = ids.iter().copied().collect();
            }
            let parts = self.parts(&ids, &held);
            let mut compiled = compile(&parts, &relations, settings);
            let (start, keys) = self.warm_start(&parts, &compiled.problem);
            let mut solver = Solver::new(&settings.solver);
            if let Some(flag) = companions.cancel {
                solver = solver.cancel(flag);
            }
            let since = companions.clock.map(|clock| Since {
                clock,
                start: clock.elapsed(),
            });
            if let Some(clock) = &since {
                solver = solver.clock(clock);
            }
            if let Some(observer) = companions.observer.as_deref_mut() {
                solver = solver.observer(observer);
            }
            outcome.solves += 1;
            let Ok(report) = solver.solve(&mut compiled.problem, &start) else {
                outcome.reverted = true;
                return outcome;
            };
            log_report(parts.len(), relations.len(), &report, &compiled.problem);
            let solved: Vec<(PrimitiveId, Primitive, f64)> = parts
                .iter()
                .filter(|p| !p.held)
                .map(|p| {
                    let local = p.local.with_params(&report.x[p.start..p.start + p.len]);
                    // The dimensions held to the solver's tolerance, stored exactly.
                    let primitive = p.dimensions.iter().fold(
                        p.frame.out_of_frame(&local),
                        |primitive, (quantity, value)| {
                            primitive
                                .with_quantity(*quantity, *value)
                                .unwrap_or(primitive)
                        },
                    );
                    let rms = p.assignment.map_or(0.0, |a| fit_rms(&primitive, a));
                    (p.id, primitive, rms)
                })
                .collect();
            let blamed = if report.termination == Termination::Cancelled
                || !solved.iter().all(|(_, p, _)| p.is_finite())
            {
                outcome.report = Some(report);
                outcome.reverted = true;
                return outcome;
            } else {
                let values = compiled.problem.constraints(&report.x);
                blame(
                    &parts,
                    &solved,
                    &compiled.hard,
                    &values,
                    &report,
                    &relations,
                    settings,
                )
            };
            match blamed {
                None => {
                    self.accept(solved, keys, &report);
                    outcome.report = Some(report);
                    return outcome;
                }
                Some((index, message)) => {
                    outcome.report = Some(report);
                    let exhausted = outcome.conflicts.len() >= settings.max_conflicts;
                    if exhausted {
                        outcome.reverted = true;
                        return outcome;
                    }
                    if let Some(r) = self.relations.get_mut(index) {
                        r.mode = Mode::Off;
                    }
                    if let Some(&relation) = self.relation_ids.get(index) {
                        outcome.conflicts.push(Conflict { relation, message });
                    }
                }
            }
        }
    }
}

impl Document {
    /// The parts of `ids` not `held` that have dimensions.
    fn dimensioned(
        &self,
        ids: &BTreeSet<PrimitiveId>,
        held: &BTreeSet<PrimitiveId>,
    ) -> BTreeSet<PrimitiveId> {
        ids.difference(held)
            .copied()
            .filter(|id| self.dimensions_of(*id).next().is_some())
            .collect()
    }

    /// The parts of a solve of `ids`, with their frames and variable ranges.
    fn parts(&self, ids: &BTreeSet<PrimitiveId>, held: &BTreeSet<PrimitiveId>) -> Vec<Part<'_>> {
        let mut parts = Vec::with_capacity(ids.len());
        let mut start = 0;
        for id in ids {
            let Some(placed) = self.primitives.get(id) else {
                continue;
            };
            let record = self.snaps.get(id);
            let frame = Frame::of(&placed.primitive);
            let local = frame.into_frame(&placed.primitive);
            let is_held = held.contains(id);
            let len = if is_held { 0 } else { local.params().len() };
            parts.push(Part {
                id: *id,
                primitive: &placed.primitive,
                assignment: record.map(|r| &r.assignment),
                own_rms: record.map(|r| r.rms),
                frame,
                local,
                start,
                len,
                held: is_held,
                dimensions: self
                    .dimensions_of(*id)
                    .map(|d| (d.quantity, d.value))
                    .collect(),
            });
            start += len;
        }
        parts
    }

    /// The active relations among `ids` that reach a part not `held`, with their
    /// indices.
    fn relations_between(
        &self,
        ids: &BTreeSet<PrimitiveId>,
        held: &BTreeSet<PrimitiveId>,
    ) -> Vec<(usize, &Relation)> {
        self.relations
            .iter()
            .enumerate()
            .filter(|(_, r)| {
                active(r)
                    && r.members.iter().all(|m| ids.contains(m))
                    && r.members.iter().any(|m| !held.contains(m))
            })
            .collect()
    }

    /// The start of a solve: the parts as they are, and the multipliers of the same
    /// constraints in earlier solves (zero for new ones); with the constraints' keys.
    fn warm_start(&self, parts: &[Part<'_>], problem: &Problem) -> (Start, Vec<(String, usize)>) {
        let keys = constraint_keys(problem);
        let ne = problem.equality_count();
        let warm: Vec<f64> = keys
            .iter()
            .map(|k| self.multipliers.get(k).copied().unwrap_or(0.0))
            .collect();
        let start = Start {
            x: parts
                .iter()
                .filter(|p| !p.held)
                .flat_map(|p| p.local.params())
                .collect(),
            multipliers: Some(Multipliers {
                equality: warm[..ne].to_vec(),
                inequality: warm[ne..].iter().map(|v| v.max(0.0)).collect(),
            }),
            penalty: None,
        };
        (start, keys)
    }
}

impl Document {
    /// Sets the mode of relation `id` and re-solves the parts it touches (and those
    /// related to them); `None` when there is no such relation.
    pub fn set_relation_mode(
        &mut self,
        id: RelationId,
        mode: Mode,
        settings: &GlobalSettings,
        companions: Companions<'_>,
    ) -> Option<GlobalOutcome> {
        let relation = self.relation_mut(id)?;
        relation.mode = mode;
        let members = relation.members.clone();
        Some(self.solve(Some(&members), settings, companions))
    }
}

/// Logs how a solve went (at debug level).
fn log_report(parts: usize, relations: usize, report: &SolveReport, problem: &Problem) {
    log::debug!(
        "global solve of {parts} part(s), {relations} relation(s): {:?} after {} outer, {} inner, {} evaluations, ‖c‖∞ {:.2e} at {:?}, objective {:.3e}",
        report.termination,
        report.outer_iterations,
        report.inner_iterations,
        report.evaluations,
        report.max_violation,
        report
            .worst_constraint
            .and_then(|k| problem.constraint_label(k)),
        report.objective
    );
}

impl Document {
    /// Stores a solve's parts and remembers its multipliers for the next one.
    fn accept(
        &mut self,
        solved: Vec<(PrimitiveId, Primitive, f64)>,
        keys: Vec<(String, usize)>,
        report: &SolveReport,
    ) {
        let values = report
            .multipliers
            .equality
            .iter()
            .chain(&report.multipliers.inequality);
        for (key, value) in keys.into_iter().zip(values) {
            self.multipliers.insert(key, *value);
        }
        for (id, primitive, rms) in solved {
            if let Some(placed) = self.primitives.get_mut(&id) {
                placed.primitive = primitive;
                placed.fit.rms = rms;
            }
        }
    }
}

/// A key per constraint of `problem` that stays the same between solves of a growing
/// model: its label and how many constraints before it have that label.
fn constraint_keys(problem: &Problem) -> Vec<(String, usize)> {
    let count = problem.equality_count() + problem.inequality_count();
    let mut seen: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    (0..count)
        .map(|k| {
            let label = problem.constraint_label(k).unwrap_or("");
            let n = seen.entry(label).or_insert(0);
            *n += 1;
            (label.to_owned(), *n - 1)
        })
        .collect()
}

/// The relation responsible for a broken solve (its index in [`Document::relations`],
/// with a message naming it and saying why), or `None` when the solve is fine.
fn blame(
    parts: &[Part<'_>],
    solved: &[(PrimitiveId, Primitive, f64)],
    hard: &[(usize, std::ops::Range<usize>)],
    values: &[f64],
    report: &SolveReport,
    relations: &[(usize, &Relation)],
    settings: &GlobalSettings,
) -> Option<(usize, String)> {
    let relation = |index: usize| relations.iter().find(|(i, _)| *i == index).map(|r| r.1);
    // Infeasible: the hard relation with the largest residual.
    let residual = |range: &std::ops::Range<usize>| {
        range
            .clone()
            .map(|i| values.get(i).map_or(0.0, |v| v.abs()))
            .fold(0.0, f64::max)
    };
    let worst = hard
        .iter()
        .map(|(index, range)| (*index, residual(range)))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((index, value)) = worst {
        if value > settings.violation_tol {
            let r = relation(index)?;
            return Some((
                index,
                format!(
                    "{} switched off: the hard relations cannot all hold (its residual stays at {value:.2e})",
                    describe(index, r)
                ),
            ));
        }
    }
    // A fit got much worse: the strongest pull among the relations of those parts.
    let worse: Vec<(PrimitiveId, f64, f64)> = parts
        .iter()
        .filter(|p| !p.held)
        .zip(solved)
        .filter_map(|(part, (_, primitive, rms))| {
            // A dimensioned part may leave its strokes: the user's size overrides them.
            if !part.dimensions.is_empty() {
                return None;
            }
            let own = part.own_rms?;
            let allowed = settings.max_worsening * own.max(WORSENING_FLOOR * part.primitive.size());
            (*rms > allowed && primitive.is_finite()).then_some((part.id, own, *rms))
        })
        .collect();
    if worse.is_empty() {
        return None;
    }
    let pull = |range: &std::ops::Range<usize>| {
        range
            .clone()
            .map(|i| report.multipliers.equality.get(i).map_or(0.0, |l| l.abs()))
            .sum::<f64>()
    };
    let (index, _) = hard
        .iter()
        .filter(|(index, _)| {
            relation(*index)
                .is_some_and(|r| r.members.iter().any(|m| worse.iter().any(|w| w.0 == *m)))
        })
        .map(|(index, range)| (*index, pull(range)))
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let r = relation(index)?;
    let (id, own, rms) = worse[0];
    Some((
        index,
        format!(
            "{} switched off: with it, part #{} fits its strokes {:.1}× worse (RMS {rms:.3} against {own:.3})",
            describe(index, r),
            id.0,
            rms / own.max(f64::MIN_POSITIVE)
        ),
    ))
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::{Companions, GlobalSettings, Mode};
    use crate::core::model::{Document, Fit, Placed, PrimitiveId, Quantity, Relation, RelationId};
    use crate::core::primitive::{Cylinder, Feature, Primitive};
    use crate::core::relation::RelationKind;

    fn cylinder(x: f64, axis: DVec3) -> Placed {
        Placed {
            primitive: Primitive::Cylinder(Cylinder {
                center: DVec3::new(x, 0.0, 0.0),
                axis: axis.normalize(),
                length: 10.0,
                radius: 2.0,
            }),
            fit: Fit::default(),
        }
    }

    fn relate(
        doc: &mut Document,
        kind: RelationKind,
        a: PrimitiveId,
        b: PrimitiveId,
    ) -> RelationId {
        doc.add_relation(Relation {
            kind,
            members: vec![a, b],
            features: vec![Some(Feature::Top), Some(Feature::Top)],
            mode: Mode::Hard,
        })
        .expect("the relation suits its members")
    }

    fn axis(doc: &Document, id: PrimitiveId) -> DVec3 {
        match &doc.get(id).expect("placed").primitive {
            Primitive::Cylinder(c) => c.axis,
            _ => unreachable!("only cylinders here"),
        }
    }

    #[test]
    fn contradicting_hard_relations_end_with_one_switched_off_and_named() {
        let mut doc = Document::new();
        let a = doc.add(cylinder(0.0, DVec3::Y));
        let b = doc.add(cylinder(8.0, DVec3::new(0.3, 1.0, 0.1)));
        let parallel = relate(&mut doc, RelationKind::Parallel, a, b);
        let orthogonal = relate(&mut doc, RelationKind::Orthogonal, a, b);
        let outcome = doc.solve(None, &GlobalSettings::default(), Companions::default());
        assert_eq!(outcome.conflicts.len(), 1, "{outcome:?}");
        assert!(!outcome.reverted, "the rest is solved: {outcome:?}");
        let off = outcome.conflicts[0].relation;
        let relation = doc.relation(off).expect("the conflict names a relation");
        assert_eq!(relation.mode, Mode::Off);
        let message = &outcome.conflicts[0].message;
        let index = doc.relation_position(off).expect("a relation");
        assert!(
            message.contains(&format!("relation {index} ("))
                && message.contains(relation.kind.name()),
            "the message names the relation: {message}"
        );
        // The relation left on holds.
        let other = if off == parallel {
            orthogonal
        } else {
            parallel
        };
        let kept = doc.relation(other).expect("kept").kind;
        let d = axis(&doc, a).dot(axis(&doc, b));
        match kept {
            RelationKind::Parallel => assert!(d.abs() > 1.0 - 1e-6, "parallel: {d}"),
            _ => assert!(d.abs() < 1e-3, "orthogonal: {d}"),
        }
    }

    #[test]
    fn only_the_changed_parts_component_is_solved() {
        let mut doc = Document::new();
        let a = doc.add(cylinder(0.0, DVec3::Y));
        let b = doc.add(cylinder(8.0, DVec3::new(0.1, 1.0, 0.0)));
        let c = doc.add(cylinder(16.0, DVec3::new(0.2, 1.0, 0.0)));
        let d = doc.add(cylinder(24.0, DVec3::new(0.3, 1.0, 0.0)));
        relate(&mut doc, RelationKind::Parallel, a, b);
        relate(&mut doc, RelationKind::Parallel, c, d);
        let before = doc.clone();
        let outcome = doc.solve(
            Some(&[b]),
            &GlobalSettings::default(),
            Companions::default(),
        );
        assert_eq!(outcome.solved, vec![a, b]);
        assert!(axis(&doc, a).cross(axis(&doc, b)).length() < 1e-4);
        assert_eq!(doc.get(c), before.get(c), "another component is left alone");
        assert_eq!(doc.get(d), before.get(d));
    }

    #[test]
    fn a_conflicting_change_is_settled_where_it_was_made() {
        let mut doc = Document::new();
        let b = doc.add(cylinder(0.0, DVec3::Y));
        let c = doc.add(cylinder(8.0, DVec3::new(0.05, 1.0, 0.0)));
        let d = doc.add(cylinder(16.0, DVec3::new(-0.05, 1.0, 0.0)));
        relate(&mut doc, RelationKind::Parallel, c, b);
        relate(&mut doc, RelationKind::Parallel, d, b);
        let settings = GlobalSettings::default();
        doc.solve(None, &settings, Companions::default());
        let before = doc.clone();
        // The new part is parallel to one settled leg and orthogonal to another: the
        // two cannot both hold while the legs stay parallel.
        let n = doc.add(cylinder(24.0, DVec3::new(0.5, 1.0, 0.0)));
        relate(&mut doc, RelationKind::Parallel, n, c);
        relate(&mut doc, RelationKind::Orthogonal, n, d);
        let outcome = doc.solve(Some(&[n]), &settings, Companions::default());
        assert_eq!(outcome.conflicts.len(), 1, "{outcome:?}");
        assert!(!outcome.reverted, "{outcome:?}");
        assert_eq!(
            outcome.solved,
            vec![c, d, n],
            "b is beyond the change's reach"
        );
        assert_eq!(doc.get(b), before.get(b), "the settled part stays put");
        assert!(axis(&doc, c).cross(axis(&doc, b)).length() < 1e-3);
        assert!(axis(&doc, d).cross(axis(&doc, b)).length() < 1e-3);
    }

    #[test]
    fn off_relations_are_ignored_and_soft_ones_compromise() {
        let mut doc = Document::new();
        let a = doc.add(cylinder(0.0, DVec3::Y));
        let b = doc.add(cylinder(8.0, DVec3::new(0.3, 1.0, 0.0)));
        let parallel = relate(&mut doc, RelationKind::Parallel, a, b);
        doc.relations_mut()[0].mode = Mode::Off;
        let before = doc.clone();
        doc.solve(None, &GlobalSettings::default(), Companions::default());
        let angle = |doc: &Document| axis(doc, a).angle_between(axis(doc, b));
        assert!(
            (angle(&doc) - angle(&before)).abs() < 1e-9,
            "off: nothing moves"
        );
        let settings = GlobalSettings::default();
        doc.set_relation_mode(parallel, Mode::Soft, &settings, Companions::default());
        let soft = angle(&doc);
        assert!(soft < 0.5 * angle(&before), "soft: closer ({soft})");
        doc.set_relation_mode(parallel, Mode::Hard, &settings, Companions::default());
        assert!(angle(&doc) < 1e-3, "hard: parallel ({})", angle(&doc));
    }

    fn radius(doc: &Document, id: PrimitiveId) -> f64 {
        doc.get(id)
            .and_then(|p| p.primitive.quantity(Quantity::Radius))
            .expect("a cylinder")
    }

    #[test]
    fn a_typed_radius_holds_and_the_rest_is_refitted_to_the_strokes() {
        use glam::DVec2;

        use crate::core::sketch::{StrokeClass, StrokeId};
        use crate::core::snap::{snap, SnapContext, SnapSettings};

        // The outline of a side-on cylinder: two lines 20 apart, 60 long (sketch space).
        let line = |x: f64| {
            (0..=20)
                .map(|i| DVec2::new(x, 100.0 + 3.0 * f64::from(i)))
                .collect::<Vec<_>>()
        };
        let (l, r) = (line(40.0), line(60.0));
        let context = SnapContext::new([
            (StrokeId(0), l.as_slice(), StrokeClass::Silhouette),
            (StrokeId(1), r.as_slice(), StrokeClass::Silhouette),
        ]);
        let dropped = Primitive::Cylinder(Cylinder {
            center: DVec3::new(52.0, -128.0, 0.0),
            axis: DVec3::Y,
            length: 70.0,
            radius: 12.0,
        });
        let result = snap(&context, &dropped, &SnapSettings::default()).expect("snaps");
        let mut doc = Document::new();
        let id = doc.add_snapped(&result);
        let Primitive::Cylinder(fitted) = doc.get(id).expect("placed").primitive.clone() else {
            unreachable!("a cylinder")
        };
        assert!((fitted.radius - 10.0).abs() < 0.2, "{fitted:?}");
        // Moved off-centre a little, then dimensioned: the solve recentres it between
        // the lines with the typed radius.
        let mut moved = fitted.clone();
        moved.center.x += 3.0;
        moved.length *= 1.1;
        doc.insert(
            id,
            Placed {
                primitive: Primitive::Cylinder(moved),
                fit: doc.get(id).expect("placed").fit.clone(),
            },
        );
        doc.set_dimension(id, Quantity::Radius, 12.5)
            .expect("a cylinder has a radius");
        assert!((radius(&doc, id) - 12.5).abs() < 1e-12, "set at once");
        let outcome = doc.solve(
            Some(&[id]),
            &GlobalSettings::default(),
            Companions::default(),
        );
        assert!(outcome.report.is_some(), "solved without relations");
        assert!(
            outcome.conflicts.is_empty() && !outcome.reverted,
            "{outcome:?}"
        );
        let Primitive::Cylinder(solved) = doc.get(id).expect("placed").primitive.clone() else {
            unreachable!("a cylinder")
        };
        assert!(
            (solved.radius - 12.5).abs() <= 1e-6 * 12.5,
            "the dimension holds: {}",
            solved.radius
        );
        assert!(
            (solved.center.x - 50.0).abs() < 0.5,
            "recentred between its strokes: {solved:?}"
        );
        assert!(
            (solved.length - fitted.length).abs() < 0.05 * fitted.length,
            "the length is refitted to the strokes: {} against {}",
            solved.length,
            fitted.length
        );
    }

    #[test]
    fn a_hard_relation_against_two_dimensions_is_switched_off() {
        let mut doc = Document::new();
        let a = doc.add(cylinder(0.0, DVec3::Y));
        let b = doc.add(cylinder(8.0, DVec3::Y));
        let same = relate(&mut doc, RelationKind::SameRadius, a, b);
        doc.set_dimension(a, Quantity::Radius, 2.0).expect("valid");
        doc.set_dimension(b, Quantity::Radius, 3.0).expect("valid");
        let outcome = doc.solve(None, &GlobalSettings::default(), Companions::default());
        assert_eq!(outcome.conflicts.len(), 1, "{outcome:?}");
        assert_eq!(outcome.conflicts[0].relation, same);
        assert!(!outcome.reverted, "{outcome:?}");
        assert_eq!(doc.relations()[0].mode, Mode::Off);
        assert_eq!(doc.dimensions().len(), 2, "dimensions are never dropped");
        assert!((radius(&doc, a) - 2.0).abs() <= 2e-6, "{}", radius(&doc, a));
        assert!((radius(&doc, b) - 3.0).abs() <= 3e-6, "{}", radius(&doc, b));
    }

    #[test]
    fn a_dimension_and_a_relation_that_agree_both_hold() {
        let mut doc = Document::new();
        let a = doc.add(cylinder(0.0, DVec3::Y));
        let mut other = cylinder(8.0, DVec3::Y);
        if let Primitive::Cylinder(c) = &mut other.primitive {
            c.radius = 2.6;
        }
        let b = doc.add(other);
        relate(&mut doc, RelationKind::SameRadius, a, b);
        doc.set_dimension(a, Quantity::Radius, 2.4).expect("valid");
        let outcome = doc.solve(
            Some(&[b]),
            &GlobalSettings::default(),
            Companions::default(),
        );
        assert!(outcome.conflicts.is_empty(), "{outcome:?}");
        assert!(
            (radius(&doc, a) - 2.4).abs() <= 2.4e-6,
            "{}",
            radius(&doc, a)
        );
        assert!(
            (radius(&doc, b) - 2.4).abs() <= 2.4e-3,
            "{}",
            radius(&doc, b)
        );
    }
}
