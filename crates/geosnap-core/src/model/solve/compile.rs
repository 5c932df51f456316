//! The global problem of a set of parts and relations: each part in its own frame, its
//! features mapped into the common frame, relations and dimensions as constraints.

use std::collections::BTreeSet;
use std::ops::Range;

use glam::DVec3;

use super::conflicts::describe;
use super::{Document, GlobalSettings, PrimitiveId, Quantity, Related, RelationKey};
use crate::ad::{Expr, Graph, Vec3};
use crate::primitive::{FeatureCurve, FeatureGeometry, Primitive};
use crate::relation::{residuals, Member, Mode};
use crate::snap::{fit_terms, Assignment, Frame, Profile};
use crate::solve::Problem;

/// Weight of a part without strokes (loaded without its sketch) on staying where it is,
/// per squared parameter change in its frame.
pub(super) const ANCHOR_WEIGHT: f64 = 1.0;

/// Weight of a fitted part on staying where the solve found it, per squared parameter
/// change in its frame (a proximal term).
///
/// Strokes do not always determine every parameter: a leg whose ends are hidden shows
/// its outline, which fixes its projected length but not how far it tilts out of the
/// view, and without this term the solve drifts along that valley, lengthening the part
/// as it turns it end-on. The weight is small against the fit: moving a parameter by
/// 5 % of the part's size costs what a 0.05 % error of one curve's fit does (φ_p is
/// about the squared error in the frame), so relations and strokes still decide
/// wherever they can.
pub(super) const PROXIMAL_WEIGHT: f64 = 1e-4;

/// Samples per stroke and curve the global solve fits (evenly thinned from the snap's
/// up to 32). φ_p averages over samples, so thinning keeps its minimum where it was
/// while each evaluation gets cheaper; the reported fits use every sample.
pub(super) const SOLVE_SAMPLES: usize = 12;

/// The assignment with each stroke's samples evenly thinned to at most `n` (end points
/// kept, as the outline ends are pulled to the extreme samples).
pub(super) fn thinned(assignment: &Assignment, n: usize) -> Assignment {
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

/// One part of a solve: the primitive, its strokes and its snap's RMS.
pub(super) struct Part<'d> {
    pub(super) id: PrimitiveId,
    pub(super) primitive: &'d Primitive,
    pub(super) assignment: Option<&'d Assignment>,
    pub(super) own_rms: Option<f64>,
    /// How its snap held a bent tube's radii (see [`crate::snap::Profile`]).
    pub(super) profile: Profile,
    pub(super) frame: Frame,
    pub(super) local: Primitive,
    /// Whether it is held where it is (beyond the reach of the change).
    pub(super) held: bool,
    /// Its dimensions (quantity, value in model space), held exactly.
    pub(super) dimensions: Vec<(Quantity, f64)>,
}

/// What a group of constraints of the global problem stands for: a part's own
/// constraints (those of its shape), a dimension the user typed, or a hard relation.
/// Warm-start multipliers are stored under it, whatever the constraints' labels say.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum GroupKey {
    /// The constraints of the part's shape.
    Part(PrimitiveId),
    /// A dimension of the part, held exactly.
    Dimension(PrimitiveId, Quantity),
    /// The residuals of a hard relation.
    Relation(RelationKey),
}

/// A group of constraints: what it stands for and where its constraints are among the
/// problem's equalities and inequalities.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Group {
    pub(super) key: GroupKey,
    pub(super) equalities: Range<usize>,
    pub(super) inequalities: Range<usize>,
}

/// The compiled problem of a set of parts and relations, with the groups its
/// constraints form and where each part's variables are.
pub(super) struct Compiled {
    pub(super) problem: Problem,
    /// The groups, in the order their constraints were added.
    pub(super) groups: Vec<Group>,
    /// Each part's variables among the problem's (in the order of the parts; empty when
    /// held).
    pub(super) variables: Vec<Range<usize>>,
}

impl Compiled {
    /// The hard relations with the range of their equalities.
    pub(super) fn hard_relations(&self) -> Vec<(RelationKey, Range<usize>)> {
        self.groups
            .iter()
            .filter_map(|g| match g.key {
                GroupKey::Relation(id) => Some((id, g.equalities.clone())),
                GroupKey::Part(_) | GroupKey::Dimension(..) => None,
            })
            .collect()
    }
}

