//! glTF export of every sample model of the project (`sketches/*.script.json`, each run
//! headless as `geosnap run` does), read back with an independent reader, the `gltf`
//! crate: node names and count, mesh bounds against the model's extents in metres,
//! accessor bounds against the data, winding against the normals, and the `extras`
//! against the model. A second test runs the Khronos glTF-Validator over the same files
//! in both encodings (see [`validator_dir`] for when it runs).

use std::path::{Path, PathBuf};
use std::process::Command;

use base64::Engine as _;
use geosnap::core::model::{
    run_steps, Document, Fit, LengthUnit, Placed, PrimitiveId, Relation, SessionSettings,
};
use geosnap::core::primitive::{Bgc, Feature, Primitive, Sphere};
use geosnap::core::relation::{Mode, RelationKind};
use geosnap::core::solve::SolveContext;
use geosnap::io::gltf::{
    export_gltf, import_gltf_extras, node_name, node_names, ExportSettings, Origin,
    DEFAULT_METRES_PER_UNIT, ROOT_NAME,
};
use geosnap::io::script::load_script;
use geosnap::io::sketch_file::load_sketch;
use glam::{DMat4, DQuat, DVec3};

/// The environment variable that names the validator and makes its test mandatory.
const VALIDATOR_ENV: &str = "GEOSNAP_GLTF_VALIDATOR";

/// Each sample's name and model (with its inferred relations), with relations added
/// between its first primitives so that every multi-part sample's root `extras` carry a
/// hard and a soft relation, and its first two parts named alike (one name must become
/// two node names).
fn sample_models() -> Vec<(String, Document)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("sketches");
    let mut scripts: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("sketches/ is readable")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.to_string_lossy().ends_with(".script.json"))
        .collect();
    scripts.sort();
    assert!(scripts.len() >= 6, "six samples or more: {scripts:?}");
    scripts
        .iter()
        .map(|script_path| {
            let script = load_script(script_path).expect("the script loads");
            let sketch = load_sketch(&script.sketch).expect("the sketch loads");
            let (mut document, _) = run_steps(
                &sketch.sketch,
                &script.steps,
                &SessionSettings::default(),
                SolveContext::default(),
            );
            assert!(!document.is_empty(), "{}", script_path.display());
            let ids: Vec<PrimitiveId> = document.primitives().map(|(id, _)| id).collect();
            if let [a, b, ..] = ids[..] {
                // The feature of that name of a part, if its kind has one.
                let named = |id: PrimitiveId, name: &str| {
                    let kind = document.get(id).expect("placed").primitive.kind();
                    Feature::from_name(kind, name)
                };
                let (top, bottom) = (named(a, "top"), named(b, "bottom"));
                for (kind, features, mode) in [
                    (RelationKind::Parallel, vec![top, bottom], Mode::Hard),
                    (RelationKind::SameRadius, vec![top, bottom], Mode::Soft),
                ] {
                    document
                        .add_relation(Relation {
                            kind,
                            members: vec![a, b],
                            features,
                            mode,
                            inferred: None,
                        })
                        .expect("a valid relation");
                }
                for id in [a, b] {
                    assert!(document.set_name(id, "Pied «gauche» ⌀12"), "a part");
                }
            }
            let name = script_path
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .trim_end_matches(".script.json")
                .to_owned();
            (name, document)
        })
        .collect()
}

/// A scratch folder of this test process.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("geosnap-gltf-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    dir
}

/// The axis-aligned extents of a circle of radius `r` about `center` with unit normal
/// `n`: ± r·√(1 − nᵢ²) along each axis.
fn circle(center: DVec3, n: DVec3, r: f64) -> (DVec3, DVec3) {
    let e = (DVec3::ONE - n * n).max(DVec3::ZERO).powf(0.5) * r;
    (center - e, center + e)
}

fn union(boxes: impl IntoIterator<Item = (DVec3, DVec3)>) -> (DVec3, DVec3) {
    boxes
        .into_iter()
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
        .expect("at least one box")
}

