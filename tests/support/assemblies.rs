//! Synthetic assemblies: several ground-truth primitives designed to stand in known
//! geosemantic relations, drawn together in one sketch from one random view by the test
//! renderer ([`super::synth`]), with the script steps that place them the way a person
//! would (perturbed poses).
//!
//! # Kinds
//!
//! Each assembly is built in a canonical frame (up = +Y, overall size about 1), then
//! turned by a designer's view, scaled to 600–1800 sketch units and moved anywhere in a
//! 3000 × 3000 sketch at a random depth.
//!
//! - [`AssemblyKind::Stack`]: 2–3 coaxial cylinders and cones, each one's top end on the
//!   next one's bottom end (designed: coaxial and concentric at every joint).
//! - [`AssemblyKind::Table`]: a top (a disc or a slab) on 3–4 legs (a slab always has
//!   4) standing parallel to its axis, equal in length and radius, their tops on its
//!   underside (designed: parallel and equal legs, coplanar leg tops and underside, the
//!   legs parallel to the top's axis).
//! - [`AssemblyKind::SphereTubes`]: a ball with 2–4 radial tubes whose bottom ends sit
//!   on it (designed: on-sphere; in half of the cases the tubes are equal, designed
//!   equal-length and same-radius).
//! - [`AssemblyKind::BrickStuds`]: a brick with a 1–2 × 2–3 grid of equal studs on its
//!   top face (designed: coplanar stud bottoms and brick top, studs parallel to the
//!   brick's up axis, equal studs).
//! - [`AssemblyKind::BoxPipes`]: a box with 2–3 pipes standing out of different faces
//!   that face the viewer (designed: each pipe's bottom in its face's plane and its axis
//!   along the face normal, the pipes pairwise orthogonal).
//!
//! Issue 17 added kinds nearer real drawings, with aspect ratios and sizes varied widely
//! (squat discs to tall beakers, thin rods to fat tubes, cubes to slabs):
//!
//! - [`AssemblyKind::Handle`]: a mug-like body (an upright cylinder, height 0.5–4 ×
//!   its radius) with a handle out of its side along a horizontal axis: a straight rod
//!   whose end sits on the side (designed: orthogonal to the body); an L, a rod out of
//!   the side and one down from its end (also: the two orthogonal, the second parallel
//!   to the body, one radius); or a U, two equal rods out of the side and a grip joining
//!   their ends (designed: the body orthogonal to the first rod, the rods parallel, equal
//!   length and radius, the grip of their radius and parallel to the body).
//! - [`AssemblyKind::Tee`]: a main pipe (radius 3–18 % of its length) with a thinner
//!   branch whose end sits on its side (T joint, designed orthogonal); in half of the
//!   cases a third pipe at one end of the main one, at a right angle (L joint, designed
//!   orthogonal to the main pipe, parallel or orthogonal to the branch, and of the main
//!   pipe's radius when it is).
//! - [`AssemblyKind::Plug`]: a box with 2–3 equal prongs in a row on one face that faces
//!   the viewer: round pins or flat blades (thin boxes). Designed: each prong's bottom
//!   coplanar with the face and its axis parallel to the face normal, the prongs
//!   parallel; pins also of one radius and length (no relation kind names equal boxes).
//! - [`AssemblyKind::Valves`]: a horizontal body cylinder with three equal vertical
//!   valves standing on its top side (designed: each orthogonal to the body, the valves
//!   parallel, equal length and radius).
//! - [`AssemblyKind::Menorah`]: a base (a disc, designed coaxial and concentric with the
//!   stem's bottom, or a slab, designed coplanar with it and parallel to the stem), an
//!   upright stem, 1–2 symmetric pairs of straight arms along ±X out of the stem's sides
//!   (designed: a pair coaxial and equally long, every arm orthogonal to the stem, all
//!   arms of one radius), an equal candle on each arm's end and one on the stem's top
//!   (designed: parallel to the stem, equal length and radius, the top one coaxial and
//!   concentric with the stem).
//! - [`AssemblyKind::Drawers`]: 3–5 equal boxes in a row, each touching the next face to
//!   face: drawers stacked in a chest (3–8 times as wide as high) or books side by side
//!   on a shelf (thin and tall). Designed: the touching faces coplanar, the fronts
//!   coplanar. A rough drop on one of them meets its neighbours' edges all round it.
//! - [`AssemblyKind::Scene`]: two or three unrelated objects of
//!   [`AssemblyKind::OBJECTS`] (the five kinds above), each turned by its own designer's
//!   view (in half of the scenes all standing on one floor: one view, each object turned
//!   only about its vertical) and scaled to its own size, side by side in a row with gaps of −8 % to +20 % of
//!   their width (neighbours may overlap slightly in the drawing), at different heights
//!   and depths. Each object keeps its designed relations; parts of different objects
//!   have none. [`Assembly::object`] tells each part's object (all 0 for the other
//!   kinds).
//!
//! Sizes that are not designed equal differ by at least [`DISTINCT`] (ratio), so that a
//! relation between them is clearly not meant: inference must not find it, and precision
//! can be judged on the truth.
//!
//! # Views
//!
//! The canonical frame is turned as the renderer turns a box (pitch 10°–45°, yaw
//! 10°–80°, a random roll) and kept when each of its three axes makes at least 25° with
//! the view direction and at least 8.6° with the view plane (0.15 ≤ |z| ≤ cos 25°), so
//! every part's axis is seen as the single-primitive test sees it. The ball's tubes are
//! directed in view space: 10°–60° out of the view plane, at least 30° apart in the
//! drawing, and 40°–70° or 110°–140° apart in space (clearly neither parallel nor
//! orthogonal).
//!
//! # Conditions
//!
//! [`assembly_with`] builds the assemblies of issue 16's wider test
//! (`synthetic_conditions`): tables come from [`wide_table`] (a thin disc top of
//! thickness 0.1–0.3 × its radius, or a slab 1/15–1/5 as thick as it is wide, on legs of
//! length over radius 8–20), the other kinds as [`assembly`] builds them. The view comes
//! from the condition's range ([`view_in`]: a designer's view as above, nearly along the
//! up axis, or from the side; a ball's tubes keep their own directions), and every part
//! is drawn by [`draw_with`] under the condition, with hidden lines when asked. That test
//! runs the kinds of [`AssemblyKind::ISSUE_16`] (the first five). As in
//! [`assembly`], each part is drawn whole, as if the others were transparent (but a row
//! of drawers, drawn as the row hides them: [`in_the_row`]), and
//! [`Assembly::part_of`] tells which part each stroke belongs to. [`assembly`] is
//! unchanged: the same seed gives the same assembly as before.

use std::f64::consts::TAU;

use geosnap::core::geom::projection::sketch_from_view;
use geosnap::core::model::Step;
use geosnap::core::primitive::{
    Cone, Cuboid, Cylinder, Feature, Placement, Primitive, PrimitiveKind, Sphere,
};
use geosnap::core::relation::RelationKind;
use geosnap::core::sketch::{Sketch, Stroke, StrokeId};
use glam::{DQuat, DVec2, DVec3};

use super::synth::{
    draw, draw_with, random_rotation, Condition, Rng, Style, SynthStroke, ViewRange,
};

/// Smallest ratio between sizes (radii, lengths) that are not designed equal.
pub(crate) const DISTINCT: f64 = 1.3;

/// The kinds of assembly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum AssemblyKind {
    /// Coaxial cylinders and cones, end on end.
    Stack,
    /// A top on parallel, equal legs.
    Table,
    /// A ball with radial tubes.
    SphereTubes,
    /// A brick with studs on its top face.
    BrickStuds,
    /// A box with pipes out of orthogonal faces.
    BoxPipes,
    /// A mug-like body with a straight, L or U handle at its side.
    Handle,
    /// A main pipe with a branch meeting its side (T joint), maybe an L joint at an end.
    Tee,
    /// A box with two or three equal prongs standing on one face.
    Plug,
    /// A horizontal body with three equal vertical valves standing on it.
    Valves,
    /// A stem on a base with symmetric pairs of arms and equal candles.
    Menorah,
    /// Two or three unrelated objects of the kinds [`AssemblyKind::OBJECTS`] side by side.
    Scene,
    /// A row of equal boxes touching face to face: drawers in a chest, books on a shelf.
    Drawers,
}

