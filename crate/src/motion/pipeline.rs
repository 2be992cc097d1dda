//! The in-betweening pipeline on ONNX models (thesis Fig. 5.1):
//! dense input → generator (tract) → RC-FK → path predictor (tract) →
//! integrated root path → post-processing → motion.

use super::dense::{base_channels, dense_channels, dense_input, Base, Norm};
use super::feet::{lock_feet, FootLockStats};
use super::{post, Keyframe, Motion};
use crate::error::{Error, Result};
use crate::rcfk::RcSkeleton;
use crate::rotation::quat::{matrix_to_quat, quat_to_matrix_unit, slerp};
use crate::rotation::Mat3;
use crate::runtime::{Model, TensorF32};
use crate::skeleton::Bvh;

pub use super::{Request, MAX_GAP, MAX_LONG_GAP};

/// The two networks plus what they need: skeleton, ranges, normalization.
pub struct TweenModels {
    generator: Model,
    path: Model,
    /// RC-FK on the model's skeleton.
    pub rc: RcSkeleton,
    /// The skeleton as a BVH with no frames (channel orders for output).
    pub template: Bvh,
    /// Normalization constants.
    pub norm: Norm,
    /// The interpolation the generator was trained to correct.
    pub base: Base,
    /// The variation a request gets when it names none: the manifest's
    /// `variation`, chosen for this model on training takes (1 when the
    /// manifest has none).
    pub default_variation: f32,
}

/// The whole-pose keys that carry rotations, with them: what the base and
/// SLERP+LERP interpolate.
fn rotation_keys(keys: &[Keyframe]) -> impl Iterator<Item = (&Keyframe, &Vec<Mat3<f64>>)> {
    keys.iter()
        .filter(|k| k.mask.iter().all(|m| *m))
        .filter_map(|k| k.rotations.as_ref().map(|r| (k, r)))
}

/// Milliseconds spent in each stage.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Dense input and generator.
    pub generator_ms: f64,
    /// RC-FK over all frames.
    pub rcfk_ms: f64,
    /// Path predictor and integration.
    pub path_ms: f64,
    /// Post-processing.
    pub post_ms: f64,
}

/// Mean keyframe errors (BVH units).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KeyError {
    /// Root position error at keys that give the root.
    pub root: f64,
    /// Joint position error (relative to the root) over given coordinates.
    pub local: f64,
}

/// A synthesis result.
#[derive(Clone, Debug)]
pub struct Output {
    /// The motion.
    pub motion: Motion,
    /// Stage timings.
    pub times: StageTimes,
    /// Key errors before post-processing.
    pub key_error_raw: KeyError,
    /// Key errors after post-processing (equal to raw when it is off).
    pub key_error: KeyError,
    /// What foot locking did (all zero when it is off).
    pub foot_lock: FootLockStats,
    /// Hierarchical synthesis (a gap over [`MAX_GAP`]): the frames of the
    /// critical keys made first; empty when the networks ran directly.
    pub critical_frames: Vec<usize>,
}

impl TweenModels {
    /// Loads the generator and path predictor from ONNX bytes and the
    /// generator's manifest JSON.
    pub fn new(generator_onnx: &[u8], path_onnx: &[u8], manifest_json: &str) -> Result<Self> {
        let m = super::manifest::parse(manifest_json)?;
        Ok(TweenModels {
            generator: Model::from_onnx_bytes(generator_onnx)?,
            path: Model::from_onnx_bytes(path_onnx)?,
            rc: m.rc,
            template: m.template,
            norm: m.norm,
            base: m.base,
            default_variation: m.variation,
        })
    }

    /// Loads `tween_generator.onnx`, `tween_path.onnx` and the manifest from
    /// a folder (native; in a browser, fetch the bytes and use [`Self::new`]).
    pub fn load_dir(dir: &std::path::Path) -> Result<Self> {
        let read = |n: &str| crate::runtime::read_file(dir, n);
        let manifest = String::from_utf8(read("tween_generator.manifest.json")?)
            .map_err(|e| Error::Invalid(e.to_string()))?;
        Self::new(
            &read("tween_generator.onnx")?,
            &read("tween_path.onnx")?,
            &manifest,
        )
    }

