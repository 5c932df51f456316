//! Benchmarks of the glTF export: a 200-primitive model (the six kinds in turn, random
//! poses and sizes in a 2000-unit box) at the default tessellation
//! ([`DEFAULT_SEGMENTS`] segments per circle), encoded in memory as `.glb` and as
//! `.gltf`, and exported to a file (encoding plus the atomic write with its `fsync`),
//! with the file sizes.
//!
//! Run with `cargo bench --no-default-features --bench gltf`.

#![expect(clippy::print_stdout, reason = "benchmark output")]

mod support;

use geosnap::core::model::{Document, Fit, Placed};
use geosnap::core::primitive::{Bgc, Cone, Cuboid, Cylinder, Primitive, Sgc, Sphere};
use geosnap::io::gltf::{encode_gltf, export_gltf, ExportSettings, GltfFormat, DEFAULT_SEGMENTS};
use glam::{DQuat, DVec3};
use support::{timed, Bench, Rng, Table};

/// The number of primitives of the model.
const PRIMITIVES: usize = 200;

fn unit(rng: &mut Rng) -> DVec3 {
    DVec3::new(rng.normal(), rng.normal(), rng.normal()).normalize_or(DVec3::Y)
}

/// The benchmark model: kinds in palette order, seeded random poses and sizes.
fn model() -> Document {
    let mut rng = Rng::new(200);
    let mut doc = Document::new();
    for i in 0..PRIMITIVES {
        let center = DVec3::new(
            rng.uniform(0.0, 2000.0),
            rng.uniform(-2000.0, 0.0),
            rng.uniform(-300.0, 300.0),
        );
        let (size, radius) = (rng.uniform(40.0, 200.0), rng.uniform(10.0, 50.0));
        let axis = unit(&mut rng);
        let primitive = match i % 6 {
            0 => Primitive::Cylinder(Cylinder {
                center,
                axis,
                length: size,
                radius,
            }),
            1 => Primitive::Cone(Cone {
                center,
                axis,
                length: size,
                radius_bottom: radius,
                radius_top: radius * rng.uniform(0.2, 0.9),
            }),
            2 => Primitive::Sphere(Sphere { center, radius }),
            3 => Primitive::Cuboid(Cuboid {
                center,
                rotation: DQuat::from_axis_angle(axis, rng.uniform(0.0, 3.0)),
                size: DVec3::new(size, rng.uniform(20.0, 150.0), rng.uniform(20.0, 150.0)),
            }),
            4 => Primitive::Sgc(Sgc {
                center,
                axis,
                length: size,
                radii: (0..8).map(|_| radius * rng.uniform(0.6, 1.2)).collect(),
            }),
            _ => {
                let bend = rng.uniform(0.1, 0.4);
                let spine = (0..7)
                    .map(|k| {
                        let t = bend * f64::from(k);
                        center + DVec3::new(size * t.sin(), size * (1.0 - t.cos()), 0.0)
                    })
                    .collect();
                Primitive::Bgc(Bgc::through(spine, radius * 0.5))
            }
        };
        doc.add(Placed {
            primitive,
            fit: Fit::default(),
        });
    }
    doc
}

fn main() {
    let bench = Bench::from_env();
    bench.print_intro("glTF export benchmarks");
    let doc = model();
    let settings = ExportSettings::default();
    let table = Table::new(
        &format!("{PRIMITIVES}-primitive model, {DEFAULT_SEGMENTS} segments per circle (default)"),
        34,
        &[("bytes", 9), ("triangles", 9)],
    );
    for format in [GltfFormat::Glb, GltfFormat::Gltf] {
        let mut last = None;
        let stats = bench.each(|_| {
            let (result, time) = timed(|| encode_gltf(&doc, format, &settings));
            last = result.ok().map(|(_, report)| report);
            time
        });
        let report = last.expect("the model exports");
        table.row(
            &format!("encode_gltf .{} (in memory)", format.extension()),
            &stats,
            &[report.bytes.to_string(), report.triangles.to_string()],
        );
    }
    let dir = std::env::temp_dir().join(format!("geosnap-bench-gltf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let path = dir.join("bench.glb");
    let mut last = None;
    let stats = bench.each(|_| {
        let (result, time) = timed(|| export_gltf(&doc, &path, &settings));
        last = result.ok();
        time
    });
    let report = last.expect("the model exports");
    table.row(
        "export_gltf .glb (file, atomic)",
        &stats,
        &[report.bytes.to_string(), report.triangles.to_string()],
    );
    std::fs::remove_dir_all(&dir).expect("cleaned up");
}