impl AssemblyKind {
    /// Every kind.
    pub(crate) const ALL: [Self; 12] = [
        Self::Stack,
        Self::Table,
        Self::SphereTubes,
        Self::BrickStuds,
        Self::BoxPipes,
        Self::Handle,
        Self::Tee,
        Self::Plug,
        Self::Valves,
        Self::Menorah,
        Self::Scene,
        Self::Drawers,
    ];

    /// The kinds of issue 16's wider snapping test (`synthetic_conditions`), the first
    /// five of [`AssemblyKind::ALL`].
    pub(crate) const ISSUE_16: [Self; 5] = [
        Self::Stack,
        Self::Table,
        Self::SphereTubes,
        Self::BrickStuds,
        Self::BoxPipes,
    ];

    /// The kinds a [`AssemblyKind::Scene`] draws its objects from.
    pub(crate) const OBJECTS: [Self; 5] = [
        Self::Handle,
        Self::Tee,
        Self::Plug,
        Self::Valves,
        Self::Menorah,
    ];

    /// A short name.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Stack => "stack",
            Self::Table => "table",
            Self::SphereTubes => "ball+tubes",
            Self::BrickStuds => "brick+studs",
            Self::BoxPipes => "box+pipes",
            Self::Handle => "handle",
            Self::Tee => "tee",
            Self::Plug => "plug",
            Self::Valves => "valves",
            Self::Menorah => "menorah",
            Self::Scene => "scene",
            Self::Drawers => "drawers",
        }
    }
}

/// A relation the assembly was designed with, between parts (indices into
/// [`Assembly::parts`]) and their features named on the truth.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Designed {
    /// The kind.
    pub(crate) kind: RelationKind,
    /// The parts.
    pub(crate) members: Vec<usize>,
    /// The feature of each part (`None` for kinds about the whole solid).
    pub(crate) features: Vec<Option<&'static str>>,
}

fn rel(kind: RelationKind, a: (usize, &'static str), b: (usize, &'static str)) -> Designed {
    Designed {
        kind,
        members: vec![a.0, b.0],
        features: vec![Some(a.1), Some(b.1)],
    }
}

fn equal_length(a: usize, b: usize) -> Designed {
    Designed {
        kind: RelationKind::EqualLength,
        members: vec![a, b],
        features: vec![None, None],
    }
}

/// A drawn assembly.
#[derive(Clone, Debug)]
pub(crate) struct Assembly {
    /// Its kind.
    pub(crate) kind: AssemblyKind,
    /// The ground-truth parts in model space, in the order they are placed.
    pub(crate) parts: Vec<Primitive>,
    /// The designed relations.
    pub(crate) designed: Vec<Designed>,
    /// The object (of a [`AssemblyKind::Scene`]) each part belongs to: parts of
    /// different objects have no designed relation. All 0 for the other kinds.
    pub(crate) object: Vec<usize>,
    /// The strokes of every part, part after part.
    pub(crate) strokes: Vec<SynthStroke>,
    /// The part (index into `parts`) each stroke belongs to.
    pub(crate) part_of: Vec<usize>,
    /// The hand.
    pub(crate) style: Style,
}

impl Assembly {
    /// The strokes as a sketch, each with the renderer's class as an override (as the
    /// single-primitive test gives the classes to the snapper).
    pub(crate) fn sketch(&self) -> Sketch {
        Sketch {
            strokes: self
                .strokes
                .iter()
                .enumerate()
                .map(|(i, s)| Stroke {
                    id: StrokeId(i as u32),
                    points: s.points.clone(),
                    closed: false,
                    class_override: Some(s.class),
                })
                .collect(),
            view_box: None,
        }
    }

    /// One placement step per part, perturbed as a person or a script gives it (see
    /// [`placement`]).
    pub(crate) fn steps(&self, rng: &mut Rng) -> Vec<Step> {
        self.parts
            .iter()
            .map(|p| Step::Place {
                kind: p.kind(),
                placement: placement(p, rng),
            })
            .collect()
    }
}

/// The seed-determined assembly of `kind`.
pub(crate) fn assembly(kind: AssemblyKind, seed: u64) -> Assembly {
    let mut rng = Rng::new(seed);
    let style = Style::random(&mut rng);
    let view = match kind {
        AssemblyKind::SphereTubes => DQuat::IDENTITY,
        _ => view(&mut rng),
    };
    let design = canonical(kind, &mut rng, view);
    // A scene's objects are about 1 across each, side by side: drawn 500–900 units
    // across each, the row spans most of the sketch, centred in it.
    let (size, centre) = if kind == AssemblyKind::Scene {
        let size = rng.log_range(500.0, 900.0);
        let centre = DVec3::new(
            1500.0 + rng.range(-150.0, 150.0),
            -1500.0 + rng.range(-300.0, 300.0),
            rng.range(-300.0, 300.0),
        );
        (size, centre)
    } else {
        let size = rng.log_range(600.0, 1800.0);
        let centre = DVec3::new(
            rng.range(size, 3000.0 - size),
            -rng.range(size, 3000.0 - size),
            rng.range(-size, size),
        );
        (size, centre)
    };
    let parts: Vec<Primitive> = design
        .parts
        .iter()
        .map(|p| moved(p, view, size, centre))
        .collect();
    let mut strokes = Vec::new();
    let mut part_of = Vec::new();
    for (i, p) in parts.iter().enumerate() {
        let mut drawn = draw(p, style, &mut rng);
        if kind == AssemblyKind::Drawers {
            drawn.retain(|s| in_the_row(&parts, i, &s.label));
        }
        part_of.extend(std::iter::repeat_n(i, drawn.len()));
        strokes.extend(drawn);
    }
    Assembly {
        kind,
        parts,
        designed: design.designed,
        object: design.object,
        strokes,
        part_of,
        style,
    }
}

/// An assembly in the canonical frame: its parts, its designed relations and the object
/// each part belongs to (all 0 but in a [`AssemblyKind::Scene`]).
#[derive(Clone, Debug)]
pub(crate) struct Design {
    /// The parts, in the order they are placed.
    pub(crate) parts: Vec<Primitive>,
    /// The designed relations.
    pub(crate) designed: Vec<Designed>,
    /// The object of each part.
    pub(crate) object: Vec<usize>,
}

impl Design {
    /// One object's parts and relations.
    fn one((parts, designed): (Vec<Primitive>, Vec<Designed>)) -> Self {
        Self {
            object: vec![0; parts.len()],
            parts,
            designed,
        }
    }
}

/// The parts of an assembly of `kind`, its designed relations and objects, in the
/// canonical frame, for the designer's `view` (the turn [`moved`] will give them; a
/// ball's tubes are directed for the identity view, see the module docs).
pub(crate) fn canonical(kind: AssemblyKind, rng: &mut Rng, view: DQuat) -> Design {
    match kind {
        AssemblyKind::Scene => scene(rng, view),
        _ => Design::one(object(kind, rng, view)),
    }
}

/// The parts and designed relations of one object of `kind` (not a scene) in the
/// canonical frame, for the designer's `view`.
fn object(kind: AssemblyKind, rng: &mut Rng, view: DQuat) -> (Vec<Primitive>, Vec<Designed>) {
    match kind {
        AssemblyKind::Stack => stack(rng),
        AssemblyKind::Table => table(rng),
        AssemblyKind::SphereTubes => sphere_tubes(rng),
        AssemblyKind::BrickStuds => brick_studs(rng),
        AssemblyKind::BoxPipes => box_pipes(rng, view),
        AssemblyKind::Handle => handle(rng),
        AssemblyKind::Tee => tee(rng),
        AssemblyKind::Plug => plug(rng, view),
        AssemblyKind::Valves => valves(rng),
        AssemblyKind::Menorah => menorah(rng),
        AssemblyKind::Drawers => drawers(rng),
        AssemblyKind::Scene => unreachable!("a scene is made of objects, not one"),
    }
}

