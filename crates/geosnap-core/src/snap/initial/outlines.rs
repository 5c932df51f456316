//! Starting poses of a solid of revolution read off its two drawn outlines.
//!
//! Seen from the side, a cylinder draws two long parallel outlines and a cone two that
//! converge. Their direction is the image axis, their separation the diameter (at each
//! end, for a cone) and their extent along the axis the projected length: an outline
//! ends where it meets the end ellipse at the end of its major axis, level with the end's
//! centre. When the ends are hidden, cut by the parts in front or drawn in one stroke
//! with an outline, the outlines are the strongest evidence of where the part is, and a
//! rough drop (off by a tenth of the size, which across a long thin part is several
//! radii) can sit on one of them, or beside both.
//!
//! The straight strokes near the drop that run roughly its way are joined into lines:
//! strokes on one line continue one another across the gaps where something in front
//! hides the outline, or draw it twice over. Two lines that run together (parallel, or
//! converging for a cone) at about the dropped diameter apart, beside one another over
//! most of the shorter one, draw a pair of outlines; the pair nearest the drop (in place,
//! radius and direction) gives the start: its image axis, the line midway between the
//! outlines and the diameter (at each end, for a cone or an SGC). The tilt out of the
//! view plane stays the drop's (the outlines do not show it; the fit reads it off
//! whatever the ends draw), and so does the extent along the axis: outlines in line
//! with this part's run on past it (a table's back leg behind its front one, a stack of
//! equal cylinders), and a start stretched along them was a part spanning its
//! neighbours as often as the part meant. The ends drawn across the outlines decide the
//! length.

use glam::{DVec2, DVec3};

use super::{strokes_near, Revolution};
use crate::primitive::Primitive;
use crate::snap::assign::ROUGHLY_STRAIGHT;
use crate::snap::context::{SnapContext, SnapStroke};

/// Outline strokes run within this of the dropped image axis (radians, 25°): a rough
/// drop's axis is off by up to 10° in 3D, and more once projected near the view axis.
const ALONG_DROP: f64 = 0.436;

/// Strokes within this of each other's direction (radians, 8°) may draw one line, and
/// two lines within it the outlines of a cylinder (or a straight SGC).
const SAME_LINE: f64 = 0.14;

/// A cone's outlines may converge by up to this (radians, 50°): a squat cone's do.
const CONE_SPREAD: f64 = 0.87;

/// Strokes whose mean points lie within this share of the dropped radius of each
/// other's line lie on one line: a hand's offset along a line is a few hundredths of a
/// radius, and the two outlines are two radii apart.
const LINE_OFFSET: f64 = 0.25;

/// A gap along a line up to this share of the dropped projected length is something in
/// front of the outline (an arm across a stem), not its end.
const LINE_GAP: f64 = 0.5;

/// Two outlines lie between these multiples of the dropped diameter apart.
const SEPARATION: (f64, f64) = (0.5, 2.0);

/// At most this many lines (the longest) are paired.
const MAX_LINES: usize = 48;

/// One outline line: strokes on one line, their length-weighted mean direction (unit,
/// signed like the drop's image axis) and mean point, and their extent along the
/// dropped image axis measured from the drop's image centre.
#[derive(Clone, Copy, Debug)]
struct Line {
    dir: DVec2,
    point: DVec2,
    along: (f64, f64),
    weight: f64,
}

impl Line {
    /// The line's offset across the dropped image axis (`frame`: origin, unit axis) at
    /// `t` along it.
    fn offset_at(&self, frame: (DVec2, DVec2), t: f64) -> f64 {
        let (origin, axis) = frame;
        let normal = axis.perp();
        let p = self.point - origin;
        let run = self.dir.dot(axis).max(1e-6);
        p.dot(normal) + (t - p.dot(axis)) * self.dir.dot(normal) / run
    }

    /// Whether `other` continues this line: about the same direction, each one's mean
    /// point within `offset` of the other's line, and a gap along of at most `gap`.
    fn continued_by(&self, other: &Self, offset: f64, gap: f64) -> bool {
        let across = |a: &Self, b: &Self| (b.point - a.point).dot(a.dir.perp()).abs();
        self.dir.dot(other.dir) >= SAME_LINE.cos()
            && across(self, other) <= offset
            && across(other, self) <= offset
            && self.along.0.max(other.along.0) - self.along.1.min(other.along.1) <= gap
    }

