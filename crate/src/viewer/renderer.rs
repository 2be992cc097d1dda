//! The wgpu renderer: draws a [`Scene`] from an [`OrbitCamera`] into any
//! color target (a canvas surface in the browser, an offscreen texture in
//! headless tests). It keeps GPU resources only; the scene is rebuilt by the
//! caller every frame, as in rerun's re_renderer.

use super::camera::OrbitCamera;
use super::scene::Scene;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Quat, Vec3};
use wgpu::util::DeviceExt;

const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Vertex {
    pos: [f32; 3],
    normal: [f32; 3],
    /// Per-vertex tint, multiplied with the instance color (white for
    /// joints and bones; a mesh's own vertex colors when it has them).
    tint: [f32; 4],
}

const WHITE: [f32; 4] = [1.0; 4];

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Instance {
    model: [[f32; 4]; 4],
    color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct LineVertex {
    pos: [f32; 3],
    color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    light_dir: [f32; 4],
}

struct MeshBuffers {
    vertex: wgpu::Buffer,
    index: wgpu::Buffer,
    count: u32,
}

/// A unit sphere (radius 1), as a subdivided octahedron's vertices pushed out.
fn sphere_mesh(rings: u32, segments: u32) -> (Vec<Vertex>, Vec<u32>) {
    let mut v = Vec::new();
    let mut idx = Vec::new();
    for r in 0..=rings {
        let th = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let ph = 2.0 * std::f32::consts::PI * s as f32 / segments as f32;
            let n = [th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()];
            v.push(Vertex {
                pos: n,
                normal: n,
                tint: WHITE,
            });
        }
    }
    let w = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let a = r * w + s;
            let b = a + w;
            idx.extend_from_slice(&[a, a + 1, b, a + 1, b + 1, b]);
        }
    }
    (v, idx)
}

/// A unit bone: a cylinder of radius 1 from y = 0 to y = 1 that tapers to
/// 0.55 at the top, so the bone shows which way it points.
fn bone_mesh(segments: u32) -> (Vec<Vertex>, Vec<u32>) {
    let mut v = Vec::new();
    let mut idx = Vec::new();
    let top = 0.55;
    let slope = 1.0 - top;
    for s in 0..=segments {
        let ph = 2.0 * std::f32::consts::PI * s as f32 / segments as f32;
        let (c, sn) = (ph.cos(), ph.sin());
        let n = Vec3::new(c, slope, sn).normalize().to_array();
        v.push(Vertex {
            pos: [c, 0.0, sn],
            normal: n,
            tint: WHITE,
        });
        v.push(Vertex {
            pos: [c * top, 1.0, sn * top],
            normal: n,
            tint: WHITE,
        });
    }
    for s in 0..segments {
        let a = 2 * s;
        idx.extend_from_slice(&[a, a + 2, a + 1, a + 1, a + 2, a + 3]);
    }
    (v, idx)
}

fn upload(device: &wgpu::Device, (v, i): (Vec<Vertex>, Vec<u32>), label: &str) -> MeshBuffers {
    MeshBuffers {
        vertex: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(&v),
            usage: wgpu::BufferUsages::VERTEX,
        }),
        index: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(&i),
            usage: wgpu::BufferUsages::INDEX,
        }),
        count: i.len() as u32,
    }
}

fn instance(m: Mat4, color: [f32; 4]) -> Instance {
    Instance {
        model: m.to_cols_array_2d(),
        color,
    }
}

/// Per-frame draw lists built from a scene.
#[derive(Default)]
struct DrawLists {
    spheres: Vec<Instance>,
    bones: Vec<Instance>,
    lines: Vec<LineVertex>,
    mesh_vertices: Vec<Vertex>,
    mesh_instances: Vec<(std::ops::Range<u32>, Instance)>,
}

/// Line-list vertices of the scene's strips (a shade darker towards the tips).
fn strip_lines(scene: &Scene) -> Vec<LineVertex> {
    let mut lines = Vec::new();
    for s in &scene.strips {
        if s.strip_len < 2 {
            continue;
        }
        for strip in s.points.chunks_exact(s.strip_len) {
            let n = (strip.len() - 1) as f32;
            for (k, w) in strip.windows(2).enumerate() {
                let shade = |t: f32| {
                    let f = 1.0 - 0.35 * t / n;
                    [s.color[0] * f, s.color[1] * f, s.color[2] * f, s.color[3]]
                };
                lines.push(LineVertex {
                    pos: w[0],
                    color: shade(k as f32),
                });
                lines.push(LineVertex {
                    pos: w[1],
                    color: shade(k as f32 + 1.0),
                });
            }
        }
    }
    lines
}

/// Revision, point count and strip length of each strip set.
type StripsKey = Vec<(u64, usize, usize)>;

/// What identifies the strips' content for the cached buffer.
fn strips_key(scene: &Scene) -> StripsKey {
    scene
        .strips
        .iter()
        .map(|s| (s.revision, s.points.len(), s.strip_len))
        .collect()
}

