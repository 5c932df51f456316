//! Fuzzes the sketch importers: random bytes, random SVG-ish documents (random elements,
//! attributes, transforms and path data with garbage numbers) and random JSON must give
//! `Ok` or `Err`, never a panic or a hang.
//!
//! Each input runs on a named thread with a generous deadline, so a hang fails the test
//! instead of stalling the suite, and a panic is reported with the input that caused it.

use std::fmt::Write as _;
use std::sync::mpsc;
use std::time::Duration;

use geosnap::io::sketch_file::{load_sketch_from_bytes, parse_sketch_file};
use geosnap::io::svg::{import_svg, SvgOptions};
use proptest::prelude::*;

/// Far beyond any real import (milliseconds); only a hang gets near it.
const DEADLINE: Duration = Duration::from_mins(1);

/// Runs every importer on `data` on its own thread; fails on a panic or a hang, and
/// checks what an `Ok` must hold.
fn never_panics_or_hangs(data: Vec<u8>) {
    let (sender, receiver) = mpsc::channel();
    let worker = std::thread::Builder::new()
        .name("io-fuzz-case".to_owned())
        .spawn(move || {
            let options = SvgOptions::default();
            if let Ok(import) = import_svg(&data, &options) {
                for stroke in &import.sketch.strokes {
                    assert!(stroke.points.len() >= 2, "a stroke has < 2 points");
                    assert!(
                        stroke.points.iter().all(|p| p.is_finite()),
                        "a stroke has a non-finite point"
                    );
                }
                if import.sketch.strokes.is_empty() {
                    assert!(!import.warnings.is_empty(), "no strokes and no warning");
                }
            }
            let _ = parse_sketch_file(&data);
            let _ = load_sketch_from_bytes(&data, &options);
            let _ = sender.send(());
        })
        .expect("the worker thread starts");
    match receiver.recv_timeout(DEADLINE) {
        Ok(()) => worker.join().expect("the worker finished"),
        Err(mpsc::RecvTimeoutError::Timeout) => panic!("an importer hung for {DEADLINE:?}"),
        Err(mpsc::RecvTimeoutError::Disconnected) => match worker.join() {
            Ok(()) => panic!("the worker ended without reporting"),
            Err(payload) => std::panic::resume_unwind(payload),
        },
    }
}

/// Numbers a sloppy or hostile file may contain.
fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        12 => (-2000.0f64..2000.0).prop_map(|v| format!("{v:.3}")),
        4 => (-20i32..20).prop_map(|v| v.to_string()),
        1 => prop::sample::select(vec![
            "NaN", "nan", "inf", "-inf", "Infinity", "1e39", "-1e39", "3.4e38", "1e308",
            "1e-320", "1e400", "-0", ".", "-", "1e", "1e+", "0x10", "1,5", "", " ", "--5",
            "5e-", ".e1", "1.2.3", "99999999999999999999999", "1e-45", "1e38",
        ])
        .prop_map(str::to_owned),
    ]
}

/// Path data: commands mostly with the right number of arguments, now and then one
/// too few or too many, with the occasional garbage number.
fn path_data() -> impl Strategy<Value = String> {
    let command = prop::sample::select(vec![
        ("M", 2),
        ("m", 2),
        ("L", 2),
        ("l", 2),
        ("H", 1),
        ("h", 1),
        ("V", 1),
        ("v", 1),
        ("C", 6),
        ("c", 6),
        ("S", 4),
        ("s", 4),
        ("Q", 4),
        ("q", 4),
        ("T", 2),
        ("t", 2),
        ("A", 7),
        ("a", 7),
        ("Z", 0),
        ("z", 0),
        ("X", 2),
    ]);
    let segment = (
        command,
        prop_oneof![8 => Just(0i32), 1 => Just(-1), 1 => Just(1)],
        prop::collection::vec(number(), 8),
        prop::bool::ANY,
    )
        .prop_map(|((command, arity), off, numbers, commas)| {
            let count = usize::try_from((arity + off).max(0)).unwrap_or(0);
            let separator = if commas { "," } else { " " };
            format!("{command} {}", numbers[..count].join(separator))
        });
    prop::collection::vec(segment, 0..10).prop_map(|parts| parts.join(" "))
}

fn transform() -> impl Strategy<Value = String> {
    let function = prop::sample::select(vec![
        "matrix",
        "translate",
        "scale",
        "rotate",
        "skewX",
        "skewY",
        "bogus",
    ]);
    prop::collection::vec((function, prop::collection::vec(number(), 0..7)), 0..4).prop_map(
        |parts| {
            parts
                .into_iter()
                .map(|(f, args)| format!("{f}({})", args.join(" ")))
                .collect::<Vec<_>>()
                .join(" ")
        },
    )
}

