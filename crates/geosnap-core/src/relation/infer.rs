//! Inference on release: the relations a designer meant between a newly snapped
//! primitive and those already placed, each with its confidence and evidence, with no
//! duplicates and no redundant chains.
//!
//! **Candidates come from the contact graph** ([`super::contact`]): the new part is
//! compared only with the parts a few joints away from it ([`MAX_HOPS`]), and with the
//! parts that repeat it (one kind and size: candles, legs, prongs) a few more
//! ([`ALIKE_HOPS`]), nearest first, so parts of different objects are never
//! related and the work grows with the contacts, not with the square of the parts.
//! Where a candidate is judged against the drawing, the drawing's own noise for its
//! parts (their fit RMS) widens every position, radius and length threshold it is
//! tighter than (a few times at most), and ends drawn on each other may lie apart along
//! their axis by more than across it. Each candidate that nearly holds
//! ([`super::closeness`]) is weighed ([`super::evidence`]): how the parts meet, whether
//! they repeat one another or lie across a part both join, how closely it holds against the drawing's noise, and a
//! prior per kind and situation. A confident candidate becomes a hard relation, a
//! middling one a suggestion ([`Mode::Suggested`]), a weak one is not kept.
//!
//! Two parts meet in one plane at most, and repeated parts meet what they share the
//! same way: where a part repeating the new one already has one of its planes in one
//! with a plane of the other part (a stud's bottom on the brick's top), that pair comes
//! first, before faces facing each other and nearness on the paper. Parts read off the
//! same strokes ([`ContactGraph::separate`]) are never related to each other.
//!
//! A candidate is dropped when what it says already follows from the relations kept so
//! far (hard ones for a hard candidate; hard and suggested ones for a suggestion):
//! - parallel, coaxial, concentric, coplanar, same radius and equal length are
//!   equivalences: each keeps a union–find of the entities it relates (directions, axis
//!   lines, centres, planes, radii, lengths), seeded with the relations already in the
//!   model, and a candidate whose two entities are already joined is redundant. Three
//!   parallel legs get two relations, not three;
//! - coaxial implies parallel (a coaxial pair joins the directions too), and a pair that
//!   is both coaxial and concentric is coplanar there already; two boxes with two pairs
//!   of parallel edges have the third pair parallel already;
//! - orthogonal is kept once per pair of direction classes; a box edge orthogonal to a
//!   tube says nothing new about the box's other parallel edges; and it is proposed only
//!   between parts that touch in the drawing (at a joint it is likely; where outlines
//!   merely cross, too unlikely to keep);
//! - collinear centres are not proposed where the three centres are already on one
//!   coaxial axis.
//!
//! Two ends are proposed concentric only where they face each other (outward normals
//! opposed), as stacked ends do: ends facing the same way would put one solid inside
//! the other, and ends facing apart by less than a right angle one through the other
//! (a stem on the far face of a thin base, which the paper cannot tell from the near
//! one, or the near face in the mirror reading of the stem).
//!
//! Relations in [`Mode::Off`] do not count as known.

use std::collections::{BTreeSet, HashMap};

use super::contact::{ContactGraph, Outline};
use super::evidence::{confidence, prior, Contact, Evidence, Inferred};
use super::{
    closeness_by, coplanar, equal_length, holds, standing, tilt, InferenceSettings, Member, Mode,
    RelationKind, MIN_PROJECTED_AXIS,
};
use crate::primitive::{Axis, Feature, FeatureCurve, FeatureGeometry, PrimitiveKind};

/// How many joints apart two parts may be and still be related: a table's leg reaches
/// another leg through the top (2), a menorah's candle its stem through its arm (2),
/// and 3 leaves one part to spare between them (a collar on the stem, a foot under a
/// leg).
pub const MAX_HOPS: u32 = 3;

/// How many joints apart alike parts (one kind and size) are still compared: twice
/// [`MAX_HOPS`]. Repeated parts sit symmetrically about what joins them (candles across
/// a menorah's arms, legs across a table's top), seldom further; in a busy drawing,
/// parts of other objects touching this one are further still.
pub const ALIKE_HOPS: u32 = 2 * MAX_HOPS;

/// Parts of one kind whose sizes differ by less than this fraction repeat one another
/// (when they are of one object but not stacked on each other).
const REPEAT_SIZE: f64 = 0.2;

/// How many times the position tolerance ends that sit on each other in the drawing may
/// lie apart along their common axis and still be taken as concentric: where an end stops
/// along its axis is pinned by a stroke's end only (overshoots and gaps where parts join
/// are common), while its place across the axis is pinned by both silhouettes.
const AXIAL_SLACK: f64 = 5.0;

/// A placed primitive as inference sees it.
#[derive(Clone, Copy, Debug)]
pub struct Part<'a> {
    /// Its kind.
    pub kind: PrimitiveKind,
    /// Its feature curves (at the snapped or solved pose).
    pub features: &'a [FeatureCurve<f64>],
    /// Its outline in the drawing.
    pub outline: &'a Outline,
    /// Its size ([`crate::primitive::Primitive::size`]).
    pub size: f64,
    /// Its fit RMS relative to its size: the drawing's noise for this part (0 for a part
    /// without strokes).
    pub noise: f64,
    /// How far the depth components of its `bottom` and `top` ends' normals may move
    /// and still match the drawing ([`tilt::slack`]; 0 for parts without ends, and for
    /// parts placed without strokes).
    pub tilt: [f64; 2],
    /// The direction its side lines are drawn in on the paper, where they show one
    /// ([`crate::model::reading::drawn_axis`]); `None` where none is drawn (or the part
    /// was placed without strokes).
    pub drawn_axis: Option<glam::DVec2>,
    /// One standard deviation of its length as its strokes pin it, relative to the
    /// length (infinite where they do not pin it; 0 where it is not known).
    pub length_spread: f64,
}

impl Part<'_> {
    /// The tilt slack of the direction `feature` names (0 for a box face, and where no
    /// feature is named).
    fn tilt_of(&self, feature: Option<Feature>) -> f64 {
        match feature {
            Some(Feature::Bottom) => self.tilt[0],
            Some(Feature::Top) => self.tilt[1],
            _ => 0.0,
        }
    }
}

/// A relation inferred by [`infer`]: the proposal, the mode its confidence earns
/// ([`Mode::Hard`] or [`Mode::Suggested`]), its confidence and its evidence.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    /// The relation.
    pub proposal: Proposal,
    /// Hard or suggested.
    pub mode: Mode,
    /// Its confidence and evidence.
    pub inferred: Inferred,
}

/// A relation between parts, by index, with the feature each member uses (`None` for
/// kinds about the whole solid).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Proposal {
    /// The kind.
    pub kind: RelationKind,
    /// The parts, as indices into the slice given to [`infer`].
    pub members: Vec<usize>,
    /// The feature of each member.
    pub features: Vec<Option<Feature>>,
}

/// A box's directions: one face per axis.
const BOX_DIRECTIONS: [Feature; 3] = [
    Feature::face(Axis::X, true),
    Feature::face(Axis::Y, true),
    Feature::face(Axis::Z, true),
];

