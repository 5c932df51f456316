//! What the app says in plain words: the names of the kinds and dimensions a designer
//! reads (the files and the command line keep their short names, `sgc`, `radius_top`),
//! how a solve ended, why a snap failed, and lengths with their unit.
//!
//! **Units.** Lengths are in the document's unit ([`Unit`], millimetres unless the user
//! picks another in Settings or the export dialog): one sketch unit is one of it, every
//! length the app shows carries its symbol ([`length`]), and the glTF export converts it
//! to metres.

use crate::core::model::{Document, PrimitiveId, Quantity, Relation};
use crate::core::primitive::{Feature, PrimitiveKind};
use crate::core::relation::RelationKind;
use crate::core::snap::SnapError;
use crate::core::solve::Termination;

/// The unit of the document's lengths: what one sketch unit is (kept by the document,
/// see [`Document::unit`]).
pub(crate) use crate::core::model::LengthUnit as Unit;

/// A length in sketch units with its unit: "12.5 mm".
pub(crate) fn length(value: f64, unit: Unit) -> String {
    format!("{value:.1} {}", unit.symbol())
}

/// The name of a kind as the palette and the panels show it.
pub(crate) fn kind_title(kind: PrimitiveKind) -> &'static str {
    match kind {
        PrimitiveKind::Cylinder => "Cylinder",
        PrimitiveKind::Cone => "Cone",
        PrimitiveKind::Sphere => "Sphere",
        PrimitiveKind::Cuboid => "Box",
        PrimitiveKind::Sgc => "Profile",
        PrimitiveKind::Bgc => "Bent tube",
    }
}

/// The name of a kind inside a sentence ("a profile").
pub(crate) fn kind_noun(kind: PrimitiveKind) -> &'static str {
    match kind {
        PrimitiveKind::Cylinder => "cylinder",
        PrimitiveKind::Cone => "cone",
        PrimitiveKind::Sphere => "sphere",
        PrimitiveKind::Cuboid => "box",
        PrimitiveKind::Sgc => "profile",
        PrimitiveKind::Bgc => "bent tube",
    }
}

/// What a kind is, in full (the tooltip and the properties panel).
pub(crate) fn kind_long(kind: PrimitiveKind) -> &'static str {
    match kind {
        PrimitiveKind::Cylinder => "a straight tube with two equal round ends",
        PrimitiveKind::Cone => "a truncated cone: two round ends of different radii",
        PrimitiveKind::Sphere => "a ball",
        PrimitiveKind::Cuboid => "a box: three pairs of parallel faces",
        PrimitiveKind::Sgc => {
            "a straight generalized cylinder (SGC): a straight axis with a radius that \
             varies along it (vases, bottles)"
        }
        PrimitiveKind::Bgc => {
            "a bent generalized cylinder (BGC): a curved axis in a plane with a radius \
             along it (handles, pipes)"
        }
    }
}

/// The kind named `name` in a file or an error ("sgc"), in a sentence.
fn noun_of(name: &'static str) -> &'static str {
    PrimitiveKind::from_name(name).map_or(name, kind_noun)
}

/// The name of a dimension ("top radius").
pub(crate) fn quantity_name(quantity: Quantity) -> &'static str {
    match quantity {
        Quantity::Radius => "radius",
        Quantity::RadiusTop => "top radius",
        Quantity::RadiusBottom => "bottom radius",
        Quantity::Length => "length",
        Quantity::Width => "width",
        Quantity::Height => "height",
        Quantity::Depth => "depth",
    }
}

/// How a solve ended, in words ("settled", "did not settle within its iteration
/// budget").
pub(crate) fn termination(how: Termination) -> &'static str {
    match how {
        Termination::Converged => "settled",
        Termination::MaxOuterIterations => "did not settle within its iteration budget",
        Termination::MaxEvaluations => "did not settle within its evaluation budget",
        Termination::TimeLimit => "did not settle within its time limit",
        Termination::Cancelled => "was cancelled",
        Termination::Infeasible => "could not make every relation hold at once",
        Termination::Stalled => "stopped making progress",
        Termination::NumericalFailure => "failed: a value became infinite",
    }
}

/// Why a snap failed, in words; with `developer`, the counts and figures too.
pub(crate) fn snap_error(error: &SnapError, developer: bool) -> String {
    match error {
        SnapError::NotEnoughStrokes { kind, found } => {
            let text = format!(
                "too few strokes near the {} to tell its shape (it needs its outlines or \
                 ends drawn here)",
                noun_of(kind)
            );
            if developer {
                format!("{text} [{found}]")
            } else {
                text
            }
        }
        SnapError::RanAway { kind, factor } => {
            let text = format!(
                "the strokes here do not describe one {}: the fit ran away from the drop",
                noun_of(kind)
            );
            if developer {
                format!("{text} [size ×{factor:.1}]")
            } else {
                text
            }
        }
        SnapError::NonFinite(kind) => {
            format!("the {} lost its shape while fitting", noun_of(kind))
        }
        SnapError::Cancelled => "cancelled".to_owned(),
    }
}

