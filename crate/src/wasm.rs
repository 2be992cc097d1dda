//! The wasm-bindgen layer: thin wrappers that turn [`crate::Error`] into JS
//! `Error`s. All logic lives in the pure-Rust modules.

use crate::rotation::batch::{self, Repr};
use crate::rotation::curves;
use crate::rotation::euler::Axis;
use crate::runtime::{Model, TensorF32};
use wasm_bindgen::prelude::*;

fn js_err(e: crate::Error) -> JsError {
    JsError::new(&e.to_string())
}

fn parse_axis(axis: &str) -> Result<Axis, JsError> {
    match axis {
        "x" | "X" => Ok(Axis::X),
        "y" | "Y" => Ok(Axis::Y),
        "z" | "Z" => Ok(Axis::Z),
        _ => Err(JsError::new(&format!(
            "unknown axis '{axis}'; accepted: x, y, z"
        ))),
    }
}

/// The crate version.
#[wasm_bindgen]
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// Numbers per rotation in a representation (`"6d"` → 6).
#[wasm_bindgen(js_name = rotationDim)]
pub fn rotation_dim(repr: &str) -> Result<usize, JsError> {
    Ok(Repr::parse(repr).map_err(js_err)?.dim())
}

/// Converts a batch of rotations, e.g. `convertRotations("quat", "6d", q)`.
/// Names: matrix, 6d, 5d, quat, quat_gq, quat_gu, axis_angle, rodrigues,
/// euler:XYZ (upper case intrinsic, lower case extrinsic).
#[wasm_bindgen(js_name = convertRotations)]
pub fn convert_rotations(from: &str, to: &str, input: &[f32]) -> Result<Vec<f32>, JsError> {
    let f = Repr::parse(from).map_err(js_err)?;
    let t = Repr::parse(to).map_err(js_err)?;
    batch::convert(f, t, input).map_err(js_err)
}

/// Geodesic distances (radians, eq. 4.12) between two batches.
#[wasm_bindgen(js_name = geodesicDistances)]
pub fn geodesic_distances(repr: &str, a: &[f32], b: &[f32]) -> Result<Vec<f32>, JsError> {
    let r = Repr::parse(repr).map_err(js_err)?;
    batch::geodesic(r, a, b).map_err(js_err)
}

/// The rotation circle about `axis` ("x", "y", "z") in `repr`, `steps`
/// samples (Figure C.1's input).
#[wasm_bindgen(js_name = rotationCircle)]
pub fn rotation_circle(repr: &str, axis: &str, steps: usize) -> Result<Vec<f32>, JsError> {
    let r = Repr::parse(repr).map_err(js_err)?;
    curves::rotation_circle(r, parse_axis(axis)?, steps).map_err(js_err)
}

/// PCA to 2-D of `points` with `dim` numbers per row.
#[wasm_bindgen(js_name = pca2d)]
pub fn pca_2d(points: &[f32], dim: usize) -> Result<Vec<f32>, JsError> {
    if dim == 0 || points.len() % dim != 0 {
        return Err(JsError::new(&format!(
            "pca2d: {} numbers is not a multiple of dim = {dim}",
            points.len()
        )));
    }
    Ok(curves::pca_2d(points, dim))
}

/// An ONNX model run by tract.
#[wasm_bindgen]
pub struct OnnxModel {
    inner: Model,
}

#[wasm_bindgen]
impl OnnxModel {
    /// Parses a model from the bytes of an .onnx file.
    #[wasm_bindgen(constructor)]
    pub fn new(bytes: &[u8]) -> Result<OnnxModel, JsError> {
        Ok(OnnxModel {
            inner: Model::from_onnx_bytes(bytes).map_err(js_err)?,
        })
    }

    /// Runs a single-input model; returns its first output, flattened.
    pub fn run(&self, input: &[f32], shape: &[u32]) -> Result<Vec<f32>, JsError> {
        let t = TensorF32::new(input.to_vec(), shape.iter().map(|d| *d as usize).collect())
            .map_err(js_err)?;
        let mut out = self.inner.run(&[t]).map_err(js_err)?;
        if out.is_empty() {
            return Err(JsError::new("model produced no output"));
        }
        Ok(out.swap_remove(0).data)
    }
}

/// A BVH clip: skeleton plus motion.
#[wasm_bindgen]
pub struct BvhClip {
    inner: crate::skeleton::Bvh,
}

#[wasm_bindgen]
impl BvhClip {
    /// Parses BVH text. Throws an `Error` naming the line on malformed input.
    pub fn parse(text: &str) -> Result<BvhClip, JsError> {
        Ok(BvhClip {
            inner: crate::skeleton::Bvh::parse(text).map_err(js_err)?,
        })
    }

    /// Parses BVH bytes (for example a file's `ArrayBuffer` as `Uint8Array`).
    #[wasm_bindgen(js_name = fromBytes)]
    pub fn from_bytes(bytes: &[u8]) -> Result<BvhClip, JsError> {
        Ok(BvhClip {
            inner: crate::skeleton::Bvh::parse_bytes(bytes).map_err(js_err)?,
        })
    }

    /// Joint names in file order (End Sites are `<parent>_Nub`).
    #[wasm_bindgen(getter, js_name = jointNames)]
    pub fn joint_names(&self) -> Vec<String> {
        self.inner.joints.iter().map(|j| j.name.clone()).collect()
    }

    /// Parent index per joint (−1 for the root).
    #[wasm_bindgen(getter)]
    pub fn parents(&self) -> Vec<i32> {
        self.inner
            .joints
            .iter()
            .map(|j| j.parent.map_or(-1, |p| p as i32))
            .collect()
    }

    /// Rest offsets, `joints × 3`.
    #[wasm_bindgen(getter)]
    pub fn offsets(&self) -> Vec<f32> {
        self.inner.joints.iter().flat_map(|j| j.offset).collect()
    }

    /// Number of frames.
    #[wasm_bindgen(getter, js_name = frameCount)]
    pub fn frame_count(&self) -> usize {
        self.inner.frame_count()
    }

    /// Seconds per frame.
    #[wasm_bindgen(getter, js_name = frameTime)]
    pub fn frame_time(&self) -> f64 {
        self.inner.frame_time
    }

    /// Channels per frame.
    #[wasm_bindgen(getter, js_name = channelCount)]
    pub fn channel_count(&self) -> usize {
        self.inner.channel_count()
    }

    /// All channel values, `frames × channels`.
    #[wasm_bindgen(getter)]
    pub fn motion(&self) -> Vec<f32> {
        self.inner.motion.clone()
    }

    /// Global joint positions for frames `[start, end)`, `frames × joints × 3`.
    #[wasm_bindgen(js_name = fkPositions)]
    pub fn fk_positions(&self, start: usize, end: usize) -> Result<Vec<f32>, JsError> {
        crate::skeleton::fk::positions(&self.inner, start, end).map_err(js_err)
    }

    /// Writes the clip as BVH text.
    #[wasm_bindgen(js_name = toBvh)]
    pub fn to_bvh(&self) -> String {
        self.inner.write()
    }
}
