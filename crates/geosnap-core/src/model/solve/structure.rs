//! What the hard relations say before any number is solved: which of them repeat what the
//! relations before them say already, and which contradict them outright.
//!
//! Six of the kinds say that two things are *the same*: parallel (a direction), coaxial
//! (an axis line, and so its direction), coplanar (a plane, and its normal), concentric
//! (a centre), same radius (a radius) and equal length (a length). Sameness is
//! transitive, so a relation between two things already the same through the relations
//! before it is *implied*: it is kept, and it holds when they hold, but it is not handed
//! to the solver again. In a model where every pair of 200 parts is made parallel, 199
//! relations are solved and 19,701 are implied; without this, every evaluation of the
//! solve pays for all 19,900 and the solver meets a constraint Jacobian of rank 400 in
//! 60,000 rows.
//!
//! Orthogonal is not a sameness, but two facts about directions are exact:
//! - a direction is never orthogonal to itself, so an orthogonal between two directions
//!   already parallel contradicts the relations before it, as a parallel between two
//!   directions already orthogonal does;
//! - no four directions of space are pairwise orthogonal, so an orthogonal that would
//!   close such a four contradicts the relations before it (all pairs of many parts made
//!   orthogonal), and an orthogonal between two directions already orthogonal is implied.
//!
//! The relations are taken in the solve's precedence, oldest first: the newer of two
//! relations that contradict each other is the one named, as the rank-based check of
//! [`super::conflicts`] does after a solve. What this module does not decide (a coaxial
//! and a concentric that pull one centre two ways, an orthogonal implied through a
//! chain of others) the solve and that check still meet. Two things of one part are the
//! same thing where the part's shape makes them so: the two ends of a cylinder, cone or
//! generalized cylinder share one axis (direction and line), a cylinder's two ends one
//! radius, and opposite faces of a box one normal direction.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use super::conflicts::describe;
use super::{Conflict, Document, PrimitiveId, Related, Relation, RelationKey};
use crate::primitive::{Axis, Feature, Primitive, Shape};
use crate::relation::{residuals, Member, Mode, RelationKind};

/// What a relation's members share when it holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Quantity {
    Direction,
    Line,
    Point,
    Plane,
    Radius,
    Length,
}

/// Which of a part's things a member names, after the part's shape has made equal
/// things one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Slot {
    /// The axis of a solid of revolution or a straight generalized cylinder.
    Axis,
    /// A cylinder's one radius.
    Radius,
    /// The normal direction of a box's two faces across `Axis`.
    Faces(Axis),
    /// The whole part (its length).
    Whole,
    /// One feature, not shared.
    Own(Option<Feature>),
}

/// One thing of one part that relations may make the same as another.
type Key = (PrimitiveId, Quantity, Slot);

/// The slot a member's `feature` of `primitive` names for `quantity`.
fn slot(primitive: &Primitive, feature: Option<Feature>, quantity: Quantity) -> Slot {
    let end = matches!(feature, Some(Feature::Top | Feature::Bottom));
    let straight = matches!(
        primitive,
        Primitive::Cylinder(_) | Primitive::Cone(_) | Primitive::Sgc(_)
    );
    match (quantity, feature) {
        (Quantity::Length, _) => Slot::Whole,
        (Quantity::Direction | Quantity::Line, _) if end && straight => Slot::Axis,
        (Quantity::Radius, _) if end && matches!(primitive, Primitive::Cylinder(_)) => Slot::Radius,
        (Quantity::Direction, Some(Feature::Face { axis, .. })) => Slot::Faces(axis),
        _ => Slot::Own(feature),
    }
}

/// Disjoint sets over keys, with the orthogonal pairs between direction sets.
#[derive(Default)]
struct Classes {
    index: HashMap<Key, usize>,
    parent: Vec<usize>,
    /// For each direction set's root, the roots of the sets orthogonal to it.
    orthogonal: BTreeMap<usize, BTreeSet<usize>>,
    /// For each set's root, the roots of the sets it can never be one with: a part's
    /// two ends (their centres and planes are a length apart), a box's opposite faces.
    apart: BTreeMap<usize, BTreeSet<usize>>,
}

impl Classes {
    /// The root of `key`'s set, made a set of its own when new.
    fn find(&mut self, key: Key) -> usize {
        let next = self.parent.len();
        let mut i = *self.index.entry(key).or_insert(next);
        if i == next {
            self.parent.push(next);
        }
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    /// The sets orthogonal to root `a`.
    fn normal_to(&self, a: usize) -> impl Iterator<Item = usize> + '_ {
        self.orthogonal.get(&a).into_iter().flatten().copied()
    }

