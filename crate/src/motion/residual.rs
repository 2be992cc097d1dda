//! A supervised residual on SLERP+LERP (issue 19, stage 1;
//! `train/deeprep_train/motion/residual.py`): a 1-D convolutional network reads SLERP+LERP of
//! whole-pose keys in the first key's frame (its root x/z and heading
//! removed) with each frame's phase between its keys, and outputs a
//! correction of the root position and of every joint's 6D rotation value
//! (ch. 4's continuous representation), scaled by a gate that is 0 at keys,
//! so keys are exact without post-processing.
//!
//! `variation` scales the correction: 0 is SLERP+LERP exactly, 1 the
//! network as trained.

use super::baseline::slerp_lerp;
use super::{Keyframe, Motion};
use crate::error::{Error, Result};
use crate::rotation::Mat3;
use crate::runtime::{Model, TensorF32};
use crate::skeleton::Bvh;
use serde::Deserialize;

/// Frames per unit of the network's phase inputs "frames since the previous
/// key" and "to the next" (one second at 60 fps), as `residual.py` trains it.
pub(super) const PHASE_FRAMES: f64 = 60.0;

#[derive(Deserialize)]
struct Manifest {
    kind: String,
    skeleton_bvh: String,
    rotating: Vec<usize>,
    scale: f64,
    gate_frames: f64,
    /// The variation used when a request names none (chosen on training
    /// takes; absent in older manifests: 1, the network as trained).
    #[serde(default)]
    variation: Option<f32>,
    /// Whether `method: model` runs this network for whole-pose keys
    /// (set when it beat the generator on training takes).
    #[serde(default)]
    default_for_whole_pose_keys: bool,
    /// A gap-filling network's (`tween_fill_long`: this network fine-tuned
    /// on gaps in captured motion): the shortest and longest gap the
    /// `model` fill gives it ([`crate::motion::fill::method_for`]).
    #[serde(default)]
    fill_from: Option<usize>,
    #[serde(default)]
    fill_up_to: Option<usize>,
}

impl Manifest {
    /// Its flags for the planner, checked: what both [`info_of_manifest`]
    /// and a loaded network's `info()` give.
    fn info(&self) -> Result<super::plan::ResidualInfo> {
        let bad = |e: Error| Error::Invalid(format!("residual manifest: {e}"));
        let variation = self.variation.unwrap_or(1.0);
        super::check_variation(variation).map_err(bad)?;
        Ok(super::plan::ResidualInfo {
            variation,
            default_for_whole_pose_keys: self.default_for_whole_pose_keys,
            fill_gaps: crate::motion::fill::band(self.fill_from, self.fill_up_to).map_err(bad)?,
        })
    }
}

/// What the request planner needs of a residual manifest's text (without
/// loading the network): its default variation, whether `model` runs it
/// for whole-pose keys and, for a gap-filling network, its band.
pub fn info_of_manifest(json: &str) -> Result<super::plan::ResidualInfo> {
    let m: Manifest = serde_json::from_str(json)
        .map_err(|e| Error::Invalid(format!("residual manifest: {e}")))?;
    m.info()
}

/// The residual in-betweening network with its skeleton.
pub struct ResidualModel {
    net: Model,
    /// The skeleton as a BVH with no frames.
    pub template: Bvh,
    rotating: Vec<usize>,
    scale: f64,
    gate_frames: f64,
    /// Its manifest's flags for the planner: the variation a request
    /// without one runs at, whether `model` runs it for whole-pose keys
    /// without DNA, and a gap-filling network's band.
    info: super::plan::ResidualInfo,
}

pub(super) type V3 = [f64; 3];

pub(super) fn mul(a: &Mat3<f64>, b: &Mat3<f64>) -> Mat3<f64> {
    crate::rotation::mul(a, b)
}

pub(super) fn transpose(m: &Mat3<f64>) -> Mat3<f64> {
    std::array::from_fn(|i| std::array::from_fn(|j| m[j][i]))
}

