//! What happens when a part is released: relation inference against the placed parts
//! ([`crate::relation::infer`]), with the view's mirror ambiguity settled by the
//! relations.
//!
//! An orthographic drawing shows a solid of revolution and its reflection in the
//! view-parallel plane through its centre alike in outline (the axis (x, y, z) and
//! (x, y, −z) project alike); what can tell them apart is which end is drawn whole (the
//! end facing the viewer) and which only on its near half ([`super::reading`]). Where
//! the strokes say which end faces the viewer, that reading stands: the drawing's
//! ambiguity is never settled against the drawing. Where they do not (both ends whole,
//! or not drawn), the relations decide: a leg whose axis leans towards the viewer while
//! the others lean away is parallel to none of them, so both poses are tried and the one
//! with more hard relations, then the greater summed confidence of all its relations, is
//! kept (the snapped one on a tie). Boxes
//! and bent tubes are not mirrored: which of their edges and end halves are drawn tells
//! the two poses apart already.
//!
//! The free choice may have been made wrong earlier: a table top drawn with hidden
//! lines keeps its snapped mirror, and the legs, whose drawn ends say which way they
//! face, are then parallel to it only against their drawing. Where the reading the
//! drawing refuses would have had more hard relations, the earlier parts those would
//! have been with, and every part related to them, are mirrored together instead, when
//! the strokes of each leave its reading open ([`Document::mirror_free`]): mirrored
//! together they keep every relation among them, and the new part keeps its reading.
//!
//! One drawn part read twice (a drop meant for one of a row of valves that snapped onto
//! its neighbour: mostly the same samples of the drawing) is not related to
//! itself ([`crate::relation::contact::ContactGraph::separate`]).
//!
//! [`Document::release`] is the whole release: inference, then the part is settled in
//! depth where its relations hold ([`Document::settle_depth`]: the drawing leaves its
//! depth free), then the global solve of the parts it changed.

use std::collections::{BTreeMap, BTreeSet};

use glam::{DVec2, DVec3};

use super::reading::{drawn_axis, DrawnEnds, EndDrawn};
use super::{
    Companions, Document, GlobalOutcome, GlobalSettings, PrimitiveId, Relation, RelationId,
};
use crate::primitive::{Feature, FeatureCurve, FeatureGeometry, Primitive, PrimitiveKind};
use crate::relation::contact::{ContactGraph, Outline};
use crate::relation::infer::{infer_bridged, infer_in, Found, Part, Proposal, ALIKE_HOPS};
use crate::relation::{residuals, tilt, InferenceSettings, Member, Mode};
use crate::sketch::StrokeId;
use crate::snap::Assignment;

/// The residual ‖ψ‖ (scale-free) above which a new hard relation that still misses after
/// the part is settled in depth is made a suggestion: about 11° between directions, or
/// a fifth of the sizes involved between positions. Thresholds of inference are a
/// little over half that (8°, a tenth), so such a relation held in the drawing and
/// misses in depth only.
const DEPTH_UNMET: f64 = 0.2;

/// Depths tried on a coarse pass by [`Document::settle_depth`] before it refines the best.
const DEPTH_STEPS: i32 = 40;

/// The residual ‖ψ‖ (scale-free) at which [`Document::settle_depth`]'s robust loss turns
/// from quadratic to logarithmic.
const DEPTH_SCALE: f64 = 0.05;

/// Two parts closer than this fraction of their size in every feature's drawn centre, and in size,
/// coincide ([`Document::duplicate_of`]): far below what a drawing tells apart (a part
/// snaps to its strokes within a per cent or two), far above round-off.
pub(super) const COINCIDENT: f64 = 0.01;

/// Whether `a` and `b` coincide (see [`COINCIDENT`]). Their feature curves are computed
/// only for parts of one kind, size and place, so a release pays little for asking.
fn coincide(a: &Primitive, b: &Primitive) -> bool {
    let size = a.size().max(b.size());
    // In the drawing: a copy drawn over the first at another depth, or mirrored in
    // depth (a release may have turned the first), is the same strokes.
    let near = |p: DVec3, q: DVec3| p.truncate().distance(q.truncate()) <= COINCIDENT * size;
    if a.kind() != b.kind()
        || (a.size() - b.size()).abs() > COINCIDENT * size
        || !near(a.center(), b.center())
    {
        return false;
    }
    let (ours, theirs) = (a.current_shape().features, b.current_shape().features);
    let centre = |f: &FeatureCurve<f64>| match &f.geometry {
        FeatureGeometry::Circle { center, .. } | FeatureGeometry::Rectangle { center, .. } => {
            center.to_dvec3()
        }
    };
    ours.iter()
        .all(|f| theirs.iter().any(|g| near(centre(f), centre(g))))
}

/// The samples of the drawing an assignment takes: (stroke, index among the stroke's
/// samples) pairs, a whole stroke for all of its samples.
fn taken(assignment: &Assignment) -> BTreeSet<(StrokeId, usize)> {
    assignment
        .curves
        .iter()
        .flatten()
        .flat_map(|a| {
            let indices: Vec<usize> = a
                .part
                .clone()
                .unwrap_or_else(|| (0..a.samples.len()).collect());
            indices.into_iter().map(move |i| (a.stroke, i))
        })
        .collect()
}

/// Whether two parts snapped with the assignments `ours` and `theirs` were read off the
/// same strokes: more than half of each one's samples are the other's. Two parts of a
/// drawing share samples only where they meet (a stroke drawn on round a joint), and a
/// stroke drawn on from one part to the next (across a stem, between two arms) is taken
/// in pieces, each part its own; parts that share most of their samples are one part
/// read twice (a drop meant for one of a row of valves that snapped onto its
/// neighbour). Both ways: a part whose strokes a greedy earlier snap took in with many
/// others of its own is still a part of its own. A part without strokes (placed
/// freely) is read off none.
fn same_samples(ours: &Assignment, theirs: &Assignment) -> bool {
    let (a, b) = (taken(ours), taken(theirs));
    let shared = a.intersection(&b).count();
    !a.is_empty() && 2 * shared > a.len() && 2 * shared > b.len()
}

/// How many of `found` are hard.
fn hard_count(found: &[Found]) -> usize {
    found.iter().filter(|f| f.mode == Mode::Hard).count()
}

