//! Benchmark of opening a large drawing (issue 18, "Large drawings"): a 2,900-stroke SVG
//! read from bytes ([`import_svg`]) and prepared for snapping
//! ([`SnapContext::prepare`]: clean-up, duplicate merging and classification), which is
//! what `geosnap check`, `geosnap run` and the application do before the first snap.
//!
//! The drawing is generated with a fixed seed from the project's sample drawings
//! (`sketches/*.svg`), tiled on a grid of 1200 × 900 cells, each copy turned by up to 5°
//! and scaled by 0.9–1.1, until 2,600 strokes; then 300 strokes of clutter (hatching,
//! short arcs and wobbly scribbles, drawn with a hand's jitter), and 2 % of the strokes
//! drawn a second time: half pasted exactly, half retraced within half a unit. The
//! preparation merges those duplicates and says how many it merged.
//!
//! Run with `cargo bench --no-default-features --bench open_drawing`. In smoke mode (and
//! in a debug build) the drawing holds 290 strokes instead.

#![expect(clippy::print_stdout, reason = "benchmark output")]

mod support;

use std::f64::consts::TAU;
use std::fmt::Write as _;
use std::path::Path;

use geosnap::core::snap::SnapContext;
use geosnap::io::svg::{import_svg, SvgOptions};
use glam::DVec2;
use support::{timed, Bench, Rng, Table};

/// A grid cell (the small samples' viewBox).
const CELL: DVec2 = DVec2::new(1200.0, 900.0);
/// The samples tiled, with their size in cells.
const SAMPLES: [(&str, u32); 8] = [
    ("box", 1),
    ("cones", 1),
    ("cylinders", 1),
    ("pipe", 1),
    ("sheet", 3),
    ("sphere", 1),
    ("stand", 1),
    ("vase", 1),
];

/// A polyline and whether it is closed.
type Polyline = (Vec<DVec2>, bool);

/// The strokes of each sample and its size in cells.
fn samples() -> Vec<(Vec<Polyline>, u32)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("sketches");
    SAMPLES
        .iter()
        .map(|&(name, cells)| {
            let svg =
                std::fs::read(dir.join(format!("{name}.svg"))).expect("the samples are there");
            let import = import_svg(&svg, &SvgOptions::default()).expect("the samples import");
            let strokes = import
                .sketch
                .strokes
                .into_iter()
                .map(|s| (s.points, s.closed))
                .collect();
            (strokes, cells)
        })
        .collect()
}

/// A clutter stroke near `at`, with a hand's jitter: a hatching line, a short arc or a
/// scribble.
fn clutter(rng: &mut Rng, at: DVec2) -> Polyline {
    let size = rng.uniform(20.0, 120.0);
    let angle = rng.uniform(0.0, TAU);
    let (u, v) = (DVec2::from_angle(angle), DVec2::from_angle(angle).perp());
    let kind = rng.uniform(0.0, 1.0);
    let jitter = |p: DVec2, rng: &mut Rng| p + 0.6 * DVec2::new(rng.normal(), rng.normal());
    let points: Vec<DVec2> = if kind < 0.5 {
        (0..12)
            .map(|i| at + u * size * (f64::from(i) / 11.0 - 0.5))
            .collect()
    } else if kind < 0.8 {
        let sweep = rng.uniform(0.5, 2.5);
        (0..16)
            .map(|i| {
                let t = sweep * f64::from(i) / 15.0;
                at + (u * t.cos() + v * t.sin()) * (size / 2.0)
            })
            .collect()
    } else {
        let mut p = at;
        (0..20)
            .map(|_| {
                p += DVec2::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)) * size / 4.0;
                p
            })
            .collect()
    };
    (points.into_iter().map(|p| jitter(p, rng)).collect(), false)
}

