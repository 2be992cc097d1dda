//! HairNet run by tract (Sec. 3.2.3–3.2.4): an orientation image becomes
//! 32 × 32 strand features; features bilinearly upsampled on the scalp to
//! any strand count go through the strand MLPs (positions and curvatures);
//! each strand is then smoothed and its curls restored.

use super::scalp::Scalp;
use super::{strand, upsample, GRID, POINTS};
use crate::error::{Error, Result};
use crate::runtime::{Model, TensorF32};
use serde::Deserialize;

#[derive(Deserialize)]
struct Decoding {
    feature_channels: usize,
    pos_scale: f32,
    curv_scale: f32,
}

#[derive(Deserialize)]
struct Manifest {
    decoding: Decoding,
}

/// Reconstruction settings (Sec. 3.2.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reconstruct {
    /// Strands to grow (bilinear feature upsampling); 1024 = the grid itself.
    pub strands: usize,
    /// Gaussian smoothing along strands, in samples (0: none).
    pub smooth_sigma: f32,
    /// Mean missing curvature (1/m) above which curls are added; infinite: never.
    pub curl_threshold: f32,
}

impl Reconstruct {
    /// Gaussian smoothing's largest sigma, in samples (a strand has 100).
    pub const MAX_SMOOTH: f32 = 50.0;

    /// Checks the settings by [`crate::error::check_option`]'s rule: strands
    /// in [1, 200000], smoothing in [0, 50] samples, the curl threshold in
    /// [0, inf] (inf: never curl).
    pub fn check(&self) -> Result<()> {
        use crate::error::check_option;
        check_option("strands", self.strands as f64, 1.0, 200_000.0)?;
        check_option(
            "smooth (sigma in samples)",
            self.smooth_sigma as f64,
            0.0,
            Self::MAX_SMOOTH as f64,
        )?;
        check_option(
            "curl (threshold in 1/m)",
            self.curl_threshold as f64,
            0.0,
            f64::INFINITY,
        )
    }
}

impl Default for Reconstruct {
    fn default() -> Self {
        Reconstruct {
            strands: 30_000,
            smooth_sigma: 1.5,
            curl_threshold: 15.0,
        }
    }
}

/// A reconstructed hair: absolute strand points with per-sample curvature.
#[derive(Clone, Debug, PartialEq)]
pub struct Strands {
    /// Scalp coordinates of each strand's root.
    pub uv: Vec<(f32, f32)>,
    /// Points, [`POINTS`] per strand, absolute metres.
    pub points: Vec<[f32; 3]>,
    /// Predicted curvature per sample (1/m).
    pub curvature: Vec<f32>,
    /// How many strands had curls restored.
    pub curled: usize,
}

/// One 1 × 1-conv layer of a strand head: `weight` is out × in, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    /// Out × in weights.
    pub weight: Vec<f32>,
    /// Out biases.
    pub bias: Vec<f32>,
}

/// The strand heads' weights (for the GPU decoder): three layers each.
#[derive(Clone, Debug, PartialEq)]
pub struct HeadWeights {
    /// Feature channels.
    pub channels: usize,
    /// Position head: C→C (ReLU), C→C (tanh), C→300.
    pub pos: [Layer; 3],
    /// Curvature head: C→C (ReLU), C→C (tanh), C→100.
    pub curv: [Layer; 3],
}

fn head_weights(onnx: &[u8], c: usize) -> Result<HeadWeights> {
    let proto =
        crate::runtime::read_proto(onnx).map_err(|e| Error::Model(format!("hair strands: {e}")))?;
    let g = proto
        .graph
        .ok_or_else(|| Error::Model("hair strands: no graph".into()))?;
    let get = |name: &str, len: usize| -> Result<Vec<f32>> {
        let t = g
            .initializer
            .iter()
            .find(|t| t.name == name)
            .ok_or_else(|| Error::Model(format!("hair strands: no initializer '{name}'")))?;
        let v = crate::runtime::initializer_floats(t);
        if v.len() != len {
            return Err(Error::Model(format!(
                "hair strands: '{name}' has {} values, expected {len}",
                v.len()
            )));
        }
        Ok(v)
    };
    let head = |h: &str, out: usize| -> Result<[Layer; 3]> {
        let layer = |k: usize, o: usize| -> Result<Layer> {
            Ok(Layer {
                weight: get(&format!("heads.{h}.{k}.weight"), o * c)?,
                bias: get(&format!("heads.{h}.{k}.bias"), o)?,
            })
        };
        Ok([layer(0, c)?, layer(2, c)?, layer(4, out)?])
    };
    Ok(HeadWeights {
        channels: c,
        pos: head("pos", 3 * POINTS)?,
        curv: head("curv", POINTS)?,
    })
}

/// What turns raw head outputs into strands: the output scales and the
/// scalp. Copyable, so GPU decodes can finish without the model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrandDecoding {
    /// Metres per network position unit.
    pub pos_scale: f32,
    /// 1/m per network curvature unit.
    pub curv_scale: f32,
    /// The scalp the strands grow from.
    pub scalp: Scalp,
}

