//! HairNet (ch. 3) on the CPU: photo input, strand features, strands, collisions.

use super::{flat3, install_panic_hook, js_err, points3};
use wasm_bindgen::prelude::*;

/// HairNet (thesis ch. 3) with its reconstruction: strand features from a
/// 3 × 256 × 256 orientation image, bilinear upsampling to any strand
/// count, strand MLPs, smoothing and curl restoration; plus the project's
/// procedural test hair and its renders, and feature-space interpolation.
#[wasm_bindgen]
pub struct HairLab {
    pub(super) model: crate::hair::HairModel,
    body: crate::hair::Body,
}

#[wasm_bindgen]
impl HairLab {
    /// Loads `hair_features.onnx`, `hair_strands.onnx` (bytes) and
    /// `hair_features.manifest.json` (text).
    #[wasm_bindgen(constructor)]
    pub fn new(features: &[u8], strands: &[u8], manifest: &str) -> Result<HairLab, JsError> {
        install_panic_hook();
        Ok(HairLab {
            model: crate::hair::HairModel::new(features, strands, manifest).map_err(js_err)?,
            body: crate::hair::Body::default(),
        })
    }

    /// The hair classes' names (e.g. "M-curly").
    #[wasm_bindgen(js_name = classNames)]
    pub fn class_names() -> Vec<String> {
        crate::hair::HairClass::all()
            .iter()
            .map(|c| c.name())
            .collect()
    }

    /// A procedural hair of class `class` (seeded) rendered from `yawDeg`
    /// as the network's 3 × 256 × 256 input; `testHair` gives its strands.
    #[wasm_bindgen(js_name = testImage)]
    pub fn test_image(&self, class: &str, seed: u32, yaw_deg: f32) -> Result<Vec<f32>, JsError> {
        let job = crate::hair::HairJob {
            input: crate::hair::HairInput::Test {
                hair: crate::hair::TestHair::named(class, seed as u64).map_err(js_err)?,
                yaw_deg,
            },
            reconstruct: Default::default(),
        };
        job.image(&self.body).map_err(js_err)
    }

    /// The same procedural hair's strands (1024 × 100 × 3, absolute metres).
    #[wasm_bindgen(js_name = testHair)]
    pub fn test_hair(&self, class: &str, seed: u32) -> Result<Vec<f32>, JsError> {
        let hair = crate::hair::TestHair::named(class, seed as u64).map_err(js_err)?;
        Ok(flat3(&hair.hair(&self.body).map_err(js_err)?.points))
    }

    /// The network input (3 × 256 × 256) from a photo (Sec. 3.2.1): `grey`
    /// values and a `hair` mask (and optionally a `body` mask; empty for
    /// none), each `width` × `height`, mask values above 0.5 set. A Gabor
    /// filter bank finds the strand orientation at each hair pixel.
    #[wasm_bindgen(js_name = photoInput)]
    pub fn photo_input(
        &self,
        grey: &[f32],
        hair: &[f32],
        body: &[f32],
        width: usize,
        height: usize,
    ) -> Result<Vec<f32>, JsError> {
        let body = (!body.is_empty()).then_some(body);
        crate::hair::orientation::network_input(
            grey,
            hair,
            body,
            width,
            height,
            &crate::hair::orientation::Gabor::default(),
        )
        .map_err(js_err)
    }

    /// Strand features (C × 32 × 32) of an image.
    pub fn features(&self, image: &[f32]) -> Result<Vec<f32>, JsError> {
        self.model.features(image).map_err(js_err)
    }

    /// Strands (count × 100 × 3, absolute metres) from strand features:
    /// upsampled to `count`, decoded, smoothed (`smoothSigma` samples) and
    /// curled where the predicted curvature asks (`curlThreshold`, 1/m;
    /// Infinity disables).
    pub fn strands(
        &self,
        features: &[f32],
        count: usize,
        smooth_sigma: f32,
        curl_threshold: f32,
    ) -> Result<Vec<f32>, JsError> {
        let opts = crate::hair::Reconstruct {
            strands: count,
            smooth_sigma,
            curl_threshold,
        };
        Ok(flat3(
            &self
                .model
                .strands_from_features(features, &opts)
                .map_err(js_err)?
                .points,
        ))
    }

    /// Fig. B.2: (1 − t)·a + t·b in strand-feature space.
    #[wasm_bindgen(js_name = blendFeatures)]
    pub fn blend_features(a: &[f32], b: &[f32], t: f32) -> Result<Vec<f32>, JsError> {
        crate::hair::blend_features(a, b, t).map_err(js_err)
    }

    /// Eq. 3.3's collision error of strands (absolute, 100 points each).
    #[wasm_bindgen(js_name = collisionError)]
    pub fn collision_error(&self, points: &[f32]) -> Result<f32, JsError> {
        let p = points3(points, "strands")?;
        Ok(self.body.collision_error(&p, crate::hair::POINTS))
    }

    /// The body's four ellipsoids as a mesh: positions (× 3) then use `bodyTriangles`.
    #[wasm_bindgen(js_name = bodyPositions)]
    pub fn body_positions(&self) -> Vec<f32> {
        flat3(&self.body.mesh().0)
    }

    /// Triangles of `bodyPositions`.
    #[wasm_bindgen(js_name = bodyTriangles)]
    pub fn body_triangles(&self) -> Vec<u32> {
        self.body.mesh().1
    }
}
