//! Which parts a solve takes: the connected components of the relation graph holding a
//! changed part, and within them the parts within reach of the change.

use std::collections::BTreeSet;

use super::{Document, PrimitiveId, Related, Relation};

/// Whether a relation takes part in solves.
pub(super) fn active(relation: &Relation) -> bool {
    relation.mode.is_enforced()
}

/// The parts within `reach` relations of `changed` (active relations only).
pub(super) fn neighbourhood(
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
pub(super) fn held_beyond(
    document: &Document,
    ids: &BTreeSet<PrimitiveId>,
    changed: &[PrimitiveId],
    reach: usize,
) -> BTreeSet<PrimitiveId> {
    let near = neighbourhood(document, changed, reach);
    ids.difference(&near).copied().collect()
}

/// The parts connected to `changed` through active relations.
pub(super) fn component(document: &Document, changed: &[PrimitiveId]) -> BTreeSet<PrimitiveId> {
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
    /// The parts of `ids` not `held` that have dimensions.
    pub(super) fn dimensioned(
        &self,
        ids: &BTreeSet<PrimitiveId>,
        held: &BTreeSet<PrimitiveId>,
    ) -> BTreeSet<PrimitiveId> {
        ids.difference(held)
            .copied()
            .filter(|id| self.dimensions_of(*id).next().is_some())
            .collect()
    }

    /// The active relations among `ids` that reach a part not `held`.
    pub(super) fn relations_between(
        &self,
        ids: &BTreeSet<PrimitiveId>,
        held: &BTreeSet<PrimitiveId>,
    ) -> Vec<Related<'_>> {
        self.relations_with_ids()
            .enumerate()
            .filter(|(_, (_, r))| {
                active(r)
                    && r.members.iter().all(|m| ids.contains(m))
                    && r.members.iter().any(|m| !held.contains(m))
            })
            .map(|(position, (id, relation))| Related {
                id,
                position,
                relation,
            })
            .collect()
    }
}
