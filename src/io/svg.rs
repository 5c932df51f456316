//! SVG import: a drawing becomes a [`Sketch`] of polylines in sketch space.
//!
//! # What is imported
//!
//! The document is parsed by [usvg], which resolves CSS, `use`, nested `svg`, inherited
//! attributes and every `transform`, and turns the basic shapes (`line`, `polyline`,
//! `polygon`, `rect`, `circle`, `ellipse`) and all path commands (lines, quadratic and
//! cubic Béziers, elliptical arcs, relative and smooth forms) into absolute Bézier paths.
//! Each *subpath* becomes one [`Stroke`], `closed` when the subpath ends with `Z` (a
//! closing point that repeats the first one is dropped). Strokes get ids `0..n` in
//! document order and no class override.
//!
//! # Sketch space
//!
//! Sketch space is formats.md §1: the user units of the root `viewBox`, with every
//! transform inside the document applied. The root `width`/`height` do **not** scale it:
//! usvg folds the viewBox→viewport mapping (`preserveAspectRatio` included) into a root
//! transform, and the importer undoes exactly that mapping, so a file with
//! `viewBox="0 0 1536 2048" width="21.3in"` spans 0..1536 × 0..2048. Without a viewBox
//! the user units are the root's px and the extent is `0..width × 0..height`.
//! A `transform` on the root `<svg>` element (SVG 2) acts in viewport units and is applied
//! as such (a `translate(10)` on a root drawn at twice its viewBox size moves the drawing
//! by 5 sketch units). [`Sketch::view_box`] is set to the viewBox, or to the px extent.
//!
//! # Flattening tolerance
//!
//! Curves are flattened by kurbo (its flattening bounds the Hausdorff distance between
//! curve and polyline) **after** the transform, at a tolerance *relative to the drawing*:
//! `tolerance = relative_tolerance × diagonal of the view box`, by default
//! [`DEFAULT_RELATIVE_TOLERANCE`] = 1e-4 (0.41 units on a 2448 × 3264 drawing). So the
//! same drawing at any scale gives the same polylines. Elliptical arcs are first turned
//! into cubics by usvg at a fixed accuracy (0.1 of the element's own user units, at least
//! four cubics per ellipse, i.e. a radial error ≤ 2.7e-4 · radius), which at the default
//! tolerance adds at most about the tolerance again; a finer tolerance does not make arcs
//! more accurate than that. As a safety floor, a subpath is never flattened finer than
//! 1e-6 of its own extent, which bounds the points per curve on absurd input.
//!
//! # Warnings and degenerate input
//!
//! Content that is not imported is reported in [`SvgImport::warnings`], never silently
//! dropped and never fatal: text, images, foreign objects, markers (arrowheads are not
//! strokes), clipping and masks (strokes are imported whole), hidden elements
//! (`display:none`, `visibility:hidden`, neither fill nor stroke: what is not drawn is not
//! imported), elements usvg rejects (invalid, empty or non-finite geometry), non-finite or
//! absurd (|x| > 1e100) points, which are dropped, and subpaths left with fewer than two
//! distinct points, which are dropped. An empty document or one without drawable geometry
//! gives `Ok` with zero strokes and a warning; the caller decides. Malformed XML is
//! [`LoadError::Svg`]. No input panics; documents nested deeper than 256 elements or
//! producing more than [`SvgOptions::max_points`] points are [`LoadError::TooComplex`].
//!
//! [usvg]: https://docs.rs/usvg

use std::collections::{BTreeMap, HashSet};

use glam::DVec2;
use kurbo::{Affine, PathEl, Point};
use usvg::roxmltree;
use usvg::tiny_skia_path::PathSegment;

use crate::core::sketch::{Sketch, Stroke, StrokeId};
use crate::io::LoadError;

/// The default flattening tolerance, as a fraction of the view box diagonal.
pub const DEFAULT_RELATIVE_TOLERANCE: f64 = 1e-4;

/// The default limit on the total number of imported points.
pub const DEFAULT_MAX_POINTS: usize = 20_000_000;

/// The deepest element nesting accepted (the SVG parser recurses per level).
const MAX_DEPTH: usize = 256;

/// The most XML nodes parsed (usvg itself stops at a million SVG elements).
const MAX_XML_NODES: u32 = 4_000_000;

/// Geometry numbers in the file beyond this magnitude make their element be dropped: usvg
/// would build millions of cubics for an arc that large.
const MAX_SOURCE_NUMBER: f64 = 1e12;

/// Coordinates beyond this magnitude are treated like non-finite ones.
const MAX_COORDINATE: f64 = 1e100;

/// The finest flattening tolerance, relative to the extent of the subpath flattened.
const MIN_TOLERANCE_OF_EXTENT: f64 = 1e-6;

/// How many element ids a warning lists before saying "and n more".
const MAX_LISTED_IDS: usize = 5;

/// The SVG namespace.
const SVG_NS: &str = "http://www.w3.org/2000/svg";

/// Drawable elements: each becomes one path in usvg.
const SHAPES: [&str; 7] = [
    "path", "rect", "circle", "ellipse", "line", "polyline", "polygon",
];

/// Elements whose content is drawn but not imported.
const UNSUPPORTED: [&str; 8] = [
    "text",
    "flowRoot",
    "image",
    "foreignObject",
    "video",
    "audio",
    "iframe",
    "canvas",
];

/// Options of [`import_svg`]; build with [`SvgOptions::default`] and the checked `with_*`.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgOptions {
    relative_tolerance: f64,
    max_points: usize,
}

impl Default for SvgOptions {
    fn default() -> Self {
        Self {
            relative_tolerance: DEFAULT_RELATIVE_TOLERANCE,
            max_points: DEFAULT_MAX_POINTS,
        }
    }
}

impl SvgOptions {
    /// Sets the flattening tolerance as a fraction of the view box diagonal: the largest
    /// distance between a curve and its polyline is about `tolerance × diagonal`.
    ///
    /// # Errors
    ///
    /// [`LoadError::InvalidOption`] unless `0 < tolerance ≤ 1`.
    pub fn with_relative_tolerance(self, tolerance: f64) -> Result<Self, LoadError> {
        if tolerance > 0.0 && tolerance <= 1.0 {
            Ok(Self {
                relative_tolerance: tolerance,
                ..self
            })
        } else {
            Err(LoadError::InvalidOption {
                name: "relative_tolerance",
                value: tolerance,
                expected: "a number in (0, 1]",
            })
        }
    }

    /// Sets the largest number of points an import may produce; a drawing with more is
    /// [`LoadError::TooComplex`] (a guard against absurd files, not a quality setting).
    #[must_use]
    pub fn with_max_points(self, max_points: usize) -> Self {
        Self { max_points, ..self }
    }

    /// The flattening tolerance as a fraction of the view box diagonal.
    pub fn relative_tolerance(&self) -> f64 {
        self.relative_tolerance
    }

    /// The largest number of points an import may produce.
    pub fn max_points(&self) -> usize {
        self.max_points
    }
}

/// The result of [`import_svg`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SvgImport {
    /// The strokes in sketch space, with ids `0..n` in document order, and the view box.
    pub sketch: Sketch,
    /// Human-readable notes on content that was not imported, for the user to see.
    pub warnings: Vec<String>,
}

