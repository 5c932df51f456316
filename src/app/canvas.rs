//! The sketch canvas: the reference image, the strokes (coloured by class, or by
//! assignment for the selected part), the parts' projected outlines, the drag preview,
//! and the tools. Pan with the right or middle button (or Space + drag), zoom with the
//! wheel, F fits the drawing.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use egui::{Color32, Pos2, Rect, Sense, Stroke as Pen, Ui, Vec2};
use glam::DVec2;

use super::view3d::part_color;
use super::{words, GeosnapApp};
use crate::core::primitive::Primitive;
use crate::core::sketch::{classify_sketch, ClassifyOptions, StrokeClass, StrokeId};
use crate::core::snap::Verdict;

const FEATURE: Color32 = Color32::from_rgb(40, 110, 220);
const SILHOUETTE: Color32 = Color32::from_rgb(45, 45, 50);
const PREVIEW: Color32 = Color32::from_rgb(240, 130, 20);
/// The most characters of a part's name drawn at its centre on the canvas.
const MAX_LABEL_CHARS: usize = 24;

/// The tools of the canvas.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Click a part to select it; drag a part to move and re-snap it.
    Select,
    /// Draw strokes.
    Draw,
    /// Click or drag over strokes to erase them.
    Erase,
    /// Click a stroke to switch it between feature and silhouette.
    Reclassify,
}

/// The canvas's state: its pan and zoom, the tool, the stroke being drawn, the
/// reference image shown under the strokes, and the strokes' classes.
#[derive(Debug)]
pub(crate) struct Canvas {
    view: CanvasView,
    tool: Tool,
    /// The stroke being drawn (sketch space).
    drawing: Option<Vec<DVec2>>,
    image: ReferenceImage,
    /// The strokes' automatic classes, with the strokes' revision they were found for.
    classes: Option<(u64, Vec<(StrokeId, StrokeClass)>)>,
    /// Where the last drop was released (sketch space), until its job ends.
    dropped_at: Option<DVec2>,
    /// Why the last drop placed nothing, shown where it was released for a while.
    drop_note: Option<DropNote>,
    /// The screen rectangles of the labels painted in the last frame: part ids (with
    /// their badges) and relation labels.
    labels: Vec<Rect>,
    /// The verdict badges painted in the last frame: each part's and its colour.
    badges: Vec<(crate::core::model::PrimitiveId, Color32)>,
}

/// A short message on the canvas at the point where a drop failed.
#[derive(Clone, Debug)]
pub(crate) struct DropNote {
    /// The drop point (sketch space).
    at: DVec2,
    /// What went wrong.
    text: String,
    /// When it goes away.
    until: Instant,
}

/// How long a failed drop's note stays on the canvas.
const DROP_NOTE_FOR: Duration = Duration::from_secs(6);

impl Default for Canvas {
    fn default() -> Self {
        Self {
            view: CanvasView::default(),
            tool: Tool::Select,
            drawing: None,
            image: ReferenceImage::default(),
            classes: None,
            dropped_at: None,
            drop_note: None,
            labels: Vec::new(),
            badges: Vec::new(),
        }
    }
}

impl Canvas {
    /// The pan and zoom.
    pub(crate) fn view(&self) -> &CanvasView {
        &self.view
    }

    /// Fits the drawing at the next frame.
    pub(crate) fn request_fit(&mut self) {
        self.view.request_fit();
    }

    /// The tool, to show or pick.
    pub(crate) fn tool_mut(&mut self) -> &mut Tool {
        &mut self.tool
    }

    /// Drops the stroke being drawn; whether there was one.
    pub(crate) fn cancel_stroke(&mut self) -> bool {
        self.drawing.take().is_some()
    }

    /// Remembers where a drop was released, for a note if it fails.
    pub(crate) fn dropped(&mut self, at: DVec2) {
        self.dropped_at = Some(at);
        self.drop_note = None;
    }

    /// The drop's job ended: when it placed nothing, `failure` says why, shown at the
    /// drop point for a few seconds.
    pub(crate) fn drop_ended(&mut self, failure: Option<String>) {
        let Some(at) = self.dropped_at.take() else {
            return;
        };
        self.drop_note = failure.map(|text| DropNote {
            at,
            text,
            until: Instant::now() + DROP_NOTE_FOR,
        });
    }

    /// The screen rectangles of the labels painted in the last frame (part ids with
    /// their badges, then relation labels).
    pub(crate) fn labels(&self) -> &[Rect] {
        &self.labels
    }

    /// The verdict badges painted in the last frame: each part's and its colour.
    pub(crate) fn badges(&self) -> &[(crate::core::model::PrimitiveId, Color32)] {
        &self.badges
    }

    /// The note of a failed drop on the canvas, while it is shown.
    pub(crate) fn drop_note(&self) -> Option<&str> {
        self.drop_note
            .as_ref()
            .filter(|n| n.until > Instant::now())
            .map(|n| n.text.as_str())
    }

    /// Takes the strokes' classes found elsewhere (off the UI thread) for the strokes
    /// of `revision`.
    pub(crate) fn set_classes(&mut self, revision: u64, classes: Vec<(StrokeId, StrokeClass)>) {
        self.classes = Some((revision, classes));
    }

    /// The reference image.
    pub(crate) fn image(&self) -> &ReferenceImage {
        &self.image
    }

    /// The reference image, to change.
    pub(crate) fn image_mut(&mut self) -> &mut ReferenceImage {
        &mut self.image
    }
}

