//! The 3D view: an orbit camera, the scene's triangles and lines, and a wgpu renderer
//! that draws them offscreen (colour + depth, 4× MSAA) with the WGSL shader of
//! `shaders/mesh.wgsl`, into a texture the UI shows as an image.
//!
//! The camera and the scene are plain data ([`OrbitCamera`], [`Scene`]), so the app can
//! also paint them without a GPU (its software fallback) and tests can check the maths.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use eframe::egui_wgpu::{wgpu, RenderState};
use glam::{Mat4, Vec3};

use crate::core::primitive::TriMesh;

/// One vertex: position and normal in model space (a zero normal draws unlit), colour
/// in linear RGBA.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    /// Position.
    pub position: [f32; 3],
    /// Unit normal, or zero for lines.
    pub normal: [f32; 3],
    /// Colour.
    pub color: [f32; 4],
}

/// What the 3D view shows: triangles (shaded) and lines (the grid, unlit).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// Triangle vertices.
    pub vertices: Vec<Vertex>,
    /// Triangles as vertex indices.
    pub indices: Vec<u32>,
    /// Line vertices, in pairs.
    pub lines: Vec<Vertex>,
}

impl Scene {
    /// Adds a mesh in one colour.
    pub fn add_mesh(&mut self, mesh: &TriMesh, color: [f32; 4]) {
        let base = self.vertices.len() as u32;
        self.vertices.extend(
            mesh.positions
                .iter()
                .zip(&mesh.normals)
                .map(|(p, n)| Vertex {
                    position: p.as_vec3().to_array(),
                    normal: n.as_vec3().to_array(),
                    color,
                }),
        );
        self.indices
            .extend(mesh.triangles.iter().flatten().map(|i| base + i));
    }

    /// Adds a ground grid in the plane y = `height` around `center`, `cells` each way
    /// with `step` spacing.
    pub fn add_grid(&mut self, center: Vec3, height: f32, step: f32, cells: i32) {
        let half = step * cells as f32;
        let color = |k: i32| {
            if k == 0 {
                [0.45, 0.45, 0.5, 1.0]
            } else if k % 5 == 0 {
                [0.62, 0.62, 0.66, 1.0]
            } else {
                [0.74, 0.74, 0.77, 1.0]
            }
        };
        for k in -cells..=cells {
            let t = step * k as f32;
            let c = color(k);
            let line = |a: Vec3, b: Vec3| {
                [a, b].map(|p| Vertex {
                    position: p.to_array(),
                    normal: [0.0; 3],
                    color: c,
                })
            };
            self.lines.extend(line(
                Vec3::new(center.x + t, height, center.z - half),
                Vec3::new(center.x + t, height, center.z + half),
            ));
            self.lines.extend(line(
                Vec3::new(center.x - half, height, center.z + t),
                Vec3::new(center.x + half, height, center.z + t),
            ));
        }
    }

    /// The bounds of the triangles, `None` when there are none.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut it = self.vertices.iter().map(|v| Vec3::from(v.position));
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }
}

/// A camera orbiting a target: yaw about +Y, pitch above the ground, distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at.
    pub target: Vec3,
    /// Angle about +Y from the +Z (front) view, radians.
    pub yaw: f32,
    /// Angle above the horizontal, radians (kept within ±89°).
    pub pitch: f32,
    /// Distance from the target.
    pub distance: f32,
    /// Vertical field of view, radians.
    pub fov: f32,
    /// Orthographic instead of perspective: parallel rays, as the drawing is seen
    /// (its view is orthographic along −z). The view then spans
    /// [`Self::half_height`] above and below the target.
    pub ortho: bool,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        Self {
            target: Vec3::ZERO,
            yaw: 0.5,
            pitch: 0.35,
            distance: 1000.0,
            fov: 35f32.to_radians(),
            ortho: false,
        }
    }
}

