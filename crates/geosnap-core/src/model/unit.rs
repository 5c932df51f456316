//! What a document's lengths are in, and the names designers give parts.
//!
//! **Unit.** Model space has no unit of its own: one sketch unit is one model unit
//! (formats.md §1). A [`LengthUnit`] says what that unit is in the world, so lengths can
//! be shown with a symbol ("12.5 mm") and exported in metres. Millimetres unless the
//! document says otherwise, which is also what a file without a unit means.
//!
//! **Names.** A part may carry a name a designer gave it ("left leg"). Names are free
//! text, cleaned by [`clean_name`]: trimmed, control characters (new lines, tabs) made
//! spaces, at most [`MAX_NAME_CHARS`] characters; an empty or blank name is no name.
//! Names need not be unique: parts are addressed by their ids.

/// What one unit of the document (one sketch unit) is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LengthUnit {
    /// Millimetres (the default).
    #[default]
    Millimetre,
    /// Centimetres.
    Centimetre,
    /// Metres.
    Metre,
    /// Inches.
    Inch,
}

impl LengthUnit {
    /// Every unit, as menus list them.
    pub const ALL: [Self; 4] = [Self::Millimetre, Self::Centimetre, Self::Metre, Self::Inch];

    /// The symbol shown after a length and written in files: `mm`, `cm`, `m`, `in`.
    pub fn symbol(self) -> &'static str {
        match self {
            Self::Millimetre => "mm",
            Self::Centimetre => "cm",
            Self::Metre => "m",
            Self::Inch => "in",
        }
    }

    /// The unit's name in a menu ("millimetres").
    pub fn name(self) -> &'static str {
        match self {
            Self::Millimetre => "millimetres",
            Self::Centimetre => "centimetres",
            Self::Metre => "metres",
            Self::Inch => "inches",
        }
    }

    /// One of it, in words ("millimetre", "inch").
    pub fn singular(self) -> &'static str {
        match self {
            Self::Millimetre => "millimetre",
            Self::Centimetre => "centimetre",
            Self::Metre => "metre",
            Self::Inch => "inch",
        }
    }

    /// Metres in one of it (0.001 for millimetres).
    pub fn metres(self) -> f64 {
        match self {
            Self::Millimetre => 0.001,
            Self::Centimetre => 0.01,
            Self::Metre => 1.0,
            Self::Inch => 0.0254,
        }
    }

    /// The unit whose [`Self::symbol`] is `symbol` (exactly, as files write it).
    pub fn from_symbol(symbol: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|u| u.symbol() == symbol)
    }
}

/// The most characters (Unicode scalar values) a part's name keeps; longer names are cut.
pub const MAX_NAME_CHARS: usize = 80;

/// A part's name as a document keeps it: control characters (new lines, tabs, …) become
/// spaces, the ends are trimmed, and it is cut to [`MAX_NAME_CHARS`] characters (on a
/// character boundary, then trimmed again). `None` for an empty or blank name, which
/// means "no name".
///
/// # Examples
///
/// ```
/// use geosnap_core::model::clean_name;
///
/// assert_eq!(clean_name("  left leg\n").as_deref(), Some("left leg"));
/// assert_eq!(clean_name(" \t "), None);
/// assert_eq!(clean_name(&"é".repeat(500)).map(|n| n.chars().count()), Some(80));
/// ```
pub fn clean_name(name: &str) -> Option<String> {
    let spaced: String = name
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let cut: String = spaced.trim().chars().take(MAX_NAME_CHARS).collect();
    let cut = cut.trim_end();
    (!cut.is_empty()).then(|| cut.to_owned())
}

#[cfg(test)]
mod tests {
    use super::{clean_name, LengthUnit, MAX_NAME_CHARS};

    #[test]
    fn units_read_back_from_their_symbols() {
        for unit in LengthUnit::ALL {
            assert_eq!(LengthUnit::from_symbol(unit.symbol()), Some(unit));
            assert!(unit.metres() > 0.0, "{unit:?}");
        }
        assert_eq!(LengthUnit::default(), LengthUnit::Millimetre);
        assert_eq!(LengthUnit::from_symbol("MM"), None, "symbols are exact");
        assert_eq!(LengthUnit::from_symbol("ft"), None);
    }

    #[test]
    fn names_are_cleaned_and_bounded_without_panicking() {
        assert_eq!(clean_name("Seat").as_deref(), Some("Seat"));
        assert_eq!(clean_name("").as_deref(), None);
        assert_eq!(clean_name("   ").as_deref(), None);
        assert_eq!(clean_name("\u{3000}\n").as_deref(), None, "a wide space");
        assert_eq!(clean_name("a\nb\tc").as_deref(), Some("a b c"));
        assert_eq!(clean_name("\u{0}x\u{7f}").as_deref(), Some("x"));
        // Multi-byte characters, combining marks, emoji: cut on character boundaries.
        let long = "🪑é\u{301}漢".repeat(100);
        let name = clean_name(&long).expect("a name");
        assert_eq!(name.chars().count(), MAX_NAME_CHARS);
        assert!(long.starts_with(&name));
        // A cut that ends on a space is trimmed.
        let spaced = format!("{} tail", "x".repeat(MAX_NAME_CHARS - 1));
        assert_eq!(clean_name(&spaced), Some("x".repeat(MAX_NAME_CHARS - 1)));
    }
}
