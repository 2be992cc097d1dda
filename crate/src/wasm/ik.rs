//! IK from joint positions (Sec. 4.4.3).

use super::js_err;
use wasm_bindgen::prelude::*;

/// IK from joint positions (thesis Sec. 4.4.3): lifts poses given as global
/// joint positions to joint rotations on the model's skeleton.
#[wasm_bindgen]
pub struct IkSolver {
    inner: crate::ik::IkModel,
}

/// The result of [`IkSolver::solve`].
#[wasm_bindgen]
pub struct IkResult {
    bvh: String,
    channels: Vec<f32>,
    positions: Vec<f32>,
    mean_error: f64,
    max_error: f64,
}

#[wasm_bindgen]
impl IkResult {
    /// The poses as a BVH clip on the model's skeleton.
    #[wasm_bindgen(getter)]
    pub fn bvh(&self) -> String {
        self.bvh.clone()
    }
    /// BVH channel values, `frames × channelCount`.
    #[wasm_bindgen(getter)]
    pub fn channels(&self) -> Vec<f32> {
        self.channels.clone()
    }
    /// Forward kinematics of the solution, `frames × joints × 3`.
    #[wasm_bindgen(getter)]
    pub fn positions(&self) -> Vec<f32> {
        self.positions.clone()
    }
    /// Mean distance between input and reconstructed joints (BVH units).
    #[wasm_bindgen(getter, js_name = meanError)]
    pub fn mean_error(&self) -> f64 {
        self.mean_error
    }
    /// Largest such distance.
    #[wasm_bindgen(getter, js_name = maxError)]
    pub fn max_error(&self) -> f64 {
        self.max_error
    }
}

#[wasm_bindgen]
impl IkSolver {
    /// Loads `ik.onnx` (bytes) with `ik.manifest.json` (text).
    #[wasm_bindgen(constructor)]
    pub fn new(onnx: &[u8], manifest: &str) -> Result<IkSolver, JsError> {
        Ok(IkSolver {
            inner: crate::ik::IkModel::new(onnx, manifest).map_err(js_err)?,
        })
    }
    /// The skeleton as BVH text (no frames); joint order of the inputs.
    #[wasm_bindgen(getter, js_name = skeletonBvh)]
    pub fn skeleton_bvh(&self) -> String {
        self.inner.skeleton().write()
    }
    /// Joints per pose.
    #[wasm_bindgen(getter)]
    pub fn joints(&self) -> usize {
        self.inner.joints()
    }
    /// Solves `frames` poses of global joint positions (`frames × joints × 3`).
    pub fn solve(&self, positions: &[f32], frames: usize) -> Result<IkResult, JsError> {
        let sol = self.inner.solve(positions, frames).map_err(js_err)?;
        Ok(IkResult {
            bvh: sol.bvh.write(),
            channels: sol.bvh.motion,
            positions: sol.positions,
            mean_error: sol.mean_error,
            max_error: sol.max_error,
        })
    }
}