fn draw_lists(scene: &Scene) -> DrawLists {
    let mut d = DrawLists::default();
    if let Some(g) = scene.grid {
        let n = (g.extent / g.step).floor() as i32;
        for i in -n..=n {
            let t = i as f32 * g.step;
            let c = if i == 0 {
                [0.45, 0.47, 0.52, 1.0]
            } else {
                [0.24, 0.25, 0.29, 1.0]
            };
            for (a, b) in [
                ([t, g.height, -g.extent], [t, g.height, g.extent]),
                ([-g.extent, g.height, t], [g.extent, g.height, t]),
            ] {
                d.lines.push(LineVertex { pos: a, color: c });
                d.lines.push(LineVertex { pos: b, color: c });
            }
        }
    }
    let ground = scene.grid.map_or(0.0, |g| g.height);
    for p in &scene.trajectory {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(1.3, 0.25, 1.3),
            Quat::IDENTITY,
            Vec3::new(p[0], ground + 0.3, p[2]),
        );
        d.spheres.push(instance(m, scene.trajectory_color));
    }
    for sk in &scene.skeletons {
        for (j, p) in sk.positions.iter().enumerate() {
            let pj = Vec3::from(*p);
            if !pj.is_finite() {
                continue;
            }
            d.spheres.push(instance(
                Mat4::from_scale_rotation_translation(
                    Vec3::splat(sk.joint_radius),
                    Quat::IDENTITY,
                    pj,
                ),
                sk.color,
            ));
            let Some(Some(parent)) = sk.parents.get(j) else {
                continue;
            };
            let Some(pp) = sk.positions.get(*parent).map(|p| Vec3::from(*p)) else {
                continue;
            };
            let dir = pj - pp;
            let len = dir.length();
            if !(len > 1e-4) || !pp.is_finite() {
                continue;
            }
            let rot = Quat::from_rotation_arc(Vec3::Y, dir / len);
            let m = Mat4::from_scale_rotation_translation(
                Vec3::new(sk.bone_radius, len, sk.bone_radius),
                rot,
                pp,
            );
            let c = sk.color;
            d.bones
                .push(instance(m, [c[0] * 0.85, c[1] * 0.85, c[2] * 0.85, c[3]]));
        }
    }
    for m in &scene.meshes {
        let start = d.mesh_vertices.len() as u32;
        let colored = m.vertex_colors.len() == m.positions.len();
        for t in m.indices.chunks_exact(3) {
            let Some(p) = t
                .iter()
                .map(|&i| m.positions.get(i as usize).map(|p| Vec3::from(*p)))
                .collect::<Option<Vec<_>>>()
            else {
                continue;
            };
            let n = (p[1] - p[0])
                .cross(p[2] - p[0])
                .normalize_or_zero()
                .to_array();
            for (q, &i) in p.into_iter().zip(t) {
                d.mesh_vertices.push(Vertex {
                    pos: q.to_array(),
                    normal: n,
                    tint: if colored {
                        m.vertex_colors[i as usize]
                    } else {
                        WHITE
                    },
                });
            }
        }
        let end = d.mesh_vertices.len() as u32;
        d.mesh_instances
            .push((start..end, instance(Mat4::IDENTITY, m.color)));
    }
    d
}

/// A vertex buffer reused across frames: it grows (to the next power of
/// two) when a frame needs more, and is refilled with `write_buffer`, so
/// drawing every frame allocates nothing on the GPU.
#[derive(Default)]
struct DynBuffer {
    buffer: Option<wgpu::Buffer>,
    capacity: u64,
}

