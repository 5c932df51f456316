//! The global solve (problem 2 of the optimisation details of Shtof, Agathos, Gingold,
//! Shamir and Cohen-Or, *Geosemantic Snapping for Sketch-Based Modeling*, Eurographics
//! 2013): min Σφ_p s.t. every C_p and every hard ψ_g, with soft relations as weighted
//! terms of the objective, from x_start = (the current primitives: the previous solution
//! and the new part's snap).
//!
//! **Frames.** Each primitive keeps the variables of its own snapping problem, in its own
//! normalised frame (centre at the origin, size 1, see [`Frame`](crate::snap::Frame)), so φ_p is exactly the
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
//! the model.
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
//! **Before solving** ([`structure`]), the hard relations are read as statements: those
//! that say again what the relations before them say (a parallel between two directions
//! already parallel through others) are left out of the solve, as they hold when those
//! hold (checked after it); those that contradict the relations before them whatever
//! the numbers (an orthogonal between two directions already parallel, a fourth
//! direction orthogonal to three that are pairwise so) are switched off at once, without
//! a solve. A model with every pair of 200 parts related solves a few hundred relations,
//! not 19,900.
//!
//! After [`GlobalSettings::max_conflicts`] rounds, or once the solves after the first have
//! spent one solve's evaluation cap, a still broken component is put back as it was: the
//! user is never left with a broken model, nor kept waiting for round after round of a
//! large solve that does not converge.

mod compile;
mod conflicts;
mod reach;
mod settings;
mod structure;
mod warm;

use std::collections::{BTreeSet, HashSet};
use std::ops::ControlFlow;
use std::time::Duration;

use super::{Document, PrimitiveId, Quantity, Relation, RelationId};
use crate::primitive::Primitive;
use crate::relation::Mode;
use crate::snap::fit_rms;
use crate::solve::{
    Clock, Problem, SolveContext, SolveError, SolveReport, Solver, Start, Termination,
};
use compile::{compile, Compiled, Part};
use conflicts::{blame, contradicting_conflicts, contradictions};
use reach::{component, held_beyond};

pub use settings::GlobalSettings;
pub(crate) use warm::WarmStarts;

/// What a relation's constraint group is keyed by.
pub(crate) type RelationKey = RelationId;

/// A relation taking part in a solve: its id, its place in [`Document::relations`]
/// (which messages and constraint labels name it by) and the relation.
#[derive(Clone, Copy, Debug)]
pub(super) struct Related<'d> {
    pub(super) id: RelationId,
    pub(super) position: usize,
    pub(super) relation: &'d Relation,
}

/// A part's fit may worsen freely up to this fraction of its size (RMS), whatever its own
/// snap achieved.
pub const WORSENING_FLOOR: f64 = 0.005;

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
    /// Solves run (1 plus one per round of conflicts found by solving).
    pub solves: usize,
    /// Solver evaluations in all of them.
    pub evaluations: u64,
    /// Hard relations taken into account but not solved, as the relations before them
    /// imply them (see [`GlobalSettings`] and the module docs): they hold when those hold.
    pub implied: usize,
    /// Whether the result was refused and the parts put back as they were.
    pub reverted: bool,
}

/// The companions of a global solve (cancel flag, clock, observer): the solver's own
/// [`SolveContext`], under the name the model's API gives it.
pub type Companions<'a> = SolveContext<'a>;

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

