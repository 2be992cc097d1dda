//! BVH clips: parsing, joints, motion, forward kinematics.

use super::js_err;
use wasm_bindgen::prelude::*;

/// A BVH clip: skeleton plus motion.
#[wasm_bindgen]
pub struct BvhClip {
    inner: crate::skeleton::Bvh,
}

impl BvhClip {
    /// The parsed clip (for the other wasm modules).
    pub(crate) fn bvh(&self) -> &crate::skeleton::Bvh {
        &self.inner
    }
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

    /// Global joint positions of one channel row on this clip's skeleton
    /// (a pose that is not one of its frames, such as a key being edited),
    /// `joints × 3`. Throws on a row of the wrong length or a non-finite value.
    #[wasm_bindgen(js_name = poseFk)]
    pub fn pose_fk(&self, channels: &[f32]) -> Result<Vec<f32>, JsError> {
        crate::skeleton::fk::pose_positions(&self.inner, channels).map_err(js_err)
    }

    /// Writes the clip as BVH text.
    #[wasm_bindgen(js_name = toBvh)]
    pub fn to_bvh(&self) -> String {
        self.inner.write()
    }
}