    fn are_orthogonal(&self, a: usize, b: usize) -> bool {
        self.orthogonal.get(&a).is_some_and(|s| s.contains(&b))
    }

    /// Joins roots `a` and `b` (distinct), carrying their orthogonal pairs over.
    fn join(&mut self, a: usize, b: usize) {
        self.parent[b] = a;
        for pairs in [&mut self.orthogonal, &mut self.apart] {
            let moved = pairs.remove(&b).unwrap_or_default();
            for other in moved {
                if let Some(set) = pairs.get_mut(&other) {
                    set.remove(&b);
                    set.insert(a);
                }
                pairs.entry(a).or_default().insert(other);
            }
        }
    }

    fn are_apart(&self, a: usize, b: usize) -> bool {
        self.apart.get(&a).is_some_and(|s| s.contains(&b))
    }

    /// Records what part `id`'s shape makes distinct or orthogonal (see [`Classes::apart`]):
    /// the ends of a solid, and a box's opposite faces and its three face directions.
    fn seed(&mut self, id: PrimitiveId, primitive: &Primitive) {
        let keep_apart = |classes: &mut Self, quantity, f: Feature, g: Feature| {
            let a = classes.find((id, quantity, Slot::Own(Some(f))));
            let b = classes.find((id, quantity, Slot::Own(Some(g))));
            classes.apart.entry(a).or_default().insert(b);
            classes.apart.entry(b).or_default().insert(a);
        };
        match primitive {
            Primitive::Sphere(_) => {}
            Primitive::Cuboid(_) => {
                for axis in [Axis::X, Axis::Y, Axis::Z] {
                    let (f, g) = (Feature::face(axis, true), Feature::face(axis, false));
                    keep_apart(self, Quantity::Point, f, g);
                    keep_apart(self, Quantity::Plane, f, g);
                }
                let faces = [Axis::X, Axis::Y, Axis::Z]
                    .map(|axis| self.find((id, Quantity::Direction, Slot::Faces(axis))));
                for (i, a) in faces.iter().enumerate() {
                    for b in &faces[i + 1..] {
                        self.make_orthogonal(*a, *b);
                    }
                }
            }
            _ => {
                keep_apart(self, Quantity::Point, Feature::Top, Feature::Bottom);
                keep_apart(self, Quantity::Plane, Feature::Top, Feature::Bottom);
            }
        }
    }

    fn make_orthogonal(&mut self, a: usize, b: usize) {
        self.orthogonal.entry(a).or_default().insert(b);
        self.orthogonal.entry(b).or_default().insert(a);
    }

    /// Whether an orthogonal between roots `a` and `b` would close four pairwise
    /// orthogonal directions: two sets orthogonal to both and to each other.
    fn closes_four(&self, a: usize, b: usize) -> bool {
        let common: Vec<usize> = self
            .normal_to(a)
            .filter(|c| self.are_orthogonal(*c, b))
            .collect();
        common
            .iter()
            .enumerate()
            .any(|(i, c)| common[i + 1..].iter().any(|d| self.are_orthogonal(*c, *d)))
    }
}

/// What the structure of the hard relations says (see the module docs).
#[derive(Debug, Default)]
pub(super) struct Structure {
    /// Hard relations implied by those before them: kept, not solved.
    pub(super) implied: HashSet<RelationKey>,
    /// Hard relations that contradict those before them, with the reason in words.
    pub(super) contradicted: Vec<(RelationKey, String)>,
}