/// The model's extents of a primitive in model units, from its parameters: the end
/// circles of solids of revolution, the profile circles of an SGC, the spine circles of a
/// BGC (normal to the spine), the box's corners; and its largest radius.
fn extents(p: &Primitive) -> ((DVec3, DVec3), f64) {
    let revolved = |center: DVec3, axis: DVec3, length: f64, radii: &[f64]| {
        let k = radii.len();
        union(radii.iter().enumerate().map(|(i, r)| {
            let h = length * (i as f64 / (k - 1) as f64 - 0.5);
            circle(center + axis * h, axis, *r)
        }))
    };
    let widest = |radii: &[f64]| radii.iter().copied().fold(0.0, f64::max);
    match p {
        Primitive::Cylinder(c) => (
            revolved(c.center, c.axis, c.length, &[c.radius, c.radius]),
            c.radius,
        ),
        Primitive::Cone(c) => (
            revolved(c.center, c.axis, c.length, &[c.radius_bottom, c.radius_top]),
            c.radius_bottom.max(c.radius_top),
        ),
        Primitive::Sgc(s) => (
            revolved(s.center, s.axis, s.length, &s.radii),
            widest(&s.radii),
        ),
        Primitive::Sphere(s) => ((s.center - s.radius, s.center + s.radius), s.radius),
        Primitive::Cuboid(b) => {
            let half = b
                .axes()
                .iter()
                .zip(b.size.to_array())
                .map(|(a, size)| a.abs() * size / 2.0)
                .sum::<DVec3>();
            ((b.center - half, b.center + half), 0.0)
        }
        Primitive::Bgc(b) => {
            let k = b.spine.len();
            let tangent =
                |i: usize| (b.spine[(i + 1).min(k - 1)] - b.spine[i.saturating_sub(1)]).normalize();
            (
                union((0..k).map(|i| circle(b.spine[i], tangent(i), b.radii[i]))),
                widest(&b.radii),
            )
        }
    }
}

/// The buffer of a read-back file: the GLB's BIN chunk, or the `.gltf`'s data URI.
fn buffer_data(gltf: &gltf::Gltf) -> Vec<u8> {
    if let Some(blob) = &gltf.blob {
        return blob.clone();
    }
    let Some(buffer) = gltf.buffers().next() else {
        return Vec::new();
    };
    let gltf::buffer::Source::Uri(uri) = buffer.source() else {
        panic!("a .gltf buffer is a URI")
    };
    let data = uri
        .strip_prefix("data:application/octet-stream;base64,")
        .expect("an embedded base64 buffer");
    base64::engine::general_purpose::STANDARD
        .decode(data)
        .expect("valid base64")
}

fn transform(node: &gltf::Node<'_>) -> DMat4 {
    let (t, r, s) = node.transform().decomposed();
    DMat4::from_scale_rotation_translation(
        DVec3::from(s.map(f64::from)),
        DQuat::from_array(r.map(f64::from)),
        DVec3::from(t.map(f64::from)),
    )
}

/// Checks one primitive node's mesh, material and extras; returns its local positions.
fn check_mesh(node: &gltf::Node<'_>, name: &str, kind: &str, data: &[u8]) -> Vec<[f32; 3]> {
    let extras: serde_json::Value =
        serde_json::from_str(node.extras().as_ref().expect("node extras").get())
            .expect("extras are JSON");
    assert_eq!(extras["kind"].as_str(), Some(kind), "{name}: extras kind");
    let mesh = node.mesh().expect("a mesh per primitive node");
    assert_eq!(mesh.primitives().count(), 1, "{name}: one mesh primitive");
    let primitive = mesh.primitives().next().expect("a mesh primitive");
    assert_eq!(
        primitive.mode(),
        gltf::mesh::Mode::Triangles,
        "{name}: triangles"
    );
    let material = primitive.material();
    assert_eq!(material.name(), Some(name), "{name}: its own material");
    let pbr = material.pbr_metallic_roughness();
    assert!(pbr.metallic_factor() < 0.5, "{name}: a dielectric");
    let reader = primitive.reader(|_| Some(data));
    let positions: Vec<[f32; 3]> = reader.read_positions().expect("positions").collect();
    let normals: Vec<[f32; 3]> = reader.read_normals().expect("normals").collect();
    let indices: Vec<u32> = reader.read_indices().expect("indices").into_u32().collect();
    assert_eq!(
        positions.len(),
        normals.len(),
        "{name}: a normal per vertex"
    );
    assert!(
        indices.iter().all(|i| (*i as usize) < positions.len()),
        "{name}: indices in range"
    );

    // Accessor bounds are exactly the f32 data's.
    let bounds = primitive.bounding_box();
    for k in 0..3 {
        let lo = positions.iter().map(|p| p[k]).fold(f32::INFINITY, f32::min);
        let hi = positions
            .iter()
            .map(|p| p[k])
            .fold(f32::NEG_INFINITY, f32::max);
        assert!(lo.to_bits() == bounds.min[k].to_bits(), "{name}: min {k}");
        assert!(hi.to_bits() == bounds.max[k].to_bits(), "{name}: max {k}");
    }
    // Unit normals, and counter-clockwise front faces (the winding agrees with them).
    let p = |i: u32| DVec3::from(positions[i as usize].map(f64::from));
    let n = |i: u32| DVec3::from(normals[i as usize].map(f64::from));
    assert!(
        normals.iter().all(|v| {
            let len = DVec3::from(v.map(f64::from)).length();
            (len - 1.0).abs() < 1e-6
        }),
        "{name}: unit normals"
    );
    for t in indices.chunks(3) {
        let face = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
        assert!(
            face.dot(n(t[0]) + n(t[1]) + n(t[2])) > 0.0,
            "{name}: {t:?} winds clockwise"
        );
    }
    positions
}

