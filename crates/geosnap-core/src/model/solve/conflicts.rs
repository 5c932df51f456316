//! Finding the relations responsible for a broken solve, and naming them.
//!
//! **Contradictions in one pass** ([`contradictions`]). When the hard relations cannot
//! all hold, the solve ends with constraints it could not meet. At that point the
//! constraint Jacobian shows which: the constraints are taken in order of precedence
//! (each part's own shape and the user's dimensions first, then the relations from
//! oldest to newest), and each relation's rows are reduced against the span of the
//! rows before it (Gram–Schmidt, as a rank-revealing QR with the columns in that
//! order). A relation whose residual has a part that no move outside that span can
//! reduce contradicts the relations before it, to first order: every such relation is
//! named at once, and the solve runs once more, not once per culprit. A relation whose
//! rows lie wholly in the span and whose residual is met is redundant: it says again
//! what the others say, and is kept.
//!
//! **A fit made much worse** ([`blame`]): the relation pulling hardest on the part
//! whose fit suffered (by its multipliers) is named, one per solve.

use super::compile::{Compiled, GroupKey, Part};
use super::{
    Conflict, GlobalSettings, PrimitiveId, Related, Relation, RelationKey, WORSENING_FLOOR,
};
use crate::primitive::Primitive;
use crate::solve::{SolveReport, Termination};

/// A relation in words, named by its place in the document's list:
/// `relation 3 (coaxial of #0 top, #2 bottom)`.
pub(super) fn describe(index: usize, relation: &Relation) -> String {
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

/// The summed |multiplier| of a hard relation's equalities `range`: how hard it pulls.
fn pull(report: &SolveReport, range: &std::ops::Range<usize>) -> f64 {
    range
        .clone()
        .map(|i| report.multipliers.equality.get(i).map_or(0.0, |l| l.abs()))
        .sum()
}

/// The hard relation that pulls hardest among those `among` accepts, with its place in the
/// document's list and the relation itself.
fn strongest<'r>(
    hard: &[(RelationKey, std::ops::Range<usize>)],
    report: &SolveReport,
    relations: &'r [Related<'r>],
    among: impl Fn(&Relation) -> bool,
) -> Option<(RelationKey, &'r Related<'r>)> {
    hard.iter()
        .filter_map(|(index, range)| {
            let r = relations.iter().find(|r| r.id == *index)?;
            among(r.relation).then(|| (*index, r, pull(report, range)))
        })
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .map(|(index, r, _)| (index, r))
}