    /// Joints per pose.
    pub fn joints(&self) -> usize {
        self.template.joints.len()
    }

    /// Prepares the networks for requests of any length
    /// ([`Model::prepare_any_shape`]), so that a long-lived caller's first
    /// request of each length does not wait for plan optimization.
    /// Returns whether a plan was built (false when already prepared).
    pub fn prepare_any_length(&self) -> Result<bool> {
        let g = self.generator.prepare_any_shape()?;
        let p = self.path.prepare_any_shape()?;
        Ok(g || p)
    }

    /// Synthesizes a motion. `now_ms` is a clock (milliseconds) for the
    /// stage timings; pass `|| 0.0` to skip timing.
    ///
    /// Gaps between keys up to [`MAX_GAP`] frames run the networks
    /// directly. Longer ones, up to [`MAX_LONG_GAP`], run hierarchically
    /// (Sec. 5.4.3: critical frames first, then the shorter intervals): the
    /// whole request is first synthesized on a timeline compressed by
    /// `f = ⌈longest gap / MAX_GAP⌉`, whose poses at evenly spaced frames
    /// inside each long gap (at most 300 frames apart) become whole-pose
    /// critical keys; the request with them then runs directly. The coarse
    /// pass plays the motion f times faster, so only its poses and root
    /// positions are kept, not its timing. The output lists the critical
    /// frames; key errors after post-processing are measured on the request's
    /// own keys.
    pub fn synthesize(&self, req: &Request, now_ms: &dyn Fn() -> f64) -> Result<Output> {
        let j = self.joints();
        req.validate(j, self.default_variation)?;
        let longest = req
            .keys
            .windows(2)
            .map(|w| w[1].frame - w[0].frame)
            .max()
            .unwrap_or(0);
        if longest <= MAX_GAP {
            return self.synthesize_direct(req, now_ms);
        }
        let f = longest.div_ceil(MAX_GAP);
        let coarse_frames = (req.frames - 1) / f + 1;
        let mut coarse_keys: Vec<Keyframe> = Vec::with_capacity(req.keys.len());
        for k in &req.keys {
            let frame = ((k.frame + f / 2) / f).min(coarse_frames - 1);
            if coarse_keys.last().is_some_and(|c| c.frame >= frame) {
                continue; // keys closer than f frames share a coarse frame: the first stays
            }
            coarse_keys.push(Keyframe { frame, ..k.clone() });
        }
        let coarse = self.synthesize_direct(
            &Request {
                keys: coarse_keys,
                frames: coarse_frames,
                dna: req.dna.clone(),
                post_process: true,
                foot_lock: None,
                variation: req.variation,
            },
            now_ms,
        )?;
        let coarse_bvh = coarse.motion.to_bvh(&self.template, f as f64 / 60.0)?;
        const PIECE: usize = 300;
        let mut keys = req.keys.clone();
        let mut critical = Vec::new();
        for w in req.keys.windows(2) {
            let (a, b) = (w[0].frame, w[1].frame);
            if b - a <= MAX_GAP {
                continue;
            }
            let pieces = (b - a).div_ceil(PIECE);
            for i in 1..pieces {
                let t = a + i * (b - a) / pieces;
                let ct = ((t + f / 2) / f).min(coarse_frames - 1);
                keys.push(Keyframe::from_bvh(&coarse_bvh, ct, t)?);
                critical.push(t);
            }
        }
        keys.sort_by_key(|k| k.frame);
        let mut out = self.synthesize_direct(
            &Request {
                keys,
                ..req.clone()
            },
            now_ms,
        )?;
        // after post-processing: on the request's own keys; before it: as the
        // fine pass measured it, over its keys, critical ones included
        out.key_error = self.key_error(&out.motion, &req.keys);
        out.critical_frames = critical;
        Ok(out)
    }

