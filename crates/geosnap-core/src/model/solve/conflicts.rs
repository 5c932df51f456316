//! Finding the relation responsible for a broken solve, and naming it.

use super::compile::Part;
use super::{
    Conflict, GlobalSettings, PrimitiveId, Related, Relation, RelationKey, WORSENING_FLOOR,
};
use crate::primitive::Primitive;
use crate::solve::SolveReport;

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
    let relation = |id: RelationKey| relations.iter().find(|r| r.id == id);
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
        if value > settings.violation_tol() {
            let r = relation(index)?;
            return Some(Conflict {
                relation: index,
                message: format!(
                    "{} switched off: the hard relations cannot all hold (its residual stays at {value:.2e})",
                    describe(r.position, r.relation)
                ),
            });
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
            let allowed =
                settings.max_worsening() * own.max(WORSENING_FLOOR * part.primitive.size());
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
            relation(*index).is_some_and(|r| {
                r.relation
                    .members
                    .iter()
                    .any(|m| worse.iter().any(|w| w.0 == *m))
            })
        })
        .map(|(index, range)| (*index, pull(range)))
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let r = relation(index)?;
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