impl OrbitCamera {
    /// The eye position.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + Vec3::new(sy * cp, sp, cy * cp) * self.distance
    }

    /// Half the height the view shows at the target's distance (all of the view, when
    /// orthographic).
    pub fn half_height(&self) -> f32 {
        self.distance * (self.fov / 2.0).tan()
    }

    /// Projection × view for an aspect ratio (width / height), depth 0..1.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let far = self.distance * 20.0 + 1.0;
        let aspect = aspect.max(1e-3);
        let projection = if self.ortho {
            // Everything within `far` of the eye, in front or behind: nothing in the
            // model is clipped for standing nearer than the eye.
            let (h, w) = (self.half_height(), self.half_height() * aspect);
            glam::camera::rh::proj::directx::orthographic(-w, w, -h, h, -far, far)
        } else {
            let near = (self.distance * 0.01).max(1e-3);
            glam::camera::rh::proj::directx::perspective(self.fov, aspect, near, far)
        };
        projection * glam::camera::rh::view::look_at_mat4(self.eye(), self.target, Vec3::Y)
    }

    /// Turns the camera by a drag of (dx, dy) in points.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.008;
        self.pitch = (self.pitch + dy * 0.008).clamp(-1.55, 1.55);
    }

    /// Moves the target in the view plane by a drag of (dx, dy) points in a view
    /// `height` points tall.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        let forward = (self.target - self.eye()).normalize_or_zero();
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let up = right.cross(forward);
        let per_point = 2.0 * self.half_height() / height.max(1.0);
        self.target += (-right * dx + up * dy) * per_point;
    }

    /// Zooms by `factor` (> 1 moves closer).
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance / factor).clamp(1e-2, 1e7);
        }
    }

    /// Frames the box (lo, hi): looks at its centre from far enough to see it whole.
    pub fn fit(&mut self, lo: Vec3, hi: Vec3) {
        let radius = ((hi - lo).length() / 2.0).max(1e-3);
        self.target = (lo + hi) / 2.0;
        self.distance = radius / (self.fov / 2.0).sin() * 1.1;
    }

    /// Where a model point lands in a view of `size` (x right, y down, in the view's
    /// units), with its depth; `None` behind the camera.
    pub fn project(&self, point: Vec3, size: [f32; 2]) -> Option<(f32, f32, f32)> {
        let clip = self.view_proj(size[0] / size[1]) * point.extend(1.0);
        if clip.w <= 1e-6 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some((
            f32::midpoint(ndc.x, 1.0) * size[0],
            (1.0 - ndc.y) / 2.0 * size[1],
            ndc.z,
        ))
    }
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Uniforms {
    view_proj: [[f32; 4]; 4],
    light: [f32; 4],
    eye: [f32; 4],
}

/// The format the 3D view is drawn in (the shaders write linear colour).
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The same texels as egui reads them: gamma-encoded bytes.
const SHOWN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Multisampling on a GPU; a software rasterizer (llvmpipe) gets 1 sample, as MSAA
/// multiplies its fragment work.
const GPU_SAMPLES: u32 = 4;

/// How the 3D view's colour target gets sRGB-encoded bytes, which egui reads as they are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TargetEncoding {
    /// Drawn through an sRGB view of the shown texture ([`COLOR_FORMAT`]): the hardware
    /// encodes, and blends in linear light.
    View,
    /// Where a texture cannot be viewed in another format (GL, WebGL): the target is
    /// plain 8-bit unorm and the shader encodes (its `ENCODE_SRGB` constant).
    Shader,
}

impl TargetEncoding {
    fn of(adapter: &wgpu::Adapter) -> Self {
        let flags = adapter.get_downlevel_capabilities().flags;
        if flags.contains(wgpu::DownlevelFlags::VIEW_FORMATS) {
            Self::View
        } else {
            Self::Shader
        }
    }

    /// The format the pipelines draw in.
    fn format(self) -> wgpu::TextureFormat {
        match self {
            Self::View => COLOR_FORMAT,
            Self::Shader => SHOWN_FORMAT,
        }
    }

    /// The other views the shown texture needs.
    fn view_formats(self) -> &'static [wgpu::TextureFormat] {
        match self {
            Self::View => &[COLOR_FORMAT],
            Self::Shader => &[],
        }
    }

    /// The shader's pipeline-overridable constants.
    fn constants(self) -> &'static [(&'static str, f64)] {
        match self {
            Self::View => &[],
            Self::Shader => &[("ENCODE_SRGB", 1.0)],
        }
    }
}

