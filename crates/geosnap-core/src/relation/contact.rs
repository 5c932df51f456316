//! Which parts meet in the drawing, and how: the contact graph that relation inference
//! draws its candidates from.
//!
//! A drawing shows no depth, so contact is judged on the parts' projected outlines
//! ([`Outline`]: convex pieces in the view plane, one for a straight solid, one per spine
//! segment for a bent tube). Two parts touch when their outlines come within a tenth of
//! the smaller part's size ([`InferenceSettings::distance`]), and a part never further
//! than its own thickness (its widest end's radius) from the other: a thin rod whose end
//! stops two of its widths short of a part is drawn apart from it, however long the rod.
//! How they touch ([`Contact`]) is read off where their ends lie: on the other's end (a
//! stack), inside its end face or box (a leg under a table top, a stud on a brick), on a
//! ball, or on its side (a T, an L, a handle).
//!
//! The graph's edges are the joints (an end on the other part): a relation is looked
//! for between parts a few joints apart ([`ContactGraph::hops_from`]), never between
//! parts of different objects, so the candidates grow with the contacts, not with the
//! square of the parts. Outlines that cross with no end on the other (parts drawn one
//! behind the other, or crossing through) relate those two parts weakly and carry
//! nothing further.
//!
//! [`InferenceSettings::distance`]: super::InferenceSettings::distance

use glam::{DVec2, DVec3};

use super::evidence::Contact;
use super::infer::Part;
use crate::primitive::{Feature, FeatureGeometry, Primitive, PrimitiveKind};

/// How many of its own thicknesses (its widest end's radius) a part may stand clear of
/// another and still touch it in the drawing (see [`end_reach`]).
const GAP_IN_THICKNESSES: f64 = 1.0;

/// Points sampled on each circle of an outline.
const CIRCLE_SAMPLES: usize = 24;

/// A part's projected outline: convex polygons (counter-clockwise) whose union covers
/// it, with their bounding box.
#[derive(Clone, Debug, PartialEq)]
pub struct Outline {
    pieces: Vec<Vec<DVec2>>,
    lo: DVec2,
    hi: DVec2,
}

impl Outline {
    /// The outline of `primitive` as drawn (model (x, y); depth dropped): the convex hull
    /// of its projected curves, or for a bent tube one hull per spine segment (of the two
    /// cross-sections bounding it).
    pub fn of(primitive: &Primitive) -> Self {
        let pieces = if let Primitive::Bgc(bgc) = primitive {
            let rings: Vec<Vec<DVec2>> = bgc
                .spine
                .iter()
                .enumerate()
                .map(|(k, p)| {
                    let prev = bgc.spine[k.saturating_sub(1)];
                    let next = bgc.spine[(k + 1).min(bgc.spine.len() - 1)];
                    ring(*p, next - prev, bgc.radii.get(k).copied().unwrap_or(0.0))
                })
                .collect();
            rings
                .windows(2)
                .map(|w| hull(w[0].iter().chain(&w[1]).copied().collect()))
                .collect()
        } else {
            let points: Vec<DVec2> = primitive
                .current_shape()
                .curves
                .iter()
                .flat_map(|c| c.curve.points(CIRCLE_SAMPLES))
                .collect();
            vec![hull(points)]
        };
        Self::from_pieces(pieces)
    }