/// What one reading in depth of a new part ([`depth_variants`]) has for it: how well its
/// drawn ends agree with it ([`DrawnEnds::agreement`]), and the relations inferred with
/// it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ReadingScore {
    /// The drawn ends' agreement.
    agreement: i32,
    /// How many of its relations are hard.
    hard: usize,
    /// The sum of its relations' confidences, hard and suggested.
    confidence: f64,
}

impl ReadingScore {
    fn of(agreement: i32, found: &[Found]) -> Self {
        Self {
            agreement,
            hard: hard_count(found),
            confidence: found.iter().map(|f| f.inferred.confidence).sum(),
        }
    }
}

/// Whether reading `a` is to be kept over reading `b`: the drawing first (a reading
/// its strokes agree with less is never taken for more relations), then more hard
/// relations, then the greater summed confidence of all its relations (`b`, the one
/// held so far, on a tie).
///
/// The sum rather than the count: a confidence reads as how likely a relation is meant,
/// so the sum is how many of them are likely right. A stem whose ends are hidden finds,
/// in the reading its base shares, a coaxial suggestion at the edge of the tilt its
/// drawing leaves open; in the other, a chance collinearity of centres. Counted, they
/// tie; weighed, the coaxial wins.
fn better_reading(a: ReadingScore, b: ReadingScore) -> bool {
    const EQUAL: f64 = 1e-9;
    (a.agreement, a.hard) > (b.agreement, b.hard)
        || ((a.agreement, a.hard) == (b.agreement, b.hard) && a.confidence > b.confidence + EQUAL)
}

/// Whether the relations `a` weigh more than `b` in one same reading of the drawing:
/// more hard ones, or as many and a greater summed confidence ([`better_reading`]).
fn weighs_more(a: &[Found], b: &[Found]) -> bool {
    better_reading(ReadingScore::of(0, a), ReadingScore::of(0, b))
}

