//! The region of the drawing a point lies in: what a drop that points at a part says of
//! its size, shape and direction.
//!
//! A part is drawn by its outlines, so a point inside a part's picture is enclosed by
//! strokes: rays cast from it meet the part's own outlines first. The region they
//! enclose (the part of the picture seen from the point) has the part's proportions: a
//! table leg's region is as thin as the leg, a lying rod's runs across the page, a
//! disc's top ellipse is as wide as the disc. The ladder of sizes of a point drop
//! (see [`super::point`]) guesses sizes and directions from the drawing around the
//! point, but only in the proportions of the palette's primitives (a rod a third as
//! wide as it is long): on a rod ten times as long as it is wide, a guess as long as
//! the rod reads its neighbours' outlines, and one as wide as it is short. The region
//! gives the guess the part's own proportions.
//!
//! The region is read from [`RAYS`] rays. A ray that meets no stroke within reach has
//! left through a gap (a missing stroke, an open end): its wedge is left out, and a
//! region most of whose rays leave is no region ([`CLOSED`]). A stroke through the
//! point itself (a hidden line, an ellipse the drop lands on) would cut the region to a
//! sliver: hits much nearer than the typical one ([`THROUGH`]) are passed through.

use glam::DVec2;

use super::SnapContext;

/// Rays cast from the point.
pub(super) const RAYS: usize = 64;

/// A region is read only where at least this share of the rays meet a stroke.
const CLOSED: f64 = 0.75;

/// A ray's hit nearer than this share of the median hit distance is a stroke through
/// the point, and the ray goes on past it.
const THROUGH: f64 = 0.15;

/// The region around a point (view space, y up): its centroid, its major direction,
/// and its half extents along the major and minor directions (those of a rectangle
/// with its second moments).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Region {
    /// The region's centroid.
    pub(super) centre: DVec2,
    /// Its major direction (a unit vector, pointing up or right).
    pub(super) major: DVec2,
    /// Its half extent along `major`.
    pub(super) half_major: f64,
    /// Its half extent across `major`.
    pub(super) half_minor: f64,
}

impl Region {
    /// The direction across the major one (a unit vector, pointing up or left).
    pub(super) fn minor(&self) -> DVec2 {
        self.major.perp()
    }
}

/// The region of the drawing of `context` around view point `point`, read from rays
/// reaching at most `reach`; `None` where too few rays meet a stroke (the point is not
/// enclosed) or the region has no area.
pub(super) fn region_at(context: &SnapContext, point: DVec2, reach: f64) -> Option<Region> {
    if !(point.is_finite() && reach.is_finite() && reach > 0.0) {
        return None;
    }
    let directions: Vec<DVec2> = (0..RAYS)
        .map(|k| DVec2::from_angle(std::f64::consts::TAU * k as f64 / RAYS as f64))
        .collect();
    // Every ray's hits, nearest first, by the strokes whose bounds lie within reach.
    let mut hits: Vec<Vec<f64>> = vec![Vec::new(); RAYS];
    for stroke in &context.strokes {
        let (lo, hi) = stroke.bounds;
        if (lo - point).max(point - hi).max(DVec2::ZERO).length() > reach {
            continue;
        }
        for pair in stroke.points.windows(2) {
            for (ray, d) in hits.iter_mut().zip(&directions) {
                if let Some(t) = ray_hit(point, *d, pair[0], pair[1])
                    && t <= reach
                {
                    ray.push(t);
                }
            }
        }
    }
    for ray in &mut hits {
        ray.sort_by(f64::total_cmp);
    }
    let mut firsts: Vec<f64> = hits.iter().filter_map(|r| r.first().copied()).collect();
    if (firsts.len() as f64) < CLOSED * RAYS as f64 {
        return None;
    }
    firsts.sort_by(f64::total_cmp);
    let through = THROUGH * firsts[firsts.len() / 2];
    let reached: Vec<Option<DVec2>> = hits
        .iter()
        .zip(&directions)
        .map(|(ray, d)| ray.iter().find(|t| **t > through).map(|t| *d * *t))
        .collect();
    moments(&reached).map(|(centre, xx, xy, yy)| {
        let angle = 0.5 * (2.0 * xy).atan2(xx - yy);
        let major = DVec2::from_angle(angle);
        let major = if major.y < 0.0 || (major.y == 0.0 && major.x < 0.0) {
            -major
        } else {
            major
        };
        let spread = (0.25 * (xx - yy).powi(2) + xy * xy).sqrt();
        let mean = 0.5 * (xx + yy);
        Region {
            centre: point + centre,
            major,
            half_major: (3.0 * (mean + spread)).max(0.0).sqrt(),
            half_minor: (3.0 * (mean - spread)).max(0.0).sqrt(),
        }
    })
}

