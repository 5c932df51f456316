//! Session files end to end: a modelling session on the project's sample sketches is
//! saved, reopened and re-solved, and comes out as it went in; bad files give their
//! errors and garbled bytes never panic.

use std::path::{Path, PathBuf};

use geosnap::core::model::{
    run_steps, Companions, Document, GlobalSettings, LengthUnit, PrimitiveId, Quantity, Relation,
    SessionSettings,
};
use geosnap::core::primitive::{Feature, Primitive};
use geosnap::core::relation::{Mode, RelationKind};
use geosnap::core::sketch::StrokeId;
use geosnap::core::solve::SolveContext;
use geosnap::io::script::{load_script, parse_script};
use geosnap::io::session::{
    load_session, parse_session, save_session, session_bytes, Session, SessionError,
};
use geosnap::io::sketch_file::load_sketch;
use geosnap::io::svg::{import_svg, SvgOptions};
use geosnap::samples::{VASE_SCRIPT, VASE_SVG};
use proptest::prelude::*;
use serde_json::{json, Value};

/// A session of the bundled vase sample, with its part's length dimensioned and
/// re-solved so that the document holds a dimension and warm multipliers.
fn vase_session() -> Session {
    let sketch = import_svg(VASE_SVG.as_bytes(), &SvgOptions::default())
        .expect("the sample imports")
        .sketch;
    let script = parse_script(VASE_SCRIPT.as_bytes(), Path::new("")).expect("the script parses");
    let (mut document, _) = run_steps(
        &sketch,
        &script.steps,
        &SessionSettings::default(),
        SolveContext::default(),
    );
    dimension_first(&mut document);
    Session {
        sketch,
        image: Some(PathBuf::from("vase.png")),
        document,
    }
}

/// Dimensions the first part's first quantity 2 % above what it is, and re-solves it.
fn dimension_first(document: &mut Document) {
    let Some((id, quantity, value)) = document.primitives().find_map(|(id, placed)| {
        let q = *Quantity::of_kind(placed.primitive.kind()).first()?;
        Some((id, q, placed.primitive.quantity(q)?))
    }) else {
        return;
    };
    document
        .set_dimension(id, quantity, value * 1.02)
        .expect("a quantity of its kind");
    document.solve(
        Some(&[id]),
        &GlobalSettings::default(),
        Companions::default(),
    );
}

/// A sample sketch of `sketches/` run through its script.
fn sample_session(name: &str) -> Session {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("sketches");
    let script = load_script(dir.join(format!("{name}.script.json"))).expect("the script loads");
    let sketch = load_sketch(&script.sketch)
        .expect("the sketch loads")
        .sketch;
    let (mut document, _) = run_steps(
        &sketch,
        &script.steps,
        &SessionSettings::default(),
        SolveContext::default(),
    );
    let ids: Vec<PrimitiveId> = document.primitives().map(|(id, _)| id).collect();
    if document.relations().is_empty() && ids.len() >= 2 {
        // A relation the user added by hand, soft, so that modes are exercised.
        document
            .add_relation(Relation {
                kind: RelationKind::Parallel,
                members: vec![ids[0], ids[1]],
                features: [ids[0], ids[1]]
                    .map(|id| {
                        let kind = document.get(id).expect("placed").primitive.kind();
                        Feature::from_name(kind, "top")
                    })
                    .to_vec(),
                mode: Mode::Soft,
                inferred: None,
            })
            .expect("both parts have a top");
    }
    dimension_first(&mut document);
    Session {
        sketch,
        image: None,
        document,
    }
}

/// The largest difference between two primitives' geometry (a box's rotation compared
/// by its axes, since a quaternion and its negative are the same rotation).
fn difference(a: &Primitive, b: &Primitive) -> f64 {
    let gap = |x: &[f64], y: &[f64]| {
        if x.len() == y.len() {
            x.iter()
                .zip(y)
                .map(|(u, v)| (u - v).abs())
                .fold(0.0, f64::max)
        } else {
            f64::INFINITY
        }
    };
    match (a, b) {
        (Primitive::Cuboid(p), Primitive::Cuboid(q)) => {
            let flat = |c: &geosnap::core::primitive::Cuboid| {
                let mut v = c.center.to_array().to_vec();
                v.extend(c.size.to_array());
                for axis in c.axes() {
                    v.extend(axis.to_array());
                }
                v
            };
            gap(&flat(p), &flat(q))
        }
        _ if a.kind() == b.kind() => gap(&a.params(), &b.params()),
        _ => f64::INFINITY,
    }
}