impl DynBuffer {
    fn upload(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        data: &[u8],
        label: &str,
    ) -> Option<wgpu::Buffer> {
        if data.is_empty() {
            return None;
        }
        let len = data.len() as u64;
        if self.buffer.is_none() || self.capacity < len {
            if let Some(old) = self.buffer.take() {
                old.destroy();
            }
            self.capacity = len.next_power_of_two().max(256);
            self.buffer = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: self.capacity,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        let b = self.buffer.as_ref()?;
        queue.write_buffer(b, 0, data);
        Some(b.clone())
    }
}

/// GPU pipelines and reusable buffers for drawing scenes.
pub struct Renderer {
    lit: wgpu::RenderPipeline,
    line: wgpu::RenderPipeline,
    globals: wgpu::Buffer,
    bind: wgpu::BindGroup,
    sphere: MeshBuffers,
    bone: MeshBuffers,
    depth: Option<(wgpu::TextureView, u32, u32)>,
    spheres: DynBuffer,
    bones: DynBuffer,
    lines: DynBuffer,
    strips: DynBuffer,
    strips_cached: Option<(StripsKey, u32)>,
    mesh_vertices: DynBuffer,
    mesh_instances: DynBuffer,
}

impl Renderer {
    /// Builds the pipelines for color targets of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("deeprep viewer"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shaders.wgsl").into()),
        });
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("viewer"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let depth = Some(wgpu::DepthStencilState {
            format: DEPTH,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        });
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 7 => Float32x4],
        };
        let instance_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Instance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![2 => Float32x4, 3 => Float32x4, 4 => Float32x4, 5 => Float32x4, 6 => Float32x4],
        };
        let lit = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("lit"),
            layout: Some(&pl),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_lit"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout), Some(instance_layout)],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: depth.clone(),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_lit"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: Some(wgpu::BlendState::REPLACE),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let line = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("line"),
            layout: Some(&pl),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_line"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<LineVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4],
                })],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::LineList,
                ..Default::default()
            },
            depth_stencil: depth,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_line"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Renderer {
            lit,
            line,
            globals,
            bind,
            sphere: upload(device, sphere_mesh(10, 16), "sphere"),
            bone: upload(device, bone_mesh(12), "bone"),
            depth: None,
            spheres: DynBuffer::default(),
            bones: DynBuffer::default(),
            lines: DynBuffer::default(),
            strips: DynBuffer::default(),
            strips_cached: None,
            mesh_vertices: DynBuffer::default(),
            mesh_instances: DynBuffer::default(),
        }
    }

    fn depth_view(&mut self, device: &wgpu::Device, w: u32, h: u32) -> wgpu::TextureView {
        if let Some((v, dw, dh)) = &self.depth {
            if *dw == w && *dh == h {
                return v.clone();
            }
        }
        let t = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let v = t.create_view(&wgpu::TextureViewDescriptor::default());
        self.depth = Some((v.clone(), w, h));
        v
    }

    /// Draws `scene` seen by `camera` into `target` (`width` × `height`).
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &wgpu::TextureView,
        width: u32,
        height: u32,
        scene: &Scene,
        camera: &OrbitCamera,
    ) {
        let (w, h) = (width.max(1), height.max(1));
        let g = Globals {
            view_proj: camera.view_proj(w as f32 / h as f32).to_cols_array_2d(),
            light_dir: [0.4, 0.9, 0.5, 0.0],
        };
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&g));
        let lists = draw_lists(scene);
        let spheres = self.spheres.upload(
            device,
            queue,
            bytemuck::cast_slice(&lists.spheres),
            "spheres",
        );
        let bones = self
            .bones
            .upload(device, queue, bytemuck::cast_slice(&lists.bones), "bones");
        let lines = self
            .lines
            .upload(device, queue, bytemuck::cast_slice(&lists.lines), "lines");
        // Strips (e.g. 30K hair strands) are uploaded only when they change.
        let key = strips_key(scene);
        let strip_count = match &self.strips_cached {
            Some((k, n)) if *k == key => *n,
            _ => {
                let v = strip_lines(scene);
                self.strips
                    .upload(device, queue, bytemuck::cast_slice(&v), "strips");
                self.strips_cached = Some((key, v.len() as u32));
                v.len() as u32
            }
        };
        let strips = (strip_count > 0)
            .then(|| self.strips.buffer.clone())
            .flatten();
        let mesh_v = self.mesh_vertices.upload(
            device,
            queue,
            bytemuck::cast_slice(&lists.mesh_vertices),
            "mesh",
        );
        let mesh_i: Vec<Instance> = lists.mesh_instances.iter().map(|m| m.1).collect();
        let mesh_inst = self.mesh_instances.upload(
            device,
            queue,
            bytemuck::cast_slice(&mesh_i),
            "mesh instances",
        );
        let depth = self.depth_view(device, w, h);
        let bg = scene.background;
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("viewer"),
        });
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("viewer"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: bg[0] as f64,
                            g: bg[1] as f64,
                            b: bg[2] as f64,
                            a: bg[3] as f64,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.bind, &[]);
            if let Some(l) = &lines {
                pass.set_pipeline(&self.line);
                pass.set_vertex_buffer(0, l.slice(..));
                pass.draw(0..lists.lines.len() as u32, 0..1);
            }
            if let Some(b) = &strips {
                pass.set_pipeline(&self.line);
                pass.set_vertex_buffer(0, b.slice(..));
                pass.draw(0..strip_count, 0..1);
            }
            pass.set_pipeline(&self.lit);
            for (mesh, inst, n) in [
                (&self.sphere, &spheres, lists.spheres.len()),
                (&self.bone, &bones, lists.bones.len()),
            ] {
                if let Some(ib) = inst {
                    pass.set_vertex_buffer(0, mesh.vertex.slice(..));
                    pass.set_vertex_buffer(1, ib.slice(..));
                    pass.set_index_buffer(mesh.index.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..mesh.count, 0, 0..n as u32);
                }
            }
            if let (Some(v), Some(ib)) = (&mesh_v, &mesh_inst) {
                pass.set_vertex_buffer(0, v.slice(..));
                pass.set_vertex_buffer(1, ib.slice(..));
                for (k, (range, _)) in lists.mesh_instances.iter().enumerate() {
                    pass.draw(range.clone(), k as u32..k as u32 + 1);
                }
            }
        }
        queue.submit([enc.finish()]);
    }
}
