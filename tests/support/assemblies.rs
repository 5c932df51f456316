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
//! is drawn by [`draw_with`] under the condition, with hidden lines when asked. As in
//! [`assembly`], each part is drawn whole, as if the others were transparent, and
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
}

impl AssemblyKind {
    /// Every kind.
    pub(crate) const ALL: [Self; 5] = [
        Self::Stack,
        Self::Table,
        Self::SphereTubes,
        Self::BrickStuds,
        Self::BoxPipes,
    ];

    /// A short name.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Stack => "stack",
            Self::Table => "table",
            Self::SphereTubes => "ball+tubes",
            Self::BrickStuds => "brick+studs",
            Self::BoxPipes => "box+pipes",
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
    let (canonical, designed) = canonical(kind, &mut rng, view);
    let size = rng.log_range(600.0, 1800.0);
    let centre = DVec3::new(
        rng.range(size, 3000.0 - size),
        -rng.range(size, 3000.0 - size),
        rng.range(-size, size),
    );
    let parts: Vec<Primitive> = canonical
        .iter()
        .map(|p| moved(p, view, size, centre))
        .collect();
    let mut strokes = Vec::new();
    let mut part_of = Vec::new();
    for (i, p) in parts.iter().enumerate() {
        let drawn = draw(p, style, &mut rng);
        part_of.extend(std::iter::repeat_n(i, drawn.len()));
        strokes.extend(drawn);
    }
    Assembly {
        kind,
        parts,
        designed,
        strokes,
        part_of,
        style,
    }
}

/// The parts of an assembly of `kind` and its designed relations, in the canonical
/// frame, for the designer's `view` (the turn [`moved`] will give them; a ball's tubes
/// are directed for the identity view, see the module docs).
pub(crate) fn canonical(
    kind: AssemblyKind,
    rng: &mut Rng,
    view: DQuat,
) -> (Vec<Primitive>, Vec<Designed>) {
    match kind {
        AssemblyKind::Stack => stack(rng),
        AssemblyKind::Table => table(rng),
        AssemblyKind::SphereTubes => sphere_tubes(rng),
        AssemblyKind::BrickStuds => brick_studs(rng),
        AssemblyKind::BoxPipes => box_pipes(rng, view),
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
    let mut rng = Rng::new(seed);
    let style = Style::random(&mut rng);
    let view = match kind {
        AssemblyKind::SphereTubes => DQuat::IDENTITY,
        _ => view_in(&mut rng, condition.view()),
    };
    let (canonical, designed) = match kind {
        AssemblyKind::Table => wide_table(&mut rng),
        _ => canonical(kind, &mut rng, view),
    };
    let size = rng.log_range(600.0, 1800.0);
    let centre = DVec3::new(
        rng.range(size, 3000.0 - size),
        -rng.range(size, 3000.0 - size),
        rng.range(-size, size),
    );
    let parts: Vec<Primitive> = canonical
        .iter()
        .map(|p| moved(p, view, size, centre))
        .collect();
    let mut strokes = Vec::new();
    let mut part_of = Vec::new();
    for (i, p) in parts.iter().enumerate() {
        let drawn = draw_with(p, style, &mut rng, condition, hidden_lines);
        part_of.extend(std::iter::repeat_n(i, drawn.len()));
        strokes.extend(drawn);
    }
    Assembly {
        kind,
        parts,
        designed,
        strokes,
        part_of,
        style,
    }
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