pub(super) fn apply(m: &Mat3<f64>, v: V3) -> V3 {
    std::array::from_fn(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// The first two columns, as `train/deeprep_train/motion/residual.py`'s `sixd`.
pub(super) fn sixd(m: &Mat3<f64>) -> [f64; 6] {
    [m[0][0], m[1][0], m[2][0], m[0][1], m[1][1], m[2][1]]
}

/// Gram-Schmidt back to a rotation (columns b1, b2, b1 × b2).
pub(super) fn from_sixd(r: &[f64; 6]) -> Option<Mat3<f64>> {
    let norm = |v: V3| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let (a1, a2) = ([r[0], r[1], r[2]], [r[3], r[4], r[5]]);
    let n1 = norm(a1);
    if !(n1 > 1e-9) {
        return None;
    }
    let b1 = a1.map(|x| x / n1);
    let d = b1[0] * a2[0] + b1[1] * a2[1] + b1[2] * a2[2];
    let u: V3 = std::array::from_fn(|i| a2[i] - d * b1[i]);
    let n2 = norm(u);
    if !(n2 > 1e-9) {
        return None;
    }
    let b2 = u.map(|x| x / n2);
    let b3 = [
        b1[1] * b2[2] - b1[2] * b2[1],
        b1[2] * b2[0] - b1[0] * b2[2],
        b1[0] * b2[1] - b1[1] * b2[0],
    ];
    Some(std::array::from_fn(|i| [b1[i], b2[i], b3[i]]))
}

/// Rotation by `t` radians about y, as `train/deeprep_train/motion/residual.py`'s `rot_y`.
pub(super) fn rot_y(t: f64) -> Mat3<f64> {
    let (s, c) = t.sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}

impl ResidualModel {
    /// Loads the network (the bytes of `tween_residual.onnx`) and its manifest.
    pub fn new(onnx: &[u8], manifest_json: &str) -> Result<Self> {
        let m: Manifest = serde_json::from_str(manifest_json)
            .map_err(|e| Error::Invalid(format!("residual manifest: {e}")))?;
        if m.kind != "residual-tween" {
            return Err(Error::Invalid(format!(
                "residual manifest: kind '{}', expected 'residual-tween'",
                m.kind
            )));
        }
        let template = Bvh::parse(&m.skeleton_bvh)?;
        let j = template.joints.len();
        let mut expected = template
            .joints
            .iter()
            .enumerate()
            .filter(|(_, jt)| !jt.channels.is_empty())
            .map(|(i, _)| i);
        if m.rotating
            .iter()
            .any(|&r| r >= j || expected.next() != Some(r))
            || expected.next().is_some()
            || m.rotating.first() != Some(&0)
        {
            return Err(Error::Invalid(
                "residual manifest: 'rotating' must list the skeleton's joints with channels, the root first".into(),
            ));
        }
        if !(m.scale > 0.0 && m.gate_frames > 0.0) {
            return Err(Error::Invalid(
                "residual manifest: scale and gate_frames must be positive".into(),
            ));
        }
        let info = m.info()?;
        Ok(ResidualModel {
            net: Model::from_onnx_bytes(onnx)?,
            template,
            rotating: m.rotating,
            scale: m.scale,
            gate_frames: m.gate_frames,
            info,
        })
    }

    /// Loads `tween_residual.onnx` and its manifest from a folder.
    pub fn load_dir(dir: &std::path::Path) -> Result<Self> {
        Self::load_named(dir, "tween_residual")
    }

    /// Loads `NAME.onnx` and `NAME.manifest.json` from a folder (the
    /// long-gap filling network is `tween_fill_long`).
    pub fn load_named(dir: &std::path::Path, name: &str) -> Result<Self> {
        let read = |n: &str| crate::runtime::read_file(dir, n);
        let manifest = String::from_utf8(read(&format!("{name}.manifest.json"))?)
            .map_err(|e| Error::Invalid(e.to_string()))?;
        Self::new(&read(&format!("{name}.onnx"))?, &manifest)
    }

    /// Prepares the network for requests of any length
    /// ([`crate::runtime::Model::prepare_any_shape`]).
    pub fn prepare_any_length(&self) -> Result<()> {
        self.net.prepare_any_shape().map(|_| ())
    }

    /// Builds and keeps the network's own plan for `frames` frames
    /// ([`crate::runtime::Model::prepare_shape`]): faster than the plan for
    /// any length, but 100-360 ms to build in wasm, so a worker calls it when
    /// idle after a request of that length. Returns whether a plan was built.
    pub fn prepare_length(&self, frames: usize) -> Result<bool> {
        super::check_frames(frames)?;
        if frames == 0 {
            return Err(Error::Invalid("a plan for 0 frames".into()));
        }
        self.net
            .prepare_shape(&[vec![1, self.input_channels(), frames]])
    }

    /// The network's input channels: root position (3), 6D of each rotating
    /// joint, then the phase and gate features (4).
    fn input_channels(&self) -> usize {
        3 + 6 * self.rotating.len() + 4
    }

    /// What the request planner (`motion::plan`) needs of this network.
    pub fn info(&self) -> super::plan::ResidualInfo {
        self.info
    }

    /// In-betweens whole-pose keys over `frames` frames. Frames before the
    /// first and after the last key hold those keys, as SLERP+LERP does.
    pub fn synthesize(&self, keys: &[Keyframe], frames: usize, variation: f32) -> Result<Motion> {
        super::check_variation(variation)?;
        super::validate_keys(keys, frames, self.template.joints.len())?;
        if let Some(i) = keys
            .iter()
            .position(|k| k.rotations.is_none() || !k.mask.iter().all(|m| *m))
        {
            return Err(Error::Invalid(format!(
                "the residual network takes whole-pose keys only; key {i} (frame {}) gives part of a pose \
                 (root-only and 2-D keys go to the generator: method model or generator)",
                keys[i].frame
            )));
        }
        let base = slerp_lerp(keys, frames)?;
        if base.rotations.first().map(|r| r.len()) != Some(self.template.joints.len()) {
            return Err(Error::Shape {
                what: "keys".into(),
                expected: format!(
                    "{} joints (the model's skeleton)",
                    self.template.joints.len()
                ),
                found: format!("{}", base.rotations.first().map_or(0, |r| r.len())),
            });
        }
        let n = frames;
        let k = self.rotating.len();
        let cin = self.input_channels();
        // the first key's frame: its root x/z and heading removed
        let k0 = keys[0].frame;
        let r0 = base.rotations[k0][0];
        let c = rot_y(-r0[0][2].atan2(r0[2][2]));
        let ct = transpose(&c);
        let off = [base.root[k0][0], 0.0, base.root[k0][2]];
        let (first, last) = (k0, keys[keys.len() - 1].frame);
        let mut x = vec![0f32; cin * n];
        let mut gate = vec![0f64; n];
        let mut seg = 0;
        for t in 0..n {
            let root = apply(&c, std::array::from_fn(|i| base.root[t][i] - off[i]));
            for i in 0..3 {
                x[i * n + t] = (root[i] / self.scale) as f32;
            }
            for (s, &j) in self.rotating.iter().enumerate() {
                let m = if j == 0 {
                    mul(&c, &base.rotations[t][0])
                } else {
                    base.rotations[t][j]
                };
                for (q, v) in sixd(&m).iter().enumerate() {
                    x[(3 + 6 * s + q) * n + t] = *v as f32;
                }
            }
            while seg + 2 < keys.len() && keys[seg + 1].frame <= t {
                seg += 1;
            }
            let (a, b) = if keys.len() > 1 {
                (keys[seg].frame, keys[seg + 1].frame)
            } else {
                (k0, k0)
            };
            let span = (b - a).max(1) as f64;
            let dp = t as f64 - a as f64;
            let dn = b as f64 - t as f64;
            let g = if t > first && t < last {
                1.0 - (-dp.min(dn) / self.gate_frames).exp()
            } else {
                0.0
            };
            gate[t] = g;
            let ph = [
                (dp / span).clamp(0.0, 1.0),
                dp.max(0.0) / PHASE_FRAMES,
                dn.max(0.0) / PHASE_FRAMES,
                g,
            ];
            for (q, v) in ph.iter().enumerate() {
                x[(3 + 6 * k + q) * n + t] = *v as f32;
            }
        }
        let out = self.net.run(&[TensorF32::new(x, vec![1, cin, n])?])?;
        let res = out
            .into_iter()
            .next()
            .ok_or_else(|| Error::Model("the residual network gave no output".into()))?;
        let cout = 3 + 6 * k;
        if res.shape != [1, cout, n] {
            return Err(Error::Model(format!(
                "residual output {:?}, expected [1, {cout}, {n}]",
                res.shape
            )));
        }
        crate::error::check_finite("residual network output", &res.data)?;
        let r = |ch: usize, t: usize| res.data[ch * n + t] as f64;
        // the motion is the base, moved frame by frame in place (each frame
        // is read before it is written; no copy of the base)
        let mut m = base;
        for t in 0..n {
            let w = variation as f64 * gate[t];
            if w == 0.0 {
                continue;
            }
            let root = apply(&c, std::array::from_fn(|i| m.root[t][i] - off[i]));
            let moved: V3 = std::array::from_fn(|i| root[i] + w * r(i, t) * self.scale);
            let back = apply(&ct, moved);
            m.root[t] = std::array::from_fn(|i| back[i] + off[i]);
            let frame = &mut m.rotations[t];
            for (s, &j) in self.rotating.iter().enumerate() {
                let b = if j == 0 { mul(&c, &frame[0]) } else { frame[j] };
                let b6 = sixd(&b);
                let v: [f64; 6] = std::array::from_fn(|q| b6[q] + w * r(3 + 6 * s + q, t));
                let rot = from_sixd(&v).ok_or_else(|| Error::Degenerate {
                    what: "residual 6D output".into(),
                    index: t,
                })?;
                frame[j] = if j == 0 { mul(&ct, &rot) } else { rot };
            }
        }
        Ok(m)
    }
}