/// What one relation does to the classes.
enum Verdict {
    Joins,
    Implied,
    Contradicts(&'static str),
    /// A kind this module does not reason about.
    Opaque,
}

/// A two-member relation's members: each part's id, primitive and feature.
struct Pair<'d> {
    members: [(PrimitiveId, &'d Primitive, Option<Feature>); 2],
}

impl<'d> Pair<'d> {
    /// The members of `related` when it has two and both are in `document`.
    fn of(document: &'d Document, related: &Related<'_>) -> Option<Self> {
        let relation = related.relation;
        let member = |k: usize| {
            let id = *relation.members.get(k)?;
            let placed = document.get(id)?;
            Some((
                id,
                &placed.primitive,
                relation.features.get(k).copied().flatten(),
            ))
        };
        (relation.members.len() == 2).then_some(())?;
        Some(Self {
            members: [member(0)?, member(1)?],
        })
    }

    /// The two members' keys for `quantity`.
    fn keys(&self, quantity: Quantity) -> (Key, Key) {
        let key = |(id, p, f): (PrimitiveId, &Primitive, Option<Feature>)| {
            (id, quantity, slot(p, f, quantity))
        };
        (key(self.members[0]), key(self.members[1]))
    }
}

/// The quantity a sameness kind makes one beside the direction, and whether it makes
/// the directions one too; `None` for the kinds that are no sameness.
fn sameness(kind: RelationKind) -> Option<(Option<Quantity>, bool)> {
    match kind {
        RelationKind::Parallel => Some((None, true)),
        RelationKind::Coaxial => Some((Some(Quantity::Line), true)),
        RelationKind::Coplanar => Some((Some(Quantity::Plane), true)),
        RelationKind::Concentric => Some((Some(Quantity::Point), false)),
        RelationKind::SameRadius => Some((Some(Quantity::Radius), false)),
        RelationKind::EqualLength => Some((Some(Quantity::Length), false)),
        RelationKind::Orthogonal | RelationKind::CollinearCenters | RelationKind::OnSphere => None,
    }
}

/// The structure of the hard `relations` of `document`, in their order.
pub(super) fn analyse(document: &Document, relations: &[Related<'_>]) -> Structure {
    let mut classes = Classes::default();
    let mut structure = Structure::default();
    let mut kept: Vec<(&Related<'_>, Pair<'_>)> = Vec::new();
    let mut seeded = HashSet::new();
    for related in relations {
        if related.relation.mode != Mode::Hard {
            continue;
        }
        let Some(pair) = Pair::of(document, related) else {
            continue;
        };
        for (id, primitive, _) in pair.members {
            if seeded.insert(id) {
                classes.seed(id, primitive);
            }
        }
        match judge(&mut classes, related.relation.kind, &pair) {
            Verdict::Contradicts(why) => structure.contradicted.push((related.id, why.to_owned())),
            Verdict::Joins | Verdict::Implied => kept.push((related, pair)),
            Verdict::Opaque => {}
        }
    }
    if structure.contradicted.is_empty() {
        structure.implied = spanning(document, &mut classes, &kept);
    }
    structure
}

/// The verdict on one relation of `kind` between `pair`, applied to `classes` when it
/// joins.
fn judge(classes: &mut Classes, kind: RelationKind, pair: &Pair<'_>) -> Verdict {
    let roots = |classes: &mut Classes, q| {
        let (a, b) = pair.keys(q);
        (classes.find(a), classes.find(b))
    };
    if kind == RelationKind::Orthogonal {
        let (a, b) = roots(classes, Quantity::Direction);
        return if a == b {
            Verdict::Contradicts("its directions are parallel by the relations before it")
        } else if classes.are_orthogonal(a, b) {
            Verdict::Implied
        } else if classes.closes_four(a, b) {
            Verdict::Contradicts(
                "with the relations before it, it would make four directions pairwise orthogonal",
            )
        } else {
            classes.make_orthogonal(a, b);
            Verdict::Joins
        };
    }
    let Some((own, direction)) = sameness(kind) else {
        return Verdict::Opaque;
    };
    if direction {
        let (a, b) = roots(classes, Quantity::Direction);
        if a != b && classes.are_orthogonal(a, b) {
            return Verdict::Contradicts(
                "its directions are orthogonal by the relations before it",
            );
        }
    }
    if let Some(q) = own {
        let (a, b) = roots(classes, q);
        if a != b && classes.are_apart(a, b) {
            return Verdict::Contradicts(
                "with the relations before it, it would make a part's two ends or a box's \
                 opposite faces one, a part of no size",
            );
        }
    }
    if joins(classes, kind, pair) {
        Verdict::Joins
    } else {
        Verdict::Implied
    }
}

/// Joins the sets a sameness relation of `kind` between `pair` makes one in `classes`;
/// whether it joined any (false: the relation says nothing new).
fn joins(classes: &mut Classes, kind: RelationKind, pair: &Pair<'_>) -> bool {
    let Some((own, direction)) = sameness(kind) else {
        return true;
    };
    let mut joined = false;
    for q in own
        .into_iter()
        .chain(direction.then_some(Quantity::Direction))
    {
        let (a, b) = pair.keys(q);
        let (a, b) = (classes.find(a), classes.find(b));
        if a != b {
            classes.join(a, b);
            joined = true;
        }
    }
    joined
}

/// The relations of `kept` that the others imply: all but a spanning forest of each
/// quantity's sets, and all but one orthogonal per pair of direction sets (as `classes`
/// has them after every relation).
///
/// Which relations span a set is free, as they all say the same; those that hold best
/// where the solve starts are taken, by their residuals there (Kruskal's rule). A part
/// tied to a set only through a relation that is far off at the start can be pulled the
/// wrong way, or not at all: a direction at right angles to the one it is made parallel
/// to sits on a saddle of the cross product, and the solver shrinks the axis instead.
fn spanning(
    document: &Document,
    classes: &mut Classes,
    kept: &[(&Related<'_>, Pair<'_>)],
) -> HashSet<RelationKey> {
    let mut shapes: HashMap<PrimitiveId, Shape<f64>> = HashMap::new();
    let mut order: Vec<(f64, usize)> = kept
        .iter()
        .enumerate()
        .map(|(i, (r, _))| (residual_at_start(document, r.relation, &mut shapes), i))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut forest = Classes::default();
    let mut orthogonal_pairs: HashSet<(usize, usize)> = HashSet::new();
    let mut implied = HashSet::new();
    for (_, i) in order {
        let (related, pair) = &kept[i];
        let needed = if related.relation.kind == RelationKind::Orthogonal {
            let (a, b) = pair.keys(Quantity::Direction);
            let (a, b) = (classes.find(a), classes.find(b));
            orthogonal_pairs.insert((a.min(b), a.max(b)))
        } else {
            joins(&mut forest, related.relation.kind, pair)
        };
        if !needed {
            implied.insert(related.id);
        }
    }
    implied
}

impl Structure {
    /// The contradicted relations as conflicts, named by their place among `all`.
    pub(super) fn named(&self, all: &[Related<'_>]) -> Vec<Conflict> {
        let by_id: HashMap<RelationKey, &Related<'_>> = all.iter().map(|r| (r.id, r)).collect();
        self.contradicted
            .iter()
            .filter_map(|(id, why)| {
                let r = by_id.get(id)?;
                Some(Conflict {
                    relation: *id,
                    message: format!(
                        "{} switched off: it contradicts the relations before it ({why})",
                        describe(r.position, r.relation)
                    ),
                })
            })
            .collect()
    }

    /// The implied relations among `all` that do not hold to `tol` on the `solved` parts
    /// (the others as `document` has them).
    pub(super) fn unmet(
        &self,
        document: &Document,
        all: &[Related<'_>],
        solved: &[(PrimitiveId, Primitive, f64)],
        tol: f64,
    ) -> Vec<RelationKey> {
        let solved: HashMap<PrimitiveId, &Primitive> =
            solved.iter().map(|(id, p, _)| (*id, p)).collect();
        let primitive = |id: PrimitiveId| {
            solved
                .get(&id)
                .copied()
                .or_else(|| document.get(id).map(|p| &p.primitive))
        };
        let mut shapes = HashMap::new();
        all.iter()
            .filter(|r| self.implied.contains(&r.id))
            .filter(|r| residual(r.relation, &mut shapes, primitive).is_some_and(|v| v > tol))
            .map(|r| r.id)
            .collect()
    }
}

/// The largest |ψ| of `relation` on the parts `primitive` gives, their shapes cached in
/// `shapes`; `None` when a member is missing or the residuals cannot be written.
fn residual<'p>(
    relation: &Relation,
    shapes: &mut HashMap<PrimitiveId, Shape<f64>>,
    primitive: impl Fn(PrimitiveId) -> Option<&'p Primitive>,
) -> Option<f64> {
    for id in &relation.members {
        if !shapes.contains_key(id) {
            shapes.insert(*id, primitive(*id)?.current_shape());
        }
    }
    let members: Vec<Member<'_, f64>> = relation
        .members
        .iter()
        .enumerate()
        .map(|(k, id)| Member {
            features: &shapes[id].features,
            feature: relation.features.get(k).copied().flatten(),
        })
        .collect();
    let psi = residuals(relation.kind, &members).ok()?;
    Some(psi.iter().fold(0.0, |m: f64, v| m.max(v.abs())))
}

/// The largest |ψ| of `relation` where the solve starts (the parts as `document` has
/// them); infinite when it cannot be evaluated, so such a relation spans last.
fn residual_at_start(
    document: &Document,
    relation: &Relation,
    shapes: &mut HashMap<PrimitiveId, Shape<f64>>,
) -> f64 {
    residual(relation, shapes, |id| {
        document.get(id).map(|p| &p.primitive)
    })
    .filter(|v| v.is_finite())
    .unwrap_or(f64::INFINITY)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::analyse;
    use crate::model::{Document, Fit, Placed, PrimitiveId, Relation, RelationId};
    use crate::primitive::{Cuboid, Cylinder, Feature, Primitive};
    use crate::relation::{Mode, RelationKind};

    fn cylinder(doc: &mut Document, x: f64, axis: DVec3) -> PrimitiveId {
        doc.add(Placed {
            primitive: Primitive::Cylinder(Cylinder {
                center: DVec3::new(x, 0.0, 0.0),
                axis: axis.normalize(),
                length: 10.0,
                radius: 2.0,
            }),
            fit: Fit::default(),
        })
    }

    fn relate(
        doc: &mut Document,
        kind: RelationKind,
        [a, b]: [PrimitiveId; 2],
        features: [Feature; 2],
    ) -> RelationId {
        doc.add_relation(Relation {
            kind,
            members: vec![a, b],
            features: features.map(Some).to_vec(),
            mode: Mode::Hard,
            inferred: None,
        })
        .expect("the relation suits its members")
    }

    const TOPS: [Feature; 2] = [Feature::Top, Feature::Top];

    /// The implied relations and the contradicted ones of `doc`, every part taken.
    fn structure(doc: &Document) -> (Vec<RelationId>, Vec<RelationId>) {
        let ids = doc.primitives.keys().copied().collect();
        let relations = doc.relations_between(&ids, &std::collections::BTreeSet::new());
        let s = analyse(doc, &relations);
        let mut implied: Vec<RelationId> = s.implied.into_iter().collect();
        implied.sort();
        (
            implied,
            s.contradicted.into_iter().map(|(id, _)| id).collect(),
        )
    }

    #[test]
    fn all_pairs_of_a_sameness_leave_a_spanning_tree_to_solve() {
        let mut doc = Document::new();
        let parts: Vec<PrimitiveId> = (0..6)
            .map(|i| {
                cylinder(
                    &mut doc,
                    10.0 * f64::from(i),
                    DVec3::new(0.05 * f64::from(i), 1.0, 0.0),
                )
            })
            .collect();
        let mut all = Vec::new();
        for (i, a) in parts.iter().enumerate() {
            for b in &parts[i + 1..] {
                all.push(relate(&mut doc, RelationKind::Parallel, [*a, *b], TOPS));
                all.push(relate(&mut doc, RelationKind::SameRadius, [*a, *b], TOPS));
            }
        }
        let (implied, contradicted) = structure(&doc);
        assert!(contradicted.is_empty());
        // 15 pairs of each kind, 5 of each span the six parts.
        assert_eq!(implied.len(), 2 * (15 - 5), "{implied:?}");
        // The neighbours in angle span the parallels: they hold best at the start.
        let spanning: Vec<&Relation> = all
            .iter()
            .filter(|r| !implied.contains(r))
            .filter_map(|r| doc.relation(*r))
            .filter(|r| r.kind == RelationKind::Parallel)
            .collect();
        for r in spanning {
            let (a, b) = (r.members[0].0, r.members[1].0);
            assert_eq!(a.abs_diff(b), 1, "{r:?}");
        }
    }

    #[test]
    fn the_ends_of_one_axis_and_opposite_faces_of_a_box_are_one_direction() {
        let mut doc = Document::new();
        let a = cylinder(&mut doc, 0.0, DVec3::Y);
        let b = cylinder(&mut doc, 10.0, DVec3::Y);
        relate(&mut doc, RelationKind::Parallel, [a, b], TOPS);
        let again = relate(
            &mut doc,
            RelationKind::Parallel,
            [a, b],
            [Feature::Bottom, Feature::Top],
        );
        let box_ = doc.add(Placed {
            primitive: Primitive::Cuboid(Cuboid {
                center: DVec3::new(30.0, 0.0, 0.0),
                rotation: glam::DQuat::IDENTITY,
                size: DVec3::splat(10.0),
            }),
            fit: Fit::default(),
        });
        let up = Feature::Face {
            axis: crate::primitive::Axis::Y,
            positive: true,
        };
        let down = Feature::Face {
            axis: crate::primitive::Axis::Y,
            positive: false,
        };
        relate(
            &mut doc,
            RelationKind::Parallel,
            [a, box_],
            [Feature::Top, up],
        );
        let opposite = relate(
            &mut doc,
            RelationKind::Parallel,
            [b, box_],
            [Feature::Top, down],
        );
        let (implied, contradicted) = structure(&doc);
        assert!(contradicted.is_empty());
        assert_eq!(implied, vec![again, opposite]);
    }

    #[test]
    fn an_orthogonal_within_a_parallel_set_and_a_parallel_across_an_orthogonal_contradict() {
        let mut doc = Document::new();
        let [a, b, c, d] = [0.0, 10.0, 20.0, 30.0].map(|x| cylinder(&mut doc, x, DVec3::Y));
        relate(&mut doc, RelationKind::Parallel, [a, b], TOPS);
        relate(&mut doc, RelationKind::Coaxial, [b, c], TOPS);
        let within = relate(&mut doc, RelationKind::Orthogonal, [a, c], TOPS);
        relate(&mut doc, RelationKind::Orthogonal, [c, d], TOPS);
        let across = relate(&mut doc, RelationKind::Parallel, [d, a], TOPS);
        let (_, contradicted) = structure(&doc);
        assert_eq!(contradicted, vec![within, across]);
    }

    #[test]
    fn four_pairwise_orthogonal_directions_contradict_and_a_repeated_orthogonal_is_implied() {
        let mut doc = Document::new();
        let axes = [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(1.0, 1.0, 1.0)];
        let parts: Vec<PrimitiveId> = axes
            .iter()
            .enumerate()
            .map(|(i, axis)| cylinder(&mut doc, 10.0 * i as f64, *axis))
            .collect();
        let mut last = None;
        for i in 0..4 {
            for j in i + 1..4 {
                last = Some(relate(
                    &mut doc,
                    RelationKind::Orthogonal,
                    [parts[i], parts[j]],
                    TOPS,
                ));
            }
        }
        // The sixth pair closes the four; the fifth (1, 3) does not yet.
        let (_, contradicted) = structure(&doc);
        assert_eq!(contradicted, vec![last.expect("six pairs")]);

        let mut doc = Document::new();
        let [a, b, c] = [0.0, 10.0, 20.0].map(|x| cylinder(&mut doc, x, DVec3::Y));
        relate(&mut doc, RelationKind::Parallel, [a, b], TOPS);
        let first = relate(&mut doc, RelationKind::Orthogonal, [a, c], TOPS);
        let second = relate(&mut doc, RelationKind::Orthogonal, [b, c], TOPS);
        let (implied, contradicted) = structure(&doc);
        assert!(contradicted.is_empty());
        assert_eq!(implied.len(), 1);
        assert!(implied == vec![first] || implied == vec![second]);
    }

    #[test]
    fn what_a_part_keeps_apart_or_at_right_angles_is_never_made_one() {
        // Top on top, bottom on bottom, then top on bottom: both rods of no length.
        let mut doc = Document::new();
        let [a, b] = [0.0, 10.0].map(|x| cylinder(&mut doc, x, DVec3::Y));
        relate(&mut doc, RelationKind::Concentric, [a, b], TOPS);
        relate(
            &mut doc,
            RelationKind::Concentric,
            [a, b],
            [Feature::Bottom, Feature::Bottom],
        );
        let third = relate(
            &mut doc,
            RelationKind::Concentric,
            [a, b],
            [Feature::Top, Feature::Bottom],
        );
        assert_eq!(structure(&doc).1, vec![third]);

        // A rod parallel to a box's x faces and then to its y faces.
        let mut doc = Document::new();
        let rod = cylinder(&mut doc, 0.0, DVec3::X);
        let box_ = doc.add(Placed {
            primitive: Primitive::Cuboid(Cuboid {
                center: DVec3::new(30.0, 0.0, 0.0),
                rotation: glam::DQuat::IDENTITY,
                size: DVec3::splat(10.0),
            }),
            fit: Fit::default(),
        });
        let face = |axis| Feature::face(axis, true);
        relate(
            &mut doc,
            RelationKind::Parallel,
            [rod, box_],
            [Feature::Top, face(crate::primitive::Axis::X)],
        );
        let second = relate(
            &mut doc,
            RelationKind::Parallel,
            [rod, box_],
            [Feature::Top, face(crate::primitive::Axis::Y)],
        );
        assert_eq!(structure(&doc).1, vec![second]);
    }
}