/// A part as a designer names it: the name given to it ("Left leg"), else its kind and
/// its id ("Cylinder 2"); "part 2" when it is not in the model.
pub(crate) fn part_name(document: &Document, id: PrimitiveId) -> String {
    match (document.name(id), document.get(id)) {
        (Some(name), _) => name.to_owned(),
        (None, Some(placed)) => kind_id(placed.primitive.kind(), id),
        (None, None) => format!("part {}", id.0),
    }
}

/// A part by its kind and id, whatever its name ("Cylinder 2").
pub(crate) fn kind_id(kind: PrimitiveKind, id: PrimitiveId) -> String {
    format!("{} {}", kind_title(kind), id.0)
}

/// At most `max` characters of `text`, with "…" for what is left out (a long name on
/// the drawing).
pub(crate) fn shortened(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        return text.to_owned();
    }
    let kept: String = text.chars().take(max.saturating_sub(1)).collect();
    format!("{}…", kept.trim_end())
}

/// A feature of a part in words: "Cylinder 2's bottom", "Box 1's top face", "Sphere
/// 3" (its outline is the sphere itself).
fn member(document: &Document, id: PrimitiveId, feature: Option<Feature>) -> String {
    let name = part_name(document, id);
    match feature {
        None | Some(Feature::Outline) => name,
        Some(f @ Feature::Face { .. }) => format!("{name}'s {} face", f.name()),
        Some(f) => format!("{name}'s {}", f.name()),
    }
}

/// A relation as a sentence: "Cylinder 2's bottom is concentric with Cylinder 1's top",
/// "The centres of Sphere 1, Cylinder 2 and Cone 3 lie on one line".
pub(crate) fn relation_sentence(document: &Document, relation: &Relation) -> String {
    let members: Vec<String> = relation
        .members
        .iter()
        .enumerate()
        .map(|(k, id)| member(document, *id, relation.features.get(k).copied().flatten()))
        .collect();
    let verb = match relation.kind {
        RelationKind::Parallel => "is parallel to",
        RelationKind::Orthogonal => "is perpendicular to",
        RelationKind::Coaxial => "shares its axis with",
        RelationKind::Concentric => "is concentric with",
        RelationKind::Coplanar => "lies in one plane with",
        RelationKind::SameRadius => "has the same radius as",
        RelationKind::EqualLength => "is as long as",
        RelationKind::OnSphere => "sits on",
        RelationKind::CollinearCenters => {
            let centres = relation
                .members
                .iter()
                .map(|id| part_name(document, *id))
                .collect::<Vec<_>>();
            return format!("The centres of {} lie on one line", list(&centres));
        }
    };
    match members.as_slice() {
        [a, b] => format!("{a} {verb} {b}"),
        _ => format!("{}: {}", relation_kind_name(relation.kind), list(&members)),
    }
}

/// A relation kind's name in words ("same radius").
pub(crate) fn relation_kind_name(kind: RelationKind) -> String {
    match kind {
        RelationKind::CollinearCenters => "centres in line".to_owned(),
        RelationKind::OnSphere => "on a sphere".to_owned(),
        RelationKind::Orthogonal => "perpendicular".to_owned(),
        _ => kind.name().replace('_', " "),
    }
}

/// "a", "a and b", "a, b and c".
fn list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

/// A conflict message of the solver ("relation 2 (concentric of #2 bottom, #1 top)
/// switched off: …, part #2 collapses …") in words: the relation as a sentence, the
/// parts by name ("“Cylinder 2's bottom is concentric with Cylinder 1's top” was
/// switched off: …, Cylinder 2 collapses …").
pub(crate) fn conflict(document: &Document, relation: Option<&Relation>, message: &str) -> String {
    let (subject, reason) = match (relation, message.split_once(" switched off")) {
        (Some(relation), Some((_, reason))) => {
            (relation_sentence(document, relation), reason.to_owned())
        }
        _ => return parts_by_name(document, message),
    };
    let reason = parts_by_name(document, reason.trim_start_matches(':').trim_start());
    format!("“{subject}” was switched off: {reason}")
}

/// "part #2" and "#2" in a message become the part's name ("Cylinder 2").
fn parts_by_name(document: &Document, text: &str) -> String {
    let text = text.replace("part #", "#");
    let mut out = String::with_capacity(text.len());
    let mut rest = text.as_str();
    while let Some(at) = rest.find('#') {
        out.push_str(&rest[..at]);
        let digits: String = rest[at + 1..]
            .chars()
            .take_while(char::is_ascii_digit)
            .collect();
        match digits.parse::<u32>() {
            Ok(n) => out.push_str(&part_name(document, PrimitiveId(n))),
            Err(_) => out.push('#'),
        }
        rest = &rest[at + 1 + digits.len()..];
    }
    out.push_str(rest);
    out
}