/// The offscreen targets at one size.
struct Targets {
    size: [u32; 2],
    msaa: Option<wgpu::TextureView>,
    resolve: wgpu::TextureView,
    depth: wgpu::TextureView,
    texture_id: egui::TextureId,
}

/// Draws [`Scene`]s with wgpu into a texture the UI shows.
pub struct Viewport3d {
    triangles: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    targets: Option<Targets>,
    /// Static geometry (the model and grid), uploaded when its key changes.
    cached: Option<(u64, Arc<Buffers>)>,
    samples: u32,
    encoding: TargetEncoding,
    /// What the texture shows now: a frame that would look the same is not drawn again.
    shown: Option<Shown>,
}

/// The inputs of the last frame drawn.
#[derive(Clone, Debug, PartialEq)]
struct Shown {
    size: [u32; 2],
    camera: OrbitCamera,
    model: u64,
    overlay: Scene,
    background: [f32; 4],
}

impl std::fmt::Debug for Viewport3d {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Viewport3d").finish_non_exhaustive()
    }
}

struct Buffers {
    vertices: Option<wgpu::Buffer>,
    indices: Option<wgpu::Buffer>,
    index_count: u32,
    lines: Option<wgpu::Buffer>,
    line_count: u32,
}

impl Buffers {
    fn new(device: &wgpu::Device, scene: &Scene) -> Self {
        let buffer = |label: &str, data: &[u8], usage: wgpu::BufferUsages| {
            (!data.is_empty()).then(|| {
                let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: data.len() as u64,
                    usage,
                    mapped_at_creation: true,
                });
                if let Ok(mut mapped) = buffer.slice(..).get_mapped_range_mut() {
                    mapped.copy_from_slice(data);
                }
                buffer.unmap();
                buffer
            })
        };
        Self {
            vertices: buffer(
                "geosnap vertices",
                bytemuck::cast_slice(&scene.vertices),
                wgpu::BufferUsages::VERTEX,
            ),
            indices: buffer(
                "geosnap indices",
                bytemuck::cast_slice(&scene.indices),
                wgpu::BufferUsages::INDEX,
            ),
            index_count: scene.indices.len() as u32,
            lines: buffer(
                "geosnap lines",
                bytemuck::cast_slice(&scene.lines),
                wgpu::BufferUsages::VERTEX,
            ),
            line_count: scene.lines.len() as u32,
        }
    }
}

