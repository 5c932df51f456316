//! What the app says in plain words: the names of the kinds and dimensions a designer
//! reads (the files and the command line keep their short names, `sgc`, `radius_top`),
//! how a solve ended, why a snap failed, and lengths with their unit.
//!
//! **Units.** One sketch unit is one millimetre: the glTF export writes
//! `io::gltf::DEFAULT_METRES_PER_UNIT` = 0.001 m per unit unless told otherwise, so every
//! length the app shows is in millimetres ([`mm`]).

use crate::core::model::Quantity;
use crate::core::primitive::PrimitiveKind;
use crate::core::snap::SnapError;
use crate::core::solve::Termination;

/// The unit of every length the app shows (one sketch unit).
pub(crate) const UNIT: &str = "mm";

/// A length in sketch units with its unit: "12.5 mm".
pub(crate) fn mm(value: f64) -> String {
    format!("{value:.1} {UNIT}")
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
    use super::{kind_noun, kind_title, mm, split_figures};
    use crate::core::primitive::PrimitiveKind;

    #[test]
    fn no_kind_is_named_by_its_file_name() {
        for kind in PrimitiveKind::ALL {
            for shown in [kind_title(kind), kind_noun(kind)] {
                let shown = shown.to_lowercase();
                assert!(shown != "sgc" && shown != "bgc", "{shown}");
            }
        }
        assert_eq!(mm(12.345), "12.3 mm");
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