/// The reference image shown under the strokes: the editor names the file, this holds
/// its texture.
pub(crate) struct ReferenceImage {
    /// The file shown, its texture and its size in pixels.
    shown: Option<(PathBuf, egui::TextureHandle, [usize; 2])>,
    /// A file that could not be read (not tried again).
    failed: Option<PathBuf>,
    /// The opacity it is drawn with.
    opacity: f32,
}

impl std::fmt::Debug for ReferenceImage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ReferenceImage")
            .field(
                "shown",
                &self.shown.as_ref().map(|(path, _, size)| (path, size)),
            )
            .field("failed", &self.failed)
            .field("opacity", &self.opacity)
            .finish()
    }
}

impl Default for ReferenceImage {
    fn default() -> Self {
        Self {
            shown: None,
            failed: None,
            opacity: 0.5,
        }
    }
}

impl ReferenceImage {
    /// Whether an image is shown.
    pub(crate) fn is_shown(&self) -> bool {
        self.shown.is_some()
    }

    /// The texture shown, its size in pixels and its opacity.
    pub(crate) fn texture(&self) -> Option<(egui::TextureId, [usize; 2], f32)> {
        self.shown
            .as_ref()
            .map(|(_, texture, size)| (texture.id(), *size, self.opacity))
    }

    /// The opacity, to show or set.
    pub(crate) fn opacity_mut(&mut self) -> &mut f32 {
        &mut self.opacity
    }

    /// Shows `texture`, read from `path`.
    pub(crate) fn show(&mut self, path: PathBuf, texture: egui::TextureHandle) {
        let size = texture.size();
        self.shown = Some((path, texture, size));
    }

    /// Shows nothing; with `forget_failed`, a file that could not be read is tried again.
    pub(crate) fn clear(&mut self, forget_failed: bool) {
        self.shown = None;
        if forget_failed {
            self.failed = None;
        }
    }

    /// Shows the image at `wanted` (the editor's, after undo, redo or opening), once per
    /// change; why it cannot be shown, once.
    pub(crate) fn sync(&mut self, ctx: &egui::Context, wanted: Option<&PathBuf>) -> Option<String> {
        let shown = self.shown.as_ref().map(|(p, _, _)| p);
        if shown == wanted || (wanted.is_some() && wanted == self.failed.as_ref()) {
            return None;
        }
        self.shown = None;
        let path = wanted?.clone();
        match std::fs::read(&path)
            .map_err(anyhow::Error::from)
            .and_then(|bytes| super::files::load_texture(ctx, &path, &bytes))
        {
            Ok(texture) => {
                self.show(path, texture);
                None
            }
            Err(error) => {
                let warning = format!(
                    "The reference image {} could not be shown: {error:#}",
                    path.display()
                );
                // Not again every frame; the path stays in the work.
                self.failed = Some(path);
                Some(warning)
            }
        }
    }
}

/// The canvas's pan and zoom: the sketch point at the view's centre and the points per
/// sketch unit.
#[derive(Clone, Debug, PartialEq)]
pub struct CanvasView {
    /// The sketch point shown at the centre.
    pub center: DVec2,
    /// Screen points per sketch unit.
    pub zoom: f64,
    fit_pending: bool,
    rect: Rect,
}

impl Default for CanvasView {
    fn default() -> Self {
        Self {
            center: DVec2::ZERO,
            zoom: 1.0,
            fit_pending: true,
            rect: Rect::from_min_size(Pos2::ZERO, Vec2::splat(1.0)),
        }
    }
}

impl CanvasView {
    /// A view showing sketch point `center` at the middle of `rect`, `zoom` screen
    /// points per sketch unit.
    pub(crate) fn looking_at(center: DVec2, zoom: f64, rect: Rect) -> Self {
        Self {
            center,
            zoom,
            fit_pending: false,
            rect,
        }
    }

    /// Fits the drawing at the next frame.
    pub fn request_fit(&mut self) {
        self.fit_pending = true;
    }

    /// The screen point of a sketch point.
    pub fn to_screen(&self, p: DVec2) -> Pos2 {
        let c = self.rect.center();
        let d = (p - self.center) * self.zoom;
        Pos2::new(c.x + d.x as f32, c.y + d.y as f32)
    }

    /// A sketch polyline on screen, without the points that change it by less than a
    /// quarter pixel (Douglas–Peucker): a software rasterizer pays per triangle, and a
    /// finely resampled stroke seen zoomed out has many points to a pixel.
    pub fn screen_line(&self, points: &[DVec2]) -> Vec<Pos2> {
        let screen: Vec<Pos2> = points.iter().map(|p| self.to_screen(*p)).collect();
        simplify_polyline(&screen, SCREEN_TOLERANCE)
    }

    /// The sketch point of a screen point.
    pub fn to_sketch(&self, p: Pos2) -> DVec2 {
        let c = self.rect.center();
        self.center + DVec2::new(f64::from(p.x - c.x), f64::from(p.y - c.y)) / self.zoom
    }

    /// The canvas's rectangle on screen (as of the last frame).
    pub fn rect(&self) -> Rect {
        self.rect
    }

    fn fit(&mut self, lo: DVec2, hi: DVec2) {
        let size = (hi - lo).max(DVec2::splat(1e-6));
        let w = f64::from(self.rect.width()).max(1.0);
        let h = f64::from(self.rect.height()).max(1.0);
        self.center = (lo + hi) / 2.0;
        self.zoom = (w / size.x).min(h / size.y) * 0.9;
        self.fit_pending = false;
    }