impl StrandDecoding {
    /// Converts raw head outputs laid out strand after strand (positions
    /// k × 300 with point j axis a at 3j + a, curvatures k × 100, network
    /// units; what the GPU decoder returns) into root-relative points and
    /// curvatures, as [`HairModel::decode`] returns them.
    pub fn outputs_to_strands(
        &self,
        pos: &[f32],
        curv: &[f32],
        k: usize,
    ) -> Result<(Vec<[f32; 3]>, Vec<f32>)> {
        if pos.len() != k * 3 * POINTS || curv.len() != k * POINTS {
            return Err(Error::Shape {
                what: "strand outputs".into(),
                expected: format!("{k} × 300 and {k} × 100"),
                found: format!("{} and {}", pos.len(), curv.len()),
            });
        }
        let points = pos
            .chunks_exact(3)
            .map(|p| {
                [
                    p[0] * self.pos_scale,
                    p[1] * self.pos_scale,
                    p[2] * self.pos_scale,
                ]
            })
            .collect();
        let curvature = curv
            .iter()
            .map(|c| (c * self.curv_scale).max(0.0))
            .collect();
        Ok((points, curvature))
    }

    /// Places decoded root-relative strands at their roots, smooths them and
    /// restores curls (Sec. 3.2.4).
    pub fn finish(
        &self,
        uv: Vec<(f32, f32)>,
        local: &[[f32; 3]],
        curvature: Vec<f32>,
        opts: &Reconstruct,
    ) -> Result<Strands> {
        if local.len() != uv.len() * POINTS || curvature.len() != local.len() {
            return Err(Error::Invalid("hair: strand count mismatch".into()));
        }
        let mut points = Vec::with_capacity(local.len());
        let mut curled = 0;
        for (i, &(u, v)) in uv.iter().enumerate() {
            let (root, _) = self.scalp.root(u, v);
            let s: Vec<[f32; 3]> = local[i * POINTS..(i + 1) * POINTS]
                .iter()
                .map(|p| [p[0] + root[0], p[1] + root[1], p[2] + root[2]])
                .collect();
            let (s, c) = strand::restore(
                &s,
                &curvature[i * POINTS..(i + 1) * POINTS],
                opts.smooth_sigma,
                opts.curl_threshold,
            );
            curled += c as usize;
            points.extend(s);
        }
        Ok(Strands {
            uv,
            points,
            curvature,
            curled,
        })
    }
}

/// The two exported graphs.
pub struct HairModel {
    features: Model,
    heads: Model,
    weights: HeadWeights,
    channels: usize,
    pos_scale: f32,
    curv_scale: f32,
    scalp: Scalp,
}

impl HairModel {
    /// Loads `hair_features.onnx`, `hair_strands.onnx` (bytes) and the
    /// features graph's manifest.
    pub fn new(features: &[u8], strands: &[u8], manifest_json: &str) -> Result<Self> {
        let m: Manifest = serde_json::from_str(manifest_json)
            .map_err(|e| Error::Invalid(format!("hair manifest: {e}")))?;
        if m.decoding.feature_channels == 0
            || !(m.decoding.pos_scale > 0.0 && m.decoding.curv_scale > 0.0)
        {
            return Err(Error::Invalid("hair manifest: bad decoding block".into()));
        }
        Ok(HairModel {
            features: Model::from_onnx_bytes(features)?,
            heads: Model::from_onnx_bytes(strands)?,
            weights: head_weights(strands, m.decoding.feature_channels)?,
            channels: m.decoding.feature_channels,
            pos_scale: m.decoding.pos_scale,
            curv_scale: m.decoding.curv_scale,
            scalp: Scalp::default(),
        })
    }

    /// Loads the bundled files from a folder.
    pub fn load_dir(dir: &std::path::Path) -> Result<Self> {
        let read = |n: &str| crate::runtime::read_file(dir, n);
        let m = String::from_utf8(read("hair_features.manifest.json")?)
            .map_err(|e| Error::Invalid(e.to_string()))?;
        Self::new(
            &read("hair_features.onnx")?,
            &read("hair_strands.onnx")?,
            &m,
        )
    }

    /// Feature channels per strand.
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// The strand heads' weights (for [`super::gpu::GpuStrandDecoder`]).
    pub fn head_weights(&self) -> &HeadWeights {
        &self.weights
    }

    /// The scales and scalp that finish a decode.
    pub fn decoding(&self) -> StrandDecoding {
        StrandDecoding {
            pos_scale: self.pos_scale,
            curv_scale: self.curv_scale,
            scalp: self.scalp,
        }
    }

    /// See [`StrandDecoding::outputs_to_strands`].
    pub fn outputs_to_strands(
        &self,
        pos: &[f32],
        curv: &[f32],
        k: usize,
    ) -> Result<(Vec<[f32; 3]>, Vec<f32>)> {
        self.decoding().outputs_to_strands(pos, curv, k)
    }