fn stroke_ids(document: &Document, id: PrimitiveId) -> Option<Vec<Vec<StrokeId>>> {
    document.snap_record(id).map(|r| {
        r.assignment
            .curves
            .iter()
            .map(|c| c.iter().map(|a| a.stroke).collect())
            .collect()
    })
}

/// Everything a session keeps is back, and a re-solve of both gives the same model.
fn assert_round_trip(session: &Session) {
    let bytes = session_bytes(session).expect("encodes");
    let back = parse_session(&bytes).expect("reads back");
    assert_eq!(back.sketch, session.sketch, "kept by the session file");
    assert_eq!(back.image, session.image, "kept by the session file");
    let (before, after) = (&session.document, &back.document);
    assert_eq!(before.len(), after.len(), "kept by the session file");
    for ((ia, a), (ib, b)) in before.primitives().zip(after.primitives()) {
        assert_eq!(ia, ib, "kept by the session file");
        assert!(
            difference(&a.primitive, &b.primitive) < 1e-12,
            "{:?} vs {:?}",
            a.primitive,
            b.primitive
        );
        assert_eq!(a.fit, b.fit, "kept by the session file");
        assert_eq!(
            stroke_ids(before, ia),
            stroke_ids(after, ib),
            "kept by the session file"
        );
        let (ra, rb) = (before.snap_record(ia), after.snap_record(ib));
        assert_eq!(
            ra.map(|r| r.rms),
            rb.map(|r| r.rms),
            "kept by the session file"
        );
        let samples = |r: Option<&geosnap::core::model::SnapRecord>| {
            r.map(|r| {
                r.assignment
                    .curves
                    .iter()
                    .map(|c| c.iter().map(|a| a.samples.clone()).collect::<Vec<_>>())
                    .collect::<Vec<_>>()
            })
        };
        assert_eq!(samples(ra), samples(rb), "the same samples are rebuilt");
    }
    assert_eq!(
        before.relations(),
        after.relations(),
        "kept by the session file"
    );
    assert_eq!(
        before.dimensions(),
        after.dimensions(),
        "kept by the session file"
    );
    assert_eq!(before.skipped, after.skipped, "kept by the session file");
    assert_eq!(before.unit(), after.unit(), "kept by the session file");
    for (id, _) in before.primitives() {
        assert_eq!(before.name(id), after.name(id), "kept by the session file");
    }
    assert_eq!(
        before.next_id(),
        after.next_id(),
        "deleted parts' ids stay retired"
    );
    assert!(
        before.warm_multipliers().eq(after.warm_multipliers()),
        "warm starts kept"
    );

    let (mut before, mut after) = (before.clone(), after.clone());
    let settings = GlobalSettings::default();
    let a = before.solve(None, &settings, Companions::default());
    let b = after.solve(None, &settings, Companions::default());
    assert_eq!(a.conflicts, b.conflicts, "kept by the session file");
    for ((_, p), (_, q)) in before.primitives().zip(after.primitives()) {
        let d = difference(&p.primitive, &q.primitive);
        assert!(
            d <= 1e-9 * p.primitive.size().max(1.0),
            "re-solves differ by {d}"
        );
    }
}

#[test]
fn the_ids_of_deleted_parts_stay_retired_after_reopening() {
    let mut session = vase_session();
    let part = session
        .document
        .primitives()
        .next()
        .expect("a part")
        .1
        .clone();
    let extra = session.document.add(part.clone());
    session.document.remove(extra);
    let back = parse_session(&session_bytes(&session).expect("encodes")).expect("reads back");
    let mut document = back.document;
    let next = document.add(part);
    assert!(next > extra, "{next:?} after {extra:?}");
}

