//! The mesh autoencoder (ch. 2).

use super::{flat3, install_panic_hook, js_err, points3};
use wasm_bindgen::prelude::*;

/// The mesh autoencoder (thesis ch. 2) with the mesh it was trained on (the
/// bundled RobotExpressive.glb, or any OBJ or glTF template a model was
/// trained on): poses or deforms the mesh, encodes its welded mesh into a
/// few latent vertices, decodes, and edits one latent vertex's code (Fig.
/// 2.7). Positions are flat `vertices × 3` arrays of the welded mesh.
#[wasm_bindgen]
pub struct MeshLab {
    template: crate::mesh::Template,
    codec: crate::mesh::MeshCodec,
}

impl MeshLab {
    fn with(
        template: crate::mesh::Template,
        encoder: &[u8],
        decoder: &[u8],
        manifest: &str,
    ) -> Result<MeshLab, JsError> {
        let codec = crate::mesh::MeshCodec::new(encoder, decoder, manifest).map_err(js_err)?;
        template
            .check_model(codec.vertices(), codec.levels(), codec.trained_on())
            .map_err(js_err)?;
        Ok(MeshLab { template, codec })
    }
}

#[wasm_bindgen]
impl MeshLab {
    /// Loads a glTF template (`.glb` bytes) and the autoencoder (encoder and
    /// decoder `.onnx` bytes, `mesh_autoencoder.manifest.json` text). Fails,
    /// naming both, when the glTF's welded mesh is not the model's.
    #[wasm_bindgen(constructor)]
    pub fn new(
        glb: &[u8],
        encoder: &[u8],
        decoder: &[u8],
        manifest: &str,
    ) -> Result<MeshLab, JsError> {
        install_panic_hook();
        let template = crate::mesh::Template::from_glb(glb).map_err(js_err)?;
        MeshLab::with(template, encoder, decoder, manifest)
    }

    /// The same for an OBJ template (its text).
    #[wasm_bindgen(js_name = fromObj)]
    pub fn from_obj(
        obj: &str,
        encoder: &[u8],
        decoder: &[u8],
        manifest: &str,
    ) -> Result<MeshLab, JsError> {
        install_panic_hook();
        let template = crate::mesh::Template::from_obj(obj).map_err(js_err)?;
        MeshLab::with(template, encoder, decoder, manifest)
    }

    /// Whether the template is rigged (its clips pose it); otherwise random
    /// poses are smooth deformations.
    #[wasm_bindgen(getter, js_name = hasRig)]
    pub fn has_rig(&self) -> bool {
        self.template.rig.is_some()
    }

    /// Welded vertex count.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.template.topology.rest.len()
    }

    /// Triangles over welded vertices (3 indices each).
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Vec<u32> {
        self.template
            .topology
            .triangles
            .iter()
            .flat_map(|t| t.map(|i| i as u32))
            .collect()
    }

    /// The animation clips' names.
    #[wasm_bindgen(getter, js_name = clipNames)]
    pub fn clip_names(&self) -> Vec<String> {
        self.template
            .rig
            .iter()
            .flat_map(|r| &r.animations)
            .map(|a| a.name.clone())
            .collect()
    }

    /// The clips' durations in seconds.
    #[wasm_bindgen(getter, js_name = clipDurations)]
    pub fn clip_durations(&self) -> Vec<f32> {
        self.template
            .rig
            .iter()
            .flat_map(|r| &r.animations)
            .map(|a| a.duration)
            .collect()
    }

    /// Welded vertex index of each latent vertex.
    #[wasm_bindgen(getter, js_name = latentVertices)]
    pub fn latent_vertices(&self) -> Vec<u32> {
        self.template
            .topology
            .latent_vertices()
            .into_iter()
            .map(|v| v as u32)
            .collect()
    }

    /// For each latent vertex, the rig node it was seeded at ("" when the
    /// sampler chose it).
    #[wasm_bindgen(getter, js_name = latentNames)]
    pub fn latent_names(&self) -> Vec<String> {
        self.template
            .topology
            .latent_vertices()
            .iter()
            .map(|v| {
                self.template
                    .topology
                    .seeds
                    .iter()
                    .find(|s| s.1 == *v)
                    .map_or(String::new(), |s| s.0.clone())
            })
            .collect()
    }

    /// Per welded vertex, the latent vertex nearest by graph distance.
    #[wasm_bindgen(getter, js_name = latentRegions)]
    pub fn latent_regions(&self) -> Vec<u32> {
        self.template
            .topology
            .latent_regions()
            .into_iter()
            .map(|v| v as u32)
            .collect()
    }

    /// Latent codes per latent vertex.
    #[wasm_bindgen(getter, js_name = latentChannels)]
    pub fn latent_channels(&self) -> usize {
        self.codec.latent_shape().1
    }

    /// The rest pose.
    #[wasm_bindgen(js_name = restPose)]
    pub fn rest_pose(&self) -> Vec<f32> {
        flat3(&self.template.topology.rest)
    }

    /// Clip `clip` at `time` seconds (clamped to the clip).
    #[wasm_bindgen(js_name = clipPose)]
    pub fn clip_pose(&self, clip: usize, time: f32) -> Result<Vec<f32>, JsError> {
        Ok(flat3(&self.template.clip_pose(clip, time).map_err(js_err)?))
    }

    /// A random pose like the training set's: a random clip frame with every
    /// joint turned up to `maxDegrees` (30 in training), or for a template
    /// without a rig a random smooth deformation (`deeprep mesh deform`'s).
    #[wasm_bindgen(js_name = randomPose)]
    pub fn random_pose(&self, seed: u32, max_degrees: f32) -> Result<Vec<f32>, JsError> {
        Ok(flat3(
            &self
                .template
                .random_pose(seed as u64, max_degrees)
                .map_err(js_err)?,
        ))
    }

    /// Latent codes (latent vertices × channels) of a welded pose.
    pub fn encode(&self, positions: &[f32]) -> Result<Vec<f32>, JsError> {
        let p = points3(positions, "encode")?;
        self.codec.encode(&p).map_err(js_err)
    }

    /// Welded positions from latent codes.
    pub fn decode(&self, codes: &[f32]) -> Result<Vec<f32>, JsError> {
        Ok(flat3(&self.codec.decode(codes).map_err(js_err)?))
    }

    /// Codes `a` with latent vertex `vertex` blended towards `b` by `t`.
    #[wasm_bindgen(js_name = blendOne)]
    pub fn blend_one(
        &self,
        a: &[f32],
        b: &[f32],
        vertex: usize,
        t: f32,
    ) -> Result<Vec<f32>, JsError> {
        self.codec.blend_one(a, b, vertex, t).map_err(js_err)
    }
}