/// Where the ray from `from` along unit `d` meets the segment `a`–`b`: the distance
/// along the ray, `None` when it misses or runs along it.
fn ray_hit(from: DVec2, d: DVec2, a: DVec2, b: DVec2) -> Option<f64> {
    let e = b - a;
    let denom = d.perp_dot(e);
    if denom.abs() < 1e-12 * e.length() {
        return None;
    }
    let w = a - from;
    let t = w.perp_dot(e) / denom;
    let s = w.perp_dot(d) / denom;
    (t > 0.0 && (0.0..=1.0).contains(&s)).then_some(t)
}

/// The centroid and central second moments (per unit area: xx, xy, yy) of the
/// fan of triangles between the point (the origin) and each two neighbouring rays'
/// hits; a wedge with a ray that met nothing is left out. `None` without area.
fn moments(reached: &[Option<DVec2>]) -> Option<(DVec2, f64, f64, f64)> {
    let (mut area, mut first) = (0.0, DVec2::ZERO);
    let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
    for (k, a) in reached.iter().enumerate() {
        let (Some(a), Some(b)) = (a, reached[(k + 1) % reached.len()]) else {
            continue;
        };
        let w = 0.5 * a.perp_dot(b);
        if w <= 0.0 {
            continue;
        }
        // The triangle (0, a, b): its first moment is w (a + b) / 3, its second
        // w / 6 (a aᵀ + b bᵀ + (a bᵀ + b aᵀ) / 2).
        area += w;
        first += w * (*a + b) / 3.0;
        xx += w / 6.0 * (a.x * a.x + b.x * b.x + a.x * b.x);
        yy += w / 6.0 * (a.y * a.y + b.y * b.y + a.y * b.y);
        xy += w / 6.0 * (a.x * a.y + b.x * b.y + 0.5 * (a.x * b.y + b.x * a.y));
    }
    if area <= 0.0 || !area.is_finite() {
        return None;
    }
    let c = first / area;
    Some((
        c,
        xx / area - c.x * c.x,
        xy / area - c.x * c.y,
        yy / area - c.y * c.y,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::snap::point::tests::context;

    fn segment(a: DVec2, b: DVec2) -> Vec<DVec2> {
        (0..=20).map(|i| a.lerp(b, f64::from(i) / 20.0)).collect()
    }

    /// A rectangle's outline in sketch space (y down), in four strokes.
    fn rectangle(lo: DVec2, hi: DVec2) -> Vec<Vec<DVec2>> {
        let (a, b, c, d) = (lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y));
        vec![segment(a, b), segment(b, c), segment(c, d), segment(d, a)]
    }

    #[test]
    fn a_thin_upright_rod_has_a_thin_upright_region() {
        // A leg 20 wide and 200 tall, a wider slab beside it.
        let mut strokes = rectangle(DVec2::new(100.0, 100.0), DVec2::new(120.0, 300.0));
        strokes.extend(rectangle(
            DVec2::new(140.0, 100.0),
            DVec2::new(400.0, 140.0),
        ));
        let ctx = context(&strokes);
        // Sketch (112, 210) is view (112, -210).
        let r = region_at(&ctx, DVec2::new(112.0, -210.0), 1000.0).expect("enclosed");
        assert!(r.major.y > 0.99, "upright: {:?}", r.major);
        assert!((r.half_major - 100.0).abs() < 5.0, "{}", r.half_major);
        assert!((r.half_minor - 10.0).abs() < 1.0, "{}", r.half_minor);
        assert!(r.centre.distance(DVec2::new(110.0, -200.0)) < 2.0);
    }

    #[test]
    fn a_stroke_through_the_point_is_passed() {
        // A square 100 across with a line through its middle, the point on the line.
        let mut strokes = rectangle(DVec2::new(0.0, 0.0), DVec2::new(100.0, 100.0));
        strokes.push(segment(DVec2::new(0.0, 50.0), DVec2::new(100.0, 50.0)));
        let ctx = context(&strokes);
        let r = region_at(&ctx, DVec2::new(40.0, -50.0), 1000.0).expect("enclosed");
        assert!(r.half_minor > 40.0, "{r:?}");
    }

    #[test]
    fn an_open_point_has_no_region() {
        let ctx = context(&[segment(DVec2::new(0.0, 0.0), DVec2::new(100.0, 0.0))]);
        assert!(region_at(&ctx, DVec2::new(50.0, -50.0), 1000.0).is_none());
        assert!(region_at(&ctx, DVec2::new(f64::NAN, 0.0), 1000.0).is_none());
    }
}
