//! The overlay PNG: the strokes in grey, each primitive's projected curves in its own
//! colour, and the strokes it was assigned drawn over in that colour, so a person can
//! check a run at a glance; and a small label per relation (`PAR`, `COAX`, `R=`, ...)
//! linked by thin lines to the features it relates (grey for soft relations, light red
//! for those switched off). Drawn with tiny-skia; the labels use a small built-in stroke
//! font, as tiny-skia draws no text.

mod coverage;
mod polyline;

use std::path::Path;

use glam::DVec2;
use tiny_skia::{Color, LineCap, LineJoin, Paint, PathBuilder, Pixmap, Stroke as Pen, Transform};

use crate::core::geom::projection::sketch_from_view;
use crate::core::model::Document;
use crate::core::primitive::{FeatureGeometry, Primitive};
use crate::core::relation::{Mode, RelationKind};
use crate::core::sketch::{Sketch, StrokeClass, StrokeId};
use crate::io::atomic::write_atomic;

/// One primitive to draw, with the strokes assigned to it.
#[derive(Clone, Debug)]
pub struct OverlayItem<'a> {
    /// The primitive (model space).
    pub primitive: &'a Primitive,
    /// Its assigned strokes.
    pub strokes: &'a [StrokeId],
}

/// One relation to mark: its kind, the sketch-space points of the features it relates,
/// and its mode.
#[derive(Clone, Debug)]
pub struct OverlayRelation {
    /// The kind.
    pub kind: RelationKind,
    /// The projected centre of each member's feature, in sketch space.
    pub anchors: Vec<DVec2>,
    /// The mode.
    pub mode: Mode,
}

impl OverlayRelation {
    /// The marks of every relation of `document`.
    pub fn of_document(document: &Document) -> Vec<Self> {
        document
            .relations()
            .iter()
            .map(|r| Self {
                kind: r.kind,
                anchors: r
                    .members
                    .iter()
                    .enumerate()
                    .filter_map(|(k, id)| {
                        let primitive = &document.get(*id)?.primitive;
                        let feature = r.features.get(k).copied().flatten();
                        let shape = primitive.current_shape();
                        let centre = feature
                            .and_then(|feature| {
                                shape.features.iter().find(|f| f.feature == feature)
                            })
                            .map_or(primitive.center(), |f| match &f.geometry {
                                FeatureGeometry::Circle { center, .. }
                                | FeatureGeometry::Rectangle { center, .. } => center.to_dvec3(),
                            });
                        Some(sketch_from_view(centre.truncate()))
                    })
                    .collect(),
                mode: r.mode,
            })
            .collect()
    }
}

/// The label of a relation kind.
fn label(kind: RelationKind) -> &'static str {
    match kind {
        RelationKind::Parallel => "PAR",
        RelationKind::Orthogonal => "ORTH",
        RelationKind::Coaxial => "COAX",
        RelationKind::Concentric => "CONC",
        RelationKind::Coplanar => "COPL",
        RelationKind::CollinearCenters => "COL",
        RelationKind::SameRadius => "R=",
        RelationKind::EqualLength => "L=",
        RelationKind::OnSphere => "SPH",
    }
}

/// The strokes of a glyph on a 4 × 6 grid (y down), as polylines.
fn glyph(c: char) -> &'static [&'static [(u8, u8)]] {
    match c {
        'A' => &[&[(0, 6), (0, 2), (2, 0), (4, 2), (4, 6)], &[(0, 3), (4, 3)]],
        'C' => &[&[(4, 0), (0, 0), (0, 6), (4, 6)]],
        'H' => &[&[(0, 0), (0, 6)], &[(4, 0), (4, 6)], &[(0, 3), (4, 3)]],
        'L' => &[&[(0, 0), (0, 6), (4, 6)]],
        'N' => &[&[(0, 6), (0, 0), (4, 6), (4, 0)]],
        'O' => &[&[(0, 0), (4, 0), (4, 6), (0, 6), (0, 0)]],
        'P' => &[&[(0, 6), (0, 0), (4, 0), (4, 3), (0, 3)]],
        'R' => &[&[(0, 6), (0, 0), (4, 0), (4, 3), (0, 3), (4, 6)]],
        'S' => &[&[(4, 0), (0, 0), (0, 3), (4, 3), (4, 6), (0, 6)]],
        'T' => &[&[(0, 0), (4, 0)], &[(2, 0), (2, 6)]],
        'X' => &[&[(0, 0), (4, 6)], &[(4, 0), (0, 6)]],
        '=' => &[&[(0, 2), (4, 2)], &[(0, 4), (4, 4)]],
        _ => &[],
    }
}

