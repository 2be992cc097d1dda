//! The mesh autoencoder (ch. 2).

use super::{flat3, install_panic_hook, js_err, points3};
use wasm_bindgen::prelude::*;

/// The mesh autoencoder (thesis ch. 2) with the rig it was trained on
/// (RobotExpressive.glb): poses the robot, encodes its welded mesh into a
/// few latent vertices, decodes, and edits one latent vertex's code (Fig. 2.7).
/// Positions are flat `vertices × 3` arrays of the welded mesh.
#[wasm_bindgen]
pub struct MeshLab {
    rig: crate::mesh::Rig,
    topo: crate::mesh::Topology,
    codec: crate::mesh::MeshCodec,
}

#[wasm_bindgen]
impl MeshLab {
    /// Loads the rig (`.glb` bytes) and the autoencoder (encoder and decoder
    /// `.onnx` bytes, `mesh_autoencoder.manifest.json` text). Fails when the
    /// rig's welded mesh is not the one the model was trained on.
    #[wasm_bindgen(constructor)]
    pub fn new(
        glb: &[u8],
        encoder: &[u8],
        decoder: &[u8],
        manifest: &str,
    ) -> Result<MeshLab, JsError> {
        install_panic_hook();
        let rig = crate::mesh::Rig::from_glb(glb).map_err(js_err)?;
        let topo = crate::mesh::Topology::robot(&rig).map_err(js_err)?;
        let codec = crate::mesh::MeshCodec::new(encoder, decoder, manifest).map_err(js_err)?;
        if topo.rest.len() != codec.vertices() || topo.levels.len() + 1 != codec.levels() {
            return Err(JsError::new(&format!(
                "this glTF welds to {} vertices in {} levels; the mesh model was trained on RobotExpressive.glb ({} vertices, {} levels)",
                topo.rest.len(),
                topo.levels.len() + 1,
                codec.vertices(),
                codec.levels()
            )));
        }
        Ok(MeshLab { rig, topo, codec })
    }

    /// Welded vertex count.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.topo.rest.len()
    }

    /// Triangles over welded vertices (3 indices each).
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Vec<u32> {
        self.topo
            .triangles
            .iter()
            .flat_map(|t| t.map(|i| i as u32))
            .collect()
    }

    /// The animation clips' names.
    #[wasm_bindgen(getter, js_name = clipNames)]
    pub fn clip_names(&self) -> Vec<String> {
        self.rig.animations.iter().map(|a| a.name.clone()).collect()
    }

    /// The clips' durations in seconds.
    #[wasm_bindgen(getter, js_name = clipDurations)]
    pub fn clip_durations(&self) -> Vec<f32> {
        self.rig.animations.iter().map(|a| a.duration).collect()
    }

    /// Welded vertex index of each latent vertex.
    #[wasm_bindgen(getter, js_name = latentVertices)]
    pub fn latent_vertices(&self) -> Vec<u32> {
        self.topo
            .latent_vertices()
            .into_iter()
            .map(|v| v as u32)
            .collect()
    }

    /// For each latent vertex, the rig node it was seeded at ("" when the
    /// sampler chose it).
    #[wasm_bindgen(getter, js_name = latentNames)]
    pub fn latent_names(&self) -> Vec<String> {
        self.topo
            .latent_vertices()
            .iter()
            .map(|v| {
                self.topo
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
        self.topo
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
        flat3(&self.topo.rest)
    }

    /// Clip `clip` at `time` seconds (clamped to the clip).
    #[wasm_bindgen(js_name = clipPose)]
    pub fn clip_pose(&self, clip: usize, time: f32) -> Result<Vec<f32>, JsError> {
        let p = self.rig.animation_pose(clip, time).map_err(js_err)?;
        Ok(flat3(&self.topo.weld_pose(&p).map_err(js_err)?))
    }

    /// A random pose like the training set's: a random clip frame with every
    /// joint turned up to `maxDegrees` (30 in training).
    #[wasm_bindgen(js_name = randomPose)]
    pub fn random_pose(&self, seed: u32, max_degrees: f32) -> Result<Vec<f32>, JsError> {
        let mut rng = crate::rng::Rng::new(seed as u64);
        let (local, _, _) = self
            .rig
            .jittered_locals(&mut rng, max_degrees.to_radians())
            .map_err(js_err)?;
        let p = self.rig.pose(&local).map_err(js_err)?;
        Ok(flat3(&self.topo.weld_pose(&p).map_err(js_err)?))
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