/// The part `p` turned by `r`, scaled by `s` about the origin and moved by `t`.
pub(crate) fn moved(p: &Primitive, r: DQuat, s: f64, t: DVec3) -> Primitive {
    match p {
        Primitive::Cylinder(c) => Primitive::Cylinder(Cylinder {
            center: r * c.center * s + t,
            axis: r * c.axis,
            length: c.length * s,
            radius: c.radius * s,
        }),
        Primitive::Cone(c) => Primitive::Cone(Cone {
            center: r * c.center * s + t,
            axis: r * c.axis,
            length: c.length * s,
            radius_bottom: c.radius_bottom * s,
            radius_top: c.radius_top * s,
        }),
        Primitive::Sphere(b) => Primitive::Sphere(Sphere {
            center: r * b.center * s + t,
            radius: b.radius * s,
        }),
        Primitive::Cuboid(b) => Primitive::Cuboid(Cuboid {
            center: r * b.center * s + t,
            rotation: r * b.rotation,
            size: b.size * s,
        }),
        Primitive::Sgc(_) | Primitive::Bgc(_) => unreachable!("assemblies have no SGC or BGC"),
    }
}

/// A designer's view of the canonical frame (module docs).
pub(crate) fn view(rng: &mut Rng) -> DQuat {
    let max_z = 25f64.to_radians().cos();
    loop {
        let pitch = rng.degrees(10.0, 45.0) * rng.sign();
        let yaw = rng.degrees(10.0, 80.0) * rng.sign();
        let roll = rng.range(0.0, TAU);
        let r = DQuat::from_rotation_z(roll)
            * DQuat::from_rotation_x(pitch)
            * DQuat::from_rotation_y(yaw);
        if [DVec3::X, DVec3::Y, DVec3::Z]
            .iter()
            .all(|a| (0.15..=max_z).contains(&(r * *a).z.abs()))
        {
            return r;
        }
    }
}

/// A value in [lo, hi) that differs by at least [`DISTINCT`] from every value of
/// `taken` (the last try when none is found).
fn distinct(rng: &mut Rng, lo: f64, hi: f64, taken: &[f64]) -> f64 {
    let mut v = rng.range(lo, hi);
    for _ in 0..200 {
        if taken.iter().all(|t| v.max(*t) / v.min(*t) >= DISTINCT) {
            return v;
        }
        v = rng.range(lo, hi);
    }
    v
}

/// A part along +Y from `bottom` (its bottom end's height) with an upright axis.
fn upright_cylinder(x: f64, bottom: f64, z: f64, length: f64, radius: f64) -> Primitive {
    Primitive::Cylinder(Cylinder {
        center: DVec3::new(x, bottom + length / 2.0, z),
        axis: DVec3::Y,
        length,
        radius,
    })
}

fn stack(rng: &mut Rng) -> (Vec<Primitive>, Vec<Designed>) {
    let n = 2 + (rng.next_u64() % 2) as usize;
    let mut parts = Vec::with_capacity(n);
    let (mut radii, mut lengths) = (Vec::new(), Vec::new());
    let mut y = -0.5;
    for _ in 0..n {
        let length = distinct(rng, 0.22, 0.42, &lengths);
        lengths.push(length);
        if rng.chance(0.6) {
            let radius = distinct(rng, 0.1, 0.36, &radii);
            radii.push(radius);
            parts.push(upright_cylinder(0.0, y, 0.0, length, radius));
        } else {
            // A cone whose contours are clearly there: |slope| ≤ 0.37 keeps |β| ≤ 0.8 in
            // every view (elevation ≤ 65°).
            let (mut rb, mut rt) = (0.3, 0.15);
            for _ in 0..100 {
                rb = distinct(rng, 0.12, 0.36, &radii);
                rt = distinct(rng, 0.08, 0.3, &[&radii[..], &[rb]].concat());
                if (rb - rt).abs() / length <= 0.37 {
                    break;
                }
            }
            rt = rb + (rt - rb).clamp(-0.37 * length, 0.37 * length);
            radii.extend([rb, rt]);
            parts.push(Primitive::Cone(Cone {
                center: DVec3::new(0.0, y + length / 2.0, 0.0),
                axis: DVec3::Y,
                length,
                radius_bottom: rb,
                radius_top: rt,
            }));
        }
        y += length;
    }
    let mut designed = Vec::new();
    for i in 0..n - 1 {
        designed.push(rel(RelationKind::Coaxial, (i, "top"), (i + 1, "bottom")));
        designed.push(rel(RelationKind::Concentric, (i, "top"), (i + 1, "bottom")));
    }
    (parts, designed)
}

fn table(rng: &mut Rng) -> (Vec<Primitive>, Vec<Designed>) {
    let thickness = rng.range(0.15, 0.25);
    let leg_length = rng.range(0.5, 0.8);
    let leg_radius = leg_length * rng.range(0.09, 0.12);
    let mut parts = Vec::new();
    let corners: Vec<DVec2> = if rng.chance(0.5) {
        let radius = rng.range(0.4, 0.5);
        parts.push(Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::Y,
            length: thickness,
            radius,
        }));
        let n = if rng.chance(0.5) { 3 } else { 4 };
        let phase = rng.range(0.0, TAU);
        (0..n)
            .map(|k| DVec2::from_angle(phase + TAU * k as f64 / n as f64) * (0.65 * radius))
            .collect()
    } else {
        let depth = rng.range(0.55, 0.9);
        parts.push(Primitive::Cuboid(Cuboid {
            center: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
            size: DVec3::new(1.0, thickness, depth),
        }));
        let margin = 1.5 * leg_radius + 0.04;
        let (hx, hz) = (0.5 - margin, depth / 2.0 - margin);
        vec![
            DVec2::new(-hx, -hz),
            DVec2::new(hx, -hz),
            DVec2::new(hx, hz),
            DVec2::new(-hx, hz),
        ]
    };
    for c in &corners {
        parts.push(upright_cylinder(
            c.x,
            -thickness / 2.0 - leg_length,
            c.y,
            leg_length,
            leg_radius,
        ));
    }
    let designed = table_relations(parts.len());
    (parts, designed)
}

/// The designed relations of a table of `n` parts (the top, then the legs).
fn table_relations(n: usize) -> Vec<Designed> {
    let mut designed = vec![rel(RelationKind::Parallel, (0, "top"), (1, "top"))];
    for leg in 1..n {
        designed.push(rel(RelationKind::Coplanar, (0, "bottom"), (leg, "top")));
        if leg + 1 < n {
            designed.push(rel(RelationKind::Parallel, (leg, "top"), (leg + 1, "top")));
            designed.push(rel(
                RelationKind::SameRadius,
                (leg, "top"),
                (leg + 1, "top"),
            ));
            designed.push(equal_length(leg, leg + 1));
        }
    }
    designed
}

/// A table of the wider variety (module docs, "Conditions"): a thin disc top (thickness
/// 0.1–0.3 × its radius) or a slab (thickness 1/15–1/5 of its width), on rod-like legs
/// (length over radius 8–20).
fn wide_table(rng: &mut Rng) -> (Vec<Primitive>, Vec<Designed>) {
    let leg_length = rng.range(0.5, 0.8);
    let leg_radius = leg_length / rng.range(8.0, 20.0);
    let mut parts = Vec::new();
    let (thickness, corners): (f64, Vec<DVec2>) = if rng.chance(0.5) {
        let radius = rng.range(0.4, 0.5);
        let thickness = radius * rng.range(0.1, 0.3);
        parts.push(Primitive::Cylinder(Cylinder {
            center: DVec3::ZERO,
            axis: DVec3::Y,
            length: thickness,
            radius,
        }));
        let n = if rng.chance(0.5) { 3 } else { 4 };
        let phase = rng.range(0.0, TAU);
        let corners = (0..n)
            .map(|k| DVec2::from_angle(phase + TAU * k as f64 / n as f64) * (0.65 * radius))
            .collect();
        (thickness, corners)
    } else {
        let thickness = rng.log_range(1.0 / 15.0, 0.2);
        let depth = rng.range(0.5, 0.9);
        parts.push(Primitive::Cuboid(Cuboid {
            center: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
            size: DVec3::new(1.0, thickness, depth),
        }));
        let margin = 1.5 * leg_radius + 0.04;
        let (hx, hz) = (0.5 - margin, depth / 2.0 - margin);
        let corners = vec![
            DVec2::new(-hx, -hz),
            DVec2::new(hx, -hz),
            DVec2::new(hx, hz),
            DVec2::new(-hx, hz),
        ];
        (thickness, corners)
    };
    for c in &corners {
        parts.push(upright_cylinder(
            c.x,
            -thickness / 2.0 - leg_length,
            c.y,
            leg_length,
            leg_radius,
        ));
    }
    let designed = table_relations(parts.len());
    (parts, designed)
}

