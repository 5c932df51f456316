//! The camera convention (formats.md §1): model space is right-handed with x to the
//! right, y up and z towards the viewer; the view is orthographic along −z, and the model
//! point (x, y, z) is drawn at the sketch point (x, −y).
//!
//! The *view plane* is model space's xy plane: a sketch point (u, v) is the view-plane
//! point (u, −v). Fitting works in view-plane coordinates so that projection is just
//! "drop z".

use glam::{DVec2, DVec3};

/// The view-plane point of a sketch point: (u, v) ↦ (u, −v).
pub fn view_from_sketch(p_sketch: DVec2) -> DVec2 {
    DVec2::new(p_sketch.x, -p_sketch.y)
}

/// The sketch point of a view-plane point: (x, y) ↦ (x, −y).
pub fn sketch_from_view(p_view: DVec2) -> DVec2 {
    DVec2::new(p_view.x, -p_view.y)
}

/// The sketch point where the model point is drawn: (x, y, z) ↦ (x, −y).
pub fn sketch_from_model(p_model: DVec3) -> DVec2 {
    DVec2::new(p_model.x, -p_model.y)
}

/// A 2D image direction in sketch space (y down) as a model-space direction in the view
/// plane (z = 0), normalised; `None` for a zero or non-finite direction.
pub fn model_direction_from_sketch(d_sketch: DVec2) -> Option<DVec3> {
    DVec3::new(d_sketch.x, -d_sketch.y, 0.0).try_normalize()
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::{
        model_direction_from_sketch, sketch_from_model, sketch_from_view, view_from_sketch,
    };

    #[test]
    fn y_flips_between_sketch_and_model() {
        let p = DVec2::new(3.0, 4.0);
        assert_eq!(view_from_sketch(p), DVec2::new(3.0, -4.0));
        assert_eq!(sketch_from_view(view_from_sketch(p)), p);
        assert_eq!(
            sketch_from_model(DVec3::new(1.0, 2.0, 9.0)),
            DVec2::new(1.0, -2.0)
        );
        // "Up the page" in the sketch is +y in the model.
        assert_eq!(
            model_direction_from_sketch(DVec2::new(0.0, -5.0)),
            Some(DVec3::Y)
        );
        assert_eq!(model_direction_from_sketch(DVec2::ZERO), None);
    }
}
