//! The 3D view panel. It opens on the view from the drawing: the drawing's own camera
//! (orthographic along −z, see `core::geom::projection`), with the strokes and the
//! reference image behind the model, framed as the canvas frames them, so each part can
//! be checked against what was drawn; 0 (or Home) comes back to it. Orbit (left drag,
//! kept above the horizon so the camera does not go under the grid) leaves it for a
//! perspective view; pan (right or middle drag, or Shift + left), zoom (wheel), fit
//! (F or double-click), the standard views (front, top, side, isometric: see
//! [`Standard`]) and an axis gizmo in the lower left corner. Drawn by [`crate::render::Viewport3d`] on the
//! GPU, or, without a wgpu device (the glow renderer, UI tests), painted in software:
//! flat-shaded triangles sorted back to front.

use egui::{Color32, Pos2, Rect, Sense, Ui};
use glam::{DVec2, Vec3};

use super::canvas::CanvasView;
use crate::core::model::{Document, PrimitiveId};
use crate::core::primitive::Primitive;
use crate::core::sketch::Stroke;
use crate::render::{OrbitCamera, Scene, Viewport3d};

/// Segments around circles in the 3D view.
const VIEW_SEGMENTS: usize = 32;

/// The colour of part `index` (shared by the canvas outlines and the 3D view).
pub(crate) fn part_color(index: usize) -> Color32 {
    const PALETTE: [Color32; 8] = [
        Color32::from_rgb(66, 133, 200),
        Color32::from_rgb(230, 126, 34),
        Color32::from_rgb(46, 160, 90),
        Color32::from_rgb(190, 70, 160),
        Color32::from_rgb(200, 60, 60),
        Color32::from_rgb(120, 100, 200),
        Color32::from_rgb(160, 140, 40),
        Color32::from_rgb(40, 160, 170),
    ];
    PALETTE[index % PALETTE.len()]
}

fn linear(color: Color32, alpha: f32) -> [f32; 4] {
    let rgba = egui::Rgba::from(color);
    [rgba.r(), rgba.g(), rgba.b(), alpha]
}

/// What to emphasise in the 3D view.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Emphasis {
    /// The selected part.
    pub selected: Option<PrimitiveId>,
    /// Members of the hovered relation.
    pub related: Vec<PrimitiveId>,
    /// Parts hidden in the outliner.
    pub hidden: Vec<PrimitiveId>,
}

/// What the view from the drawing shows behind the model: the strokes and the
/// reference image, where the canvas shows them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Backdrop<'a> {
    /// The strokes (sketch space).
    pub strokes: &'a [Stroke],
    /// The reference image: its texture, its size in pixels (it spans the sketch from
    /// the origin to that size) and the opacity it is drawn with.
    pub image: Option<(egui::TextureId, [usize; 2], f32)>,
}

impl Backdrop<'_> {
    /// The sketch-space box of the strokes and the image.
    fn bounds(&self) -> Option<(DVec2, DVec2)> {
        let points = self.strokes.iter().flat_map(|s| s.points.iter().copied());
        let image = self
            .image
            .into_iter()
            .flat_map(|(_, [w, h], _)| [DVec2::ZERO, DVec2::new(w as f64, h as f64)]);
        points.chain(image).fold(None, |acc, p| {
            Some(acc.map_or((p, p), |(lo, hi): (DVec2, DVec2)| (lo.min(p), hi.max(p))))
        })
    }
}

/// The 3D view's state.
#[derive(Debug)]
pub(crate) struct View3d {
    pub camera: OrbitCamera,
    /// Whether the view is the one from the drawing (the default).
    drawing: bool,
    /// The box of the strokes and the image, as model-space x and y (z = 0).
    drawn: Option<(Vec3, Vec3)>,
    /// Width over height of the view, as of the last frame.
    aspect: f32,
    gpu: Option<Viewport3d>,
    model: Scene,
    model_key: Option<(u64, Emphasis, bool)>,
    generation: u64,
    fitted: bool,
    /// Whether the user moved the camera (then it stops following the model).
    moved: bool,
    /// The drag preview shown, and when it was last changed: during a drag the 3D
    /// preview follows at most every [`PREVIEW_EVERY`], as each new one costs a render.
    overlay: (Scene, Option<std::time::Instant>),
    /// The box a fit frames: the model's bounds, or the grid's when the model is empty.
    frame: Option<(Vec3, Vec3)>,
    /// The model's bounds, without the grid.
    bounds: Option<(Vec3, Vec3)>,
}