impl Document {
    /// Solves the components of the model holding the `changed` parts (every part when
    /// `changed` is `None`) with their relations, switching off conflicting relations (see
    /// the module docs), and stores the solved primitives with their new fits.
    ///
    /// # Examples
    ///
    /// ```
    /// use glam::DVec3;
    /// use geosnap_core::model::{Companions, Document, Fit, GlobalSettings, Placed, Relation};
    /// use geosnap_core::primitive::{Cylinder, Feature, Primitive};
    /// use geosnap_core::relation::{Mode, RelationKind};
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
    ///     inferred: None,
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
    pub fn solve(
        &mut self,
        changed: Option<&[PrimitiveId]>,
        settings: &GlobalSettings,
        mut companions: Companions<'_>,
    ) -> GlobalOutcome {
        let all: Vec<PrimitiveId> = self.primitives.keys().copied().collect();
        let ids = component(self, changed.unwrap_or(&all));
        let held = match (changed, settings.reach()) {
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
        let mut scope = Scope {
            ids,
            held,
            unmet: HashSet::new(),
            first_evaluations: None,
        };
        while let ControlFlow::Continue(()) =
            self.solve_round(&mut scope, settings, &mut companions, &mut outcome)
        {}
        outcome
    }

    /// One round of the global solve: compile, solve, blame. `Continue` when a
    /// conflicting relation was switched off and the scope must be solved again; `Break`
    /// when the solve is stored or put back (as `outcome` says).
    fn solve_round(
        &mut self,
        scope: &mut Scope,
        settings: &GlobalSettings,
        companions: &mut Companions<'_>,
        outcome: &mut GlobalOutcome,
    ) -> ControlFlow<()> {
        let all = self.relations_between(&scope.ids, &scope.held);
        outcome.relations = all.len();
        let mut structure = structure::analyse(self, &all);
        structure.implied.retain(|id| !scope.unmet.contains(id));
        if !structure.contradicted.is_empty() {
            let named = structure.named(&all);
            self.switch_off(named, outcome);
            return ControlFlow::Continue(());
        }
        outcome.implied = structure.implied.len();
        let relations: Vec<Related<'_>> = all
            .iter()
            .filter(|r| !structure.implied.contains(&r.id))
            .copied()
            .collect();
        if relations.is_empty() {
            // Unrelated parts are at their own snaps' optimum already, unless the user
            // dimensioned them: those are refitted with their dimensions held.
            scope.ids = self.dimensioned(&scope.ids, &scope.held);
            if scope.ids.is_empty() {
                return ControlFlow::Break(());
            }
            scope.held.clear();
            outcome.solved = scope.ids.iter().copied().collect();
        }
        let parts = self.parts(&scope.ids, &scope.held);
        let mut compiled = compile(&parts, &relations, settings);
        let (start, keys) = self.warm_start(&parts, &compiled);
        outcome.solves += 1;
        let Ok(report) = run_solver(&mut compiled.problem, &start, settings, companions) else {
            outcome.reverted = true;
            return ControlFlow::Break(());
        };
        outcome.evaluations += report.evaluations;
        scope.first_evaluations.get_or_insert(report.evaluations);
        log_report(parts.len(), relations.len(), &report, &compiled.problem);
        let solved = solved_parts(&parts, &compiled, &report);
        if report.termination == Termination::Cancelled
            || !solved.iter().all(|(_, p, _)| p.is_finite())
        {
            outcome.report = Some(report);
            outcome.reverted = true;
            return ControlFlow::Break(());
        }
        let values = compiled.problem.constraints(&report.x);
        let hard = compiled.hard_relations();
        // Contradictions first, all at once, from the rank of the constraints: where
        // the solve ended at the least violation it could reach (infeasible or stalled),
        // not where it ran out of effort half way.
        let contradicting = if matches!(
            report.termination,
            Termination::Infeasible | Termination::Stalled
        ) {
            contradictions(&mut compiled, &report.x, &values, settings.violation_tol())
        } else {
            Vec::new()
        };
        if !contradicting.is_empty() && may_solve_again(scope, outcome, settings) {
            outcome.report = Some(report);
            self.switch_off(contradicting_conflicts(contradicting, &relations), outcome);
            return ControlFlow::Continue(());
        }
        let blamed = blame(
            &parts, &solved, &hard, &values, &report, &relations, settings,
        );
        let Some(conflict) = blamed else {
            let unmet = structure.unmet(self, &all, &solved, settings.violation_tol());
            if !unmet.is_empty() {
                // Implied relations came out beyond the tolerance (at the end of a long
                // chain of relations, each just within it): solve them too.
                scope.unmet.extend(unmet);
                return ControlFlow::Continue(());
            }
            self.accept(solved, keys, &report);
            outcome.report = Some(report);
            return ControlFlow::Break(());
        };
        outcome.report = Some(report);
        if !may_solve_again(scope, outcome, settings) {
            outcome.reverted = true;
            return ControlFlow::Break(());
        }
        self.switch_off(vec![conflict], outcome);
        ControlFlow::Continue(())
    }

    /// Switches the relations of `conflicts` off and records them in `outcome`.
    fn switch_off(&mut self, conflicts: Vec<Conflict>, outcome: &mut GlobalOutcome) {
        for conflict in conflicts {
            if let Some(r) = self.relation_mut(conflict.relation) {
                r.mode = Mode::Off;
            }
            outcome.conflicts.push(conflict);
        }
    }
}

/// Whether a broken solve may switch a relation off and solve again: after at most
/// [`GlobalSettings::max_conflicts`] rounds, and while the solves after the first have
/// spent less than one solve's evaluation cap in all. A large component whose solve
/// runs to its cap would otherwise cost that cap again per round: 200 parts made
/// coaxial all at once took 2.4 s a round, and nine rounds.
fn may_solve_again(scope: &Scope, outcome: &GlobalOutcome, settings: &GlobalSettings) -> bool {
    let again = outcome
        .evaluations
        .saturating_sub(scope.first_evaluations.unwrap_or(0));
    outcome.solves <= settings.max_conflicts() && again < settings.solver().max_evaluations()
}

/// The parts a global solve takes (`ids`) and those of them it holds where they are.
struct Scope {
    ids: BTreeSet<PrimitiveId>,
    held: BTreeSet<PrimitiveId>,
    /// Implied relations that did not hold after a solve without them: solved from then
    /// on.
    unmet: HashSet<RelationKey>,
    /// The evaluations of the first solve.
    first_evaluations: Option<u64>,
}

/// Runs the solver on `problem` from `start`, with the companions and a clock that starts
/// now.
fn run_solver(
    problem: &mut Problem,
    start: &Start,
    settings: &GlobalSettings,
    companions: &mut Companions<'_>,
) -> Result<SolveReport, SolveError> {
    let since = companions.clock.map(|clock| Since {
        clock,
        start: clock.elapsed(),
    });
    let mut context = companions.reborrow();
    if let Some(clock) = &since {
        context.clock = Some(clock);
    }
    Solver::with_context(settings.solver(), context).solve(problem, start)
}

/// The free parts as solved (in model space, dimensions stored exactly), with their fits'
/// RMS.
fn solved_parts(
    parts: &[Part<'_>],
    compiled: &Compiled,
    report: &SolveReport,
) -> Vec<(PrimitiveId, Primitive, f64)> {
    parts
        .iter()
        .zip(&compiled.variables)
        .filter(|(p, _)| !p.held)
        .map(|(p, vars)| {
            let local = p.local.with_params(&report.x[vars.clone()]);
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
        .collect()
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

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::{Companions, GlobalSettings, Mode};
    use crate::model::{Document, Fit, Placed, PrimitiveId, Quantity, Relation, RelationId};
    use crate::primitive::{Cylinder, Feature, Primitive};
    use crate::relation::RelationKind;

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
            inferred: None,
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
    fn contradictions_in_the_relations_alone_are_found_before_any_solve() {
        // Two triangles of parallels closed by an orthogonal each: the closing ones
        // contradict the parallels before them whatever the numbers, and one solve
        // follows.
        let mut doc = Document::new();
        let mut closing = Vec::new();
        for x in [0.0, 100.0] {
            let a = doc.add(cylinder(x, DVec3::Y));
            let b = doc.add(cylinder(x + 8.0, DVec3::new(0.1, 1.0, 0.05)));
            let c = doc.add(cylinder(x + 16.0, DVec3::new(-0.1, 1.0, 0.1)));
            relate(&mut doc, RelationKind::Parallel, a, b);
            relate(&mut doc, RelationKind::Parallel, b, c);
            closing.push(relate(&mut doc, RelationKind::Orthogonal, a, c));
        }
        let outcome = doc.solve(None, &GlobalSettings::default(), Companions::default());
        let mut blamed: Vec<RelationId> = outcome.conflicts.iter().map(|c| c.relation).collect();
        blamed.sort();
        assert_eq!(blamed, closing, "{outcome:#?}");
        assert_eq!(outcome.solves, 1, "{outcome:#?}");
        assert!(
            outcome.conflicts[0].message.contains("contradicts"),
            "{outcome:#?}"
        );
    }

    #[test]
    fn every_contradiction_is_found_in_one_pass_and_the_newest_is_blamed() {
        // Two pairs of equal lengths against the user's lengths: the relations alone
        // are consistent, the numbers are not. Both are found from one solve's Jacobian,
        // then one more solve.
        let mut doc = Document::new();
        let mut equal = Vec::new();
        for x in [0.0, 100.0] {
            let a = doc.add(cylinder(x, DVec3::Y));
            let b = doc.add(cylinder(x + 8.0, DVec3::new(0.1, 1.0, 0.05)));
            doc.set_dimension(a, Quantity::Length, 10.0)
                .expect("a length");
            doc.set_dimension(b, Quantity::Length, 14.0)
                .expect("a length");
            equal.push(relate(&mut doc, RelationKind::EqualLength, a, b));
        }
        let outcome = doc.solve(None, &GlobalSettings::default(), Companions::default());
        let mut blamed: Vec<RelationId> = outcome.conflicts.iter().map(|c| c.relation).collect();
        blamed.sort();
        assert_eq!(blamed, equal, "{outcome:#?}");
        assert_eq!(outcome.solves, 2, "{outcome:#?}");
        assert!(
            outcome.conflicts[0].message.contains("contradicts"),
            "{outcome:#?}"
        );
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
    fn multipliers_stay_with_their_group_when_a_group_is_added_before_it() {
        use std::collections::BTreeSet;

        use super::compile::compile;

        let mut doc = Document::new();
        let a = doc.add(cylinder(0.0, DVec3::Y));
        let b = doc.add(cylinder(8.0, DVec3::new(0.3, 1.0, 0.1)));
        relate(&mut doc, RelationKind::Parallel, a, b);
        let settings = GlobalSettings::default();
        doc.solve(None, &settings, Companions::default());
        // The warm start of the relation's equalities, and where they are.
        let warm = |doc: &Document| {
            let ids: BTreeSet<PrimitiveId> = doc.primitives.keys().copied().collect();
            let parts = doc.parts(&ids, &BTreeSet::new());
            let relations = doc.relations_between(&ids, &BTreeSet::new());
            let compiled = compile(&parts, &relations, &settings);
            let (start, _) = doc.warm_start(&parts, &compiled);
            let range = compiled.hard_relations()[0].1.clone();
            let equality = start.multipliers.expect("warm").equality;
            (equality[range.clone()].to_vec(), range)
        };
        let (before, at) = warm(&doc);
        assert!(before.iter().any(|m| *m != 0.0), "{before:?}");
        // A dimension of the first part: its group comes before the relation's.
        doc.set_dimension(a, Quantity::Radius, 2.0).expect("valid");
        let (after, moved) = warm(&doc);
        assert_eq!(moved.start, at.start + 1, "the relation's equalities moved");
        assert_eq!(after, before, "its multipliers moved with them");
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
    fn a_held_part_is_never_taken_for_a_free_one_that_collapsed() {
        // A long settled part held beyond the change's reach, before two short free
        // ones in the solve's list: each free part's extents are compared with its own,
        // not with the held part's (a length of 400 against one of 10 read as a
        // collapse, and a relation that holds was switched off for it).
        let mut doc = Document::new();
        let mut long = cylinder(0.0, DVec3::Y);
        if let Primitive::Cylinder(c) = &mut long.primitive {
            c.length = 400.0;
        }
        let b = doc.add(long);
        let c = doc.add(cylinder(8.0, DVec3::new(0.05, 1.0, 0.0)));
        relate(&mut doc, RelationKind::Parallel, c, b);
        let settings = GlobalSettings::default();
        doc.solve(None, &settings, Companions::default());
        let n = doc.add(cylinder(16.0, DVec3::new(0.1, 1.0, 0.0)));
        relate(&mut doc, RelationKind::Parallel, n, c);
        let outcome = doc.solve(Some(&[n]), &settings, Companions::default());
        assert_eq!(outcome.solved, vec![c, n], "b is held: {outcome:?}");
        assert!(outcome.conflicts.is_empty(), "{outcome:?}");
        assert!(axis(&doc, n).cross(axis(&doc, c)).length() < 1e-3);
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

        use crate::sketch::{StrokeClass, StrokeId};
        use crate::snap::{snap, SnapContext, SnapSettings};

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
