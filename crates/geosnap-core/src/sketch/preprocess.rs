//! Cleaning strokes before classification and snapping.
//!
//! [`preprocess`] turns imported or drawn strokes into well-behaved polylines: finite,
//! without repeated points, dots or duplicate strokes, uniformly resampled and lightly
//! smoothed.
//!
//! Every length threshold is a fraction of the *sketch size*, the diagonal of the
//! bounding box of all finite points, so the result does not depend on the drawing's
//! units: a sketch scaled by 10 preprocesses to the same strokes scaled by 10.

use std::collections::BTreeMap;

use glam::DVec2;

use super::{Sketch, Stroke, StrokeId};
use crate::geom::{segment_distance, BoxIndex};

/// Settings for [`preprocess`]; every length is a fraction of the sketch's bounding-box
/// diagonal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreprocessOptions {
    /// Target distance between consecutive resampled points. Default 0.005 (0.5 %: about
    /// 15 sketch units on a 2448 × 3264 drawing, 3.6 on a 512 × 512 one).
    pub spacing: f64,
    /// The fewest points a resampled stroke gets, however short. Default 8.
    pub min_points: usize,
    /// Strokes shorter than this are dots and are dropped. Default 0.002 (0.2 %).
    pub min_length: f64,
    /// Consecutive points closer than this are duplicates. Default 1e−9.
    pub duplicate_tolerance: f64,
    /// Passes of the `[1, 2, 1]/4` smoothing filter after resampling. Default 1.
    pub smoothing_passes: usize,
    /// The largest distance at which a stroke that retraces another counts as the same
    /// stroke drawn twice (a near duplicate, merged into the earlier one). The distance
    /// used is twice the drawing's jitter (see [`preprocess_report`]), at least a third
    /// of this and at most this. Default 0.0005 (0.05 %: about 0.75 units on a 1200 × 900
    /// drawing, 2 on a 2448 × 3264 one; the synthetic "sketchy" strokes, redrawn 0.3–1.2 %
    /// of a curve's extent apart, lost an assembly at 0.0015). 0 merges exact duplicates
    /// only.
    pub retrace_tolerance: f64,
}

impl Default for PreprocessOptions {
    fn default() -> Self {
        Self {
            spacing: 0.005,
            min_points: 8,
            min_length: 0.002,
            duplicate_tolerance: 1e-9,
            smoothing_passes: 1,
            retrace_tolerance: 0.0005,
        }
    }
}

/// A stroke merged into an earlier one because it is the same stroke drawn twice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MergedStroke {
    /// The stroke left out.
    pub dropped: StrokeId,
    /// The earlier stroke it repeats, which is kept.
    pub kept: StrokeId,
    /// Whether it repeats the kept stroke point for point (in either order), rather
    /// than retracing it within the tolerance.
    pub exact: bool,
}

/// What [`preprocess_report`] made of a sketch.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Preprocessed {
    /// The cleaned sketch.
    pub sketch: Sketch,
    /// One human-readable note per change that loses something (dropped points or
    /// strokes, merged duplicates), in stroke order.
    pub notes: Vec<String>,
    /// The duplicate strokes merged, exact and near, in the order of the strokes left
    /// out: what a user is told as "merged N duplicate strokes".
    pub merged: Vec<MergedStroke>,
}

/// Cleans, resamples and smooths every stroke of `sketch`, returning the new sketch and
/// one human-readable note per change that loses something (dropped points or strokes),
/// in stroke order; [`preprocess_report`] with its result in a tuple.
///
/// # Examples
///
/// ```
/// use geosnap_core::sketch::{preprocess, PreprocessOptions, Sketch, Stroke, StrokeId};
/// use glam::DVec2;
///
/// let stroke = Stroke {
///     id: StrokeId(0),
///     points: vec![DVec2::ZERO, DVec2::ZERO, DVec2::new(100.0, 0.0)],
///     closed: false,
///     class_override: None,
/// };
/// let sketch = Sketch { strokes: vec![stroke], view_box: None };
/// let (clean, notes) = preprocess(&sketch, &PreprocessOptions::default());
/// // 0.5 % of the 100-unit diagonal: 201 points, 0.5 apart.
/// assert_eq!(clean.strokes[0].points.len(), 201);
/// assert!(notes.is_empty());
/// ```
pub fn preprocess(sketch: &Sketch, options: &PreprocessOptions) -> (Sketch, Vec<String>) {
    let done = preprocess_report(sketch, options);
    (done.sketch, done.notes)
}