    fn synthesize_direct(&self, req: &Request, now_ms: &dyn Fn() -> f64) -> Result<Output> {
        let j = self.joints();
        let p = 3 * j;
        let variation = req.validate(j, self.default_variation)?;
        let n = req.frames.div_ceil(64).max(1) * 64;
        let t0 = now_ms();
        let dense = dense_input(&req.keys, n, &self.norm);
        // Whole-pose keys with rotations also give the generator their raw
        // RC-FK values (its output is their interpolation plus a correction).
        let d = self.rc.output_dim();
        let rot_rows: Vec<(usize, Vec<f32>, Vec<bool>)> = rotation_keys(&req.keys)
            .map(|(k, r)| (k.frame, self.rc.raw_from_rotations(r), vec![true; d]))
            .collect();
        // Values: the keys' raw values interpolated between keys as the
        // model was trained (the manifest's base); then the distance
        // transform, as in the dense format.
        let mut dense_rot = dense_channels(&rot_rows, d, n, &self.norm);
        let base = base_channels(&rot_rows, d, n, self.base);
        dense_rot[..d * n].copy_from_slice(&base);
        let dna = self.dna(req)?;
        let k = dna.len() / p;
        let mut out = self.generator.run(&[
            TensorF32::new(dense, vec![1, 2 * p, n])?,
            TensorF32::new(dense_rot, vec![1, 2 * d, n])?,
            TensorF32::new(dna, vec![1, k, p])?,
        ])?;
        let raw = &mut out[0];
        if raw.shape != [1, d, n] {
            return Err(Error::Model(format!(
                "generator output {:?}, expected [1, {d}, {n}]",
                raw.shape
            )));
        }
        let t1 = now_ms();
        let mut rotations = Vec::with_capacity(n);
        let mut frame = vec![0.0f32; d];
        let mut local_in = vec![0.0f32; p * n];
        for t in 0..n {
            for c in 0..d {
                frame[c] = raw.data[c * n + t];
            }
            let rots = self.rc.local_rotations(&frame)?;
            let pos = self.rc.fk(&rots, [0.0; 3]);
            for c in 0..p {
                local_in[c * n + t] = pos[c] / self.norm.scale;
            }
            rotations.push(rots);
        }
        let t2 = now_ms();
        let vel = &self
            .path
            .run(&[TensorF32::new(local_in.clone(), vec![1, p, n])?])?[0];
        let anchor = req.keys.iter().find(|k| k.has_root());
        let (t_anchor, r_anchor) = match anchor {
            Some(k) => (
                k.frame,
                [
                    k.positions[0] as f64,
                    k.positions[1] as f64,
                    k.positions[2] as f64,
                ],
            ),
            None => (0, [0.0; 3]),
        };
        let mut cum = vec![[0.0f64; 3]; n];
        for t in 1..n {
            for c in 0..3 {
                cum[t][c] = cum[t - 1][c] + vel.data[c * n + t - 1] as f64 * self.norm.scale as f64;
            }
        }
        let mut root: Vec<[f64; 3]> = (0..req.frames)
            .map(|t| [0, 1, 2].map(|c| r_anchor[c] + cum[t][c] - cum[t_anchor][c]))
            .collect();
        post::scale_root_deviation(&mut root, &req.keys, variation as f64);
        rotations.truncate(req.frames);
        self.blend_pose(&mut rotations, &req.keys, variation)?;
        let mut motion = Motion { root, rotations };
        let t3 = now_ms();
        let key_error_raw = self.key_error(&motion, &req.keys);
        let mut foot_lock = FootLockStats::default();
        let key_error = if req.post_process {
            // 2-D keys become rotation keys fitted to their x/y (motion::xy)
            let keys = super::xy::pin_xy_keys(&motion, &self.template, &req.keys);
            post::make_keys_exact(&mut motion, &keys);
            if let Some(cfg) = &req.foot_lock {
                foot_lock = lock_feet(&mut motion, &self.template, &req.keys, cfg);
            }
            self.key_error(&motion, &req.keys)
        } else {
            key_error_raw.clone()
        };
        let t4 = now_ms();
        Ok(Output {
            motion,
            times: StageTimes {
                generator_ms: t1 - t0,
                rcfk_ms: t2 - t1,
                path_ms: t3 - t2,
                post_ms: t4 - t3,
            },
            key_error_raw,
            key_error,
            foot_lock,
            critical_frames: Vec::new(),
        })
    }

