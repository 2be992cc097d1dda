//! Any ONNX model run by tract.

use super::js_err;
use crate::runtime::{Model, TensorF32};
use wasm_bindgen::prelude::*;

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
