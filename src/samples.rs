//! The sample sketches built into the binary, so geosnap can be tried without any file.

/// The default sample: a vase (a straight generalized cylinder) drawn by hand, as SVG.
pub const VASE_SVG: &str = include_str!("../sketches/vase.svg");

/// The placement script of [`VASE_SVG`], naming it as `vase.svg`.
pub const VASE_SCRIPT: &str = include_str!("../sketches/vase.script.json");

#[cfg(test)]
mod tests {
    use super::{VASE_SCRIPT, VASE_SVG};

    #[test]
    fn the_sample_is_a_sketch_and_a_script() {
        assert!(VASE_SVG.contains("<svg"));
        assert!(VASE_SCRIPT.contains("\"vase.svg\""));
    }
}
