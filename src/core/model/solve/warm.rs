//! Warm starts: the multipliers of earlier solves, found again for the same
//! constraints, and the solved parts stored with their multipliers.

use super::compile::Part;
use super::{Document, PrimitiveId};
use crate::core::primitive::Primitive;
use crate::core::solve::{Multipliers, Problem, SolveReport, Start};

/// A key per constraint of `problem` that stays the same between solves of a growing
/// model: its label and how many constraints before it have that label.
pub(super) fn constraint_keys(problem: &Problem) -> Vec<(String, usize)> {
    let count = problem.equality_count() + problem.inequality_count();
    let mut seen: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
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
    pub(super) fn warm_start(
        &self,
        parts: &[Part<'_>],
        problem: &Problem,
    ) -> (Start, Vec<(String, usize)>) {
        let keys = constraint_keys(problem);
        let ne = problem.equality_count();
        let warm: Vec<f64> = keys
            .iter()
            .map(|k| self.multipliers.get(k).copied().unwrap_or(0.0))
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
        keys: Vec<(String, usize)>,
        report: &SolveReport,
    ) {
        let values = report
            .multipliers
            .equality
            .iter()
            .chain(&report.multipliers.inequality);
        for (key, value) in keys.into_iter().zip(values) {
            self.multipliers.insert(key, *value);
        }
        for (id, primitive, rms) in solved {
            if let Some(placed) = self.primitives.get_mut(&id) {
                placed.primitive = primitive;
                placed.fit.rms = rms;
            }
        }
    }
}