    /// An outline of the given convex pieces (each made convex and counter-clockwise).
    pub fn from_pieces(pieces: Vec<Vec<DVec2>>) -> Self {
        let pieces: Vec<Vec<DVec2>> = pieces
            .into_iter()
            .map(hull)
            .filter(|p| !p.is_empty())
            .collect();
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for p in pieces.iter().flatten() {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        Self { pieces, lo, hi }
    }

    /// Whether the outline has no finite extent (an empty or broken part).
    fn is_empty(&self) -> bool {
        !(self.lo.is_finite() && self.hi.is_finite())
    }

    /// The distance from `p` to the outline (0 inside).
    pub fn distance_to_point(&self, p: DVec2) -> f64 {
        self.pieces
            .iter()
            .map(|piece| polygon_point_distance(piece, p))
            .fold(f64::INFINITY, f64::min)
    }

    /// The distance between two outlines (0 where they overlap).
    pub fn distance(&self, other: &Self) -> f64 {
        if self.is_empty() || other.is_empty() {
            return f64::INFINITY;
        }
        // The boxes' gap bounds the distance from below.
        let gap = (other.lo - self.hi)
            .max(self.lo - other.hi)
            .max(DVec2::ZERO);
        let mut best = f64::INFINITY;
        if gap.length() > best {
            return best;
        }
        for a in &self.pieces {
            for b in &other.pieces {
                best = best.min(polygon_distance(a, b));
                if best == 0.0 {
                    return 0.0;
                }
            }
        }
        best
    }

    /// The bounding box's gap to another's, per axis (0 where they overlap).
    fn box_gap(&self, other: &Self) -> f64 {
        (other.lo - self.hi)
            .max(self.lo - other.hi)
            .max(DVec2::ZERO)
            .length()
    }
}

/// The projected points of a circle at `center` across `tangent` of radius `r`.
fn ring(center: DVec3, tangent: DVec3, r: f64) -> Vec<DVec2> {
    let t = tangent.normalize_or_zero();
    let (u, v) = if t == DVec3::ZERO {
        (DVec3::X, DVec3::Y)
    } else {
        t.any_orthonormal_pair()
    };
    (0..CIRCLE_SAMPLES)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / CIRCLE_SAMPLES as f64;
            let p = center + (u * a.cos() + v * a.sin()) * r;
            DVec2::new(p.x, p.y)
        })
        .collect()
}

/// The convex hull of `points`, counter-clockwise (Andrew's monotone chain); non-finite
/// points are dropped.
fn hull(mut points: Vec<DVec2>) -> Vec<DVec2> {
    points.retain(|p| p.is_finite());
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut lower: Vec<DVec2> = Vec::new();
    for &p in &points {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<DVec2> = Vec::new();
    for &p in points.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// Whether `p` lies inside the convex counter-clockwise polygon `poly`.
fn inside(poly: &[DVec2], p: DVec2) -> bool {
    poly.len() >= 3
        && (0..poly.len()).all(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            (b - a).perp_dot(p - a) >= 0.0
        })
}

/// The distance from `p` to the segment a–b.
fn segment_point(a: DVec2, b: DVec2, p: DVec2) -> f64 {
    crate::geom::segment_distance(a, b, p)
}

/// The edges of a polygon (a point or a segment has one degenerate edge).
fn edges(poly: &[DVec2]) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
    let n = poly.len();
    (0..n).map(move |i| (poly[i], poly[(i + 1) % n]))
}

/// The distance from `p` to a convex polygon (0 inside).
fn polygon_point_distance(poly: &[DVec2], p: DVec2) -> f64 {
    if inside(poly, p) {
        return 0.0;
    }
    edges(poly)
        .map(|(a, b)| segment_point(a, b, p))
        .fold(f64::INFINITY, f64::min)
}