/// Reads one exported file back and checks it against the model.
fn check_file(path: &Path, document: &Document, settings: &ExportSettings) {
    let what = path.display();
    let bytes = std::fs::read(path).expect("the export exists");
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap_or_else(|e| panic!("{what}: {e}"));
    let data = buffer_data(&gltf);
    let s = settings.metres_per_unit();

    let scene = gltf.default_scene().expect("a default scene");
    let roots: Vec<gltf::Node<'_>> = scene.nodes().collect();
    assert_eq!(roots.len(), 1, "{what}: one root node");
    let root = &roots[0];
    assert_eq!(root.name(), Some(ROOT_NAME), "{what}: the root's name");
    assert!(root.mesh().is_none(), "{what}: the root has no mesh");
    assert_eq!(
        gltf.nodes().count(),
        document.len() + 1,
        "{what}: node count"
    );
    let names: Vec<String> = root
        .children()
        .map(|n| n.name().unwrap_or_default().to_owned())
        .collect();
    let node_names = node_names(document);
    let expected: Vec<String> = node_names.values().cloned().collect();
    assert_eq!(names, expected, "{what}: node names");
    let unique: std::collections::BTreeSet<&String> = names.iter().collect();
    assert_eq!(unique.len(), names.len(), "{what}: each node named once");
    for (id, placed) in document.primitives() {
        let name = &node_names[&id];
        match document.name(id) {
            // A given name, as given or with the part's id after it when taken.
            Some(given) => assert!(
                *name == given || *name == format!("{given}_{}", id.0),
                "{what}: {name} for {given}"
            ),
            None => assert_eq!(*name, node_name(placed.primitive.kind(), id), "{what}"),
        }
    }

    let root_from_model = transform(root);
    let mut world = Vec::new();
    for (node, (id, placed)) in root.children().zip(document.primitives()) {
        let kind = placed.primitive.kind();
        let name = node_names[&id].clone();
        let positions = check_mesh(&node, &name, kind.name(), &data);
        // The node's mesh, placed in the scene, covers the primitive's extents in metres.
        let world_from_local = root_from_model * transform(&node);
        let mesh_box = union(positions.iter().map(|q| {
            let w = world_from_local.transform_point3(DVec3::from(q.map(f64::from)));
            (w, w)
        }));
        let ((lo, hi), radius) = extents(&placed.primitive);
        let model_box = (
            root_from_model.transform_point3(lo * s),
            root_from_model.transform_point3(hi * s),
        );
        let sag = radius * s * (1.0 - (std::f64::consts::TAU / settings.segments() as f64).cos());
        let eps = 1e-6 * (model_box.1 - model_box.0).length().max(1e-3) + 1e-6;
        for k in 0..3 {
            let (m0, m1, e0, e1) = (mesh_box.0[k], mesh_box.1[k], model_box.0[k], model_box.1[k]);
            assert!(
                m0 >= e0 - eps && m0 <= e0 + sag + eps && m1 <= e1 + eps && m1 >= e1 - sag - eps,
                "{name} axis {k}: mesh {m0}..{m1}, model {e0}..{e1} (sag {sag})"
            );
        }
        world.push(mesh_box);
    }

    if settings.origin() == Origin::Ground && !document.is_empty() {
        let (lo, hi) = union(world);
        let tol = 1e-5 * (hi - lo).length();
        assert!(lo.y.abs() < tol, "{what}: stands on y = 0: {lo}");
        assert!(
            (lo.x + hi.x).abs() < tol && (lo.z + hi.z).abs() < tol,
            "{what}: centred"
        );
    }

    // The extras give the model back.
    let back = import_gltf_extras(path).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(
        (back.metres_per_unit - s).abs() <= 1e-15 * s,
        "{what}: the scale"
    );
    assert_eq!(back.document.relations(), document.relations(), "{what}");
    assert_eq!(back.document.len(), document.len(), "{what}: primitives");
    for (id, placed) in document.primitives() {
        let again = &back.document.get(id).expect("the same ids").primitive;
        assert_same(&placed.primitive, again, &format!("{what} #{}", id.0));
        assert_eq!(back.document.name(id), document.name(id), "{what}: names");
    }
}

