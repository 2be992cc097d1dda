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
    /// Which matrix kernel plans optimized from now on run wide f32
    /// products with (`runtime::matmul_kernel`): `"auto"` (the default:
    /// deeprep's 3x12 kernel on x86-64 hosts, tract's 8x8 elsewhere),
    /// `"own"` (deeprep's) or `"tract"` (tract's). For benchmarks; plans
    /// already built keep theirs.
    #[wasm_bindgen(js_name = setMatmulKernel)]
    pub fn set_matmul_kernel(policy: &str) -> Result<(), JsError> {
        use crate::runtime::matmul_kernel::{set_policy, Policy};
        set_policy(match policy {
            "auto" => Policy::Auto,
            "own" => Policy::Own,
            "tract" => Policy::Tract,
            _ => {
                return Err(JsError::new(&format!(
                    "setMatmulKernel: {policy:?} is not \"auto\", \"own\" or \"tract\""
                )))
            }
        });
        Ok(())
    }

    /// The matrix kernel chosen (`runtime::matmul_kernel::choose`), as
    /// JSON: `{kernel, by}` (`by`: `"x86-64 host"`, `"other host"`, or the
    /// policy that fixed it); chooses now if no plan has yet.
    #[wasm_bindgen(js_name = matmulKernel)]
    pub fn matmul_kernel() -> Result<String, JsError> {
        let c = crate::runtime::matmul_kernel::choose().map_err(js_err)?;
        serde_json::to_string(&c).map_err(|e| JsError::new(&e.to_string()))
    }

    /// Parses a model from the bytes of an .onnx file.
    #[wasm_bindgen(constructor)]
    pub fn new(bytes: &[u8]) -> Result<OnnxModel, JsError> {
        Ok(OnnxModel {
            inner: Model::from_onnx_bytes(bytes).map_err(js_err)?,
        })
    }

    /// Parses a model whose weights come as factors (`MatMul` of two
    /// initializers, the mesh autoencoder's W = A·B) and multiplies them
    /// out once, as `MeshCodec` does (`Model::from_onnx_bytes_folding_factors`).
    #[wasm_bindgen(js_name = withFoldedFactors)]
    pub fn with_folded_factors(bytes: &[u8]) -> Result<OnnxModel, JsError> {
        Ok(OnnxModel {
            inner: Model::from_onnx_bytes_folding_factors(bytes)
                .map_err(js_err)?
                .0,
        })
    }

    /// Optimizes, once, one plan with the model's symbolic dimensions
    /// (a frame count) left free, which then runs every shape, so that a
    /// new shape does not wait for a plan of its own
    /// (`runtime::Model::prepare_any_shape`). Returns whether a plan was
    /// built (false for a model without symbols, or when one exists).
    #[wasm_bindgen(js_name = prepareAnyShape)]
    pub fn prepare_any_shape(&self) -> Result<bool, JsError> {
        self.inner.prepare_any_shape().map_err(js_err)
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

    /// Runs a model of any number of inputs: their values one after the
    /// other in `data`, their shapes one after the other in `shapes`, and
    /// each shape's rank in `ranks`. Returns the first output, flattened.
    #[wasm_bindgen(js_name = runInputs)]
    pub fn run_inputs(
        &self,
        data: &[f32],
        shapes: &[u32],
        ranks: &[u32],
    ) -> Result<Vec<f32>, JsError> {
        let inputs = inputs_from("runInputs", data, shapes, ranks)?;
        let mut out = self.inner.run(&inputs).map_err(js_err)?;
        if out.is_empty() {
            return Err(JsError::new("model produced no output"));
        }
        Ok(out.swap_remove(0).data)
    }

    /// Where tract spends its time in this browser (issue 23): `runs`
    /// profiled runs on inputs given as [`runInputs`](Self::run_inputs)
    /// takes them, every node of tract's plan timed with
    /// `performance.now()` (whose resolution the browser may coarsen to
    /// 0.1 ms), summed per operator. Returns JSON: `[{op, ms, share,
    /// nodes}]`, ms per run, slowest first.
    #[wasm_bindgen(js_name = profileInputs)]
    pub fn profile_inputs(
        &self,
        data: &[f32],
        shapes: &[u32],
        ranks: &[u32],
        runs: u32,
    ) -> Result<String, JsError> {
        let inputs = inputs_from("profileInputs", data, shapes, ranks)?;
        let clock = now_ms;
        let times = (0..runs.clamp(1, 100))
            .map(|_| self.inner.profile(&inputs, &clock))
            .collect::<Result<Vec<_>, _>>()
            .map_err(js_err)?;
        serde_json::to_string(&crate::runtime::per_op(&times))
            .map_err(|e| JsError::new(&e.to_string()))
    }
}

/// `performance.now()` in a window or a worker; `Date.now()` without one.
fn now_ms() -> f64 {
    let global = js_sys::global();
    js_sys::Reflect::get(&global, &JsValue::from_str("performance"))
        .ok()
        .and_then(|p| {
            let now = js_sys::Reflect::get(&p, &JsValue::from_str("now")).ok()?;
            now.dyn_into::<js_sys::Function>()
                .ok()?
                .call0(&p)
                .ok()?
                .as_f64()
        })
        .unwrap_or_else(js_sys::Date::now)
}

/// Inputs given as values one after the other in `data`, shapes one after
/// the other in `shapes` and each shape's rank in `ranks`; errors name the
/// method `what`.
fn inputs_from(
    what: &str,
    data: &[f32],
    shapes: &[u32],
    ranks: &[u32],
) -> Result<Vec<TensorF32>, JsError> {
    let mut inputs = Vec::with_capacity(ranks.len());
    let (mut at, mut dim) = (0usize, 0usize);
    for &r in ranks {
        let shape: Vec<usize> = shapes
            .get(dim..dim + r as usize)
            .ok_or_else(|| {
                JsError::new(&format!(
                    "{what}: the ranks ask for more dimensions than shapes has"
                ))
            })?
            .iter()
            .map(|&d| d as usize)
            .collect();
        dim += r as usize;
        let n = shape.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
        let values = n
            .and_then(|n| data.get(at..at.checked_add(n)?))
            .ok_or_else(|| {
                JsError::new(&format!(
                    "{what}: the shapes ask for more values than data has"
                ))
            })?;
        at += values.len();
        inputs.push(TensorF32::new(values.to_vec(), shape).map_err(js_err)?);
    }
    if at != data.len() || dim != shapes.len() {
        return Err(JsError::new(&format!(
            "{what}: data or shapes left over after the inputs"
        )));
    }
    Ok(inputs)
}