/// Imports an SVG document as a sketch of polylines in sketch space.
///
/// See the [module documentation](self) for sketch space, the tolerance and what is
/// reported in the warnings.
///
/// # Errors
///
/// [`LoadError::Svg`] for data that is not well-formed SVG (bad XML, not UTF-8, no
/// `<svg>` root, an invalid size), [`LoadError::CompressedSvg`] for svgz, and
/// [`LoadError::TooComplex`] past the nesting or point limits.
///
/// # Examples
///
/// ```
/// use geosnap::io::svg::{import_svg, SvgOptions};
///
/// let svg = br#"<svg xmlns="http://www.w3.org/2000/svg" width="2in" height="1in"
///                    viewBox="0 0 200 100">
///     <g transform="translate(10 0)"><path d="M 0 10 L 50 10 L 50 60 Z"/></g>
///     <text x="5" y="5">note</text>
/// </svg>"#;
/// let import = import_svg(svg, &SvgOptions::default())?;
/// let stroke = &import.sketch.strokes[0];
/// assert!(stroke.closed);
/// assert_eq!(stroke.points.len(), 3);
/// // usvg stores coordinates in f32: expect about 1e-7 relative error.
/// assert!(stroke.points[1].distance(glam::DVec2::new(60.0, 10.0)) < 1e-4);
/// assert!(import.warnings[0].contains("text"));
/// # Ok::<(), geosnap::io::LoadError>(())
/// ```
pub fn import_svg(data: &[u8], options: &SvgOptions) -> Result<SvgImport, LoadError> {
    let data = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data);
    if data.starts_with(&[0x1f, 0x8b]) {
        return Err(LoadError::CompressedSvg);
    }
    if data.iter().all(u8::is_ascii_whitespace) {
        return Ok(SvgImport {
            sketch: Sketch::default(),
            warnings: vec!["the svg data is empty: no strokes imported".to_owned()],
        });
    }
    let text = std::str::from_utf8(data).map_err(|_| LoadError::Svg {
        source: usvg::Error::NotAnUtf8Str,
    })?;
    let xml = parse_xml(text)?;
    // Arcs become cubics at a fixed absolute accuracy inside usvg, so an absurd radius
    // means millions of cubics (or an endless loop), and huge positions or transforms
    // overflow its f32 geometry: drop such elements first.
    let absurd = AbsurdGeometry::find(&xml, text)?;
    let sanitized: String;
    let xml = if absurd.ranges.is_empty() {
        xml
    } else {
        sanitized = absurd.blank(text);
        parse_xml(&sanitized)?
    };
    let survey = Survey::of(&xml)?;
    let tree = usvg::Tree::from_xmltree(&xml, &usvg_options())
        .map_err(|source| LoadError::Svg { source })?;

    let mut warnings = survey.warnings();
    if !absurd.ids.is_empty() {
        let ids: Vec<&str> = absurd.ids.iter().filter_map(|id| id.as_deref()).collect();
        warnings.push(format!(
            "{} element(s) with coordinates, sizes or transforms beyond ±{MAX_SOURCE_NUMBER:e} \
             were not imported{}",
            absurd.ids.len(),
            list_ids(&ids)
        ));
    }
    let (view_box, sketch_from_canvas) = sketch_frame(&survey.root, tree.size());
    let tolerance = options.relative_tolerance * view_box.1.length();
    let mut collector = Collector::new(tolerance, options.max_points);
    let usvg_ids = collector.add_tree(&tree, sketch_from_canvas)?;
    warnings.extend(survey.dropped_warning(collector.usvg_paths, &usvg_ids));
    warnings.extend(collector.warnings());
    let strokes = collector.strokes;
    if strokes.is_empty() {
        warnings.push("the svg has no drawable geometry: no strokes imported".to_owned());
    }
    Ok(SvgImport {
        sketch: Sketch {
            strokes,
            view_box: Some(view_box),
        },
        warnings,
    })
}

/// The view box `(min, size)` of the sketch and the transform from usvg's canvas (the
/// root viewport, px) to sketch space, which undoes usvg's viewBox mapping.
fn sketch_frame(root: &RootInfo, size: usvg::Size) -> ((DVec2, DVec2), Affine) {
    if let Some(vb) = root.view_box {
        let canvas_from_view_box = view_box_transform(vb, root.aspect, size.width(), size.height());
        (
            (DVec2::new(vb[0], vb[1]), DVec2::new(vb[2], vb[3])),
            canvas_from_view_box.inverse(),
        )
    } else {
        let size = DVec2::new(f64::from(size.width()), f64::from(size.height()));
        ((DVec2::ZERO, size), Affine::IDENTITY)
    }
}

/// Parses XML as usvg does (DTDs allowed: roxmltree guards against entity bombs).
fn parse_xml(text: &str) -> Result<roxmltree::Document<'_>, LoadError> {
    roxmltree::Document::parse_with_options(
        text,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            nodes_limit: MAX_XML_NODES,
            ..roxmltree::ParsingOptions::default()
        },
    )
    .map_err(|e| LoadError::Svg {
        source: usvg::Error::ParsingFailed(e),
    })
}

/// The attributes that carry coordinates, sizes or transforms, separated by spaces: an
/// element with a number beyond [`MAX_SOURCE_NUMBER`] in any of them is not imported.
const COORDINATE_ATTRIBUTES: &str =
    "x y width height cx cy r rx ry x1 y1 x2 y2 points d transform viewBox";

/// Elements with numbers beyond [`MAX_SOURCE_NUMBER`] in a coordinate attribute, found
/// before usvg sees them: usvg and tiny-skia work in `f32` and build arcs, strokes and
/// bounds at fixed accuracies, so such numbers cost unbounded memory or time.
#[derive(Debug, Default)]
struct AbsurdGeometry {
    /// Byte ranges of the elements in the text, in document order.
    ranges: Vec<std::ops::Range<usize>>,
    /// The id (if any) of each element concerned.
    ids: Vec<Option<String>>,
}

impl AbsurdGeometry {
    /// Finds them, in every attribute of [`COORDINATE_ATTRIBUTES`]. On the root `<svg>`
    /// the whole drawing is refused, as its frame is in doubt.
    fn find(xml: &roxmltree::Document<'_>, text: &str) -> Result<Self, LoadError> {
        let mut found = Self::default();
        let root = xml.root_element();
        for node in xml.descendants().filter(roxmltree::Node::is_element) {
            if !matches!(node.tag_name().namespace(), None | Some(SVG_NS)) {
                continue;
            }
            let Some(attribute) = node.attributes().find(|a| {
                COORDINATE_ATTRIBUTES
                    .split(' ')
                    .any(|name| name == a.name())
                    && has_absurd_number(a.value())
            }) else {
                continue;
            };
            let range = node.range();
            // Guard against roxmltree's documented position limits: the range must hold
            // the element.
            let sane = text.get(range.clone()).is_some_and(|e| e.starts_with('<'));
            if node == root || !sane {
                return Err(LoadError::TooComplex {
                    reason: format!(
                        "the root <svg> has `{}` beyond ±{MAX_SOURCE_NUMBER:e}",
                        attribute.name()
                    ),
                });
            }
            found.ranges.push(range);
            found.ids.push(node.attribute("id").map(str::to_owned));
        }
        found.ranges.sort_by_key(|range| range.start);
        Ok(found)
    }

    /// The text without those elements (and their content), so usvg never sees them.
    fn blank(&self, text: &str) -> String {
        let mut out = String::with_capacity(text.len());
        let mut at = 0;
        for range in &self.ranges {
            if range.start < at {
                continue;
            }
            out.push_str(text.get(at..range.start).unwrap_or_default());
            at = range.end;
        }
        out.push_str(text.get(at..).unwrap_or_default());
        out
    }
}

/// Whether a number in an attribute value exceeds [`MAX_SOURCE_NUMBER`] in magnitude (or
/// overflows). Numbers are read as SVG does, so `1.5.5` is `1.5` and `.5`.
fn has_absurd_number(value: &str) -> bool {
    let bytes = value.as_bytes();
    let digits = |i: &mut usize| {
        let start = *i;
        while bytes.get(*i).is_some_and(u8::is_ascii_digit) {
            *i += 1;
        }
        *i > start
    };
    let mut i = 0;
    while i < bytes.len() {
        let start = i;
        let mut any = digits(&mut i);
        if bytes.get(i) == Some(&b'.') {
            i += 1;
            any |= digits(&mut i);
        }
        if !any {
            i = start + 1;
            continue;
        }
        if matches!(bytes.get(i), Some(b'e' | b'E')) {
            let mut j = i + 1;
            if matches!(bytes.get(j), Some(b'+' | b'-')) {
                j += 1;
            }
            if digits(&mut j) {
                i = j;
            }
        }
        let number = value.get(start..i).and_then(|s| s.parse::<f64>().ok());
        if number.is_some_and(|n| n.abs() > MAX_SOURCE_NUMBER) {
            return true;
        }
    }
    false
}

/// The usvg options: no image loading (a drawing's images are reported, not imported,
/// and a file must not make us read other files) and markers switched off.
fn usvg_options() -> usvg::Options<'static> {
    usvg::Options {
        image_href_resolver: usvg::ImageHrefResolver {
            resolve_data: Box::new(|_, _, _| None),
            resolve_string: Box::new(|_, _| None),
        },
        // Marker decorations (arrowheads) would otherwise become strokes of their own.
        style_sheet: Some("* { marker: none !important; }".to_owned()),
        ..usvg::Options::default()
    }
}

/// The kurbo form of a usvg transform.
fn affine_of(t: usvg::Transform) -> Affine {
    Affine::new([
        f64::from(t.sx),
        f64::from(t.ky),
        f64::from(t.kx),
        f64::from(t.sy),
        f64::from(t.tx),
        f64::from(t.ty),
    ])
}

/// Formats up to [`MAX_LISTED_IDS`] element ids as a suffix for a warning.
fn list_ids(ids: &[&str]) -> String {
    if ids.is_empty() {
        return String::new();
    }
    let shown: Vec<String> = ids
        .iter()
        .take(MAX_LISTED_IDS)
        .map(|id| format!("#{id}"))
        .collect();
    let more = ids.len().saturating_sub(MAX_LISTED_IDS);
    if more > 0 {
        format!(" ({} and {more} more)", shown.join(", "))
    } else {
        format!(" ({})", shown.join(", "))
    }
}