/// The seed-determined assembly of `kind` of the wider variety (tables of
/// [`wide_table`]; the other kinds as [`assembly`] builds them), seen from a view of
/// `condition`'s range ([`view_in`]) and drawn part by part under `condition` with
/// hidden lines when `hidden_lines` ([`draw_with`]).
pub(crate) fn assembly_with(
    kind: AssemblyKind,
    seed: u64,
    condition: Condition,
    hidden_lines: bool,
) -> Assembly {
    assembly_with_hand(kind, seed, condition, hidden_lines, 1.0)
}

/// [`assembly_with`] drawn by a hand whose errors are scaled by `hand`
/// ([`Style::steadier`]): the same parts, view and condition.
pub(crate) fn assembly_with_hand(
    kind: AssemblyKind,
    seed: u64,
    condition: Condition,
    hidden_lines: bool,
    hand: f64,
) -> Assembly {
    let mut rng = Rng::new(seed);
    let style = Style::random(&mut rng).steadier(hand);
    let view = match kind {
        AssemblyKind::SphereTubes => DQuat::IDENTITY,
        _ => view_in(&mut rng, condition.view()),
    };
    let design = match kind {
        AssemblyKind::Table => Design::one(wide_table(&mut rng)),
        _ => canonical(kind, &mut rng, view),
    };
    let size = rng.log_range(600.0, 1800.0);
    let centre = DVec3::new(
        rng.range(size, 3000.0 - size),
        -rng.range(size, 3000.0 - size),
        rng.range(-size, size),
    );
    let parts: Vec<Primitive> = design
        .parts
        .iter()
        .map(|p| moved(p, view, size, centre))
        .collect();
    let mut strokes = Vec::new();
    let mut part_of = Vec::new();
    for (i, p) in parts.iter().enumerate() {
        let mut drawn = draw_with(p, style, &mut rng, condition, hidden_lines);
        if kind == AssemblyKind::Drawers {
            drawn.retain(|s| in_the_row(&parts, i, &s.label));
        }
        part_of.extend(std::iter::repeat_n(i, drawn.len()));
        strokes.extend(drawn);
    }
    Assembly {
        kind,
        parts,
        designed: design.designed,
        object: design.object,
        strokes,
        part_of,
        style,
    }
}

/// Whether the edge of box `m` of a row of touching boxes ([`drawers`]) that `label`
/// names (as the renderer names a box's edges) is drawn in the row's drawing: the row
/// is one box to the eye, whose faces hide what lies behind them. An edge on the face
/// two boxes share is drawn once (by the first of them), and only where it lies on a
/// face of the row that faces the viewer (a line across the chest's front); the hidden
/// ones are not drawn, even with hidden lines (a designer dashes the chest's hidden
/// corners, not the lines between drawers behind it). Every other edge lies on the
/// row's own edges and is drawn as the box alone draws it.
fn in_the_row(parts: &[Primitive], m: usize, label: &str) -> bool {
    let Primitive::Cuboid(b) = &parts[m] else {
        return true;
    };
    let Some((along, si, sj)) = edge_of(label) else {
        return true;
    };
    let axes = b.axes();
    let row = match parts.get(1).or(parts.first()) {
        Some(next) => {
            let d = next.center() - parts[0].center();
            (0..3)
                .max_by(|x, y| d.dot(axes[*x]).abs().total_cmp(&d.dot(axes[*y]).abs()))
                .unwrap_or(0)
        }
        None => return true,
    };
    let (i, j) = ((along + 1) % 3, (along + 2) % 3);
    // The edge's side along the row, and the face of the row it lies on otherwise.
    let (on_row, other, s_other) = if i == row {
        (si, j, sj)
    } else if j == row {
        (sj, i, si)
    } else {
        return true;
    };
    // Which way the row runs along that axis (the first box at its low end or not).
    let ahead = (parts[parts.len() - 1].center() - parts[0].center()).dot(axes[row]) > 0.0;
    let toward_next = (on_row > 0.0) == ahead;
    let shared = if toward_next {
        m + 1 < parts.len()
    } else {
        m > 0
    };
    if !shared {
        return true;
    }
    // The later box's copy of a shared edge is left out; the first's is drawn where the
    // row's face it lies on faces the viewer.
    toward_next && axes[other].z * s_other > 0.0
}

/// The axis a box edge runs along and its two signs, from the renderer's label
/// (`"edge ∥x (+1,-1)"`, maybe `"hidden "` before it and a piece number after it).
fn edge_of(label: &str) -> Option<(usize, f64, f64)> {
    let rest = label.trim_start_matches("hidden ").strip_prefix("edge ∥")?;
    let along = ["x", "y", "z"].iter().position(|a| rest.starts_with(a))?;
    let signs = rest.get(1..)?.trim().strip_prefix('(')?;
    let (si, rest) = signs.split_once(',')?;
    let (sj, _) = rest.split_once(')')?;
    Some((along, si.parse().ok()?, sj.parse().ok()?))
}

/// A view of the canonical frame from `range`: a designer's view ([`view`]); nearly
/// along the up axis (within 10°–25° of the view direction); or from the side (the up
/// axis 2.9°–8.6° out of the view plane, no axis within 25° of the view direction: a
/// box's top face nearly edge-on but not quite, see the renderer's "Views").
pub(crate) fn view_in(rng: &mut Rng, range: ViewRange) -> DQuat {
    let max_z = 25f64.to_radians().cos();
    match range {
        ViewRange::Designer => view(rng),
        ViewRange::NearAxial => loop {
            let r = random_rotation(rng);
            if (max_z..=10f64.to_radians().cos()).contains(&(r * DVec3::Y).z.abs()) {
                return r;
            }
        },
        ViewRange::SideOn => loop {
            let r = random_rotation(rng);
            let z = [DVec3::X, DVec3::Y, DVec3::Z].map(|a| (r * a).z.abs());
            if (0.05..=0.15).contains(&z[1]) && z.iter().all(|v| *v <= max_z) {
                return r;
            }
        },
    }
}

fn sphere_tubes(rng: &mut Rng) -> (Vec<Primitive>, Vec<Designed>) {
    let radius = 0.35;
    let n = 2 + (rng.next_u64() % 3) as usize;
    let equal = rng.chance(0.5);
    let mut dirs: Vec<DVec3> = Vec::new();
    let (lo, hi) = (10f64.to_radians().sin(), 60f64.to_radians().sin());
    let mut tries = 0;
    while dirs.len() < n {
        tries += 1;
        if tries > 10_000 {
            dirs.clear();
            tries = 0;
        }
        let d = rng.unit_vector();
        if !(lo..=hi).contains(&d.z.abs()) {
            continue;
        }
        let ok = dirs.iter().all(|e| {
            let angle = d.angle_between(*e).to_degrees();
            let apart = (40.0..=70.0).contains(&angle) || (110.0..=140.0).contains(&angle);
            let drawn = d.truncate().angle_to(e.truncate()).abs().to_degrees();
            apart && drawn >= 30.0
        });
        if ok {
            dirs.push(d);
        }
    }
    let mut parts = vec![Primitive::Sphere(Sphere {
        center: DVec3::ZERO,
        radius,
    })];
    let (mut radii, mut lengths) = (Vec::new(), Vec::new());
    let (r0, l0) = (rng.range(0.09, 0.15), rng.range(0.35, 0.6));
    for d in &dirs {
        let (r, l) = if equal {
            (r0, l0)
        } else {
            (
                distinct(rng, 0.07, 0.2, &radii),
                distinct(rng, 0.25, 0.8, &lengths),
            )
        };
        radii.push(r);
        lengths.push(l);
        parts.push(Primitive::Cylinder(Cylinder {
            center: *d * (radius + l / 2.0),
            axis: *d,
            length: l,
            radius: r,
        }));
    }
    let mut designed = Vec::new();
    for tube in 1..parts.len() {
        designed.push(rel(
            RelationKind::OnSphere,
            (0, "outline"),
            (tube, "bottom"),
        ));
        if equal && tube + 1 < parts.len() {
            designed.push(rel(
                RelationKind::SameRadius,
                (tube, "top"),
                (tube + 1, "top"),
            ));
            designed.push(equal_length(tube, tube + 1));
        }
    }
    (parts, designed)
}