/// A message from the core split into what a designer reads and the developer figures:
/// a trailing parenthesis with a residual or an RMS ("(its residual stays at 2.1e-3)")
/// goes to the second part.
pub(crate) fn split_figures(text: &str) -> (String, Option<String>) {
    if let Some(open) = text.rfind(" (") {
        let tail = &text[open + 2..];
        if tail.contains("residual") || tail.contains("RMS") {
            let detail = tail.trim_end_matches(['.', ')']).to_owned();
            let rest = text[open + 2..]
                .find(')')
                .map_or("", |close| &text[open + 2 + close + 1..]);
            return (format!("{}{rest}", &text[..open]), Some(detail));
        }
    }
    (text.to_owned(), None)
}

#[cfg(test)]
mod tests {
    use super::{kind_noun, kind_title, length, split_figures, Unit};
    use crate::core::primitive::PrimitiveKind;

    #[test]
    fn no_kind_is_named_by_its_file_name() {
        for kind in PrimitiveKind::ALL {
            for shown in [kind_title(kind), kind_noun(kind)] {
                let shown = shown.to_lowercase();
                assert!(shown != "sgc" && shown != "bgc", "{shown}");
            }
        }
        assert_eq!(length(12.345, Unit::Millimetre), "12.3 mm");
        assert_eq!(length(2.0, Unit::Inch), "2.0 in");
        assert_eq!(Unit::from_symbol("cm"), Some(Unit::Centimetre));
    }

    #[test]
    fn relations_and_conflicts_read_as_sentences() {
        use glam::DVec3;

        use super::{conflict, member, relation_sentence};
        use crate::core::model::{Document, Fit, Placed, Relation};
        use crate::core::primitive::{Axis, Feature, Primitive, Sphere};
        use crate::core::relation::{Mode, RelationKind};

        let mut document = Document::new();
        let [a, b] = [0.0, 8.0].map(|x| {
            document.add(Placed {
                primitive: Primitive::Sphere(Sphere {
                    center: DVec3::X * x,
                    radius: 3.0,
                }),
                fit: Fit::default(),
            })
        });
        let relation = Relation {
            kind: RelationKind::Concentric,
            members: vec![b, a],
            features: vec![Some(Feature::Outline), Some(Feature::Outline)],
            mode: Mode::Hard,
            inferred: None,
        };
        let id = document.add_relation(relation).expect("valid");
        let relation = &document.relation(id).expect("added").clone();
        assert_eq!(
            relation_sentence(&document, relation),
            "Sphere 1 is concentric with Sphere 0"
        );
        assert_eq!(member(&document, a, Some(Feature::Top)), "Sphere 0's top");
        assert_eq!(
            member(&document, a, Some(Feature::face(Axis::Z, true))),
            "Sphere 0's front face"
        );
        let message = "relation 0 (concentric of #1 outline, #0 outline) switched off: with \
                       it, part #1 collapses (a size of 3.000 becomes 0.001)";
        assert_eq!(
            conflict(&document, Some(relation), message),
            "“Sphere 1 is concentric with Sphere 0” was switched off: with it, Sphere 1 \
             collapses (a size of 3.000 becomes 0.001)"
        );
        // A named part goes by its name, "#" and all.
        assert!(document.set_name(b, "Knob #0"));
        assert_eq!(
            relation_sentence(&document, relation),
            "Knob #0 is concentric with Sphere 0"
        );
        assert_eq!(
            conflict(&document, Some(relation), message),
            "“Knob #0 is concentric with Sphere 0” was switched off: with it, Knob #0 \
             collapses (a size of 3.000 becomes 0.001)"
        );
    }

    #[test]
    fn long_names_are_shortened_on_character_boundaries() {
        use super::shortened;
        assert_eq!(shortened("Leg", 5), "Leg");
        assert_eq!(shortened("Left front leg", 9), "Left fro…");
        assert_eq!(
            shortened("Pied de table", 6),
            "Pied…",
            "no space before the dots"
        );
        assert_eq!(shortened("🪑🪑🪑🪑", 3), "🪑🪑…");
        assert_eq!(shortened("abc", 0), "…");
    }

    #[test]
    fn figures_are_split_off_messages() {
        let (text, detail) = split_figures(
            "coaxial #1 #2 switched off: the hard relations cannot all hold (its residual stays at 2.10e-3)",
        );
        assert_eq!(
            text,
            "coaxial #1 #2 switched off: the hard relations cannot all hold"
        );
        assert_eq!(detail.as_deref(), Some("its residual stays at 2.10e-3"));
        let plain = "2 relations inferred.";
        assert_eq!(split_figures(plain), (plain.to_owned(), None));
    }
}