/// The same primitive up to rounding (×s then ÷s); a box's rotation up to its sign.
fn assert_same(a: &Primitive, b: &Primitive, what: &str) {
    assert_eq!(a.kind(), b.kind(), "{what}");
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs()).max(1.0);
    let (pa, pb) = match (a, b) {
        (Primitive::Cuboid(x), Primitive::Cuboid(y)) => {
            let flat = |c: &geosnap::core::primitive::Cuboid| {
                let mut v = c.center.to_array().to_vec();
                v.extend(c.axes().iter().flat_map(DVec3::to_array));
                v.extend(c.size.to_array());
                v
            };
            (flat(x), flat(y))
        }
        (Primitive::Bgc(x), Primitive::Bgc(y)) => {
            let flat = |c: &Bgc| {
                let mut v: Vec<f64> = c.spine.iter().flat_map(DVec3::to_array).collect();
                v.extend(&c.radii);
                v.extend(c.plane_normal.to_array());
                v
            };
            (flat(x), flat(y))
        }
        _ => (a.params(), b.params()),
    };
    assert_eq!(pa.len(), pb.len(), "{what}");
    for (x, y) in pa.iter().zip(&pb) {
        assert!(close(*x, *y), "{what}: {x} vs {y}");
    }
}

#[test]
fn every_sample_exports_and_reads_back_with_the_gltf_crate() {
    let dir = scratch("roundtrip");
    let variants = [
        ExportSettings::default(),
        ExportSettings::new(0.0254, 7, Origin::Model).expect("valid settings"),
    ];
    for (name, document) in sample_models() {
        for (v, settings) in variants.iter().enumerate() {
            for ext in ["glb", "gltf"] {
                let path = dir.join(format!("{name}-{v}.{ext}"));
                let report = export_gltf(&document, &path, settings)
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                assert_eq!(report.nodes, document.len());
                assert!(report.warnings.is_empty(), "{:?}", report.warnings);
                check_file(&path, &document, settings);
            }
        }
    }
    std::fs::remove_dir_all(&dir).expect("cleaned up");
}

#[test]
fn an_empty_model_reads_back_empty() {
    let dir = scratch("empty");
    for ext in ["glb", "gltf"] {
        let path = dir.join(format!("empty.{ext}"));
        let report = export_gltf(&Document::new(), &path, &ExportSettings::default())
            .expect("an empty model exports");
        assert_eq!(report.warnings.len(), 1);
        check_file(&path, &Document::new(), &ExportSettings::default());
    }
    std::fs::remove_dir_all(&dir).expect("cleaned up");
}

/// The validator's package folder: `GEOSNAP_GLTF_VALIDATOR` when set (the test must run
/// then, and fails when it cannot), else `tools/validator` when `.ci/run` (or a
/// developer) installed it there; `None` skips the test with a note.
fn validator_dir() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os(VALIDATOR_ENV) {
        let dir = PathBuf::from(dir);
        assert!(
            dir.join("node_modules/gltf-validator").is_dir() || dir.join("package.json").is_file(),
            "{VALIDATOR_ENV}={} does not hold the gltf-validator package",
            dir.display()
        );
        return Some(dir);
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/validator");
    let node = Command::new("node").arg("--version").output().is_ok();
    (node && dir.join("node_modules/gltf-validator").is_dir()).then_some(dir)
}