    /// Scalp coordinates for `count` strands: the grid's own cells for
    /// 1024, else an even `dense_uv` spread.
    pub fn strand_uv(count: usize) -> Vec<(f32, f32)> {
        if count == GRID * GRID {
            (0..GRID * GRID)
                .map(|i| Scalp::cell_uv(i % GRID, i / GRID, GRID))
                .collect()
        } else {
            upsample::dense_uv(count)
        }
    }

    /// See [`StrandDecoding::finish`].
    pub fn finish(
        &self,
        uv: Vec<(f32, f32)>,
        local: &[[f32; 3]],
        curvature: Vec<f32>,
        opts: &Reconstruct,
    ) -> Result<Strands> {
        self.decoding().finish(uv, local, curvature, opts)
    }

    /// The scalp the strands grow from.
    pub fn scalp(&self) -> &Scalp {
        &self.scalp
    }

    /// Strand features (C × 32 × 32, channel-major) of a 3 × 256 × 256 image.
    pub fn features(&self, image: &[f32]) -> Result<Vec<f32>> {
        if image.len() != 3 * 256 * 256 {
            return Err(Error::Shape {
                what: "hair image".into(),
                expected: "3 × 256 × 256 numbers".into(),
                found: format!("{}", image.len()),
            });
        }
        let out = self
            .features
            .run(&[TensorF32::new(image.to_vec(), vec![1, 3, 256, 256])?])?;
        let f = out
            .into_iter()
            .next()
            .ok_or_else(|| Error::Model("hair features: no output".into()))?;
        if f.data.len() != self.channels * GRID * GRID {
            return Err(Error::Model(format!(
                "hair features: output shape {:?}",
                f.shape
            )));
        }
        Ok(f.data)
    }

    /// Runs the strand MLPs on `k` feature vectors (k × C, strand after
    /// strand): root-relative points (k × [`POINTS`]) and curvatures.
    pub fn decode(&self, feats: &[f32], k: usize) -> Result<(Vec<[f32; 3]>, Vec<f32>)> {
        let c = self.channels;
        if k == 0 || feats.len() != k * c {
            return Err(Error::Shape {
                what: "strand features".into(),
                expected: format!("{k} × {c}"),
                found: format!("{}", feats.len()),
            });
        }
        let mut chw = vec![0.0f32; c * k];
        for i in 0..k {
            for ch in 0..c {
                chw[ch * k + i] = feats[i * c + ch];
            }
        }
        let out = self.heads.run(&[TensorF32::new(chw, vec![1, c, k, 1])?])?;
        let (pos, curv) = match out.as_slice() {
            [p, q] if p.data.len() == 3 * POINTS * k && q.data.len() == POINTS * k => (p, q),
            _ => return Err(Error::Model("hair strands: unexpected outputs".into())),
        };
        let mut points = Vec::with_capacity(k * POINTS);
        let mut curvature = Vec::with_capacity(k * POINTS);
        for i in 0..k {
            for j in 0..POINTS {
                let at = |a: usize| pos.data[(3 * j + a) * k + i] * self.pos_scale;
                points.push([at(0), at(1), at(2)]);
                curvature.push((curv.data[j * k + i] * self.curv_scale).max(0.0));
            }
        }
        Ok((points, curvature))
    }

    /// Strands from strand features (C × 32 × 32): upsampled to
    /// `opts.strands`, decoded, placed at their roots, smoothed, curls restored.
    pub fn strands_from_features(&self, features: &[f32], opts: &Reconstruct) -> Result<Strands> {
        opts.check()?;
        let uv = Self::strand_uv(opts.strands);
        let feats = upsample::upsample(features, self.channels, GRID, &uv)?;
        let (local, curvature) = self.decode(&feats, uv.len())?;
        self.finish(uv, &local, curvature, opts)
    }

    /// The whole reconstruction from an image.
    pub fn reconstruct(&self, image: &[f32], opts: &Reconstruct) -> Result<Strands> {
        self.strands_from_features(&self.features(image)?, opts)
    }
}

/// The blend weights taken by [`blend_features`] and the mesh codec's
/// `blend_one`: interpolation in [0, 1], extrapolation up to one step either side.
pub const BLEND_T: (f64, f64) = (-1.0, 2.0);

/// Fig. B.2's interpolation, in strand-feature space: (1 − t)·a + t·b.
pub fn blend_features(a: &[f32], b: &[f32], t: f32) -> Result<Vec<f32>> {
    if a.len() != b.len() {
        return Err(Error::Invalid(
            "hair blend: the feature grids differ in size".into(),
        ));
    }
    crate::error::check_option("blend t", t as f64, BLEND_T.0, BLEND_T.1)?;
    Ok(a.iter().zip(b).map(|(x, y)| x + t * (y - x)).collect())
}