/// Issue 18: part names and the document's unit are kept by the session (in its
/// model); a session without them reads as before (no names, millimetres).
#[test]
fn names_and_the_unit_round_trip_and_old_sessions_read_as_before() {
    let mut session = vase_session();
    let plain = session_bytes(&session).expect("encodes");
    let text = String::from_utf8_lossy(&plain);
    assert!(
        !text.contains(r#""unit""#) && !text.contains(r#""name""#),
        "millimetres and no names are left unsaid"
    );
    let back = parse_session(&plain).expect("reads back");
    assert_eq!(back.document.unit(), LengthUnit::Millimetre);

    let id = session.document.primitives().next().expect("a part").0;
    assert!(session.document.set_name(id, "Vase body “tall” 🏺"));
    session.document.set_unit(LengthUnit::Centimetre);
    let bytes = session_bytes(&session).expect("encodes");
    let value: Value = serde_json::from_slice(&bytes).expect("json");
    assert_eq!(value["model"]["unit"], json!("cm"));
    assert_eq!(
        value["model"]["primitives"][0]["name"],
        json!("Vase body “tall” 🏺")
    );
    assert_round_trip(&session);
    let back = parse_session(&bytes).expect("reads back");
    assert_eq!(back.document.name(id), Some("Vase body “tall” 🏺"));
    assert_eq!(back.document.unit(), LengthUnit::Centimetre);

    // A unit this build does not know is refused, named, with the one meant.
    let typo = changed(&session, |v| v["model"]["unit"] = json!("cn"));
    let error = chain(&parse_session(&typo).expect_err("refused"));
    assert!(error.contains(r#"unknown unit "cn""#), "{error}");
    let typo = changed(&session, |v| {
        let model = v["model"].as_object_mut().expect("an object");
        let unit = model.remove("unit").expect("a unit");
        model.insert("units".to_owned(), unit);
    });
    let error = chain(&parse_session(&typo).expect_err("refused"));
    assert!(error.contains("did you mean `unit`?"), "{error}");
}

#[test]
fn the_bundled_vase_round_trips_and_re_solves_alike() {
    let session = vase_session();
    assert!(!session.document.dimensions().is_empty(), "as expected");
    assert!(session.document.snap_records().count() > 0, "as expected");
    assert_round_trip(&session);
}

#[test]
fn the_sample_sketches_round_trip_with_their_relations() {
    let mut relations = 0;
    for name in ["cylinders", "cones", "box", "pipe"] {
        let session = sample_session(name);
        relations += session.document.relations().len();
        assert_round_trip(&session);
    }
    assert!(relations > 0, "some relations were exercised");
}

#[test]
fn save_and_load_go_through_the_file_with_the_image_resolved() {
    let dir = std::env::temp_dir().join(format!("geosnap-session-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let path = dir.join("vase.session.json");
    let session = vase_session();
    save_session(&path, &session).expect("saves");
    let back = load_session(&path).expect("loads");
    assert_eq!(back.image, Some(dir.join("vase.png")));
    assert_eq!(
        back.document.dimensions(),
        session.document.dimensions(),
        "kept by the session file"
    );
    let missing = load_session(dir.join("nothing.json")).expect_err("no such file");
    assert!(matches!(missing, SessionError::Read { .. }), "{missing}");
    std::fs::write(&path, b"{}").expect("writes");
    let error = load_session(&path).expect_err("not a session");
    assert!(error.to_string().contains("vase.session.json"), "{error}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The session's JSON, changed by `change`.
fn changed(session: &Session, change: impl FnOnce(&mut Value)) -> Vec<u8> {
    let mut value: Value =
        serde_json::from_slice(&session_bytes(session).expect("encodes")).expect("json");
    change(&mut value);
    serde_json::to_vec(&value).expect("encodes")
}

/// The error and its causes on one line.
fn chain(error: &SessionError) -> String {
    let mut text = error.to_string();
    let mut source = std::error::Error::source(error);
    while let Some(cause) = source {
        text.push_str(": ");
        text.push_str(&cause.to_string());
        source = cause.source();
    }
    text
}

#[test]
fn each_bad_input_gives_its_error() {
    let session = vase_session();
    let error = |bytes: &[u8]| parse_session(bytes).expect_err("refused");
    assert!(matches!(error(b"{nope"), SessionError::Json { .. }));
    assert!(matches!(error(b"[1, 2]"), SessionError::WrongFormat { .. }));
    let e = error(&changed(&session, |v| v["format"] = json!("geosnap-model")));
    assert!(
        matches!(e, SessionError::WrongFormat { .. }) && e.to_string().contains("geosnap-model"),
        "{e}"
    );
    let e = error(&changed(&session, |v| v["version"] = json!(2)));
    assert!(
        matches!(e, SessionError::UnsupportedVersion { .. }) && e.to_string().contains('2'),
        "{e}"
    );
    let e = error(&changed(&session, |v| {
        v.as_object_mut().expect("an object").remove("model");
    }));
    assert!(matches!(e, SessionError::Missing("model")), "{e}");
    let e = error(&changed(&session, |v| {
        v["sketch"]["strokes"][0]["points"] = json!([[0.0, 0.0]]);
    }));
    assert!(
        matches!(e, SessionError::Sketch { .. }) && chain(&e).contains("point"),
        "{}",
        chain(&e)
    );
    let e = error(&changed(&session, |v| {
        v["model"]["primitives"][0]["kind"] = json!("teapot");
    }));
    assert!(
        matches!(e, SessionError::Model { .. }) && chain(&e).contains("teapot"),
        "{}",
        chain(&e)
    );
    let e = error(&changed(&session, |v| {
        v["model"]["relations"] = json!([{ "kind": "parallel", "members": [0, 99] }]);
    }));
    assert!(
        matches!(e, SessionError::Model { .. }) && chain(&e).contains("no primitive 99"),
        "{}",
        chain(&e)
    );
    for (dimension, says) in [
        (
            json!({ "primitive": 99, "quantity": "length", "value": 1.0 }),
            "no primitive 99",
        ),
        (
            json!({ "primitive": 0, "quantity": "width", "value": 1.0 }),
            "has no width",
        ),
        (
            json!({ "primitive": 0, "quantity": "length", "value": -1.0 }),
            "positive",
        ),
    ] {
        let e = error(&changed(&session, |v| v["dimensions"] = json!([dimension])));
        assert!(
            matches!(e, SessionError::Dimension { index: 0, .. }) && chain(&e).contains(says),
            "{}",
            chain(&e)
        );
    }
    let e = error(&changed(&session, |v| {
        v["dimensions"] = json!([{ "primitive": 0, "quantity": "volume", "value": 1.0 }]);
    }));
    assert!(
        matches!(
            e,
            SessionError::Entry {
                field: "dimensions",
                ..
            }
        ),
        "{}",
        chain(&e)
    );
}

#[test]
fn bad_snap_records_give_their_errors() {
    let session = vase_session();
    let error = |bytes: &[u8]| parse_session(bytes).expect_err("refused");
    let e = error(&changed(&session, |v| {
        v["snaps"][0]["primitive"] = json!(99);
    }));
    assert!(
        matches!(e, SessionError::Snap { index: 0, .. }) && chain(&e).contains("no primitive 99"),
        "{}",
        chain(&e)
    );
    let e = error(&changed(&session, |v| {
        v["snaps"][0]["curves"][0] = json!([9999]);
    }));
    assert!(
        matches!(e, SessionError::Snap { .. }) && chain(&e).contains("stroke 9999"),
        "{}",
        chain(&e)
    );
    let e = error(&changed(&session, |v| {
        v["snaps"][0]["curves"] = json!([[]]);
    }));
    assert!(
        matches!(e, SessionError::Snap { .. }) && chain(&e).contains("projected curves"),
        "{}",
        chain(&e)
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Truncated or garbled session bytes give an error or a session, never a panic.
    #[test]
    fn garbled_bytes_never_panic(cut in 0.0f64..1.0, flips in prop::collection::vec((0.0f64..1.0, any::<u8>()), 0..6)) {
        thread_local! {
            static BYTES: Vec<u8> = session_bytes(&vase_session()).expect("encodes");
        }
        let mut bytes = BYTES.with(Clone::clone);
        let n = bytes.len();
        for (at, byte) in flips {
            let i = ((at * n as f64) as usize).min(n - 1);
            bytes[i] = byte;
        }
        bytes.truncate((cut * n as f64) as usize + usize::from(cut > 0.99) * n);
        let _ = parse_session(&bytes);
    }
}