/// The hard relation to switch off when the hard relations cannot all hold: the one with
/// the largest residual; or, when they all hold only by breaking a part's own
/// constraints (parallel and orthogonal both hold on an axis shrunk to nothing), the one
/// that pulls hardest. `None` when the solve met its constraints.
fn unholdable(
    hard: &[(RelationKey, std::ops::Range<usize>)],
    values: &[f64],
    report: &SolveReport,
    relations: &[Related<'_>],
    settings: &GlobalSettings,
) -> Option<Conflict> {
    let relation = |id: RelationKey| relations.iter().find(|r| r.id == id);
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
    if let Some((index, value)) = worst
        && value > settings.violation_tol()
    {
        let r = relation(index)?;
        return Some(Conflict {
                relation: index,
                message: format!(
                    "{} switched off: the hard relations cannot all hold (its residual stays at {value:.2e})",
                    describe(r.position, r.relation)
                ),
            });
    }
    let stuck = matches!(
        report.termination,
        Termination::Infeasible | Termination::Stalled
    );
    if !(stuck && report.max_violation > settings.violation_tol()) {
        return None;
    }
    let (index, r) = strongest(hard, report, relations, |_| true)?;
    Some(Conflict {
        relation: index,
        message: format!(
            "{} switched off: the hard relations hold together only by breaking a part's \
             own shape (a violation of {:.2e} stays), and it pulls hardest",
            describe(r.position, r.relation),
            report.max_violation
        ),
    })
}

/// A part whose extent (a length, a radius, a box side) falls below this fraction of what
/// it was before the solve has collapsed, and one that grows beyond its inverse has run
/// away: no relation a designer means does that. (Residuals are relative to the parts'
/// sizes, so relations that cannot hold may seem to by blowing a part up.)
const COLLAPSED: f64 = 0.05;

/// The extents of a primitive that a collapse shrinks: its lengths and largest radius,
/// or a box's sides.
fn extents(p: &Primitive) -> Vec<f64> {
    let largest = |r: &[f64]| r.iter().copied().fold(0.0, f64::max);
    match p {
        Primitive::Cylinder(c) => vec![c.length, c.radius],
        Primitive::Cone(c) => vec![c.length, c.radius_bottom.max(c.radius_top)],
        Primitive::Sphere(s) => vec![s.radius],
        Primitive::Cuboid(b) => b.size.to_array().to_vec(),
        Primitive::Sgc(s) => vec![s.length, largest(&s.radii)],
        Primitive::Bgc(b) => vec![b.spine_length(), largest(&b.radii)],
    }
}

/// The hard relation to switch off when the solve collapsed a part or let it run away
/// (see [`COLLAPSED`]):
/// the one of that part's relations that pulls hardest. `None` when no part collapsed.
fn collapsed(
    parts: &[Part<'_>],
    solved: &[(PrimitiveId, Primitive, f64)],
    hard: &[(RelationKey, std::ops::Range<usize>)],
    report: &SolveReport,
    relations: &[Related<'_>],
) -> Option<Conflict> {
    // `solved` holds the free parts only, in order: the held ones are skipped here too,
    // or a held box's sides would be set against the next free part's length.
    let (id, before, after) =
        parts
            .iter()
            .filter(|p| !p.held)
            .zip(solved)
            .find_map(|(part, (id, after, _))| {
                let (b, a) = (extents(part.primitive), extents(after));
                b.iter()
                    .zip(&a)
                    .find(|(b, a)| !(**a >= COLLAPSED * **b && **a <= **b / COLLAPSED))
                    .map(|(b, a)| (*id, *b, *a))
            })?;
    let (index, r) = strongest(hard, report, relations, |r| r.members.contains(&id))?;
    Some(Conflict {
        relation: index,
        message: format!(
            "{} switched off: with it, part #{} {} (a size of {before:.3} becomes {after:.3})",
            describe(r.position, r.relation),
            id.0,
            if after < before {
                "collapses"
            } else {
                "runs away"
            }
        ),
    })
}

/// The relation responsible for a broken solve, or `None` when the solve is fine.
pub(super) fn blame(
    parts: &[Part<'_>],
    solved: &[(PrimitiveId, Primitive, f64)],
    hard: &[(RelationKey, std::ops::Range<usize>)],
    values: &[f64],
    report: &SolveReport,
    relations: &[Related<'_>],
    settings: &GlobalSettings,
) -> Option<Conflict> {
    if let Some(conflict) = unholdable(hard, values, report, relations, settings)
        .or_else(|| collapsed(parts, solved, hard, report, relations))
    {
        return Some(conflict);
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
            let allowed =
                settings.max_worsening() * own.max(WORSENING_FLOOR * part.primitive.size());
            (*rms > allowed && primitive.is_finite()).then_some((part.id, own, *rms))
        })
        .collect();
    if worse.is_empty() {
        return None;
    }
    let (index, r) = strongest(hard, report, relations, |r| {
        r.members.iter().any(|m| worse.iter().any(|w| w.0 == *m))
    })?;
    let (id, own, rms) = worse[0];
    Some(Conflict {
        relation: index,
        message: format!(
            "{} switched off: with it, part #{} fits its strokes {:.1}× worse (RMS {rms:.3} against {own:.3})",
            describe(r.position, r.relation),
            id.0,
            rms / own.max(f64::MIN_POSITIVE)
        ),
    })
}

/// A row reduced below this fraction of its length against the rows before it is
/// dependent on them. Not a round-off level: a solve that ends with contradicting
/// relations ends at a compromise where they are all a little off, and there the rows
/// of a relation implied by the others are dependent only to within that compromise
/// (a few per cent of their length).
const DEPENDENT: f64 = 0.05;

/// The hard relations that contradict the constraints before them at the solve's end
/// `x` (see the module docs), newest last, each with the part of its residual that no
/// independent move reduces; `values` are the constraint values at `x` and `tol` the
/// violation tolerance. Empty when the hard relations hold to `tol`.
pub(super) fn contradictions(
    compiled: &mut Compiled,
    x: &[f64],
    values: &[f64],
    tol: f64,
) -> Vec<(RelationKey, f64)> {
    let n = compiled.problem.var_count();
    let jacobian = compiled.problem.constraint_jacobian(x);
    let row = |i: usize| &jacobian[i * n..(i + 1) * n];
    let mut groups: Vec<_> = compiled.groups.iter().collect();
    // Precedence: shapes and dimensions, then relations oldest first.
    groups.sort_by_key(|g| match g.key {
        GroupKey::Part(_) | GroupKey::Dimension(..) => (0, None),
        GroupKey::Relation(id) => (1, Some(id)),
    });
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut found = Vec::new();
    for group in groups {
        let rows: Vec<Vec<f64>> = group
            .equalities
            .clone()
            .map(|i| {
                let reduced = reduce(row(i), &basis);
                let length = norm(row(i));
                if norm(&reduced) <= DEPENDENT * length {
                    vec![0.0; n]
                } else {
                    reduced
                }
            })
            .collect();
        let residual: Vec<f64> = group
            .equalities
            .clone()
            .map(|i| values.get(i).copied().unwrap_or(0.0))
            .collect();
        if let GroupKey::Relation(id) = group.key {
            let left = unreachable_residual(&rows, &residual);
            if left > tol {
                found.push((id, left));
                continue; // its rows do not join the span: the later ones meet the rest
            }
        }
        for i in group.equalities.clone() {
            // Within the group too: a parallel's three rows have rank two.
            let reduced = reduce(row(i), &basis);
            let size = norm(&reduced);
            if size > DEPENDENT * norm(row(i)) {
                basis.push(reduced.iter().map(|v| v / size).collect());
            }
        }
    }
    // A relation that only repeats a contradicted one (legs 1 ∥ 3 beside 1 ∥ 2 ∥ 3) shares
    // in the compromise and shows a residual too, smaller than the culprit's: only the
    // clear culprits go; a lesser one left over is met in the next round.
    let worst = found.iter().map(|(_, left)| *left).fold(0.0, f64::max);
    found.retain(|(_, left)| *left >= CULPRIT_SHARE * worst);
    found
}

/// The relations [`contradictions`] found, as conflicts named by their place among
/// `relations`.
pub(super) fn contradicting_conflicts(
    found: Vec<(RelationKey, f64)>,
    relations: &[Related<'_>],
) -> Vec<Conflict> {
    found
        .into_iter()
        .filter_map(|(id, left)| {
            let r = relations.iter().find(|r| r.id == id)?;
            Some(Conflict {
                relation: id,
                message: format!(
                    "{} switched off: it contradicts the relations before it (a residual of \
                     {left:.2e} that no move they allow can meet)",
                    describe(r.position, r.relation)
                ),
            })
        })
        .collect()
}

/// The least share of the largest unmet residual for which a contradicting relation is
/// named in the same pass.
const CULPRIT_SHARE: f64 = 0.5;

/// The Euclidean norm.
fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// `row` with its components along the orthonormal `basis` taken out (modified
/// Gram–Schmidt, twice for accuracy).
fn reduce(row: &[f64], basis: &[Vec<f64>]) -> Vec<f64> {
    let mut r = row.to_vec();
    for _ in 0..2 {
        for q in basis {
            let d: f64 = q.iter().zip(&r).map(|(a, b)| a * b).sum();
            for (v, qv) in r.iter_mut().zip(q) {
                *v -= d * qv;
            }
        }
    }
    r
}

/// The norm of the part of `residual` (one value per row) that moves along the reduced
/// `rows` cannot reach: the residual of the least-squares problem min ‖R d + c‖ in the
/// rows' own space, R the reduced rows. Computed from the rows' Gram matrix R Rᵀ
/// (small: a relation has at most six rows), whose range is where R d can go.
fn unreachable_residual(rows: &[Vec<f64>], residual: &[f64]) -> f64 {
    let k = rows.len();
    let gram: Vec<Vec<f64>> = (0..k)
        .map(|i| {
            (0..k)
                .map(|j| rows[i].iter().zip(&rows[j]).map(|(a, b)| a * b).sum())
                .collect()
        })
        .collect();
    // Orthonormal basis of the Gram matrix's column space (its columns by Gram–Schmidt).
    let scale = (0..k).map(|i| gram[i][i]).fold(0.0, f64::max);
    let mut span: Vec<Vec<f64>> = Vec::new();
    // The Gram matrix is symmetric: its rows are its columns.
    for column in &gram {
        let reduced = reduce(column, &span);
        let size = norm(&reduced);
        if size > 1e-9 * scale && size > 0.0 {
            span.push(reduced.iter().map(|v| v / size).collect());
        }
    }
    norm(&reduce(residual, &span))
}