    /// This line and `other` as one (length-weighted).
    fn joined(&self, other: &Self) -> Self {
        let weight = (self.weight + other.weight).max(f64::MIN_POSITIVE);
        let (a, b) = (self.weight / weight, other.weight / weight);
        Self {
            dir: (self.dir * a + other.dir * b).normalize_or(self.dir),
            point: self.point * a + other.point * b,
            along: (
                self.along.0.min(other.along.0),
                self.along.1.max(other.along.1),
            ),
            weight,
        }
    }
}

/// A stroke as a piece of line seen from the drop (`frame`: its image centre and unit
/// image axis).
fn stroke_line(s: &SnapStroke, frame: (DVec2, DVec2)) -> Line {
    let (origin, axis) = frame;
    let dir = if s.direction.dot(axis) < 0.0 {
        -s.direction
    } else {
        s.direction
    };
    let n = s.points.len().max(1) as f64;
    let point = s.points.iter().copied().sum::<DVec2>() / n;
    let along = s
        .points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let t = (*p - origin).dot(axis);
            (lo.min(t), hi.max(t))
        });
    Line {
        dir,
        point,
        along,
        weight: s.length,
    }
}

/// The lines the outline strokes near a drop draw (module docs): strokes taken longest
/// first, each joining the first line it continues.
fn outline_lines(
    strokes: &[&SnapStroke],
    frame: (DVec2, DVec2),
    offset: f64,
    gap: f64,
) -> Vec<Line> {
    let mut pieces: Vec<Line> = strokes.iter().map(|s| stroke_line(s, frame)).collect();
    pieces.sort_by(|a, b| b.weight.total_cmp(&a.weight));
    let mut lines: Vec<Line> = Vec::new();
    for piece in pieces {
        match lines
            .iter_mut()
            .find(|l| l.continued_by(&piece, offset, gap))
        {
            Some(line) => *line = line.joined(&piece),
            None => lines.push(piece),
        }
    }
    lines
}

/// Starting poses of a dropped cylinder, cone or SGC from two outlines drawn near it (see
/// the module docs); none when it is another kind, is seen too nearly along its axis for
/// its outlines to say much, or no two lines near it draw outlines.
pub(crate) fn outline_poses(context: &SnapContext, primitive: &Primitive) -> Vec<Primitive> {
    let Some(dropped) = Revolution::of(primitive) else {
        return Vec::new();
    };
    let image = dropped.axis.truncate();
    let shrink = image.length();
    let projected = dropped.length * shrink;
    let radius = f64::midpoint(dropped.radii.0, dropped.radii.1);
    // A squat image: its outlines are short, and its end ellipses tell more.
    if !(projected > 2.0 * radius) || !(radius > 0.0) {
        return Vec::new();
    }
    let axis = image / shrink;
    let frame = (dropped.center.truncate(), axis);
    let size = primitive.size();
    let strokes = strokes_near(context, primitive, 0.3 * size, |s| {
        s.straightness <= ROUGHLY_STRAIGHT
            && s.direction.dot(axis).abs() >= ALONG_DROP.cos()
            && s.length >= 0.1 * projected
    });
    let mut lines = outline_lines(&strokes, frame, LINE_OFFSET * radius, LINE_GAP * projected);
    // In a dense drawing the longest lines are the outlines worth pairing; the pairs cost
    // the square of the lines.
    lines.sort_by(|a, b| b.weight.total_cmp(&a.weight));
    lines.truncate(MAX_LINES);
    let spread = if matches!(primitive, Primitive::Cone(_)) {
        CONE_SPREAD
    } else {
        SAME_LINE
    };
    let mut best: Option<(f64, Revolution)> = None;
    for (i, a) in lines.iter().enumerate() {
        for b in &lines[i + 1..] {
            let Some((cost, pose)) = pair_pose(a, b, frame, &dropped, spread, size) else {
                continue;
            };
            if best.as_ref().is_none_or(|(c, _)| cost < *c) {
                best = Some((cost, pose));
            }
        }
    }
    best.and_then(|(_, pose)| pose.applied_to(primitive))
        .into_iter()
        .collect()
}

