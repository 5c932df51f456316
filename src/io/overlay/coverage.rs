//! Drawing a very long polyline through a coverage mask.
//!
//! tiny-skia composites every stroked path on its own, in short runs of pixels, so a
//! stroke of a hundred thousand long segments thrown over the page (a scribble) costs a
//! pipeline call for every few pixels of every segment: tens of seconds, although the
//! page holds only a million pixels. Here the stroke's coverage is computed into a mask
//! over its bounds instead (each pixel keeps the largest coverage any segment gives it,
//! so overlaps merge as in the path's own fill), and the mask is composited once.
//!
//! A segment covers a pixel by how far the pixel's centre lies inside the segment's
//! outline (a capsule `width / 2` around it, round caps and joins, as the pen draws it),
//! with one pixel of anti-aliasing across the edge: `clamp(width / 2 + 0.5 − d, 0, 1)`
//! for the distance `d` from the centre to the segment. A segment's work is its length
//! times a few pixels across, whatever its direction.

use glam::DVec2;
use tiny_skia::{Mask, Paint, Pixmap, Rect, Transform};

/// Draws the polyline `points` (pixels) `width` wide in `paint` onto `pixmap`, through a
/// coverage mask composited over the polyline's bounds (see the module docs). Parts
/// outside the image are clipped; nothing is drawn for no points or a non-positive
/// width.
pub(super) fn draw_through_mask(
    pixmap: &mut Pixmap,
    points: &[DVec2],
    width: f64,
    paint: &Paint<'_>,
) {
    let Some(rect) = bounds_on(pixmap, points, width) else {
        return;
    };
    // tiny-skia takes a mask the size of the image, in the image's pixels.
    let Some(mut mask) = Mask::new(pixmap.width(), pixmap.height()) else {
        return;
    };
    let radius = width / 2.0 + 0.5;
    let size = (mask.width() as usize, mask.height() as usize);
    let data = mask.data_mut();
    if let [single] = points {
        add_segment(data, size, *single, *single, radius);
    }
    for w in points.windows(2) {
        add_segment(data, size, w[0], w[1], radius);
    }
    pixmap.fill_rect(rect, paint, Transform::identity(), Some(&mask));
}

/// The part of `pixmap` that the polyline `points`, `width` wide, may cover (whole
/// pixels); `None` when that is nothing.
fn bounds_on(pixmap: &Pixmap, points: &[DVec2], width: f64) -> Option<Rect> {
    if !(width > 0.0) {
        return None;
    }
    let reach = width / 2.0 + 1.0;
    let (lo, hi) = points.iter().filter(|p| p.is_finite()).fold(
        None,
        |bounds: Option<(DVec2, DVec2)>, p| {
            Some(bounds.map_or((*p, *p), |(lo, hi)| (lo.min(*p), hi.max(*p))))
        },
    )?;
    let image = DVec2::new(f64::from(pixmap.width()), f64::from(pixmap.height()));
    let lo = (lo - reach).floor().clamp(DVec2::ZERO, image);
    let hi = (hi + reach).ceil().clamp(DVec2::ZERO, image);
    let size = hi - lo;
    if !(size.x >= 1.0 && size.y >= 1.0) {
        return None;
    }
    Rect::from_xywh(lo.x as f32, lo.y as f32, size.x as f32, size.y as f32)
}

/// Adds the coverage of the segment `a`–`b` (pixels), `radius`
/// around it including the anti-aliased pixel (see the module docs), to the mask `data`
/// of `size` (width, height): each pixel keeps the larger coverage. The segment is
/// walked along its major axis, one row (or column) of pixels at a time, over the few
/// pixels across it that it can reach.
fn add_segment(data: &mut [u8], size: (usize, usize), a: DVec2, b: DVec2, radius: f64) {
    if !(a.is_finite() && b.is_finite() && radius > 0.0) {
        return;
    }
    // In (major, minor) coordinates: x along the segment's major axis.
    let steep = (b.y - a.y).abs() > (b.x - a.x).abs();
    let swap = |p: DVec2| if steep { DVec2::new(p.y, p.x) } else { p };
    let (major_size, minor_size) = if steep { (size.1, size.0) } else { size };
    let (p, q) = (swap(a), swap(b));
    let (lo, hi) = if p.x <= q.x { (p, q) } else { (q, p) };
    let slope = if hi.x > lo.x {
        (hi.y - lo.y) / (hi.x - lo.x)
    } else {
        0.0
    };
    let span = |from: f64, to: f64, limit: usize| {
        let limit = limit as f64;
        (
            from.floor().clamp(0.0, limit) as usize,
            to.ceil().clamp(0.0, limit) as usize,
        )
    };
    // Every pixel within `radius` of the segment lies within `radius` of its line, so
    // within `radius·√(1 + slope²)` across of the line's point in that row.
    let half = radius * (1.0 + slope * slope).sqrt();
    let along = hi - lo;
    let inverse = if along.length_squared() > 0.0 {
        along.length_squared().recip()
    } else {
        0.0
    };
    let reach = radius * radius;
    let (first, last) = span(lo.x - radius, hi.x + radius, major_size);
    for i in first..last {
        let centre = i as f64 + 0.5;
        let across = lo.y + (centre - lo.x) * slope;
        let (from, to) = span(across - half - 0.5, across + half + 0.5, minor_size);
        for j in from..to {
            let index = if steep {
                i * size.0 + j
            } else {
                j * size.0 + i
            };
            // A pixel already fully covered stays so (a scribble covers most many times).
            let Some(value) = data.get_mut(index).filter(|v| **v < u8::MAX) else {
                continue;
            };
            let pixel = DVec2::new(centre, j as f64 + 0.5);
            let t = ((pixel - lo).dot(along) * inverse).clamp(0.0, 1.0);
            let squared = pixel.distance_squared(lo + along * t);
            if squared < reach {
                *value = (*value).max(to_byte((radius - squared.sqrt()).min(1.0)));
            }
        }
    }
}

