//! Keyframe in-betweening (thesis ch. 5): keyframes, the dense input format,
//! the network pipeline, post-processing, and the interpolation baselines.
//!
//! - [`Keyframe`]: a pose at a frame, full or partial (per-coordinate mask).
//! - [`dense`]: the dense keyframe input of Fig. 5.3.
//! - [`pipeline`]: generator → RC-FK → path predictor → integrated root →
//!   post-processing, on ONNX models run by tract.
//! - [`residual`]: a supervised residual on SLERP+LERP (issue 19, stage 1).
//! - [`plan`]: which pipeline serves a request, at which variation (the
//!   one place that decides it); [`serve`] runs the plan.
//! - [`baseline`]: SLERP+LERP and zero-velocity.
//! - [`clip`]: keys from frames of a user's clip, the result spliced back (any frame rate).
//! - [`post`]: the correction that makes keyframes exact (Sec. 5.2.6).
//! - [`keys`]: the keys file (JSON) of the CLI and the examples.
//! - [`manifest`]: the networks' manifest, checked without the runtime.
//! - [`feet`]: foot locking (contacts pinned by two-bone IK; not in the thesis).
//! - [`fill`]: gaps in captured motion filled from the frames around them;
//!   [`fill_mlp`], the short-gap fill network it runs.

pub mod baseline;
pub mod clip;
pub mod cond;
pub mod dense;
pub mod dna;
pub mod edit;
pub mod feet;
pub mod fill;
#[cfg(feature = "onnx")]
pub mod fill_mlp;
pub mod keys;
pub mod manifest;
#[cfg(feature = "onnx")]
pub mod pipeline;
pub mod plan;
pub mod post;
#[cfg(feature = "onnx")]
pub mod residual;
#[cfg(feature = "onnx")]
pub mod serve;
pub mod spline;
pub mod xy;

use crate::error::{Error, Result};
use crate::rotation::{mul_vec, Mat3};
use crate::skeleton::Bvh;
use feet::FootLock;

/// The longest motion deeprep synthesizes or interpolates: 36,000 frames
/// (10 minutes at 60 fps). Longer requests are errors, so memory and time
/// stay bounded whatever a caller asks for.
pub const MAX_FRAMES: usize = 36_000;

/// Checks a requested motion length against [`MAX_FRAMES`].
pub fn check_frames(frames: usize) -> Result<()> {
    if frames > MAX_FRAMES {
        return Err(Error::Invalid(format!(
            "{frames} frames requested; deeprep synthesizes at most {MAX_FRAMES} (10 minutes at 60 fps)"
        )));
    }
    Ok(())
}

/// Longest allowed gap between consecutive keys for the networks, frames
/// (10 s at 60 fps, the thesis' 600-frame sampling bound, inside its
/// 636-frame reach).
pub const MAX_GAP: usize = 600;

/// The longest gap between keys hierarchical synthesis takes (Sec. 5.4.3:
/// critical frames first, then the shorter intervals): 3,000 frames, 50 s.
pub const MAX_LONG_GAP: usize = 3000;

/// A synthesis request.
#[derive(Clone, Debug)]
pub struct Request {
    /// Keyframes, sorted by frame.
    pub keys: Vec<Keyframe>,
    /// Output length in frames (60 fps).
    pub frames: usize,
    /// Motion DNA: representative local poses without root rotation
    /// (`joints × 3` each, BVH units). `None`: the whole-pose keys serve.
    pub dna: Option<Vec<Vec<f32>>>,
    /// Apply the post-processing that makes keys exact.
    pub post_process: bool,
    /// After that post-processing, pin feet in contact ([`feet`]);
    /// `None`: leave the feet as synthesized. Ignored without post-processing.
    pub foot_lock: Option<FootLock>,
    /// How much of the networks' departure from plain interpolation to
    /// keep, in [0, 2]: each joint's local rotation is slerped from
    /// SLERP+LERP between the whole-pose keys (0) to the generator's (1),
    /// and the root path's deviation from the keys' root positions
    /// interpolated linearly is scaled by it. 1 is the networks as trained;
    /// 0 is SLERP+LERP; above 1 extrapolates. `None` takes the model's
    /// default (`TweenModels::default_variation`).
    pub variation: Option<f32>,
}