/// Cleans, resamples and smooths every stroke of `sketch`, and merges the strokes drawn
/// twice; see [`Preprocessed`] for what it returns.
///
/// The steps, per stroke:
///
/// 1. drop non-finite points;
/// 2. drop consecutive duplicate points (closer than
///    [`PreprocessOptions::duplicate_tolerance`]), and the last point of a closed stroke
///    when it repeats the first; an open stroke that ends where it started becomes closed;
/// 3. drop *dots*: strokes shorter than [`PreprocessOptions::min_length`];
/// 4. drop exact duplicates of an earlier stroke (same points after steps 1–2, in either
///    order, and same `closed` flag), listed in [`Preprocessed::merged`];
/// 5. resample each stroke to uniform arc-length spacing
///    ([`PreprocessOptions::spacing`], with at least [`PreprocessOptions::min_points`]
///    points);
/// 6. smooth with [`PreprocessOptions::smoothing_passes`] passes of the `[1, 2, 1]/4`
///    filter, keeping the endpoints of open strokes and wrapping around closed ones;
/// 7. merge *near duplicates*: a stroke that retraces an earlier kept one along its
///    whole length (every point of either within the tolerance of the other, both open
///    or both closed, with the same class override) is left out and listed in
///    [`Preprocessed::merged`]. The tolerance is twice the drawing's *jitter*, the median
///    over its strokes of the RMS distance the smoothing moved their points, kept
///    between a third of [`PreprocessOptions::retrace_tolerance`] and all of it: the
///    same line pasted twice, or drawn twice within a pixel or so, is one stroke. Strokes
///    that overlap over part of their length (sketchy strokes that together draw one
///    line) or run side by side further apart are evidence and stay.
///
/// Every length threshold is a fraction of the *sketch size*, the diagonal of the
/// bounding box of all finite points, so the result does not depend on the drawing's
/// units: a sketch scaled by 10 preprocesses to the same strokes scaled by 10. Stroke
/// ids, `closed` flags (except as noted in step 2) and class overrides are kept, and the
/// order of the surviving strokes is unchanged.
///
/// Never panics: an empty sketch, or one without a finite point, gives an empty sketch.
/// Options out of range are clamped: a spacing that is not positive and finite falls
/// back to the default, and `min_points` is at least 2.
///
/// # Examples
///
/// ```
/// use geosnap_core::sketch::{preprocess_report, PreprocessOptions, Sketch, Stroke, StrokeId};
/// use glam::DVec2;
///
/// let line = |id, dy: f64| Stroke {
///     id: StrokeId(id),
///     points: vec![DVec2::new(0.0, dy), DVec2::new(100.0, 50.0 + dy)],
///     closed: false,
///     class_override: None,
/// };
/// // The same line drawn twice, a hundredth of a unit apart, and a line beside it.
/// let sketch = Sketch { strokes: vec![line(0, 0.0), line(1, 0.01), line(2, 20.0)], view_box: None };
/// let done = preprocess_report(&sketch, &PreprocessOptions::default());
/// assert_eq!(done.sketch.strokes.len(), 2);
/// assert_eq!(done.merged.len(), 1);
/// assert_eq!((done.merged[0].dropped, done.merged[0].kept), (StrokeId(1), StrokeId(0)));
/// ```
pub fn preprocess_report(sketch: &Sketch, options: &PreprocessOptions) -> Preprocessed {
    let mut notes = Vec::new();
    let size = sketch_size(sketch);
    let defaults = PreprocessOptions::default();
    let positive_or = |v: f64, d: f64| if v > 0.0 && v.is_finite() { v } else { d };
    let spacing = positive_or(options.spacing, defaults.spacing) * size;
    let min_length = options.min_length.max(0.0) * size;
    let tolerance = options.duplicate_tolerance.max(0.0) * size;
    let min_points = options.min_points.max(2);
    let mut merged = Vec::new();
    let mut jitter = Vec::new();

    let mut seen: BTreeMap<(bool, Vec<[u64; 2]>), u32> = BTreeMap::new();
    let mut strokes = Vec::with_capacity(sketch.strokes.len());
    for stroke in &sketch.strokes {
        let id = stroke.id.0;
        let (points, closed) = clean_points(stroke, tolerance, &mut notes);
        let candidate = Stroke {
            id: stroke.id,
            points,
            closed,
            class_override: stroke.class_override,
        };
        let length = candidate.length();
        if !length.is_finite() {
            notes.push(format!("stroke {id}: dropped, its length overflows"));
            continue;
        }
        if candidate.points.len() < 2 || length < min_length || !(length > 0.0) {
            notes.push(format!(
                "stroke {id}: dropped as a dot (length {length:.3} < {min_length:.3})"
            ));
            continue;
        }
        let key = (closed, canonical_key(&candidate.points));
        if let Some(&original) = seen.get(&key) {
            notes.push(format!(
                "stroke {id}: dropped as a duplicate of stroke {original}"
            ));
            merged.push(MergedStroke {
                dropped: stroke.id,
                kept: StrokeId(original),
                exact: true,
            });
            continue;
        }
        seen.insert(key, id);
        let resampled = resample(&candidate.points, closed, spacing, min_points);
        let mut points = resampled.clone();
        for _ in 0..options.smoothing_passes {
            points = smooth(&points, closed);
        }
        jitter.push(rms_distance(&resampled, &points));
        strokes.push(Stroke {
            points,
            ..candidate
        });
    }
    let strokes = merge_retraced(
        strokes,
        (&mut jitter, options.retrace_tolerance.max(0.0) * size),
        &mut notes,
        &mut merged,
    );
    Preprocessed {
        sketch: Sketch {
            strokes,
            view_box: sketch.view_box,
        },
        notes,
        merged,
    }
}