impl Document {
    /// Infers the relations between part `id` and the other parts
    /// ([`crate::relation::infer`]), adds them (hard or suggested, with their confidence
    /// and evidence) and returns their ids. The part may be replaced by its mirror image
    /// in depth when that one has more relations and its strokes do not tell the two
    /// apart (see the module docs and [`reading`](super::reading)); earlier parts whose
    /// strokes leave their reading open may be mirrored instead, when the new part's
    /// strokes settle its own. Relations already in the model
    /// (not off) count as known, so nothing redundant is added.
    #[expect(
        clippy::too_many_lines,
        reason = "one release in order: the parts, their contacts, both mirror readings, \
                  the turn of earlier parts the drawing leaves free, the parts joined"
    )]
    pub fn infer_relations(
        &mut self,
        id: PrimitiveId,
        settings: &InferenceSettings,
    ) -> Vec<RelationId> {
        if self.duplicate_of(id).is_some() {
            // A second copy of a part relates to nothing: every relation would tie it to
            // the first or repeat the first's.
            return Vec::new();
        }
        // Copies of earlier parts are left out: the new part relates to the first copy.
        let ids: Vec<PrimitiveId> = self
            .primitives
            .keys()
            .copied()
            .filter(|other| *other == id || self.duplicate_of(*other).is_none())
            .collect();
        let Some(new) = ids.iter().position(|i| *i == id) else {
            return Vec::new();
        };
        let placed: Vec<&super::Placed> = ids.iter().map(|i| &self.primitives[i]).collect();
        let mut features: Vec<Vec<FeatureCurve<f64>>> = placed
            .iter()
            .map(|p| p.primitive.current_shape().features)
            .collect();
        let outlines: Vec<Outline> = placed.iter().map(|p| Outline::of(&p.primitive)).collect();
        let mut sizes: Vec<Measures> = ids
            .iter()
            .zip(&placed)
            .zip(&features)
            .map(|((id, p), f)| self.measures(*id, p, f))
            .collect();
        let existing = self.known_proposals(&ids, &features);
        let snapped = self.primitives[&id].primitive.clone();
        let drawn = self
            .snaps
            .get(&id)
            .map(|record| DrawnEnds::of(&snapped, &record.assignment));
        // A mirror image in depth draws the same outline: one contact graph serves every
        // variant and the pass over the parts the new one joins.
        let mut graph =
            ContactGraph::new(&parts_of(&sizes, &features, &outlines), settings.distance());
        self.separate_read_twice(&mut graph, &ids);
        // The lengths' spreads of the parts equal lengths may be inferred with: the new
        // part and the alike parts within reach.
        let reach = graph.hops_from(new, ALIKE_HOPS);
        let kind = sizes[new].kind;
        for (i, m) in sizes.iter_mut().enumerate() {
            if i == new || (m.kind == kind && reach[i].is_some()) {
                m.length_spread = self.length_spread(ids[i]);
            }
        }
        let mut tried: Vec<(i32, Primitive, Vec<Found>)> = Vec::new();
        for variant in depth_variants(&snapped) {
            let reading = drawn.map_or(0, |d| d.agreement(&variant));
            features[new] = variant.current_shape().features;
            let parts = parts_of(&sizes, &features, &outlines);
            let found = infer_in(&graph, &parts, new, &existing, settings);
            log::debug!(
                "part #{} as {:?} (reading {reading}): {} relation(s)",
                id.0,
                variant.params(),
                found.len(),
            );
            tried.push((reading, variant, found));
        }
        // The drawing first: a reading its strokes contradict is never taken for more
        // relations ([`better_reading`]).
        let Some(pick) = (0..tried.len()).reduce(|b, i| {
            let score = |t: &(i32, Primitive, Vec<Found>)| ReadingScore::of(t.0, &t.2);
            if better_reading(score(&tried[i]), score(&tried[b])) {
                i
            } else {
                b
            }
        }) else {
            return Vec::new();
        };
        let (reading, chosen, mut found) = tried.swap_remove(pick);
        features[new] = chosen.current_shape().features;
        // The reading the drawing refused would have had more relations (more hard
        // ones, or as many and more confident ones: a suggestion the chosen reading
        // lacks): the parts they were with may be the ones read in the wrong mirror,
        // where their own strokes leave it open.
        if let Some((_, _, refused)) = tried
            .iter()
            .find(|t| t.0 < reading && weighs_more(&t.2, &found))
        {
            let seeds: Vec<usize> = refused
                .iter()
                .flat_map(|f| f.proposal.members.iter().copied())
                .filter(|&m| m != new)
                .collect();
            if let Some(turned) = self.free_group(&ids, new, &seeds) {
                let before: Vec<Vec<FeatureCurve<f64>>> =
                    turned.iter().map(|(i, _)| features[*i].clone()).collect();
                for (i, p) in &turned {
                    features[*i] = p.current_shape().features;
                }
                let again = infer_in(
                    &graph,
                    &parts_of(&sizes, &features, &outlines),
                    new,
                    &existing,
                    settings,
                );
                if weighs_more(&again, &found) {
                    found = again;
                    for (i, p) in turned {
                        if let Some(placed) = self.primitives.get_mut(&ids[i]) {
                            placed.primitive = p;
                        }
                    }
                } else {
                    for ((i, _), f) in turned.iter().zip(before) {
                        features[*i] = f;
                    }
                }
            }
        }
        // The parts the new one joins (placed before it) are related now too.
        let parts = parts_of(&sizes, &features, &outlines);
        let mut known = existing;
        known.extend(found.iter().map(|f| (f.proposal.clone(), f.mode)));
        found.extend(infer_bridged(&graph, &parts, new, &known, settings));
        if let Some(placed) = self.primitives.get_mut(&id) {
            placed.primitive = chosen;
        }
        self.add_inferred(&ids, found)
    }

    /// The parts (positions in `ids`, with their mirror images) related, through the
    /// relations that are not off, to the parts `seeds` (positions in `ids`; `new`, the
    /// part being released, left out), each mirrored in depth about their mean depth,
    /// when every one of them is free to be: its strokes leave its mirror reading open
    /// ([`Document::mirror_free`]). `None` when some part is not, or there are none.
    /// Mirrored together, the group keeps every relation among its parts.
    fn free_group(
        &self,
        ids: &[PrimitiveId],
        new: usize,
        seeds: &[usize],
    ) -> Option<Vec<(usize, Primitive)>> {
        let mut group: Vec<usize> = Vec::new();
        let mut frontier: Vec<usize> = seeds.to_vec();
        while let Some(i) = frontier.pop() {
            if i == new || group.contains(&i) {
                continue;
            }
            group.push(i);
            for r in self.relations.iter().filter(|r| r.mode != Mode::Off) {
                if r.members.contains(&ids[i]) {
                    frontier.extend(
                        r.members
                            .iter()
                            .filter_map(|m| ids.iter().position(|x| x == m)),
                    );
                }
            }
        }
        if group.is_empty() || !group.iter().all(|&i| self.mirror_free(ids[i])) {
            return None;
        }
        let depth = group
            .iter()
            .map(|&i| self.primitives[&ids[i]].primitive.center().z)
            .sum::<f64>()
            / group.len() as f64;
        Some(
            group
                .into_iter()
                .map(|i| {
                    let p = &self.primitives[&ids[i]].primitive;
                    let shift = DVec3::new(0.0, 0.0, -2.0 * (p.center().z - depth));
                    (i, p.mirrored_in_depth().transformed(shift, 1.0))
                })
                .collect(),
        )
    }

    /// Whether part `id`'s strokes leave its mirror reading in depth open: a ball, or a
    /// solid of revolution whose drawn ends agree with both readings alike (both drawn
    /// whole, with hidden lines; or not drawn). Boxes and bent tubes are not (which of
    /// their edges and halves are drawn tells the two apart), nor parts placed without
    /// a snap.
    fn mirror_free(&self, id: PrimitiveId) -> bool {
        let (Some(placed), Some(record)) = (self.primitives.get(&id), self.snaps.get(&id)) else {
            return false;
        };
        let p = &placed.primitive;
        match p.kind() {
            PrimitiveKind::Sphere => true,
            PrimitiveKind::Cylinder | PrimitiveKind::Cone | PrimitiveKind::Sgc => {
                let drawn = DrawnEnds::of(p, &record.assignment);
                drawn.agreement(p) == drawn.agreement(&p.mirrored_in_depth())
            }
            PrimitiveKind::Cuboid | PrimitiveKind::Bgc => false,
        }
    }

    /// Keeps apart in `graph` (over the parts `ids`) the parts that are one drawn part
    /// read twice ([`ContactGraph::separate`]): their snaps took mostly the same samples
    /// of the drawing ([`same_samples`]).
    fn separate_read_twice(&self, graph: &mut ContactGraph, ids: &[PrimitiveId]) {
        graph.separate(
            |a, b| match (self.snaps.get(&ids[a]), self.snaps.get(&ids[b])) {
                (Some(x), Some(y)) => same_samples(&x.assignment, &y.assignment),
                _ => false,
            },
        );
    }

    /// What inference reads of part `id` (`placed`, with its feature curves
    /// `features`) besides its curves.
    fn measures(
        &self,
        id: PrimitiveId,
        placed: &super::Placed,
        features: &[FeatureCurve<f64>],
    ) -> Measures {
        let size = placed.primitive.size();
        Measures {
            kind: placed.primitive.kind(),
            size,
            noise: if size > 0.0 {
                placed.fit.rms / size
            } else {
                0.0
            },
            tilt: self.tilt_slack(id, features),
            drawn_axis: self
                .snaps
                .get(&id)
                .and_then(|r| drawn_axis(&placed.primitive, &r.assignment)),
            length_spread: 0.0,
        }
    }

    /// How loosely the strokes of part `id` pin its length: one standard deviation,
    /// relative ([`crate::snap::Spread::length`] of its snap's fit at its current pose);
    /// 0 where not known (no snap, a kind without a straight length, a fit whose
    /// curvature cannot be read). It costs a fit's curvature, so a release asks it only
    /// of the parts it may relate lengths of.
    fn length_spread(&self, id: PrimitiveId) -> f64 {
        let (Some(placed), Some(record)) = (self.primitives.get(&id), self.snaps.get(&id)) else {
            return 0.0;
        };
        if !matches!(
            placed.primitive.kind(),
            PrimitiveKind::Cylinder | PrimitiveKind::Cone | PrimitiveKind::Sgc
        ) {
            return 0.0;
        }
        crate::snap::spread_of(
            &placed.primitive,
            &record.assignment,
            record.rms,
            record.profile,
        )
        .map_or(0.0, |s| s.length)
    }

    /// How far the depth components of part `id`'s end normals (`bottom`, `top`) are
    /// left open by its strokes ([`tilt::slack`]): a solid of revolution's axis is pinned
    /// by whichever of its ends is drawn, a bent tube's ends each by their own; a part
    /// with no end drawn leaves its tilt free. Parts placed without strokes, and parts
    /// without ends, have none. `features` are the part's feature curves at its current
    /// pose (computed once per release for every part).
    fn tilt_slack(&self, id: PrimitiveId, features: &[FeatureCurve<f64>]) -> [f64; 2] {
        let (Some(placed), Some(record)) = (self.primitives.get(&id), self.snaps.get(&id)) else {
            return [0.0; 2];
        };
        let p = &placed.primitive;
        if !matches!(
            p.kind(),
            PrimitiveKind::Cylinder | PrimitiveKind::Cone | PrimitiveKind::Sgc | PrimitiveKind::Bgc
        ) {
            return [0.0; 2];
        }
        let drawn = DrawnEnds::of(p, &record.assignment);
        let radius = |feature: Feature, end: EndDrawn| {
            (end != EndDrawn::Blank)
                .then(|| {
                    features.iter().find_map(|f| match &f.geometry {
                        FeatureGeometry::Circle { radius, .. } if f.feature == feature => {
                            Some(*radius)
                        }
                        _ => None,
                    })
                })
                .flatten()
        };
        let (bottom, top) = (
            radius(Feature::Bottom, drawn.bottom),
            radius(Feature::Top, drawn.top),
        );
        let rms = placed.fit.rms;
        if p.kind() == PrimitiveKind::Bgc {
            [tilt::slack(bottom, rms), tilt::slack(top, rms)]
        } else {
            let largest = match (bottom, top) {
                (Some(a), Some(b)) => Some(a.max(b)),
                (a, b) => a.or(b),
            };
            let axis = tilt::slack(largest, rms);
            [axis; 2]
        }
    }

    /// The earliest other part that part `id` coincides with: the same kind, size and
    /// place, every feature curve where one of the other's is (to 1 % of the size), as
    /// when one drop is made twice. Inference relates such a copy to nothing, and
    /// relates later parts to the first copy only. `None` when there is
    /// none, or no part `id`.
    pub fn duplicate_of(&self, id: PrimitiveId) -> Option<PrimitiveId> {
        let part = &self.primitives.get(&id)?.primitive;
        self.primitives
            .iter()
            .filter(|(other, _)| **other < id)
            .find(|(_, p)| coincide(part, &p.primitive))
            .map(|(other, _)| *other)
    }

    /// The relations of the model that are not off, as proposals over the parts'
    /// positions in `ids` (with `features` their feature curves, in the same order) with
    /// their modes, for inference to count as known. A relation whose member is not in
    /// `ids`, or that names a feature its member lacks, is left out.
    fn known_proposals(
        &self,
        ids: &[PrimitiveId],
        features: &[Vec<FeatureCurve<f64>>],
    ) -> Vec<(Proposal, Mode)> {
        self.relations
            .iter()
            .filter(|r| r.mode != Mode::Off)
            .filter_map(|r| {
                let members: Option<Vec<usize>> = r
                    .members
                    .iter()
                    .map(|m| ids.iter().position(|i| i == m))
                    .collect();
                let members = members?;
                // A feature the member lacks leaves the relation out.
                let chosen = members
                    .iter()
                    .enumerate()
                    .map(|(k, &i)| match r.features.get(k).copied().flatten() {
                        Some(feature) => features[i]
                            .iter()
                            .any(|f| f.feature == feature)
                            .then_some(Some(feature)),
                        None => Some(None),
                    })
                    .collect::<Option<Vec<_>>>()?;
                Some((
                    Proposal {
                        kind: r.kind,
                        members,
                        features: chosen,
                    },
                    r.mode,
                ))
            })
            .collect()
    }

    /// Adds the relations `found` (members as positions in `ids`) in their modes, with
    /// their confidence and evidence, and returns the ids of those the model accepted.
    fn add_inferred(&mut self, ids: &[PrimitiveId], found: Vec<Found>) -> Vec<RelationId> {
        let mut added = Vec::with_capacity(found.len());
        for f in found {
            let relation = Relation {
                kind: f.proposal.kind,
                members: f.proposal.members.iter().map(|&i| ids[i]).collect(),
                features: f.proposal.features,
                mode: f.mode,
                inferred: Some(f.inferred),
            };
            if let Ok(relation) = self.add_relation(relation) {
                added.push(relation);
            }
        }
        added
    }

    /// Accepts every suggested relation (makes it hard) and returns their ids; the
    /// model is not re-solved (see [`Document::solve`]).
    pub fn accept_suggestions(&mut self) -> Vec<RelationId> {
        let ids: Vec<RelationId> = self
            .relations_with_ids()
            .filter(|(_, r)| r.mode == Mode::Suggested)
            .map(|(id, _)| id)
            .collect();
        for id in &ids {
            if let Some(r) = self.relation_mut(*id) {
                r.mode = Mode::Hard;
            }
        }
        ids
    }

    /// Releases part `id` as the tool does when the user lets go of it: infers its
    /// relations ([`Document::infer_relations`]) and solves the parts it changed
    /// ([`Document::solve`] of `[id]`). Returns the relations added and the solve's
    /// outcome. The app, `geosnap run` and the benchmarks all release through it.
    ///
    /// # Examples
    ///
    /// ```
    /// use glam::DVec3;
    /// use geosnap_core::model::{Companions, Document, Fit, GlobalSettings, Placed};
    /// use geosnap_core::primitive::{Cylinder, Primitive};
    /// use geosnap_core::relation::{InferenceSettings, Mode, RelationKind};
    ///
    /// // A can stacked on another, end on end, drawn a little askew.
    /// let can = |y: f64, axis: DVec3| Placed {
    ///     primitive: Primitive::Cylinder(Cylinder {
    ///         center: DVec3::new(0.0, y, 0.0),
    ///         axis: axis.normalize(),
    ///         length: 10.0,
    ///         radius: 3.0,
    ///     }),
    ///     fit: Fit::default(),
    /// };
    /// let mut doc = Document::new();
    /// doc.add(can(0.0, DVec3::Y));
    /// let new = doc.add(can(10.0, DVec3::new(0.02, 1.0, 0.0)));
    /// let (added, outcome) = doc.release(
    ///     new,
    ///     &InferenceSettings::default(),
    ///     &GlobalSettings::default(),
    ///     Companions::default(),
    /// );
    /// assert!(added.iter().any(|&r| doc
    ///     .relation(r)
    ///     .is_some_and(|r| r.kind == RelationKind::Coaxial && r.mode == Mode::Hard)));
    /// assert!(outcome.conflicts.is_empty());
    /// ```
    pub fn release(
        &mut self,
        id: PrimitiveId,
        inference: &InferenceSettings,
        global: &GlobalSettings,
        companions: Companions<'_>,
    ) -> (Vec<RelationId>, GlobalOutcome) {
        let added = self.infer_relations(id, inference);
        self.settle_depth(id);
        self.suggest_what_depth_cannot_meet(id, &added);
        let outcome = self.solve(Some(&[id]), global, companions);
        (added, outcome)
    }

    /// Makes suggestions of those hard relations among `added` (part `id`'s, just
    /// inferred) that still miss by more than [`DEPTH_UNMET`] once the part is settled
    /// in depth, and returns them. Inference reads relations off the drawing, where the
    /// part's depth is free; the settled depth is where they hold together best. One
    /// that misses there contradicts the others in depth (a cone's bottom read as on a
    /// cup's rim by coplanarity and at its base by coaxiality): enforced, it would wreck a
    /// fit and be switched off after a solve. As a suggestion it costs nothing, and the
    /// user may still accept it.
    fn suggest_what_depth_cannot_meet(
        &mut self,
        id: PrimitiveId,
        added: &[RelationId],
    ) -> Vec<RelationId> {
        let mut demoted = Vec::new();
        for &r in added {
            let Some(relation) = self.relation(r) else {
                continue;
            };
            if relation.mode != Mode::Hard {
                continue;
            }
            let shapes: Option<Vec<Vec<FeatureCurve<f64>>>> = relation
                .members
                .iter()
                .map(|m| Some(self.primitives.get(m)?.primitive.current_shape().features))
                .collect();
            let Some(shapes) = shapes else { continue };
            let members: Vec<Member<'_, f64>> = shapes
                .iter()
                .zip(&relation.features)
                .map(|(features, feature)| Member {
                    features,
                    feature: *feature,
                })
                .collect();
            let Ok(psi) = residuals(relation.kind, &members) else {
                continue;
            };
            let miss = psi.iter().map(|v| v * v).sum::<f64>().sqrt();
            if miss > DEPTH_UNMET {
                log::debug!(
                    "part #{}: {} misses by {miss:.3} at its settled depth; suggested",
                    id.0,
                    relation.kind.name()
                );
                if let Some(relation) = self.relation_mut(r) {
                    relation.mode = Mode::Suggested;
                }
                demoted.push(r);
            }
        }
        demoted
    }

    /// Moves part `id` along the view direction to where its relations that are not off
    /// hold best (least Σ ln(1 + ‖ψ‖²/σ²) over its relations, σ = 0.05, with the other
    /// parts where they are). Returns the distance moved.
    ///
    /// A drawing does not show depth, so a snap leaves a part at an arbitrary depth and
    /// its fit is the same at every depth. Its relations are not: a pipe standing on a
    /// box's face must be as deep as that face. Started far off in depth, the global
    /// solve meets the relations by whatever moves are cheapest at first, such as
    /// lengthening the pipe, and can end in a worse fit than moving it back in depth
    /// would give. Settling the depth first costs nothing in fit and starts the solve
    /// next to its answer.
    pub fn settle_depth(&mut self, id: PrimitiveId) -> f64 {
        let Some(part) = self.primitives.get(&id).map(|p| p.primitive.clone()) else {
            return 0.0;
        };
        let relations: Vec<&Relation> = self
            .relations
            .iter()
            .filter(|r| r.mode.is_enforced() && r.members.contains(&id))
            .collect();
        if relations.is_empty() {
            return 0.0;
        }
        let others: BTreeMap<PrimitiveId, Vec<FeatureCurve<f64>>> = relations
            .iter()
            .flat_map(|r| r.members.iter().copied())
            .filter(|m| *m != id)
            .filter_map(|m| {
                Some((
                    m,
                    self.primitives.get(&m)?.primitive.current_shape().features,
                ))
            })
            .collect();
        let misfit = |dz: f64| depth_misfit(&part, id, &relations, &others, dz);
        // Depths within a few sizes of the parts involved.
        let reach = others
            .keys()
            .filter_map(|m| self.primitives.get(m))
            .map(|p| p.primitive.size() + (p.primitive.center().z - part.center().z).abs())
            .fold(part.size(), f64::max)
            * 2.0;
        let dz = least_misfit_depth(reach, misfit);
        let (before, after) = (misfit(0.0), misfit(dz));
        if !(after.is_finite() && after < 0.5 * before) {
            return 0.0;
        }
        if let Some(placed) = self.primitives.get_mut(&id) {
            placed.primitive = part.transformed(DVec3::new(0.0, 0.0, dz), 1.0);
        }
        dz
    }
}