    /// Zooms by `factor` keeping the sketch point under `anchor` in place.
    fn zoom_about(&mut self, anchor: Pos2, factor: f64) {
        let before = self.to_sketch(anchor);
        self.zoom = (self.zoom * factor).clamp(1e-4, 1e4);
        let after = self.to_sketch(anchor);
        self.center += before - after;
    }
}

/// How far (in pixels) a painted polyline may stray from the true one.
const SCREEN_TOLERANCE: f32 = 0.25;

/// The Douglas–Peucker simplification of a polyline: the points whose removal moves the
/// line by at most `tolerance` are dropped; the ends are always kept.
pub(crate) fn simplify_polyline(points: &[Pos2], tolerance: f32) -> Vec<Pos2> {
    if points.len() < 3 {
        return points.to_vec();
    }
    let mut keep = vec![false; points.len()];
    keep[0] = true;
    keep[points.len() - 1] = true;
    let mut spans = vec![(0, points.len() - 1)];
    while let Some((i, j)) = spans.pop() {
        let (a, b) = (points[i], points[j]);
        let ab = b - a;
        let len2 = ab.length_sq();
        let mut worst = (0.0_f32, i);
        for (k, p) in points.iter().enumerate().take(j).skip(i + 1) {
            let ap = *p - a;
            let d2 = if len2 > 0.0 {
                let t = (ap.dot(ab) / len2).clamp(0.0, 1.0);
                (ap - ab * t).length_sq()
            } else {
                ap.length_sq()
            };
            if d2 > worst.0 {
                worst = (d2, k);
            }
        }
        if worst.0 > tolerance * tolerance {
            keep[worst.1] = true;
            spans.push((i, worst.1));
            spans.push((worst.1, j));
        }
    }
    points
        .iter()
        .zip(keep)
        .filter_map(|(p, k)| k.then_some(*p))
        .collect()
}

/// Light smoothing and even resampling of a drawn stroke (spacing in sketch units).
pub(crate) fn smooth_and_resample(points: &[DVec2], spacing: f64) -> Vec<DVec2> {
    if points.len() < 3 || !(spacing > 0.0) {
        return points.to_vec();
    }
    let mut smooth = points.to_vec();
    for _ in 0..2 {
        let prev = smooth.clone();
        for i in 1..prev.len() - 1 {
            smooth[i] = prev[i - 1] * 0.25 + prev[i] * 0.5 + prev[i + 1] * 0.25;
        }
    }
    let mut out = vec![smooth[0]];
    let mut carry = 0.0;
    for w in smooth.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = a.distance(b);
        let mut t = spacing - carry;
        while t <= len {
            out.push(a.lerp(b, t / len));
            t += spacing;
        }
        carry = (carry + len) % spacing;
    }
    let last = *smooth.last().expect("three points or more");
    if out
        .last()
        .is_some_and(|p| p.distance(last) > spacing * 0.25)
    {
        out.push(last);
    }
    out
}

/// Distance from `p` to a polyline.
fn distance_to_polyline(p: DVec2, points: &[DVec2]) -> f64 {
    match points {
        [] => f64::INFINITY,
        [only] => p.distance(*only),
        _ => points
            .windows(2)
            .map(|w| {
                let (a, b) = (w[0], w[1]);
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared().max(1e-18)).clamp(0.0, 1.0);
                p.distance(a + ab * t)
            })
            .fold(f64::INFINITY, f64::min),
    }
}

/// The view-plane outline points of a primitive, in sketch space.
fn outlines(primitive: &Primitive) -> Vec<(bool, Vec<DVec2>)> {
    primitive
        .current_shape()
        .curves
        .into_iter()
        .map(|c| {
            (
                c.visible,
                c.curve
                    .points(48)
                    .into_iter()
                    .map(|p| DVec2::new(p.x, -p.y))
                    .collect(),
            )
        })
        .collect()
}

impl GeosnapApp {
    fn stroke_classes(&mut self) -> &[(StrokeId, StrokeClass)] {
        let revision = self.editor.strokes_revision();
        let stale = self
            .canvas
            .classes
            .as_ref()
            .is_none_or(|(r, _)| *r != revision);
        if stale {
            let classes = classify_sketch(self.editor.sketch(), &ClassifyOptions::default())
                .into_iter()
                .map(|c| (c.id, c.class))
                .collect();
            self.canvas.classes = Some((revision, classes));
        }
        self.canvas
            .classes
            .as_ref()
            .map(|(_, c)| c.as_slice())
            .unwrap_or_default()
    }