/// Where labels go: the mean of the anchors, moved down while it would cover an earlier
/// label.
fn place(anchors: &[DVec2], taken: &mut Vec<DVec2>, step: f64) -> Option<DVec2> {
    let n = anchors.len();
    if n == 0 {
        return None;
    }
    let mut at = anchors.iter().copied().sum::<DVec2>() / n as f64;
    while taken
        .iter()
        .any(|t| (t.y - at.y).abs() < step && (t.x - at.x).abs() < 4.0 * step)
    {
        at.y += step;
    }
    taken.push(at);
    Some(at)
}

/// Why an overlay could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OverlayError {
    /// The image could not be encoded.
    #[error("cannot encode the overlay image: {0}")]
    Encode(String),
    /// The file could not be written.
    #[error("cannot write {}", path.display())]
    Write {
        /// The file.
        path: std::path::PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
}

/// Distinct colours for primitives (a qualitative palette, cycled).
const PALETTE: [(u8, u8, u8); 10] = [
    (228, 26, 28),
    (55, 126, 184),
    (77, 175, 74),
    (152, 78, 163),
    (255, 127, 0),
    (166, 86, 40),
    (247, 129, 191),
    (0, 166, 166),
    (180, 160, 0),
    (90, 90, 200),
];

/// The largest side of the image, in pixels.
const MAX_SIDE: f64 = 1400.0;

/// A polyline of more segments than this (after simplifying) is drawn through a coverage
/// mask (see [`coverage`]): tiny-skia's cost per segment is too high for a scribble of a
/// hundred thousand. The strokes of a drawing have a few hundred at most.
const MASKED_SEGMENTS: usize = 4096;

/// How far (in pixels) simplifying a polyline before drawing may move it: a quarter of a
/// pixel, which anti-aliasing hides.
const SIMPLIFY_TOLERANCE: f64 = 0.25;