/// The alignment part of `preserveAspectRatio`, as fractions of the free space.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Aspect {
    /// `None` for `preserveAspectRatio="none"` (non-uniform scaling), else the x and y
    /// alignment (0 = min, 0.5 = mid, 1 = max).
    align: Option<(f32, f32)>,
    /// `slice` (cover the viewport) rather than `meet` (fit inside it).
    slice: bool,
}

impl Default for Aspect {
    fn default() -> Self {
        Self {
            align: Some((0.5, 0.5)),
            slice: false,
        }
    }
}

impl Aspect {
    /// Parses `preserveAspectRatio` as SVG does: `[defer] <align> [meet|slice]`; anything
    /// else is the default `xMidYMid meet`.
    fn parse(text: &str) -> Self {
        let mut words = text.split_ascii_whitespace().peekable();
        if words.peek() == Some(&"defer") {
            words.next();
        }
        let align = match words.next() {
            Some("none") => None,
            Some(word) => {
                let fraction = |s: &str| match s {
                    "Min" => Some(0.0),
                    "Mid" => Some(0.5),
                    "Max" => Some(1.0),
                    _ => None,
                };
                let parsed = word
                    .strip_prefix('x')
                    .filter(|rest| rest.len() == 7 && rest.is_char_boundary(3))
                    .and_then(|rest| {
                        let (x, y) = rest.split_at(3);
                        Some((fraction(x)?, fraction(y.strip_prefix('Y')?)?))
                    });
                match parsed {
                    Some(align) => Some(align),
                    None => return Self::default(),
                }
            }
            None => return Self::default(),
        };
        let slice = match words.next() {
            None | Some("meet") => false,
            Some("slice") => true,
            Some(_) => return Self::default(),
        };
        Self { align, slice }
    }
}

/// The mapping from viewBox user units to the viewport (px), as usvg computes it.
fn view_box_transform(
    view_box: [f64; 4],
    aspect: Aspect,
    viewport_width: f32,
    viewport_height: f32,
) -> Affine {
    // usvg computes this in f32; doing exactly the same arithmetic makes the inverse undo
    // its mapping to the last bit, so an untransformed point comes back exactly.
    let [x, y, w, h] = view_box.map(|v| v as f32);
    let (sx, sy) = (viewport_width / w, viewport_height / h);
    let (sx, sy, (ax, ay)) = match aspect.align {
        None => (sx, sy, (0.0, 0.0)),
        Some(align) => {
            let s = if aspect.slice { sx.max(sy) } else { sx.min(sy) };
            (s, s, align)
        }
    };
    let (free_x, free_y) = (viewport_width - w * sx, viewport_height - h * sy);
    let tx = -x * sx + ax * free_x;
    let ty = -y * sy + ay * free_y;
    Affine::new([sx, 0.0, 0.0, sy, tx, ty].map(f64::from))
}

/// Parses one SVG number at the start of `text` (after spaces), as usvg does: no `inf` or
/// `NaN`, and an `e` followed by `m` or `x` is a unit, not an exponent. Returns the
/// number and the rest after the number, its spaces and at most one comma.
fn parse_list_number(text: &str) -> Option<(f64, &str)> {
    let is_space = |b: u8| matches!(b, b' ' | b'\t' | b'\n' | b'\r');
    let bytes = text.as_bytes();
    let mut i = 0;
    while bytes.get(i).copied().is_some_and(is_space) {
        i += 1;
    }
    let start = i;
    let digits = |i: &mut usize| {
        while bytes.get(*i).is_some_and(u8::is_ascii_digit) {
            *i += 1;
        }
    };
    if matches!(bytes.get(i), Some(b'+' | b'-')) {
        i += 1;
    }
    match bytes.get(i) {
        Some(b'0'..=b'9') => digits(&mut i),
        Some(b'.') => {}
        _ => return None,
    }
    if bytes.get(i) == Some(&b'.') {
        i += 1;
        digits(&mut i);
    }
    if matches!(bytes.get(i), Some(b'e' | b'E')) && !matches!(bytes.get(i + 1), Some(b'm' | b'x')) {
        i += 1;
        if matches!(bytes.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        if !bytes.get(i).is_some_and(u8::is_ascii_digit) {
            return None;
        }
        digits(&mut i);
    }
    let value: f64 = text
        .get(start..i)?
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())?;
    while bytes.get(i).copied().is_some_and(is_space) {
        i += 1;
    }
    if bytes.get(i) == Some(&b',') {
        i += 1;
    }
    Some((value, text.get(i..)?))
}

/// Parses a `viewBox` as usvg does; `None` if it is invalid (usvg then ignores it).
fn parse_view_box(text: &str) -> Option<[f64; 4]> {
    let mut values = [0.0; 4];
    let mut rest = text;
    for value in &mut values {
        let (v, r) = parse_list_number(rest)?;
        *value = v;
        rest = r;
    }
    let [x, y, w, h] = values.map(|v| v as f32);
    let valid = w > 0.0 && h > 0.0 && [x, y, w, h, x + w, y + h].iter().all(|v| v.is_finite());
    valid.then_some(values)
}

/// Facts about the root `<svg>` element.
#[derive(Debug, Default)]
struct RootInfo {
    /// The valid `viewBox` as `[x, y, width, height]`.
    view_box: Option<[f64; 4]>,
    /// The `viewBox` attribute was present but invalid.
    invalid_view_box: bool,
    /// `preserveAspectRatio`.
    aspect: Aspect,
    /// `width` or `height` is missing or a percentage (the size is then not absolute).
    relative_size: bool,
}

/// What the XML holds beyond what usvg reports: content that is not imported, and the
/// drawable elements, to notice the ones usvg drops.
#[derive(Debug, Default)]
struct Survey {
    root: RootInfo,
    /// Unsupported element name → how many are drawn.
    unsupported: BTreeMap<String, usize>,
    /// Markers are defined and referenced.
    markers: bool,
    /// Drawn elements with a clip path or mask.
    clipped: usize,
    /// Drawable elements hidden by `display:none` (on them or an ancestor).
    hidden: usize,
    /// Drawable elements in drawn context.
    shapes: usize,
    /// The ids of those, for the ones that have one.
    shape_ids: Vec<String>,
    /// `use` or `switch` make the element count differ from usvg's path count.
    has_use_or_switch: bool,
}

impl Survey {
    /// Walks the document without recursion (elements with absurd geometry are already
    /// removed from it, and reported).
    fn of(xml: &roxmltree::Document<'_>) -> Result<Self, LoadError> {
        let mut survey = Self::default();
        let root = xml.root_element();
        survey.root = RootInfo {
            view_box: root.attribute("viewBox").and_then(parse_view_box),
            invalid_view_box: root.attribute("viewBox").and_then(parse_view_box).is_none()
                && root.has_attribute("viewBox"),
            aspect: root
                .attribute("preserveAspectRatio")
                .map(Aspect::parse)
                .unwrap_or_default(),
            relative_size: ["width", "height"].iter().any(|name| {
                root.attribute(*name)
                    .is_none_or(|v| v.trim_end().ends_with('%'))
            }),
        };
        let mut marker_defined = false;
        let mut marker_used = false;
        // (node, depth, drawn context: every ancestor is svg/g/a, hidden by display:none)
        let mut stack = vec![(root, 1usize, true, false)];
        while let Some((node, depth, drawn, hidden)) = stack.pop() {
            // Popping a stack of reversed children visits elements in document order.
            if depth > MAX_DEPTH {
                return Err(LoadError::TooComplex {
                    reason: format!("elements are nested more than {MAX_DEPTH} deep"),
                });
            }
            let name = node.tag_name().name();
            let svg = matches!(node.tag_name().namespace(), None | Some(SVG_NS));
            let hidden = hidden || is_display_none(node);
            marker_defined |= svg && name == "marker";
            marker_used |= node.attributes().any(|a| {
                a.name().starts_with("marker")
                    || (a.name() == "style" && a.value().contains("marker"))
            });
            if svg && drawn && !hidden {
                if node.has_attribute("clip-path")
                    || node.has_attribute("mask")
                    || node
                        .attribute("style")
                        .is_some_and(|s| s.contains("clip-path") || s.contains("mask"))
                {
                    survey.clipped += 1;
                }
                if UNSUPPORTED.contains(&name) {
                    *survey.unsupported.entry(name.to_owned()).or_default() += 1;
                }
                if name == "use" || name == "switch" {
                    survey.has_use_or_switch = true;
                }
            }
            if svg && drawn && SHAPES.contains(&name) {
                if hidden {
                    survey.hidden += 1;
                } else {
                    survey.shapes += 1;
                    if let Some(id) = node.attribute("id").filter(|id| !id.is_empty()) {
                        survey.shape_ids.push(id.to_owned());
                    }
                }
            }
            let children_drawn = drawn && svg && matches!(name, "svg" | "g" | "a");
            // Push in reverse so the walk visits elements in document order.
            let children: Vec<_> = node
                .children()
                .filter(roxmltree::Node::is_element)
                .collect();
            for child in children.into_iter().rev() {
                stack.push((child, depth + 1, children_drawn, hidden));
            }
        }
        survey.markers = marker_defined && marker_used;
        Ok(survey)
    }