fn brick_studs(rng: &mut Rng) -> (Vec<Primitive>, Vec<Designed>) {
    let depth = rng.range(0.45, 0.7);
    let height = rng.range(0.35, 0.5);
    let cols = 2 + (rng.next_u64() % 2) as usize;
    let rows = 1 + (rng.next_u64() % 2) as usize;
    let pitch = (1.0 / cols as f64).min(depth / rows as f64);
    let radius = pitch * rng.range(0.22, 0.3);
    let length = radius * rng.range(0.8, 1.2);
    let mut parts = vec![Primitive::Cuboid(Cuboid {
        center: DVec3::ZERO,
        rotation: DQuat::IDENTITY,
        size: DVec3::new(1.0, height, depth),
    })];
    for row in 0..rows {
        for col in 0..cols {
            let x = (col as f64 + 0.5) / cols as f64 - 0.5;
            let z = ((row as f64 + 0.5) / rows as f64 - 0.5) * depth;
            parts.push(upright_cylinder(x, height / 2.0, z, length, radius));
        }
    }
    let mut designed = vec![rel(RelationKind::Parallel, (0, "top"), (1, "top"))];
    for stud in 1..parts.len() {
        designed.push(rel(RelationKind::Coplanar, (0, "top"), (stud, "bottom")));
        if stud + 1 < parts.len() {
            designed.push(rel(
                RelationKind::SameRadius,
                (stud, "top"),
                (stud + 1, "top"),
            ));
            designed.push(equal_length(stud, stud + 1));
        }
    }
    (parts, designed)
}

fn box_pipes(rng: &mut Rng, view: DQuat) -> (Vec<Primitive>, Vec<Designed>) {
    let size = DVec3::new(1.0, rng.range(0.5, 0.9), rng.range(0.5, 0.9));
    let mut parts = vec![Primitive::Cuboid(Cuboid {
        center: DVec3::ZERO,
        rotation: DQuat::IDENTITY,
        size,
    })];
    // The faces towards the viewer: one per local axis, with its outward sign.
    let mut faces: Vec<(usize, f64)> = (0..3)
        .map(|k| {
            let axis = DVec3::AXES[k];
            let sign = if (view * axis).z > 0.0 { 1.0 } else { -1.0 };
            (k, sign)
        })
        .collect();
    if rng.chance(0.5) {
        let drop = (rng.next_u64() % 3) as usize;
        faces.remove(drop);
    }
    let (mut radii, mut lengths) = (Vec::new(), Vec::new());
    let mut designed = Vec::new();
    for (k, sign) in &faces {
        let n = DVec3::AXES[*k] * *sign;
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let face_min = size[i].min(size[j]);
        let r = distinct(rng, 0.1 * face_min, 0.2 * face_min, &radii).max(0.06);
        let l = distinct(rng, 0.35, 0.7, &lengths);
        radii.push(r);
        lengths.push(l);
        let offset = DVec3::AXES[i] * (size[i] * rng.range(-0.15, 0.15))
            + DVec3::AXES[j] * (size[j] * rng.range(-0.15, 0.15));
        let base = n * (size[*k] / 2.0) + offset;
        parts.push(Primitive::Cylinder(Cylinder {
            center: base + n * (l / 2.0),
            axis: n,
            length: l,
            radius: r,
        }));
        let face = Feature::FACES[2 * k + usize::from(*sign < 0.0)].name();
        let pipe = parts.len() - 1;
        designed.push(rel(RelationKind::Coplanar, (0, face), (pipe, "bottom")));
        designed.push(rel(RelationKind::Parallel, (0, face), (pipe, "top")));
    }
    for a in 1..parts.len() {
        for b in a + 1..parts.len() {
            designed.push(rel(RelationKind::Orthogonal, (a, "top"), (b, "top")));
        }
    }
    (parts, designed)
}

/// A cylinder whose bottom end is centred at `bottom`, along the unit `axis`.
fn cylinder_from(bottom: DVec3, axis: DVec3, length: f64, radius: f64) -> Primitive {
    Primitive::Cylinder(Cylinder {
        center: bottom + axis * (length / 2.0),
        axis,
        length,
        radius,
    })
}

/// One of the four horizontal directions of the canonical frame (±X, ±Z).
fn horizontal(rng: &mut Rng) -> DVec3 {
    [DVec3::X, DVec3::NEG_X, DVec3::Z, DVec3::NEG_Z][(rng.next_u64() % 4) as usize]
}

/// The designed relations of a chain of equal cylinders (`parts`, consecutive pairs):
/// parallel, same radius and equal length.
fn equal_row(parts: &[usize], designed: &mut Vec<Designed>) {
    for w in parts.windows(2) {
        designed.push(rel(RelationKind::Parallel, (w[0], "top"), (w[1], "top")));
        designed.push(rel(RelationKind::SameRadius, (w[0], "top"), (w[1], "top")));
        designed.push(equal_length(w[0], w[1]));
    }
}

/// A mug-like body (an upright cylinder from a squat disc to a tall beaker) with a
/// handle at its side, out along a horizontal axis: a straight rod whose bottom end sits
/// on the body's side (orthogonal to the body); an L (a rod out of the side, then one
/// down from its end: orthogonal to the first, parallel to the body, one radius); or a U
/// (two equal rods out of the side at two heights and a grip joining their ends,
/// parallel to the body, one radius).
fn handle(rng: &mut Rng) -> (Vec<Primitive>, Vec<Designed>) {
    use RelationKind::{Orthogonal, Parallel, SameRadius};
    let radius = rng.log_range(0.15, 0.4);
    let height = (radius * rng.log_range(0.5, 4.0)).clamp(0.12, 1.0);
    let out = horizontal(rng);
    let rod = radius * rng.log_range(0.07, 0.25);
    let side = |y: f64| out * radius + DVec3::Y * y;
    let mut parts = vec![cylinder_from(
        DVec3::NEG_Y * (height / 2.0),
        DVec3::Y,
        height,
        radius,
    )];
    let mut designed = vec![rel(Orthogonal, (0, "top"), (1, "top"))];
    let shortest = (3.0 * rod).max(0.1);
    match rng.next_u64() % 3 {
        0 => {
            let y = height * rng.range(-0.25, 0.25);
            let l = distinct(rng, shortest.max(0.25), 0.75, &[height]);
            parts.push(cylinder_from(side(y), out, l, rod));
        }
        1 => {
            let y = height * rng.range(0.1, 0.35);
            let l1 = distinct(rng, shortest, shortest + 0.35, &[height]);
            let l2 = distinct(rng, shortest, shortest + 0.5, &[height, l1]);
            parts.push(cylinder_from(side(y), out, l1, rod));
            let corner = side(y) + out * (l1 - rod);
            parts.push(cylinder_from(corner - DVec3::Y * l2, DVec3::Y, l2, rod));
            designed.extend([
                rel(Orthogonal, (1, "top"), (2, "top")),
                rel(Parallel, (0, "top"), (2, "top")),
                rel(SameRadius, (1, "top"), (2, "top")),
            ]);
        }
        _ => {
            let (hi, lo) = (
                height * rng.range(0.15, 0.35),
                -height * rng.range(0.15, 0.35),
            );
            let grip = hi - lo;
            let l = distinct(rng, shortest, shortest + 0.3, &[height, grip]);
            parts.push(cylinder_from(side(hi), out, l, rod));
            parts.push(cylinder_from(side(lo), out, l, rod));
            parts.push(cylinder_from(
                side(lo) + out * (l - rod),
                DVec3::Y,
                grip,
                rod,
            ));
            designed.extend([
                rel(Parallel, (1, "top"), (2, "top")),
                equal_length(1, 2),
                rel(SameRadius, (1, "top"), (2, "top")),
                rel(SameRadius, (2, "top"), (3, "top")),
                rel(Parallel, (0, "top"), (3, "top")),
            ]);
        }
    }
    (parts, designed)
}