/// Steps 1–2 of [`preprocess_report`] on one stroke: its finite points without
/// repeats, and whether it is closed; notes the points dropped.
fn clean_points(stroke: &Stroke, tolerance: f64, notes: &mut Vec<String>) -> (Vec<DVec2>, bool) {
    let finite: Vec<DVec2> = stroke
        .points
        .iter()
        .copied()
        .filter(|p| p.is_finite())
        .collect();
    let dropped = stroke.points.len() - finite.len();
    if dropped > 0 {
        notes.push(format!(
            "stroke {}: dropped {dropped} non-finite point(s)",
            stroke.id.0
        ));
    }
    let mut closed = stroke.closed;
    let mut points = dedup(&finite, tolerance);
    if points.len() > 2
        && let (Some(first), Some(last)) = (points.first(), points.last())
        && first.distance(*last) <= tolerance
    {
        points.pop();
        closed = true;
    }
    (points, closed)
}

/// The RMS distance between corresponding points of `a` and `b`.
fn rms_distance(a: &[DVec2], b: &[DVec2]) -> f64 {
    let sum: f64 = a.iter().zip(b).map(|(p, q)| p.distance_squared(*q)).sum();
    (sum / a.len().max(1) as f64).sqrt()
}

/// Step 7 of [`preprocess_report`]: leaves out the strokes that retrace an earlier one,
/// given the strokes' `jitter` and the largest tolerance `cap`, noting each.
fn merge_retraced(
    mut strokes: Vec<Stroke>,
    (jitter, cap): (&mut [f64], f64),
    notes: &mut Vec<String>,
    merged: &mut Vec<MergedStroke>,
) -> Vec<Stroke> {
    jitter.sort_by(f64::total_cmp);
    let median = jitter.get(jitter.len() / 2).copied().unwrap_or(0.0);
    let tolerance = (2.0 * median).clamp(cap / 3.0, cap);
    if tolerance > 0.0 && tolerance.is_finite() {
        let retraced = retraced(&strokes, tolerance);
        let mut kept = Vec::with_capacity(strokes.len());
        for (stroke, of) in strokes.into_iter().zip(&retraced) {
            match of {
                Some(original) => {
                    notes.push(format!(
                        "stroke {}: merged into stroke {}, which it retraces within {tolerance:.3}",
                        stroke.id.0, original.0
                    ));
                    merged.push(MergedStroke {
                        dropped: stroke.id,
                        kept: *original,
                        exact: false,
                    });
                }
                None => kept.push(stroke),
            }
        }
        strokes = kept;
    }
    strokes
}

