//! What happens when a part is released: relation inference against the placed parts
//! ([`crate::core::relation::infer`]), with the view's mirror ambiguity settled by the
//! relations.
//!
//! An orthographic drawing shows a solid of revolution and its reflection in the
//! view-parallel plane through its centre identically (the axis (x, y, z) and (x, y, −z)
//! project alike), so the snap cannot know which was meant. The relations can: a leg
//! whose axis leans towards the viewer while the others lean away is parallel to none of
//! them. Both poses are tried and the one with more relations is kept (the snapped one
//! on a tie). Boxes and bent tubes are not mirrored: which of their edges and end halves
//! are drawn tells the two poses apart already.
//!
//! [`Document::release`] is the whole release: inference, then the global solve of the
//! parts it changed.

use super::{Companions, Document, GlobalOutcome, GlobalSettings, PrimitiveId, Relation};
use crate::core::primitive::{FeatureCurve, Primitive, PrimitiveKind};
use crate::core::relation::infer::{infer, Part, Proposal};
use crate::core::relation::{InferenceSettings, Mode};

/// The feature of `features` named `name`, as the `'static` name inference uses.
fn static_name(features: &[FeatureCurve<f64>], name: &str) -> Option<&'static str> {
    features.iter().find(|f| f.name == name).map(|f| f.name)
}

impl Document {
    /// Infers the relations between part `id` and the other parts, adds them as hard
    /// relations and returns their indices in [`Document::relations`]. The part may be
    /// replaced by its mirror image in depth when that one has more relations (see the
    /// module docs). Relations already in the model (not off) count as known, so nothing
    /// redundant is added.
    pub fn infer_relations(&mut self, id: PrimitiveId, settings: &InferenceSettings) -> Vec<usize> {
        let ids: Vec<PrimitiveId> = self.primitives.keys().copied().collect();
        let Some(new) = ids.iter().position(|i| *i == id) else {
            return Vec::new();
        };
        let mut features: Vec<Vec<FeatureCurve<f64>>> = self
            .primitives
            .values()
            .map(|p| p.primitive.current_shape().features)
            .collect();
        let kinds: Vec<PrimitiveKind> = self
            .primitives
            .values()
            .map(|p| p.primitive.kind())
            .collect();
        let existing: Vec<Proposal> = self
            .relations
            .iter()
            .filter(|r| r.mode != Mode::Off)
            .filter_map(|r| {
                let members: Option<Vec<usize>> = r
                    .members
                    .iter()
                    .map(|m| ids.iter().position(|i| i == m))
                    .collect();
                let members = members?;
                let names = members
                    .iter()
                    .enumerate()
                    .map(
                        |(k, &i)| match r.features.get(k).and_then(|f| f.as_deref()) {
                            Some(name) => static_name(&features[i], name).map(Some),
                            None => Some(None),
                        },
                    )
                    .collect::<Option<Vec<_>>>()?;
                Some(Proposal {
                    kind: r.kind,
                    members,
                    features: names,
                })
            })
            .collect();
        let snapped = self.primitives[&id].primitive.clone();
        let mut variants = vec![snapped.clone()];
        if matches!(
            snapped.kind(),
            PrimitiveKind::Cylinder | PrimitiveKind::Cone | PrimitiveKind::Sgc
        ) {
            variants.push(snapped.mirrored_in_depth());
        }
        let mut best: Option<(Primitive, Vec<Proposal>)> = None;
        for variant in variants {
            features[new] = variant.current_shape().features;
            let parts: Vec<Part<'_>> = kinds
                .iter()
                .zip(&features)
                .map(|(kind, f)| Part {
                    kind: *kind,
                    features: f,
                })
                .collect();
            let proposals = infer(&parts, new, &existing, settings);
            log::debug!(
                "part #{} as {:?}: {} relation(s) {:?}",
                id.0,
                variant.params(),
                proposals.len(),
                proposals.iter().map(|p| p.kind.name()).collect::<Vec<_>>()
            );
            if best.as_ref().is_none_or(|b| proposals.len() > b.1.len()) {
                best = Some((variant, proposals));
            }
        }
        let Some((chosen, proposals)) = best else {
            return Vec::new();
        };
        if let Some(placed) = self.primitives.get_mut(&id) {
            placed.primitive = chosen;
        }
        let mut added = Vec::with_capacity(proposals.len());
        for p in proposals {
            let relation = Relation {
                kind: p.kind,
                members: p.members.iter().map(|&i| ids[i]).collect(),
                features: p.features.iter().map(|f| f.map(str::to_owned)).collect(),
                mode: Mode::Hard,
            };
            if self.add_relation(relation).is_ok() {
                added.push(self.relations.len() - 1);
            }
        }
        added
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
    /// use geosnap::core::model::{Companions, Document, Fit, GlobalSettings, Placed};
    /// use geosnap::core::primitive::{Cylinder, Primitive};
    /// use geosnap::core::relation::{InferenceSettings, RelationKind};
    ///
    /// let leg = |x: f64, axis: DVec3| Placed {
    ///     primitive: Primitive::Cylinder(Cylinder {
    ///         center: DVec3::new(x, 0.0, 0.0),
    ///         axis: axis.normalize(),
    ///         length: 10.0,
    ///         radius: 1.0,
    ///     }),
    ///     fit: Fit::default(),
    /// };
    /// let mut doc = Document::new();
    /// doc.add(leg(0.0, DVec3::Y));
    /// let new = doc.add(leg(5.0, DVec3::new(0.02, 1.0, 0.0)));
    /// let (added, outcome) = doc.release(
    ///     new,
    ///     &InferenceSettings::default(),
    ///     &GlobalSettings::default(),
    ///     Companions::default(),
    /// );
    /// assert!(added.iter().any(|&i| doc.relations()[i].kind == RelationKind::Parallel));
    /// assert!(outcome.conflicts.is_empty());
    /// ```
    pub fn release(
        &mut self,
        id: PrimitiveId,
        inference: &InferenceSettings,
        global: &GlobalSettings,
        companions: Companions<'_>,
    ) -> (Vec<usize>, GlobalOutcome) {
        let added = self.infer_relations(id, inference);
        let outcome = self.solve(Some(&[id]), global, companions);
        (added, outcome)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use crate::core::model::{Document, Fit, Placed};
    use crate::core::primitive::{Cylinder, Primitive};
    use crate::core::relation::{InferenceSettings, RelationKind};

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

    #[test]
    fn a_part_snapped_in_the_wrong_mirror_pose_is_turned_by_its_relations() {
        let mut doc = Document::new();
        let a = doc.add(leg(0.0, DVec3::new(0.0, 0.9, 0.44)));
        // The same leg seen in the same drawing, but snapped leaning the other way in
        // depth: parallel to nothing as it is.
        let b = doc.add(leg(6.0, DVec3::new(0.0, 0.9, -0.44)));
        let added = doc.infer_relations(b, &InferenceSettings::default());
        let kinds: Vec<RelationKind> = added.iter().map(|&i| doc.relations()[i].kind).collect();
        assert!(kinds.contains(&RelationKind::Parallel), "{kinds:?}");
        let Primitive::Cylinder(turned) = &doc.get(b).expect("placed").primitive else {
            unreachable!("a cylinder")
        };
        assert!((turned.axis.z - 0.44 / DVec3::new(0.0, 0.9, 0.44).length()).abs() < 1e-12);
        assert!(doc.relations().iter().all(|r| r.members.contains(&a)));
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