impl Request {
    /// Checks the request for a skeleton of `joints` joints and returns the
    /// variation it runs at (`default` when it names none): the length, the
    /// keys, the variation's range and the gaps between keys.
    pub fn validate(&self, joints: usize, default: f32) -> Result<f32> {
        if self.frames == 0 {
            return Err(Error::Invalid("the requested length is 0 frames".into()));
        }
        validate_keys(&self.keys, self.frames, joints)?;
        let variation = self.variation.unwrap_or(default);
        check_variation(variation)?;
        check_long_gaps(&self.keys)?;
        if let Some(d) = &self.dna {
            if d.iter().any(|p| p.len() != 3 * joints) {
                return Err(Error::Shape {
                    what: "Motion DNA poses".into(),
                    expected: format!("{} numbers each ({joints} joints × 3)", 3 * joints),
                    found: "other lengths".into(),
                });
            }
        }
        Ok(variation)
    }
}

/// A keyframe.
#[derive(Clone, Debug)]
pub struct Keyframe {
    /// Frame index in the output.
    pub frame: usize,
    /// Joint positions, `joints × 3`, BVH units: joint 0 is the root's
    /// global position, every other joint is relative to the root (world
    /// orientation).
    pub positions: Vec<f32>,
    /// Which of the `joints × 3` coordinates are given (partial keys: root
    /// only, chosen joints, 2-D x/y only).
    pub mask: Vec<bool>,
    /// Local rotations (BVH joint frames) when the key is a whole pose with
    /// rotations (keys taken from a BVH); used to make keys exact.
    pub rotations: Option<Vec<Mat3<f64>>>,
}

impl Keyframe {
    /// A whole-pose key from frame `src` of a BVH clip, placed at `frame`.
    pub fn from_bvh(bvh: &Bvh, src: usize, frame: usize) -> Result<Keyframe> {
        if src >= bvh.frame_count() {
            return Err(Error::Invalid(format!(
                "key frame {src} is outside the clip's {} frames",
                bvh.frame_count()
            )));
        }
        let pose = crate::skeleton::Pose::read(bvh, bvh.frame(src));
        let g = pose.global(bvh);
        let root = g.positions[0];
        let mut positions = Vec::with_capacity(3 * bvh.joints.len());
        for (i, p) in g.positions.iter().enumerate() {
            let q = if i == 0 { *p } else { *p - root };
            positions.extend_from_slice(&[q.x as f32, q.y as f32, q.z as f32]);
        }
        let rotations = pose.rotation_matrices();
        Ok(Keyframe {
            frame,
            mask: vec![true; positions.len()],
            positions,
            rotations: Some(rotations),
        })
    }

    /// A root-only key (Sec. 5.4.1): the root's global position at `frame`,
    /// nothing else, on a skeleton of `joints` joints.
    pub fn root_only(frame: usize, root: [f32; 3], joints: usize) -> Keyframe {
        let mut positions = vec![0.0; 3 * joints];
        let mut mask = vec![false; 3 * joints];
        positions[..3].copy_from_slice(&root);
        mask[..3].fill(true);
        Keyframe {
            frame,
            positions,
            mask,
            rotations: None,
        }
    }