/// A main pipe along X (a long rod to a fat tube) with a thinner branch whose bottom end
/// sits on its side, at a right angle (T joint) or, in a quarter of the cases, leaning
/// 30°–60° from it (a lateral, Y joint: nothing designed between the two); in half of
/// the cases a third pipe at one end of the main one, at a right angle to it (L joint),
/// of the main pipe's radius in half of those.
fn tee(rng: &mut Rng) -> (Vec<Primitive>, Vec<Designed>) {
    use RelationKind::{Orthogonal, Parallel, SameRadius};
    const ACROSS: [DVec3; 4] = [DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z];
    let length = rng.range(0.7, 1.1);
    let radius = length * rng.log_range(0.03, 0.18);
    let mut parts = vec![cylinder_from(
        DVec3::NEG_X * (length / 2.0),
        DVec3::X,
        length,
        radius,
    )];
    let branch = ACROSS[(rng.next_u64() % 4) as usize];
    let branch_radius = radius * rng.range(0.3, 0.75);
    let branch_length = distinct(rng, 0.25, 0.7, &[length]);
    let x = length * rng.range(-0.25, 0.25);
    parts.push(cylinder_from(
        DVec3::X * x + branch * radius,
        branch,
        branch_length,
        branch_radius,
    ));
    let mut designed = vec![rel(Orthogonal, (0, "top"), (1, "top"))];
    if rng.chance(0.5) {
        let end = rng.sign();
        let dir = ACROSS[(rng.next_u64() % 4) as usize];
        let same = rng.chance(0.5);
        let r = if same {
            radius
        } else {
            distinct(rng, 0.25 * radius, 0.77 * radius, &[radius, branch_radius])
        };
        let l = distinct(rng, 0.25, 0.7, &[length, branch_length]);
        parts.push(cylinder_from(
            DVec3::X * (end * (length / 2.0 - r)) + dir * radius,
            dir,
            l,
            r,
        ));
        designed.push(rel(Orthogonal, (0, "top"), (2, "top")));
        let along = if dir.dot(branch).abs() > 0.5 {
            Parallel
        } else {
            Orthogonal
        };
        designed.push(rel(along, (1, "top"), (2, "top")));
        if same {
            designed.push(rel(SameRadius, (0, "top"), (2, "top")));
        }
    }
    // In a quarter of the cases the branch is a lateral: leaning 30°–60° from square
    // towards either end of the main pipe (a Y joint: an end on a side that is not
    // square). Drawn last, so that every other draw of a case is as before.
    if rng.chance(0.25) {
        let lean = rng.degrees(30.0, 60.0) * rng.sign();
        let leaning = branch * lean.cos() + DVec3::X * lean.sin();
        parts[1] = cylinder_from(
            DVec3::X * x + branch * radius,
            leaning,
            branch_length,
            branch_radius,
        );
        designed.retain(|d| !d.members.contains(&1));
        if let Some(Primitive::Cylinder(third)) = parts.get(2) {
            if third.axis.dot(leaning).abs() < 1e-9 {
                designed.push(rel(Orthogonal, (1, "top"), (2, "top")));
            }
        }
    }
    (parts, designed)
}

/// A box body (a cube to a slab) with 2–3 equal prongs standing on the face of one axis
/// that faces the viewer, in a row: round pins (cylinders) or flat blades (thin boxes).
/// Designed: each prong's bottom coplanar with the face and its axis along the face
/// normal, the prongs parallel; pins also have one radius and one length (no relation
/// names equal box sizes).
fn plug(rng: &mut Rng, view: DQuat) -> (Vec<Primitive>, Vec<Designed>) {
    use RelationKind::{Coplanar, Parallel};
    let size = DVec3::new(1.0, rng.log_range(0.15, 0.9), rng.log_range(0.15, 0.9));
    let mut parts = vec![Primitive::Cuboid(Cuboid {
        center: DVec3::ZERO,
        rotation: DQuat::IDENTITY,
        size,
    })];
    let k = (rng.next_u64() % 3) as usize;
    let sign = if (view * DVec3::AXES[k]).z > 0.0 {
        1.0
    } else {
        -1.0
    };
    let normal = DVec3::AXES[k] * sign;
    let (mut i, mut j) = ((k + 1) % 3, (k + 2) % 3);
    if size[j] > size[i] {
        std::mem::swap(&mut i, &mut j);
    }
    let face = Feature::FACES[2 * k + usize::from(sign < 0.0)].name();
    let underside = Feature::FACES[2 * k + usize::from(sign > 0.0)].name();
    let count = 2 + (rng.next_u64() % 2) as usize;
    let pitch = size[i] * rng.range(0.18, 0.3);
    let length = rng.range(0.15, 0.6);
    let pins = rng.chance(0.5);
    let radius = (pitch * rng.range(0.12, 0.3)).min(0.3 * size[j]);
    let blade = DVec3::AXES[i] * (pitch * rng.range(0.25, 0.5))
        + DVec3::AXES[j] * (size[j] * rng.range(0.04, 0.12)).min(radius);
    let offset = DVec3::AXES[j] * (size[j] * rng.range(-0.15, 0.15));
    for m in 0..count {
        let t = (m as f64 - (count - 1) as f64 / 2.0) * pitch;
        let bottom = normal * (size[k] / 2.0) + DVec3::AXES[i] * t + offset;
        if pins {
            parts.push(cylinder_from(bottom, normal, length, radius));
        } else {
            parts.push(Primitive::Cuboid(Cuboid {
                center: bottom + normal * (length / 2.0),
                rotation: DQuat::IDENTITY,
                size: blade + DVec3::AXES[k] * length,
            }));
        }
    }
    let (top, bottom) = if pins {
        ("top", "bottom")
    } else {
        (face, underside)
    };
    let mut designed = Vec::new();
    for prong in 1..parts.len() {
        designed.push(rel(Coplanar, (0, face), (prong, bottom)));
        designed.push(rel(Parallel, (0, face), (prong, top)));
    }
    let prongs: Vec<usize> = (1..parts.len()).collect();
    if pins {
        equal_row(&prongs, &mut designed);
    } else {
        for w in prongs.windows(2) {
            designed.push(rel(Parallel, (w[0], top), (w[1], top)));
        }
    }
    (parts, designed)
}

/// 3–5 equal boxes in a row, each touching the next face to face: drawers stacked in a
/// chest (wide and flat, 3–8 times as wide as high, one on another along Y) or books
/// standing side by side on a shelf (thin and tall, one beside another along X).
/// Designed: each pair of neighbours' touching faces coplanar, and their fronts (+Z)
/// coplanar (no relation kind names equal boxes).
fn drawers(rng: &mut Rng) -> (Vec<Primitive>, Vec<Designed>) {
    let n = 3 + (rng.next_u64() % 3) as usize;
    let books = rng.chance(0.5);
    let along = usize::from(!books);
    let step = rng.range(0.6, 1.0) / n as f64;
    let size = if books {
        DVec3::new(step, rng.range(0.6, 1.0), rng.range(0.35, 0.7))
    } else {
        DVec3::new(1.0, step, rng.range(0.4, 0.9))
    };
    let parts: Vec<Primitive> = (0..n)
        .map(|m| {
            let t = (m as f64 - (n - 1) as f64 / 2.0) * step;
            Primitive::Cuboid(Cuboid {
                center: DVec3::AXES[along] * t,
                rotation: DQuat::IDENTITY,
                size,
            })
        })
        .collect();
    let (plus, minus) = (
        Feature::FACES[2 * along].name(),
        Feature::FACES[2 * along + 1].name(),
    );
    let front = Feature::FACES[4].name();
    let mut designed = Vec::new();
    for m in 1..n {
        designed.push(rel(RelationKind::Coplanar, (m - 1, plus), (m, minus)));
        designed.push(rel(RelationKind::Coplanar, (m - 1, front), (m, front)));
    }
    (parts, designed)
}