/// Renders the overlay as PNG bytes.
///
/// # Errors
///
/// [`OverlayError::Encode`] if the image cannot be made (for example an empty sketch of
/// zero size is drawn as a small blank image instead).
pub fn overlay_png(
    sketch: &Sketch,
    items: &[OverlayItem<'_>],
    relations: &[OverlayRelation],
) -> Result<Vec<u8>, OverlayError> {
    let (canvas, mut pixmap) = Canvas::new(sketch)?;
    let draw =
        |pixmap: &mut Pixmap, points: &[DVec2], closed: bool, rgb: (u8, u8, u8), width: f32| {
            canvas.draw(pixmap, points, closed, rgb, width);
        };
    for stroke in &sketch.strokes {
        draw(
            &mut pixmap,
            &stroke.points,
            stroke.closed,
            (170, 170, 170),
            1.5,
        );
    }
    for (i, item) in items.iter().enumerate() {
        let rgb = PALETTE[i % PALETTE.len()];
        let light = (
            rgb.0.midpoint(255),
            rgb.1.midpoint(255),
            rgb.2.midpoint(255),
        );
        for id in item.strokes {
            if let Some(stroke) = sketch.stroke(*id) {
                draw(&mut pixmap, &stroke.points, stroke.closed, light, 4.0);
            }
        }
        for curve in item.primitive.current_shape().curves {
            if !curve.visible {
                continue;
            }
            let points = curve.curve.points(64);
            let sketch_points: Vec<DVec2> = points.into_iter().map(sketch_from_view).collect();
            draw(&mut pixmap, &sketch_points, false, rgb, 2.0);
        }
        // A small cross at the centre.
        let c = sketch_from_view(item.primitive.center().truncate());
        let r = 6.0 / canvas.scale;
        draw(
            &mut pixmap,
            &[c - DVec2::new(r, 0.0), c + DVec2::new(r, 0.0)],
            false,
            rgb,
            2.0,
        );
        draw(
            &mut pixmap,
            &[c - DVec2::new(0.0, r), c + DVec2::new(0.0, r)],
            false,
            rgb,
            2.0,
        );
    }
    // Relations: a label at the mean of the features, linked to each of them.
    let unit = 2.0 / canvas.scale; // one grid step of the font: 2 pixels
    let mut taken = Vec::new();
    for relation in relations {
        let rgb = match relation.mode {
            Mode::Hard => (40, 40, 40),
            Mode::Soft => (130, 130, 130),
            Mode::Off => (235, 150, 150),
            Mode::Suggested => (70, 120, 200),
        };
        let Some(at) = place(&relation.anchors, &mut taken, 9.0 * unit) else {
            continue;
        };
        for anchor in &relation.anchors {
            draw(&mut pixmap, &[at, *anchor], false, (190, 190, 190), 0.75);
        }
        let text = label(relation.kind);
        let width = text.chars().count() as f64 * 6.0 * unit;
        let origin = at - DVec2::new(width / 2.0, 3.0 * unit);
        for (k, c) in text.chars().enumerate() {
            let left = origin + DVec2::new(k as f64 * 6.0 * unit, 0.0);
            for line in glyph(c) {
                let points: Vec<DVec2> = line
                    .iter()
                    .map(|(x, y)| left + DVec2::new(f64::from(*x), f64::from(*y)) * unit)
                    .collect();
                draw(&mut pixmap, &points, false, rgb, 1.5);
            }
        }
    }
    pixmap
        .encode_png()
        .map_err(|e| OverlayError::Encode(e.to_string()))
}

/// The image of a sketch: white, its view box (or stroke bounds) scaled to at most
/// `MAX_SIDE` pixels.
struct Canvas {
    lo: DVec2,
    scale: f64,
}

impl Canvas {
    fn new(sketch: &Sketch) -> Result<(Self, Pixmap), OverlayError> {
        let (lo, hi) = sketch
            .view_box
            .map(|(min, size)| (min, min + size))
            .or_else(|| sketch.bounds())
            .unwrap_or((DVec2::ZERO, DVec2::splat(100.0)));
        let extent = (hi - lo).max(DVec2::splat(1e-9));
        let scale = MAX_SIDE / extent.max_element();
        let width = (extent.x * scale).ceil().clamp(16.0, MAX_SIDE) as u32;
        let height = (extent.y * scale).ceil().clamp(16.0, MAX_SIDE) as u32;
        let mut pixmap =
            Pixmap::new(width, height).ok_or_else(|| OverlayError::Encode("bad size".into()))?;
        pixmap.fill(Color::WHITE);
        Ok((Self { lo, scale }, pixmap))
    }

    /// Strokes a polyline given in sketch space: simplified to the pixel grid (it moves
    /// by at most [`SIMPLIFY_TOLERANCE`] pixels), then drawn in pieces of at most
    /// [`polyline::PIECE_SEGMENTS`] segments, or, beyond [`MASKED_SEGMENTS`] segments,
    /// through a coverage mask (see [`coverage`]), so that its cost grows with its
    /// length however dense or tangled it is (see [`polyline`]).
    fn draw(
        &self,
        pixmap: &mut Pixmap,
        points: &[DVec2],
        closed: bool,
        rgb: (u8, u8, u8),
        width: f32,
    ) {
        let mut pixels: Vec<DVec2> = points
            .iter()
            .filter(|p| p.is_finite())
            .map(|p| (*p - self.lo) * self.scale)
            .collect();
        if closed {
            if let Some(&first) = pixels.first() {
                pixels.push(first);
            }
        }
        let pixels = polyline::simplify(&pixels, SIMPLIFY_TOLERANCE);
        let mut paint = Paint::default();
        paint.set_color_rgba8(rgb.0, rgb.1, rgb.2, 255);
        paint.anti_alias = true;
        let pen = Pen {
            width,
            line_cap: LineCap::Round,
            line_join: LineJoin::Round,
            ..Pen::default()
        };
        if pixels.len() > MASKED_SEGMENTS {
            coverage::draw_through_mask(pixmap, &pixels, f64::from(width), &paint);
            return;
        }
        for piece in polyline::pieces(&pixels, polyline::PIECE_SEGMENTS) {
            let mut pb = PathBuilder::new();
            let mut iter = piece.iter().map(|p| (p.x as f32, p.y as f32));
            let Some((x, y)) = iter.next() else { continue };
            pb.move_to(x, y);
            for (x, y) in iter {
                pb.line_to(x, y);
            }
            if let Some(path) = pb.finish() {
                pixmap.stroke_path(&path, &paint, &pen, Transform::identity(), None);
            }
        }
    }
}

/// Renders a sketch with its strokes coloured by class, as PNG bytes: features (end
/// ellipses and arcs) blue, silhouettes black; strokes missing from `classes` grey.
///
/// # Errors
///
/// [`OverlayError::Encode`] if the image cannot be made.
pub fn classes_png(
    sketch: &Sketch,
    classes: &[(StrokeId, StrokeClass)],
) -> Result<Vec<u8>, OverlayError> {
    let (canvas, mut pixmap) = Canvas::new(sketch)?;
    for stroke in &sketch.strokes {
        let class = classes.iter().find(|(id, _)| *id == stroke.id).map(|c| c.1);
        let (rgb, width) = match class {
            Some(StrokeClass::Feature) => ((31, 119, 180), 3.0),
            Some(StrokeClass::Silhouette) => ((20, 20, 20), 2.0),
            None => ((170, 170, 170), 1.5),
        };
        canvas.draw(&mut pixmap, &stroke.points, stroke.closed, rgb, width);
    }
    pixmap
        .encode_png()
        .map_err(|e| OverlayError::Encode(e.to_string()))
}

/// Renders the overlay and writes it atomically to `path`.
///
/// # Errors
///
/// [`OverlayError`] when it cannot be encoded or written.
pub fn save_overlay(
    path: impl AsRef<Path>,
    sketch: &Sketch,
    items: &[OverlayItem<'_>],
    relations: &[OverlayRelation],
) -> Result<(), OverlayError> {
    let path = path.as_ref();
    let bytes = overlay_png(sketch, items, relations)?;
    write_atomic(path, &bytes).map_err(|source| OverlayError::Write {
        path: path.to_owned(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::{glyph, label, overlay_png, OverlayItem, OverlayRelation};
    use crate::core::primitive::{Primitive, Sphere};
    use crate::core::relation::{Mode, RelationKind};
    use crate::core::sketch::{Sketch, Stroke, StrokeId};

    #[test]
    fn an_overlay_is_a_png_and_empty_input_is_fine() {
        let sketch = Sketch {
            strokes: vec![Stroke {
                id: StrokeId(0),
                points: vec![DVec2::new(0.0, 0.0), DVec2::new(100.0, 50.0)],
                closed: false,
                class_override: None,
            }],
            view_box: None,
        };
        let sphere = Primitive::Sphere(Sphere {
            center: DVec3::new(50.0, -25.0, 0.0),
            radius: 20.0,
        });
        let png = overlay_png(
            &sketch,
            &[OverlayItem {
                primitive: &sphere,
                strokes: &[StrokeId(0)],
            }],
            &[OverlayRelation {
                kind: RelationKind::Coaxial,
                anchors: vec![DVec2::new(10.0, 10.0), DVec2::new(50.0, 25.0)],
                mode: Mode::Off,
            }],
        )
        .unwrap();
        assert_eq!(&png[1..4], b"PNG");
        assert!(overlay_png(&Sketch::default(), &[], &[]).is_ok());
    }

    #[test]
    fn every_relation_label_can_be_drawn() {
        for kind in RelationKind::ALL {
            for c in label(kind).chars() {
                assert!(!glyph(c).is_empty(), "{kind:?}: no glyph for {c:?}");
            }
        }
    }
}