#[test]
fn every_export_passes_the_khronos_validator() {
    let Some(validator) = validator_dir() else {
        eprintln!(
            "NOTE: glTF-Validator not installed (npm install in tools/validator, or set \
             {VALIDATOR_ENV}): validation skipped"
        );
        return;
    };
    let dir = scratch("validate");
    let mut models = sample_models();
    models.push(("empty".to_owned(), Document::new()));
    let mut tiny = Document::new();
    tiny.add(Placed {
        primitive: Primitive::Sphere(Sphere {
            center: DVec3::new(3.0, -4.0, 5.0),
            radius: 0.5,
        }),
        fit: Fit::default(),
    });
    models.push(("tiny".to_owned(), tiny));
    let mut files = Vec::new();
    for (name, document) in &models {
        for ext in ["glb", "gltf"] {
            let path = dir.join(format!("{name}.{ext}"));
            export_gltf(document, &path, &ExportSettings::default()).expect("exports");
            files.push(path);
        }
    }
    let coarse = dir.join("coarse.glb");
    let settings = ExportSettings::new(1.0, 3, Origin::Model).expect("valid settings");
    export_gltf(&models[0].1, &coarse, &settings).expect("exports");
    files.push(coarse);
    // A sphere of 200 × 401 vertices: u32 indices.
    let dense = dir.join("dense.gltf");
    let settings = ExportSettings::new(DEFAULT_METRES_PER_UNIT, 400, Origin::default())
        .expect("valid settings");
    let tiny = &models.last().expect("the tiny model").1;
    export_gltf(tiny, &dense, &settings).expect("exports");
    files.push(dense);

    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gltf_validate.mjs");
    let output = Command::new("node")
        .arg(script)
        .arg(&validator)
        .args(&files)
        .output()
        .expect("node runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "the validator found problems");
    assert_eq!(
        stdout.matches(": errors 0, warnings 0, infos 0").count(),
        files.len(),
        "one clean report per file"
    );
    std::fs::remove_dir_all(&dir).expect("cleaned up");
}

#[test]
fn the_cli_exports_a_model_file_and_refuses_bad_settings() {
    let dir = scratch("cli");
    let (_, document) = sample_models().swap_remove(0);
    let model = dir.join("sample.model.json");
    geosnap::io::model_file::save_model(&model, &document, "sample.svg").expect("saved");
    let geosnap = env!("CARGO_BIN_EXE_geosnap");
    let out = dir.join("sample.gltf");
    let run = Command::new(geosnap)
        .arg("export")
        .arg(&model)
        .arg("--out")
        .arg(&out)
        .args(["--scale", "0.01", "--segments", "12"])
        .output()
        .expect("the binary runs");
    assert!(run.status.success(), "{run:?}");
    let back = import_gltf_extras(&out).expect("the export reads back");
    assert!((back.metres_per_unit - 0.01).abs() < 1e-15, "the --scale");
    assert_eq!(back.document.len(), document.len(), "every primitive");
    // Without --scale, the model's unit decides: millimetres by default, inches here.
    for (unit, metres) in [(None, 0.001), (Some(LengthUnit::Inch), 0.0254)] {
        let mut document = document.clone();
        if let Some(unit) = unit {
            document.set_unit(unit);
        }
        geosnap::io::model_file::save_model(&model, &document, "sample.svg").expect("saved");
        let run = Command::new(geosnap)
            .arg("export")
            .arg(&model)
            .arg("--out")
            .arg(&out)
            .output()
            .expect("the binary runs");
        assert!(run.status.success(), "{run:?}");
        let back = import_gltf_extras(&out).expect("the export reads back");
        assert!(
            (back.metres_per_unit - metres).abs() < 1e-15,
            "{unit:?}: {}",
            back.metres_per_unit
        );
    }
    for (args, message) in [
        (["--scale", "-1"], "metres_per_unit = -1"),
        (["--segments", "2"], "segments = 2"),
    ] {
        let run = Command::new(geosnap)
            .arg("export")
            .arg(&model)
            .arg("--out")
            .arg(dir.join("bad.glb"))
            .args(args)
            .output()
            .expect("the binary runs");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "{args:?} must fail");
        assert!(stderr.contains(message), "{stderr}");
        assert!(!dir.join("bad.glb").exists(), "nothing written");
    }
    std::fs::remove_dir_all(&dir).expect("cleaned up");
}
