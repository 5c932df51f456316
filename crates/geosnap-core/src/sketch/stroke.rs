//! The stroke and sketch types.

use glam::DVec2;
use serde::{Deserialize, Serialize};

/// Identifies a stroke within its [`Sketch`]; stable under deletion of other strokes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct StrokeId(pub u32);

/// What a stroke depicts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StrokeClass {
    /// An ellipse or elliptical arc (a circular end seen at an angle) or a box edge.
    Feature,
    /// The outline of a side of a primitive.
    Silhouette,
}

/// One drawn polyline in sketch space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stroke {
    /// The stroke's id.
    pub id: StrokeId,
    /// The points, in drawing order (at least two, all finite, after preprocessing).
    pub points: Vec<DVec2>,
    /// Whether the polyline is closed (the last point connects back to the first).
    #[serde(default)]
    pub closed: bool,
    /// A class set by the user, which wins over the inferred one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub class_override: Option<StrokeClass>,
}

impl Stroke {
    /// The length of the polyline (including the closing segment of a closed stroke).
    pub fn length(&self) -> f64 {
        let open: f64 = self.points.windows(2).map(|w| w[0].distance(w[1])).sum();
        match (self.closed, self.points.first(), self.points.last()) {
            (true, Some(a), Some(b)) => open + a.distance(*b),
            _ => open,
        }
    }
}

/// A sketch: strokes in sketch space and the extent of the drawing.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Sketch {
    /// The strokes, in drawing order.
    pub strokes: Vec<Stroke>,
    /// The drawing's extent in sketch space: the SVG viewBox `(min, size)`, or the
    /// reference image's pixel grid; `None` when unknown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub view_box: Option<(DVec2, DVec2)>,
}

impl Sketch {
    /// The stroke with this id.
    pub fn stroke(&self, id: StrokeId) -> Option<&Stroke> {
        self.strokes.iter().find(|s| s.id == id)
    }

    /// The axis-aligned bounds of all stroke points, `None` for an empty sketch.
    pub fn bounds(&self) -> Option<(DVec2, DVec2)> {
        let mut points = self.strokes.iter().flat_map(|s| s.points.iter().copied());
        let first = points.next()?;
        Some(points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }

    /// A fresh stroke id, larger than every id in use.
    pub fn next_id(&self) -> StrokeId {
        StrokeId(self.strokes.iter().map(|s| s.id.0 + 1).max().unwrap_or(0))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::{Sketch, Stroke, StrokeId};

    #[test]
    fn length_bounds_and_ids() {
        let square = Stroke {
            id: StrokeId(3),
            points: vec![
                DVec2::ZERO,
                DVec2::new(1.0, 0.0),
                DVec2::new(1.0, 1.0),
                DVec2::new(0.0, 1.0),
            ],
            closed: true,
            class_override: None,
        };
        assert!((square.length() - 4.0).abs() < 1e-12);
        let sketch = Sketch {
            strokes: vec![square],
            view_box: None,
        };
        assert_eq!(sketch.bounds(), Some((DVec2::ZERO, DVec2::ONE)));
        assert_eq!(sketch.next_id(), StrokeId(4));
        assert!(sketch.stroke(StrokeId(3)).is_some());
        assert!(Sketch::default().bounds().is_none());
    }
}
