//! The wasm-bindgen layer: thin wrappers that turn [`crate::Error`] into JS
//! `Error`s, one file per system. All logic lives in the pure-Rust modules.
//! The GPU parts (the viewer, HairNet's WebGPU decoder) need the `gpu`
//! feature; without it the package is the in-betweening, IK, mesh and hair
//! CPU API alone (what the synthesis worker loads).

mod bvh;
mod dna;
mod hair;
#[cfg(feature = "gpu")]
mod hair_gpu;
mod ik;
mod mesh;
mod motion;
mod onnx;
mod rotation;
#[cfg(feature = "gpu")]
mod viewer;

pub use bvh::BvhClip;
pub use dna::{dna_frames_of_clip, dna_frames_of_pool};
pub use hair::HairLab;
#[cfg(feature = "gpu")]
pub use hair_gpu::GpuHairDecoder;
pub use ik::{IkResult, IkSolver};
pub use mesh::MeshLab;
pub use motion::{InbetweenResult, Inbetweener, SynthesizeOptions};
pub use onnx::OnnxModel;
pub use rotation::{convert_rotations, geodesic_distances, pca_2d, rotation_circle, rotation_dim};
#[cfg(feature = "gpu")]
pub use viewer::Viewer;

use wasm_bindgen::prelude::*;

/// Sends Rust panic messages to the browser console (a panic is a bug: the
/// API returns `Error`s for bad input).
fn install_panic_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        std::panic::set_hook(Box::new(|info| {
            web_sys::console::error_1(&format!("deeprep panicked: {info}").into());
        }));
    });
}

/// Runs when the module is instantiated (every page and worker that calls
/// `init()`), so a panic anywhere is reported on the console with its
/// message before the instance traps.
#[wasm_bindgen(start)]
pub fn start() {
    install_panic_hook();
}

fn js_err(e: crate::Error) -> JsError {
    JsError::new(&e.to_string())
}

/// The crate version.
#[wasm_bindgen]
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// The longest gap between keys the networks run in one pass
/// (`motion::MAX_GAP`, 600 frames); longer gaps run hierarchically, up to
/// 3,000 frames. The npm worker loads the conditional network when a
/// request has such a gap and its manifest makes it their model.
#[wasm_bindgen(js_name = maxGap)]
pub fn max_gap() -> u32 {
    crate::motion::MAX_GAP as u32
}

/// `[x, y, z]` points as one flat array.
fn flat3(p: &[[f32; 3]]) -> Vec<f32> {
    p.iter().flat_map(|v| v.iter().copied()).collect()
}

fn points3(flat: &[f32], what: &str) -> Result<Vec<[f32; 3]>, JsError> {
    if !flat.len().is_multiple_of(3) {
        return Err(JsError::new(&format!(
            "{what}: expected a multiple of 3 numbers, found {}",
            flat.len()
        )));
    }
    Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}