/// The pose two lines `a` and `b` draw as outlines of `dropped` (seen from `frame`), and
/// its cost: how far it is from the drop in place (over `size`), radius (log ratio) and
/// direction (in [`ALONG_DROP`]s). `None` when they do not draw outlines of it: more
/// than `spread` apart in direction, too near or far apart, or beside one another over
/// less than half the shorter one.
fn pair_pose(
    a: &Line,
    b: &Line,
    frame: (DVec2, DVec2),
    dropped: &Revolution,
    spread: f64,
    size: f64,
) -> Option<(f64, Revolution)> {
    let (origin, axis) = frame;
    if a.dir.dot(b.dir) < spread.cos() {
        return None;
    }
    let image = dropped.axis.truncate();
    let projected = dropped.length * image.length();
    let (ea, eb) = (a.along.1 - a.along.0, b.along.1 - b.along.0);
    let overlap = a.along.1.min(b.along.1) - a.along.0.max(b.along.0);
    if overlap < 0.5 * ea.min(eb) || ea.min(eb) < 0.2 * projected {
        return None;
    }
    let separation = |t: f64| (b.offset_at(frame, t) - a.offset_at(frame, t)).abs();
    let middle = 0.5 * (a.along.1.min(b.along.1) + a.along.0.max(b.along.0));
    let diameter = dropped.radii.0 + dropped.radii.1;
    let apart = separation(middle);
    if apart < SEPARATION.0 * diameter || apart > SEPARATION.1 * diameter {
        return None;
    }
    // The extent stays the drop's: outlines in line with this part's run on behind it
    // (a table's back leg behind its front one), and its ends decide the rest.
    let (lo, hi) = (-projected / 2.0, projected / 2.0);
    let t = f64::midpoint(lo, hi);
    let dir = (a.dir + b.dir).normalize_or(axis);
    let across = 0.5 * (a.offset_at(frame, t) + b.offset_at(frame, t));
    let center = origin + axis * t + axis.perp() * across;
    let radii = if (dropped.radii.0 - dropped.radii.1).abs() > 0.0 || spread > SAME_LINE {
        (separation(lo) / 2.0, separation(hi) / 2.0)
    } else {
        (apart / 2.0, apart / 2.0)
    };
    let shrink = image.length();
    let length = (hi - lo) / dir.dot(axis).max(1e-6) / shrink;
    let pose = Revolution {
        center: DVec3::new(center.x, center.y, dropped.center.z),
        axis: DVec3::new(dir.x * shrink, dir.y * shrink, dropped.axis.z).normalize(),
        length,
        radii,
    };
    let r = f64::midpoint(dropped.radii.0, dropped.radii.1);
    let cost = center.distance(dropped.center.truncate()) / size
        + (apart / 2.0 / r).ln().abs()
        + dir.angle_to(axis).abs() / ALONG_DROP;
    Some((cost, pose))
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::outline_poses;
    use crate::primitive::{Curve2, Cylinder, Primitive};
    use crate::sketch::StrokeClass;
    use crate::snap::initial::tests::strokes_of;
    use crate::snap::SnapContext;

    /// A straight stroke from `a` to `b` (sketch space, y down) with a small zigzag, as a
    /// hand draws it.
    fn line(a: DVec2, b: DVec2) -> Vec<DVec2> {
        let n = (b - a).perp().normalize() * 1.5;
        (0..=40)
            .map(|i| {
                let q = a.lerp(b, f64::from(i) / 40.0);
                let q = if i % 2 == 0 { q + n } else { q - n };
                DVec2::new(q.x, q.y)
            })
            .collect()
    }

    fn context(strokes: &[Vec<DVec2>]) -> SnapContext {
        strokes_of(strokes, StrokeClass::Silhouette)
    }

    /// An upright cylinder dropped at `x` (view plane), 600 long, of radius `r`.
    fn dropped(x: f64, r: f64) -> Primitive {
        let axis = DVec3::new(0.0, 0.9, 0.19f64.sqrt());
        Primitive::Cylinder(Cylinder {
            center: DVec3::new(x, -300.0, 0.0),
            axis,
            length: 600.0 / 0.9,
            radius: r,
        })
    }

    #[test]
    fn outlines_cut_by_parts_in_front_give_the_stem_beside_a_drop_off_to_one_side() {
        // A stem 40 wide between x = 180 and 220, from y = 30 to 570 (sketch space), its
        // outlines cut twice by arms in front of it; nothing of its ends is drawn.
        let mut strokes = Vec::new();
        for x in [180.0, 220.0] {
            for (y0, y1) in [(30.0, 200.0), (240.0, 400.0), (440.0, 570.0)] {
                strokes.push(line(DVec2::new(x, y0), DVec2::new(x, y1)));
            }
        }
        // Something else upright further right.
        strokes.push(line(DVec2::new(300.0, 100.0), DVec2::new(300.0, 500.0)));
        // The drop sits on the right outline, a quarter too wide.
        let poses = outline_poses(&context(&strokes), &dropped(225.0, 25.0));
        assert_eq!(poses.len(), 1, "{poses:?}");
        let Primitive::Cylinder(c) = &poses[0] else {
            panic!("not a cylinder: {:?}", poses[0]);
        };
        assert!((c.center.x - 200.0).abs() < 2.0, "{c:?}");
        assert!((c.center.y + 300.0).abs() < 5.0, "{c:?}");
        assert!((c.radius - 20.0).abs() < 1.5, "{c:?}");
        // The extent along the axis stays the drop's: the ends decide it in the fit.
        let projected = c.length * c.axis.truncate().length();
        assert!((projected - 600.0).abs() < 1.0, "{c:?}");
        assert!(c.axis.truncate().normalize().dot(DVec2::Y) > 0.999, "{c:?}");
    }

    #[test]
    fn no_outline_pair_gives_no_start() {
        // One outline alone, and a line too far from it to be the other.
        let strokes = [
            line(DVec2::new(180.0, 30.0), DVec2::new(180.0, 570.0)),
            line(DVec2::new(400.0, 30.0), DVec2::new(400.0, 570.0)),
        ];
        assert!(outline_poses(&context(&strokes), &dropped(200.0, 20.0)).is_empty());
    }

    /// A stem seen from the side and a little above, its outlines cut where two arms
    /// pass in front of it, and the arms' outlines across it; its ends are hidden (under
    /// a cup, in a base).
    fn stem_behind_arms() -> (SnapContext, Cylinder) {
        let stem = Cylinder {
            center: DVec3::new(400.0, -400.0, 0.0),
            axis: DVec3::new(0.05, 0.97, 0.24).normalize(),
            length: 600.0,
            radius: 24.0,
        };
        let shape = Primitive::Cylinder(stem.clone()).current_shape();
        // Arms in front: bands of the view's y where the stem is hidden.
        let hidden = |y: f64| (-300.0..-250.0).contains(&y) || (-520.0..-470.0).contains(&y);
        let mut strokes: Vec<Vec<DVec2>> = Vec::new();
        for c in shape.curves.iter().filter(|c| c.visible) {
            if matches!(c.curve, Curve2::Ellipse { .. }) {
                continue;
            }
            let points = c.curve.points(120);
            let mut run: Vec<DVec2> = Vec::new();
            for p in points {
                if hidden(p.y) {
                    if run.len() > 1 {
                        strokes.push(std::mem::take(&mut run));
                    }
                    run.clear();
                } else {
                    run.push(DVec2::new(p.x, -p.y));
                }
            }
            if run.len() > 1 {
                strokes.push(run);
            }
        }
        for (y0, y1) in [(250.0, 300.0), (470.0, 520.0)] {
            strokes.push(line(DVec2::new(150.0, y0), DVec2::new(650.0, y0 + 10.0)));
            strokes.push(line(DVec2::new(150.0, y1), DVec2::new(650.0, y1 + 10.0)));
        }
        (context(&strokes), stem)
    }

    #[test]
    fn a_stem_behind_arms_dropped_beside_its_outline_snaps_onto_it() {
        let (context, stem) = stem_behind_arms();
        // Dropped upright, a tenth of its length off to the right (two and a half radii)
        // and a fifth too wide.
        let dropped = Primitive::Cylinder(Cylinder {
            center: DVec3::new(460.0, -420.0, 0.0),
            axis: DVec3::new(0.0, 0.97, 0.24).normalize(),
            length: 560.0,
            radius: 29.0,
        });
        let result = crate::snap::snap(&context, &dropped, &crate::snap::SnapSettings::default())
            .expect("it snaps");
        let Primitive::Cylinder(c) = &result.primitive else {
            panic!("not a cylinder: {:?}", result.primitive);
        };
        let off = (c.center.truncate() - stem.center.truncate()).length();
        assert!(
            off < 0.03 * stem.length && (c.radius / stem.radius - 1.0).abs() < 0.07,
            "landed {off:.1} off the stem's centre with radius {:.1}: {c:?}",
            c.radius
        );
        assert!(
            c.axis
                .truncate()
                .normalize()
                .dot(stem.axis.truncate().normalize())
                > 0.996
        );
    }
}
