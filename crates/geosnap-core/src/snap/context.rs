//! The strokes as the snapper sees them: view-plane points, class, straightness and
//! bounds, computed once per sketch.

use glam::DVec2;

use super::holds::image_box;
use super::pieces::turn_pieces;
use crate::geom::projection::view_from_sketch;
use crate::primitive::Primitive;
use crate::sketch::{
    classify_sketch, preprocess_report, ClassifyOptions, MergedStroke, PreprocessOptions, Sketch,
    StrokeClass, StrokeId,
};

/// One stroke prepared for matching.
#[derive(Clone, Debug, PartialEq)]
pub struct SnapStroke {
    /// The stroke's id.
    pub id: StrokeId,
    /// Its points in view-plane coordinates (y up), evenly spaced.
    pub points: Vec<DVec2>,
    /// Its effective class.
    pub class: StrokeClass,
    /// Whether it is (nearly) straight: RMS distance to its chord line ≤ 2 % of its
    /// length. Box edges take straight strokes of either class.
    pub straight: bool,
    /// Its RMS distance to its principal line over its extent along that line: 0 for a
    /// ruler-straight stroke, about 0.1 for a quarter of a circle. A hand's jitter makes a
    /// short straight stroke score a few hundredths.
    pub straightness: f64,
    /// Its unit principal direction (sign arbitrary).
    pub direction: DVec2,
    /// Axis-aligned bounds `(min, max)`.
    pub bounds: (DVec2, DVec2),
    /// Its length.
    pub length: f64,
}

/// The strokes of a sketch ready for snapping.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SnapContext {
    /// The strokes.
    pub strokes: Vec<SnapStroke>,
    /// The pieces of the strokes drawn round a turn (a U, an L), each under its stroke's
    /// id: what the starting poses read besides whole strokes ([`super::pieces`]). The
    /// constructors keep them in step with `strokes`; a context whose strokes are
    /// changed afterwards is rebuilt with [`SnapContext::of`].
    pub(crate) pieces: Vec<SnapStroke>,
    /// The parts placed before the one being snapped (see [`SnapContext::with_placed`]).
    pub(crate) placed: Vec<PlacedPart>,
}

/// A part placed before the one being snapped, with the box round its image.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PlacedPart {
    /// The part as it lies.
    pub(crate) primitive: Primitive,
    /// Its image's lower and upper corners in the view plane.
    pub(crate) image: (DVec2, DVec2),
}

impl SnapContext {
    /// Prepares strokes given in sketch space with their effective classes. Strokes with
    /// fewer than two finite points are left out.
    pub fn new<'a>(
        strokes: impl IntoIterator<Item = (StrokeId, &'a [DVec2], StrokeClass)>,
    ) -> Self {
        let strokes = strokes
            .into_iter()
            .filter_map(|(id, points, class)| {
                let points: Vec<DVec2> = points
                    .iter()
                    .filter(|p| p.is_finite())
                    .map(|p| view_from_sketch(*p))
                    .collect();
                prepare(id, points, class)
            })
            .collect();
        Self::of(strokes)
    }

    /// A context of prepared strokes, with their pieces.
    pub(crate) fn of(strokes: Vec<SnapStroke>) -> Self {
        let pieces = strokes
            .iter()
            .flat_map(|s| {
                turn_pieces(&s.points)
                    .into_iter()
                    .filter_map(|r| prepare(s.id, s.points[r].to_vec(), s.class))
            })
            .collect();
        Self {
            strokes,
            pieces,
            placed: Vec::new(),
        }
    }

    /// This context with `parts` as the parts of the model placed before the one it
    /// snaps. A reading that holds one of them (its outline encloses the placed part and
    /// runs along that part's edges on opposite sides, and at some depth the placed part
    /// lies inside it, see `snap::holds`) reads that part and its neighbours as one: no
    /// designer models a part as a piece of one placed before, so it gives way to a
    /// reading that holds none. Non-finite parts are left out.
    ///
    /// # Examples
    ///
    /// ```
    /// use geosnap_core::primitive::{Primitive, Sphere};
    /// use geosnap_core::snap::SnapContext;
    /// use glam::DVec3;
    ///
    /// let placed = Primitive::Sphere(Sphere { center: DVec3::ZERO, radius: 50.0 });
    /// let context = SnapContext::default().with_placed([placed]);
    /// assert_eq!(context.placed().count(), 1);
    /// ```
    #[must_use]
    pub fn with_placed(mut self, parts: impl IntoIterator<Item = Primitive>) -> Self {
        self.set_placed(parts);
        self
    }

