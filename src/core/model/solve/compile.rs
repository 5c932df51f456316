//! The global problem of a set of parts and relations: each part in its own frame, its
//! features mapped into the common frame, relations and dimensions as constraints.

use std::collections::BTreeSet;

use glam::DVec3;

use super::conflicts::describe;
use super::{Document, GlobalSettings, PrimitiveId, Quantity, Relation};
use crate::core::ad::{Expr, Graph, Vec3};
use crate::core::primitive::{FeatureCurve, FeatureGeometry, Primitive};
use crate::core::relation::{residuals, Member, Mode};
use crate::core::snap::{fit_terms, Assignment, Frame};
use crate::core::solve::Problem;

/// Weight of a part without strokes (loaded without its sketch) on staying where it is,
/// per squared parameter change in its frame.
pub(super) const ANCHOR_WEIGHT: f64 = 1.0;

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
    pub(super) frame: Frame,
    pub(super) local: Primitive,
    /// Its variables' range in the solve's x (empty when held).
    pub(super) start: usize,
    pub(super) len: usize,
    /// Whether it is held where it is (beyond the reach of the change).
    pub(super) held: bool,
    /// Its dimensions (quantity, value in model space), held exactly.
    pub(super) dimensions: Vec<(Quantity, f64)>,
}

/// The compiled problem of a set of parts and relations, with where each relation's
/// equations are.
pub(super) struct Compiled {
    pub(super) problem: Problem,
    /// (relation index, range of its equalities among the problem's equalities).
    pub(super) hard: Vec<(usize, std::ops::Range<usize>)>,
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
        name: f.name,
        geometry,
    }
}

/// The equalities holding a free part's dimensions, in its frame: sizes map by 1/s.
pub(super) fn dimension_equalities<'g>(
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
pub(super) fn compile(
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
                    feature: relation.features.get(k).and_then(|f| f.as_deref()),
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

impl Document {
    /// The parts of a solve of `ids`, with their frames and variable ranges.
    pub(super) fn parts(
        &self,
        ids: &BTreeSet<PrimitiveId>,
        held: &BTreeSet<PrimitiveId>,
    ) -> Vec<Part<'_>> {
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
}
