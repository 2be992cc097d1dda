//! The strand MLPs as a WGSL compute shader (WebGPU in browsers, Vulkan
//! natively): one invocation per strand reads its C features and writes its
//! 300 position and 100 curvature outputs, so 30K strands decode in one
//! dispatch. Its results are checked against the CPU path (tract), which
//! stays the fallback where compute shaders are unavailable (WebGL2).
//! Only GPU plumbing lives here; the weights come from [`super::model`].

use super::model::HeadWeights;
use super::POINTS;
use crate::error::{Error, Result};
use wgpu::util::DeviceExt;

const WORKGROUP: u32 = 64;

/// Compute pipeline and weights on one device.
pub struct GpuStrandDecoder {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    weights: wgpu::Buffer,
    channels: usize,
}

/// A dispatched decode whose results are being copied to `readback`; map it
/// ([`crate::viewer::gpu::map_read`]), wait, then call [`Pending::read`].
pub struct Pending {
    /// The buffer to map for reading.
    pub readback: wgpu::Buffer,
    strands: usize,
}

fn shader(c: usize, offsets: &[usize; 12]) -> String {
    // offsets: pos w0 b0 w1 b1 w2 b2, curv w0 b0 w1 b1 w2 b2 (in f32s)
    format!(
        r#"
@group(0) @binding(0) var<storage, read> feats: array<f32>;
@group(0) @binding(1) var<storage, read> wts: array<f32>;
@group(0) @binding(2) var<storage, read_write> outp: array<f32>;
@group(0) @binding(3) var<uniform> params: vec4<u32>;

const C: u32 = {c}u;

fn head(s: u32, w0: u32, b0: u32, w1: u32, b1: u32, w2: u32, b2: u32, n_out: u32, out_base: u32) {{
    var x: array<f32, {c}>;
    var h: array<f32, {c}>;
    for (var i = 0u; i < C; i++) {{ x[i] = feats[s * C + i]; }}
    for (var o = 0u; o < C; o++) {{
        var a = wts[b0 + o];
        for (var i = 0u; i < C; i++) {{ a += wts[w0 + o * C + i] * x[i]; }}
        h[o] = max(a, 0.0);
    }}
    for (var o = 0u; o < C; o++) {{
        var a = wts[b1 + o];
        for (var i = 0u; i < C; i++) {{ a += wts[w1 + o * C + i] * h[i]; }}
        x[o] = tanh(a);
    }}
    for (var o = 0u; o < n_out; o++) {{
        var a = wts[b2 + o];
        for (var i = 0u; i < C; i++) {{ a += wts[w2 + o * C + i] * x[i]; }}
        outp[out_base + o] = a;
    }}
}}

@compute @workgroup_size({WORKGROUP})
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let s = gid.x;
    let n = params.x;
    if (s >= n) {{ return; }}
    head(s, {p0}u, {p1}u, {p2}u, {p3}u, {p4}u, {p5}u, {np}u, s * {np}u);
    head(s, {c0}u, {c1}u, {c2}u, {c3}u, {c4}u, {c5}u, {nc}u, n * {np}u + s * {nc}u);
}}
"#,
        p0 = offsets[0],
        p1 = offsets[1],
        p2 = offsets[2],
        p3 = offsets[3],
        p4 = offsets[4],
        p5 = offsets[5],
        c0 = offsets[6],
        c1 = offsets[7],
        c2 = offsets[8],
        c3 = offsets[9],
        c4 = offsets[10],
        c5 = offsets[11],
        np = 3 * POINTS,
        nc = POINTS,
    )
}

impl GpuStrandDecoder {
    /// Uploads the weights and builds the pipeline. Fails on devices
    /// without compute shaders or storage buffers (WebGL2).
    pub fn new(device: &wgpu::Device, w: &HeadWeights) -> Result<Self> {
        if device.limits().max_storage_buffers_per_shader_stage < 3 {
            return Err(Error::Invalid("GPU strand decoding needs compute shaders with storage buffers (WebGPU, Vulkan, Metal, DX12); use the CPU path".into()));
        }
        let c = w.channels;
        let mut all = Vec::new();
        let mut offsets = [0usize; 12];
        for (k, layer) in w.pos.iter().chain(w.curv.iter()).enumerate() {
            offsets[2 * k] = all.len();
            all.extend_from_slice(&layer.weight);
            offsets[2 * k + 1] = all.len();
            all.extend_from_slice(&layer.bias);
        }
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("strand decoder"),
            source: wgpu::ShaderSource::Wgsl(shader(c, &offsets).into()),
        });
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty,
            count: None,
        };
        let storage = |read_only| wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("strand decoder"),
            entries: &[
                entry(0, storage(true)),
                entry(1, storage(true)),
                entry(2, storage(false)),
                entry(
                    3,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
            ],
        });
        let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("strand decoder"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("strand decoder"),
            layout: Some(&pl),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let weights = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("strand decoder weights"),
            contents: bytemuck::cast_slice(&all),
            usage: wgpu::BufferUsages::STORAGE,
        });
        Ok(GpuStrandDecoder {
            pipeline,
            layout,
            weights,
            channels: c,
        })
    }

    /// Dispatches the decode of `k` feature vectors (k × C, strand after
    /// strand) and queues the copy of the outputs into a readback buffer.
    pub fn dispatch(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        feats: &[f32],
        k: usize,
    ) -> Result<Pending> {
        let c = self.channels;
        if k == 0 || feats.len() != k * c {
            return Err(Error::Shape {
                what: "strand features".into(),
                expected: format!("{k} × {c}"),
                found: format!("{}", feats.len()),
            });
        }
        let groups = (k as u32).div_ceil(WORKGROUP);
        if groups > device.limits().max_compute_workgroups_per_dimension {
            return Err(Error::Invalid(format!(
                "{k} strands are too many for one dispatch"
            )));
        }
        let out_len = (k * 4 * POINTS * 4) as u64;
        let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("strand features"),
            contents: bytemuck::cast_slice(feats),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("strand count"),
            contents: bytemuck::cast_slice(&[k as u32, 0, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("strand outputs"),
            size: out_len,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("strand readback"),
            size: out_len,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("strand decoder"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: input.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.weights.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: output.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: params.as_entire_binding(),
                },
            ],
        });
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("strand decoder"),
        });
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("strand decoder"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(groups, 1, 1);
        }
        enc.copy_buffer_to_buffer(&output, 0, &readback, 0, out_len);
        queue.submit([enc.finish()]);
        Ok(Pending {
            readback,
            strands: k,
        })
    }

    /// Native: dispatch, wait for the GPU, read back.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn decode_blocking(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        feats: &[f32],
        k: usize,
    ) -> Result<(Vec<f32>, Vec<f32>)> {
        let p = self.dispatch(device, queue, feats, k)?;
        crate::viewer::gpu::map_read_blocking(device, p.readback.slice(..))?;
        p.read()
    }
}

impl Pending {
    /// Raw network outputs of the mapped buffer: positions (k × 300, point
    /// j axis a at 3j + a) and curvatures (k × 100), strand after strand,
    /// in network units (multiply by the manifest's scales).
    pub fn read(self) -> Result<(Vec<f32>, Vec<f32>)> {
        let data = self
            .readback
            .slice(..)
            .get_mapped_range()
            .map_err(|e| Error::Invalid(format!("readback: {e:?}")))?;
        let all: &[f32] = bytemuck::cast_slice(&data);
        let np = self.strands * 3 * POINTS;
        Ok((all[..np].to_vec(), all[np..].to_vec()))
    }
}
