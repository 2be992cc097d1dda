//! HairNet's strand MLPs on WebGPU compute.

use super::hair::HairLab;
use super::{flat3, js_err};
use crate::viewer::gpu;
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
impl HairLab {
    /// Opens a WebGPU device and uploads the strand MLPs for
    /// [`GpuHairDecoder`]: a Promise that rejects where WebGPU compute is
    /// unavailable (then use `strands`, the CPU path).
    #[wasm_bindgen(js_name = openGpu)]
    pub fn open_gpu(&self) -> js_sys::Promise {
        let weights = self.model.head_weights().clone();
        let decoding = self.model.decoding();
        let channels = self.model.channels();
        wasm_bindgen_futures::future_to_promise(async move {
            let fail = |m: String| JsValue::from(JsError::new(&m));
            let instance = gpu::instance(wgpu::Backends::BROWSER_WEBGPU);
            let adapter = instance
                .request_adapter(&wgpu::RequestAdapterOptions::default())
                .await
                .map_err(|e| fail(format!("no WebGPU adapter: {e}")))?;
            let (device, queue) = gpu::open_device(
                &adapter,
                wgpu::Limits::downlevel_defaults(),
                "deeprep hair decoder",
                |m| web_sys::console::warn_1(&m.into()),
            )
            .await
            .map_err(|e| fail(e.to_string()))?;
            let decoder = crate::hair::gpu::GpuStrandDecoder::new(&device, &weights)
                .map_err(|e| fail(e.to_string()))?;
            Ok(GpuHairDecoder {
                device,
                queue,
                decoder: std::rc::Rc::new(decoder),
                decoding,
                channels,
            }
            .into())
        })
    }
}

/// HairNet's strand MLPs on WebGPU compute (a WGSL shader, one invocation
/// per strand), for tens of thousands of strands at once. Open it with
/// `HairLab.openGpu()`; where WebGPU is missing, use `HairLab.strands`.
#[wasm_bindgen]
pub struct GpuHairDecoder {
    device: wgpu::Device,
    queue: wgpu::Queue,
    decoder: std::rc::Rc<crate::hair::gpu::GpuStrandDecoder>,
    decoding: crate::hair::StrandDecoding,
    channels: usize,
}

#[wasm_bindgen]
impl GpuHairDecoder {
    /// Like `HairLab.strands`, decoded on the GPU: a Promise of the strands
    /// (count × 100 × 3, absolute metres).
    pub fn strands(
        &self,
        features: &[f32],
        count: usize,
        smooth_sigma: f32,
        curl_threshold: f32,
    ) -> Result<js_sys::Promise, JsError> {
        let opts = crate::hair::Reconstruct {
            strands: count,
            smooth_sigma,
            curl_threshold,
        };
        opts.check().map_err(js_err)?;
        let uv = crate::hair::HairModel::strand_uv(count);
        let feats =
            crate::hair::upsample::upsample(features, self.channels, crate::hair::GRID, &uv)
                .map_err(js_err)?;
        let pending = self
            .decoder
            .dispatch(&self.device, &self.queue, &feats, uv.len())
            .map_err(js_err)?;
        let decoding = self.decoding;
        Ok(wasm_bindgen_futures::future_to_promise(async move {
            let err = |e: crate::Error| JsValue::from(JsError::new(&e.to_string()));
            gpu::map_read(pending.readback.slice(..))
                .await
                .map_err(err)?;
            let n = uv.len();
            let (pos, curv) = pending.read().map_err(err)?;
            let (local, curvature) = decoding.outputs_to_strands(&pos, &curv, n).map_err(err)?;
            let s = decoding.finish(uv, &local, curvature, &opts).map_err(err)?;
            Ok(js_sys::Float32Array::from(flat3(&s.points).as_slice()).into())
        }))
    }
}