/// The features giving a part's directions, one per direction class.
fn directions(part: &Part<'_>) -> &'static [Feature] {
    match part.kind {
        PrimitiveKind::Cylinder | PrimitiveKind::Cone | PrimitiveKind::Sgc => &[Feature::Top],
        PrimitiveKind::Cuboid => &BOX_DIRECTIONS,
        PrimitiveKind::Sphere | PrimitiveKind::Bgc => &[],
    }
}

/// The end circles of a part (a sphere's outline is not an end).
fn ends(part: &Part<'_>) -> &'static [Feature] {
    match part.kind {
        PrimitiveKind::Cylinder | PrimitiveKind::Cone | PrimitiveKind::Sgc | PrimitiveKind::Bgc => {
            &[Feature::Bottom, Feature::Top]
        }
        PrimitiveKind::Sphere | PrimitiveKind::Cuboid => &[],
    }
}

/// The circles of a part, the sphere's outline included.
fn circles(part: &Part<'_>) -> &'static [Feature] {
    match part.kind {
        PrimitiveKind::Sphere => &[Feature::Outline],
        _ => ends(part),
    }
}

/// The flat features of a part: end circles and box faces.
fn planes(part: &Part<'_>) -> &'static [Feature] {
    match part.kind {
        PrimitiveKind::Cuboid => &Feature::FACES,
        _ => ends(part),
    }
}

/// The projected centre and the unit normal of a part's flat `feature`.
fn plane_of(part: &Part<'_>, feature: Feature) -> Option<(glam::DVec2, glam::DVec3)> {
    part.features
        .iter()
        .find(|f| f.feature == feature)
        .map(|f| match &f.geometry {
            FeatureGeometry::Circle { center, normal, .. }
            | FeatureGeometry::Rectangle { center, normal, .. } => {
                (glam::DVec2::new(center.x, center.y), normal.to_dvec3())
            }
        })
}

/// What of a part an entity of inference is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Slot {
    /// The part as a whole: its axis line, its length, a cylinder's one radius.
    Whole,
    /// One of its features: a centre, a plane, a radius.
    Feature(Feature),
    /// One of its direction classes ([`Feature::direction_class`]).
    Direction(usize),
}

/// An entity of inference: a part (by index) and what of it.
type Entity = (usize, Slot);

/// A union–find over entities.
#[derive(Default)]
struct Classes {
    parent: HashMap<Entity, Entity>,
}

impl Classes {
    fn find(&mut self, x: Entity) -> Entity {
        let mut root = x;
        while let Some(&p) = self.parent.get(&root) {
            if p == root {
                break;
            }
            root = p;
        }
        // Path compression.
        let mut cur = x;
        while cur != root {
            let next = self.parent.get(&cur).copied().unwrap_or(root);
            self.parent.insert(cur, root);
            cur = next;
        }
        root
    }

    /// Joins two entities; false when they were joined already.
    fn union(&mut self, a: Entity, b: Entity) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        self.parent.insert(ra, rb);
        true
    }
}

/// What the kept relations already say.
#[derive(Default)]
struct Known {
    parallel: Classes,
    coaxial: Classes,
    concentric: Classes,
    coplanar: Classes,
    radius: Classes,
    length: Classes,
    orthogonal: BTreeSet<(Entity, Entity)>,
    others: Vec<Proposal>,
}

impl Known {
    /// Records `p`; false when it follows from what is known.
    fn add(&mut self, parts: &[Part<'_>], p: &Proposal) -> bool {
        let entity = |i: usize| {
            (
                p.members[i],
                p.features[i].map_or(Slot::Whole, Slot::Feature),
            )
        };
        // A bent tube's ends have an axis and a direction each.
        let end_of_bent = |i: usize| {
            (parts[p.members[i]].kind == PrimitiveKind::Bgc)
                .then_some(p.features[i])
                .flatten()
                .map(|f| (p.members[i], Slot::Feature(f)))
        };
        let direction = |i: usize| {
            end_of_bent(i).unwrap_or_else(|| {
                let class = p.features[i].map_or(0, Feature::direction_class);
                (p.members[i], Slot::Direction(class))
            })
        };
        let whole = |i: usize| end_of_bent(i).unwrap_or((p.members[i], Slot::Whole));
        match p.kind {
            RelationKind::Parallel => {
                let boxes = p
                    .members
                    .iter()
                    .all(|&m| parts[m].kind == PrimitiveKind::Cuboid);
                if boxes && self.box_turn_known(&p.members, direction(0), direction(1)) {
                    return false;
                }
                self.parallel.union(direction(0), direction(1))
            }
            RelationKind::Coaxial => {
                let new = self.coaxial.union(whole(0), whole(1));
                self.parallel.union(direction(0), direction(1));
                new
            }
            RelationKind::Concentric => self.concentric.union(entity(0), entity(1)),
            RelationKind::Coplanar => self.coplanar.union(entity(0), entity(1)),
            RelationKind::SameRadius => {
                // A cylinder has one radius, whichever end names it.
                let radius = |i: usize| match parts[p.members[i]].kind {
                    PrimitiveKind::Cylinder => whole(i),
                    _ => entity(i),
                };
                self.radius.union(radius(0), radius(1))
            }
            RelationKind::EqualLength => self.length.union(whole(0), whole(1)),
            RelationKind::Orthogonal => {
                let (a, b) = (
                    self.parallel.find(direction(0)),
                    self.parallel.find(direction(1)),
                );
                let key = if a <= b { (a, b) } else { (b, a) };
                self.orthogonal.insert(key)
            }
            RelationKind::OnSphere | RelationKind::CollinearCenters => {
                if self.others.contains(p) {
                    false
                } else {
                    self.others.push(p.clone());
                    true
                }
            }
        }
    }

    /// Whether two boxes' directions `a` and `b` are parallel already because their two
    /// other directions are: two pairs of parallel edges fix a box's turn, so the third
    /// pair follows.
    fn box_turn_known(&mut self, members: &[usize], a: Entity, b: Entity) -> bool {
        let (Slot::Direction(ca), Slot::Direction(cb)) = (a.1, b.1) else {
            return false;
        };
        let (ma, mb) = (members[0], members[1]);
        let mut joined = Vec::new();
        for x in (0..3).filter(|&x| x != ca) {
            for y in (0..3).filter(|&y| y != cb) {
                if self.parallel.find((ma, Slot::Direction(x)))
                    == self.parallel.find((mb, Slot::Direction(y)))
                {
                    joined.push((x, y));
                }
            }
        }
        joined
            .iter()
            .any(|&(x, y)| joined.iter().any(|&(u, v)| u != x && v != y))
    }

    /// Whether two parts are on one axis already.
    fn coaxial(&mut self, a: usize, b: usize) -> bool {
        self.coaxial.find((a, Slot::Whole)) == self.coaxial.find((b, Slot::Whole))
    }
}

/// The projected centre of a part: the mean of its features' centres.
fn centre(part: &Part<'_>) -> glam::DVec2 {
    let n = part.features.len().max(1) as f64;
    part.features
        .iter()
        .map(|f| match &f.geometry {
            FeatureGeometry::Circle { center, .. } | FeatureGeometry::Rectangle { center, .. } => {
                glam::DVec2::new(center.x, center.y)
            }
        })
        .sum::<glam::DVec2>()
        / n
}

/// The relations between part `new` and the others, given the relations already in the
/// model (`existing`, each with its mode; off ones are left out), each with its mode,
/// confidence and evidence. See the module docs for the rules.
pub fn infer(
    parts: &[Part<'_>],
    new: usize,
    existing: &[(Proposal, Mode)],
    settings: &InferenceSettings,
) -> Vec<Found> {
    let graph = ContactGraph::new(parts, settings.distance);
    infer_in(&graph, parts, new, existing, settings)
}

/// As [`infer`], in the contact graph of `parts` built already (a part's mirror image in
/// depth has the same outline, so one graph serves both).
pub fn infer_in(
    graph: &ContactGraph,
    parts: &[Part<'_>],
    new: usize,
    existing: &[(Proposal, Mode)],
    settings: &InferenceSettings,
) -> Vec<Found> {
    if new >= parts.len() {
        return Vec::new();
    }
    let hops = within_reach(graph, parts, new, usize::MAX);
    let others: Vec<usize> = (0..parts.len())
        .filter(|&i| i != new && hops[i].is_some() && !graph.kept_apart(new, i))
        .collect();
    infer_among(parts, new, &others, existing, settings, graph, &hops)
}

/// How many joints apart each part is from `from` (as [`ContactGraph::hops_avoiding`],
/// without part `avoid`), for the parts inference compares with it: those within
/// [`MAX_HOPS`], and beyond them, up to [`ALIKE_HOPS`], the parts that repeat it
/// ([`alike`]). A menorah's candles are four joints apart across its arms, and alike by
/// design.
fn within_reach(
    graph: &ContactGraph,
    parts: &[Part<'_>],
    from: usize,
    avoid: usize,
) -> Vec<Option<u32>> {
    let object = graph.hops_avoiding(from, ALIKE_HOPS, avoid);
    object
        .iter()
        .enumerate()
        .map(|(i, h)| match h {
            Some(h) if *h <= MAX_HOPS => Some(*h),
            Some(h) if alike(&parts[from], &parts[i]) => Some(*h),
            _ => None,
        })
        .collect()
}

/// Whether two parts are alike: one kind and one size (within [`REPEAT_SIZE`]).
fn alike(a: &Part<'_>, b: &Part<'_>) -> bool {
    a.kind == b.kind && (a.size - b.size).abs() <= REPEAT_SIZE * a.size.max(b.size)
}

/// The relations a part `via` brings about between others: parts placed before the
/// part that joins them (a menorah's cups before its arms) were out of each other's
/// reach when they were released. For each part `via` has a joint with, the parts that
/// only `via` brings within [`MAX_HOPS`] of it are compared with it, as on its own
/// release. `graph` is the contact graph of `parts`; `existing` holds the relations known
/// so far (those `via`'s release found included).
pub fn infer_bridged(
    graph: &ContactGraph,
    parts: &[Part<'_>],
    via: usize,
    existing: &[(Proposal, Mode)],
    settings: &InferenceSettings,
) -> Vec<Found> {
    if via >= parts.len() {
        return Vec::new();
    }
    let mut known: Vec<(Proposal, Mode)> = existing.to_vec();
    let mut out = Vec::new();
    let neighbours: Vec<usize> = graph.joints(via).collect();
    for n in neighbours {
        let before = within_reach(graph, parts, n, via);
        let hops = within_reach(graph, parts, n, usize::MAX);
        let others: Vec<usize> = (0..parts.len())
            .filter(|&j| {
                j != n
                    && j != via
                    && hops[j].is_some()
                    && before[j].is_none()
                    && !graph.kept_apart(n, j)
            })
            .collect();
        if others.is_empty() {
            continue;
        }
        let found = infer_among(parts, n, &others, &known, settings, graph, &hops);
        known.extend(found.iter().map(|f| (f.proposal.clone(), f.mode)));
        out.extend(found);
    }
    out
}

/// The relations between part `new` and `others` (all within reach of it: `hops` says
/// how far), given the relations known so far.
fn infer_among(
    parts: &[Part<'_>],
    new: usize,
    others: &[usize],
    existing: &[(Proposal, Mode)],
    settings: &InferenceSettings,
    graph: &ContactGraph,
    hops: &[Option<u32>],
) -> Vec<Found> {
    let mut run = Inference {
        parts,
        new,
        settings,
        graph,
        hops,
        enforced: Known::default(),
        all: Known::default(),
        out: Vec::new(),
    };
    for (p, mode) in existing {
        if mode.is_enforced() {
            run.enforced.add(parts, p);
        }
        if *mode != Mode::Off {
            run.all.add(parts, p);
        }
    }
    let here = centre(&parts[new]);
    let mut others = others.to_vec();
    others.sort_by(|&a, &b| {
        hops[a].cmp(&hops[b]).then(
            centre(&parts[a])
                .distance(here)
                .total_cmp(&centre(&parts[b]).distance(here)),
        )
    });
    for &other in &others {
        let coaxial = run.axes(other);
        run.circles_and_planes(other, coaxial);
        run.solids(other);
    }
    run.collinear(&others);
    run.out
}

/// One run of [`infer`]: what is known so far and what was found.
struct Inference<'p, 'a> {
    parts: &'p [Part<'a>],
    new: usize,
    settings: &'p InferenceSettings,
    graph: &'p ContactGraph,
    /// How many joints apart each part is from the new one.
    hops: &'p [Option<u32>],
    /// What the enforced relations say (hard candidates are checked against it).
    enforced: Known,
    /// What the enforced and suggested relations say (suggestions are checked against
    /// it).
    all: Known,
    out: Vec<Found>,
}

impl Inference<'_, '_> {
    /// The members of `p` as relation tests see them.
    fn members(&self, p: &Proposal) -> Vec<Member<'_, f64>> {
        p.members
            .iter()
            .zip(&p.features)
            .map(|(&i, f)| Member {
                features: self.parts[i].features,
                feature: *f,
            })
            .collect()
    }

    /// Whether `p` holds within `settings`: its kind's test, or for the like ends of
    /// repeated parts, their planes level ([`coplanar::level`]).
    fn test(&self, p: &Proposal, settings: &InferenceSettings) -> bool {
        let members = self.members(p);
        holds(p.kind, &members, settings)
            || (self.like_ends_of_repeated(p) && coplanar::level(&members, settings))
    }

    /// Whether `p` nearly holds: within the thresholds widened by the drawing's noise
    /// ([`Self::settings_for`]). Tilts moved within what the drawn ends show
    /// ([`Self::within_tilt`]) are weighed apart: they make suggestions only.
    fn holds(&self, p: &Proposal) -> bool {
        self.settings.enabled(p.kind) && self.test(p, &self.settings_for(p))
    }

    /// Whether `p` (parallel, coaxial or orthogonal) holds once its members' tilts move
    /// within their slack: directions that agree on the paper, with depth the drawing
    /// leaves open. Orthogonal only at a T (an end of one on the other's side: a branch,
    /// a handle), where square is the joint a designer builds, and only where both tilts
    /// are pinned by drawn ends: with a tilt free, any two directions apart on the paper
    /// can be made square. Not for an end on a face: a part standing there is meant
    /// along the face's normal (splayed legs under a camera's body came out square to its
    /// faces).
    fn within_tilt(&self, p: &Proposal) -> bool {
        if p.members.len() != 2 || p.members[0] == p.members[1] {
            return false;
        }
        let slack = [0, 1].map(|i| self.parts[p.members[i]].tilt_of(p.features[i]));
        if p.kind == RelationKind::Orthogonal
            && (self.graph.between(p.members[0], p.members[1]) != Contact::EndOnSide
                || slack.iter().any(|&s| s >= tilt::FREE))
        {
            return false;
        }
        tilt::holds(p.kind, &self.members(p), &self.settings_for(p), slack)
    }

    /// How far inside its thresholds `p` holds with its members' tilts moved within their
    /// slack ([`Self::within_tilt`]), where `p` is coaxial between repeated parts on
    /// opposite sides of a part both join ([`Self::across_a_hub`]): a menorah's paired
    /// arms. Such a pair is built on one line, so where its depth
    /// is the snap's guess from ends drawn small it is weighed as a pair that holds as
    /// drawn, not as one at the edge of its thresholds (a suggestion at most). `None`
    /// otherwise, or where it does not hold even so.
    fn paired_across(&self, p: &Proposal) -> Option<f64> {
        if p.kind != RelationKind::Coaxial
            || p.members.len() != 2
            || !self.repeated(p.members[0], p.members[1])
        {
            return None;
        }
        let other = p.members.iter().copied().find(|&m| m != self.new)?;
        if !self.across_a_hub(other) {
            return None;
        }
        let slack = [0, 1].map(|i| self.parts[p.members[i]].tilt_of(p.features[i]));
        let members = self.members(p);
        closeness_by(|s| tilt::holds(p.kind, &members, s, slack), self.settings)
    }

    /// Whether `p` is a coplanar candidate between the same end (or face) of two
    /// repeated parts: the rims of a menorah's cups, the feet of a table's legs. Those
    /// are meant level even where neither is drawn inside the other's outline.
    fn like_ends_of_repeated(&self, p: &Proposal) -> bool {
        p.kind == RelationKind::Coplanar
            && p.members.len() == 2
            && p.features[0].is_some()
            && p.features[0] == p.features[1]
            && self.repeated(p.members[0], p.members[1])
    }

    /// Whether parts `a` and `b` repeat one another: alike ([`alike`]), of one object
    /// but not stacked on each other (two joints apart or more, or sharing a joint).
    fn repeated(&self, a: usize, b: usize) -> bool {
        let (new, other) = if a == self.new { (a, b) } else { (b, a) };
        new == self.new
            && new != other
            && alike(&self.parts[new], &self.parts[other])
            && (self.hops[other].is_some_and(|h| h >= 2) || self.graph.share_a_joint(new, other))
    }

    /// The thresholds for `p`: the settings with the drawing's noise for its members
    /// (their fit RMS, combined as independent errors) and, for ends that sit on each
    /// other in the drawing, the axial slack ([`AXIAL_SLACK`]).
    fn settings_for(&self, p: &Proposal) -> InferenceSettings {
        let mut members = p.members.clone();
        members.sort_unstable();
        members.dedup();
        let noise = members
            .iter()
            .map(|&m| (self.parts[m].noise * self.parts[m].size).powi(2))
            .sum::<f64>()
            .sqrt();
        let stacked = p.kind == RelationKind::Concentric
            && members.len() == 2
            && matches!(
                self.graph.between(members[0], members[1]),
                Contact::EndOnEnd | Contact::EndOnFace
            );
        self.settings
            .for_members(noise, if stacked { AXIAL_SLACK } else { 1.0 })
    }

    /// Whether some direction of `other` is parallel to one of the new part's.
    fn parallel_to_new(&self, other: usize) -> bool {
        let (new_part, other_part) = (self.parts[self.new], self.parts[other]);
        directions(&new_part).iter().any(|&a| {
            directions(&other_part)
                .iter()
                .any(|&b| self.holds(&self.pair(RelationKind::Parallel, other, a, b)))
        })
    }

    /// The kind's threshold in the relative units of the parts' noise.
    fn threshold(&self, kind: RelationKind) -> f64 {
        let s = self.settings;
        match kind {
            RelationKind::Parallel | RelationKind::Orthogonal => s.angle_degrees.to_radians().sin(),
            RelationKind::SameRadius => s.radius,
            RelationKind::EqualLength => s.length,
            _ => s.distance,
        }
    }

    /// The evidence for `p` (which holds to `closeness` of its thresholds).
    fn evidence(&self, p: &Proposal, closeness: f64) -> Evidence {
        let other = p.members.iter().copied().find(|&m| m != self.new);
        let (contact, hops) = match other {
            Some(o) => (
                self.graph.between(self.new, o),
                self.hops[o].unwrap_or(u32::MAX),
            ),
            None => (Contact::Apart, 0),
        };
        // Alike parts of one object, not stacked on each other: legs under one top,
        // candles on a menorah's arms, prongs on a plug.
        let repeated = other.is_some_and(|o| self.repeated(self.new, o));
        let noise = p
            .members
            .iter()
            .map(|&m| self.parts[m].noise)
            .fold(0.0, f64::max);
        let across = other.is_some_and(|o| self.across_a_hub(o));
        let branches = other.is_some_and(|o| self.branches_of_one_hub(o));
        // Branches are cut from one stock only as far as the drawing shows it within
        // the thresholds themselves: radii that agree only within a rough drawing's
        // noise (studs sketched a tenth apart on a rough brick) say nothing more.
        let one_stock = branches && closeness < 1.0;
        Evidence {
            contact,
            hops,
            repeated,
            across,
            branches,
            closeness,
            noise,
            prior: prior(p.kind, contact, hops, repeated, across, one_stock),
        }
    }

    /// Whether the new part and `other` are branches of one part: of one kind, not
    /// joined to each other, and each joined to a third part with an end in the same way
    /// (both on its side, both on its faces, both on a ball), as a menorah's arms on its
    /// stem. Stacked tiers (ends on ends) are not branches.
    fn branches_of_one_hub(&self, other: usize) -> bool {
        let new = self.new;
        self.parts[new].kind == self.parts[other].kind
            && !self.graph.between(new, other).is_joint()
            && self.graph.joints(new).any(|hub| {
                let contact = self.graph.between(new, hub);
                hub != other
                    && matches!(
                        contact,
                        Contact::EndOnSide | Contact::EndOnFace | Contact::EndOnSphere
                    )
                    && self.graph.between(other, hub) == contact
            })
    }

    /// Whether the new part and `other` lie on opposite sides of a part both join: on
    /// the paper, that part's centre projects between theirs onto the line through them.
    fn across_a_hub(&self, other: usize) -> bool {
        self.hub_between(other).is_some()
    }

    /// The part the new part and `other` both join, lying between them
    /// ([`Self::across_a_hub`]), if any.
    fn hub_between(&self, other: usize) -> Option<usize> {
        let a = centre(&self.parts[self.new]);
        let d = centre(&self.parts[other]) - a;
        let span = d.length_squared();
        if span <= 0.0 {
            return None;
        }
        self.graph.joints(self.new).find(|&hub| {
            hub != other
                && self.graph.joints(other).any(|j| j == hub)
                && (0.0..1.0).contains(&((centre(&self.parts[hub]) - a).dot(d) / span))
        })
    }

    /// Whether the new part's end `a` and `other`'s end `b` face each other across a
    /// round part both join (`hub`, [`Self::hub_between`]), on its two sides rather than at its axis: farther apart
    /// (in 3D) than its radius. A menorah's arms built out of its stem's sides leave it a
    /// stem's width apart and neither meet nor share a centre; arms built through it
    /// (one U through the stem, their ends hidden inside it) meet at its axis. Where the
    /// stem is thin the two differ by less than the depth a snap guesses, so such ends
    /// are held one centre or one plane by a suggestion at most.
    fn apart_across_a_hub(&self, hub: Option<usize>, other: usize, a: Feature, b: Feature) -> bool {
        let Some(hub) = hub else {
            return false;
        };
        let radius = self.parts[hub]
            .features
            .iter()
            .filter_map(|f| match &f.geometry {
                FeatureGeometry::Circle { radius, .. } => Some(*radius),
                FeatureGeometry::Rectangle { .. } => None,
            })
            .fold(0.0, f64::max);
        let end = |part: &Part<'_>, feature: Feature| {
            part.features.iter().find_map(|f| match &f.geometry {
                FeatureGeometry::Circle { center, normal, .. } if f.feature == feature => {
                    Some((center.to_dvec3(), normal.to_dvec3()))
                }
                _ => None,
            })
        };
        let (Some((ca, na)), Some((cb, nb))) =
            (end(&self.parts[self.new], a), end(&self.parts[other], b))
        else {
            return false;
        };
        radius > 0.0 && na.dot(nb) < 0.0 && ca.distance(cb) > radius
    }

    /// Weighs `p` and keeps it, hard or as a suggestion, if it holds, is confident enough
    /// and says something new; whether it was kept.
    fn propose(&mut self, p: Proposal) -> bool {
        if !self.settings.enabled(p.kind) {
            return false;
        }
        if let Some(closeness) = closeness_by(|s| self.test(&p, s), self.settings) {
            return self.keep(p, closeness, false);
        }
        // A pair built on one line across a hub, weighed with the depth its ends leave
        // open ([`Self::paired_across`]).
        if let Some(closeness) = self.paired_across(&p) {
            return self.keep(p, closeness, false);
        }
        // One that holds only within the drawing's noise, the axial slack or its
        // members' tilt slack, not within the thresholds, is at their edge: the drawing
        // does not show it exact, so it is at most a suggestion.
        if self.holds(&p) || self.within_tilt(&p) {
            return self.keep(p, 1.0, false);
        }
        // Lengths the strokes leave open, or sizes of repeated parts that differ no more
        // than parts that repeat one another do: at most a suggestion.
        (self.within_spread(&p) || self.alike_sizes(&p)) && self.keep(p, 1.0, true)
    }

    /// [`Self::propose`] for a candidate the drawing cannot settle (ends that lie on
    /// either side of a part between them or meet inside it, as a depth it leaves open
    /// says): kept as a suggestion at most.
    fn propose_at_most_suggested(&mut self, p: Proposal) -> bool {
        if !self.settings.enabled(p.kind) {
            return false;
        }
        let closeness = closeness_by(|s| self.test(&p, s), self.settings)
            .or_else(|| self.holds(&p).then_some(1.0));
        closeness.is_some_and(|c| self.keep(p, c, true))
    }

    /// Whether `p` (same radius or equal length) is between parts that repeat one
    /// another ([`Self::repeated`]) whose sizes differ by no more than repeated parts'
    /// do ([`REPEAT_SIZE`]): cups of one design on a menorah, sketched a little longer or
    /// shorter each, are meant alike.
    fn alike_sizes(&self, p: &Proposal) -> bool {
        matches!(p.kind, RelationKind::EqualLength | RelationKind::SameRadius)
            && p.members.len() == 2
            && self.repeated(p.members[0], p.members[1])
            && holds(
                p.kind,
                &self.members(p),
                &self.settings.with_sizes_at_least(REPEAT_SIZE / 2.0),
            )
    }

    /// Whether `p` (equal length) holds within what its members' strokes pin of their
    /// lengths ([`Part::length_spread`]): a stud whose bottom is hidden behind the brick's
    /// edge, cups whose rims are sketched loosely. Where the strokes leave a length so
    /// open that the window takes any two lengths of one order
    /// ([`equal_length::informative`]), only parts that repeat one another
    /// ([`Self::repeated`]: studs, cups) are held equal by it: a menorah's arm seen nearly
    /// along its axis is as long as any of its candles within that window, and meant as
    /// long as none.
    fn within_spread(&self, p: &Proposal) -> bool {
        if p.kind != RelationKind::EqualLength
            || p.members.len() != 2
            || p.members[0] == p.members[1]
        {
            return false;
        }
        let members = self.members(p);
        let spread = [0, 1].map(|i| self.parts[p.members[i]].length_spread);
        equal_length::within_spread(&members, spread)
            && (equal_length::informative(&members, spread)
                || self.repeated(p.members[0], p.members[1]))
    }

    /// How far inside the thresholds widened for a part standing on a face
    /// ([`standing`]) `p` holds, as a fraction of them; `None` where it fails there too.
    fn standing_fraction(&self, p: &Proposal) -> Option<f64> {
        if !self.drawn_standing(p) {
            return None;
        }
        let wide = standing::settings(&self.settings_for(p));
        closeness_by(|s| self.test(p, s), &wide)
    }

    /// Whether the drawing leaves a member of the pair `p` standing up from the other:
    /// its side lines are not drawn, or drawn along the other member's normal on the
    /// paper within the angle threshold (or that normal points nearly at the viewer),
    /// so that its end ellipse alone leans it
    /// ([`standing`]). Side lines drawn leaning (a tripod's legs under a camera) show
    /// the lean meant.
    fn drawn_standing(&self, p: &Proposal) -> bool {
        if p.members.len() != 2 {
            return false;
        }
        let sin = self.settings.angle_degrees.to_radians().sin();
        (0..2).any(|i| {
            let (stander, base) = (self.parts[p.members[i]], self.parts[p.members[1 - i]]);
            if !matches!(p.features[i], Some(Feature::Top | Feature::Bottom)) {
                return false;
            }
            let Some(feature) = p.features[1 - i] else {
                return false;
            };
            let Some(drawn) = stander.drawn_axis else {
                return true;
            };
            plane_of(&base, feature).is_some_and(|(_, normal)| {
                // A face seen nearly face on shows no direction for its normal on the
                // paper: the side lines cannot disagree with it.
                let n = normal.truncate();
                n.length() < MIN_PROJECTED_AXIS || drawn.perp_dot(n.normalize()).abs() <= sin
            })
        })
    }

    /// Weighs `p` between a part and the face one of its ends sits on, leaning beyond
    /// the angle threshold ([`standing`]), which holds at `fraction` of the widened
    /// thresholds ([`Self::standing_fraction`]): kept as a suggestion at most, if it is
    /// confident enough and says something new; whether it was kept.
    fn propose_standing(&mut self, p: Proposal, fraction: f64) -> bool {
        if !self.settings.enabled(p.kind) {
            return false;
        }
        let closeness = standing::closeness(fraction, self.settings).max(1.0);
        self.keep(p, closeness, true)
    }

    /// Whether the new part and `other` meet with an end on a face and one of them
    /// has ends: a part that may stand on the other ([`standing`]).
    fn stands_on(&self, other: usize) -> bool {
        self.hops[other] == Some(1)
            && self.graph.between(self.new, other) == Contact::EndOnFace
            && !(ends(&self.parts[self.new]).is_empty() && ends(&self.parts[other]).is_empty())
    }

    /// Keeps `p`, which holds to `closeness` of its thresholds, hard or as a suggestion
    /// by its confidence (a suggestion at most when `at_most_suggested`), if it says
    /// something new; whether it was kept.
    fn keep(&mut self, p: Proposal, closeness: f64, at_most_suggested: bool) -> bool {
        let evidence = self.evidence(&p, closeness);
        let confidence = confidence(&evidence, self.threshold(p.kind));
        let mode = if confidence >= self.settings.hard_confidence() && !at_most_suggested {
            if !self.enforced.add(self.parts, &p) {
                return false;
            }
            self.all.add(self.parts, &p);
            Mode::Hard
        } else if confidence >= self.settings.suggest_confidence() {
            if !self.all.add(self.parts, &p) {
                return false;
            }
            Mode::Suggested
        } else {
            return false;
        };
        self.out.push(Found {
            proposal: p,
            mode,
            inferred: Inferred {
                confidence,
                evidence,
            },
        });
        true
    }

    /// A relation between the new part's feature `a` and `other`'s feature `b`.
    fn pair(&self, kind: RelationKind, other: usize, a: Feature, b: Feature) -> Proposal {
        Proposal {
            kind,
            members: vec![self.new, other],
            features: vec![Some(a), Some(b)],
        }
    }

    /// Whether the new part and `other` may be proposed square at all: always, unless
    /// both are boxes and fewer than two pairs of their directions are square. Two
    /// boxes that meet meet face to face, and share a direction (their facing faces'
    /// normals, a block turned on another about it): four pairs of their directions are
    /// then square. One square pair alone is no joint but two boxes side by side at
    /// some angle, touching only on the paper (two objects of a scene).
    fn square_enough(&self, other: usize) -> bool {
        let (a, b) = (self.parts[self.new], self.parts[other]);
        if a.kind != PrimitiveKind::Cuboid || b.kind != PrimitiveKind::Cuboid {
            return true;
        }
        let square = directions(&a)
            .iter()
            .flat_map(|&x| directions(&b).iter().map(move |&y| (x, y)))
            .filter(|&(x, y)| self.holds(&self.pair(RelationKind::Orthogonal, other, x, y)))
            .count();
        square >= 2
    }

    /// Axes: coaxial first (it implies parallel), then parallel, then orthogonal unless
    /// some direction is parallel and only between parts that touch in the drawing (at a
    /// joint, or crossing) or repeat one another on one hub; then, for a part standing
    /// on the other's face, parallel leaning ([`standing`]).
    /// Returns whether the parts are coaxial.
    fn axes(&mut self, other: usize) -> bool {
        let (new_part, other_part) = (self.parts[self.new], self.parts[other]);
        let mut coaxial = false;
        'pairs: for &a in ends(&new_part) {
            for &b in ends(&other_part) {
                if self.propose(self.pair(RelationKind::Coaxial, other, a, b)) {
                    coaxial = true;
                    break 'pairs;
                }
            }
        }
        let mut parallel_somewhere = coaxial;
        // Parallels that hold only with the tilts moved: weighed after orthogonal, which
        // a joint drawn square in 3D wins.
        let mut on_paper = Vec::new();
        for &a in directions(&new_part) {
            for &b in directions(&other_part) {
                let p = self.pair(RelationKind::Parallel, other, a, b);
                if self.holds(&p) {
                    parallel_somewhere = true;
                    self.propose(p);
                } else {
                    on_paper.push(p);
                }
            }
        }
        let touching =
            self.hops[other] == Some(1) && self.graph.between(self.new, other) != Contact::Apart;
        // Alike parts on one hub (tubes on a ball): square is a layout, weakly.
        let on_one_hub =
            self.repeated(self.new, other) && self.graph.share_a_joint(self.new, other);
        let mut square = Vec::new();
        if !parallel_somewhere && (touching || on_one_hub) && self.square_enough(other) {
            for &a in directions(&new_part) {
                for &b in directions(&other_part) {
                    if self.propose(self.pair(RelationKind::Orthogonal, other, a, b)) {
                        square.push((a, b));
                    }
                }
            }
        }
        if square.is_empty() {
            for p in on_paper {
                parallel_somewhere |= self.propose(p);
            }
        }
        if !parallel_somewhere && self.stands_on(other) {
            // Standing up from the face, drawn leaning: the pair of directions nearest
            // each other, unless it was just found square.
            let best = directions(&new_part)
                .iter()
                .flat_map(|&a| directions(&other_part).iter().map(move |&b| (a, b)))
                .filter(|pair| !square.contains(pair))
                .filter_map(|(a, b)| {
                    let p = self.pair(RelationKind::Parallel, other, a, b);
                    self.standing_fraction(&p).map(|f| (f, p))
                })
                .min_by(|x, y| x.0.total_cmp(&y.0));
            if let Some((fraction, p)) = best {
                self.propose_standing(p, fraction);
            }
        }
        coaxial
    }

    /// Centres and radii of circles; then planes: ends on ends, ends on faces (studs on
    /// a brick) and faces on faces, tested both ways round (the test asks for the second
    /// centre inside the first outline).
    fn circles_and_planes(&mut self, other: usize, coaxial: bool) {
        let (new_part, other_part) = (self.parts[self.new], self.parts[other]);
        let hub = self.hub_between(other);
        let mut centred = Vec::new();
        for &a in circles(&new_part) {
            for &b in circles(&other_part) {
                if (a == Feature::Outline) != (b == Feature::Outline) {
                    continue; // a tube's end at a ball's centre is inside the ball
                }
                // Stacked ends face each other (outward normals opposed): each body
                // leaves the shared centre away from the other. Ends facing the same
                // way put one solid inside the other (parts drawn one behind the
                // other: not related at these ends at all), and ends facing apart by
                // less than a right angle put one through the other (a stem on the far
                // face of its base, in the mirror reading of either): not a stack,
                // though the radii may still be alike.
                let alignment = match (plane_of(&new_part, a), plane_of(&other_part, b)) {
                    (Some((_, na)), Some((_, nb))) if a != Feature::Outline => na.dot(nb),
                    _ => -1.0,
                };
                if alignment > self.settings.angle_degrees.to_radians().cos() {
                    continue;
                }
                if alignment < 0.0 {
                    let p = self.pair(RelationKind::Concentric, other, a, b);
                    if self.apart_across_a_hub(hub, other, a, b) {
                        self.propose_at_most_suggested(p);
                    } else {
                        if self.holds(&p) {
                            centred.push((a, b));
                        }
                        self.propose(p);
                    }
                }
                if a != Feature::Outline && b != Feature::Outline {
                    self.propose(self.pair(RelationKind::SameRadius, other, a, b));
                }
            }
        }
        // At most one plane per pair of parts: a leg's top drawn inside a table top's
        // outline lies, in the drawing, within both faces of the top, but it can meet
        // one only.
        let alike = self.met_by_repeated(other);
        let plane = self.meeting_planes(
            other,
            // One axis and one centre: one plane already.
            |a, b| coaxial && centred.contains(&(a, b)),
            Self::holds,
            &alike,
        );
        if let Some(p) = plane {
            // Ends apart across a part both join meet in one plane only as far as their
            // depth is the snap's guess: a suggestion at most.
            let apart = match (p.features[0], p.features[1]) {
                (Some(x), Some(y)) if p.members[0] == self.new => {
                    self.apart_across_a_hub(hub, other, x, y)
                }
                (Some(x), Some(y)) => self.apart_across_a_hub(hub, other, y, x),
                _ => false,
            };
            if apart {
                self.propose_at_most_suggested(p);
            } else {
                self.propose(p);
            }
        } else if self.stands_on(other) {
            // The end of one sitting on the other's face, drawn leaning: the two
            // facing each other (outward normals opposed), as sitting on it asks.
            let plane = self.meeting_planes(
                other,
                |_, _| false,
                |inference, p| inference.facing(p) && inference.standing_fraction(p).is_some(),
                &alike,
            );
            if let Some((p, fraction)) =
                plane.and_then(|p| self.standing_fraction(&p).map(|f| (p, f)))
            {
                self.propose_standing(p, fraction);
            }
        }
    }

    /// Whether the two flat features of `p` face each other: outward normals opposed.
    fn facing(&self, p: &Proposal) -> bool {
        let normal = |i: usize| {
            p.features[i].and_then(|f| plane_of(&self.parts[p.members[i]], f).map(|(_, n)| n))
        };
        p.members.len() == 2
            && matches!((normal(0), normal(1)), (Some(a), Some(b)) if a.dot(b) < 0.0)
    }

    /// The pairs (a plane of the new part, a plane of `other`) already in one plane
    /// for some part that repeats the new one ([`Self::repeated`]), as far as the
    /// relations kept say: the feet of the legs already under this top, the bottoms of
    /// the studs already on this brick. Repeated parts meet what they share the same
    /// way.
    fn met_by_repeated(&mut self, other: usize) -> Vec<(Feature, Feature)> {
        let (new_part, other_part) = (self.parts[self.new], self.parts[other]);
        let mut pairs = Vec::new();
        for r in 0..self.parts.len() {
            if r == self.new || r == other || !self.repeated(self.new, r) {
                continue;
            }
            for &a in planes(&new_part) {
                for &b in planes(&other_part) {
                    if self.all.coplanar.find((r, Slot::Feature(a)))
                        == self.all.coplanar.find((other, Slot::Feature(b)))
                        && !pairs.contains(&(a, b))
                    {
                        pairs.push((a, b));
                    }
                }
            }
        }
        pairs
    }

    /// The coplanar candidate between a plane `a` of the new part and a plane `b` of
    /// `other` (pairs `skip` names left out) that `test` passes, tried both ways round
    /// (the tests ask for the second centre inside the first outline): of those, the
    /// pairs parts repeating the new one already meet `other` by (`alike`, see
    /// [`Self::met_by_repeated`]) first, then the faces in contact (outward normals
    /// opposed: a leg's top under the table's underside, a stud's bottom on a brick's
    /// top), then the pair whose centres are nearer in the drawing.
    fn meeting_planes(
        &self,
        other: usize,
        skip: impl Fn(Feature, Feature) -> bool,
        test: impl Fn(&Self, &Proposal) -> bool,
        alike: &[(Feature, Feature)],
    ) -> Option<Proposal> {
        let (new_part, other_part) = (self.parts[self.new], self.parts[other]);
        let mut planar: Vec<(bool, bool, f64, Proposal)> = Vec::new();
        for &a in planes(&new_part) {
            for &b in planes(&other_part) {
                if skip(a, b) {
                    continue;
                }
                let p = self.pair(RelationKind::Coplanar, other, a, b);
                let p = if test(self, &p.clone().swapped()) {
                    p.swapped()
                } else if test(self, &p) {
                    p
                } else {
                    continue;
                };
                let (Some((ca, na)), Some((cb, nb))) =
                    (plane_of(&new_part, a), plane_of(&other_part, b))
                else {
                    continue;
                };
                planar.push((
                    alike.contains(&(a, b)),
                    na.dot(nb) < 0.0,
                    ca.distance(cb),
                    p,
                ));
            }
        }
        planar.sort_by(|x, y| y.0.cmp(&x.0).then(y.1.cmp(&x.1)).then(x.2.total_cmp(&y.2)));
        planar.into_iter().next().map(|(_, _, _, p)| p)
    }

    /// Whole solids: equal lengths, and a tube on a ball either way round.
    fn solids(&mut self, other: usize) {
        let (new, new_part, other_part) = (self.new, self.parts[self.new], self.parts[other]);
        if !ends(&new_part).is_empty() && !ends(&other_part).is_empty() {
            self.propose(Proposal {
                kind: RelationKind::EqualLength,
                members: vec![new, other],
                features: vec![None, None],
            });
        }
        for (sphere, tube) in [(other, new), (new, other)] {
            if self.parts[sphere].kind != PrimitiveKind::Sphere {
                continue;
            }
            for &end in ends(&self.parts[tube]) {
                let p = Proposal {
                    kind: RelationKind::OnSphere,
                    members: vec![sphere, tube],
                    features: vec![Some(Feature::Outline), Some(end)],
                };
                if self.propose(p) {
                    break;
                }
            }
        }
    }

    /// Collinear centres: the new part's two ends and one other circle, off any known
    /// axis.
    fn collinear(&mut self, others: &[usize]) {
        let new = self.new;
        let [a, b] = ends(&self.parts[new]) else {
            return;
        };
        for &other in others {
            if self.all.coaxial(new, other) || self.parallel_to_new(other) {
                // On a parallel part's end the line is its axis: coaxial says it; and
                // parts drawn one behind the other would line up by chance.
                continue;
            }
            for &c in circles(&self.parts[other]) {
                let p = Proposal {
                    kind: RelationKind::CollinearCenters,
                    members: vec![new, new, other],
                    features: vec![Some(*a), Some(*b), Some(c)],
                };
                if self.propose(p) {
                    break;
                }
            }
        }
    }
}

impl Proposal {
    /// The same relation between (member 1, member 0): used to build a pair with the new
    /// part second and put it first again.
    fn swapped(mut self) -> Self {
        self.members.swap(0, 1);
        self.features.swap(0, 1);
        self
    }
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec2, DVec3};

    use super::{infer, Found, Part, Proposal};
    use crate::primitive::{Axis, Bgc, Cuboid, Cylinder, Feature, FeatureCurve, Primitive};
    use crate::relation::contact::Outline;
    use crate::relation::tilt::FREE;
    use crate::relation::{InferenceSettings, Mode, RelationKind};

    /// Relations inferred placing `primitives` one by one, as on release (hard and
    /// suggested), every tilt pinned.
    fn place_all_found(primitives: &[Primitive]) -> Vec<Found> {
        place_all_tilted(primitives, &vec![[0.0; 2]; primitives.len()])
    }

    /// As [`place_all_found`], with each part's tilt slack (`bottom`, `top`).
    fn place_all_tilted(primitives: &[Primitive], tilts: &[[f64; 2]]) -> Vec<Found> {
        let drawn: Vec<Option<DVec2>> = primitives.iter().map(side_lines).collect();
        place_all_drawn(primitives, tilts, &drawn, &vec![0.0; primitives.len()])
    }

    /// The direction a cylinder's or cone's side lines run on the paper when drawn as
    /// it is.
    fn side_lines(p: &Primitive) -> Option<DVec2> {
        match p {
            Primitive::Cylinder(c) => c.axis.truncate().try_normalize(),
            Primitive::Cone(c) => c.axis.truncate().try_normalize(),
            _ => None,
        }
    }

    /// As [`place_all_tilted`], with the direction each part's side lines are drawn in
    /// and how loosely its strokes pin its length ([`Part::length_spread`]).
    fn place_all_drawn(
        primitives: &[Primitive],
        tilts: &[[f64; 2]],
        drawn: &[Option<DVec2>],
        spreads: &[f64],
    ) -> Vec<Found> {
        let features: Vec<Vec<FeatureCurve<f64>>> = primitives
            .iter()
            .map(|p| p.current_shape().features)
            .collect();
        let outlines: Vec<Outline> = primitives.iter().map(Outline::of).collect();
        let parts: Vec<Part<'_>> = primitives
            .iter()
            .zip(&features)
            .zip(&outlines)
            .zip(tilts)
            .zip(drawn)
            .zip(spreads)
            .map(|(((((p, f), o), tilt), drawn_axis), spread)| Part {
                kind: p.kind(),
                features: f,
                outline: o,
                size: p.size(),
                noise: 0.005,
                tilt: *tilt,
                drawn_axis: *drawn_axis,
                length_spread: *spread,
            })
            .collect();
        let mut found: Vec<Found> = Vec::new();
        for new in 1..parts.len() {
            let existing: Vec<(Proposal, Mode)> =
                found.iter().map(|f| (f.proposal.clone(), f.mode)).collect();
            found.extend(infer(
                &parts[..=new],
                new,
                &existing,
                &InferenceSettings::default(),
            ));
        }
        found
    }

    /// The hard relations inferred placing `primitives` one by one.
    fn place_all(primitives: &[Primitive]) -> Vec<Proposal> {
        place_all_found(primitives)
            .into_iter()
            .filter(|f| f.mode == Mode::Hard)
            .map(|f| f.proposal)
            .collect()
    }

    fn count(relations: &[Proposal], kind: RelationKind) -> usize {
        relations.iter().filter(|r| r.kind == kind).count()
    }

    const TILT: DVec3 = DVec3::new(0.0, 0.94, 0.34);

    fn cylinder(center: DVec3, length: f64, radius: f64) -> Primitive {
        Primitive::Cylinder(Cylinder {
            center,
            axis: TILT.normalize(),
            length,
            radius,
        })
    }

    /// Three legs of `length` under a round top centred at x = 40, at x = 0, 25, 80 (the
    /// top placed first).
    fn table(length: f64) -> Vec<Primitive> {
        table_with_legs([length; 3])
    }

    #[test]
    fn three_legs_give_chains_not_triangles() {
        let r = place_all(&table(60.0));
        // Top and three legs: one direction class, three relations.
        assert_eq!(count(&r, RelationKind::Parallel), 3, "{r:#?}");
        assert_eq!(count(&r, RelationKind::SameRadius), 2, "{r:#?}");
        assert_eq!(count(&r, RelationKind::EqualLength), 2, "{r:#?}");
        assert_eq!(count(&r, RelationKind::Coaxial), 0, "{r:#?}");
        assert_eq!(count(&r, RelationKind::Orthogonal), 0, "{r:#?}");
        // Each leg meets the top's underside.
        assert_eq!(count(&r, RelationKind::Coplanar), 3, "{r:#?}");
    }

    #[test]
    fn repeated_legs_are_confident_and_their_evidence_says_why() {
        let found = place_all_found(&table(60.0));
        let equal = found
            .iter()
            .find(|f| f.proposal.kind == RelationKind::EqualLength)
            .expect("equal legs");
        assert_eq!(equal.mode, Mode::Hard);
        assert!(equal.inferred.evidence.repeated, "{equal:#?}");
        assert_eq!(equal.inferred.evidence.hops, 2, "{equal:#?}");
        assert!(equal.inferred.confidence > 0.8, "{equal:#?}");
    }

    /// A table whose three legs (at x = 0, 25, 80, under a round top centred at x = 40,
    /// placed first) have the given lengths, each reaching up to the top.
    fn table_with_legs(lengths: [f64; 3]) -> Vec<Primitive> {
        let axis = TILT.normalize();
        let mut parts = vec![Primitive::Cylinder(Cylinder {
            center: DVec3::X * 40.0 + axis * 62.0,
            axis,
            length: 4.0,
            radius: 60.0,
        })];
        parts.extend(
            [0.0, 25.0, 80.0]
                .iter()
                .zip(lengths)
                .map(|(x, l)| cylinder(DVec3::X * *x + axis * (60.0 - l / 2.0), l, 3.0)),
        );
        parts
    }

    #[test]
    fn repeated_legs_sketched_a_little_apart_in_length_are_suggested_equal() {
        let equal = |lengths| {
            place_all_found(&table_with_legs(lengths))
                .into_iter()
                .filter(|f| f.proposal.kind == RelationKind::EqualLength)
                .map(|f| f.mode)
                .collect::<Vec<_>>()
        };
        // 10 % apart: repeated parts, meant alike; beyond the threshold, so the odd one
        // is suggested equal to each neighbour, the other two hard.
        let mut modes = equal([60.0, 66.0, 60.0]);
        modes.sort_by_key(|m| m.name());
        assert_eq!(modes, [Mode::Hard, Mode::Suggested, Mode::Suggested]);
        // 40 % apart: meant different.
        assert_eq!(equal([60.0, 84.0, 60.0]), [Mode::Hard]);
    }

    #[test]
    fn a_length_the_strokes_leave_open_is_still_held_equal_to_its_repeats() {
        let equal = |lengths, spreads: [f64; 4]| {
            let parts = table_with_legs(lengths);
            let drawn: Vec<Option<DVec2>> = parts.iter().map(side_lines).collect();
            place_all_drawn(&parts, &[[0.0; 2]; 4], &drawn, &spreads)
                .into_iter()
                .filter(|f| f.proposal.kind == RelationKind::EqualLength)
                .map(|f| f.mode)
                .collect::<Vec<_>>()
        };
        let open = f64::INFINITY;
        // The middle leg's length is not pinned, so its window takes any length
        // (`equal_length::informative`); 15 % longer, it still repeats its neighbours,
        // and is suggested equal to each.
        let modes = equal([60.0, 69.0, 60.0], [0.0, 0.0, open, 0.0]);
        assert_eq!(modes.len(), 3, "{modes:?}");
    }

    #[test]
    fn parts_of_different_objects_are_not_related() {
        // Two tables far apart: legs of one are parallel to legs of the other in the
        // drawing, but nothing joins them.
        let mut parts = table(60.0);
        parts.extend(
            table(60.0)
                .into_iter()
                .map(|p| p.transformed(DVec3::X * 400.0, 1.0)),
        );
        let r = place_all_found(&parts);
        assert!(
            r.iter().all(|f| f.proposal.members.iter().all(|&m| m < 4)
                || f.proposal.members.iter().all(|&m| m >= 4)),
            "{r:#?}"
        );
    }

    #[test]
    fn a_coincidental_length_is_at_most_suggested() {
        // A stem and a shade stacked end on end with lengths 2 % apart: one axis by
        // design, one length by chance.
        let axis = TILT.normalize();
        let stem = cylinder(DVec3::ZERO, 50.0, 2.0);
        let shade = Primitive::Cylinder(Cylinder {
            center: axis * 50.5,
            axis,
            length: 51.0,
            radius: 20.0,
        });
        let found = place_all_found(&[stem, shade]);
        let coaxial = found
            .iter()
            .find(|f| f.proposal.kind == RelationKind::Coaxial)
            .expect("coaxial");
        assert_eq!(coaxial.mode, Mode::Hard, "{found:#?}");
        assert!(
            found
                .iter()
                .filter(|f| f.proposal.kind == RelationKind::EqualLength)
                .all(|f| f.mode == Mode::Suggested),
            "{found:#?}"
        );
    }

    #[test]
    fn a_stack_is_coaxial_and_concentric_where_it_touches() {
        let axis = TILT.normalize();
        let stack = [
            cylinder(DVec3::ZERO, 20.0, 10.0),
            cylinder(axis * 15.0, 10.0, 6.0),
            cylinder(axis * 25.0, 10.0, 3.0),
        ];
        let r = place_all(&stack);
        assert_eq!(count(&r, RelationKind::Coaxial), 2, "{r:#?}");
        assert_eq!(count(&r, RelationKind::Parallel), 0, "{r:#?}");
        assert_eq!(count(&r, RelationKind::Concentric), 2, "{r:#?}");
        assert_eq!(count(&r, RelationKind::Coplanar), 0, "{r:#?}");
        assert_eq!(count(&r, RelationKind::CollinearCenters), 0, "{r:#?}");
        let first = r
            .iter()
            .find(|p| p.kind == RelationKind::Concentric)
            .expect("concentric");
        assert_eq!(
            first.features,
            vec![Some(Feature::Bottom), Some(Feature::Top)]
        );
    }

    #[test]
    fn a_stem_sits_on_the_face_of_its_base_it_faces_in_either_reading() {
        // A thin disc seen at a slant: both its faces project within the concentric
        // threshold of the stem's bottom. The stem's depth is a guess: in the reading
        // mirrored against the base's, its bottom faces the base's far face at less
        // than a right angle, so that face would put the stem through the disc.
        let base = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: TILT.normalize(),
            length: 2.0,
            radius: 20.0,
        });
        let near_face = TILT.normalize();
        for axis in [TILT, DVec3::new(TILT.x, TILT.y, -TILT.z)] {
            let axis = axis.normalize();
            let stem = Primitive::Cylinder(Cylinder {
                center: near_face + axis * 20.0,
                axis,
                length: 40.0,
                radius: 3.0,
            });
            let found = place_all_found(&[base.clone(), stem]);
            let centred: Vec<_> = found
                .iter()
                .filter(|f| f.proposal.kind == RelationKind::Concentric)
                .map(|f| f.proposal.features.clone())
                .collect();
            assert_eq!(
                centred,
                vec![vec![Some(Feature::Bottom), Some(Feature::Top)]],
                "stem axis {axis}: {found:#?}"
            );
        }
    }

    /// An upright stem 100 long of `radius`, centred at the origin.
    fn upright_stem(radius: f64) -> Primitive {
        Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::Y,
            length: 100.0,
            radius,
        })
    }

    #[test]
    fn arms_out_of_both_sides_of_a_stem_are_coaxial_across_it() {
        // Two arms leave the stem's sides on one line on the paper; the second leans
        // 3° in depth, within the angle threshold but beyond the drawing's noise. Two
        // contacts apart, that is a suggestion at most; on one line across the part
        // both join, it is as sure as a joint.
        let stem = upright_stem(5.0);
        let lean = 3f64.to_radians();
        let right = DVec3::new(lean.cos(), 0.0, lean.sin());
        let arms = [
            rod(DVec3::new(-25.0, 10.0, 0.0), DVec3::NEG_X, 40.0),
            rod(DVec3::new(5.0, 10.0, 0.0) + right * 20.0, right, 40.0),
        ];
        let found = place_all_found(&[stem, arms[0].clone(), arms[1].clone()]);
        let coaxial = found
            .iter()
            .find(|f| f.proposal.kind == RelationKind::Coaxial)
            .unwrap_or_else(|| panic!("no coaxial: {found:#?}"));
        assert_eq!(coaxial.proposal.members, vec![2, 1]);
        assert_eq!(coaxial.mode, Mode::Hard, "{coaxial:#?}");
        let evidence = &coaxial.inferred.evidence;
        assert!(evidence.across && evidence.hops == 2, "{evidence:#?}");
        assert!(evidence
            .describe(RelationKind::Coaxial)
            .contains("both sides"));
        // Each arm touches the stem only: nothing there is across anything.
        assert!(found
            .iter()
            .filter(|f| f.proposal.members.contains(&0))
            .all(|f| !f.inferred.evidence.across));
    }

    #[test]
    fn paired_arms_are_coaxial_across_their_stem_with_the_depth_their_ends_leave_open() {
        // The second arm leans 20° in depth, beyond the angle threshold; its small drawn
        // ends leave its tilt open by 0.5. Repeated on one line across the stem, the pair
        // is coaxial; the same arm 40 % shorter is no repeat, and only suggested.
        let stem = upright_stem(5.0);
        let lean = 20f64.to_radians();
        let right = DVec3::new(lean.cos(), 0.0, lean.sin());
        let coaxial = |length: f64| {
            let parts = [
                stem.clone(),
                rod(DVec3::new(-25.0, 10.0, 0.0), DVec3::NEG_X, 40.0),
                rod(
                    DVec3::new(5.0, 10.0, 0.0) + right * (length / 2.0),
                    right,
                    length,
                ),
            ];
            place_all_tilted(&parts, &[[0.0; 2], [0.05; 2], [0.5; 2]])
                .into_iter()
                .find(|f| f.proposal.kind == RelationKind::Coaxial)
        };
        let paired = coaxial(40.0).expect("coaxial arms");
        assert_eq!(paired.mode, Mode::Hard, "{paired:#?}");
        assert!(paired.inferred.evidence.across, "{paired:#?}");
        assert!(paired.inferred.evidence.closeness < 1.0, "{paired:#?}");
        let lone = coaxial(24.0).expect("coaxial arms");
        assert_eq!(lone.mode, Mode::Suggested, "{lone:#?}");
    }

    #[test]
    fn staggered_arms_across_a_stem_are_not_made_coaxial() {
        // Two alike arms out of the stem's sides at heights 8 apart (four arm radii), the
        // second leaning 20° in depth with its tilt open: repeated across the stem, but
        // not on one line on the paper, so not coaxial.
        let stem = upright_stem(5.0);
        let lean = 20f64.to_radians();
        let right = DVec3::new(lean.cos(), 0.0, lean.sin());
        let parts = [
            stem,
            rod(DVec3::new(-25.0, 10.0, 0.0), DVec3::NEG_X, 40.0),
            rod(DVec3::new(5.0, 18.0, 0.0) + right * 20.0, right, 40.0),
        ];
        let found = place_all_tilted(&parts, &[[0.0; 2], [0.05; 2], [0.5; 2]]);
        assert!(
            found
                .iter()
                .all(|f| f.proposal.kind != RelationKind::Coaxial),
            "{found:#?}"
        );
    }

    #[test]
    fn arms_out_of_a_stems_two_sides_do_not_share_a_centre_but_arms_through_it_do() {
        // A thin stem (radius 0.1) with an arm of radius 2 out of each side: their inner
        // ends lie on the stem's two sides, 0.2 apart, near enough for one centre at
        // these radii, but the stem lies between them: at most a suggestion. Arms
        // through the stem meet at its axis.
        let stem = upright_stem(0.1);
        let modes = |inner: f64| {
            let parts = [
                stem.clone(),
                rod(DVec3::new(-inner - 20.0, 10.0, 0.0), DVec3::NEG_X, 40.0),
                rod(DVec3::new(inner + 20.0, 10.0, 0.0), DVec3::X, 40.0),
            ];
            place_all_found(&parts)
                .into_iter()
                .filter(|f| {
                    f.proposal.members.contains(&1)
                        && f.proposal.members.contains(&2)
                        && matches!(
                            f.proposal.kind,
                            RelationKind::Concentric | RelationKind::Coplanar
                        )
                })
                .map(|f| (f.proposal.kind, f.mode))
                .collect::<Vec<_>>()
        };
        let out_of_sides = modes(0.1);
        assert!(
            out_of_sides.iter().all(|(_, mode)| *mode != Mode::Hard),
            "{out_of_sides:?}"
        );
        let through = modes(0.0);
        assert!(
            through.contains(&(RelationKind::Concentric, Mode::Hard)),
            "{through:?}"
        );
    }

    /// A menorah's stem with an arm out of each side at different heights, of different
    /// lengths (so not repeated), with radii `left` and `right`.
    fn stem_with_arms(left: f64, right: f64) -> Vec<Primitive> {
        let arm = |center: DVec3, axis: DVec3, length: f64, radius: f64| {
            Primitive::Cylinder(Cylinder {
                center,
                axis,
                length,
                radius,
            })
        };
        vec![
            upright_stem(5.0),
            arm(DVec3::new(-25.0, -20.0, 0.0), DVec3::NEG_X, 40.0, left),
            arm(DVec3::new(17.5, 25.0, 0.0), DVec3::X, 25.0, right),
        ]
    }

    #[test]
    fn branches_of_one_stem_drawn_of_one_radius_are_of_one_radius() {
        let same_radius = |found: &[Found]| {
            found
                .iter()
                .find(|f| f.proposal.kind == RelationKind::SameRadius)
                .cloned()
        };
        let found = place_all_found(&stem_with_arms(3.0, 3.0));
        let equal = same_radius(&found).unwrap_or_else(|| panic!("none: {found:#?}"));
        assert_eq!(equal.mode, Mode::Hard, "{equal:#?}");
        let evidence = &equal.inferred.evidence;
        assert!(evidence.branches && !evidence.repeated, "{evidence:#?}");
        assert!(evidence
            .describe(RelationKind::SameRadius)
            .contains("branches of one part"));
        // 4 % apart: inside the threshold, beyond the drawing's noise: a suggestion.
        let found = place_all_found(&stem_with_arms(3.0, 3.12));
        let near = same_radius(&found).unwrap_or_else(|| panic!("none: {found:#?}"));
        assert_eq!(near.mode, Mode::Suggested, "{near:#?}");
        // The stem is joined to each arm, so it is no branch of anything.
        assert!(found
            .iter()
            .filter(|f| f.proposal.members.contains(&0))
            .all(|f| !f.inferred.evidence.branches));
    }

    fn rod(center: DVec3, axis: DVec3, length: f64) -> Primitive {
        Primitive::Cylinder(Cylinder {
            center,
            axis: axis.normalize(),
            length,
            radius: 2.0,
        })
    }

    #[test]
    fn only_joined_rods_are_orthogonal() {
        // Two tubes leaving a ball of radius 5 at right angles: their outlines meet near
        // the ball, but their ends are 7 units apart, neither on the other's body.
        let (x, y) = (DVec3::X, DVec3::Y);
        let tubes = [rod(x * 20.0, x, 30.0), rod(y * 20.0, y, 30.0)];
        let r = place_all(&tubes);
        assert_eq!(count(&r, RelationKind::Orthogonal), 0, "{r:#?}");
        // A T: the second rod's end lies on the first one's side.
        let tee = [rod(DVec3::ZERO, x, 60.0), rod(y * 16.0, y, 30.0)];
        let r = place_all(&tee);
        assert_eq!(count(&r, RelationKind::Orthogonal), 1, "{r:#?}");
    }

    #[test]
    fn two_pairs_of_parallel_edges_fix_a_boxs_turn() {
        let view = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.6);
        let brick = |y: f64| {
            Primitive::Cuboid(Cuboid {
                center: view * DVec3::new(0.0, y, 0.0),
                rotation: view,
                size: DVec3::new(80.0, 20.0, 40.0),
            })
        };
        let r = place_all(&[brick(0.0), brick(20.0)]);
        assert_eq!(count(&r, RelationKind::Parallel), 2, "{r:#?}");
    }

    /// A brick seen at a slant and a block against its +X end on the paper, turned by
    /// `turn` in the brick's frame.
    fn brick_and_block(turn: DQuat) -> [Primitive; 2] {
        let view = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.6);
        [
            brick_seen(view),
            Primitive::Cuboid(Cuboid {
                center: view * DVec3::new(62.0, 0.0, 0.0),
                rotation: view * turn,
                size: DVec3::new(40.0, 30.0, 24.0),
            }),
        ]
    }

    /// The orthogonals inferred between [`brick_and_block`] with the block turned
    /// `x_deg` about X, then `y_deg` about Y.
    fn squares_of_block_turned(x_deg: f64, y_deg: f64) -> usize {
        let turn =
            DQuat::from_rotation_y(y_deg.to_radians()) * DQuat::from_rotation_x(x_deg.to_radians());
        place_all_found(&brick_and_block(turn))
            .iter()
            .filter(|f| f.proposal.kind == RelationKind::Orthogonal)
            .count()
    }

    #[test]
    fn boxes_side_by_side_with_one_square_pair_of_directions_are_not_made_square() {
        // Turned 40° about X, then 35° about Y: the brick's Y is square to the block's
        // X exactly, and no other pair is square or parallel. Boxes joined face to face
        // share a direction; these touch only on the paper.
        assert_eq!(squares_of_block_turned(40.0, 35.0), 0);
    }

    #[test]
    fn boxes_turned_a_little_on_each_other_are_still_square() {
        // Turned 12° about X, then 12° about Y: no direction within the angle threshold
        // of parallel, but two pairs square, as a block drawn a little off its brick's
        // face: square relations may still align them.
        assert!(squares_of_block_turned(12.0, 12.0) > 0);
    }

    #[test]
    fn a_stud_sits_on_the_brick_and_stands_up_from_it() {
        let view = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.6);
        let r = place_all(&[brick_seen(view), upright_stud(view, 25.0, 10.0)]);
        assert_eq!(count(&r, RelationKind::Parallel), 1, "{r:#?}");
        assert_eq!(count(&r, RelationKind::Orthogonal), 0, "{r:#?}");
        let on = r
            .iter()
            .find(|p| p.kind == RelationKind::Coplanar)
            .expect("coplanar");
        assert_eq!(on.members, vec![0, 1]);
        assert_eq!(
            on.features,
            vec![Some(Feature::face(Axis::Y, true)), Some(Feature::Bottom)]
        );
    }

    #[test]
    fn repeated_studs_sit_on_the_brick_the_same_way() {
        // Seen steeply from above: the second stud's top is drawn right over the
        // centre of the brick's underside, nearer on the paper than its bottom is to the
        // top face's centre; facing each other, both pairs would hold. The first stud
        // sits on the top face; the second, repeating it, does the same.
        let view = DQuat::from_rotation_x(1.0) * DQuat::from_rotation_y(0.3);
        let r = place_all(&[
            brick_seen(view),
            upright_stud(view, 25.0, 10.0),
            upright_stud(view, -4.9, 15.9),
        ]);
        for s in [1, 2] {
            let on = r
                .iter()
                .find(|p| p.kind == RelationKind::Coplanar && p.members == vec![0, s])
                .unwrap_or_else(|| panic!("stud {s} on the brick: {r:#?}"));
            assert_eq!(
                on.features,
                vec![Some(Feature::face(Axis::Y, true)), Some(Feature::Bottom)],
                "stud {s}"
            );
        }
    }

    /// An 80 × 20 × 40 brick centred at the origin, turned by `view`.
    fn brick_seen(view: DQuat) -> Primitive {
        Primitive::Cuboid(Cuboid {
            center: DVec3::ZERO,
            rotation: view,
            size: DVec3::new(80.0, 20.0, 40.0),
        })
    }

    /// A stud standing upright on the top face of [`brick_seen`]`(view)`, at (x, z) in
    /// the brick's frame.
    fn upright_stud(view: DQuat, x: f64, z: f64) -> Primitive {
        let up = view * DVec3::Y;
        Primitive::Cylinder(Cylinder {
            center: up * 13.0 + view * DVec3::new(x, 0.0, z),
            axis: up,
            length: 6.0,
            radius: 5.0,
        })
    }

    /// A brick seen from above at a slant, and a stud on its top face leaning `lean`
    /// (radians) off the face's normal towards the brick's side.
    fn brick_and_leaning_stud(lean: f64) -> [Primitive; 2] {
        let view = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.6);
        let up = view * DVec3::Y;
        let axis = view * DVec3::new(lean.sin(), lean.cos(), 0.0);
        let brick = brick_seen(view);
        let bottom = up * 10.0 + view * DVec3::new(25.0, 0.0, 10.0);
        let stud = Primitive::Cylinder(Cylinder {
            center: bottom + axis * 3.0,
            axis,
            length: 6.0,
            radius: 5.0,
        });
        [brick, stud]
    }

    /// Places the brick and a stud leaning `lean` (radians) whose side lines are drawn
    /// upright on the brick (`upright`) or as the stud leans.
    fn place_stud(lean: f64, upright: bool) -> Vec<Found> {
        let parts = brick_and_leaning_stud(lean);
        let up = DQuat::from_rotation_x(0.5) * DQuat::from_rotation_y(0.6) * DVec3::Y;
        let sides = if upright {
            up.truncate().try_normalize()
        } else {
            side_lines(&parts[1])
        };
        place_all_drawn(&parts, &[[0.0; 2]; 2], &[None, sides], &[0.0; 2])
    }

    #[test]
    fn a_stud_drawn_leaning_on_the_brick_is_suggested_upright_on_it() {
        let found = place_stud(25f64.to_radians(), true);
        let of = |kind| found.iter().find(|f| f.proposal.kind == kind);
        let upright = of(RelationKind::Parallel).expect("parallel suggested");
        assert_eq!(upright.mode, Mode::Suggested, "{found:#?}");
        assert_eq!(
            upright.proposal.features[0..2],
            [Some(Feature::Top), Some(Feature::face(Axis::Y, true))]
        );
        assert!(upright.inferred.evidence.closeness > 1.0, "{upright:#?}");
        assert!(upright
            .inferred
            .evidence
            .describe(RelationKind::Parallel)
            .contains("leans"));
        let on = of(RelationKind::Coplanar).expect("coplanar suggested");
        assert_eq!(on.mode, Mode::Suggested, "{found:#?}");
        assert!(on.proposal.features.contains(&Some(Feature::Bottom)));
        assert!(on
            .proposal
            .features
            .contains(&Some(Feature::face(Axis::Y, true))));
        // Side lines drawn leaning as its end: meant leaning (a tripod's legs).
        let leaning = place_stud(25f64.to_radians(), false);
        assert!(
            leaning.iter().all(|f| !matches!(
                f.proposal.kind,
                RelationKind::Parallel | RelationKind::Coplanar
            )),
            "{leaning:#?}"
        );
        // Within the threshold it is hard, as before.
        let straight = place_all_found(&brick_and_leaning_stud(3f64.to_radians()));
        assert!(straight
            .iter()
            .any(|f| f.proposal.kind == RelationKind::Parallel && f.mode == Mode::Hard));
    }

    #[test]
    fn a_part_lying_on_the_face_is_not_suggested_upright() {
        let found = place_stud(60f64.to_radians(), true);
        assert!(
            found.iter().all(|f| !(matches!(
                f.proposal.kind,
                RelationKind::Parallel | RelationKind::Coplanar
            ) && f
                .proposal
                .features
                .contains(&Some(Feature::face(Axis::Y, true))))),
            "{found:#?}"
        );
    }

    #[test]
    fn tubes_square_on_one_ball_are_suggested_orthogonal() {
        let ball = Primitive::Sphere(crate::primitive::Sphere {
            center: DVec3::ZERO,
            radius: 20.0,
        });
        let tube = |axis: DVec3| {
            let axis = axis.normalize();
            Primitive::Cylinder(Cylinder {
                center: axis * 35.0,
                axis,
                length: 30.0,
                radius: 6.0,
            })
        };
        let found = place_all_found(&[
            ball,
            tube(DVec3::new(1.0, 0.0, 0.3)),
            tube(DVec3::new(0.0, 1.0, 0.0)),
        ]);
        let square = found
            .iter()
            .find(|f| f.proposal.kind == RelationKind::Orthogonal)
            .expect("orthogonal suggested");
        assert_eq!(square.mode, Mode::Suggested, "{found:#?}");
        assert!(square.inferred.evidence.repeated);
        assert_eq!(square.inferred.evidence.hops, 2);
        // At another angle (a star of five): nothing.
        let found = place_all_found(&[
            Primitive::Sphere(crate::primitive::Sphere {
                center: DVec3::ZERO,
                radius: 20.0,
            }),
            tube(DVec3::new(1.0, 0.0, 0.0)),
            tube(DVec3::new(0.31, 0.95, 0.0)),
        ]);
        assert!(
            found
                .iter()
                .all(|f| f.proposal.kind != RelationKind::Orthogonal),
            "{found:#?}"
        );
    }

    #[test]
    fn alike_parts_are_related_a_few_joints_further_than_others() {
        // A stack along one axis: a small cup, a long rod, a wide disc, a long rod, and
        // a second small cup four joints from the first. Nothing between the cups is
        // alike them; the cups are alike.
        let axis = TILT.normalize();
        let mut parts = Vec::new();
        let mut at = 0.0;
        for (length, radius) in [
            (20.0, 10.0),
            (120.0, 3.0),
            (8.0, 30.0),
            (110.0, 3.5),
            (20.5, 10.2),
        ] {
            parts.push(Primitive::Cylinder(Cylinder {
                center: axis * (at + length / 2.0),
                axis,
                length,
                radius,
            }));
            at += length;
        }
        let found = place_all_found(&parts);
        let cups: Vec<&Found> = found
            .iter()
            .filter(|f| f.proposal.members.contains(&0) && f.proposal.members.contains(&4))
            .collect();
        assert!(
            cups.iter()
                .any(|f| f.proposal.kind == RelationKind::EqualLength),
            "{found:#?}"
        );
        assert!(
            cups.iter().all(|f| f.inferred.evidence.repeated),
            "{cups:#?}"
        );
    }

    #[test]
    fn the_feet_of_repeated_legs_are_suggested_level() {
        let found = place_all_found(&table(60.0));
        let level: Vec<&Found> = found
            .iter()
            .filter(|f| {
                f.proposal.kind == RelationKind::Coplanar && !f.proposal.members.contains(&0)
            })
            .collect();
        assert!(!level.is_empty(), "{found:#?}");
        for f in &level {
            assert_eq!(
                f.proposal.features,
                vec![Some(Feature::Bottom); 2],
                "{f:#?}"
            );
            assert_eq!(
                f.mode,
                Mode::Suggested,
                "side by side is not enforced unasked"
            );
            assert!(f.inferred.evidence.repeated);
        }
        // The legs' tops meet the table top already: their planes are known.
        assert_eq!(level.len(), 2, "a chain over three legs: {level:#?}");
    }

    /// The axis leaning `lean` (radians) off the paper's up direction towards the viewer.
    fn up(lean: f64) -> DVec3 {
        DVec3::new(0.0, lean.cos(), lean.sin())
    }

    #[test]
    fn an_axis_whose_depth_the_drawing_leaves_open_is_suggested_coaxial() {
        // Stacked on the paper, 40° apart in depth: the upper part's ends are not drawn
        // (its tilt is free), so the drawing does not say they differ.
        let (a, b) = (up(0.5), up(-0.2));
        let lower = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: a,
            length: 40.0,
            radius: 8.0,
        });
        let upper = Primitive::Cylinder(Cylinder {
            center: a * 20.0 + b * 30.0,
            axis: b,
            length: 60.0,
            radius: 4.0,
        });
        let coaxial = |found: &[Found]| {
            found
                .iter()
                .find(|f| f.proposal.kind == RelationKind::Coaxial)
                .map(|f| f.mode)
        };
        let pinned = place_all_tilted(&[lower.clone(), upper.clone()], &[[0.0; 2]; 2]);
        assert_eq!(coaxial(&pinned), None, "{pinned:#?}");
        let open = place_all_tilted(&[lower, upper], &[[0.0; 2], [FREE; 2]]);
        assert_eq!(coaxial(&open), Some(Mode::Suggested), "{open:#?}");
    }

    #[test]
    fn a_tee_whose_depth_its_ends_leave_open_is_suggested_square() {
        // A main pipe leaning in depth, and a branch whose end sits on its side, drawn
        // square to it on the paper's terms (the drawn branch is the square one with its
        // depth moved: 20° off square in 3D).
        let main_axis = DVec3::new(1.0, 0.0, 0.6).normalize();
        let square = DVec3::new(-0.3, 1.0, 0.5).normalize();
        assert!(main_axis.dot(square).abs() < 1e-12);
        let drawn = DVec3::new(-0.3, 1.0, -0.2).normalize();
        let main = rod(DVec3::ZERO, main_axis, 60.0);
        let branch = |at: DVec3| rod(at + drawn * 15.0, drawn, 30.0);
        let orthogonal = |found: &[Found]| {
            found
                .iter()
                .find(|f| f.proposal.kind == RelationKind::Orthogonal)
                .map(|f| f.mode)
        };
        let tee = [main.clone(), branch(DVec3::Y)];
        // Tilts pinned by their ends: 20° is no square joint.
        let pinned = place_all_tilted(&tee, &[[0.0; 2]; 2]);
        assert_eq!(orthogonal(&pinned), None, "{pinned:#?}");
        // The branch's small ends pin its depth only loosely: square is suggested.
        let loose = place_all_tilted(&tee, &[[0.0; 2], [0.7; 2]]);
        assert_eq!(orthogonal(&loose), Some(Mode::Suggested), "{loose:#?}");
        // No ends drawn: any two directions could be made square; nothing is said.
        let open = place_all_tilted(&tee, &[[0.0; 2], [FREE; 2]]);
        assert_eq!(orthogonal(&open), None, "{open:#?}");
        // Beside the main pipe, not on it: no joint, no square.
        let apart = [main, branch(DVec3::new(0.0, 12.0, 0.0))];
        let apart = place_all_tilted(&apart, &[[0.0; 2], [0.7; 2]]);
        assert_eq!(orthogonal(&apart), None, "{apart:#?}");
    }

    #[test]
    fn a_bent_tubes_end_is_coaxial_with_the_part_it_runs_into() {
        // A quarter arc in the paper's plane ending downwards, and a cup under it.
        let spine: Vec<DVec3> = (0..8)
            .map(|k| {
                let t = std::f64::consts::FRAC_PI_2 * (1.0 - f64::from(k) / 7.0);
                DVec3::new(50.0 - 50.0 * t.cos(), 50.0 * t.sin(), 0.0)
            })
            .collect();
        let end = spine[7];
        let tube = Primitive::Bgc(Bgc {
            spine,
            radii: vec![4.0; 8],
            plane_normal: DVec3::Z,
        });
        let cup = Primitive::Cylinder(Cylinder {
            center: end - DVec3::new(0.0, 10.0, 0.0),
            axis: DVec3::new(0.0, 1.0, 0.0),
            length: 20.0,
            radius: 6.0,
        });
        let found = place_all_found(&[tube, cup]);
        let coaxial = found
            .iter()
            .find(|f| f.proposal.kind == RelationKind::Coaxial)
            .unwrap_or_else(|| panic!("no coaxial: {found:#?}"));
        assert_eq!(coaxial.mode, Mode::Hard, "{coaxial:#?}");
        assert!(
            coaxial.proposal.features.contains(&Some(Feature::Top)),
            "the tube's end at the cup: {coaxial:#?}"
        );
    }
}