/// One attribute as `(name, value)`.
fn attribute() -> impl Strategy<Value = (String, String)> {
    let numeric = prop::sample::select(vec![
        "x",
        "y",
        "width",
        "height",
        "cx",
        "cy",
        "r",
        "rx",
        "ry",
        "x1",
        "y1",
        "x2",
        "y2",
        "stroke-width",
        "opacity",
    ]);
    let styles = prop::sample::select(vec![
        "display:none",
        "visibility:hidden",
        "fill:none;stroke:black",
        "fill:none;stroke:none",
        "marker:url(#m)",
        "clip-path:url(#c)",
        "stroke:url(#nothing)",
        "transform: rotate(45deg)",
    ]);
    let fixed = prop::sample::select(vec![
        ("id", "m"),
        ("id", "c"),
        ("id", "p"),
        ("id", "g"),
        ("href", "#p"),
        ("href", "#g"),
        ("xlink:href", "#p"),
        ("fill", "none"),
        ("stroke", "black"),
        ("clip-path", "url(#c)"),
        ("marker-end", "url(#m)"),
        ("display", "none"),
        ("preserveAspectRatio", "xMaxYMin slice"),
        ("href", "data:image/png;base64,AAAA"),
        ("href", "/etc/passwd"),
    ]);
    prop_oneof![
        3 => path_data().prop_map(|d| ("d".to_owned(), d)),
        3 => (numeric, number()).prop_map(|(name, v)| (name.to_owned(), v)),
        2 => transform().prop_map(|t| ("transform".to_owned(), t)),
        1 => prop::collection::vec(number(), 0..9)
            .prop_map(|v| ("points".to_owned(), v.join(" "))),
        1 => prop::collection::vec(number(), 0..5)
            .prop_map(|v| ("viewBox".to_owned(), v.join(" "))),
        1 => styles.prop_map(|s| ("style".to_owned(), s.to_owned())),
        1 => fixed.prop_map(|(name, value)| (name.to_owned(), value.to_owned())),
    ]
}

/// Attributes with distinct names (XML forbids repeats), serialised.
fn attributes(max: usize) -> impl Strategy<Value = String> {
    prop::collection::vec(attribute(), 0..max).prop_map(|attributes| {
        let unique: std::collections::BTreeMap<String, String> = attributes.into_iter().collect();
        unique.iter().fold(String::new(), |mut out, (name, value)| {
            let _ = write!(out, " {name}=\"{value}\"");
            out
        })
    })
}

fn element_name() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "path",
        "rect",
        "circle",
        "ellipse",
        "line",
        "polyline",
        "polygon",
        "g",
        "svg",
        "use",
        "defs",
        "symbol",
        "clipPath",
        "mask",
        "marker",
        "pattern",
        "switch",
        "a",
        "text",
        "tspan",
        "image",
        "foreignObject",
        "style",
        "linearGradient",
        "filter",
        "unknown",
    ])
}

/// A `<path>` with (mostly plausible) data, so the geometry code sees plenty of input.
fn path_element() -> impl Strategy<Value = String> {
    (path_data(), attributes(3)).prop_map(|(d, attributes)| {
        let attributes = attributes.replace(" d=\"", " data-d=\"");
        format!("<path d=\"M 10 10 {d}\"{attributes}/>")
    })
}

/// A random element tree, serialised.
fn element() -> impl Strategy<Value = String> {
    let any_leaf = (element_name(), attributes(6))
        .prop_map(|(name, attributes)| format!("<{name}{attributes}/>"));
    let leaf = prop_oneof![2 => path_element(), 1 => any_leaf];
    leaf.prop_recursive(4, 48, 6, |inner| {
        (
            element_name(),
            attributes(4),
            prop::collection::vec(inner, 0..6),
        )
            .prop_map(|(name, attributes, children)| {
                format!("<{name}{attributes}>{}</{name}>", children.concat())
            })
    })
}