    /// Sets the parts placed before the one this context snaps (see
    /// [`SnapContext::with_placed`]), in place of those it had.
    pub fn set_placed(&mut self, parts: impl IntoIterator<Item = Primitive>) {
        self.placed = parts
            .into_iter()
            .filter(Primitive::is_finite)
            .filter_map(|primitive| {
                let image = image_box(&primitive)?;
                Some(PlacedPart { primitive, image })
            })
            .collect();
    }

    /// The parts placed before the one this context snaps (see
    /// [`SnapContext::with_placed`]).
    pub fn placed(&self) -> impl Iterator<Item = &Primitive> {
        self.placed.iter().map(|p| &p.primitive)
    }

    /// Prepares a whole sketch: preprocessing (dots dropped, duplicate strokes merged,
    /// strokes resampled and lightly smoothed, all relative to the sketch's size) and
    /// automatic classification, with user overrides winning. Stroke ids are kept.
    /// [`SnapContext::prepare`] also says what the preprocessing changed.
    pub fn from_sketch(sketch: &Sketch) -> Self {
        Self::prepare(sketch).context
    }

    /// [`SnapContext::from_sketch`], with what the preparation merged and dropped: the
    /// count a user interface or the command line reports as "merged N duplicate
    /// strokes" is `prepared.merged.len()`.
    ///
    /// # Examples
    ///
    /// ```
    /// use geosnap_core::sketch::{Sketch, Stroke, StrokeId};
    /// use geosnap_core::snap::SnapContext;
    /// use glam::DVec2;
    ///
    /// let line = |id| Stroke {
    ///     id: StrokeId(id),
    ///     points: vec![DVec2::ZERO, DVec2::new(300.0, 100.0)],
    ///     closed: false,
    ///     class_override: None,
    /// };
    /// // The same line pasted twice.
    /// let sketch = Sketch { strokes: vec![line(0), line(1)], view_box: None };
    /// let prepared = SnapContext::prepare(&sketch);
    /// assert_eq!(prepared.context.strokes.len(), 1);
    /// assert_eq!(prepared.merged.len(), 1);
    /// ```
    pub fn prepare(sketch: &Sketch) -> Prepared {
        let done = preprocess_report(sketch, &PreprocessOptions::default());
        let classes = classify_sketch(&done.sketch, &ClassifyOptions::default());
        let context = Self::new(
            done.sketch
                .strokes
                .iter()
                .zip(&classes)
                .map(|(stroke, c)| (stroke.id, stroke.points.as_slice(), c.class)),
        );
        Prepared {
            context,
            merged: done.merged,
            notes: done.notes,
        }
    }

    /// The stroke with this id.
    pub fn stroke(&self, id: StrokeId) -> Option<&SnapStroke> {
        self.strokes.iter().find(|s| s.id == id)
    }
}

/// A sketch prepared for snapping ([`SnapContext::prepare`]) and what the preparation
/// changed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prepared {
    /// The strokes ready for snapping.
    pub context: SnapContext,
    /// The duplicate strokes merged into earlier ones (exact and near duplicates): a
    /// user is told "merged N duplicate strokes" with `N = merged.len()`.
    pub merged: Vec<MergedStroke>,
    /// One human-readable note per stroke or point dropped or merged, in stroke order.
    pub notes: Vec<String>,
}

/// A stroke (or a piece of one) prepared for matching: its length, bounds, principal
/// direction and straightness; `None` for fewer than two points or no length.
pub(crate) fn prepare(id: StrokeId, points: Vec<DVec2>, class: StrokeClass) -> Option<SnapStroke> {
    if points.len() < 2 {
        return None;
    }
    let length: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
    if !(length > 0.0) {
        return None;
    }
    let n = points.len() as f64;
    let mean = points.iter().copied().sum::<DVec2>() / n;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in &points {
        let d = *p - mean;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    // Principal direction of the 2×2 scatter matrix.
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let direction = DVec2::from_angle(angle);
    let normal = direction.perp();
    let rms = (points
        .iter()
        .map(|p| (*p - mean).dot(normal).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let t = p.dot(direction);
            (lo.min(t), hi.max(t))
        });
    let straightness = rms / (hi - lo).max(f64::MIN_POSITIVE);
    let bounds = points.iter().fold((points[0], points[0]), |(lo, hi), p| {
        (lo.min(*p), hi.max(*p))
    });
    Some(SnapStroke {
        id,
        straight: rms <= 0.02 * length,
        straightness,
        direction,
        bounds,
        length,
        points,
        class,
    })
}