/// What inference reads of a part besides its curves: its kind, size, noise, tilt
/// slack and the direction its side lines are drawn in (see [`Part`]).
struct Measures {
    kind: PrimitiveKind,
    size: f64,
    noise: f64,
    tilt: [f64; 2],
    drawn_axis: Option<DVec2>,
    length_spread: f64,
}

/// The parts as inference sees them: each one's measures, feature curves and outline, in
/// one order.
fn parts_of<'a>(
    sizes: &[Measures],
    features: &'a [Vec<FeatureCurve<f64>>],
    outlines: &'a [Outline],
) -> Vec<Part<'a>> {
    sizes
        .iter()
        .zip(features)
        .zip(outlines)
        .map(|((m, f), outline)| Part {
            kind: m.kind,
            features: f,
            outline,
            size: m.size,
            noise: m.noise,
            tilt: m.tilt,
            drawn_axis: m.drawn_axis,
            length_spread: m.length_spread,
        })
        .collect()
}

/// The poses of a snapped part that the drawing cannot tell apart: the part itself and,
/// for a solid of revolution, its mirror image in depth (see the module docs).
fn depth_variants(snapped: &Primitive) -> Vec<Primitive> {
    let mut variants = vec![snapped.clone()];
    if matches!(
        snapped.kind(),
        PrimitiveKind::Cylinder | PrimitiveKind::Cone | PrimitiveKind::Sgc
    ) {
        variants.push(snapped.mirrored_in_depth());
    }
    variants
}