/// A random document: a root `<svg>` with random size attributes and content.
fn svg_document() -> impl Strategy<Value = String> {
    let length = prop_oneof![
        6 => (1.0f64..3000.0).prop_map(|v| format!("{v:.2}")),
        1 => (1.0f64..30.0).prop_map(|v| format!("{v:.2}in")),
        1 => number(),
    ];
    (
        prop::option::of(length.clone()),
        prop::option::of(length),
        prop::option::of(prop::collection::vec(number(), 0..5)),
        prop::option::of(prop::sample::select(vec![
            "none",
            "xMinYMax slice",
            "bogus",
        ])),
        prop::collection::vec(prop_oneof![path_element(), element()], 0..6),
    )
        .prop_map(|(width, height, view_box, aspect, children)| {
            let size = |name: &str, value: Option<String>| {
                value.map_or(String::new(), |v| format!(" {name}=\"{v}\""))
            };
            format!(
                "<svg xmlns=\"http://www.w3.org/2000/svg\" \
                 xmlns:xlink=\"http://www.w3.org/1999/xlink\"{}{}{}{}>{}</svg>",
                size("width", width),
                size("height", height),
                size("viewBox", view_box.map(|v| v.join(" "))),
                size("preserveAspectRatio", aspect.map(str::to_owned)),
                children.concat()
            )
        })
}

/// Random JSON values with the sketch file's keys, so validation paths are reached.
fn json_value() -> impl Strategy<Value = serde_json::Value> {
    use serde_json::{json, Value};
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(|v| json!(v)),
        any::<f64>().prop_map(|v| json!(v)),
        prop::sample::select(vec!["geosnap-sketch", "feature", "silhouette", "x", ""])
            .prop_map(|s| json!(s)),
    ];
    leaf.prop_recursive(4, 64, 6, |inner| {
        let key = prop::sample::select(vec![
            "format", "version", "image", "view_box", "strokes", "id", "points", "closed", "class",
            "other",
        ]);
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(Value::Array),
            prop::collection::btree_map(key, inner, 0..6).prop_map(|m| Value::Object(
                m.into_iter().map(|(k, v)| (k.to_owned(), v)).collect()
            )),
        ]
    })
}

/// Nearly valid sketch files: right header, mostly valid strokes with random flaws.
fn sketch_file() -> impl Strategy<Value = serde_json::Value> {
    use serde_json::{json, Value};
    let coordinate = prop_oneof![
        20 => (-1e6f64..1e6).prop_map(|v| json!(v)),
        1 => Just(Value::Null),
        1 => Just(json!("1")),
    ];
    let point = prop_oneof![
        20 => prop::collection::vec(coordinate.clone(), 2..=2),
        1 => prop::collection::vec(coordinate, 0..4),
    ];
    let class = prop_oneof![
        3 => Just(Value::Null),
        2 => Just(json!("feature")),
        2 => Just(json!("silhouette")),
        1 => json_value(),
    ];
    let stroke = (0u32..6, prop::collection::vec(point, 0..6), any::<bool>(), class).prop_map(
        |(id, points, closed, class)| {
            json!({ "id": id, "points": points, "closed": closed, "class": class })
        },
    );
    let view_box = prop_oneof![
        3 => Just(Value::Null),
        3 => (-1e3f64..1e3, -1e3f64..1e3, -1.0f64..1e3, -1.0f64..1e3)
            .prop_map(|(x, y, w, h)| json!([x, y, w, h])),
        1 => json_value(),
    ];
    (
        prop::sample::select(vec![0u64, 1, 1, 1, 1, 1, 1, 2, 99]),
        prop::collection::vec(stroke, 0..5),
        view_box,
    )
        .prop_map(|(version, strokes, view_box)| {
            json!({
                "format": "geosnap-sketch",
                "version": version,
                "view_box": view_box,
                "strokes": strokes,
            })
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_bytes(data in prop::collection::vec(any::<u8>(), 0..512)) {
        never_panics_or_hangs(data);
    }

    #[test]
    fn random_bytes_after_a_plausible_start(
        start in prop::sample::select(vec!["<svg", "<?xml version='1.0'?><svg ", "{\"format\":", "\u{feff}<"]),
        rest in prop::collection::vec(any::<u8>(), 0..256),
    ) {
        let mut data = start.as_bytes().to_vec();
        data.extend(rest);
        never_panics_or_hangs(data);
    }

    #[test]
    fn random_svg_documents(document in svg_document()) {
        never_panics_or_hangs(document.into_bytes());
    }

    #[test]
    fn random_svg_documents_cut_short(document in svg_document(), cut in 0.0f64..1.0) {
        let end = ((document.len() as f64) * cut) as usize;
        never_panics_or_hangs(document.as_bytes()[..end].to_vec());
    }

    #[test]
    fn random_json(value in json_value()) {
        never_panics_or_hangs(value.to_string().into_bytes());
    }

    #[test]
    fn random_sketch_files(value in sketch_file()) {
        never_panics_or_hangs(value.to_string().into_bytes());
    }
}