    /// The warnings the survey alone can give.
    fn warnings(&self) -> Vec<String> {
        let mut warnings = Vec::new();
        if self.root.invalid_view_box {
            warnings.push(
                "the root viewBox is invalid and was ignored: sketch units are the root's px"
                    .to_owned(),
            );
        }
        if self.root.view_box.is_none() && self.root.relative_size {
            warnings.push(
                "the svg has no viewBox and no absolute width and height: the sketch extent \
                 was taken from the drawing"
                    .to_owned(),
            );
        }
        for (name, count) in &self.unsupported {
            let what = match name.as_str() {
                "text" | "flowRoot" => "text is not imported",
                "image" => "images are not imported; load a reference image separately",
                _ => "embedded content is not imported",
            };
            warnings.push(format!("{count} <{name}> element(s) ignored: {what}"));
        }
        if self.markers {
            warnings.push("markers (arrowheads and other decorations) are not imported".to_owned());
        }
        if self.clipped > 0 {
            warnings.push(format!(
                "{} element(s) have a clip path or mask, which is ignored: their strokes are \
                 imported whole",
                self.clipped
            ));
        }
        if self.hidden > 0 {
            warnings.push(format!(
                "{} drawable element(s) hidden with display:none are not imported",
                self.hidden
            ));
        }
        warnings
    }

    /// The warning about drawable elements usvg dropped, found by comparing the elements
    /// with the paths usvg produced (`use` and `switch` make the counts incomparable; then
    /// only elements with an id are checked).
    fn dropped_warning(&self, usvg_paths: usize, usvg_ids: &HashSet<&str>) -> Option<String> {
        let missing: Vec<&str> = self
            .shape_ids
            .iter()
            .map(String::as_str)
            .filter(|id| !usvg_ids.contains(id))
            .collect();
        let dropped = if self.has_use_or_switch {
            missing.len()
        } else {
            self.shapes.saturating_sub(usvg_paths).max(missing.len())
        };
        (dropped > 0).then(|| {
            format!(
                "{dropped} drawable element(s) were not imported because they are invalid, \
                 empty, hidden or have non-finite coordinates{}",
                list_ids(&missing)
            )
        })
    }
}

/// Whether the element has `display: none` as an attribute or in its `style`.
fn is_display_none(node: roxmltree::Node<'_, '_>) -> bool {
    if node
        .attribute("display")
        .is_some_and(|v| v.trim() == "none")
    {
        return true;
    }
    node.attribute("style").is_some_and(|style| {
        style.split(';').any(|declaration| {
            let mut parts = declaration.splitn(2, ':');
            let key = parts.next().map(str::trim);
            let value = parts
                .next()
                .map(|v| v.trim().trim_end_matches("!important").trim());
            key == Some("display") && value == Some("none")
        })
    })
}

/// Whether a point is usable: finite and not absurdly far away.
fn usable(p: Point) -> bool {
    p.x.abs() <= MAX_COORDINATE && p.y.abs() <= MAX_COORDINATE
}

/// Turns usvg paths into strokes and counts what was dropped on the way.
#[derive(Debug)]
struct Collector {
    tolerance: f64,
    max_points: usize,
    points: usize,
    strokes: Vec<Stroke>,
    /// All paths usvg produced, visible or not.
    usvg_paths: usize,
    /// Paths usvg marks invisible (no fill and no stroke, or `visibility: hidden`).
    invisible: usize,
    /// Non-finite or absurd points dropped.
    bad_points: usize,
    /// Subpaths with fewer than two distinct points.
    degenerate: usize,
}

impl Collector {
    fn new(tolerance: f64, max_points: usize) -> Self {
        Self {
            tolerance,
            max_points,
            points: 0,
            strokes: Vec::new(),
            usvg_paths: 0,
            invisible: 0,
            bad_points: 0,
            degenerate: 0,
        }
    }