/// Whether segments a–b and c–d cross.
fn segments_cross(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let side = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    let (d1, d2) = (side(a, b, c), side(a, b, d));
    let (d3, d4) = (side(c, d, a), side(c, d, b));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// The distance between two convex polygons (0 where they overlap).
fn polygon_distance(a: &[DVec2], b: &[DVec2]) -> f64 {
    if a.iter().any(|p| inside(b, *p)) || b.iter().any(|p| inside(a, *p)) {
        return 0.0;
    }
    let mut best = f64::INFINITY;
    for (p, q) in edges(a) {
        for (r, s) in edges(b) {
            if segments_cross(p, q, r, s) {
                return 0.0;
            }
            best = best.min(segment_point(r, s, p)).min(segment_point(p, q, r));
        }
    }
    best
}

/// An end circle of a part as drawn: its feature, projected centre, radius, and unit
/// normal (model space).
#[derive(Clone, Copy, Debug)]
struct End {
    center: DVec2,
    normal: DVec3,
    radius: f64,
}

impl End {
    /// Whether `p` lies inside this end's projected ellipse grown by `grow`.
    fn covers(&self, p: DVec2, grow: f64) -> bool {
        let d = p - self.center;
        let axis = DVec2::new(self.normal.x, self.normal.y);
        let minor = self.radius * self.normal.z.abs() + grow;
        let major = self.radius + grow;
        if axis.length() < 1e-9 {
            return d.length() <= major;
        }
        let u = axis.normalize();
        (d.dot(u) / minor).powi(2) + (d.perp_dot(u) / major).powi(2) <= 1.0
    }
}

/// The end circles (`bottom`, `top`) of a part, as drawn.
fn ends(part: &Part<'_>) -> Vec<End> {
    part.features
        .iter()
        .filter(|f| matches!(f.feature, Feature::Top | Feature::Bottom))
        .filter_map(|f| match &f.geometry {
            FeatureGeometry::Circle {
                center,
                normal,
                radius,
            } => Some(End {
                center: DVec2::new(center.x, center.y),
                normal: normal.to_dvec3(),
                radius: *radius,
            }),
            FeatureGeometry::Rectangle { .. } => None,
        })
        .collect()
}

/// The sphere's outline as drawn: centre and radius.
fn ball(part: &Part<'_>) -> Option<(DVec2, f64)> {
    if part.kind != PrimitiveKind::Sphere {
        return None;
    }
    part.features.iter().find_map(|f| match &f.geometry {
        FeatureGeometry::Circle { center, radius, .. } => {
            Some((DVec2::new(center.x, center.y), *radius))
        }
        FeatureGeometry::Rectangle { .. } => None,
    })
}

/// How thick a part is drawn: its widest end's radius, or a ball's; `None` for a box
/// (whose faces are read whole).
fn thickness(part: &Part<'_>) -> Option<f64> {
    ball(part).map(|(_, r)| r).or_else(|| {
        ends(part)
            .iter()
            .map(|e| e.radius)
            .filter(|r| r.is_finite())
            .reduce(f64::max)
    })
}

/// How far from `b` an end of `a` may stop and still sit on it: the gap `tol` allowed
/// by the parts' sizes, but never more than [`GAP_IN_THICKNESSES`] of `a`'s thickness.
/// A long thin rod's end that stops two of its own widths short of another part is
/// drawn apart from it, however small that gap is against the rod's length.
fn end_reach(a: &Part<'_>, tol: f64) -> f64 {
    thickness(a).map_or(tol, |t| tol.min(GAP_IN_THICKNESSES * t))
}

/// How the ends of `a` meet `b` (the strongest way), when some end does.
fn end_contact(a: &Part<'_>, b: &Part<'_>, tol: f64, distance: f64) -> Option<Contact> {
    let b_ends = ends(b);
    let tol = end_reach(a, tol);
    let mut best: Option<Contact> = None;
    let mut take = |c: Contact| {
        if best.is_none_or(|b| c < b) {
            best = Some(c);
        }
    };
    for e in ends(a) {
        if b_ends
            .iter()
            .any(|f| e.center.distance(f.center) <= distance * (e.radius + f.radius))
        {
            take(Contact::EndOnEnd);
        } else if b_ends.iter().any(|f| f.covers(e.center, tol))
            || (b.kind == PrimitiveKind::Cuboid && b.outline.distance_to_point(e.center) <= tol)
        {
            take(Contact::EndOnFace);
        } else if let Some((c, r)) = ball(b) {
            if e.center.distance(c) <= r + tol {
                take(Contact::EndOnSphere);
            }
        } else if b.outline.distance_to_point(e.center) <= tol {
            take(Contact::EndOnSide);
        }
    }
    best
}

/// How parts `a` and `b` meet in the drawing; `grow` is the gap, relative to the
/// smaller part's size, still taken as touching (and `distance` the relative offset of
/// centres taken as the same, as in [`InferenceSettings::distance`]).
///
/// [`InferenceSettings::distance`]: super::InferenceSettings::distance
pub fn contact(a: &Part<'_>, b: &Part<'_>, grow: f64) -> Contact {
    let tol = grow * a.size.min(b.size);
    if a.outline.box_gap(b.outline) > tol {
        return Contact::Apart;
    }
    let gap = a.outline.distance(b.outline);
    if gap > tol {
        return Contact::Apart;
    }
    let found = [end_contact(a, b, tol, grow), end_contact(b, a, tol, grow)]
        .into_iter()
        .flatten()
        .min();
    match found {
        Some(c) => c,
        // Boxes side by side or stacked meet face to face.
        None if a.kind == PrimitiveKind::Cuboid && b.kind == PrimitiveKind::Cuboid => {
            Contact::EndOnFace
        }
        // Outlines that meet with no end on the other cross only where the thinner
        // part does not stand clear of the other by its own reach.
        None if gap <= end_reach(a, tol).min(end_reach(b, tol)) => Contact::Crossing,
        None => Contact::Apart,
    }
}

/// The contacts between parts: for each part, the parts it touches and how, and the
/// pairs of parts that are one drawn part read twice ([`ContactGraph::separate`]).
#[derive(Clone, Debug, Default)]
pub struct ContactGraph {
    touching: Vec<Vec<(usize, Contact)>>,
    /// Pairs (lower index first) never to be related.
    apart: Vec<(usize, usize)>,
}

impl ContactGraph {
    /// The contacts among `parts` (see [`contact`]).
    pub fn new(parts: &[Part<'_>], grow: f64) -> Self {
        let mut touching = vec![Vec::new(); parts.len()];
        for i in 0..parts.len() {
            for j in i + 1..parts.len() {
                let c = contact(&parts[i], &parts[j], grow);
                if c != Contact::Apart {
                    touching[i].push((j, c));
                    touching[j].push((i, c));
                }
            }
        }
        Self {
            touching,
            apart: Vec::new(),
        }
    }

    /// Keeps apart the touching parts that `same` says are one drawn part read twice
    /// (snapped to mostly the same strokes: a drop meant for one of a row of alike
    /// parts that snapped onto its neighbour): inference never relates the two
    /// ([`ContactGraph::kept_apart`]). Whatever they would share (an axis, an end) is
    /// the drawing's one part agreeing with itself, not a relation a designer made.
    /// Their contacts stay: each still reaches the others through the other's joints
    /// (a candle read onto the arm it stands on still reaches the other candles). Only
    /// touching parts are asked: parts read off the same strokes overlap.
    pub fn separate(&mut self, same: impl Fn(usize, usize) -> bool) {
        for (a, touching) in self.touching.iter().enumerate() {
            for (b, _) in touching {
                if a < *b && same(a, *b) {
                    self.apart.push((a, *b));
                }
            }
        }
    }

    /// Whether parts `a` and `b` are one drawn part read twice
    /// ([`ContactGraph::separate`]): never related.
    pub fn kept_apart(&self, a: usize, b: usize) -> bool {
        self.apart.contains(&(a.min(b), a.max(b)))
    }

    /// How parts `a` and `b` touch ([`Contact::Apart`] when they do not).
    pub fn between(&self, a: usize, b: usize) -> Contact {
        self.touching
            .get(a)
            .and_then(|t| t.iter().find(|(j, _)| *j == b))
            .map_or(Contact::Apart, |(_, c)| *c)
    }

    /// The joints of part `a` (the parts an end of which sits on it, or on which one of
    /// its ends sits).
    pub fn joints(&self, a: usize) -> impl Iterator<Item = usize> + '_ {
        self.touching
            .get(a)
            .into_iter()
            .flatten()
            .filter(|(_, c)| c.is_joint())
            .map(|(j, _)| *j)
    }

    /// How many joints apart each part is from `from`, up to `limit` (`None` beyond, or
    /// unreachable); a part whose outline only crosses `from`'s is one apart. `from`
    /// itself is 0.
    pub fn hops_from(&self, from: usize, limit: u32) -> Vec<Option<u32>> {
        self.hops_avoiding(from, limit, usize::MAX)
    }

    /// As [`ContactGraph::hops_from`], with the graph as if part `avoid` were not in it
    /// (`avoid` itself is unreachable).
    pub fn hops_avoiding(&self, from: usize, limit: u32, avoid: usize) -> Vec<Option<u32>> {
        let mut hops = vec![None; self.touching.len()];
        if from == avoid {
            return hops;
        }
        let Some(slot) = hops.get_mut(from) else {
            return hops;
        };
        *slot = Some(0);
        let mut frontier = vec![from];
        for depth in 1..=limit {
            let mut next = Vec::new();
            for &i in &frontier {
                for j in self.joints(i) {
                    if j != avoid && hops[j].is_none() {
                        hops[j] = Some(depth);
                        next.push(j);
                    }
                }
            }
            frontier = next;
            if frontier.is_empty() {
                break;
            }
        }
        for (j, _) in self.touching.get(from).into_iter().flatten() {
            if *j != avoid {
                hops[*j].get_or_insert(1);
            }
        }
        hops
    }

    /// Whether `a` and `b` both have a joint with one same part.
    pub fn share_a_joint(&self, a: usize, b: usize) -> bool {
        self.joints(a)
            .any(|j| j != b && self.joints(b).any(|k| k == j))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::{hull, polygon_distance, Outline};

    #[test]
    fn parts_read_off_the_same_strokes_are_kept_apart() {
        use super::{Contact, ContactGraph};

        let mut graph = ContactGraph {
            touching: vec![
                vec![(1, Contact::Crossing), (2, Contact::EndOnSide)],
                vec![(0, Contact::Crossing)],
                vec![(0, Contact::EndOnSide)],
            ],
            apart: Vec::new(),
        };
        graph.separate(|a, b| (a, b) == (0, 1));
        assert!(graph.kept_apart(1, 0) && graph.kept_apart(0, 1));
        assert!(!graph.kept_apart(0, 2));
        assert_eq!(graph.between(0, 2), Contact::EndOnSide);
    }

    /// How a rod of radius 4 and length 160 along x, whose left end stops `gap` short
    /// of the side of an upright post of radius 40 and length 300, meets it.
    fn rod_short_of_a_post(gap: f64) -> super::Contact {
        use glam::DVec3;

        use crate::primitive::{Cylinder, Primitive};
        use crate::relation::infer::Part;

        let post = Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::new(0.0, 0.96, 0.28),
            length: 300.0,
            radius: 40.0,
        });
        let rod = Primitive::Cylinder(Cylinder {
            center: DVec3::new(40.0 + gap + 80.0, 0.0, 0.0),
            axis: DVec3::X,
            length: 160.0,
            radius: 4.0,
        });
        let features = [post.current_shape().features, rod.current_shape().features];
        let outlines = [Outline::of(&post), Outline::of(&rod)];
        let part = |k: usize, p: &Primitive| Part {
            kind: p.kind(),
            features: &features[k],
            outline: &outlines[k],
            size: p.size(),
            noise: 0.005,
            tilt: [0.0; 2],
            drawn_axis: None,
            length_spread: 0.0,
        };
        super::contact(&part(0, &post), &part(1, &rod), 0.1)
    }

    #[test]
    fn a_thin_rod_touches_only_what_it_stops_on_within_its_own_width() {
        use super::Contact;

        // 10 % of the rod's length would allow a gap of 16: four of its radii, a gap
        // anyone sees in the drawing. Within its own radius it still sits on the post.
        assert_eq!(rod_short_of_a_post(0.0), Contact::EndOnSide);
        assert_eq!(rod_short_of_a_post(3.0), Contact::EndOnSide);
        assert_eq!(rod_short_of_a_post(10.0), Contact::Apart);
        assert_eq!(rod_short_of_a_post(15.0), Contact::Apart);
    }

    #[test]
    fn hulls_and_distances() {
        let square = |x: f64, y: f64| {
            vec![
                DVec2::new(x, y),
                DVec2::new(x + 1.0, y),
                DVec2::new(x + 1.0, y + 1.0),
                DVec2::new(x, y + 1.0),
                DVec2::new(x + 0.5, y + 0.5),
            ]
        };
        let a = hull(square(0.0, 0.0));
        assert_eq!(a.len(), 4);
        assert!((polygon_distance(&a, &hull(square(3.0, 0.0))) - 2.0).abs() < 1e-12);
        assert!(polygon_distance(&a, &hull(square(0.5, 0.5))) < 1e-12);
        let o = Outline::from_pieces(vec![square(0.0, 0.0)]);
        assert!((o.distance_to_point(DVec2::new(0.5, 3.0)) - 2.0).abs() < 1e-12);
        assert!(o.distance_to_point(DVec2::new(0.5, 0.5)) < 1e-12);
    }
}
