//! Warm starts: the multipliers of earlier solves, found again for the same
//! constraints, and the solved parts stored with their multipliers.
//!
//! A multiplier is stored under its constraint's [`ConstraintKey`]: the group it belongs
//! to ([`GroupKey`]) and its place in that group, so that rewording a label keeps it.
//! Session files name constraints by label and occurrence instead; multipliers read from
//! one are found by label until a solve stores them under their keys.

use std::collections::{BTreeMap, HashMap};

use super::compile::{Compiled, GroupKey, Part};
use super::{Document, PrimitiveId, RelationKey};
use crate::primitive::Primitive;
use crate::solve::{Multipliers, Problem, SolveReport, Start};

/// A constraint of the global problem as warm starts find it again: its group and its
/// place among the group's constraints (equalities first, then inequalities).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct ConstraintKey {
    group: GroupKey,
    index: usize,
}

/// A stored multiplier with the label and occurrence a session file names it by.
#[derive(Clone, Debug, PartialEq)]
struct Named {
    label: String,
    occurrence: usize,
    value: f64,
}

/// The warm-start multipliers of a document.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct WarmStarts {
    /// By constraint, from the solves accepted so far.
    solved: BTreeMap<ConstraintKey, Named>,
    /// Read from a session file, by label and occurrence: found by label until a solve
    /// stores the constraint under its key.
    loaded: BTreeMap<(String, usize), f64>,
}

impl WarmStarts {
    /// Every multiplier by label and occurrence, in that order (a solved one wins over
    /// one read with the same name).
    pub(crate) fn named(&self) -> Vec<(&str, usize, f64)> {
        let mut all: BTreeMap<(&str, usize), f64> = self
            .loaded
            .iter()
            .map(|((label, n), value)| ((label.as_str(), *n), *value))
            .collect();
        for named in self.solved.values() {
            all.insert((named.label.as_str(), named.occurrence), named.value);
        }
        all.into_iter().map(|((l, n), v)| (l, n, v)).collect()
    }

    /// Sets the multiplier of the `occurrence`-th constraint labelled `label`.
    pub(crate) fn set_named(&mut self, label: String, occurrence: usize, value: f64) {
        self.loaded.insert((label, occurrence), value);
    }

    /// Forgets the multipliers of `relations`: removed ones, and those whose place in
    /// the document's list (which their constraints' labels name) has changed.
    pub(crate) fn forget_relations(&mut self, relations: &[RelationKey]) {
        self.solved.retain(|key, _| match key.group {
            GroupKey::Relation(id) => !relations.contains(&id),
            GroupKey::Part(_) | GroupKey::Dimension(..) => true,
        });
    }

    /// The multiplier of a constraint: under its key, else under its name.
    fn get(&self, key: Option<&ConstraintKey>, name: &(String, usize)) -> f64 {
        key.and_then(|k| self.solved.get(k))
            .map(|n| n.value)
            .or_else(|| self.loaded.get(name).copied())
            .unwrap_or(0.0)
    }
}

/// The constraints of a solve, in the problem's order: each one's key and its label with
/// how many constraints before it have that label.
pub(super) struct Keys {
    keys: Vec<Option<ConstraintKey>>,
    names: Vec<(String, usize)>,
}

/// The key of every constraint of `compiled`, in the problem's order (equalities, then
/// inequalities).
fn constraint_keys(compiled: &Compiled) -> Vec<Option<ConstraintKey>> {
    let problem = &compiled.problem;
    let ne = problem.equality_count();
    let mut keys = vec![None; ne + problem.inequality_count()];
    for group in &compiled.groups {
        let key = |index| {
            Some(ConstraintKey {
                group: group.key,
                index,
            })
        };
        for (index, k) in group.equalities.clone().enumerate() {
            keys[k] = key(index);
        }
        let before = group.equalities.len();
        for (index, k) in group.inequalities.clone().enumerate() {
            keys[ne + k] = key(before + index);
        }
    }
    keys
}

/// The name of every constraint of `problem`: its label and how many constraints before
/// it have that label.
fn constraint_names(problem: &Problem) -> Vec<(String, usize)> {
    let count = problem.equality_count() + problem.inequality_count();
    let mut seen: HashMap<&str, usize> = HashMap::new();
    (0..count)
        .map(|k| {
            let label = problem.constraint_label(k).unwrap_or("");
            let n = seen.entry(label).or_insert(0);
            *n += 1;
            (label.to_owned(), *n - 1)
        })
        .collect()
}

impl Document {
    /// The start of a solve: the parts as they are, and the multipliers of the same
    /// constraints in earlier solves (zero for new ones); with the constraints' keys.
    pub(super) fn warm_start(&self, parts: &[Part<'_>], compiled: &Compiled) -> (Start, Keys) {
        let problem = &compiled.problem;
        let keys = Keys {
            keys: constraint_keys(compiled),
            names: constraint_names(problem),
        };
        let ne = problem.equality_count();
        let warm: Vec<f64> = keys
            .keys
            .iter()
            .zip(&keys.names)
            .map(|(key, name)| self.multipliers.get(key.as_ref(), name))
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

    /// Stores a solve's parts and remembers its multipliers for the next one.
    pub(super) fn accept(
        &mut self,
        solved: Vec<(PrimitiveId, Primitive, f64)>,
        keys: Keys,
        report: &SolveReport,
    ) {
        let values = report
            .multipliers
            .equality
            .iter()
            .chain(&report.multipliers.inequality);
        for ((key, (label, occurrence)), value) in keys.keys.into_iter().zip(keys.names).zip(values)
        {
            let named = Named {
                label,
                occurrence,
                value: *value,
            };
            match key {
                Some(key) => {
                    self.multipliers.solved.insert(key, named);
                }
                None => {
                    self.multipliers
                        .loaded
                        .insert((named.label, named.occurrence), named.value);
                }
            }
        }
        for (id, primitive, rms) in solved {
            if let Some(placed) = self.primitives.get_mut(&id) {
                placed.primitive = primitive;
                placed.fit.rms = rms;
            }
        }
    }
}