    /// A 2-D key (Sec. 5.4.2, the front view): global x and y of some
    /// joints (`xy[j]`, `None` where not given; joint 0 is the root), and
    /// optionally the root's global position. Joint coordinates are stored
    /// relative to the root, so a key that gives any other joint must give
    /// the root's x and y (in `root` or `xy[0]`). Depth (z) stays unknown.
    pub fn xy(frame: usize, xy: &[Option<[f32; 2]>], root: Option<[f32; 3]>) -> Result<Keyframe> {
        let joints = xy.len();
        if joints == 0 {
            return Err(Error::Invalid("a 2-D key needs one entry per joint".into()));
        }
        let mut positions = vec![0.0; 3 * joints];
        let mut mask = vec![false; 3 * joints];
        let root_xy = match (root, xy[0]) {
            (Some(r), _) => Some([r[0], r[1]]),
            (None, r) => r,
        };
        if let Some(r) = root {
            positions[..3].copy_from_slice(&r);
            mask[..3].fill(true);
        } else if let Some([x, y]) = xy[0] {
            positions[..2].copy_from_slice(&[x, y]);
            mask[..2].fill(true);
        }
        for (j, p) in xy.iter().enumerate().skip(1) {
            if let Some([x, y]) = p {
                let [rx, ry] = root_xy.ok_or_else(|| {
                    Error::Invalid(format!(
                        "a 2-D key at frame {frame} gives joint {j} but not the root's x and y"
                    ))
                })?;
                positions[3 * j] = x - rx;
                positions[3 * j + 1] = y - ry;
                mask[3 * j] = true;
                mask[3 * j + 1] = true;
            }
        }
        crate::error::check_finite(&format!("2-D key at frame {frame}"), &positions)?;
        Ok(Keyframe {
            frame,
            positions,
            mask,
            rotations: None,
        })
    }

    /// True when the key gives every coordinate (a whole pose).
    pub fn is_whole_pose(&self) -> bool {
        self.mask.iter().all(|&m| m)
    }

    /// True when the root's x, y and z are all given.
    pub fn has_root(&self) -> bool {
        self.mask.len() >= 3 && self.mask[0] && self.mask[1] && self.mask[2]
    }
}

/// Synthesized motion: per frame, the root position and every joint's local
/// rotation (BVH joint frames).
#[derive(Clone, Debug)]
pub struct Motion {
    /// Root positions.
    pub root: Vec<[f64; 3]>,
    /// Local rotations, `frames × joints`.
    pub rotations: Vec<Vec<Mat3<f64>>>,
}

impl Motion {
    /// Number of frames.
    pub fn len(&self) -> usize {
        self.root.len()
    }

    /// True when there are no frames.
    pub fn is_empty(&self) -> bool {
        self.root.is_empty()
    }