/// A trumpet-like row: a horizontal body cylinder along X (a thin rod to a fat tube)
/// with three equal vertical valves standing on its top side (designed: each valve
/// orthogonal to the body, the valves parallel, of one radius and one length).
fn valves(rng: &mut Rng) -> (Vec<Primitive>, Vec<Designed>) {
    let length = rng.range(0.8, 1.1);
    let radius = length * rng.log_range(0.04, 0.14);
    let mut parts = vec![cylinder_from(
        DVec3::NEG_X * (length / 2.0),
        DVec3::X,
        length,
        radius,
    )];
    let r = radius * rng.range(0.3, 0.75);
    let l = distinct(rng, 0.12, 0.5, &[length]);
    let pitch = length * rng.range(0.12, 0.28);
    let x0 = length * rng.range(-0.15, 0.15);
    let mut designed = Vec::new();
    for m in [-1.0, 0.0, 1.0] {
        parts.push(cylinder_from(
            DVec3::X * (x0 + m * pitch) + DVec3::Y * radius,
            DVec3::Y,
            l,
            r,
        ));
        designed.push(rel(
            RelationKind::Orthogonal,
            (0, "top"),
            (parts.len() - 1, "top"),
        ));
    }
    equal_row(&[1, 2, 3], &mut designed);
    (parts, designed)
}

/// A menorah: a base (a disc or a slab), an upright stem on its centre, 1–2 symmetric
/// pairs of straight arms out of the stem's sides along ±X (a pair in line, equally
/// long; every arm orthogonal to the stem, all of one radius), an equal candle standing
/// on each arm's end and one on the stem's top (candles parallel to the stem, of one
/// radius and one length; the top one coaxial with the stem).
fn menorah(rng: &mut Rng) -> (Vec<Primitive>, Vec<Designed>) {
    use RelationKind::{Coaxial, Concentric, Coplanar, Orthogonal, Parallel, SameRadius};
    let stem_length = rng.range(0.55, 0.85);
    let stem_radius = rng.range(0.02, 0.05);
    let disc = rng.chance(0.5);
    let (base, thickness) = if disc {
        let radius = rng.range(0.15, 0.3);
        let thickness = radius * rng.range(0.15, 0.4);
        let base = cylinder_from(DVec3::NEG_Y * 0.5, DVec3::Y, thickness, radius);
        (base, thickness)
    } else {
        let width = rng.range(0.3, 0.5);
        let thickness = rng.range(0.04, 0.1);
        let base = Primitive::Cuboid(Cuboid {
            center: DVec3::Y * (thickness / 2.0 - 0.5),
            rotation: DQuat::IDENTITY,
            size: DVec3::new(width, thickness, width * rng.range(0.5, 1.0)),
        });
        (base, thickness)
    };
    let foot = thickness - 0.5;
    let mut parts = vec![
        base,
        cylinder_from(DVec3::Y * foot, DVec3::Y, stem_length, stem_radius),
    ];
    let mut designed = if disc {
        vec![
            rel(Coaxial, (0, "top"), (1, "bottom")),
            rel(Concentric, (0, "top"), (1, "bottom")),
        ]
    } else {
        let top = Feature::FACES[2].name();
        vec![
            rel(Coplanar, (0, top), (1, "bottom")),
            rel(Parallel, (0, top), (1, "top")),
        ]
    };
    let arm_radius = stem_radius * rng.range(0.45, 0.75);
    let candle_radius = distinct(rng, 0.012, 0.04, &[arm_radius, stem_radius]);
    let candle_length = distinct(rng, 0.08, 0.2, &[stem_length]);
    let pairs = 1 + (rng.next_u64() % 2) as usize;
    let mut arm_lengths: Vec<f64> = Vec::new();
    let mut tips = Vec::new();
    for p in 0..pairs {
        let taken = [&[stem_length, candle_length][..], &arm_lengths[..]].concat();
        let l = distinct(rng, 0.12, 0.45, &taken);
        arm_lengths.push(l);
        let y = foot + stem_length * rng.range(0.4, 0.55) + 0.25 * stem_length * p as f64;
        let first = parts.len();
        for side in [-1.0, 1.0] {
            let out = DVec3::X * side;
            parts.push(cylinder_from(
                out * stem_radius + DVec3::Y * y,
                out,
                l,
                arm_radius,
            ));
            designed.push(rel(Orthogonal, (1, "top"), (parts.len() - 1, "top")));
            tips.push(out * (stem_radius + l - candle_radius) + DVec3::Y * (y + arm_radius));
        }
        designed.extend([
            rel(Coaxial, (first, "top"), (first + 1, "top")),
            equal_length(first, first + 1),
        ]);
        let arms: Vec<usize> = (2..parts.len()).collect();
        for w in arms.windows(2) {
            designed.push(rel(SameRadius, (w[0], "top"), (w[1], "top")));
        }
    }
    designed.dedup();
    let first_candle = parts.len();
    for tip in tips {
        parts.push(cylinder_from(tip, DVec3::Y, candle_length, candle_radius));
    }
    parts.push(cylinder_from(
        DVec3::Y * (foot + stem_length),
        DVec3::Y,
        candle_length,
        candle_radius,
    ));
    let top_candle = parts.len() - 1;
    designed.extend([
        rel(Coaxial, (1, "top"), (top_candle, "bottom")),
        rel(Concentric, (1, "top"), (top_candle, "bottom")),
        rel(Parallel, (1, "top"), (first_candle, "top")),
    ]);
    let candles: Vec<usize> = (first_candle..parts.len()).collect();
    equal_row(&candles, &mut designed);
    // In a quarter of the two-pair menorahs the outer pair is cut from a stock 4–10 %
    // thicker or thinner than the inner one: branches of one stem whose radii the
    // designer made differ by less than the same-radius threshold. Drawn from a
    // generator of its own, seeded by the case's sizes, so that no other draw of this
    // case or of a scene it is part of moves.
    let mut stock = Rng::new(arm_radius.to_bits() ^ candle_length.to_bits().rotate_left(17));
    if pairs == 2 && stock.chance(0.25) {
        let radius = arm_radius * (1.0 + stock.range(0.04, 0.1) * stock.sign());
        for arm in &mut parts[4..6] {
            if let Primitive::Cylinder(c) = arm {
                c.radius = radius;
            }
        }
        let across_pairs = rel(SameRadius, (3, "top"), (4, "top"));
        designed.retain(|d| *d != across_pairs);
    }
    (parts, designed)
}

/// The extent of a part's outline in the view plane (x, y), about its centre.
fn half_extent(p: &Primitive) -> DVec2 {
    let across =
        |a: DVec3, r: f64| DVec2::new(r * (1.0 - a.x * a.x).sqrt(), r * (1.0 - a.y * a.y).sqrt());
    match p {
        Primitive::Cylinder(c) => {
            c.axis.truncate().abs() * (c.length / 2.0) + across(c.axis, c.radius)
        }
        Primitive::Cone(c) => {
            c.axis.truncate().abs() * (c.length / 2.0)
                + across(c.axis, c.radius_bottom.max(c.radius_top))
        }
        Primitive::Sphere(s) => DVec2::splat(s.radius),
        Primitive::Cuboid(b) => b
            .axes()
            .iter()
            .zip([b.size.x, b.size.y, b.size.z])
            .map(|(a, s)| a.truncate().abs() * (s / 2.0))
            .sum(),
        Primitive::Sgc(_) | Primitive::Bgc(_) => unreachable!("assemblies have no SGC or BGC"),
    }
}