/// The drawing as SVG text: `sample_strokes` strokes of tiled samples, `clutter_strokes`
/// of clutter, and 2 % of them again (see the module docs); and its stroke count.
fn drawing(sample_strokes: usize, clutter_strokes: usize) -> (String, usize) {
    let samples = samples();
    let mut rng = Rng::new(18);
    let mut strokes: Vec<Polyline> = Vec::new();
    // Cells in rows of `columns`; a sample of 3 × 3 cells starts a new band of rows.
    let columns = 12u32;
    let (mut column, mut row, mut band) = (0u32, 0u32, 1u32);
    while strokes.len() < sample_strokes {
        let (sample, cells) = &samples[rng.index(samples.len())];
        if column + cells > columns {
            (column, row, band) = (0, row + band, 1);
        }
        let origin = CELL * DVec2::new(f64::from(column), f64::from(row));
        let centre = origin + CELL * f64::from(*cells) / 2.0;
        let turn = DVec2::from_angle(rng.uniform(-5.0, 5.0).to_radians());
        let scale = rng.uniform(0.9, 1.1);
        for (points, closed) in sample {
            let moved = points
                .iter()
                .map(|&p| centre + turn.rotate(p - CELL * f64::from(*cells) / 2.0) * scale)
                .collect();
            strokes.push((moved, *closed));
        }
        column += cells;
        band = band.max(*cells);
    }
    let size = CELL * DVec2::new(f64::from(columns), f64::from(row + band));
    for _ in 0..clutter_strokes {
        let at = DVec2::new(rng.uniform(0.0, size.x), rng.uniform(0.0, size.y));
        strokes.push(clutter(&mut rng, at));
    }
    let copies = strokes.len() / 50;
    for k in 0..copies {
        let (points, closed) = strokes[rng.index(strokes.len())].clone();
        let points = if k % 2 == 0 {
            points
        } else {
            let shift = DVec2::new(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5));
            points.iter().map(|&p| p + shift).collect()
        };
        strokes.push((points, closed));
    }
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {} {}\">\n",
        size.x, size.y
    );
    for (points, closed) in &strokes {
        svg.push_str("<path fill=\"none\" stroke=\"black\" d=\"");
        for (i, p) in points.iter().enumerate() {
            let _ = write!(
                svg,
                "{}{:.2},{:.2}",
                if i == 0 { "M" } else { " L" },
                p.x,
                p.y
            );
        }
        svg.push_str(if *closed { " Z\"/>\n" } else { "\"/>\n" });
    }
    svg.push_str("</svg>\n");
    (svg, strokes.len())
}

fn main() {
    let bench = Bench::from_env();
    bench.print_intro("Opening a large drawing");
    let (sample_strokes, clutter_strokes) = if bench.is_smoke() || cfg!(debug_assertions) {
        (260, 30)
    } else {
        (2600, 300)
    };
    let (svg, count) = drawing(sample_strokes, clutter_strokes);
    let table = Table::new(
        "Open (SVG bytes → import_svg → SnapContext::prepare; target ≤ 1 s for 2,900 strokes)",
        30,
        &[
            ("strokes", 8),
            ("import", 9),
            ("prepare", 9),
            ("merged", 6),
            ("kept", 6),
        ],
    );
    let case = format!("open a {count}-stroke drawing");
    if !bench.wants(&case) {
        return;
    }
    let mut last = None;
    let stats = bench.each(|_| {
        let (result, time) = timed(|| {
            let (import, import_time) =
                timed(|| import_svg(svg.as_bytes(), &SvgOptions::default()));
            let import = import.expect("the drawing imports");
            let (prepared, prepare_time) = timed(|| SnapContext::prepare(&import.sketch));
            (prepared, import_time, prepare_time)
        });
        last = Some(result);
        time
    });
    let Some((prepared, import_time, prepare_time)) = last else {
        return;
    };
    table.row(
        &case,
        &stats,
        &[
            count.to_string(),
            support::fmt_ns(import_time.as_nanos() as f64),
            support::fmt_ns(prepare_time.as_nanos() as f64),
            prepared.merged.len().to_string(),
            prepared.context.strokes.len().to_string(),
        ],
    );
}