    /// Every frame on `template`'s skeleton as the [`Pose`] its BVH row
    /// ([`Motion::to_bvh`]) reads back as, without the Euler round trip:
    /// the root at its position, other joints at their offsets, and joints
    /// without three rotation channels (which their row cannot turn) at the
    /// identity. Errors when a frame does not have the template's joints.
    pub fn poses<'a>(
        &'a self,
        template: &'a Bvh,
    ) -> Result<impl Iterator<Item = crate::skeleton::Pose> + 'a> {
        use crate::skeleton::pose::{offset, rotation_order};
        let joints = template.joints.len();
        if let Some(r) = self.rotations.iter().find(|r| r.len() != joints) {
            return Err(Error::Shape {
                what: "motion".into(),
                expected: format!("{joints} joints"),
                found: format!("{}", r.len()),
            });
        }
        let rest: Vec<glam::DVec3> = template.joints.iter().map(offset).collect();
        let turns: Vec<bool> = (0..joints)
            .map(|j| rotation_order(template, j).is_some())
            .collect();
        Ok((0..self.len()).map(move |f| {
            let mut translations = rest.clone();
            if let Some(t) = translations.first_mut() {
                *t = glam::DVec3::from(self.root[f]);
            }
            let rotations = self.rotations[f]
                .iter()
                .zip(&turns)
                .map(|(r, &turns)| {
                    if turns {
                        crate::rotation::to_glam_f64(r)
                    } else {
                        glam::DMat3::IDENTITY
                    }
                })
                .collect();
            crate::skeleton::Pose {
                translations,
                rotations,
            }
        }))
    }

    /// Writes the motion as BVH channels on `template`'s skeleton (its
    /// channel orders; root position channels get `root − offset`).
    pub fn to_bvh(&self, template: &Bvh, frame_time: f64) -> Result<Bvh> {
        let mut out = template.clone();
        out.frame_time = frame_time;
        let c = template.channel_count();
        out.motion = Vec::with_capacity(c * self.len());
        let orders = crate::skeleton::pose::rotation_orders(template);
        for pose in self.poses(template)? {
            out.motion
                .extend(pose.to_row_with_orders(template, &orders)?);
        }
        Ok(out)
    }

    /// Global rotations and positions of one frame on a skeleton given by
    /// parents and offsets (the root at its position).
    pub fn global_pose(
        &self,
        f: usize,
        parents: &[Option<usize>],
        offsets: &[[f64; 3]],
    ) -> (Vec<Mat3<f64>>, Vec<[f64; 3]>) {
        let n = parents.len();
        let mut rot = vec![crate::rotation::identity::<f64>(); n];
        let mut pos = vec![[0.0; 3]; n];
        for j in 0..n {
            match parents[j] {
                None => {
                    rot[j] = self.rotations[f][j];
                    pos[j] = self.root[f];
                }
                Some(p) => {
                    let t = mul_vec(&rot[p], &offsets[j]);
                    pos[j] = [pos[p][0] + t[0], pos[p][1] + t[1], pos[p][2] + t[2]];
                    rot[j] = crate::rotation::mul(&rot[p], &self.rotations[f][j]);
                }
            }
        }
        (rot, pos)
    }

    /// Frame `f` as a whole-pose key placed at `frame` (its root, every
    /// joint's position relative to the root and its local rotations), on a
    /// skeleton given by parents and offsets.
    pub fn key_at(
        &self,
        f: usize,
        frame: usize,
        parents: &[Option<usize>],
        offsets: &[[f64; 3]],
    ) -> Keyframe {
        let rel = self.local_positions(f, parents, offsets);
        let mut positions: Vec<f32> = rel.iter().flat_map(|p| p.map(|v| v as f32)).collect();
        positions[..3].copy_from_slice(&self.root[f].map(|v| v as f32));
        Keyframe {
            frame,
            mask: vec![true; positions.len()],
            positions,
            rotations: Some(self.rotations[f].clone()),
        }
    }

    /// Local joint positions (root at 0, world orientation) of one frame on
    /// a skeleton given by parents and offsets.
    pub fn local_positions(
        &self,
        f: usize,
        parents: &[Option<usize>],
        offsets: &[[f64; 3]],
    ) -> Vec<[f64; 3]> {
        let r = self.root[f];
        let (_, pos) = self.global_pose(f, parents, offsets);
        pos.into_iter()
            .map(|p| [p[0] - r[0], p[1] - r[1], p[2] - r[2]])
            .collect()
    }
}

/// The Motion DNA form of a whole-pose key (Sec. 5.2.5, Λ): joint
/// positions relative to the root with the root rotation removed,
/// `joints × 3`, BVH units (joint 0 is 0). Without rotations the root
/// rotation is taken as the identity.
pub fn dna_pose(k: &Keyframe) -> Vec<f32> {
    let rt = k
        .rotations
        .as_ref()
        .map(|r| crate::rotation::transpose(&r[0]));
    let j = k.positions.len() / 3;
    let mut out = Vec::with_capacity(3 * j);
    for jj in 0..j {
        let v = if jj == 0 {
            [0.0; 3]
        } else {
            [
                k.positions[3 * jj] as f64,
                k.positions[3 * jj + 1] as f64,
                k.positions[3 * jj + 2] as f64,
            ]
        };
        let v = match &rt {
            Some(m) => mul_vec(m, &v),
            None => v,
        };
        out.extend(v.iter().map(|x| *x as f32));
    }
    out
}

