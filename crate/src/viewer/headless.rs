//! Headless rendering (native only): a scene into an RGBA image, with no
//! window and no browser. Tests and the CLI use it; on a machine without a
//! GPU, Mesa's lavapipe (Vulkan) or llvmpipe (GL) serves as the adapter.

use super::camera::OrbitCamera;
use super::gpu;
use super::renderer::Renderer;
use super::scene::Scene;
use crate::error::{Error, Result};

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// A device and a renderer for offscreen images.
pub struct Headless {
    device: wgpu::Device,
    queue: wgpu::Queue,
    renderer: Renderer,
    /// The adapter's name and backend, e.g. "llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan)".
    pub adapter: String,
}

impl Headless {
    /// Opens the first adapter that Vulkan or GL offers, limited to what
    /// WebGL2 allows (so tests catch what the browser fallback cannot do).
    pub fn new() -> Result<Self> {
        Self::with_limits(wgpu::Limits::downlevel_webgl2_defaults())
    }

    /// Like [`Headless::new`] with WebGPU's downlevel limits: compute
    /// shaders and storage buffers, for GPU compute next to rendering.
    pub fn new_compute() -> Result<Self> {
        Self::with_limits(wgpu::Limits::downlevel_defaults())
    }

    fn with_limits(limits: wgpu::Limits) -> Result<Self> {
        pollster::block_on(async {
            let instance = gpu::instance(wgpu::Backends::VULKAN | wgpu::Backends::GL);
            let adapter = instance
                .request_adapter(&wgpu::RequestAdapterOptions::default())
                .await
                .map_err(|e| {
                    Error::Invalid(format!(
                        "no GPU adapter for headless rendering ({e}); install Mesa's Vulkan driver (Debian: mesa-vulkan-drivers)"
                    ))
                })?;
            let info = adapter.get_info();
            let (device, queue) =
                gpu::open_device(&adapter, limits, "deeprep headless", |m| eprintln!("{m}"))
                    .await?;
            let renderer = Renderer::new(&device, FORMAT);
            Ok(Headless {
                device,
                queue,
                renderer,
                adapter: format!("{} ({:?})", info.name, info.backend),
            })
        })
    }

    /// The device, for other GPU work on the same adapter (e.g. compute).
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue of [`Headless::device`].
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Renders `scene` at `width` × `height` and returns RGBA8 rows, top first.
    pub fn render(
        &mut self,
        scene: &Scene,
        camera: &OrbitCamera,
        width: u32,
        height: u32,
    ) -> Result<Vec<u8>> {
        if width == 0 || height == 0 || width > 8192 || height > 8192 {
            return Err(Error::Invalid(format!(
                "image size {width}x{height}: each side must be 1..8192"
            )));
        }
        let tex = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("offscreen"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = tex.create_view(&wgpu::TextureViewDescriptor::default());
        self.renderer.render(
            &self.device,
            &self.queue,
            &view,
            width,
            height,
            scene,
            camera,
        );
        let row = width * 4;
        let padded = row.div_ceil(256) * 256;
        let buf = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: (padded * height) as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut enc = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &tex,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &buf,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        self.queue.submit([enc.finish()]);
        let slice = buf.slice(..);
        gpu::map_read_blocking(&self.device, slice)?;
        let data = slice
            .get_mapped_range()
            .map_err(|e| Error::Invalid(format!("readback: {e:?}")))?;
        let mut out = Vec::with_capacity((row * height) as usize);
        for y in 0..height {
            let s = (y * padded) as usize;
            out.extend_from_slice(&data[s..s + row as usize]);
        }
        Ok(out)
    }
}