/// Two or three unrelated objects of [`AssemblyKind::OBJECTS`], each turned by its own
/// designer's view and scaled to its own size (its outline 0.75–1.3 across), side by
/// side in a row in the view plane with gaps of −8 % to +20 % of their mean width (so
/// neighbours may overlap slightly in the drawing), at different heights and depths.
/// The row, centred, is brought back into the canonical frame of `view` (which [`moved`]
/// will undo).
fn scene(rng: &mut Rng, view: DQuat) -> Design {
    let n = 2 + (rng.next_u64() % 2) as usize;
    // Each object in view space about the origin, with its outline's half extent.
    let mut objects = Vec::with_capacity(n);
    // Half of the scenes stand on one floor: every object upright (its Y) in one view,
    // turned only about its vertical, so that parts of different objects share that
    // direction and may line up by chance.
    let floor = rng.chance(0.5).then(|| self::view(rng));
    for _ in 0..n {
        let kind = AssemblyKind::OBJECTS[(rng.next_u64() % 5) as usize];
        let turn = match floor {
            Some(floor) => floor * DQuat::from_rotation_y(rng.range(0.0, TAU)),
            None => self::view(rng),
        };
        let (parts, designed) = object(kind, rng, turn);
        let parts: Vec<Primitive> = parts
            .iter()
            .map(|p| moved(p, turn, 1.0, DVec3::ZERO))
            .collect();
        let (lo, hi) = outline(&parts);
        let scale = rng.log_range(0.75, 1.3) / (hi - lo).max_element();
        let parts: Vec<Primitive> = parts
            .iter()
            .map(|p| moved(p, DQuat::IDENTITY, scale, DVec3::ZERO))
            .collect();
        objects.push((parts, designed, lo * scale, hi * scale));
    }
    let mean_width = objects.iter().map(|o| o.3.x - o.2.x).sum::<f64>() / n as f64;
    let mut design = Design {
        parts: Vec::new(),
        designed: Vec::new(),
        object: Vec::new(),
    };
    let mut cursor = 0.0;
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for (k, (parts, designed, a, b)) in objects.into_iter().enumerate() {
        let height = b.y - a.y;
        let shift = DVec3::new(
            cursor - a.x,
            -(a.y + b.y) / 2.0 + height * rng.range(-0.2, 0.2),
            mean_width * rng.range(-0.3, 0.3),
        );
        cursor += b.x - a.x + mean_width * rng.range(-0.08, 0.2);
        lo = lo.min(a + shift.truncate());
        hi = hi.max(b + shift.truncate());
        let first = design.parts.len();
        design.designed.extend(designed.into_iter().map(|mut d| {
            for m in &mut d.members {
                *m += first;
            }
            d
        }));
        design.object.extend(std::iter::repeat_n(k, parts.len()));
        design
            .parts
            .extend(parts.iter().map(|p| moved(p, DQuat::IDENTITY, 1.0, shift)));
    }
    let middle = ((lo + hi) / 2.0).extend(0.0);
    for p in &mut design.parts {
        let centred = moved(p, DQuat::IDENTITY, 1.0, -middle);
        *p = moved(&centred, view.inverse(), 1.0, DVec3::ZERO);
    }
    design
}

/// The corners of the box around the parts' outlines in the view plane.
fn outline(parts: &[Primitive]) -> (DVec2, DVec2) {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for p in parts {
        let (c, h) = (p.center().truncate(), half_extent(p));
        lo = lo.min(c - h);
        hi = hi.max(c + h);
    }
    (lo, hi)
}

/// The mirror image through the view plane, which an orthographic view cannot tell apart.
pub(crate) fn mirror(v: DVec3) -> DVec3 {
    DVec3::new(v.x, v.y, -v.z)
}

/// The six permutations of three indices.
pub(crate) const PERMUTATIONS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// The truth box's frame relabelled by its symmetries (signs, permutations and the
/// view's mirror) to the one nearest the palette's box with the same up direction: the
/// box a person means when giving its "apparent extents" (as in `synthetic_snap`).
/// Returns (up axis, sizes).
fn cuboid_as_a_person_sees_it(truth: &Cuboid) -> (DVec3, [f64; 3]) {
    let t = truth.axes();
    let mut best: Option<(f64, DVec3, [f64; 3])> = None;
    for m in [false, true] {
        for p in PERMUTATIONS {
            for signs in 0..8u32 {
                let axis = |i: usize| {
                    let s = if signs >> i & 1 == 1 { -1.0 } else { 1.0 };
                    let a = t[p[i]] * s;
                    if m {
                        mirror(a)
                    } else {
                        a
                    }
                };
                let c = [axis(0), axis(1), axis(2)];
                if c[0].cross(c[1]).dot(c[2]) <= 0.0 || c[1].truncate().length() < 1e-6 {
                    continue;
                }
                let mut place = Placement::at(DVec2::ZERO);
                place.axis = DVec2::new(c[1].x, -c[1].y);
                let Primitive::Cuboid(palette) =
                    Primitive::from_placement(PrimitiveKind::Cuboid, &place, 1.0)
                else {
                    continue;
                };
                let d = palette.axes();
                let score = (0..3).map(|i| c[i].dot(d[i])).sum::<f64>();
                if best.as_ref().is_none_or(|b| score > b.0) {
                    let sizes = [truth.size[p[0]], truth.size[p[1]], truth.size[p[2]]];
                    best = Some((score, c[1], sizes));
                }
            }
        }
    }
    let (_, up, sizes) = best.expect("a right-handed relabelling exists");
    (up, sizes)
}

/// How far a drop is from the truth: its centre by up to `centre` × the part's size (in
/// a uniformly random direction of the view plane), its axis by up to `axis_deg` (a 3D
/// rotation about a uniformly random axis, then projected), each size by a factor
/// uniform in 1 ± `size`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Perturbation {
    /// Largest centre offset, a fraction of the part's size.
    pub(crate) centre: f64,
    /// Largest axis tilt in degrees.
    pub(crate) axis_deg: f64,
    /// Largest relative size error.
    pub(crate) size: f64,
}

impl Perturbation {
    /// The drops of `synthetic_snap` and `synthetic_relations`: 15 %, 15°, ±25 %.
    pub(crate) const SCRIPT: Self = Self {
        centre: 0.15,
        axis_deg: 15.0,
        size: 0.25,
    };
    /// The drops of issue 16 (`synthetic_conditions`): 10 %, 10°, ±25 %.
    pub(crate) const ISSUE_16: Self = Self {
        centre: 0.10,
        axis_deg: 10.0,
        size: 0.25,
    };
}

/// The placement a person (or a script step) gives for a part, the drops of both
/// synthetic tests: centre off by up to 15 % of the part's size, axis by up to 15° (a 3D
/// rotation, then projected), sizes by ±25 % ([`Perturbation::SCRIPT`]).
pub(crate) fn placement(truth: &Primitive, rng: &mut Rng) -> Placement {
    perturbed_placement(truth, rng, Perturbation::SCRIPT)
}

/// The placement of a part off its truth by up to `off` (see [`Perturbation`]); a box's
/// sizes are given for the labelling of its axes a person sees (the palette's box with
/// the same up direction), an SGC's or BGC's radius as the mean of its radii and a BGC's
/// axis and length as its chord's.
pub(crate) fn perturbed_placement(
    truth: &Primitive,
    rng: &mut Rng,
    off: Perturbation,
) -> Placement {
    let size = truth.size();
    let offset = DVec2::from_angle(rng.range(0.0, TAU)) * (rng.range(0.0, off.centre) * size);
    let mut p = Placement::at(sketch_from_view(truth.center().truncate() + offset));
    let tilt = DQuat::from_axis_angle(rng.unit_vector(), rng.degrees(0.0, off.axis_deg));
    let sketch_axis = |a: DVec3| {
        let a = tilt * a;
        DVec2::new(a.x, -a.y)
    };
    let (lo, hi) = (1.0 - off.size, 1.0 + off.size);
    let mut f = || rng.range(lo, hi);
    match truth {
        Primitive::Cylinder(c) => {
            p.axis = sketch_axis(c.axis);
            p.length = Some(c.length * c.axis.truncate().length() * f());
            p.radius = Some(c.radius * f());
        }
        Primitive::Cone(c) => {
            p.axis = sketch_axis(c.axis);
            p.length = Some(c.length * c.axis.truncate().length() * f());
            p.radius_bottom = Some(c.radius_bottom * f());
            p.radius_top = Some(c.radius_top * f());
        }
        Primitive::Sphere(s) => p.radius = Some(s.radius * f()),
        Primitive::Cuboid(b) => {
            let (up, sizes) = cuboid_as_a_person_sees_it(b);
            p.axis = sketch_axis(up);
            p.size = Some([sizes[0] * f(), sizes[1] * f(), sizes[2] * f()]);
        }
        Primitive::Sgc(s) => {
            let mean = s.radii.iter().sum::<f64>() / s.radii.len() as f64;
            p.axis = sketch_axis(s.axis);
            p.length = Some(s.length * s.axis.truncate().length() * f());
            p.radius = Some(mean * f());
        }
        Primitive::Bgc(b) => {
            let chord = b.spine[b.spine.len() - 1] - b.spine[0];
            let mean = b.radii.iter().sum::<f64>() / b.radii.len() as f64;
            p.axis = sketch_axis(chord.normalize());
            p.length = Some(chord.truncate().length() * f());
            p.radius = Some(mean * f());
        }
    }
    p
}