impl Default for View3d {
    fn default() -> Self {
        Self {
            camera: drawing_camera(OrbitCamera::default()),
            drawing: true,
            drawn: None,
            aspect: 1.0,
            gpu: None,
            model: Scene::default(),
            model_key: None,
            generation: 0,
            fitted: false,
            moved: false,
            overlay: (Scene::default(), None),
            frame: None,
            bounds: None,
        }
    }
}

/// `camera` turned to the drawing's view: from the front, level, orthographic.
fn drawing_camera(camera: OrbitCamera) -> OrbitCamera {
    OrbitCamera {
        yaw: 0.0,
        pitch: 0.0,
        ortho: true,
        ..camera
    }
}

/// The standard views of the 3D view (View menu and keys 1–4, Home).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Standard {
    /// From the front (+Z), level: the direction the drawing is seen from.
    Front,
    /// From above.
    Top,
    /// From the right (+X), level.
    Side,
    /// Isometric: 45° around, 35.3° above.
    Isometric,
}

impl Standard {
    /// Yaw and pitch of the view, radians.
    fn angles(self) -> (f32, f32) {
        match self {
            Self::Front => (0.0, 0.0),
            Self::Top => (0.0, MAX_PITCH),
            Self::Side => (std::f32::consts::FRAC_PI_2, 0.0),
            Self::Isometric => (std::f32::consts::FRAC_PI_4, (1.0 / 2f32.sqrt()).atan()),
        }
    }
}

/// The lowest the orbit goes: level with the target, so the eye stays above the grid
/// (which lies under the model).
const MIN_PITCH: f32 = 0.0;
/// The highest: just short of straight down (the camera's up is +Y).
const MAX_PITCH: f32 = 1.55;

/// How often the 3D view takes a new drag preview.
const PREVIEW_EVERY: std::time::Duration = std::time::Duration::from_millis(150);

impl View3d {
    /// Frames the model at the next draw.
    pub(crate) fn request_fit(&mut self) {
        self.fitted = false;
        self.moved = false;
    }

    /// Turns the camera to a standard view (in perspective) and frames the model (or
    /// the grid, when the model is empty) at the next draw.
    pub(crate) fn standard(&mut self, view: Standard) {
        let (yaw, pitch) = view.angles();
        self.camera.yaw = yaw;
        self.camera.pitch = pitch;
        self.camera.ortho = false;
        self.drawing = false;
        self.request_fit();
    }

    /// Goes back to the view from the drawing, framing the drawing and the model at the
    /// next draw.
    pub(crate) fn drawing_view(&mut self) {
        self.camera = drawing_camera(self.camera);
        self.drawing = true;
        self.request_fit();
    }

    /// Whether the view is the one from the drawing.
    pub(crate) fn is_drawing_view(&self) -> bool {
        self.drawing
    }

    /// Frames the model now, or the grid when the model is empty; from the drawing, the
    /// drawing and the model together, as the canvas frames the drawing.
    fn fit_now(&mut self) {
        if self.drawing {
            let both = match (self.drawn, self.bounds) {
                (Some((a, b)), Some((c, d))) => Some((a.min(c), b.max(d))),
                (one, other) => one.or(other).or(self.frame),
            };
            if let Some((lo, hi)) = both {
                let size = hi - lo;
                let half = (size.y / 2.0).max(size.x / 2.0 / self.aspect.max(1e-3)) / 0.9;
                self.camera.target = (lo + hi) / 2.0;
                self.camera.distance =
                    (half.max(1e-3) / (self.camera.fov / 2.0).tan()).clamp(1e-2, 1e7);
                self.fitted = true;
            }
        } else if let Some((lo, hi)) = self.frame {
            self.camera.fit(lo, hi);
            self.fitted = true;
        }
    }

    fn rebuild(&mut self, document: &Document, revision: u64, emphasis: &Emphasis) {
        let key = (revision, emphasis.clone(), self.drawing);
        if self.model_key.as_ref() == Some(&key) {
            return;
        }
        let mut scene = Scene::default();
        for (index, (id, placed)) in document.primitives().enumerate() {
            if emphasis.hidden.contains(&id) {
                continue;
            }
            let mut color = part_color(index);
            if emphasis.selected == Some(id) {
                color = color.lerp_to_gamma(Color32::WHITE, 0.35);
            } else if emphasis.related.contains(&id) {
                color = Color32::from_rgb(250, 200, 40);
            }
            scene.add_mesh(&placed.primitive.mesh(VIEW_SEGMENTS), linear(color, 1.0));
        }
        self.bounds = scene.bounds();
        let (center, size, floor) = match self.bounds {
            Some((lo, hi)) => ((lo + hi) / 2.0, (hi - lo).max_element(), lo.y),
            None => (Vec3::ZERO, 500.0, 0.0),
        };
        // Not from the drawing: there the grid is edge-on, a line across the strokes.
        if !self.drawing {
            let step = nice_step(size / 8.0);
            scene.add_grid(
                Vec3::new(
                    (center.x / step).round() * step,
                    0.0,
                    (center.z / step).round() * step,
                ),
                floor,
                step,
                12,
            );
        }
        self.frame = Some(scene.bounds().unwrap_or_else(|| {
            let half = Vec3::new(size, 0.0, size) / 2.0;
            (center - half, center + half + Vec3::Y * size / 2.0)
        }));
        if !self.fitted || !self.moved {
            self.fit_now();
        }
        self.model = scene;
        self.model_key = Some(key);
        self.generation += 1;
    }