    /// The stroke nearest to a sketch point within `reach` sketch units.
    fn stroke_at(&self, p: DVec2, reach: f64) -> Option<StrokeId> {
        self.editor
            .sketch()
            .strokes
            .iter()
            .map(|s| (s.id, distance_to_polyline(p, &s.points)))
            .filter(|(_, d)| *d <= reach)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(id, _)| id)
    }

    /// The part whose outline (or inside of its outline's bounds) is nearest to `p`.
    fn part_at(&self, p: DVec2, reach: f64) -> Option<crate::core::model::PrimitiveId> {
        self.editor
            .document()
            .primitives()
            .filter(|(id, _)| !self.hidden.contains(id))
            .filter_map(|(id, placed)| {
                let lines = outlines(&placed.primitive);
                let d = lines
                    .iter()
                    .map(|(_, pts)| distance_to_polyline(p, pts))
                    .fold(f64::INFINITY, f64::min);
                let (lo, hi) = lines.iter().flat_map(|(_, pts)| pts.iter()).fold(
                    (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                    |(lo, hi), q| (lo.min(*q), hi.max(*q)),
                );
                let inside = p.cmpge(lo).all() && p.cmple(hi).all();
                let score = if inside { d.min(reach) * 0.5 } else { d };
                (score <= reach).then_some((id, score))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(id, _)| id)
    }

    pub(crate) fn canvas_ui(&mut self, ui: &mut Ui) {
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
        self.canvas.view.rect = rect;
        if self.canvas.view.fit_pending {
            // The drawing's strokes; without strokes the image, else the page.
            let bounds = self.editor.sketch().bounds().or_else(|| {
                self.canvas
                    .image
                    .shown
                    .as_ref()
                    .map(|(_, _, [w, h])| (DVec2::ZERO, DVec2::new(*w as f64, *h as f64)))
                    .or_else(|| self.editor.sketch().view_box.map(|(o, s)| (o, o + s)))
            });
            match bounds {
                Some((lo, hi)) => self.canvas.view.fit(lo, hi),
                None => self.canvas.view.fit(DVec2::ZERO, DVec2::new(1000.0, 800.0)),
            }
        }
        // The canvas's paper is the window's clear colour (see `App::clear_color`): a
        // software rasterizer then has one full-size fill less to shade each frame.
        let painter = ui.painter_at(rect);
        let pointer = ui.input(|i| i.pointer.hover_pos());
        let over = pointer.filter(|p| rect.contains(*p));

        // Pan and zoom (not while a primitive is dragged: the wheel sizes it then).
        let space = ui.input(|i| i.key_down(egui::Key::Space));
        if response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
            || (space && response.dragged_by(egui::PointerButton::Primary))
        {
            let d = response.drag_delta();
            self.canvas.view.center -=
                DVec2::new(f64::from(d.x), f64::from(d.y)) / self.canvas.view.zoom;
        }
        if self.drag.is_none() {
            if let Some(at) = over {
                let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
                let factor = f64::from(zoom) * (f64::from(scroll) * 0.002).exp();
                if (factor - 1.0).abs() > 1e-6 {
                    self.canvas.view.zoom_about(at, factor);
                }
            }
        }

        self.paint_image(&painter);
        self.paint_parts(&painter);
        self.paint_strokes(&painter);
        self.paint_part_ids(&painter);
        self.paint_relations(&painter);
        self.canvas_drag(ui, over);
        if !space {
            self.canvas_tools(ui, &response, over);
        }
        self.paint_drag(&painter);
        if let Some(points) = &self.canvas.drawing {
            let line = self.canvas.view.screen_line(points);
            painter.add(egui::Shape::line(line, Pen::new(2.0, SILHOUETTE)));
        }
        if self.editor.sketch().strokes.is_empty() && self.canvas.image.shown.is_none() {
            painter.text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                "Open a drawing (Ctrl+O, or drop a file here), or draw strokes with the pen tool (B)",
                egui::FontId::proportional(15.0),
                Color32::from_gray(120),
            );
        }
        painter.text(
            rect.left_top() + Vec2::new(8.0, 6.0),
            egui::Align2::LEFT_TOP,
            self.canvas_hint(),
            egui::FontId::proportional(13.0),
            Color32::from_gray(90),
        );
        self.paint_drag_legend(&painter, rect);
        self.show_drop_note(ui, rect);
        self.first_run_hint(ui, rect);
        self.show_loading(ui, rect);
    }

    /// While a file is being opened: what is being done, in the middle of the canvas.
    fn show_loading(&mut self, ui: &Ui, rect: Rect) {
        let Some(text) = self.loading() else {
            return;
        };
        let mut cancel = false;
        egui::Area::new(egui::Id::unique("loading"))
            .order(egui::Order::Foreground)
            .pivot(egui::Align2::CENTER_CENTER)
            .fixed_pos(rect.center())
            .show(ui.ctx(), |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.horizontal(|ui| {
                        ui.spinner();
                        ui.label(egui::RichText::new(text).strong());
                    });
                    ui.label("The window stays usable; the drawing shows when it is ready.");
                    cancel = ui.button("Cancel opening").clicked();
                });
            });
        if cancel {
            self.cancel_loading();
        }
    }

    /// The note of a failed drop, at the drop point, until it times out.
    fn show_drop_note(&mut self, ui: &Ui, rect: Rect) {
        let Some(note) = &self.canvas.drop_note else {
            return;
        };
        let left = note.until.saturating_duration_since(Instant::now());
        if left.is_zero() {
            self.canvas.drop_note = None;
            return;
        }
        ui.ctx().request_repaint_after(left);
        let at = self.canvas.view.to_screen(note.at);
        let width = 300.0;
        // Beside the drop point, on the side with room for it.
        let (pivot, pos) = if at.x + 12.0 + width <= rect.right() {
            (egui::Align2::LEFT_TOP, at + Vec2::new(12.0, 12.0))
        } else {
            (egui::Align2::RIGHT_TOP, at + Vec2::new(-12.0, 12.0))
        };
        let text = note.text.clone();
        egui::Area::new(egui::Id::unique("drop_note"))
            .order(egui::Order::Foreground)
            .pivot(pivot)
            .fixed_pos(pos)
            .constrain_to(rect)
            .interactable(false)
            .show(ui.ctx(), |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.set_max_width(width);
                    ui.label(
                        egui::RichText::new(text)
                            .color(Color32::from_rgb(190, 70, 10))
                            .strong(),
                    );
                });
            });
        if rect.contains(at) {
            painter_mark(ui, at, rect);
        }
    }

    /// The hint in the canvas's upper left corner: what the drag in progress does, or
    /// what the tool does.
    pub fn canvas_hint(&self) -> String {
        if let Some(drag) = &self.drag {
            let noun = words::kind_noun(drag.kind());
            let what = match drag.replacing {
                Some(id) => format!(
                    "Moving {}: release on its strokes to snap it there",
                    words::part_name(self.editor.document(), id)
                ),
                None => format!("Placing a {noun}: release on its strokes to place it"),
            };
            return match drag.pose() {
                (k, n) if n > 1 => format!("{what}; Tab: next pose ({k} of {n})"),
                _ => format!("{what}; Tab: next pose"),
            };
        }
        match self.canvas.tool {
            Tool::Select => "Select: click a part; drag it to move and re-snap",
            Tool::Draw => "Draw: drag to draw a stroke",
            Tool::Erase => "Erase: click or drag over strokes",
            Tool::Reclassify => "Reclassify: click a stroke to switch end / outline",
        }
        .to_owned()
    }

    fn paint_image(&self, painter: &egui::Painter) {
        let Some((_, texture, [w, h])) = &self.canvas.image.shown else {
            return;
        };
        let lo = self.canvas.view.to_screen(DVec2::ZERO);
        let hi = self.canvas.view.to_screen(DVec2::new(*w as f64, *h as f64));
        let alpha = (self.canvas.image.opacity.clamp(0.0, 1.0) * 255.0) as u8;
        painter.image(
            texture.id(),
            Rect::from_min_max(lo, hi),
            Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)),
            Color32::from_white_alpha(alpha),
        );
    }

    fn paint_strokes(&mut self, painter: &egui::Painter) {
        let classes: std::collections::HashMap<StrokeId, StrokeClass> =
            self.stroke_classes().iter().copied().collect();
        // The selected part's strokes, by the curve that took them.
        let mut assigned: std::collections::HashMap<StrokeId, usize> =
            std::collections::HashMap::new();
        if let Some(id) = self.selection {
            if let Some(record) = self.editor.document().snap_record(id) {
                for (k, strokes) in record.assignment.curves.iter().enumerate() {
                    for s in strokes {
                        assigned.insert(s.stroke, k);
                    }
                }
            } else if let Some(placed) = self.editor.document().get(id) {
                for s in &placed.fit.strokes {
                    assigned.insert(*s, 0);
                }
            }
        }
        for stroke in &self.editor.sketch().strokes {
            let points = self.canvas.view.screen_line(&stroke.points);
            let class = classes
                .get(&stroke.id)
                .copied()
                .unwrap_or(StrokeClass::Silhouette);
            let (width, color) = match assigned.get(&stroke.id) {
                Some(k) => (3.5, part_color(*k + 3)),
                None if class == StrokeClass::Feature => (1.6, FEATURE),
                None => (1.6, SILHOUETTE),
            };
            let shape = if stroke.closed {
                egui::Shape::closed_line(points, Pen::new(width, color))
            } else {
                egui::Shape::line(points, Pen::new(width, color))
            };
            painter.add(shape);
        }
    }

    fn paint_parts(&self, painter: &egui::Painter) {
        let related = self.emphasis().related;
        for (index, (id, placed)) in self.editor.document().primitives().enumerate() {
            if self.drag.as_ref().is_some_and(|d| d.replacing == Some(id))
                || self.hidden.contains(&id)
            {
                continue;
            }
            let selected = self.selection == Some(id);
            let highlighted = related.contains(&id);
            let color = if highlighted {
                Color32::from_rgb(235, 170, 0)
            } else {
                part_color(index)
            };
            let width = if selected || highlighted { 5.0 } else { 3.5 };
            let color = color.gamma_multiply(if selected || highlighted { 0.8 } else { 0.55 });
            for (visible, points) in outlines(&placed.primitive) {
                let line = self.canvas.view.screen_line(&points);
                let pen = if visible {
                    Pen::new(width, color)
                } else {
                    Pen::new(1.0, color.gamma_multiply(0.4))
                };
                painter.add(egui::Shape::line(line, pen));
            }
        }
    }

    /// The parts' names (or ids) at their centres, over the strokes, each with a halo of paper so
    /// it reads over a stroke of its own colour, and the snap's verdict as a badge;
    /// their rectangles are taken for the relation labels to avoid.
    fn paint_part_ids(&mut self, painter: &egui::Painter) {
        self.canvas.labels.clear();
        self.canvas.badges.clear();
        let related = self.emphasis().related;
        for (index, (id, placed)) in self.editor.document().primitives().enumerate() {
            if self.drag.as_ref().is_some_and(|d| d.replacing == Some(id))
                || self.hidden.contains(&id)
            {
                continue;
            }
            let selected = self.selection == Some(id);
            let color = if related.contains(&id) {
                Color32::from_rgb(200, 140, 0)
            } else {
                part_color(index)
            };
            // Darker than the part's outline, so the id stands out on it.
            let [r, g, b, _] = color.to_array();
            let color = Color32::from_rgb(r / 10 * 6, g / 10 * 6, b / 10 * 6);
            let c = placed.primitive.center();
            let at = self.canvas.view.to_screen(DVec2::new(c.x, -c.y));
            let font = egui::FontId::proportional(if selected { 16.0 } else { 14.0 });
            // The name given to it, shortened, else its number.
            let label = self.editor.document().name(id).map_or_else(
                || format!("#{}", id.0),
                |name| words::shortened(name, MAX_LABEL_CHARS),
            );
            let galley = painter.layout_no_wrap(label, font, color);
            let rect = egui::Align2::CENTER_CENTER.anchor_size(at, galley.size());
            halo_text(painter, rect.min, &galley, color);
            // The snap's verdict as a badge before the id: green good, amber doubtful.
            let mut taken = rect;
            if let Some(verdict) = placed.fit.verdict {
                let centre = Pos2::new(rect.left() - 7.0, rect.center().y);
                painter.circle(
                    centre,
                    4.5,
                    verdict_color(verdict),
                    Pen::new(1.5, PAPER_HALO),
                );
                self.canvas.badges.push((id, verdict_color(verdict)));
                taken = taken.union(Rect::from_center_size(centre, Vec2::splat(9.0)));
            }
            if placed.fit.strokes.is_empty() {
                // Not snapped: placed freely (a drop off the strokes, Alt + drop, a copy).
                let note = painter.layout_no_wrap(
                    "placed freely".to_owned(),
                    egui::FontId::proportional(12.5),
                    Color32::from_gray(90),
                );
                let below = egui::Align2::CENTER_TOP
                    .anchor_size(Pos2::new(rect.center().x, rect.bottom() + 1.0), note.size());
                halo_text(painter, below.min, &note, Color32::from_gray(90));
                taken = taken.union(below);
            }
            self.canvas.labels.push(taken);
        }
    }

    /// The relations of the selected part (or the hovered one): a dashed link between
    /// the members' centres, labelled with the kind.
    fn paint_relations(&mut self, painter: &egui::Painter) {
        let document = self.editor.document();
        for (id, relation) in document.relations_with_ids() {
            let shown = self.hovered_relation == Some(id)
                || self
                    .selection
                    .is_some_and(|id| relation.members.contains(&id));
            if !shown {
                continue;
            }
            let centres: Vec<Pos2> = relation
                .members
                .iter()
                .filter_map(|id| document.get(*id))
                .map(|p| {
                    let c = p.primitive.center();
                    self.canvas.view.to_screen(DVec2::new(c.x, -c.y))
                })
                .collect();
            if centres.is_empty() {
                continue;
            }
            let color = match relation.mode {
                crate::core::relation::Mode::Hard => Color32::from_rgb(90, 90, 100),
                crate::core::relation::Mode::Soft => Color32::from_rgb(150, 150, 160),
                crate::core::relation::Mode::Off => Color32::from_rgb(220, 140, 140),
                crate::core::relation::Mode::Suggested => Color32::from_rgb(80, 130, 210),
            };
            for pair in centres.windows(2) {
                painter.add(egui::Shape::dashed_line(
                    &[pair[0], pair[1]],
                    Pen::new(1.0, color),
                    5.0,
                    4.0,
                ));
            }
            let n = centres.len() as f32;
            let mid = centres.iter().fold(Vec2::ZERO, |acc, p| acc + p.to_vec2()) / n;
            let galley = painter.layout_no_wrap(
                words::relation_kind_name(relation.kind),
                egui::FontId::proportional(13.0),
                color,
            );
            // The first free spot around the link's middle: off the part ids and the
            // labels placed before it.
            let rect = free_spot(mid.to_pos2(), galley.size(), &self.canvas.labels);
            halo_text(painter, rect.min, &galley, color);
            self.canvas.labels.push(rect);
        }
    }

    fn paint_drag(&self, painter: &egui::Painter) {
        let Some(drag) = &self.drag else { return };
        if !drag.over_canvas {
            return;
        }
        // The primitive as dropped, faint; the snapped preview and its strokes, bold.
        if let Some(dragged) = self.dragged_primitive() {
            for (visible, points) in outlines(&dragged) {
                if visible {
                    let line = self.canvas.view.screen_line(&points);
                    painter.add(egui::Shape::dashed_line(
                        &line,
                        Pen::new(1.2, Color32::from_gray(140)),
                        6.0,
                        4.0,
                    ));
                }
            }
        }
        if let Some(preview) = drag.preview() {
            for id in preview.assignment.stroke_ids() {
                if let Some(stroke) = self.editor.sketch().stroke(id) {
                    let line = self.canvas.view.screen_line(&stroke.points);
                    painter.add(egui::Shape::line(
                        line,
                        Pen::new(5.0, PREVIEW.gamma_multiply(0.35)),
                    ));
                }
            }
            for (visible, points) in outlines(&preview.primitive) {
                if visible {
                    let line = self.canvas.view.screen_line(&points);
                    painter.add(egui::Shape::line(line, Pen::new(2.5, PREVIEW)));
                }
            }
        }
        let title = words::kind_title(drag.kind);
        let label = match (drag.preview(), drag.preview_error()) {
            (Some(p), _) => format!(
                "{title}: {} strokes, {} off on average",
                p.assignment.stroke_ids().len(),
                words::length(p.rms, self.unit())
            ),
            (None, Some(e)) => format!("{title}: {}", words::snap_error(e, self.status.developer)),
            (None, None) => format!("{title}…"),
        };
        let at = self.canvas.view.to_screen(drag.placement.at) + Vec2::new(14.0, 14.0);
        painter.text(
            at,
            egui::Align2::LEFT_TOP,
            label,
            egui::FontId::proportional(13.0),
            Color32::from_gray(60),
        );
    }

    /// A primitive being dragged follows the cursor; the wheel sizes it, Shift + wheel
    /// turns its axis; releasing the button drops it.
    fn canvas_drag(&mut self, ui: &Ui, over: Option<Pos2>) {
        if self.drag.is_none() {
            return;
        }
        let (pointer, released, scroll, shift, alt) = ui.input(|i| {
            (
                i.pointer.latest_pos(),
                i.pointer.any_released(),
                i.smooth_scroll_delta.y + i.smooth_scroll_delta.x,
                i.modifiers.shift,
                i.modifiers.alt,
            )
        });
        if let Some(p) = pointer {
            let at = self.canvas.view.to_sketch(p);
            self.drag_to(at, over.is_some());
        }
        if scroll.abs() > 0.0 {
            if shift {
                self.adjust_drag(1.0, f64::from(scroll) * 0.004);
            } else {
                self.adjust_drag((f64::from(scroll) * 0.002).exp(), 0.0);
            }
        }
        if released && alt {
            self.end_drag_freely();
        } else if released {
            self.end_drag();
        }
    }

    fn canvas_tools(&mut self, ui: &Ui, response: &egui::Response, over: Option<Pos2>) {
        if self.drag.is_some() {
            return;
        }
        let reach = 8.0 / self.canvas.view.zoom;
        let primary = response.dragged_by(egui::PointerButton::Primary)
            || response.drag_started_by(egui::PointerButton::Primary);
        match self.canvas.tool {
            Tool::Select => {
                if response.clicked() {
                    self.selection = over
                        .map(|p| self.canvas.view.to_sketch(p))
                        .and_then(|p| self.part_at(p, reach));
                }
                if response.drag_started_by(egui::PointerButton::Primary) {
                    let start = ui.input(|i| i.pointer.press_origin()).or(over);
                    if let Some(p) = start.map(|p| self.canvas.view.to_sketch(p)) {
                        if let Some(id) = self.part_at(p, reach) {
                            self.selection = Some(id);
                            self.begin_redrag(id, p);
                        }
                    }
                }
            }
            Tool::Draw => {
                if primary {
                    if let Some(p) = ui.input(|i| i.pointer.latest_pos()) {
                        let at = self.canvas.view.to_sketch(p);
                        let points = self.canvas.drawing.get_or_insert_with(Vec::new);
                        if points
                            .last()
                            .is_none_or(|q| q.distance(at) * self.canvas.view.zoom > 1.5)
                        {
                            points.push(at);
                        }
                    }
                }
                if response.drag_stopped() {
                    if let Some(points) = self.canvas.drawing.take() {
                        let spacing = 3.0 / self.canvas.view.zoom;
                        let resampled = smooth_and_resample(&points, spacing);
                        if self.editor.add_stroke(resampled).is_none() {
                            self.say("The stroke was too short to keep.");
                        }
                    }
                }
            }
            Tool::Erase => {
                if primary || response.clicked() {
                    if let Some(p) = over.map(|p| self.canvas.view.to_sketch(p)) {
                        if let Some(id) = self.stroke_at(p, reach) {
                            self.editor.erase_stroke(id);
                        }
                    }
                }
            }
            Tool::Reclassify => {
                if response.clicked() {
                    if let Some(p) = over.map(|p| self.canvas.view.to_sketch(p)) {
                        if let Some(id) = self.stroke_at(p, reach) {
                            let current = self
                                .stroke_classes()
                                .iter()
                                .find(|(s, _)| *s == id)
                                .map_or(StrokeClass::Silhouette, |(_, c)| *c);
                            let next = match current {
                                StrokeClass::Feature => StrokeClass::Silhouette,
                                StrokeClass::Silhouette => StrokeClass::Feature,
                            };
                            self.editor.reclassify(id, Some(next));
                        }
                    }
                }
            }
        }
    }
}