/// Per stroke, the earlier kept stroke it retraces within `tolerance` along its whole
/// length (see [`preprocess_report`], step 7), if any.
fn retraced(strokes: &[Stroke], tolerance: f64) -> Vec<Option<StrokeId>> {
    let boxes: Vec<(DVec2, DVec2)> = strokes.iter().map(|s| bounds(&s.points)).collect();
    let index = BoxIndex::new(boxes.iter().copied());
    let mut of: Vec<Option<StrokeId>> = vec![None; strokes.len()];
    for (i, stroke) in strokes.iter().enumerate() {
        let (lo, hi) = boxes[i];
        // A stroke retracing another has its bounds' corners within the tolerance.
        of[i] = index
            .near(lo, hi, tolerance)
            .into_iter()
            .take_while(|&j| j < i)
            .find(|&j| {
                let (other, (olo, ohi)) = (&strokes[j], boxes[j]);
                of[j].is_none()
                    && other.closed == stroke.closed
                    && other.class_override == stroke.class_override
                    && (olo - lo).abs().max_element() <= tolerance
                    && (ohi - hi).abs().max_element() <= tolerance
                    && within(&stroke.points, other, tolerance)
                    && within(&other.points, stroke, tolerance)
            })
            .map(|j| strokes[j].id);
    }
    of
}

/// Whether every one of `points` lies within `tolerance` of the polyline of `stroke`.
fn within(points: &[DVec2], stroke: &Stroke, tolerance: f64) -> bool {
    let line = &stroke.points;
    let closing = match (stroke.closed, line.first(), line.last()) {
        (true, Some(&a), Some(&b)) if line.len() > 2 => Some((b, a)),
        _ => None,
    };
    points.iter().all(|&p| {
        line.windows(2)
            .map(|w| (w[0], w[1]))
            .chain(closing)
            .any(|(a, b)| segment_distance(a, b, p) <= tolerance)
    })
}

/// The bounds of a stroke's points (a point at the origin for none).
fn bounds(points: &[DVec2]) -> (DVec2, DVec2) {
    let first = points.first().copied().unwrap_or(DVec2::ZERO);
    points
        .iter()
        .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)))
}

/// The diagonal of the bounding box of all finite points (0 when there are none).
fn sketch_size(sketch: &Sketch) -> f64 {
    let mut points = sketch
        .strokes
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(|p| p.is_finite());
    let Some(first) = points.next() else {
        return 0.0;
    };
    let (lo, hi) = points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
    let diagonal = (hi - lo).length();
    // Coordinates near f64::MAX can overflow the diagonal; their half does not.
    if diagonal.is_finite() {
        diagonal
    } else {
        2.0 * (hi * 0.5 - lo * 0.5).length()
    }
}

/// Drops points closer than `tolerance` to the previously kept one.
fn dedup(points: &[DVec2], tolerance: f64) -> Vec<DVec2> {
    let mut out: Vec<DVec2> = Vec::with_capacity(points.len());
    for &p in points {
        if out.last().is_none_or(|q| q.distance(p) > tolerance) {
            out.push(p);
        }
    }
    out
}

