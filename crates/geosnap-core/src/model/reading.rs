//! Which way round the drawing shows a solid of revolution: the end facing the viewer
//! is drawn whole, the end facing away only on its near half (the "U" under a standing
//! can), unless the designer drew hidden lines.
//!
//! An orthographic view shows a cylinder and its mirror image in depth with the same
//! outline, so the snap's pose and its mirror fit the strokes equally by RMS. The ends
//! tell them apart: a pose whose facing end is drawn only on its far half, or whose
//! away end is drawn as a half, contradicts the strokes less or more. [`DrawnEnds`]
//! reads, from the strokes a part was snapped to, how each end is drawn;
//! [`DrawnEnds::agreement`] scores a pose against it. The release
//! ([`Document::infer_relations`](super::Document::infer_relations)) never takes a pose
//! that agrees less with the drawing for the sake of a relation.

use glam::DVec2;

use crate::geom::fit_line;
use crate::primitive::{Curve2, CurveClass, Primitive};
use crate::snap::Assignment;

/// How an end ellipse is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndDrawn {
    /// No stroke was assigned to it.
    Blank,
    /// Only its half away from the other end: the near half of an end facing away.
    Half,
    /// Round on both sides of its centre: an end facing the viewer (or a hidden line).
    Whole,
}

/// How a solid of revolution's two ends are drawn (`bottom`, `top`), read off its snap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DrawnEnds {
    /// The `bottom` end.
    pub bottom: EndDrawn,
    /// The `top` end.
    pub top: EndDrawn,
}

/// An end's samples reaching past its centre towards the other end by more than this
/// fraction of the ellipse's extent along the axis make it whole.
const WHOLE_REACH: f64 = 0.5;

impl DrawnEnds {
    /// How the ends of `primitive` are drawn by the strokes of `assignment` (its snap's,
    /// one entry per projected curve). Parts without `top` and `bottom` ellipses, and
    /// axes seen end-on, read as blank.
    pub fn of(primitive: &Primitive, assignment: &Assignment) -> Self {
        let shape = primitive.current_shape();
        let ellipse = |name: &str| {
            shape.curves.iter().position(|c| {
                c.name == name
                    && c.class == CurveClass::Feature
                    && matches!(c.curve, Curve2::Ellipse { .. })
            })
        };
        let centre = |k: usize| match &shape.curves[k].curve {
            Curve2::Ellipse { center, a, b } => {
                Some((center.to_dvec2(), a.to_dvec2(), b.to_dvec2()))
            }
            Curve2::Polyline(_) => None,
        };
        let read = |k: Option<usize>, other: Option<usize>| -> EndDrawn {
            let (Some(k), Some(other)) = (k, other) else {
                return EndDrawn::Blank;
            };
            let samples = samples_of(assignment, k);
            let (Some((c, a, b)), Some((o, _, _))) = (centre(k), centre(other)) else {
                return EndDrawn::Blank;
            };
            let away = c - o;
            if samples.is_empty() || away.length() < 1e-9 {
                return EndDrawn::Blank;
            }
            let w = away.normalize();
            let extent = a.dot(w).hypot(b.dot(w));
            if extent <= 0.0 {
                return EndDrawn::Blank;
            }
            if samples
                .iter()
                .any(|p| (*p - c).dot(w) < -WHOLE_REACH * extent)
            {
                EndDrawn::Whole
            } else {
                EndDrawn::Half
            }
        };
        let (bottom, top) = (ellipse("bottom"), ellipse("top"));
        Self {
            bottom: read(bottom, top),
            top: read(top, bottom),
        }
    }

    /// How well a pose agrees with the drawn ends: +1 for each end drawn as its pose
    /// shows it (the facing end whole, the away end half), −1 for each drawn against it
    /// (the facing end half); a whole away end (a hidden line) and a blank end say
    /// nothing. Parts that are not solids of revolution score 0.
    pub fn agreement(&self, pose: &Primitive) -> i32 {
        let axis = match pose {
            Primitive::Cylinder(c) => c.axis,
            Primitive::Cone(c) => c.axis,
            Primitive::Sgc(s) => s.axis,
            _ => return 0,
        };
        // The outward normal of `top` is the axis: top faces the viewer when axis.z > 0.
        if axis.z.abs() < 1e-9 {
            return 0;
        }
        let (facing, away) = if axis.z > 0.0 {
            (self.top, self.bottom)
        } else {
            (self.bottom, self.top)
        };
        let facing_score = match facing {
            EndDrawn::Whole => 1,
            EndDrawn::Half => -1,
            EndDrawn::Blank => 0,
        };
        let away_score = i32::from(away == EndDrawn::Half);
        facing_score + away_score
    }
}

/// A drawn silhouette shorter than this many times its samples' spread across it is a
/// blob, not a line: it shows no direction.
const LINE_ASPECT: f64 = 3.0;