    /// Shows the view in `ui`'s remaining space.
    pub(crate) fn show(&mut self, ui: &mut Ui, frame: &eframe::Frame, content: &Content<'_>) {
        self.drawn = content.backdrop.bounds().map(|(lo, hi)| {
            // Sketch y runs down, model y up: (u, v) is drawn from (u, −v, z).
            let (a, b) = (
                Vec3::new(lo.x as f32, -hi.y as f32, 0.0),
                Vec3::new(hi.x as f32, -lo.y as f32, 0.0),
            );
            (a, b)
        });
        let size = ui.available_size();
        self.aspect = size.x.max(1.0) / size.y.max(1.0);
        self.rebuild(content.document, content.revision, content.emphasis);
        if !self.fitted {
            self.fit_now();
        }
        let (rect, response) = ui.allocate_exact_size(size, Sense::click_and_drag());
        let response = response.on_hover_text(
            "3D view: drag to orbit, right-drag or Shift+drag to pan, wheel to zoom, \
             double-click to fit; keys 1–4 front, top, side, isometric; 0 or Home: the \
             view from the drawing",
        );
        self.navigate(ui, &response, rect);
        self.take_preview(content.preview);
        let background = if ui.visuals().dark_mode {
            Color32::from_rgb(62, 66, 74)
        } else {
            Color32::from_rgb(226, 229, 234)
        };
        if self.drawing {
            // The backdrop under the model: the GPU's picture is then transparent where
            // the model is not.
            ui.painter().rect_filled(rect, 0.0, background);
            self.paint_backdrop(ui, rect, &content.backdrop);
        }
        let clear = if self.drawing {
            [0.0; 4]
        } else {
            linear(background, 1.0)
        };
        let overlay = &self.overlay.0;
        if let Some(render_state) = frame.wgpu_render_state() {
            let pixels_per_point = ui.ctx().pixels_per_point();
            let pixels = [
                (rect.width() * pixels_per_point).round().max(1.0) as u32,
                (rect.height() * pixels_per_point).round().max(1.0) as u32,
            ];
            let gpu = self
                .gpu
                .get_or_insert_with(|| Viewport3d::new(render_state));
            let texture = gpu.render(
                render_state,
                pixels,
                &self.camera,
                (self.generation, &self.model),
                overlay,
                clear,
            );
            ui.painter().image(
                texture,
                rect,
                Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)),
                Color32::WHITE,
            );
        } else {
            if !self.drawing {
                ui.painter().rect_filled(rect, 0.0, background);
            }
            paint_software(ui, rect, &self.camera, &[&self.model, overlay]);
        }
        if self.drawing {
            // The strokes again, faint, over the model: how each part's outline lies on
            // its strokes shows through.
            self.paint_strokes(ui, rect, content.backdrop.strokes, 0.3);
        }
        paint_gizmo(ui, rect, &self.camera);
        self.paint_caption(
            ui,
            rect,
            content.document.is_empty() && content.preview.is_none(),
        );
    }

    /// Orbit, pan, zoom and fit from the pointer. Orbiting leaves the view from the
    /// drawing for a perspective view.
    fn navigate(&mut self, ui: &Ui, response: &egui::Response, rect: Rect) {
        let shift = ui.input(|i| i.modifiers.shift);
        if response.dragged_by(egui::PointerButton::Primary) && !shift {
            let d = response.drag_delta();
            if d != egui::Vec2::ZERO && self.drawing {
                self.drawing = false;
                self.camera.ortho = false;
            }
            self.camera.orbit(d.x, d.y);
            self.camera.pitch = self.camera.pitch.clamp(MIN_PITCH, MAX_PITCH);
            self.moved = true;
        } else if response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
            || (response.dragged_by(egui::PointerButton::Primary) && shift)
        {
            let d = response.drag_delta();
            self.camera.pan(d.x, d.y, rect.height());
            self.moved = true;
        }
        if response.double_clicked() {
            self.request_fit();
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.camera.zoom((scroll * 0.0025).exp());
                self.moved = true;
            }
        }
    }

    /// Takes the drag's preview, at most every [`PREVIEW_EVERY`].
    fn take_preview(&mut self, preview: Option<&Primitive>) {
        let due = self
            .overlay
            .1
            .is_none_or(|at| at.elapsed() >= PREVIEW_EVERY);
        match preview {
            None => self.overlay = (Scene::default(), None),
            Some(p) if due => {
                let mut overlay = Scene::default();
                overlay.add_mesh(
                    &p.mesh(VIEW_SEGMENTS / 2),
                    linear(Color32::from_rgb(250, 170, 60), 0.75),
                );
                self.overlay = (overlay, Some(std::time::Instant::now()));
            }
            Some(_) => {}
        }
    }

    /// The canvas's view of the sketch that the camera's view from the drawing matches:
    /// sketch point (u, v) is model point (u, −v, ·), seen orthographically.
    fn sketch_view(&self, rect: Rect) -> CanvasView {
        let target = self.camera.target;
        let zoom = f64::from(rect.height()) / f64::from(2.0 * self.camera.half_height()).max(1e-9);
        CanvasView::looking_at(
            DVec2::new(f64::from(target.x), -f64::from(target.y)),
            zoom,
            rect,
        )
    }

    /// The reference image and the strokes, where the view from the drawing sees them.
    fn paint_backdrop(&self, ui: &Ui, rect: Rect, backdrop: &Backdrop<'_>) {
        let view = self.sketch_view(rect);
        let painter = ui.painter_at(rect);
        if let Some((texture, [w, h], opacity)) = backdrop.image {
            let corners = Rect::from_two_pos(
                view.to_screen(DVec2::ZERO),
                view.to_screen(DVec2::new(w as f64, h as f64)),
            );
            let alpha = (opacity.clamp(0.0, 1.0) * 255.0) as u8;
            painter.image(
                texture,
                corners,
                Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)),
                Color32::from_white_alpha(alpha),
            );
        }
        self.paint_strokes(ui, rect, backdrop.strokes, 0.8);
    }

    /// The strokes, where the view from the drawing sees them, at `opacity`.
    fn paint_strokes(&self, ui: &Ui, rect: Rect, strokes: &[Stroke], opacity: f32) {
        let view = self.sketch_view(rect);
        let painter = ui.painter_at(rect);
        let pen = egui::Stroke::new(1.2, Color32::from_rgb(50, 60, 80).gamma_multiply(opacity));
        for stroke in strokes {
            let line = view.screen_line(&stroke.points);
            if stroke.closed {
                painter.add(egui::Shape::closed_line(line, pen));
            } else {
                painter.add(egui::Shape::line(line, pen));
            }
        }
    }

    /// Which view this is, in the upper left corner, and the first step on an empty
    /// model.
    fn paint_caption(&self, ui: &Ui, rect: Rect, empty: bool) {
        let caption = if self.drawing {
            "View from the drawing"
        } else {
            "3D view · 0 or Home: back to the drawing's view"
        };
        let painter = ui.painter_at(rect);
        painter.text(
            rect.left_top() + egui::vec2(8.0, 6.0),
            egui::Align2::LEFT_TOP,
            caption,
            egui::FontId::proportional(13.0),
            Color32::from_gray(70),
        );
        if empty {
            painter.text(
                rect.center_bottom() - egui::vec2(0.0, 14.0),
                egui::Align2::CENTER_BOTTOM,
                "Drag a primitive from the palette onto the drawing",
                egui::FontId::proportional(14.0),
                ui.visuals().weak_text_color(),
            );
        }
    }
}