/// The point list as bit patterns, in the lexicographically smaller of its two drawing
/// orders, so a stroke and its reversal get the same key.
fn canonical_key(points: &[DVec2]) -> Vec<[u64; 2]> {
    let forward: Vec<[u64; 2]> = points
        .iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits()])
        .collect();
    let backward: Vec<[u64; 2]> = forward.iter().rev().copied().collect();
    forward.min(backward)
}

/// Resamples a polyline at uniform arc length: `n` equal steps with `n = ⌈L/spacing⌉`,
/// at least enough for `min_points` points. An open stroke keeps both endpoints (n + 1
/// points); a closed one starts at its first point and gets n points round the loop.
fn resample(points: &[DVec2], closed: bool, spacing: f64, min_points: usize) -> Vec<DVec2> {
    let open_length: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
    let total = match (closed, points.first(), points.last()) {
        (true, Some(a), Some(b)) => open_length + a.distance(*b),
        _ => open_length,
    };
    let min_steps = if closed { min_points } else { min_points - 1 };
    // The cap guards against absurd counts from a tiny spacing; it is far above any
    // drawing's needs (a spacing of 0.5 % gives a few hundred points per stroke).
    let steps = ((total / spacing).ceil() as usize).clamp(min_steps.max(1), 1_000_000);
    let count = if closed { steps } else { steps + 1 };
    let mut out = resample_to(points, closed, count).unwrap_or_else(|| points.to_vec());
    if !closed {
        // Exactly the original endpoint, not a rounded interpolation of it.
        if let (Some(last), Some(&end)) = (out.last_mut(), points.last()) {
            *last = end;
        }
    }
    out
}