/// Which way the side outlines of a cylinder or cone run on the paper, read off the
/// strokes of its snap (`assignment`, one entry per projected curve): the principal
/// direction of each silhouette's samples, weighted by their extent and turned to point
/// along the part's projected axis. `None` for other kinds, for a part whose silhouettes
/// have no strokes, or strokes too short for their spread to show a direction.
///
/// A freehand drawing can disagree with itself: an end ellipse drawn slanted leans the
/// snapped part, while its side lines stand up straight. This is what the side lines
/// say.
pub fn drawn_axis(primitive: &Primitive, assignment: &Assignment) -> Option<DVec2> {
    let axis = match primitive {
        Primitive::Cylinder(c) => c.axis,
        Primitive::Cone(c) => c.axis,
        _ => return None,
    }
    .truncate();
    let shape = primitive.current_shape();
    let mut sum = DVec2::ZERO;
    for (k, curve) in shape.curves.iter().enumerate() {
        if curve.class != CurveClass::Silhouette {
            continue;
        }
        if let Some((direction, extent)) = principal_line(&samples_of(assignment, k)) {
            let toward = if direction.dot(axis) < 0.0 {
                -direction
            } else {
                direction
            };
            sum += toward * extent;
        }
    }
    (sum.length() > 0.0).then(|| sum.normalize())
}

/// The samples of every stroke assigned to curve `k`.
fn samples_of(assignment: &Assignment, k: usize) -> Vec<DVec2> {
    assignment
        .curves
        .get(k)
        .into_iter()
        .flatten()
        .flat_map(|a| a.samples.iter().copied())
        .collect()
}

/// The principal direction of `points` ([`fit_line`]) and their extent along it, when
/// they lie along a line ([`LINE_ASPECT`]); `None` for fewer than two points or a blob.
fn principal_line(points: &[DVec2]) -> Option<(DVec2, f64)> {
    let line = fit_line(points)?;
    let extent = line.t_max - line.t_min;
    (extent.is_finite() && extent > 0.0 && extent > LINE_ASPECT * line.rms_residual)
        .then_some((line.direction, extent))
}

/// Strokes along the ellipses of a solid of revolution `p` as a person draws it: the
/// `top` whole, the `bottom` on its half away from the top only (or whole when
/// `hidden`), each curve its own stroke.
#[cfg(test)]
pub(crate) fn drawn(p: &Primitive, hidden: bool) -> Assignment {
    let shape = p.current_shape();
    let centre = |name: &str| {
        shape.curves.iter().find_map(|c| match &c.curve {
            Curve2::Ellipse { center, .. } if c.name == name => Some(center.to_dvec2()),
            _ => None,
        })
    };
    let (top, bottom) = (
        centre("top").expect("top"),
        centre("bottom").expect("bottom"),
    );
    let curves = shape
        .curves
        .iter()
        .map(|c| {
            let points = c.curve.points(48);
            let samples: Vec<DVec2> = match c.name.as_str() {
                "bottom" if !hidden => points
                    .into_iter()
                    .filter(|q| (*q - bottom).dot(bottom - top) >= 0.0)
                    .collect(),
                _ => points,
            };
            vec![crate::snap::AssignedStroke {
                stroke: crate::sketch::StrokeId(0),
                samples,
                mean_distance: 0.0,
                part: None,
            }]
        })
        .collect();
    Assignment { curves }
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::{drawn, drawn_axis, DrawnEnds, EndDrawn};
    use crate::primitive::{CurveClass, Cylinder, Primitive};

    /// A can leaning its top towards the viewer.
    fn can() -> Primitive {
        Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.0, 0.9, 0.44).normalize(),
            length: 40.0,
            radius: 10.0,
        })
    }

    #[test]
    fn the_side_lines_give_the_drawn_axis() {
        let p = can();
        let axis = drawn_axis(&p, &drawn(&p, false)).expect("side lines drawn");
        let along = DVec2::new(0.0, 1.0);
        assert!(axis.dot(along) > 0.9999, "{axis}");
        // Side lines drawn upright under ends drawn leaning: the side lines speak.
        let leaning = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.4, 0.8, 0.44).normalize(),
            length: 40.0,
            radius: 10.0,
        });
        let axis = drawn_axis(&leaning, &drawn(&p, false)).expect("side lines drawn");
        assert!(axis.dot(along) > 0.9999, "{axis}");
        // No side lines, no direction.
        let mut bare = drawn(&p, false);
        for (k, c) in p.current_shape().curves.iter().enumerate() {
            if c.class == CurveClass::Silhouette {
                bare.curves[k].clear();
            }
        }
        assert_eq!(drawn_axis(&p, &bare), None);
    }

    #[test]
    fn the_drawn_ends_tell_the_mirror_apart() {
        let p = can();
        let ends = DrawnEnds::of(&p, &drawn(&p, false));
        assert_eq!(ends.top, EndDrawn::Whole);
        assert_eq!(ends.bottom, EndDrawn::Half);
        assert_eq!(ends.agreement(&p), 2);
        assert_eq!(ends.agreement(&p.mirrored_in_depth()), -1);
    }

    #[test]
    fn hidden_lines_leave_the_reading_open() {
        let p = can();
        let ends = DrawnEnds::of(&p, &drawn(&p, true));
        assert_eq!(ends.agreement(&p), ends.agreement(&p.mirrored_in_depth()));
    }
}