/// What the 3D view shows: the model, the drag's preview, what to emphasise, and the
/// drawing behind the model in the view from the drawing.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Content<'a> {
    pub document: &'a Document,
    /// The model's revision (the scene is rebuilt when it changes).
    pub revision: u64,
    pub preview: Option<&'a Primitive>,
    pub emphasis: &'a Emphasis,
    pub backdrop: Backdrop<'a>,
}

/// The axis gizmo in the lower left corner of `rect`: the model's X (red), Y (green,
/// up) and Z (blue, towards the drawing's viewer) as the camera sees them.
fn paint_gizmo(ui: &Ui, rect: Rect, camera: &OrbitCamera) {
    let forward = (camera.target - camera.eye()).normalize_or_zero();
    let right = forward.cross(Vec3::Y).normalize_or_zero();
    let up = right.cross(forward);
    let origin = rect.left_bottom() + egui::vec2(38.0, -38.0);
    let length = 26.0;
    let painter = ui.painter_at(rect);
    painter.circle_filled(origin, length + 8.0, Color32::from_white_alpha(110));
    let mut axes = [
        (Vec3::X, "X", Color32::from_rgb(215, 50, 50)),
        (Vec3::Y, "Y", Color32::from_rgb(40, 160, 60)),
        (Vec3::Z, "Z", Color32::from_rgb(50, 90, 220)),
    ];
    // The axis pointing away from the viewer first, so the nearer ones lie on top.
    axes.sort_by(|a, b| b.0.dot(forward).total_cmp(&a.0.dot(forward)));
    for (axis, name, color) in axes {
        let tip = origin + egui::vec2(axis.dot(right), -axis.dot(up)) * length;
        painter.line_segment([origin, tip], egui::Stroke::new(2.0, color));
        let out = tip - origin;
        let label = if out.length() > 2.0 {
            tip + out.normalized() * 7.0
        } else {
            tip + egui::vec2(7.0, -7.0)
        };
        painter.text(
            label,
            egui::Align2::CENTER_CENTER,
            name,
            egui::FontId::proportional(11.0),
            color,
        );
    }
}