/// Motion DNA poses ([`dna_pose`] form, `p` numbers each) as one flat
/// network input divided by `scale`: one or more poses of the right size,
/// every number finite, or an error that says which.
pub fn dna_input(dna: &[Vec<f32>], p: usize, scale: f32) -> Result<Vec<f32>> {
    if dna.is_empty() || dna.iter().any(|f| f.len() != p) {
        return Err(Error::Shape {
            what: "Motion DNA".into(),
            expected: format!("one or more poses of {p} numbers"),
            found: format!("{} poses", dna.len()),
        });
    }
    let flat: Vec<f32> = dna.iter().flatten().map(|v| v / scale).collect();
    crate::error::check_finite("Motion DNA", &flat)?;
    Ok(flat)
}

/// Checks a variation by [`crate::error::check_option`]'s rule: in [0, 2]
/// (1: the networks as trained, 0: plain interpolation).
pub fn check_variation(variation: f32) -> Result<()> {
    crate::error::check_option(
        "variation (1: the networks as trained, 0: plain interpolation)",
        variation as f64,
        0.0,
        2.0,
    )
}

/// The largest key coordinate taken (BVH units, about centimetres: 10 km).
/// Past it the networks' inputs leave every range they were trained on and
/// float32 arithmetic loses the motion's detail.
pub const MAX_KEY_COORD: f32 = 1e6;

/// An error when two consecutive keys are more than [`MAX_LONG_GAP`] frames
/// apart (what no pipeline reaches, hierarchically or not).
pub fn check_long_gaps(keys: &[Keyframe]) -> Result<()> {
    for w in keys.windows(2) {
        let gap = w[1].frame.saturating_sub(w[0].frame);
        if gap > MAX_LONG_GAP {
            return Err(Error::Invalid(format!(
                "keys at frames {} and {} are {gap} frames apart; the model reaches {MAX_GAP} frames (10 s at 60 fps) directly and {MAX_LONG_GAP} (50 s) hierarchically",
                w[0].frame, w[1].frame
            )));
        }
    }
    Ok(())
}

/// Checks a key set against a length and a joint count: sorted, unique,
/// inside the length, finite, within [`MAX_KEY_COORD`], the right size.
pub fn validate_keys(keys: &[Keyframe], frames: usize, joints: usize) -> Result<()> {
    check_frames(frames)?;
    if keys.is_empty() {
        return Err(Error::Invalid("no keyframes given".into()));
    }
    for (i, k) in keys.iter().enumerate() {
        if k.frame >= frames {
            return Err(Error::Invalid(format!(
                "keyframe {i} is at frame {} but the motion has {frames} frames",
                k.frame
            )));
        }
        if i > 0 && k.frame <= keys[i - 1].frame {
            return Err(Error::Invalid(format!(
                "keyframes must be sorted with no duplicates: keyframe {i} (frame {}) follows frame {}",
                k.frame,
                keys[i - 1].frame
            )));
        }
        if k.positions.len() != 3 * joints || k.mask.len() != 3 * joints {
            return Err(Error::Shape {
                what: format!("keyframe {i}"),
                expected: format!(
                    "{} positions and mask entries ({joints} joints)",
                    3 * joints
                ),
                found: format!(
                    "{} positions, {} mask entries",
                    k.positions.len(),
                    k.mask.len()
                ),
            });
        }
        crate::error::check_finite(&format!("keyframe {i} positions"), &k.positions)?;
        if let Some(v) = k.positions.iter().find(|v| v.abs() > MAX_KEY_COORD) {
            return Err(Error::Invalid(format!(
                "keyframe {i} (frame {}): coordinate {v:e} is beyond ±{MAX_KEY_COORD:e} units (BVH units, about centimetres)",
                k.frame
            )));
        }
        if let Some(r) = &k.rotations {
            if r.len() != joints {
                return Err(Error::Shape {
                    what: format!("keyframe {i} rotations"),
                    expected: format!("{joints}"),
                    found: format!("{}", r.len()),
                });
            }
        }
    }
    Ok(())
}