/// How badly `relations` hold with part `id` (whose pose is `part`) moved by `dz` along
/// the view direction and the other members' feature curves in `others`: Σ ln(1 +
/// ‖ψ‖²/σ²) over the relations whose residuals can be evaluated, σ = [`DEPTH_SCALE`].
fn depth_misfit(
    part: &Primitive,
    id: PrimitiveId,
    relations: &[&Relation],
    others: &BTreeMap<PrimitiveId, Vec<FeatureCurve<f64>>>,
    dz: f64,
) -> f64 {
    let moved = part
        .transformed(DVec3::new(0.0, 0.0, dz), 1.0)
        .current_shape()
        .features;
    relations
        .iter()
        .filter_map(|r| {
            let members: Option<Vec<Member<'_, f64>>> = r
                .members
                .iter()
                .zip(&r.features)
                .map(|(m, f)| {
                    let features = if *m == id { &moved } else { others.get(m)? };
                    Some(Member {
                        features,
                        feature: *f,
                    })
                })
                .collect();
            residuals(r.kind, &members?).ok()
        })
        // Relation by relation, with a robust loss: the depth where most of them hold
        // wins over one that half-satisfies them all, so a relation inferred by mistake
        // does not drag the part off the others.
        .map(|psi| {
            let sq: f64 = psi.iter().map(|v| v * v).sum();
            (1.0 + sq / (DEPTH_SCALE * DEPTH_SCALE)).ln()
        })
        .sum()
}