/// The paper-coloured halo around canvas text.
const PAPER_HALO: Color32 = Color32::from_rgb(250, 250, 249);

/// Text with a halo of paper around it, so it reads over strokes of any colour.
fn halo_text(
    painter: &egui::Painter,
    at: Pos2,
    galley: &std::sync::Arc<egui::Galley>,
    color: Color32,
) {
    for (dx, dy) in [
        (-1.5, 0.0),
        (1.5, 0.0),
        (0.0, -1.5),
        (0.0, 1.5),
        (-1.0, -1.0),
        (1.0, -1.0),
        (-1.0, 1.0),
        (1.0, 1.0),
    ] {
        painter.galley_with_override_text_color(at + Vec2::new(dx, dy), galley.clone(), PAPER_HALO);
    }
    painter.galley(at, galley.clone(), color);
}

/// Where a label of `size` goes near `anchor`: the first of a ring of spots around it
/// (centred, then above and below, then beside, then further out) whose rectangle,
/// with a little margin, meets none of `taken`; the anchor itself when all are taken.
pub(crate) fn free_spot(anchor: Pos2, size: Vec2, taken: &[Rect]) -> Rect {
    let (w, h) = (size.x + 6.0, size.y + 2.0);
    let mut offsets = vec![Vec2::ZERO];
    for ring in 1..=4 {
        let r = ring as f32;
        offsets.extend([
            Vec2::new(0.0, -h * r),
            Vec2::new(0.0, h * r),
            Vec2::new(w * r * 0.75, 0.0),
            Vec2::new(-w * r * 0.75, 0.0),
            Vec2::new(w * r * 0.75, -h * r),
            Vec2::new(-w * r * 0.75, -h * r),
            Vec2::new(w * r * 0.75, h * r),
            Vec2::new(-w * r * 0.75, h * r),
        ]);
    }
    let at = |offset: Vec2| egui::Align2::CENTER_CENTER.anchor_size(anchor + offset, size);
    offsets
        .into_iter()
        .map(at)
        .find(|rect| !taken.iter().any(|t| t.expand(1.0).intersects(*rect)))
        .unwrap_or_else(|| at(Vec2::ZERO))
}