/// The terms of the global problem as they are gathered: the objective's terms, and
/// the constraints, labelled and in groups.
struct Terms<'g> {
    objective: Vec<Expr<'g>>,
    equalities: Vec<(String, Expr<'g>)>,
    inequalities: Vec<(String, Expr<'g>)>,
    groups: Vec<Group>,
}

impl<'g> Terms<'g> {
    /// Adds a group of constraints under `key`.
    fn group(
        &mut self,
        key: GroupKey,
        equalities: impl IntoIterator<Item = (String, Expr<'g>)>,
        inequalities: impl IntoIterator<Item = (String, Expr<'g>)>,
    ) {
        let (e, i) = (self.equalities.len(), self.inequalities.len());
        self.equalities.extend(equalities);
        self.inequalities.extend(inequalities);
        self.groups.push(Group {
            key,
            equalities: e..self.equalities.len(),
            inequalities: i..self.inequalities.len(),
        });
    }
}

/// A feature mapped from a part's frame into the common frame (see the module docs).
pub(super) fn to_common<'g>(
    f: &FeatureCurve<Expr<'g>>,
    scale: f64,
    offset: DVec3,
) -> FeatureCurve<Expr<'g>> {
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
            normal: normal.normalize(),
            radius: *radius * scale,
        },
        FeatureGeometry::Rectangle {
            center,
            normal,
            half_extents,
        } => FeatureGeometry::Rectangle {
            center: point(*center),
            normal: normal.normalize(),
            half_extents: half_extents.map(|(axis, h)| (axis, h * scale)),
        },
    };
    FeatureCurve {
        feature: f.feature,
        geometry,
    }
}

/// The equalities holding a free part's dimensions, in its frame (sizes map by 1/s),
/// each with its quantity.
fn dimension_equalities<'g>(
    part: &Part<'_>,
    name: &str,
    x: &[Expr<'g>],
) -> Vec<(Quantity, String, Expr<'g>)> {
    part.dimensions
        .iter()
        .filter_map(|(quantity, target)| {
            let v = quantity
                .param_index(part.primitive.kind())
                .and_then(|i| x.get(i))?;
            Some((
                *quantity,
                format!("{name}: {quantity} = {target}"),
                *v - *target / part.frame.scale,
            ))
        })
        .collect()
}