/// The depth offset in [−`reach`, `reach`] where `misfit` is least: the best of
/// [`DEPTH_STEPS`] + 1 evenly spaced depths, refined by golden sections within a step
/// of it.
fn least_misfit_depth(reach: f64, misfit: impl Fn(f64) -> f64) -> f64 {
    let step = 2.0 * reach / f64::from(DEPTH_STEPS);
    let best = (0..=DEPTH_STEPS)
        .map(|k| -reach + step * f64::from(k))
        .map(|dz| (dz, misfit(dz)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(0.0, |(dz, _)| dz);
    let (mut lo, mut hi) = (best - step, best + step);
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..60 {
        let (x1, x2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
        if misfit(x1) < misfit(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    f64::midpoint(lo, hi)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::reading::drawn;
    use crate::model::{Document, Fit, Placed, PrimitiveId, SnapRecord};
    use crate::primitive::{Cuboid, Cylinder, Feature, Primitive};
    use crate::relation::{InferenceSettings, Member, Mode, RelationKind};
    use crate::snap::Profile;

    fn leg(x: f64, axis: DVec3) -> Placed {
        Placed {
            primitive: Primitive::Cylinder(Cylinder {
                center: DVec3::new(x, 0.0, 0.0),
                axis: axis.normalize(),
                length: 10.0,
                radius: 1.0,
            }),
            fit: Fit::default(),
        }
    }

    /// Two legs under a slab (the slab first), the second snapped leaning `second`.
    fn legs_under_a_slab(second: DVec3) -> (Document, PrimitiveId, PrimitiveId) {
        let mut doc = Document::new();
        doc.add(Placed {
            primitive: Primitive::Cuboid(Cuboid {
                center: DVec3::new(3.0, 5.0, 0.0),
                rotation: glam::DQuat::IDENTITY,
                size: DVec3::new(14.0, 1.0, 6.0),
            }),
            fit: Fit::default(),
        });
        let a = doc.add(leg(0.0, DVec3::new(0.0, 0.9, 0.44)));
        let b = doc.add(leg(6.0, second));
        (doc, a, b)
    }

    fn axis_z(doc: &Document, id: PrimitiveId) -> f64 {
        let Primitive::Cylinder(c) = &doc.get(id).expect("placed").primitive else {
            unreachable!("a cylinder")
        };
        c.axis.z
    }

    #[test]
    fn a_reading_is_chosen_by_the_drawing_then_hard_relations_then_summed_confidence() {
        use super::{better_reading, ReadingScore};
        let score = |agreement, hard, confidence| ReadingScore {
            agreement,
            hard,
            confidence,
        };
        // The drawing outweighs any number of relations.
        assert!(!better_reading(score(0, 5, 4.0), score(1, 0, 0.0)));
        // More hard relations outweigh more suggestions.
        assert!(better_reading(score(1, 2, 1.2), score(1, 1, 1.9)));
        // Equal hard counts: the weight of all of them, not their number, decides.
        assert!(better_reading(score(1, 1, 1.8), score(1, 1, 1.75)));
        assert!(!better_reading(score(1, 1, 1.35), score(1, 1, 1.75)));
        // A tie keeps the one held so far.
        assert!(!better_reading(score(1, 1, 1.8), score(1, 1, 1.8)));
    }

    #[test]
    fn a_part_snapped_in_the_wrong_mirror_pose_is_turned_by_its_relations() {
        // The same leg seen in the same drawing, but snapped leaning the other way in
        // depth: parallel to nothing as it is. Its strokes (none here) cannot tell.
        let (mut doc, a, b) = legs_under_a_slab(DVec3::new(0.0, 0.9, -0.44));
        let added = doc.infer_relations(b, &InferenceSettings::default());
        let parallel = added.iter().any(|&r| {
            doc.relation(r)
                .is_some_and(|r| r.kind == RelationKind::Parallel && r.members.contains(&a))
        });
        assert!(parallel, "{:#?}", doc.relations());
        assert!((axis_z(&doc, b) - 0.44 / DVec3::new(0.0, 0.9, 0.44).length()).abs() < 1e-12);
    }

    #[test]
    fn a_reading_the_strokes_show_is_not_flipped_for_a_relation() {
        // Snapped upside down with its top towards the viewer, and drawn so: the top
        // whole, the bottom a half. Its mirror would be parallel to the other leg.
        let (mut doc, a, b) = legs_under_a_slab(DVec3::new(0.0, -0.9, 0.44));
        let snapped = doc.get(b).expect("placed").primitive.clone();
        doc.snaps.insert(
            b,
            SnapRecord {
                assignment: drawn(&snapped, false),
                rms: 0.0,
                profile: Profile::Smooth,
            },
        );
        doc.infer_relations(b, &InferenceSettings::default());
        assert!(axis_z(&doc, b) > 0.0, "turned against its strokes");
        assert!(doc
            .relations()
            .iter()
            .all(|r| !(r.kind == RelationKind::Parallel
                && r.members.contains(&a)
                && r.members.contains(&b))));
    }

    #[test]
    fn a_copy_of_a_part_relates_to_nothing_and_later_parts_relate_to_the_first() {
        let axis = DVec3::new(0.0, 0.9, 0.44);
        let mut doc = Document::new();
        let first = doc.add(leg(0.0, axis));
        let copy = doc.add(leg(0.0, axis));
        assert_eq!(doc.duplicate_of(copy), Some(first));
        assert_eq!(doc.duplicate_of(first), None, "the first is no copy");
        assert!(doc
            .infer_relations(copy, &InferenceSettings::default())
            .is_empty());
        // A leg beside them is parallel to the first only.
        let beside = doc.add(leg(2.0, axis));
        assert_eq!(doc.duplicate_of(beside), None);
        let added = doc.infer_relations(beside, &InferenceSettings::default());
        assert!(!added.is_empty());
        for r in added {
            let members = &doc.relation(r).expect("added").members;
            assert!(!members.contains(&copy), "{members:?}");
        }
        // Moved by a few per cent of its size, a part is no copy.
        let near = doc.add(leg(0.3, axis));
        assert_eq!(doc.duplicate_of(near), None);
        // The same strokes read at another depth, or mirrored in depth, are a copy.
        let deeper = doc.add(leg(0.0, axis));
        let moved = doc.primitives[&deeper]
            .primitive
            .transformed(DVec3::Z * 40.0, 1.0);
        doc.primitives.get_mut(&deeper).expect("added").primitive = moved;
        assert_eq!(doc.duplicate_of(deeper), Some(first));
        let mirrored = doc.add(leg(0.0, axis));
        let flipped = doc.primitives[&mirrored].primitive.mirrored_in_depth();
        doc.primitives.get_mut(&mirrored).expect("added").primitive = flipped;
        assert_eq!(doc.duplicate_of(mirrored), Some(first));
    }

    /// Two legs side by side, each with strokes of its own, the second (axis `second`)
    /// released: the first drawn with hidden lines (both ends whole: either mirror
    /// reading) when `first_hidden`, else with its top whole; the second with its top
    /// whole and its bottom a half. The first's and the second's depth components after
    /// the release, and the mode of a parallel between them, if any.
    fn legs_drawn(first_hidden: bool, second: DVec3) -> (f64, f64, Option<Mode>) {
        let mut doc = Document::new();
        let a = doc.add(leg(0.0, DVec3::new(0.0, 0.9, 0.44)));
        let b = doc.add(leg(2.0, second));
        for (k, (id, hidden)) in [(a, first_hidden), (b, false)].into_iter().enumerate() {
            let p = doc.get(id).expect("placed").primitive.clone();
            // Strokes of its own.
            let mut assignment = drawn(&p, hidden);
            for s in assignment.curves.iter_mut().flatten() {
                s.stroke = crate::sketch::StrokeId(k as u32);
            }
            doc.snaps.insert(
                id,
                SnapRecord {
                    assignment,
                    rms: 0.0,
                    profile: Profile::Smooth,
                },
            );
        }
        doc.infer_relations(b, &InferenceSettings::default());
        let parallel = doc
            .relations()
            .iter()
            .find(|r| {
                r.kind == RelationKind::Parallel && r.members.contains(&a) && r.members.contains(&b)
            })
            .map(|r| r.mode);
        (axis_z(&doc, a), axis_z(&doc, b), parallel)
    }

    #[test]
    fn earlier_parts_whose_strokes_leave_the_mirror_open_are_turned_for_the_drawing() {
        // The second's top faces the viewer, as snapped, and it is parallel to the first
        // only once the first is mirrored.
        let second = DVec3::new(0.0, -0.9, 0.44);
        let (a, b, parallel) = legs_drawn(true, second);
        assert!(
            a < 0.0 && b > 0.0 && parallel == Some(Mode::Hard),
            "{a} {b} {parallel:?}"
        );
        // The first drawn without hidden lines, its top whole: its reading stands too,
        // and the two are not parallel.
        let (a, b, parallel) = legs_drawn(false, second);
        assert!(
            a > 0.0 && b > 0.0 && parallel.is_none(),
            "{a} {b} {parallel:?}"
        );
    }

    #[test]
    fn earlier_parts_open_to_the_mirror_are_turned_for_a_suggestion_too() {
        // As above, the second turned 5° on the paper: parallel at the edge of its
        // threshold, a suggestion. The first is still turned for it, where its strokes
        // leave it open, rather than the suggestion lost with the refused reading.
        let second = DVec3::new(0.09, -0.9, 0.44);
        let (a, b, parallel) = legs_drawn(true, second);
        assert!(
            a < 0.0 && b > 0.0 && parallel == Some(Mode::Suggested),
            "{a} {b} {parallel:?}"
        );
        let (a, b, parallel) = legs_drawn(false, second);
        assert!(
            a > 0.0 && b > 0.0 && parallel.is_none(),
            "{a} {b} {parallel:?}"
        );
    }

    /// An assignment taking the `strokes` (id, and the range of its ten samples taken;
    /// the whole stroke for 0..10).
    fn taking(strokes: &[(u32, std::ops::Range<usize>)]) -> crate::snap::Assignment {
        crate::snap::Assignment {
            curves: vec![strokes
                .iter()
                .map(|(id, range)| crate::snap::AssignedStroke {
                    stroke: crate::sketch::StrokeId(*id),
                    samples: range
                        .clone()
                        .map(|i| glam::DVec2::new(i as f64, 0.0))
                        .collect(),
                    mean_distance: 0.0,
                    part: (*range != (0..10)).then(|| range.clone().collect()),
                })
                .collect()],
        }
    }

    #[test]
    fn a_part_read_off_another_parts_strokes_is_not_related_to_it() {
        use super::same_samples;

        let whole = |ids: &[u32]| taking(&ids.iter().map(|&i| (i, 0..10)).collect::<Vec<_>>());
        // Three of four strokes each way: one part read twice.
        assert!(same_samples(&whole(&[1, 2, 3, 4]), &whole(&[2, 3, 4, 5])));
        // One stroke shared at a joint: two parts.
        assert!(!same_samples(&whole(&[1, 2, 3, 4]), &whole(&[4, 5, 6, 7])));
        // Strokes drawn on from one arm to the other, each arm taking its own pieces.
        let left = taking(&[(1, 0..5), (2, 0..5), (3, 0..10)]);
        let right = taking(&[(1, 5..10), (2, 5..10), (4, 0..10)]);
        assert!(!same_samples(&left, &right));
        // A part whose strokes an earlier greedy snap took in among many of its own.
        assert!(!same_samples(
            &whole(&[20, 21, 22]),
            &whole(&[10, 11, 12, 13, 20, 21])
        ));
        // Placed freely: read off none.
        assert!(!same_samples(&whole(&[]), &whole(&[1])));

        // Two legs side by side, the second snapped onto the first one's strokes (a
        // little aside): parallel and coaxial would hold, but they are one drawn leg.
        let axis = DVec3::new(0.0, 0.9, 0.44);
        let mut doc = Document::new();
        let on = |doc: &mut Document, x: f64, strokes: &[u32]| {
            let id = doc.add(leg(x, axis));
            doc.snaps.insert(
                id,
                SnapRecord {
                    assignment: whole(strokes),
                    rms: 0.0,
                    profile: Profile::Smooth,
                },
            );
            id
        };
        on(&mut doc, 0.0, &[1, 2, 3, 4]);
        let again = on(&mut doc, 0.3, &[1, 2, 3, 5]);
        assert!(doc
            .infer_relations(again, &InferenceSettings::default())
            .is_empty());
        // Beside them on strokes of its own: a part of its own.
        let beside = on(&mut doc, 2.0, &[6, 7, 8, 9]);
        assert!(!doc
            .infer_relations(beside, &InferenceSettings::default())
            .is_empty());
    }

    #[test]
    fn a_relation_that_misses_at_the_settled_depth_is_only_suggested() {
        use crate::model::Relation;

        // Two legs side by side: parallel holds; coaxial misses by their spacing, which
        // no depth can make up.
        let mut doc = Document::new();
        let a = doc.add(leg(0.0, DVec3::new(0.0, 0.9, 0.44)));
        let b = doc.add(leg(6.0, DVec3::new(0.0, 0.9, 0.44)));
        let relate = |doc: &mut Document, kind| {
            let relation = Relation::new(
                kind,
                vec![b, a],
                vec![Some(Feature::Top), Some(Feature::Top)],
                Mode::Hard,
            );
            doc.add_relation(relation).expect("valid")
        };
        let parallel = relate(&mut doc, RelationKind::Parallel);
        let coaxial = relate(&mut doc, RelationKind::Coaxial);
        let demoted = doc.suggest_what_depth_cannot_meet(b, &[parallel, coaxial]);
        assert_eq!(demoted, vec![coaxial]);
        assert_eq!(doc.relation(parallel).expect("kept").mode, Mode::Hard);
        assert_eq!(doc.relation(coaxial).expect("kept").mode, Mode::Suggested);
    }

    #[test]
    fn a_released_part_is_settled_in_depth_where_its_relations_hold() {
        use crate::model::Relation;
        use crate::relation::residuals;

        // A rod on another's top end, drawn in place but snapped at the wrong depth.
        let mut doc = Document::new();
        let axis = DVec3::new(0.0, 0.9, 0.44);
        let a = doc.add(leg(0.0, axis));
        let on_top = axis.normalize() * 10.0;
        let b = doc.add(leg(0.0, axis));
        let mut moved = doc.get(b).expect("placed").clone();
        moved.primitive = moved
            .primitive
            .transformed(DVec3::new(on_top.x, on_top.y, on_top.z - 7.0), 1.0);
        doc.insert(b, moved);
        doc.add_relation(Relation {
            kind: RelationKind::Coplanar,
            members: vec![a, b],
            features: vec![Some(Feature::Top), Some(Feature::Bottom)],
            mode: Mode::Hard,
            inferred: None,
        })
        .expect("a coplanar pair of ends");
        let psi = |doc: &Document| {
            let f = |id| {
                doc.get(id)
                    .expect("placed")
                    .primitive
                    .current_shape()
                    .features
            };
            let (fa, fb) = (f(a), f(b));
            let members = [
                Member {
                    features: &fa,
                    feature: Some(Feature::Top),
                },
                Member {
                    features: &fb,
                    feature: Some(Feature::Bottom),
                },
            ];
            residuals(RelationKind::Coplanar, &members)
                .expect("coplanar")
                .iter()
                .map(|v| v.abs())
                .fold(0.0, f64::max)
        };
        assert!(psi(&doc) > 0.1, "apart at first: {}", psi(&doc));
        let before = doc.get(b).expect("placed").primitive.center();
        let dz = doc.settle_depth(b);
        let after = doc.get(b).expect("placed").primitive.center();
        assert!((dz - 7.0).abs() < 1e-6, "moved by {dz}");
        assert!(psi(&doc) < 1e-9, "the ends meet: {}", psi(&doc));
        assert_eq!(
            before.truncate(),
            after.truncate(),
            "the drawing is unchanged"
        );
    }

    #[test]
    fn a_part_alone_gets_no_relations_and_stays_as_snapped() {
        let mut doc = Document::new();
        let a = doc.add(leg(0.0, DVec3::new(0.0, 0.9, 0.44)));
        let before = doc.clone();
        assert!(doc
            .infer_relations(a, &InferenceSettings::default())
            .is_empty());
        assert_eq!(doc, before);
    }
}