/// A small cross at a failed drop's point.
fn painter_mark(ui: &Ui, at: Pos2, canvas: Rect) {
    let painter = ui
        .ctx()
        .layer_painter(egui::LayerId::new(
            egui::Order::Foreground,
            egui::Id::unique("drop_mark"),
        ))
        .with_clip_rect(canvas);
    let pen = Pen::new(2.0, Color32::from_rgb(190, 70, 10));
    let d = 5.0;
    painter.line_segment([at + Vec2::new(-d, -d), at + Vec2::new(d, d)], pen);
    painter.line_segment([at + Vec2::new(-d, d), at + Vec2::new(d, -d)], pen);
}

/// The colour of a snap's verdict: green for good, amber for doubtful, red for refused.
pub fn verdict_color(verdict: Verdict) -> Color32 {
    match verdict {
        Verdict::Good => Color32::from_rgb(60, 170, 80),
        Verdict::Doubtful => Color32::from_rgb(235, 160, 20),
        Verdict::Refused => Color32::from_rgb(210, 60, 50),
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::{distance_to_polyline, simplify_polyline, smooth_and_resample, CanvasView};

    #[test]
    fn simplified_lines_keep_their_ends_and_shape_within_the_tolerance() {
        use egui::Pos2;
        // A finely sampled arc (radius 200 px, 2000 points) and a straight run.
        let arc: Vec<Pos2> = (0..2000)
            .map(|i| {
                let t = i as f32 / 1999.0 * std::f32::consts::PI;
                Pos2::new(200.0 * t.cos(), 200.0 * t.sin())
            })
            .collect();
        let simple = simplify_polyline(&arc, 0.25);
        assert_eq!(simple.first(), arc.first());
        assert_eq!(simple.last(), arc.last());
        assert!(simple.len() < 120, "{} points kept", simple.len());
        // Every dropped point lies within the tolerance of the simplified line.
        for p in &arc {
            let d = simple
                .windows(2)
                .map(|w| {
                    let (a, b) = (w[0], w[1]);
                    let ab = b - a;
                    let t = ((*p - a).dot(ab) / ab.length_sq()).clamp(0.0, 1.0);
                    (*p - (a + ab * t)).length()
                })
                .fold(f32::INFINITY, f32::min);
            assert!(d <= 0.25 + 1e-3, "a point strays {d} px");
        }
        let straight: Vec<Pos2> = (0..50).map(|i| Pos2::new(i as f32, 2.0)).collect();
        assert_eq!(simplify_polyline(&straight, 0.25).len(), 2);
        assert_eq!(simplify_polyline(&straight[..2], 0.25).len(), 2);
        assert!(simplify_polyline(&[], 0.25).is_empty());
    }

    #[test]
    fn labels_take_the_first_free_spot_around_their_anchor() {
        use egui::{pos2, vec2, Rect};

        use super::free_spot;

        let size = vec2(60.0, 14.0);
        let anchor = pos2(100.0, 100.0);
        let free = free_spot(anchor, size, &[]);
        assert_eq!(free.center(), anchor, "centred when nothing is in the way");
        let mut taken = vec![Rect::from_center_size(anchor, vec2(20.0, 14.0))];
        for _ in 0..6 {
            let rect = free_spot(anchor, size, &taken);
            assert!(
                !taken.iter().any(|t| t.intersects(rect)),
                "{rect:?} meets {taken:?}"
            );
            assert!(rect.center().distance(anchor) < 200.0, "near its anchor");
            taken.push(rect);
        }
    }

    #[test]
    fn screen_and_sketch_points_map_back_and_forth() {
        let mut view = CanvasView {
            rect: egui::Rect::from_min_size(egui::pos2(100.0, 50.0), egui::vec2(800.0, 600.0)),
            ..CanvasView::default()
        };
        view.fit(DVec2::new(0.0, 0.0), DVec2::new(400.0, 300.0));
        let p = DVec2::new(123.0, 45.0);
        assert!(view.to_sketch(view.to_screen(p)).distance(p) < 1e-3);
        let corner = view.to_screen(DVec2::new(400.0, 300.0));
        assert!(view.rect().contains(corner), "fit shows the whole drawing");
        let anchor = egui::pos2(300.0, 200.0);
        let under = view.to_sketch(anchor);
        view.zoom_about(anchor, 2.5);
        assert!(
            view.to_sketch(anchor).distance(under) < 1e-9,
            "zoom keeps the anchor"
        );
    }

    #[test]
    fn drawn_strokes_are_resampled_evenly_and_keep_their_ends() {
        let raw: Vec<DVec2> = (0..50)
            .map(|i| DVec2::new(f64::from(i) * 0.7, if i % 2 == 0 { 0.2 } else { -0.2 }))
            .collect();
        let out = smooth_and_resample(&raw, 2.0);
        assert_eq!(out[0], raw[0]);
        assert!(out.last().expect("points").distance(raw[49]) < 0.6);
        for w in out.windows(2).take(out.len() - 2) {
            assert!((w[0].distance(w[1]) - 2.0).abs() < 0.3, "{w:?}");
        }
        let jitter = out[2..out.len() - 2]
            .iter()
            .map(|p| p.y.abs())
            .fold(0.0, f64::max);
        assert!(jitter < 0.15, "smoothing damps the zig-zag: {jitter}");
        assert!((distance_to_polyline(DVec2::new(5.0, 3.0), &out) - 3.0).abs() < 0.2);
    }
}
