//! Overlay pictures of a snap for diagnosis: the strokes grey, the truth green, the
//! dropped primitive blue and the snapped one red, fitted into a 900 × 900 PNG.

use std::path::Path;

use geosnap::core::geom::projection::sketch_from_view;
use geosnap::core::primitive::{Curve2, Primitive};
use glam::DVec2;

/// A view-plane curve as sketch points.
pub(crate) fn curve_points(curve: &Curve2<f64>) -> Vec<DVec2> {
    curve.points(96).into_iter().map(sketch_from_view).collect()
}

/// Writes an overlay: `strokes` grey, `truth` green, `dropped` blue and `snapped` red
/// (their visible projected curves).
pub(crate) fn write_overlay(
    path: &Path,
    strokes: &[&[DVec2]],
    truth: &Primitive,
    dropped: &Primitive,
    snapped: Option<&Primitive>,
) -> Result<(), String> {
    use tiny_skia::{Color, Paint, PathBuilder, Pixmap, Stroke, Transform};
    let mut layers: Vec<(Vec<Vec<DVec2>>, [u8; 4], f32)> = Vec::new();
    let strokes: Vec<Vec<DVec2>> = strokes.iter().map(|s| s.to_vec()).collect();
    layers.push((strokes, [150, 150, 150, 255], 2.5));
    let curves = |p: &Primitive| -> Vec<Vec<DVec2>> {
        p.current_shape()
            .curves
            .iter()
            .filter(|c| c.visible)
            .map(|c| curve_points(&c.curve))
            .collect()
    };
    layers.push((curves(truth), [0, 160, 0, 220], 1.5));
    layers.push((curves(dropped), [40, 80, 255, 200], 1.2));
    if let Some(p) = snapped {
        layers.push((curves(p), [220, 0, 0, 230], 1.2));
    }
    let all = layers.iter().flat_map(|l| l.0.iter().flatten());
    let (lo, hi) = all.fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let side = 900.0;
    let margin = 20.0;
    let scale = (side - 2.0 * margin) / (hi - lo).max_element().max(1e-9);
    let mut pixmap = Pixmap::new(side as u32, side as u32).ok_or("no pixmap")?;
    pixmap.fill(Color::WHITE);
    for (lines, [r, g, b, a], width) in &layers {
        let mut paint = Paint::default();
        paint.set_color_rgba8(*r, *g, *b, *a);
        paint.anti_alias = true;
        let stroke = Stroke {
            width: *width,
            ..Stroke::default()
        };
        for line in lines {
            let mut pb = PathBuilder::new();
            for (i, p) in line.iter().enumerate() {
                let q = (*p - lo) * scale + DVec2::splat(margin);
                if i == 0 {
                    pb.move_to(q.x as f32, q.y as f32);
                } else {
                    pb.line_to(q.x as f32, q.y as f32);
                }
            }
            if let Some(path) = pb.finish() {
                pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
            }
        }
    }
    pixmap.save_png(path).map_err(|e| e.to_string())
}