    /// The pose half of `variation`: every joint's local rotation slerped
    /// from SLERP+LERP between the whole-pose keys' rotations (0) to the
    /// networks' (1), extrapolating above 1. Without such keys there is no
    /// interpolation to blend with, and the pose is left as synthesized.
    fn blend_pose(
        &self,
        rotations: &mut [Vec<Mat3<f64>>],
        keys: &[Keyframe],
        variation: f32,
    ) -> Result<()> {
        let rot_keys: Vec<Keyframe> = rotation_keys(keys).map(|(k, _)| k.clone()).collect();
        if variation == 1.0 || rot_keys.is_empty() {
            return Ok(());
        }
        let plain = super::baseline::slerp_lerp(&rot_keys, rotations.len())?;
        for (frame, plain) in rotations.iter_mut().zip(&plain.rotations) {
            for (r, p) in frame.iter_mut().zip(plain) {
                let q = slerp(&matrix_to_quat(p), &matrix_to_quat(r), variation as f64);
                *r = quat_to_matrix_unit(&q);
            }
        }
        Ok(())
    }

    fn dna(&self, req: &Request) -> Result<Vec<f32>> {
        let p = 3 * self.joints();
        let s = self.norm.scale;
        if let Some(d) = &req.dna {
            return super::dna_input(d, p, s);
        }
        // The whole-pose keys, without root rotation, serve as DNA.
        let mut flat: Vec<f32> = req
            .keys
            .iter()
            .filter(|k| k.mask.iter().all(|m| *m))
            .flat_map(|k| super::dna_pose(k).into_iter().map(|v| v / s))
            .collect();
        if flat.is_empty() {
            flat = vec![0.0; p];
        }
        Ok(flat)
    }

    /// Mean key errors of a motion.
    pub fn key_error(&self, m: &Motion, keys: &[Keyframe]) -> KeyError {
        key_error(m, keys, &self.rc.parents, &self.rc.offsets)
    }
}

/// Mean key errors of a motion on a skeleton given by parents and offsets:
/// the root's position at keys that give it, and joint positions relative
/// to the root over the coordinates each key gives (x and y for 2-D keys).
pub fn key_error(
    m: &Motion,
    keys: &[Keyframe],
    parents: &[Option<usize>],
    offsets: &[[f64; 3]],
) -> KeyError {
    let (mut re, mut rn, mut le, mut ln) = (0.0, 0usize, 0.0, 0usize);
    for k in keys.iter().filter(|k| k.frame < m.len()) {
        if k.has_root() {
            let r = m.root[k.frame];
            re += (0..3)
                .map(|c| (r[c] - k.positions[c] as f64).powi(2))
                .sum::<f64>()
                .sqrt();
            rn += 1;
        }
        let pos = m.local_positions(k.frame, parents, offsets);
        // over the coordinates the key gives (x and y for 2-D keys)
        for (jj, q) in pos.iter().enumerate().skip(1) {
            let given: Vec<usize> = (0..3).filter(|&c| k.mask[3 * jj + c]).collect();
            if !given.is_empty() {
                le += given
                    .iter()
                    .map(|&c| (q[c] - k.positions[3 * jj + c] as f64).powi(2))
                    .sum::<f64>()
                    .sqrt();
                ln += 1;
            }
        }
    }
    KeyError {
        root: if rn > 0 { re / rn as f64 } else { 0.0 },
        local: if ln > 0 { le / ln as f64 } else { 0.0 },
    }
}