/// The common frame of `parts`: their mean centre O and median size S.
fn common_frame(parts: &[Part<'_>]) -> (DVec3, f64) {
    let origin = parts.iter().map(|p| p.frame.origin).sum::<DVec3>() / parts.len() as f64;
    let mut sizes: Vec<f64> = parts.iter().map(|p| p.frame.scale).collect();
    sizes.sort_by(f64::total_cmp);
    (origin, sizes[sizes.len() / 2])
}

/// Adds `part`'s terms (its fit or anchor, its shape's constraints and its dimensions,
/// unless held) and returns its features in the common frame, with its variables.
fn part_terms<'g>(
    g: &'g Graph,
    part: &Part<'_>,
    (origin, unit): (DVec3, f64),
    terms: &mut Terms<'g>,
) -> (Vec<FeatureCurve<Expr<'g>>>, Range<usize>) {
    let scale = part.frame.scale / unit;
    let offset = (part.frame.origin - origin) / unit;
    let now = part.local.params();
    if part.held {
        // Held where it is: its features are constants.
        let x: Vec<Expr<'_>> = now.iter().map(|v| g.constant(*v)).collect();
        let shape = part.local.shape(&x);
        let features = shape
            .features
            .iter()
            .map(|f| to_common(f, scale, offset))
            .collect();
        return (features, 0..0);
    }
    let first = g.var_count();
    let x = g.vars(now.len());
    let name = format!("{} {}", part.primitive.kind().name(), part.id.0);
    // The squared distance from where the part stands.
    let moved = g.sum(x.iter().zip(&now).map(|(v, n)| (*v - *n).square()));
    let (value, eqs, ineqs, feats) = if let Some(assignment) = part.assignment {
        let assignment = thinned(assignment, SOLVE_SAMPLES);
        let t = fit_terms(g, &x, &part.local, &assignment, &part.frame, part.profile);
        let value = t.objective + moved * PROXIMAL_WEIGHT;
        (value, t.equalities, t.inequalities, t.features)
    } else {
        let shape = part.local.shape(&x);
        let (eqs, ineqs) = (shape.equalities, shape.inequalities);
        (moved * ANCHOR_WEIGHT, eqs, ineqs, shape.features)
    };
    terms.objective.push(value);
    let label = |(l, e): (&str, Expr<'g>)| (format!("{name}: {l}"), e);
    terms.group(
        GroupKey::Part(part.id),
        eqs.into_iter().map(label),
        ineqs.into_iter().map(label),
    );
    for (quantity, label, e) in dimension_equalities(part, &name, &x) {
        terms.group(GroupKey::Dimension(part.id, quantity), [(label, e)], []);
    }
    let features = feats.iter().map(|f| to_common(f, scale, offset)).collect();
    (features, first..g.var_count())
}

/// Adds the `relations`' terms: a group of equalities per hard relation, a weighted
/// square per soft residual (returned, to end the objective).
fn relation_terms<'g>(
    parts: &[Part<'_>],
    features: &[Vec<FeatureCurve<Expr<'g>>>],
    relations: &[Related<'_>],
    settings: &GlobalSettings,
    terms: &mut Terms<'g>,
) -> Vec<Expr<'g>> {
    let mut soft = Vec::new();
    for related in relations {
        let relation = related.relation;
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
                let label = describe(related.position, relation);
                let eqs = psi.into_iter().map(|e| (label.clone(), e));
                terms.group(GroupKey::Relation(related.id), eqs, []);
            }
            Mode::Soft => soft.extend(psi.into_iter().map(|e| e.square() * settings.soft_weight())),
            Mode::Off | Mode::Suggested => {}
        }
    }
    soft
}

/// Builds the global problem of `parts` with the `relations` whose members are all
/// among them.
pub(super) fn compile(
    parts: &[Part<'_>],
    relations: &[Related<'_>],
    settings: &GlobalSettings,
) -> Compiled {
    let g = Graph::new();
    let common = common_frame(parts);
    let mut terms = Terms {
        objective: Vec::new(),
        equalities: Vec::new(),
        inequalities: Vec::new(),
        groups: Vec::new(),
    };
    let mut features = Vec::with_capacity(parts.len());
    let mut variables = Vec::with_capacity(parts.len());
    for part in parts {
        let (feats, vars) = part_terms(&g, part, common, &mut terms);
        features.push(feats);
        variables.push(vars);
    }
    let soft = relation_terms(parts, &features, relations, settings, &mut terms);
    terms.objective.extend(soft);
    let total = g.sum(terms.objective);
    let mut builder = Problem::builder(&g, total);
    for (label, e) in terms.equalities {
        builder = builder.equality(label, e);
    }
    for (label, e) in terms.inequalities {
        builder = builder.inequality(label, e);
    }
    Compiled {
        problem: builder.build(),
        groups: terms.groups,
        variables,
    }
}

impl Document {
    /// The parts of a solve of `ids`, with their frames.
    pub(super) fn parts(
        &self,
        ids: &BTreeSet<PrimitiveId>,
        held: &BTreeSet<PrimitiveId>,
    ) -> Vec<Part<'_>> {
        let mut parts = Vec::with_capacity(ids.len());
        for id in ids {
            let Some(placed) = self.primitives.get(id) else {
                continue;
            };
            let record = self.snaps.get(id);
            let frame = Frame::of(&placed.primitive);
            let local = frame.into_frame(&placed.primitive);
            let is_held = held.contains(id);
            parts.push(Part {
                id: *id,
                primitive: &placed.primitive,
                assignment: record.map(|r| &r.assignment),
                own_rms: record.map(|r| r.rms),
                profile: record.map_or(Profile::Smooth, |r| r.profile),
                frame,
                local,
                held: is_held,
                dimensions: self
                    .dimensions_of(*id)
                    .map(|d| (d.quantity, d.value))
                    .collect(),
            });
        }
        parts
    }
}