impl Viewport3d {
    /// Builds the pipelines on the app's device.
    pub fn new(render_state: &RenderState) -> Self {
        let device = &render_state.device;
        let software = render_state.adapter.get_info().device_type == wgpu::DeviceType::Cpu;
        let samples = if software { 1 } else { GPU_SAMPLES };
        let encoding = TargetEncoding::of(&render_state.adapter);
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("geosnap mesh.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/mesh.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("geosnap uniforms"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("geosnap uniforms"),
            size: size_of::<Uniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("geosnap uniforms"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("geosnap mesh"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4];
        let pipeline = |topology: wgpu::PrimitiveTopology, label: &str| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_main"),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: size_of::<Vertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &attributes,
                    })],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    cull_mode: None,
                    ..wgpu::PrimitiveState::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: samples,
                    ..wgpu::MultisampleState::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some("fs_main"),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: encoding.constants(),
                        ..wgpu::PipelineCompilationOptions::default()
                    },
                    targets: &[Some(wgpu::ColorTargetState {
                        format: encoding.format(),
                        blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        Self {
            triangles: pipeline(wgpu::PrimitiveTopology::TriangleList, "geosnap triangles"),
            lines: pipeline(wgpu::PrimitiveTopology::LineList, "geosnap lines"),
            uniforms,
            bind_group,
            targets: None,
            cached: None,
            samples,
            encoding,
            shown: None,
        }
    }

    fn targets(&mut self, render_state: &RenderState, size: [u32; 2]) {
        let stale = self.targets.as_ref().is_none_or(|t| t.size != size);
        if stale {
            let device = &render_state.device;
            let texture =
                |label: &str, format, samples, usage, view_formats: &[wgpu::TextureFormat]| {
                    device.create_texture(&wgpu::TextureDescriptor {
                        label: Some(label),
                        size: wgpu::Extent3d {
                            width: size[0],
                            height: size[1],
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: 1,
                        sample_count: samples,
                        dimension: wgpu::TextureDimension::D2,
                        format,
                        usage,
                        view_formats,
                    })
                };
            let target_format = self.encoding.format();
            let msaa = (self.samples > 1).then(|| {
                texture(
                    "geosnap msaa",
                    target_format,
                    self.samples,
                    wgpu::TextureUsages::RENDER_ATTACHMENT,
                    &[],
                )
                .create_view(&wgpu::TextureViewDescriptor::default())
            });
            // The shaders write linear colour through an sRGB view; egui, which treats
            // texels as gamma-encoded, reads the same bytes through a plain view (and a
            // software rasterizer samples 8-bit unorm texels on its fast path).
            let image = texture(
                "geosnap view",
                SHOWN_FORMAT,
                1,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                self.encoding.view_formats(),
            );
            let resolve = image.create_view(&wgpu::TextureViewDescriptor {
                format: Some(target_format),
                ..wgpu::TextureViewDescriptor::default()
            });
            let shown = image.create_view(&wgpu::TextureViewDescriptor::default());
            let depth = texture(
                "geosnap depth",
                DEPTH_FORMAT,
                self.samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
                &[],
            )
            .create_view(&wgpu::TextureViewDescriptor::default());
            let mut renderer = render_state.renderer.write();
            let texture_id = match self.targets.take() {
                Some(old) => {
                    renderer.update_egui_texture_from_wgpu_texture(
                        device,
                        &shown,
                        wgpu::FilterMode::Linear,
                        old.texture_id,
                    );
                    old.texture_id
                }
                None => renderer.register_native_texture(device, &shown, wgpu::FilterMode::Linear),
            };
            self.targets = Some(Targets {
                size,
                msaa,
                resolve,
                depth,
                texture_id,
            });
        }
    }

    /// Renders `model` (static: re-uploaded only when `key` changes) and `overlay` (the
    /// drag preview, uploaded every call) seen by `camera` into a texture of `size`
    /// pixels, and returns the texture to show.
    pub fn render(
        &mut self,
        render_state: &RenderState,
        size: [u32; 2],
        camera: &OrbitCamera,
        model: (u64, &Scene),
        overlay: &Scene,
        background: [f32; 4],
    ) -> egui::TextureId {
        let size = [size[0].clamp(1, 8192), size[1].clamp(1, 8192)];
        let shown = Shown {
            size,
            camera: *camera,
            model: model.0,
            overlay: overlay.clone(),
            background,
        };
        if let (Some(targets), true) = (&self.targets, self.shown.as_ref() == Some(&shown)) {
            return targets.texture_id;
        }
        self.shown = Some(shown);
        let device = render_state.device.clone();
        let queue = render_state.queue.clone();
        let eye = camera.eye();
        let light = (eye - camera.target).normalize_or_zero() + Vec3::new(-0.4, 0.8, 0.2);
        let uniforms = Uniforms {
            view_proj: camera
                .view_proj(size[0] as f32 / size[1] as f32)
                .to_cols_array_2d(),
            light: light.extend(0.0).to_array(),
            eye: eye.extend(1.0).to_array(),
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        let stale = self.cached.as_ref().is_none_or(|(k, _)| *k != model.0);
        if stale {
            self.cached = Some((model.0, Arc::new(Buffers::new(&device, model.1))));
        }
        let statics = self
            .cached
            .as_ref()
            .map(|(_, b)| Arc::clone(b))
            .expect("cached above");
        let dynamic = Buffers::new(&device, overlay);
        self.targets(render_state, size);
        let (triangles, lines, bind_group) = (&self.triangles, &self.lines, &self.bind_group);
        let targets = self.targets.as_ref().expect("made above");
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("geosnap 3D view"),
        });
        {
            let [r, g, b, a] = background.map(f64::from);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("geosnap 3D view"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: targets.msaa.as_ref().unwrap_or(&targets.resolve),
                    depth_slice: None,
                    resolve_target: targets.msaa.as_ref().map(|_| &targets.resolve),
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                        store: if targets.msaa.is_some() {
                            wgpu::StoreOp::Discard
                        } else {
                            wgpu::StoreOp::Store
                        },
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &targets.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, bind_group, &[]);
            for buffers in [&*statics, &dynamic] {
                if let Some(lines_buffer) = &buffers.lines {
                    pass.set_pipeline(lines);
                    pass.set_vertex_buffer(0, lines_buffer.slice(..));
                    pass.draw(0..buffers.line_count, 0..1);
                }
                if let (Some(v), Some(i)) = (&buffers.vertices, &buffers.indices) {
                    pass.set_pipeline(triangles);
                    pass.set_vertex_buffer(0, v.slice(..));
                    pass.set_index_buffer(i.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..buffers.index_count, 0, 0..1);
                }
            }
        }
        queue.submit([encoder.finish()]);
        targets.texture_id
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::{OrbitCamera, Scene};
    use crate::core::primitive::{Primitive, Sphere};

    #[test]
    fn the_target_projects_to_the_view_centre_and_fit_frames_the_box() {
        let mut camera = OrbitCamera::default();
        camera.fit(Vec3::splat(-50.0), Vec3::splat(50.0));
        let (x, y, z) = camera
            .project(Vec3::ZERO, [800.0, 600.0])
            .expect("the target is in front");
        assert!((x - 400.0).abs() < 1e-3 && (y - 300.0).abs() < 1e-3 && (0.0..1.0).contains(&z));
        for corner in [
            Vec3::splat(-50.0),
            Vec3::splat(50.0),
            Vec3::new(50.0, -50.0, 50.0),
        ] {
            let (x, y, _) = camera.project(corner, [600.0, 600.0]).expect("in front");
            assert!(
                (0.0..=600.0).contains(&x) && (0.0..=600.0).contains(&y),
                "{corner}"
            );
        }
    }

    #[test]
    fn orbit_keeps_the_distance_and_pan_moves_the_target_with_the_drag() {
        let mut camera = OrbitCamera::default();
        let before = camera.eye().distance(camera.target);
        camera.orbit(120.0, 5000.0);
        assert!((camera.eye().distance(camera.target) - before).abs() < 1e-2);
        assert!(camera.pitch < 1.56, "pitch is clamped short of the pole");
        let camera = OrbitCamera {
            yaw: 0.0,
            pitch: 0.0,
            ..OrbitCamera::default()
        };
        let mut panned = camera;
        panned.pan(100.0, 0.0, 500.0);
        // Dragging right moves the scene right: the target moves left (−x from the front).
        assert!(panned.target.x < 0.0 && panned.target.y.abs() < 1e-4);
        let mut zoomed = camera;
        zoomed.zoom(2.0);
        assert!((zoomed.distance - camera.distance / 2.0).abs() < 1e-3);
        zoomed.zoom(f32::NAN);
        assert!(zoomed.distance.is_finite());
    }

    #[test]
    fn a_scene_holds_meshes_and_a_grid() {
        let mut scene = Scene::default();
        let ball = Primitive::Sphere(Sphere {
            center: glam::DVec3::new(0.0, 10.0, 0.0),
            radius: 5.0,
        });
        let mesh = ball.mesh(16);
        scene.add_mesh(&mesh, [1.0; 4]);
        scene.add_mesh(&mesh, [1.0; 4]);
        assert_eq!(scene.indices.len(), mesh.triangles.len() * 6);
        assert!(scene
            .indices
            .iter()
            .all(|i| (*i as usize) < scene.vertices.len()));
        let (lo, hi) = scene.bounds().expect("triangles");
        assert!((lo.y - 5.0).abs() < 1e-4 && (hi.y - 15.0).abs() < 1e-4);
        scene.add_grid(Vec3::ZERO, 0.0, 10.0, 4);
        assert_eq!(scene.lines.len(), 2 * 2 * 9);
    }
}