/// A round grid step (1, 2 or 5 × 10ⁿ) near `raw`.
fn nice_step(raw: f32) -> f32 {
    if !(raw.is_finite() && raw > 0.0) {
        return 10.0;
    }
    let magnitude = 10f32.powf(raw.log10().floor());
    let r = raw / magnitude;
    let m = if r < 1.5 {
        1.0
    } else if r < 3.5 {
        2.0
    } else if r < 7.5 {
        5.0
    } else {
        10.0
    };
    m * magnitude
}

/// Paints scenes without a GPU: triangles flat-shaded by a head light and sorted by
/// depth, lines on top.
fn paint_software(ui: &Ui, rect: Rect, camera: &OrbitCamera, scenes: &[&Scene]) {
    let size = [rect.width().max(1.0), rect.height().max(1.0)];
    let to_screen = |p: [f32; 3]| {
        camera
            .project(Vec3::from(p), size)
            .map(|(x, y, z)| (rect.min + egui::vec2(x, y), z))
    };
    let eye = camera.eye();
    let painter = ui.painter_at(rect);
    for scene in scenes {
        for pair in scene.lines.chunks_exact(2) {
            if let (Some((a, _)), Some((b, _))) =
                (to_screen(pair[0].position), to_screen(pair[1].position))
            {
                let [r, g, bl, _] = pair[0].color;
                let color = egui::Rgba::from_rgb(r, g, bl);
                painter.line_segment([a, b], egui::Stroke::new(1.0, color));
            }
        }
    }
    let mut triangles = Vec::new();
    for scene in scenes {
        for t in scene.indices.chunks_exact(3) {
            let v = [t[0], t[1], t[2]].map(|i| scene.vertices[i as usize]);
            let projected: Option<Vec<(Pos2, f32)>> =
                v.iter().map(|v| to_screen(v.position)).collect();
            let Some(projected) = projected else { continue };
            let p = v.map(|v| Vec3::from(v.position));
            let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            let to_eye = (eye - p[0]).normalize_or_zero();
            let light = 0.35 + 0.65 * normal.dot(to_eye).abs();
            let depth = projected.iter().map(|(_, z)| z).sum::<f32>();
            let [r, g, b, a] = v[0].color;
            let color: Color32 =
                egui::Rgba::from_rgba_premultiplied(r * light * a, g * light * a, b * light * a, a)
                    .into();
            triangles.push((
                depth,
                [projected[0].0, projected[1].0, projected[2].0],
                color,
            ));
        }
    }
    triangles.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut mesh = egui::Mesh::default();
    for (_, points, color) in triangles {
        let base = mesh.vertices.len() as u32;
        for p in points {
            mesh.colored_vertex(p, color);
        }
        mesh.add_triangle(base, base + 1, base + 2);
    }
    painter.add(egui::Shape::mesh(mesh));
}

#[cfg(test)]
mod tests {
    use super::nice_step;

    #[test]
    fn grid_steps_are_round() {
        assert!((nice_step(0.9) - 1.0).abs() < 1e-6);
        assert!((nice_step(23.0) - 20.0).abs() < 1e-4);
        assert!((nice_step(4000.0) - 5000.0).abs() < 1e-2);
        assert!((nice_step(f32::NAN) - 10.0).abs() < 1e-6);
    }
}