    /// Adds every path of the tree in document order (without recursion) and returns the
    /// ids of the tree's nodes.
    fn add_tree<'t>(
        &mut self,
        tree: &'t usvg::Tree,
        sketch_from_canvas: Affine,
    ) -> Result<HashSet<&'t str>, LoadError> {
        let mut ids = HashSet::new();
        let mut stack = vec![tree.root().children().iter()];
        while let Some(top) = stack.last_mut() {
            let Some(node) = top.next() else {
                stack.pop();
                continue;
            };
            if !node.id().is_empty() {
                ids.insert(node.id());
            }
            match node {
                usvg::Node::Group(group) => stack.push(group.children().iter()),
                usvg::Node::Path(path) => {
                    self.usvg_paths += 1;
                    if path.is_visible() {
                        let affine = sketch_from_canvas * affine_of(path.abs_transform());
                        self.add_path(path.data(), affine)?;
                    } else {
                        self.invisible += 1;
                    }
                }
                // Images are never loaded and text is compiled out; the survey reports both.
                usvg::Node::Image(_) | usvg::Node::Text(_) => {}
            }
        }
        Ok(ids)
    }

    /// Splits a usvg path into subpaths in sketch space, dropping unusable points, and
    /// flattens each into a stroke.
    fn add_path(
        &mut self,
        path: &usvg::tiny_skia_path::Path,
        affine: Affine,
    ) -> Result<(), LoadError> {
        let map =
            |p: usvg::tiny_skia_path::Point| affine * Point::new(f64::from(p.x), f64::from(p.y));
        let mut current: Vec<PathEl> = Vec::new();
        // Where a segment after `Z` starts (SVG: the start of the closed subpath).
        let mut start: Option<Point> = None;
        // A point was dropped since the last element, so a curve's start is not its own.
        let mut broken = false;
        for segment in path.segments() {
            let (end, controls): (Point, Vec<Point>) = match segment {
                PathSegment::MoveTo(p) => {
                    self.finish(&current, false)?;
                    current.clear();
                    let p = map(p);
                    if usable(p) {
                        current.push(PathEl::MoveTo(p));
                        start = Some(p);
                    } else {
                        self.bad_points += 1;
                        start = None;
                    }
                    broken = false;
                    continue;
                }
                PathSegment::Close => {
                    if !current.is_empty() {
                        self.finish(&current, true)?;
                        current.clear();
                    }
                    broken = false;
                    continue;
                }
                PathSegment::LineTo(p) => (map(p), Vec::new()),
                PathSegment::QuadTo(c, p) => (map(p), vec![map(c)]),
                PathSegment::CubicTo(c1, c2, p) => (map(p), vec![map(c1), map(c2)]),
            };
            if !usable(end) {
                self.bad_points += 1;
                broken = true;
                continue;
            }
            if current.is_empty() {
                if let Some(s) = start {
                    current.push(PathEl::MoveTo(s));
                } else {
                    // The subpath's start was dropped: begin at this point instead.
                    current.push(PathEl::MoveTo(end));
                    start = Some(end);
                    broken = false;
                    continue;
                }
            }
            let curve = !broken && controls.iter().all(|&c| usable(c));
            current.push(match (curve, controls.as_slice()) {
                (true, &[c]) => PathEl::QuadTo(c, end),
                (true, &[c1, c2]) => PathEl::CurveTo(c1, c2, end),
                _ => PathEl::LineTo(end),
            });
            broken = false;
        }
        self.finish(&current, false)
    }

    /// Flattens one subpath and keeps it if it has two distinct points.
    fn finish(&mut self, elements: &[PathEl], closed: bool) -> Result<(), LoadError> {
        if elements.is_empty() {
            return Ok(());
        }
        let mut points = self.flatten(elements)?;
        if closed && points.len() > 2 {
            if let (Some(first), Some(last)) = (points.first(), points.last()) {
                // The closing point of `... L x0 y0 Z` or of a full arc repeats the first.
                if first.distance(*last) <= 0.01 * self.tolerance {
                    points.pop();
                }
            }
        }
        if points.len() < 2 {
            self.degenerate += 1;
            return Ok(());
        }
        let id = u32::try_from(self.strokes.len()).map_err(|_| LoadError::TooComplex {
            reason: "more strokes than stroke ids".to_owned(),
        })?;
        self.strokes.push(Stroke {
            id: StrokeId(id),
            points,
            closed,
            class_override: None,
        });
        Ok(())
    }

    /// The polyline of a subpath (a `MoveTo` then lines and curves), without consecutive
    /// duplicate points.
    fn flatten(&mut self, elements: &[PathEl]) -> Result<Vec<DVec2>, LoadError> {
        let mut lo = Point::new(f64::INFINITY, f64::INFINITY);
        let mut hi = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        for element in elements {
            let points: &[Point] = match element {
                PathEl::MoveTo(p) | PathEl::LineTo(p) => std::slice::from_ref(p),
                PathEl::QuadTo(a, b) => &[*a, *b],
                PathEl::CurveTo(a, b, c) => &[*a, *b, *c],
                PathEl::ClosePath => &[],
            };
            for p in points {
                lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
                hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
            }
        }
        let extent = (hi.x - lo.x).max(hi.y - lo.y);
        let tolerance = self
            .tolerance
            .max(MIN_TOLERANCE_OF_EXTENT * extent)
            .max(f64::MIN_POSITIVE);

        let mut points: Vec<DVec2> = Vec::new();
        let push = |points: &mut Vec<DVec2>, p: Point| {
            let p = DVec2::new(p.x, p.y);
            if points.last() != Some(&p) {
                points.push(p);
            }
        };
        let mut previous: Option<Point> = None;
        for &element in elements {
            match (element, previous) {
                (PathEl::QuadTo(_, end) | PathEl::CurveTo(_, _, end), Some(from)) => {
                    // One curve at a time, so the point limit is checked between curves.
                    kurbo::flatten([PathEl::MoveTo(from), element], tolerance, |el| {
                        if let PathEl::LineTo(q) = el {
                            push(&mut points, q);
                        }
                    });
                    previous = Some(end);
                }
                (
                    PathEl::MoveTo(p)
                    | PathEl::LineTo(p)
                    | PathEl::QuadTo(_, p)
                    | PathEl::CurveTo(_, _, p),
                    _,
                ) => {
                    push(&mut points, p);
                    previous = Some(p);
                }
                (PathEl::ClosePath, _) => {}
            }
            if self.points + points.len() > self.max_points {
                return Err(LoadError::TooComplex {
                    reason: format!("more than {} points", self.max_points),
                });
            }
        }
        self.points += points.len();
        Ok(points)
    }

    /// The warnings about dropped paths and points.
    fn warnings(&self) -> Vec<String> {
        let mut warnings = Vec::new();
        if self.invisible > 0 {
            warnings.push(format!(
                "{} invisible path(s) (visibility:hidden, or neither fill nor stroke) are not \
                 imported",
                self.invisible
            ));
        }
        if self.bad_points > 0 {
            warnings.push(format!(
                "{} non-finite or out-of-range point(s) were dropped",
                self.bad_points
            ));
        }
        if self.degenerate > 0 {
            warnings.push(format!(
                "{} subpath(s) with fewer than two distinct points were dropped",
                self.degenerate
            ));
        }
        warnings
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;
    use kurbo::{CubicBez, ParamCurve, QuadBez};

    use super::{import_svg, parse_view_box, Aspect, SvgImport, SvgOptions};
    use crate::io::LoadError;

    /// The default tolerance on the 1000 × 1000 test drawings.
    const TOL: f64 = 1e-4 * 1000.0 * std::f64::consts::SQRT_2;

    /// f32 storage inside usvg rounds coordinates near 1000 by about 1e-4.
    const EPS: f64 = 1e-3;

    fn doc(body: &str) -> String {
        format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
                 width="1000" height="1000" viewBox="0 0 1000 1000">{body}</svg>"#
        )
    }

    fn imported(text: &str) -> SvgImport {
        import_svg(text.as_bytes(), &SvgOptions::default()).expect("the test svg imports")
    }

    fn import_body(body: &str) -> SvgImport {
        imported(&doc(body))
    }

    fn assert_points(actual: &[DVec2], expected: &[(f64, f64)]) {
        assert_eq!(actual.len(), expected.len(), "{actual:?} vs {expected:?}");
        for (a, &(x, y)) in actual.iter().zip(expected) {
            assert!(
                a.distance(DVec2::new(x, y)) < EPS,
                "{actual:?} vs {expected:?}"
            );
        }
    }

    fn distance_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
        let ab = b - a;
        let t = if ab.length_squared() > 0.0 {
            ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        p.distance(a + t * ab)
    }

    fn distance_to_polyline(p: DVec2, points: &[DVec2], closed: bool) -> f64 {
        let mut best = f64::INFINITY;
        for w in points.windows(2) {
            best = best.min(distance_to_segment(p, w[0], w[1]));
        }
        if let (true, Some(&first), Some(&last)) = (closed, points.first(), points.last()) {
            best = best.min(distance_to_segment(p, last, first));
        }
        best
    }

    /// The largest distance from densely sampled curve points to the polyline.
    fn deviation(curve: impl Fn(f64) -> DVec2, points: &[DVec2], closed: bool) -> f64 {
        (0..=2000)
            .map(|i| distance_to_polyline(curve(f64::from(i) / 2000.0), points, closed))
            .fold(0.0, f64::max)
    }

    fn dvec(p: kurbo::Point) -> DVec2 {
        DVec2::new(p.x, p.y)
    }

    /// usvg turns arcs into cubics at 0.1 user units, and never fewer than four per
    /// ellipse, whose radial error is 2.7e-4 · radius; f32 storage adds a little.
    fn arc_error(radius: f64) -> f64 {
        (2.7e-4 * radius).min(0.1) + EPS
    }

    /// How far a flattened vertex may be from a cubic: kurbo flattens a cubic through
    /// quadratics that are within a tenth of the tolerance of it.
    const VERTEX_ERROR: f64 = 0.1 * TOL;

    #[test]
    fn lines_keep_their_vertices() {
        let import = import_body(r#"<path d="M 10 20 L 30 40 H 50 V 10 l 5 5 h -5 v 2"/>"#);
        assert!(import.warnings.is_empty(), "{:?}", import.warnings);
        let [stroke] = import.sketch.strokes.as_slice() else {
            panic!("one stroke expected");
        };
        assert!(!stroke.closed);
        assert_points(
            &stroke.points,
            &[
                (10.0, 20.0),
                (30.0, 40.0),
                (50.0, 40.0),
                (50.0, 10.0),
                (55.0, 15.0),
                (50.0, 15.0),
                (50.0, 17.0),
            ],
        );
    }

    #[test]
    fn a_closed_subpath_drops_the_repeated_start() {
        for d in [
            "M 0 0 L 100 0 L 100 100 L 0 0 Z",
            "M 0 0 L 100 0 L 100 100 Z",
            "m 0 0 100 0 0 100 z",
        ] {
            let import = import_body(&format!(r#"<path d="{d}"/>"#));
            let stroke = &import.sketch.strokes[0];
            assert!(stroke.closed, "{d}");
            assert_points(&stroke.points, &[(0.0, 0.0), (100.0, 0.0), (100.0, 100.0)]);
        }
    }

    #[test]
    fn each_subpath_is_a_stroke_with_ids_in_document_order() {
        let import = import_body(
            r#"<path d="M 0 0 L 10 0 M 20 0 L 30 0 Z M 40 0 L 50 0"/>
               <g><path d="M 0 100 L 10 100"/></g>
               <path d="M 0 0 L 10 0 L 10 10 Z L 20 20"/>"#,
        );
        let strokes = &import.sketch.strokes;
        let ids: Vec<u32> = strokes.iter().map(|s| s.id.0).collect();
        assert_eq!(ids, [0, 1, 2, 3, 4, 5]);
        let closed: Vec<bool> = strokes.iter().map(|s| s.closed).collect();
        assert_eq!(closed, [false, true, false, false, true, false]);
        assert_points(&strokes[1].points, &[(20.0, 0.0), (30.0, 0.0)]);
        assert_points(&strokes[3].points, &[(0.0, 100.0), (10.0, 100.0)]);
        // After `Z` a segment starts at the start of the closed subpath.
        assert_points(&strokes[5].points, &[(0.0, 0.0), (20.0, 20.0)]);
        assert!(strokes.iter().all(|s| s.class_override.is_none()));
    }

    #[test]
    fn cubic_beziers_are_flattened_within_tolerance() {
        let import = import_body(r#"<path d="M 100 500 C 300 100 700 900 900 500"/>"#);
        let points = &import.sketch.strokes[0].points;
        let cubic = CubicBez::new(
            (100.0, 500.0),
            (300.0, 100.0),
            (700.0, 900.0),
            (900.0, 500.0),
        );
        assert!(points.len() >= 4, "{} points", points.len());
        assert!(points[0].distance(DVec2::new(100.0, 500.0)) < EPS);
        assert!(points[points.len() - 1].distance(DVec2::new(900.0, 500.0)) < EPS);
        let error = deviation(|t| dvec(cubic.eval(t)), points, false);
        assert!(error <= TOL + EPS, "deviation {error} > {TOL}");
        // The vertices lie near the curve (kurbo flattens cubics through quadratics, so
        // they are within the tolerance, not exactly on it).
        for p in points {
            let nearest =
                kurbo::ParamCurveNearest::nearest(&cubic, kurbo::Point::new(p.x, p.y), 1e-9);
            assert!(
                nearest.distance_sq.sqrt() <= VERTEX_ERROR + EPS,
                "{p} is off the curve"
            );
        }
    }

    #[test]
    fn smooth_and_relative_cubics_match_the_explicit_form() {
        let explicit = import_body(
            r#"<path d="M 100 500 C 200 300 300 300 400 500 C 500 700 600 700 700 500"/>"#,
        );
        let smooth =
            import_body(r#"<path d="M 100 500 c 100 -200 200 -200 300 0 s 200 200 300 0"/>"#);
        assert_eq!(
            explicit.sketch.strokes[0].points.len(),
            smooth.sketch.strokes[0].points.len()
        );
        for (a, b) in explicit.sketch.strokes[0]
            .points
            .iter()
            .zip(&smooth.sketch.strokes[0].points)
        {
            assert!(a.distance(*b) < EPS, "{a} vs {b}");
        }
    }

    #[test]
    fn quadratic_beziers_are_flattened_within_tolerance() {
        // `T` reflects the previous control point: (500, 900) about (900, 100).
        let import = import_body(r#"<path d="M 100 100 Q 500 900 900 100 T 900 900"/>"#);
        let points = &import.sketch.strokes[0].points;
        let first = QuadBez::new((100.0, 100.0), (500.0, 900.0), (900.0, 100.0));
        let second = QuadBez::new((900.0, 100.0), (1300.0, -700.0), (900.0, 900.0));
        let curve = |t: f64| {
            if t < 0.5 {
                dvec(first.eval(2.0 * t))
            } else {
                dvec(second.eval(2.0 * t - 1.0))
            }
        };
        let error = deviation(curve, points, false);
        assert!(error <= TOL + EPS, "deviation {error} > {TOL}");
        assert!(
            points.iter().any(|p| p.y < 0.0),
            "the second quad bulges upwards"
        );
    }

    #[test]
    fn arcs_are_within_tolerance_of_the_true_circle() {
        let import = import_body(
            r#"<path d="M 900 500 A 400 400 0 1 1 100 500 A 400 400 0 1 1 900 500 Z"/>"#,
        );
        let stroke = &import.sketch.strokes[0];
        assert!(stroke.closed);
        assert!(stroke.points.len() > 16, "{} points", stroke.points.len());
        let centre = DVec2::splat(500.0);
        // The vertices are as close as usvg's cubics, and the polyline is within the
        // flattening tolerance of those.
        for p in &stroke.points {
            let error = (p.distance(centre) - 400.0).abs();
            assert!(
                error <= arc_error(400.0) + VERTEX_ERROR,
                "vertex {p} is {error} off the circle"
            );
        }
        let circle = |t: f64| centre + 400.0 * DVec2::from_angle(std::f64::consts::TAU * t);
        let error = deviation(circle, &stroke.points, true);
        assert!(
            error <= TOL + arc_error(400.0),
            "deviation {error} > {TOL} + {}",
            arc_error(400.0)
        );
    }

    #[test]
    fn rotated_elliptical_arcs_and_flags() {
        // Half of an ellipse with radii 300 and 100, its x axis turned by 30°.
        let import = import_body(
            r#"<path d="M 240.192 350 A 300 100 30 0 1 759.808 650"/>
               <path d="M 240.192 350 A 300 100 30 0 0 759.808 650"/>"#,
        );
        let (sin, cos) = 30f64.to_radians().sin_cos();
        for stroke in &import.sketch.strokes {
            for p in &stroke.points {
                let d = *p - DVec2::splat(500.0);
                let (u, v) = (d.x * cos + d.y * sin, -d.x * sin + d.y * cos);
                let f = (u / 300.0).powi(2) + (v / 100.0).powi(2);
                assert!((f - 1.0).abs() < 2e-3, "{p} is off the ellipse ({f})");
            }
        }
        // The sweep flag picks opposite halves.
        let mid = |i: usize| {
            let points = &import.sketch.strokes[i].points;
            points[points.len() / 2]
        };
        assert!(mid(0).distance(mid(1)) > 150.0);
    }

    #[test]
    fn basic_shapes_become_polylines() {
        let import = import_body(
            r#"<rect x="10" y="20" width="100" height="50"/>
               <line x1="0" y1="0" x2="30" y2="40" stroke="black"/>
               <polyline points="0,0 10,10 20,0" fill="none" stroke="black"/>
               <polygon points="0,0 10,10 20,0"/>
               <circle cx="500" cy="500" r="300"/>
               <ellipse cx="500" cy="500" rx="400" ry="100"/>
               <rect x="200" y="200" width="100" height="60" rx="10"/>"#,
        );
        assert!(import.warnings.is_empty(), "{:?}", import.warnings);
        let s = &import.sketch.strokes;
        assert_eq!(s.len(), 7);
        assert!(s[0].closed);
        assert_points(
            &s[0].points,
            &[(10.0, 20.0), (110.0, 20.0), (110.0, 70.0), (10.0, 70.0)],
        );
        assert!(!s[1].closed);
        assert_points(&s[1].points, &[(0.0, 0.0), (30.0, 40.0)]);
        assert!(!s[2].closed);
        assert_points(&s[2].points, &[(0.0, 0.0), (10.0, 10.0), (20.0, 0.0)]);
        assert!(s[3].closed);
        assert_points(&s[3].points, &[(0.0, 0.0), (10.0, 10.0), (20.0, 0.0)]);
        assert!(s[4].closed);
        for p in &s[4].points {
            let error = (p.distance(DVec2::splat(500.0)) - 300.0).abs();
            assert!(
                error <= arc_error(300.0) + VERTEX_ERROR,
                "{p} is {error} off the circle"
            );
        }
        let circle =
            |t: f64| DVec2::splat(500.0) + 300.0 * DVec2::from_angle(std::f64::consts::TAU * t);
        assert!(deviation(circle, &s[4].points, true) <= TOL + arc_error(300.0));
        assert!(s[5].closed);
        let ellipse: Vec<DVec2> = (0..20_000)
            .map(|i| {
                let angle = std::f64::consts::TAU * f64::from(i) / 20_000.0;
                DVec2::new(500.0 + 400.0 * angle.cos(), 500.0 + 100.0 * angle.sin())
            })
            .collect();
        for p in &s[5].points {
            let error = distance_to_polyline(*p, &ellipse, true);
            assert!(
                error <= arc_error(400.0) + VERTEX_ERROR,
                "{p} is {error} off the ellipse"
            );
        }
        assert!(s[6].closed);
        assert!(s[6].points.len() > 8, "the corners are rounded");
        for p in &s[6].points {
            assert!((200.0 - EPS..=300.0 + EPS).contains(&p.x), "{p}");
            assert!((200.0 - EPS..=260.0 + EPS).contains(&p.y), "{p}");
        }
    }

    #[test]
    fn element_and_nested_group_transforms_compose() {
        let import = import_body(
            r#"<g transform="translate(100,0)">
                 <g transform="scale(2)">
                   <path transform="rotate(90)" d="M 1 0 L 2 0"/>
                 </g>
               </g>
               <path transform="matrix(1 0 0 -1 10 20)" d="M 1 2 L 3 4"/>
               <path transform="rotate(90 50 50)" d="M 60 50 L 70 50"/>
               <path transform="skewX(45)" d="M 0 10 L 0 20"/>
               <g transform="translate(5)"><a><path transform="scale(3 2)" d="M 1 1 L 2 2"/></a></g>"#,
        );
        let s = &import.sketch.strokes;
        assert_points(&s[0].points, &[(100.0, 2.0), (100.0, 4.0)]);
        assert_points(&s[1].points, &[(11.0, 18.0), (13.0, 16.0)]);
        assert_points(&s[2].points, &[(50.0, 60.0), (50.0, 70.0)]);
        assert_points(&s[3].points, &[(10.0, 10.0), (20.0, 20.0)]);
        assert_points(&s[4].points, &[(8.0, 2.0), (11.0, 4.0)]);
    }

    #[test]
    fn the_view_box_not_the_size_defines_sketch_space() {
        let import = imported(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="21.3333in" height="28.4444in"
                    viewBox="0 0 1536 2048"><path d="M 0 0 L 1536 2048 L 768 10"/></svg>"#,
        );
        assert_eq!(
            import.sketch.view_box,
            Some((DVec2::ZERO, DVec2::new(1536.0, 2048.0)))
        );
        assert_points(
            &import.sketch.strokes[0].points,
            &[(0.0, 0.0), (1536.0, 2048.0), (768.0, 10.0)],
        );
        // The viewBox mapping is undone with usvg's own f32 arithmetic: no drift at all.
        let p = import.sketch.strokes[0].points[2];
        assert!(p.distance(DVec2::new(768.0, 10.0)) < 1e-9, "{p}");
    }

    #[test]
    fn view_box_offsets_and_aspect_ratios_are_undone() {
        for aspect in [
            "",
            "none",
            "xMinYMin slice",
            "xMaxYMax meet",
            "xMidYMax slice",
        ] {
            let text = format!(
                r#"<svg xmlns="http://www.w3.org/2000/svg" width="10cm" height="3cm"
                        viewBox="-50 -20 100 50" preserveAspectRatio="{aspect}">
                     <path d="M -50 -20 L 50 30 L 0 0"/></svg>"#
            );
            let import = imported(&text);
            assert_eq!(
                import.sketch.view_box,
                Some((DVec2::new(-50.0, -20.0), DVec2::new(100.0, 50.0))),
                "{aspect}"
            );
            assert_points(
                &import.sketch.strokes[0].points,
                &[(-50.0, -20.0), (50.0, 30.0), (0.0, 0.0)],
            );
        }
    }

    #[test]
    fn without_a_view_box_user_units_are_px() {
        let import = imported(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="3in" height="2in">
                 <path d="M 10 10 L 200 150"/></svg>"#,
        );
        assert_eq!(
            import.sketch.view_box,
            Some((DVec2::ZERO, DVec2::new(288.0, 192.0)))
        );
        assert_points(
            &import.sketch.strokes[0].points,
            &[(10.0, 10.0), (200.0, 150.0)],
        );
        assert!(import.warnings.is_empty(), "{:?}", import.warnings);

        let no_size = imported(
            r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M 10 10 L 200 150"/></svg>"#,
        );
        assert_points(
            &no_size.sketch.strokes[0].points,
            &[(10.0, 10.0), (200.0, 150.0)],
        );
        assert!(no_size.warnings.iter().any(|w| w.contains("no viewBox")));
    }

    #[test]
    fn a_root_transform_acts_in_viewport_units() {
        // The root is drawn at twice its viewBox size, so 10 px are 5 sketch units.
        let import = imported(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="200"
                    viewBox="0 0 100 100" transform="translate(10 0)">
                 <path d="M 0 0 L 10 0"/></svg>"#,
        );
        assert_points(&import.sketch.strokes[0].points, &[(5.0, 0.0), (15.0, 0.0)]);
    }

    #[test]
    fn use_elements_and_nested_svgs_are_resolved() {
        let import = import_body(
            r##"<defs><path id="p" d="M 0 0 L 10 0"/></defs>
                <use xlink:href="#p" x="100" y="5"/>
                <use href="#p" transform="scale(2)"/>
                <svg x="100" y="100" width="200" height="200" viewBox="0 0 10 10">
                  <path d="M 0 0 L 10 10"/>
                </svg>"##,
        );
        assert!(import.warnings.is_empty(), "{:?}", import.warnings);
        let s = &import.sketch.strokes;
        assert_eq!(s.len(), 3);
        assert_points(&s[0].points, &[(100.0, 5.0), (110.0, 5.0)]);
        assert_points(&s[1].points, &[(0.0, 0.0), (20.0, 0.0)]);
        assert_points(&s[2].points, &[(100.0, 100.0), (300.0, 300.0)]);
    }

    #[test]
    fn valid_documents_give_no_warnings() {
        // Links, nested svgs, clip paths in defs, styles and ids everywhere: nothing here
        // is dropped, so nothing may be reported.
        let import = import_body(
            r#"<defs><clipPath id="unused"><rect width="1" height="1"/></clipPath></defs>
               <a href="https://example.com"><path id="a" d="M 0 0 L 1 1"/></a>
               <svg id="inner" x="10" y="10" width="100" height="100" viewBox="0 0 10 10">
                 <g id="layer"><path id="b" d="M 0 0 L 1 1"/></g>
                 <circle id="c" cx="5" cy="5" r="2"/>
               </svg>
               <polyline id="d" points="0,0 5,5 10,0" style="fill:none;stroke:#000"/>
               <metadata><path d="M 0 0 L 1 1"/></metadata>"#,
        );
        assert_eq!(import.sketch.strokes.len(), 4);
        assert!(import.warnings.is_empty(), "{:?}", import.warnings);
    }

    #[test]
    fn css_styles_apply() {
        let import = import_body(
            r"<style>.s { fill: none; stroke: black }</style>
               <path class='s' d='M 0 0 L 10 0'/>",
        );
        assert_eq!(import.sketch.strokes.len(), 1);
        assert!(import.warnings.is_empty(), "{:?}", import.warnings);
    }

    #[test]
    fn unsupported_content_is_reported_not_fatal() {
        let import = import_body(
            r#"<text x="10" y="10">label</text><text>another</text>
               <image href="photo.png" width="100" height="100"/>
               <foreignObject width="10" height="10"/>
               <path d="M 0 0 L 10 0"/>"#,
        );
        assert_eq!(import.sketch.strokes.len(), 1);
        let all = import.warnings.join("\n");
        assert!(all.contains("2 <text>"), "{all}");
        assert!(all.contains("<image>"), "{all}");
        assert!(all.contains("<foreignObject>"), "{all}");
    }

    #[test]
    fn markers_do_not_become_strokes() {
        let import = import_body(
            r#"<defs><marker id="arrow" markerWidth="10" markerHeight="10">
                  <path d="M 0 0 L 10 5 L 0 10 Z"/></marker></defs>
                <path d="M 0 0 L 100 0" stroke="black" marker-end="url(#arrow)"/>
                <path d="M 0 10 L 100 10" style="stroke: black; marker-start: url(#arrow)"/>"#,
        );
        assert_eq!(import.sketch.strokes.len(), 2);
        assert!(import.warnings.iter().any(|w| w.contains("markers")));
    }

    #[test]
    fn hidden_invisible_and_clipped_elements_are_reported() {
        let import = import_body(
            r#"<path d="M 0 0 L 10 0" display="none"/>
                <g style="fill: red; display : none"><path d="M 0 0 L 10 0"/><rect width="1" height="1"/></g>
                <path d="M 0 0 L 10 0" visibility="hidden"/>
                <path d="M 0 0 L 10 0" fill="none" stroke="none"/>
                <clipPath id="c"><rect width="5" height="5"/></clipPath>
                <path d="M 0 20 L 10 20" stroke="black" clip-path="url(#c)"/>
                <path d="M 0 30 L 10 30"/>"#,
        );
        let all = import.warnings.join("\n");
        assert!(
            all.contains("3 drawable element(s) hidden with display:none"),
            "{all}"
        );
        assert!(all.contains("2 invisible path(s)"), "{all}");
        assert!(all.contains("1 element(s) have a clip path"), "{all}");
        // The clipped path is imported whole, the visible one too.
        assert_eq!(import.sketch.strokes.len(), 2);
        assert_points(
            &import.sketch.strokes[0].points,
            &[(0.0, 20.0), (10.0, 20.0)],
        );
        assert!(!all.contains("were not imported because"), "{all}");
    }

    #[test]
    fn empty_documents_are_ok_with_a_warning() {
        for text in [
            "",
            "  \n",
            "\u{feff}",
            r#"<svg xmlns="http://www.w3.org/2000/svg"/>"#,
            r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"><g/><defs/></svg>"#,
            r#"<svg xmlns="http://www.w3.org/2000/svg"><text>only text</text></svg>"#,
            r#"<svg xmlns="http://www.w3.org/2000/svg"><path d=""/><path d="M 5 5"/></svg>"#,
        ] {
            let import = imported(text);
            assert!(import.sketch.strokes.is_empty(), "{text:?}");
            assert!(
                import
                    .warnings
                    .iter()
                    .any(|w| w.contains("no drawable geometry") || w.contains("empty")),
                "{text:?}: {:?}",
                import.warnings
            );
        }
    }

    #[test]
    fn malformed_input_is_an_error() {
        for data in [
            &b"<svg"[..],
            b"not xml at all",
            b"<html><body/></html>",
            b"<svg xmlns='http://www.w3.org/2000/svg'><path></svg>",
            b"<svg xmlns='http://www.w3.org/2000/svg' width='0' height='0'/>",
            b"\xff\xfe<\x00s\x00",
        ] {
            let result = import_svg(data, &SvgOptions::default());
            assert!(
                matches!(result, Err(LoadError::Svg { .. })),
                "{:?}: {result:?}",
                String::from_utf8_lossy(data)
            );
        }
        let gzip = import_svg(&[0x1f, 0x8b, 8, 0], &SvgOptions::default());
        assert!(matches!(gzip, Err(LoadError::CompressedSvg)), "{gzip:?}");
    }

    #[test]
    fn non_finite_and_huge_coordinates_never_panic() {
        let import = import_body(
            r#"<path id="overflow" d="M 0 0 L 1e39 0 L 10 10"/>
               <path d="M 0 0 L NaN 5 L 10 10"/>
               <g id="far" transform="scale(1e30)"><path transform="scale(1e30)" d="M 0 0 L 1 1"/></g>
               <g id="wide" transform="scale(1e20)"><path d="M 0 0 C 1e10 1e10 -1e10 1e10 1e10 0"/></g>
               <g transform="scale(1e6)"><path id="big-but-fine" d="M 0 0 C 1e5 1e5 -1e5 1e5 1e5 0"/></g>
               <path d="M 1 1 L 2 2"/>"#,
        );
        let all = import.warnings.join("\n");
        assert!(all.contains("#overflow, #far, #wide"), "{all}");
        // The curve 1e11 units wide is flattened, but not at the drawing's tolerance.
        let points: usize = import.sketch.strokes.iter().map(|s| s.points.len()).sum();
        assert!(points < 100_000, "{points} points");
        for stroke in &import.sketch.strokes {
            assert!(stroke
                .points
                .iter()
                .all(|p| p.is_finite() && p.abs().max_element() <= 2e11));
        }
        assert!(import
            .sketch
            .strokes
            .iter()
            .any(|s| s.points.len() == 2 && s.points[1].distance(DVec2::splat(2.0)) < EPS));

        // A view box so small that usvg's scale overflows f32.
        let tiny = imported(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100"
                    viewBox="0 0 1e-40 1e-40"><path id="p" d="M 0 0 L 1e-40 1e-40"/></svg>"#,
        );
        for stroke in &tiny.sketch.strokes {
            assert!(stroke.points.iter().all(|p| p.is_finite()));
        }
    }

    #[test]
    fn absurd_arcs_are_dropped_before_usvg_spends_forever_on_them() {
        // usvg turns arcs into cubics at 0.1 user units: a radius of 1e30 would be
        // hundreds of thousands of cubics, 1e300 an endless loop.
        let import = import_body(
            r#"<path id="huge-arc" d="M 0 0 A 1 1 0 0 1 1e300 0"/>
               <path id="wide-arc" d='M 0 0 A 1 1 0 0 1 1e30 0'/>
               <circle id="big" r="1e30"/>
               <rect width="2e13" height="5" rx="1e13"/>
               <ellipse rx="5" ry="99999999999999999999999999"/>
               <path d="M 10 10 A 5 5 0 0 1 20 20"/>"#,
        );
        assert_eq!(import.sketch.strokes.len(), 1);
        let all = import.warnings.join("\n");
        assert!(
            all.contains("5 element(s) with coordinates, sizes or transforms beyond"),
            "{all}"
        );
        assert!(all.contains("#huge-arc, #wide-arc, #big"), "{all}");
        assert!(
            !all.contains("drawable element(s) were not imported"),
            "{all}"
        );
    }

    /// Issue 19, case 7: the guard covers every coordinate attribute, not only path data
    /// and radii; a huge number on the root refuses the drawing.
    #[test]
    fn huge_numbers_in_any_coordinate_attribute_drop_the_element() {
        let tiny = br#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><rect y="3.4028235e38" width="10" height="10"/><path d="M1 1L9 9"/></svg>"#;
        assert!(tiny.len() < 150);
        let import = import_svg(tiny, &SvgOptions::default()).expect("imported");
        assert_eq!(import.sketch.strokes.len(), 1, "the rect is dropped");
        assert!(
            import.warnings.iter().any(|w| w.contains("1 element(s)")),
            "{:?}",
            import.warnings
        );
        for attribute in [
            r#"x="2e38""#,
            r#"cx="-1e13""#,
            r#"x1="1e20""#,
            r#"points="0 0 1e30 5""#,
            r#"transform="translate(0 1e300)""#,
        ] {
            let import = import_body(&format!(
                r#"<circle id="bad" r="4" {attribute}/><path d="M1 1L9 9"/>"#
            ));
            assert_eq!(import.sketch.strokes.len(), 1, "{attribute}");
            assert!(
                import.warnings.iter().any(|w| w.contains("#bad")),
                "{attribute}"
            );
        }
        for root in [r#"viewBox="0 0 1e30 10""#, r#"width="1e20""#] {
            let text = format!(
                r#"<svg xmlns="http://www.w3.org/2000/svg" {root}><path d="M1 1L9 9"/></svg>"#
            );
            let error = import_svg(text.as_bytes(), &SvgOptions::default()).expect_err(root);
            assert!(
                matches!(error, LoadError::TooComplex { .. }),
                "{root}: {error}"
            );
        }
    }

    #[test]
    fn absurd_numbers_are_found_as_svg_reads_them() {
        use super::has_absurd_number;
        for absurd in [
            "1e13",
            "M 0 0 L 1E+40 0",
            "1.5.5 99999999999999",
            "-2e12",
            "1e999",
        ] {
            assert!(has_absurd_number(absurd), "{absurd}");
        }
        for fine in [
            "",
            "M 0 0 L 1e12 5",
            "1.5.5",
            "a 1 1 0 1176.907 5",
            "e99 E99",
            "1e-300",
            "...",
        ] {
            assert!(!has_absurd_number(fine), "{fine}");
        }
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_crash() {
        let nested = |depth: usize| {
            doc(&format!(
                "{}<path d='M 0 0 L 1 1'/>{}",
                "<g>".repeat(depth),
                "</g>".repeat(depth)
            ))
        };
        let ok = imported(&nested(200));
        assert_eq!(ok.sketch.strokes.len(), 1);
        let deep = import_svg(nested(100_000).as_bytes(), &SvgOptions::default());
        assert!(
            matches!(deep, Err(LoadError::TooComplex { .. })),
            "{deep:?}"
        );
    }

    #[test]
    fn degenerate_subpaths_are_dropped_with_a_warning() {
        let import =
            import_body(r#"<path d="M 5 5 L 5 5 M 1 1 Z M 0 0 L 3 0 M 7 7 C 7 7 7 7 7 7"/>"#);
        assert_eq!(import.sketch.strokes.len(), 1);
        assert_eq!(import.sketch.strokes[0].id.0, 0);
        assert!(
            import.warnings.iter().any(|w| w.contains("fewer than two")),
            "{:?}",
            import.warnings
        );
    }

    #[test]
    fn the_tolerance_option_controls_the_point_count() {
        let body = doc(r#"<circle cx="500" cy="500" r="400"/>"#);
        let count = |tolerance: f64| {
            let options = SvgOptions::default()
                .with_relative_tolerance(tolerance)
                .unwrap();
            import_svg(body.as_bytes(), &options)
                .unwrap()
                .sketch
                .strokes[0]
                .points
                .len()
        };
        let (coarse, default, fine) = (count(1e-2), count(1e-4), count(1e-6));
        assert!(
            coarse < default && default < fine,
            "{coarse} {default} {fine}"
        );
        for bad in [0.0, -1e-4, 2.0, f64::NAN, f64::INFINITY] {
            let result = SvgOptions::default().with_relative_tolerance(bad);
            assert!(
                matches!(result, Err(LoadError::InvalidOption { .. })),
                "{bad}"
            );
        }
    }

    #[test]
    fn the_point_limit_is_an_error() {
        let options = SvgOptions::default().with_max_points(10);
        let result = import_svg(
            doc(r#"<circle cx="500" cy="500" r="400"/>"#).as_bytes(),
            &options,
        );
        assert!(
            matches!(result, Err(LoadError::TooComplex { .. })),
            "{result:?}"
        );
    }

    #[test]
    fn view_box_parsing_follows_svg() {
        assert_eq!(
            parse_view_box("0 0 1536 2048"),
            Some([0.0, 0.0, 1536.0, 2048.0])
        );
        assert_eq!(parse_view_box(" 0,0 , 10,5 "), Some([0.0, 0.0, 10.0, 5.0]));
        assert_eq!(parse_view_box("-5-5 1e1 .5"), Some([-5.0, -5.0, 10.0, 0.5]));
        for bad in [
            "0 0 0 10",
            "0 0 -1 5",
            "a b c d",
            "0 0 10",
            "0 0 1e39 1",
            "0 0 inf 1",
            "0 0 NaN 1",
            "0 0 5em 5",
            "",
        ] {
            assert_eq!(parse_view_box(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn aspect_ratio_parsing_follows_svg() {
        assert_eq!(Aspect::parse("none").align, None);
        let a = Aspect::parse("defer xMaxYMin slice");
        assert_eq!((a.align, a.slice), (Some((1.0, 0.0)), true));
        let a = Aspect::parse("xMinYMid meet");
        assert_eq!((a.align, a.slice), (Some((0.0, 0.5)), false));
        for bad in [
            "",
            "garbage",
            "xMidYMid bogus",
            "xMidYmid",
            "xMiddYMid",
            "xMi€YMid",
        ] {
            assert_eq!(Aspect::parse(bad), Aspect::default(), "{bad:?}");
        }
    }
}
