//! The exported mesh autoencoder run by tract: welded vertex positions in,
//! a few latent vertices out, and back; plus the local latent edit of
//! Fig. 2.7 (blend one latent vertex's code between two meshes).

use crate::error::{Error, Result};
use crate::runtime::{Model, TensorF32};
use serde::Deserialize;

#[derive(Deserialize)]
struct Norm {
    center: [f32; 3],
    height: f32,
}

#[derive(Deserialize)]
struct Manifest {
    normalization: Norm,
    levels: Vec<usize>,
    inputs: Inputs,
    #[serde(default)]
    training_data: Option<String>,
}

#[derive(Deserialize)]
struct Inputs {
    decoder: Vec<serde_json::Value>,
}

/// Encoder and decoder with their normalization.
pub struct MeshCodec {
    encoder: Model,
    decoder: Model,
    norm: Norm,
    vertices: usize,
    levels: usize,
    latent: (usize, usize),
    trained_on: String,
}

impl MeshCodec {
    /// Loads both graphs and `mesh_autoencoder.manifest.json`.
    pub fn new(encoder: &[u8], decoder: &[u8], manifest_json: &str) -> Result<Self> {
        let m: Manifest = serde_json::from_str(manifest_json)
            .map_err(|e| Error::Invalid(format!("mesh manifest: {e}")))?;
        let dims: Vec<usize> = m
            .inputs
            .decoder
            .iter()
            .filter_map(|v| v.as_u64())
            .map(|v| v as usize)
            .collect();
        let (&vertices, &[l, c]) = (
            m.levels
                .first()
                .ok_or_else(|| Error::Invalid("mesh manifest: no levels".into()))?,
            dims.as_slice(),
        ) else {
            return Err(Error::Invalid(
                "mesh manifest: decoder input must be [batch, L, C]".into(),
            ));
        };
        if !(m.normalization.height > 0.0) {
            return Err(Error::Invalid(
                "mesh manifest: height must be positive".into(),
            ));
        }
        Ok(MeshCodec {
            // The kernels ship factored (W = A·B) and are multiplied out
            // here, as the thesis precomputes them at test time.
            encoder: Model::from_onnx_bytes_folding_factors(encoder)?.0,
            decoder: Model::from_onnx_bytes_folding_factors(decoder)?.0,
            norm: m.normalization,
            vertices,
            levels: m.levels.len(),
            latent: (l, c),
            trained_on: m
                .training_data
                .as_deref()
                .and_then(|t| t.split(" posed by").next())
                .unwrap_or("its training mesh")
                .to_string(),
        })
    }

    /// Sampling levels, the full mesh included (the manifest's `levels`).
    pub fn levels(&self) -> usize {
        self.levels
    }

    /// Loads `mesh_encoder.onnx`, `mesh_decoder.onnx` and the manifest from a folder.
    pub fn load_dir(dir: &std::path::Path) -> Result<Self> {
        let read = |n: &str| crate::runtime::read_file(dir, n);
        let m = String::from_utf8(read("mesh_autoencoder.manifest.json")?)
            .map_err(|e| Error::Invalid(e.to_string()))?;
        Self::new(&read("mesh_encoder.onnx")?, &read("mesh_decoder.onnx")?, &m)
    }

    /// Welded vertices per mesh.
    pub fn vertices(&self) -> usize {
        self.vertices
    }

    /// What the model was trained on, from its manifest (for messages).
    pub fn trained_on(&self) -> &str {
        &self.trained_on
    }

    /// Latent vertices and channels per latent vertex.
    pub fn latent_shape(&self) -> (usize, usize) {
        self.latent
    }

    /// Latent codes (L × C) of a mesh given as welded positions (V × 3).
    pub fn encode(&self, positions: &[[f32; 3]]) -> Result<Vec<f32>> {
        if positions.len() != self.vertices {
            return Err(Error::Shape {
                what: "mesh".into(),
                expected: format!("{} vertices", self.vertices),
                found: format!("{}", positions.len()),
            });
        }
        let c = self.norm.center;
        let x: Vec<f32> = positions
            .iter()
            .flat_map(|p| (0..3).map(move |i| (p[i] - c[i]) / self.norm.height))
            .collect();
        let out = self
            .encoder
            .run(&[TensorF32::new(x, vec![1, self.vertices, 3])?])?;
        Ok(out
            .into_iter()
            .next()
            .ok_or_else(|| Error::Invalid("encoder returned nothing".into()))?
            .data)
    }

    /// Welded positions decoded from latent codes (L × C).
    pub fn decode(&self, latent: &[f32]) -> Result<Vec<[f32; 3]>> {
        let (l, c) = self.latent;
        if latent.len() != l * c {
            return Err(Error::Shape {
                what: "latent code".into(),
                expected: format!("{l} × {c}"),
                found: format!("{}", latent.len()),
            });
        }
        let out = self
            .decoder
            .run(&[TensorF32::new(latent.to_vec(), vec![1, l, c])?])?;
        let y = out
            .into_iter()
            .next()
            .ok_or_else(|| Error::Invalid("decoder returned nothing".into()))?
            .data;
        let k = self.norm.center;
        Ok(y.chunks_exact(3)
            .map(|p| {
                [
                    p[0] * self.norm.height + k[0],
                    p[1] * self.norm.height + k[1],
                    p[2] * self.norm.height + k[2],
                ]
            })
            .collect())
    }

    /// Fig. 2.7's local edit: `a`'s codes with latent vertex `vertex` blended
    /// towards `b`'s by `t` (0: a, 1: b); the other latent vertices keep `a`'s.
    pub fn blend_one(&self, a: &[f32], b: &[f32], vertex: usize, t: f32) -> Result<Vec<f32>> {
        let (l, c) = self.latent;
        if a.len() != l * c || b.len() != l * c || vertex >= l {
            return Err(Error::Invalid(format!(
                "blend_one: codes must be {l} × {c}, vertex < {l}"
            )));
        }
        crate::error::check_option("blend t", t as f64, -1.0, 2.0)?;
        let mut out = a.to_vec();
        for k in 0..c {
            out[vertex * c + k] = a[vertex * c + k] + t * (b[vertex * c + k] - a[vertex * c + k]);
        }
        Ok(out)
    }
}
