//! The 3D view panel: orbit (left drag, kept above the horizon so the camera does not
//! go under the grid), pan (right or middle drag, or Shift + left), zoom (wheel), fit
//! (F or double-click), the standard views (front, top, side, isometric, home: see
//! [`Standard`]) and an axis gizmo in the lower left corner. Drawn by [`crate::render::Viewport3d`] on the
//! GPU, or, without a wgpu device (the glow renderer, UI tests), painted in software:
//! flat-shaded triangles sorted back to front.

use egui::{Color32, Pos2, Rect, Sense, Ui};
use glam::Vec3;

use crate::core::model::{Document, PrimitiveId};
use crate::core::primitive::Primitive;
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
}

/// The 3D view's state.
#[derive(Debug, Default)]
pub(crate) struct View3d {
    pub camera: OrbitCamera,
    gpu: Option<Viewport3d>,
    model: Scene,
    model_key: Option<(u64, Emphasis)>,
    generation: u64,
    fitted: bool,
    /// Whether the user moved the camera (then it stops following the model).
    moved: bool,
    /// The drag preview shown, and when it was last changed: during a drag the 3D
    /// preview follows at most every [`PREVIEW_EVERY`], as each new one costs a render.
    overlay: (Scene, Option<std::time::Instant>),
    /// The box a fit frames: the model's bounds, or the grid's when the model is empty.
    frame: Option<(Vec3, Vec3)>,
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
    /// The view the app starts with.
    Home,
}

impl Standard {
    /// Yaw and pitch of the view, radians.
    fn angles(self) -> (f32, f32) {
        let home = OrbitCamera::default();
        match self {
            Self::Front => (0.0, 0.0),
            Self::Top => (0.0, MAX_PITCH),
            Self::Side => (std::f32::consts::FRAC_PI_2, 0.0),
            Self::Isometric => (std::f32::consts::FRAC_PI_4, (1.0 / 2f32.sqrt()).atan()),
            Self::Home => (home.yaw, home.pitch),
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

    /// Turns the camera to a standard view and frames the model (or the grid, when the
    /// model is empty) at the next draw.
    pub(crate) fn standard(&mut self, view: Standard) {
        let (yaw, pitch) = view.angles();
        self.camera.yaw = yaw;
        self.camera.pitch = pitch;
        self.request_fit();
    }

    /// Frames the model now, or the grid when the model is empty.
    fn fit_now(&mut self) {
        if let Some((lo, hi)) = self.frame {
            self.camera.fit(lo, hi);
            self.fitted = true;
        }
    }

    fn rebuild(&mut self, document: &Document, revision: u64, emphasis: &Emphasis) {
        let key = (revision, emphasis.clone());
        if self.model_key.as_ref() == Some(&key) {
            return;
        }
        let mut scene = Scene::default();
        for (index, (id, placed)) in document.primitives().enumerate() {
            let mut color = part_color(index);
            if emphasis.selected == Some(id) {
                color = color.lerp_to_gamma(Color32::WHITE, 0.35);
            } else if emphasis.related.contains(&id) {
                color = Color32::from_rgb(250, 200, 40);
            }
            scene.add_mesh(&placed.primitive.mesh(VIEW_SEGMENTS), linear(color, 1.0));
        }
        let (center, size, floor) = match scene.bounds() {
            Some((lo, hi)) => ((lo + hi) / 2.0, (hi - lo).max_element(), lo.y),
            None => (Vec3::ZERO, 500.0, 0.0),
        };
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
    pub(crate) fn show(
        &mut self,
        ui: &mut Ui,
        frame: &eframe::Frame,
        document: &Document,
        revision: u64,
        preview: Option<&Primitive>,
        emphasis: &Emphasis,
    ) {
        self.rebuild(document, revision, emphasis);
        if !self.fitted {
            self.fit_now();
        }
        let size = ui.available_size();
        let (rect, response) = ui.allocate_exact_size(size, Sense::click_and_drag());
        let response = response.on_hover_text(
            "3D view: drag to orbit, right-drag or Shift+drag to pan, wheel to zoom, \
             double-click to fit; keys 1–4 front, top, side, isometric; Home resets",
        );
        let shift = ui.input(|i| i.modifiers.shift);
        if response.dragged_by(egui::PointerButton::Primary) && !shift {
            let d = response.drag_delta();
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
        let due = self
            .overlay
            .1
            .is_none_or(|at| at.elapsed() >= PREVIEW_EVERY);
        if preview.is_none() {
            self.overlay = (Scene::default(), None);
        } else if due {
            let mut overlay = Scene::default();
            if let Some(p) = preview {
                overlay.add_mesh(
                    &p.mesh(VIEW_SEGMENTS / 2),
                    linear(Color32::from_rgb(250, 170, 60), 0.75),
                );
            }
            self.overlay = (overlay, Some(std::time::Instant::now()));
        }
        let overlay = &self.overlay.0;
        let background = if ui.visuals().dark_mode {
            Color32::from_rgb(62, 66, 74)
        } else {
            Color32::from_rgb(226, 229, 234)
        };
        let pixels_per_point = ui.ctx().pixels_per_point();
        let pixels = [
            (rect.width() * pixels_per_point).round().max(1.0) as u32,
            (rect.height() * pixels_per_point).round().max(1.0) as u32,
        ];
        if let Some(render_state) = frame.wgpu_render_state() {
            let gpu = self
                .gpu
                .get_or_insert_with(|| Viewport3d::new(render_state));
            let texture = gpu.render(
                render_state,
                pixels,
                &self.camera,
                (self.generation, &self.model),
                overlay,
                linear(background, 1.0),
            );
            ui.painter().image(
                texture,
                rect,
                Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)),
                Color32::WHITE,
            );
        } else {
            ui.painter().rect_filled(rect, 0.0, background);
            paint_software(ui, rect, &self.camera, &[&self.model, overlay]);
        }
        paint_gizmo(ui, rect, &self.camera);
        if document.is_empty() && preview.is_none() {
            ui.painter().text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                "Drag a primitive from the palette onto the drawing",
                egui::FontId::proportional(14.0),
                ui.visuals().weak_text_color(),
            );
        }
    }
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