/// `count` points uniform in arc length along the polyline (round the loop for a closed
/// one); `None` when it has zero or non-finite length.
pub(crate) fn resample_to(points: &[DVec2], closed: bool, count: usize) -> Option<Vec<DVec2>> {
    let mut path = points.to_vec();
    if closed {
        path.push(*points.first()?);
    }
    let mut cumulative = Vec::with_capacity(path.len());
    let mut total = 0.0;
    cumulative.push(0.0);
    for w in path.windows(2) {
        total += w[0].distance(w[1]);
        cumulative.push(total);
    }
    if !(total > 0.0) || !total.is_finite() {
        return None;
    }
    // Open strokes include both endpoints; closed ones do not repeat the start.
    let steps = if closed { count } else { count - 1 };
    let mut out = Vec::with_capacity(count);
    let mut segment = 0;
    for k in 0..count {
        let target = total * k as f64 / steps as f64;
        while segment + 2 < cumulative.len() && cumulative[segment + 1] < target {
            segment += 1;
        }
        let (s0, s1) = (cumulative[segment], cumulative[segment + 1]);
        let t = if s1 > s0 {
            ((target - s0) / (s1 - s0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(path[segment].lerp(path[segment + 1], t));
    }
    Some(out)
}

/// One pass of the `[1, 2, 1]/4` filter: endpoints of an open stroke stay, a closed
/// stroke wraps around.
pub(crate) fn smooth(points: &[DVec2], closed: bool) -> Vec<DVec2> {
    let n = points.len();
    if n < 3 {
        return points.to_vec();
    }
    (0..n)
        .map(|i| {
            if !closed && (i == 0 || i == n - 1) {
                points[i]
            } else {
                let prev = points[(i + n - 1) % n];
                let next = points[(i + 1) % n];
                0.25 * prev + 0.5 * points[i] + 0.25 * next
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use std::f64::consts::TAU;

    use glam::DVec2;

    use super::{preprocess, PreprocessOptions};
    use crate::sketch::{Sketch, Stroke, StrokeClass, StrokeId};

    fn stroke(id: u32, points: Vec<DVec2>, closed: bool) -> Stroke {
        Stroke {
            id: StrokeId(id),
            points,
            closed,
            class_override: None,
        }
    }

    fn sample_sketch() -> Sketch {
        let circle: Vec<DVec2> = (0..40)
            .map(|i| DVec2::new(300.0, 200.0) + 80.0 * DVec2::from_angle(TAU * f64::from(i) / 40.0))
            .collect();
        let zigzag: Vec<DVec2> = (0..30)
            .map(|i| DVec2::new(10.0 * f64::from(i), if i % 2 == 0 { 0.0 } else { 7.0 }))
            .collect();
        let mut with_override = stroke(
            7,
            vec![DVec2::new(0.0, 400.0), DVec2::new(250.0, 380.0)],
            false,
        );
        with_override.class_override = Some(StrokeClass::Feature);
        Sketch {
            strokes: vec![
                stroke(2, circle, true),
                stroke(5, zigzag, false),
                with_override,
                // A dot, 0.05 units long on a 500-unit sketch.
                stroke(
                    9,
                    vec![DVec2::new(50.0, 50.0), DVec2::new(50.05, 50.0)],
                    false,
                ),
            ],
            view_box: Some((DVec2::ZERO, DVec2::new(500.0, 500.0))),
        }
    }

    #[test]
    fn keeps_ids_overrides_and_drops_dots() {
        let (clean, notes) = preprocess(&sample_sketch(), &PreprocessOptions::default());
        let ids: Vec<u32> = clean.strokes.iter().map(|s| s.id.0).collect();
        assert_eq!(ids, vec![2, 5, 7]);
        assert_eq!(clean.strokes[2].class_override, Some(StrokeClass::Feature));
        assert!(clean.strokes[0].closed, "closed flag kept");
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(
            notes[0].contains("stroke 9") && notes[0].contains("dot"),
            "{notes:?}"
        );
        assert_eq!(clean.view_box, sample_sketch().view_box);
    }

    #[test]
    fn resamples_uniformly_and_keeps_open_endpoints() {
        let sketch = sample_sketch();
        let options = PreprocessOptions {
            smoothing_passes: 0,
            ..PreprocessOptions::default()
        };
        let (clean, _) = preprocess(&sketch, &options);
        let size = {
            let (lo, hi) = sketch.bounds().unwrap();
            (hi - lo).length()
        };
        for (s, original) in clean.strokes.iter().zip(&sketch.strokes) {
            let steps: Vec<f64> = s.points.windows(2).map(|w| w[0].distance(w[1])).collect();
            assert!(s.points.len() >= 8, "{}", s.points.len());
            // Uniform in arc length along the original polyline: chords are at most the
            // spacing and nearly equal away from corners.
            let max = steps.iter().copied().fold(0.0, f64::max);
            assert!(max <= 0.005 * size + 1e-9, "{max}");
            if !s.closed {
                assert_eq!(s.points.first(), original.points.first());
                assert_eq!(s.points.last(), original.points.last());
            }
        }
        // The straight override stroke: exactly equal steps.
        let line = &clean.strokes[2];
        let steps: Vec<f64> = line
            .points
            .windows(2)
            .map(|w| w[0].distance(w[1]))
            .collect();
        for s in &steps {
            assert!((s - steps[0]).abs() < 1e-9, "{steps:?}");
        }
        // Short strokes get at least min_points.
        let short = Sketch {
            strokes: vec![
                stroke(0, vec![DVec2::ZERO, DVec2::new(1000.0, 0.0)], false),
                stroke(1, vec![DVec2::ZERO, DVec2::new(5.0, 0.0)], false),
            ],
            view_box: None,
        };
        let (clean, _) = preprocess(&short, &options);
        assert_eq!(clean.strokes[1].points.len(), 8);
        assert_eq!(clean.strokes[0].points.len(), 201);
    }

    #[test]
    fn scale_invariance() {
        let sketch = sample_sketch();
        let transform = |p: DVec2| p * 10.0 + DVec2::new(-3000.0, 1234.5);
        let scaled = Sketch {
            strokes: sketch
                .strokes
                .iter()
                .map(|s| Stroke {
                    points: s.points.iter().map(|&p| transform(p)).collect(),
                    ..s.clone()
                })
                .collect(),
            view_box: None,
        };
        let options = PreprocessOptions::default();
        let (a, notes_a) = preprocess(&sketch, &options);
        let (b, notes_b) = preprocess(&scaled, &options);
        assert_eq!(notes_a.len(), notes_b.len());
        assert_eq!(a.strokes.len(), b.strokes.len());
        for (sa, sb) in a.strokes.iter().zip(&b.strokes) {
            assert_eq!(sa.id, sb.id);
            assert_eq!(sa.points.len(), sb.points.len());
            for (pa, pb) in sa.points.iter().zip(&sb.points) {
                assert!(transform(*pa).distance(*pb) < 1e-9 * 5000.0, "{pa} {pb}");
            }
        }
    }

    #[test]
    fn drops_non_finite_duplicates_and_duplicate_strokes() {
        let pts = vec![
            DVec2::ZERO,
            DVec2::new(f64::NAN, 1.0),
            DVec2::ZERO,
            DVec2::new(100.0, 0.0),
            DVec2::new(100.0, f64::INFINITY),
            DVec2::new(100.0, 100.0),
        ];
        let reversed: Vec<DVec2> = pts.iter().rev().copied().collect();
        let sketch = Sketch {
            strokes: vec![
                stroke(0, pts.clone(), false),
                stroke(1, reversed, false),
                stroke(2, pts.clone(), true),
                stroke(3, vec![DVec2::splat(f64::NAN); 3], false),
                stroke(4, vec![DVec2::splat(3.0); 5], false),
            ],
            view_box: None,
        };
        let options = PreprocessOptions {
            smoothing_passes: 0,
            ..PreprocessOptions::default()
        };
        let (clean, notes) = preprocess(&sketch, &options);
        let ids: Vec<u32> = clean.strokes.iter().map(|s| s.id.0).collect();
        assert_eq!(ids, vec![0, 2], "{notes:?}");
        assert!(
            notes
                .iter()
                .any(|n| n.contains("stroke 1") && n.contains("duplicate of stroke 0")),
            "{notes:?}"
        );
        assert!(
            notes
                .iter()
                .any(|n| n.contains("stroke 3") && n.contains("dot")),
            "{notes:?}"
        );
        assert!(
            notes
                .iter()
                .any(|n| n.contains("stroke 4") && n.contains("dot")),
            "{notes:?}"
        );
        assert!(
            notes
                .iter()
                .any(|n| n.contains("stroke 0") && n.contains("2 non-finite")),
            "{notes:?}"
        );
        for s in &clean.strokes {
            assert!(s.points.iter().all(|p| p.is_finite()));
            assert!(s.points.windows(2).all(|w| w[0] != w[1]));
        }
    }

    #[test]
    fn merges_strokes_drawn_twice_but_not_overlapping_or_side_by_side_ones() {
        // On a 1000 × 600 page: a wavy line, the same drawn again backwards within 0.15
        // units, its two halves overlapping in the middle (sketchy strokes that together
        // draw it), a copy 6 units beside it, and a pasted copy of a closed loop.
        let wave = |from: f64, to: f64, dy: f64| -> Vec<DVec2> {
            (0..=60)
                .map(|i| {
                    let x = from + (to - from) * f64::from(i) / 60.0;
                    DVec2::new(x, 300.0 + 40.0 * (x / 90.0).sin() + dy)
                })
                .collect()
        };
        let mut again = wave(100.0, 900.0, 0.0);
        again.reverse();
        for (i, p) in again.iter_mut().enumerate() {
            *p += DVec2::new(0.0, 0.15 * (i as f64 * 0.7).sin());
        }
        let loop_points: Vec<DVec2> = (0..40)
            .map(|i| DVec2::new(500.0, 100.0) + 60.0 * DVec2::from_angle(TAU * f64::from(i) / 40.0))
            .collect();
        let sketch = Sketch {
            strokes: vec![
                stroke(0, wave(100.0, 900.0, 0.0), false),
                stroke(1, again, false),
                stroke(2, wave(100.0, 600.0, 0.0), false),
                stroke(3, wave(400.0, 900.0, 0.0), false),
                stroke(4, wave(100.0, 900.0, 6.0), false),
                stroke(5, loop_points.clone(), true),
                stroke(6, loop_points, true),
            ],
            view_box: Some((DVec2::ZERO, DVec2::new(1000.0, 600.0))),
        };
        let done = super::preprocess_report(&sketch, &PreprocessOptions::default());
        let ids: Vec<u32> = done.sketch.strokes.iter().map(|s| s.id.0).collect();
        assert_eq!(ids, vec![0, 2, 3, 4, 5], "{:?}", done.notes);
        let merged: Vec<(u32, u32, bool)> = done
            .merged
            .iter()
            .map(|m| (m.dropped.0, m.kept.0, m.exact))
            .collect();
        assert_eq!(merged, vec![(6, 5, true), (1, 0, false)]);
        assert!(
            done.notes
                .iter()
                .any(|n| n.contains("stroke 1: merged into stroke 0")),
            "{:?}",
            done.notes
        );
        // A tolerance of 0 merges exact duplicates only.
        let exact_only = PreprocessOptions {
            retrace_tolerance: 0.0,
            ..PreprocessOptions::default()
        };
        let done = super::preprocess_report(&sketch, &exact_only);
        assert_eq!(done.sketch.strokes.len(), 6);
        assert_eq!(done.merged.len(), 1);
    }

    #[test]
    fn smoothing_wraps_closed_strokes_and_keeps_open_ends() {
        let square = vec![
            DVec2::ZERO,
            DVec2::new(100.0, 0.0),
            DVec2::new(100.0, 100.0),
            DVec2::new(0.0, 100.0),
        ];
        let sketch = Sketch {
            strokes: vec![
                stroke(0, square.clone(), true),
                stroke(1, square.clone(), false),
            ],
            view_box: None,
        };
        let (clean, _) = preprocess(&sketch, &PreprocessOptions::default());
        let closed = &clean.strokes[0];
        // The corner at the start of the closed stroke was smoothed (wrapped); its centroid
        // is unchanged by the symmetric filter.
        assert!(
            closed.points[0].distance(DVec2::ZERO) > 1e-3,
            "{}",
            closed.points[0]
        );
        let centroid = closed.points.iter().copied().sum::<DVec2>() / closed.points.len() as f64;
        assert!(centroid.distance(DVec2::splat(50.0)) < 1e-9, "{centroid}");
        let open = &clean.strokes[1];
        assert_eq!(open.points.first(), Some(&DVec2::ZERO));
        assert_eq!(open.points.last(), Some(&DVec2::new(0.0, 100.0)));
        // An open stroke that returns to its start becomes closed.
        let mut loop_points = square;
        loop_points.push(DVec2::ZERO);
        let (clean, _) = preprocess(
            &Sketch {
                strokes: vec![stroke(0, loop_points, false)],
                view_box: None,
            },
            &PreprocessOptions::default(),
        );
        assert!(clean.strokes[0].closed);
    }

    #[test]
    fn empty_and_degenerate_sketches() {
        let (clean, notes) = preprocess(&Sketch::default(), &PreprocessOptions::default());
        assert!(clean.strokes.is_empty() && notes.is_empty());
        let single = Sketch {
            strokes: vec![stroke(0, vec![DVec2::ONE], false)],
            view_box: None,
        };
        let (clean, notes) = preprocess(&single, &PreprocessOptions::default());
        assert!(clean.strokes.is_empty());
        assert_eq!(notes.len(), 1);
        let huge = Sketch {
            strokes: vec![stroke(
                0,
                vec![DVec2::splat(-1e308), DVec2::splat(1e308)],
                false,
            )],
            view_box: None,
        };
        let (clean, _) = preprocess(&huge, &PreprocessOptions::default());
        assert!(clean
            .strokes
            .iter()
            .all(|s| s.points.iter().all(|p| p.is_finite())));
        let bad_options = PreprocessOptions {
            spacing: 0.0,
            min_points: 0,
            ..PreprocessOptions::default()
        };
        let (clean, _) = preprocess(&sample_sketch(), &bad_options);
        assert_eq!(clean.strokes.len(), 3);
    }
}