/// A coverage in [0, 1] as a mask byte (rounded).
fn to_byte(coverage: f64) -> u8 {
    (coverage * 255.0 + 0.5).clamp(0.0, 255.0) as u8
}

#[cfg(test)]
mod tests {
    use glam::DVec2;
    use tiny_skia::{Color, Paint, Pixmap};

    use super::{add_segment, draw_through_mask, to_byte};

    /// The distance from `p` to the segment `a`–`b`.
    fn segment_distance(a: DVec2, b: DVec2, p: DVec2) -> f64 {
        let ab = b - a;
        let length_squared = ab.length_squared();
        let t = if length_squared > 0.0 {
            ((p - a).dot(ab) / length_squared).clamp(0.0, 1.0)
        } else {
            0.0
        };
        p.distance(a + ab * t)
    }

    /// The coverage every pixel of a `size` mask gets from the segment `a`–`b`, by
    /// testing every pixel.
    fn every_pixel(size: (usize, usize), a: DVec2, b: DVec2, radius: f64) -> Vec<u8> {
        let mut data = vec![0; size.0 * size.1];
        for y in 0..size.1 {
            for x in 0..size.0 {
                let pixel = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                let distance = segment_distance(a, b, pixel);
                data[y * size.0 + x] = if distance < radius {
                    to_byte((radius - distance).min(1.0))
                } else {
                    0
                };
            }
        }
        data
    }

    #[test]
    fn a_segment_covers_exactly_the_pixels_within_its_reach() {
        let size = (60, 50);
        let segments = [
            (DVec2::new(5.2, 7.9), DVec2::new(50.3, 12.1)),
            (DVec2::new(5.2, 7.9), DVec2::new(12.3, 45.1)),
            (DVec2::new(50.0, 3.0), DVec2::new(3.0, 47.0)),
            (DVec2::new(30.0, 20.0), DVec2::new(30.0, 20.0)),
            (DVec2::new(-20.0, -5.0), DVec2::new(80.0, 70.0)),
            (DVec2::new(10.5, 40.5), DVec2::new(55.5, 40.5)),
        ];
        for radius in [1.25, 2.5, 0.3] {
            for (a, b) in segments {
                let mut data = vec![0; size.0 * size.1];
                add_segment(&mut data, size, a, b, radius);
                assert_eq!(data, every_pixel(size, a, b, radius), "{a} – {b}, {radius}");
            }
        }
    }

    #[test]
    fn a_long_polyline_is_drawn_where_it_runs() {
        let mut pixmap = Pixmap::new(100, 80).expect("a size");
        pixmap.fill(Color::WHITE);
        let mut paint = Paint::default();
        paint.set_color_rgba8(170, 170, 170, 255);
        let zigzag: Vec<DVec2> = (0..5000)
            .map(|i| {
                DVec2::new(
                    20.0 + 0.01 * f64::from(i),
                    if i % 2 == 0 { 10.0 } else { 70.0 },
                )
            })
            .collect();
        draw_through_mask(&mut pixmap, &zigzag, 1.5, &paint);
        let at = |x: u32, y: u32| pixmap.pixel(x, y).expect("inside").red();
        assert_eq!(at(40, 40), 170, "inside the zigzag");
        assert_eq!(at(10, 40), 255, "left of it");
        assert_eq!(at(90, 40), 255, "right of it");
        assert_eq!(at(40, 5), 255, "above it");
    }

    #[test]
    fn overlaps_keep_the_larger_coverage_and_bad_input_draws_nothing() {
        let size = (20, 20);
        let mut data = vec![0; 400];
        add_segment(
            &mut data,
            size,
            DVec2::new(2.0, 10.5),
            DVec2::new(18.0, 10.5),
            1.25,
        );
        let once = data.clone();
        add_segment(
            &mut data,
            size,
            DVec2::new(2.0, 10.5),
            DVec2::new(18.0, 10.5),
            1.25,
        );
        assert_eq!(data, once, "drawing twice changes nothing");
        assert_eq!(data[10 * 20 + 10], 255, "on the line");
        let mut blank = vec![0; 400];
        add_segment(&mut blank, size, DVec2::NAN, DVec2::ONE, 1.25);
        add_segment(&mut blank, size, DVec2::ZERO, DVec2::ONE, -1.0);
        assert!(blank.iter().all(|v| *v == 0), "nothing drawn");
        // Far beyond the image: no panic, whatever it covers.
        add_segment(
            &mut blank,
            size,
            DVec2::splat(1e300),
            DVec2::splat(-1e300),
            1.25,
        );
    }
}
