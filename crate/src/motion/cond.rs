//! One conditional in-betweening network for every kind of key (issue 47;
//! `train/deeprep_train/motion/cond.py`, whose docstring defines the input).
//!
//! Each key is one of three kinds:
//! - **pose**: a whole pose with rotations;
//! - **root**: the root's global position only (a root path);
//! - **xy**: the root's position and every joint's front-view x and y.
//!
//! The network reads a base (the keys' root positions lerped, the pose
//! keys' rotations slerped, or the training takes' mean pose where no key
//! gives a pose), the phase of each frame towards each kind of key, and
//! the keyed joints' x and y lerped between the keys that give them; it
//! outputs a residual on the base root and 6D rotations. The root's
//! residual is gated to 0 at every key and the rotations' at every pose
//! key, so root positions and poses are exact by construction; 2-D keys
//! are pinned afterwards ([`super::xy`], [`super::post::make_keys_exact`]).
//!
//! `variation` scales the residual: 0 gives the base (a mannequin sliding
//! along the root path where no pose is keyed), 1 the network as trained.

use super::Keyframe;
use crate::error::{Error, Result};
use serde::Deserialize;

#[cfg(feature = "onnx")]
pub use model::CondModel;

/// What a key gives, as the network reads it.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum KeyClass {
    /// A whole pose with rotations.
    Pose,
    /// The root's position only.
    Root,
    /// The root's position and every other joint's x and y.
    Xy,
}

/// The class of `k`, or `None` when it gives something else (some joints
/// only, a root without its depth, positions without rotations).
pub fn classify(k: &Keyframe) -> Option<KeyClass> {
    let joints = k.mask.len() / 3;
    if !k.has_root() {
        return None;
    }
    if k.is_whole_pose() {
        return k.rotations.is_some().then_some(KeyClass::Pose);
    }
    let given = |j: usize, c: usize| k.mask[3 * j + c];
    if (1..joints).all(|j| !given(j, 0) && !given(j, 1) && !given(j, 2)) {
        return Some(KeyClass::Root);
    }
    if (1..joints).all(|j| given(j, 0) && given(j, 1)) {
        return Some(KeyClass::Xy);
    }
    None
}

/// Whether the conditional network can take `keys`: every key a whole pose,
/// a root position or a 2-D key of every joint ([`classify`]), no Motion
/// DNA (it has no DNA input yet), no gap over [`MAX_GAP`](crate::motion::MAX_GAP)
/// frames.
pub fn cond_takes(keys: &[Keyframe], dna: bool) -> bool {
    cond_reads(keys, dna)
        && keys
            .windows(2)
            .all(|w| w[1].frame.abs_diff(w[0].frame) <= crate::motion::MAX_GAP)
}

/// Whether `keys` are whole poses with rotations, without Motion DNA, with a
/// gap over [`MAX_GAP`](crate::motion::MAX_GAP) frames: what the residual
/// network cannot take and the conditional network's hierarchy can.
pub fn long_gap_keys(keys: &[Keyframe], dna: bool) -> bool {
    cond_reads(keys, dna)
        && keys
            .iter()
            .all(|k| k.rotations.is_some() && k.is_whole_pose())
        && keys
            .windows(2)
            .any(|w| w[1].frame.abs_diff(w[0].frame) > crate::motion::MAX_GAP)
}

/// Whether `keys` are each a whole pose with rotations or a root position,
/// at least one a root position (a path drawn on the ground, with or without
/// poses), without Motion DNA and without a gap over
/// [`MAX_GAP`](crate::motion::MAX_GAP) frames: what a manifest's
/// `default_for_root_keys` gives the conditional network under `model`.
pub fn root_keys(keys: &[Keyframe], dna: bool) -> bool {
    let classes: Vec<Option<KeyClass>> = keys.iter().map(classify).collect();
    cond_takes(keys, dna)
        && classes
            .iter()
            .all(|c| matches!(c, Some(KeyClass::Pose | KeyClass::Root)))
        && classes.contains(&Some(KeyClass::Root))
}

/// Whether `keys` come with Motion DNA and are keys the conditional network
/// reads (whole poses, root positions, 2-D keys of every joint), no gap over
/// [`MAX_GAP`](crate::motion::MAX_GAP) frames: what a manifest's
/// `default_for_dna` gives the DNA network under `model` (longer gaps with
/// DNA stay with the generator's hierarchy).
pub fn dna_keys(keys: &[Keyframe], dna: bool) -> bool {
    dna && cond_takes(keys, false)
}

fn cond_reads(keys: &[Keyframe], dna: bool) -> bool {
    !dna && !keys.is_empty() && keys.iter().all(|k| classify(k).is_some())
}

// without the runtime only the planner's fields are read
#[cfg_attr(not(feature = "onnx"), allow(dead_code))]
#[derive(Deserialize)]
struct Manifest {
    kind: String,
    skeleton_bvh: String,
    rotating: Vec<usize>,
    scale: f64,
    gate_frames: f64,
    phase_frames: f64,
    noise_channels: usize,
    joints: usize,
    /// The training takes' mean local rotation per rotating joint, row-major.
    prior: Vec<Vec<f64>>,
    #[serde(default)]
    variation: Option<f32>,
    /// Whether `method: model` runs this network for root-only and 2-D keys.
    #[serde(default)]
    default_for_partial_keys: bool,
    /// Whether `method: model` runs this network (its hierarchy) for
    /// whole-pose keys with a gap over [`MAX_GAP`](crate::motion::MAX_GAP)
    /// frames.
    #[serde(default)]
    default_for_long_gaps: bool,
    /// Whether `method: model` runs this network for root-only keys (with
    /// or without whole poses among them; [`root_keys`]).
    #[serde(default)]
    default_for_root_keys: bool,
    /// Whether `method: model` runs this network for requests with Motion
    /// DNA ([`dna_keys`]; the DNA network, `tween_cond_dna`).
    #[serde(default)]
    default_for_dna: bool,
    /// The base over gaps with a whole-pose context frame: "slerp" (the
    /// default) or "hermite" ([`crate::motion::fill::hermite_curve`]).
    #[serde(default)]
    context_base: Option<String>,
    /// A gap-filling network's (`tween_fill`): the longest gap the `model`
    /// fill gives it ([`crate::motion::fill::method_for`]).
    #[serde(default)]
    fill_up_to: Option<usize>,
    /// ... and the shortest (default 1).
    #[serde(default)]
    fill_from: Option<usize>,
    /// Whether it was trained on the hierarchy's coarse rates too (its phase
    /// distances in 60 fps frames when a pass' frames are further apart;
    /// `cond.py --coarse-every`), so the coarse pass tells it the rate.
    #[serde(default)]
    coarse_rates: bool,
    /// Whether it takes Motion DNA (`cond.py --dna-share`): inputs `dna`
    /// ([1, k, 3J], each pose's joints relative to the root with the root's
    /// rotation removed, / scale) and `dna_w` ([1, k, frames], which poses
    /// steer each frame: [`crate::motion::dna::frame_weights`]).
    #[serde(default)]
    dna: bool,
    /// With `dna`: how far each DNA pose steers the output, in a pass'
    /// frames ([`crate::motion::dna::frame_weights`]; 0: every pose every
    /// frame, one code).
    #[serde(default)]
    dna_window: Option<usize>,
}

impl Manifest {
    /// The gap lengths the `model` fill gives a gap-filling network:
    /// `fill_from..=fill_up_to`, checked.
    fn fill_gaps(&self) -> Result<Option<(usize, usize)>> {
        crate::motion::fill::band(self.fill_from, self.fill_up_to)
            .map_err(|e| Error::Invalid(format!("conditional network manifest: {e}")))
    }
}

/// Gaps with context (issue 50; `cond.py`'s `context_spans`): consecutive
/// keys `i`, `i + 1`, both whole poses, more than a frame apart, with a
/// whole-pose key on the frame before the first or after the second.
/// Returns (i, i + 1, the key before, the key after) as key indices.
pub fn context_spans(
    keys: &[Keyframe],
    classes: &[KeyClass],
) -> Vec<(usize, usize, Option<usize>, Option<usize>)> {
    let pose_at = |i: usize, frame: usize| {
        (classes[i] == KeyClass::Pose && keys[i].frame == frame).then_some(i)
    };
    (0..keys.len().saturating_sub(1))
        .filter_map(|i| {
            let (a, b) = (keys[i].frame, keys[i + 1].frame);
            if classes[i] != KeyClass::Pose || classes[i + 1] != KeyClass::Pose || b <= a + 1 {
                return None;
            }
            let prev = i.checked_sub(1).and_then(|k| pose_at(k, a.wrapping_sub(1)));
            let next = (i + 2 < keys.len())
                .then(|| pose_at(i + 2, b + 1))
                .flatten();
            (prev.is_some() || next.is_some()).then_some((i, i + 1, prev, next))
        })
        .collect()
}

/// What the request planner needs of the conditional network.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct CondInfo {
    /// Its default variation.
    pub variation: f32,
    /// Whether the `model` method runs it for the partial keys it takes.
    pub default_for_partial_keys: bool,
    /// Whether the `model` method runs it for whole-pose keys with a gap
    /// over [`MAX_GAP`](crate::motion::MAX_GAP) frames ([`long_gap_keys`]).
    pub default_for_long_gaps: bool,
    /// Whether the `model` method runs it for root positions, alone or with
    /// whole poses ([`root_keys`]).
    pub default_for_root_keys: bool,
    /// Whether the `model` method runs it for requests with Motion DNA
    /// ([`dna_keys`]).
    pub default_for_dna: bool,
    /// A gap-filling network's shortest and longest gap under the `model`
    /// fill (its manifest's `fill_from`, default 1, and `fill_up_to`).
    pub fill_gaps: Option<(usize, usize)>,
    /// Whether it takes Motion DNA (its manifest's `dna`).
    pub dna: bool,
}

impl CondInfo {
    /// This network as the DNA network (`tween_cond_dna`, for requests with
    /// Motion DNA): an error unless its manifest says `dna`.
    pub fn as_dna_network(self) -> Result<Self> {
        if self.dna {
            Ok(self)
        } else {
            Err(Error::Invalid(
                "the DNA network's manifest does not say dna (it was trained without Motion DNA)"
                    .into(),
            ))
        }
    }
}

/// What the request planner needs of a conditional network's manifest text
/// (without loading the network).
pub fn info_of_manifest(json: &str) -> Result<CondInfo> {
    let m: Manifest = serde_json::from_str(json)
        .map_err(|e| Error::Invalid(format!("conditional network manifest: {e}")))?;
    m.info()
}

impl Manifest {
    /// Its flags for the planner, checked: what both [`info_of_manifest`]
    /// and a loaded network's `info()` give.
    fn info(&self) -> Result<CondInfo> {
        let variation = self.variation.unwrap_or(1.0);
        crate::motion::check_variation(variation)
            .map_err(|e| Error::Invalid(format!("conditional network manifest: {e}")))?;
        Ok(CondInfo {
            variation,
            default_for_partial_keys: self.default_for_partial_keys,
            default_for_long_gaps: self.default_for_long_gaps,
            default_for_root_keys: self.default_for_root_keys,
            default_for_dna: self.default_for_dna,
            fill_gaps: self.fill_gaps()?,
            dna: self.dna,
        })
    }
}

/// The longest gap between keys the network runs in one pass: the longest
/// it was trained on (`residual.sample_keys`' 300 frames).
pub const HIER_GAP: usize = 300;
/// The longest gap of a hierarchical synthesis' coarse pass.
pub const COARSE_GAP: usize = 300;
/// The longest spacing of the critical keys a coarse pass gives.
pub const CRITICAL_SPACING: usize = 300;

/// The network itself (with the runtime).
#[cfg(feature = "onnx")]
mod model {
    use super::{classify, context_spans, CondInfo, KeyClass, Manifest};
    use super::{COARSE_GAP, CRITICAL_SPACING, HIER_GAP};
    use crate::error::{Error, Result};
    use crate::motion::baseline::slerp_lerp;
    use crate::motion::residual::{apply, from_sixd, mul, rot_y, sixd, transpose, V3};
    use crate::motion::{fill, Keyframe, Motion};
    use crate::rotation::{from_glam_f64, Mat3};
    use crate::runtime::{Model, TensorF32};
    use crate::skeleton::Bvh;
    use glam::{DMat3, DQuat, DVec3};

    /// The conditional in-betweening network with its skeleton.
    pub struct CondModel {
        net: Model,
        /// The skeleton as a BVH with no frames.
        pub template: Bvh,
        /// The template's parent per joint and rest offsets (what FK and the
        /// key errors read), kept from loading.
        pub parents: Vec<Option<usize>>,
        /// See `parents`.
        pub offsets: Vec<[f64; 3]>,
        rotating: Vec<usize>,
        scale: f64,
        gate_frames: f64,
        phase_frames: f64,
        noise: usize,
        prior: Vec<Mat3<f64>>,
        /// Its manifest's flags for the planner (default variation, what
        /// `model` runs it for, its fill band, whether it takes DNA).
        info: CondInfo,
        /// Whether its base over gaps with context is the Hermite curve.
        context_base: bool,
        coarse_rates: bool,
        dna_window: usize,
    }

    /// Motion DNA poses checked and scaled for the network (flat `[k, 3J]`).
    struct DnaPoses {
        flat: Vec<f32>,
        k: usize,
    }

    /// Per frame of a group of keys: (s, frames since the previous key / P,
    /// to the next / P, gate) and the previous / next key's index in the
    /// group; `cond.py`'s `group_phase`.
    struct Phase {
        ph: Vec<[f64; 4]>,
        ab: Vec<(usize, usize)>,
    }

    fn group_phase(group: &[usize], n: usize, gate_frames: f64, phase_frames: f64) -> Phase {
        let mut ph = Vec::with_capacity(n);
        let mut ab = Vec::with_capacity(n);
        if group.is_empty() {
            return Phase {
                ph: vec![[0.0; 4]; n],
                ab: vec![(0, 0); n],
            };
        }
        let last = group.len() - 1;
        for t in 0..n {
            let (a, b, s) = if t < group[0] {
                (0, 0, 0.0)
            } else if t > group[last] {
                (last, last, 1.0)
            } else if last == 0 {
                (0, 0, 0.0)
            } else {
                // the segment whose start is the last key at or before t (the
                // last segment at the last key), as residual.key_phase
                let seg = (group.partition_point(|&k| k <= t) - 1).min(last - 1);
                let (fa, fb) = (group[seg], group[seg + 1]);
                let s = ((t as f64 - fa as f64) / (fb as f64 - fa as f64)).clamp(0.0, 1.0);
                (seg, seg + 1, s)
            };
            let dp = (t as f64 - group[a] as f64).abs();
            let dn = (group[b] as f64 - t as f64).abs();
            let gate = 1.0 - (-dp.min(dn) / gate_frames).exp();
            ph.push([s, dp / phase_frames, dn / phase_frames, gate]);
            ab.push((a, b));
        }
        Phase { ph, ab }
    }

    impl CondModel {
        /// Loads the network (the bytes of `tween_cond.onnx`) and its manifest.
        pub fn new(onnx: &[u8], manifest_json: &str) -> Result<Self> {
            let bad = |m: String| Error::Invalid(format!("conditional network manifest: {m}"));
            let m: Manifest =
                serde_json::from_str(manifest_json).map_err(|e| bad(e.to_string()))?;
            if m.kind != "cond-tween" {
                return Err(bad(format!("kind '{}', expected 'cond-tween'", m.kind)));
            }
            let template = Bvh::parse(&m.skeleton_bvh)?;
            let j = template.joints.len();
            let with_channels: Vec<usize> = (0..j)
                .filter(|&i| !template.joints[i].channels.is_empty())
                .collect();
            if m.rotating != with_channels || m.rotating.first() != Some(&0) {
                return Err(bad(
                    "'rotating' must list the skeleton's joints with channels, the root first"
                        .into(),
                ));
            }
            if m.joints != j {
                return Err(bad(format!("{} joints, the skeleton has {j}", m.joints)));
            }
            if !(m.scale > 0.0 && m.gate_frames > 0.0 && m.phase_frames > 0.0) {
                return Err(bad(
                    "scale, gate_frames and phase_frames must be positive".into()
                ));
            }
            if m.noise_channels > 1024 {
                return Err(bad(format!("{} noise channels", m.noise_channels)));
            }
            if m.prior.len() != m.rotating.len()
                || m.prior
                    .iter()
                    .any(|r| r.len() != 9 || r.iter().any(|v| !v.is_finite()))
            {
                return Err(bad(format!(
                    "'prior' must hold {} finite 3 × 3 matrices",
                    m.rotating.len()
                )));
            }
            let info = m.info()?;
            let dna_window =
                match (m.dna, m.dna_window) {
                    (false, _) => 0,
                    (true, Some(w)) => w,
                    (true, None) => return Err(bad(
                        "'dna' without 'dna_window' (an export from before per-frame DNA weights: \
                         export it again with cond.py export)"
                            .into(),
                    )),
                };
            let context_base = match m.context_base.as_deref() {
                None | Some("slerp") => false,
                Some("hermite") => true,
                Some(other) => {
                    return Err(bad(format!(
                        "context_base '{other}', expected 'slerp' or 'hermite'"
                    )))
                }
            };
            let prior = m
                .prior
                .iter()
                .map(|r| std::array::from_fn(|a| std::array::from_fn(|b| r[3 * a + b])))
                .collect();
            let parents = template.joints.iter().map(|j| j.parent).collect();
            let offsets = template
                .joints
                .iter()
                .map(|j| j.offset.map(|v| v as f64))
                .collect();
            Ok(CondModel {
                net: Model::from_onnx_bytes(onnx)?,
                template,
                parents,
                offsets,
                rotating: m.rotating,
                scale: m.scale,
                gate_frames: m.gate_frames,
                phase_frames: m.phase_frames,
                noise: m.noise_channels,
                prior,
                info,
                context_base,
                coarse_rates: m.coarse_rates,
                dna_window,
            })
        }

        /// Loads `tween_cond.onnx` and its manifest from a folder.
        pub fn load_dir(dir: &std::path::Path) -> Result<Self> {
            Self::load_named(dir, "tween_cond")
        }

        /// Loads `NAME.onnx` and `NAME.manifest.json` from a folder (the
        /// gap-filling network is `tween_fill`).
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

        /// What the request planner needs of this network.
        pub fn info(&self) -> CondInfo {
            self.info
        }

        /// Over each gap with context ([`context_spans`]), the base root
        /// (`roots`: the keys' roots in the canonical frame) and rotations
        /// (the root's turned by `c`) on [`fill::hermite_curve`].
        fn hermite_base(
            &self,
            keys: &[Keyframe],
            classes: &[KeyClass],
            roots: &[V3],
            c: &Mat3<f64>,
            base_root: &mut [V3],
            base_rot: &mut [Vec<Mat3<f64>>],
        ) -> Result<()> {
            let quats = |i: usize| -> Result<Vec<DQuat>> {
                fill::key_quats(&keys[i])
                    .ok_or_else(|| Error::Invalid(format!("key {i} is a pose without rotations")))
            };
            for (a, b, p, q) in context_spans(keys, classes) {
                let (fa, fb) = (keys[a].frame, keys[b].frame);
                if fb > base_root.len() {
                    continue;
                }
                let (qa, qb) = (quats(a)?, quats(b)?);
                let qp = p.map(quats).transpose()?;
                let qn = q.map(quats).transpose()?;
                let v = |i: usize| DVec3::from_array(roots[i]);
                let ends = fill::HermiteEnds {
                    root: [v(a), v(b)],
                    rot: [&qa, &qb],
                    prev: p.zip(qp.as_deref()).map(|(i, r)| (v(i), r)),
                    next: q.zip(qn.as_deref()).map(|(i, r)| (v(i), r)),
                };
                for (k, (root, rot)) in fill::hermite_curve(&ends, fb - fa).into_iter().enumerate()
                {
                    let t = fa + 1 + k;
                    base_root[t] = root.to_array();
                    let mut r: Vec<Mat3<f64>> = rot
                        .iter()
                        .map(|q| from_glam_f64(&DMat3::from_quat(*q)))
                        .collect();
                    r[0] = mul(c, &r[0]);
                    base_rot[t] = r;
                }
            }
            Ok(())
        }

        fn input_channels(&self) -> usize {
            let k = self.rotating.len();
            let j = self.template.joints.len();
            3 + 6 * k + 4 + 1 + 4 + 1 + 4 + 2 * j + self.noise
        }

        /// In-betweens `keys` (each a pose, root or 2-D key, [`classify`]) over
        /// `frames` frames. Poses and root positions are exact; 2-D keys are
        /// exact after [`crate::motion::xy::pin_xy_keys`] and
        /// [`crate::motion::post::make_keys_exact`], which [`crate::motion::serve`] runs.
        ///
        /// `seed` draws the network's noise input (standard normal, constant
        /// over the request); `None` gives zero noise, the seedless output.
        ///
        /// Gaps over [`HIER_GAP`] frames are synthesized hierarchically
        /// (Sec. 5.4.3): first the whole request at 1/f of the frame rate
        /// (f = ⌈longest gap / [`COARSE_GAP`]⌉, so its gaps are ones the network
        /// was trained on), from which whole poses every at most
        /// [`CRITICAL_SPACING`] frames inside each long gap become critical
        /// keys; then the request at full rate with them. On training takes
        /// (keys 1,000 frames apart) this kept the limbs at 0.70 of the
        /// truth's speed where one pass gave 0.52 (whole poses) and 0.36
        /// (root positions), with a lower MPJPE (train/notes/cond.md).
        pub fn synthesize(
            &self,
            keys: &[Keyframe],
            frames: usize,
            variation: f32,
            seed: Option<u64>,
        ) -> Result<Motion> {
            self.synthesize_critical(keys, frames, variation, seed)
                .map(|(m, _)| m)
        }

        /// [`Self::synthesize`], with the frames of the critical keys its
        /// coarse pass made (empty when every gap ran in one pass), for a
        /// caller that shows them.
        pub fn synthesize_critical(
            &self,
            keys: &[Keyframe],
            frames: usize,
            variation: f32,
            seed: Option<u64>,
        ) -> Result<(Motion, Vec<usize>)> {
            self.synthesize_dna(keys, frames, variation, seed, None)
        }

        /// [`Self::synthesize_critical`] with Motion DNA: poses of `3J`
        /// numbers, each the joints' positions relative to the root with the
        /// root's rotation removed ([`crate::motion::dna_pose`]), which the
        /// network places in its output (thesis Sec. 5.2.5). An error when
        /// the network has no DNA input (its manifest's `dna`).
        pub fn synthesize_dna(
            &self,
            keys: &[Keyframe],
            frames: usize,
            variation: f32,
            seed: Option<u64>,
            dna: Option<&[Vec<f32>]>,
        ) -> Result<(Motion, Vec<usize>)> {
            crate::motion::check_variation(variation)?;
            let dna = self.dna_poses(dna)?;
            let dna = dna.as_ref();
            crate::motion::validate_keys(keys, frames, self.template.joints.len())?;
            crate::motion::check_long_gaps(keys)?;
            let longest = keys
                .windows(2)
                .map(|w| w[1].frame - w[0].frame)
                .max()
                .unwrap_or(0);
            if longest <= HIER_GAP {
                return Ok((
                    self.synthesize_flat(keys, frames, variation, seed, 1, dna)?,
                    Vec::new(),
                ));
            }
            let f = longest.div_ceil(COARSE_GAP);
            let coarse_frames = (frames - 1) / f + 1;
            let mut coarse: Vec<Keyframe> = Vec::with_capacity(keys.len());
            for k in keys {
                let c = ((k.frame as f64 / f as f64).round() as usize).min(coarse_frames - 1);
                // keys closer than f frames share a coarse frame: the first is kept
                if coarse.last().is_none_or(|p| p.frame < c) {
                    coarse.push(Keyframe {
                        frame: c,
                        ..k.clone()
                    });
                }
            }
            // a network trained at the coarse rates is told this pass' rate
            let rate = if self.coarse_rates { f } else { 1 };
            let rough = self.synthesize_flat(&coarse, coarse_frames, variation, seed, rate, dna)?;
            let mut all: Vec<Keyframe> = keys.to_vec();
            let mut critical = Vec::new();
            for w in keys.windows(2) {
                let (a, b) = (w[0].frame, w[1].frame);
                if b - a <= HIER_GAP {
                    continue;
                }
                let m = (b - a).div_ceil(CRITICAL_SPACING);
                for i in 1..m {
                    let c = ((a as f64 + i as f64 * (b - a) as f64 / m as f64) / f as f64).round()
                        as usize;
                    let t = c * f;
                    if c >= coarse_frames || t <= a || t >= b {
                        continue;
                    }
                    all.push(rough.key_at(c, t, &self.parents, &self.offsets));
                    critical.push(t);
                }
            }
            all.sort_by_key(|k| k.frame);
            critical.sort_unstable();
            Ok((
                self.synthesize_flat(&all, frames, variation, seed, 1, dna)?,
                critical,
            ))
        }

        /// One pass of the network over `frames` frames that are each `rate`
        /// frames of the 60 fps motion apart (the hierarchy's coarse pass):
        /// the keys' phase distances are given in 60 fps frames (`cond.py`'s
        /// `group_phase` rate). [`Self::synthesize`] runs it at rate 1, and at
        /// the coarse pass' rate when the manifest says `coarse_rates`.
        pub fn synthesize_at_rate(
            &self,
            keys: &[Keyframe],
            frames: usize,
            variation: f32,
            seed: Option<u64>,
            rate: usize,
        ) -> Result<Motion> {
            crate::motion::check_variation(variation)?;
            crate::motion::validate_keys(keys, frames, self.template.joints.len())?;
            if !(1..=64).contains(&rate) {
                return Err(Error::Invalid(format!("rate {rate}: expected 1 to 64")));
            }
            self.synthesize_flat(keys, frames, variation, seed, rate, None)
        }

        /// Motion DNA poses checked and scaled for the network; `None` for
        /// none given, or a network without DNA input (an error when poses
        /// are given to it).
        fn dna_poses(&self, dna: Option<&[Vec<f32>]>) -> Result<Option<DnaPoses>> {
            let p = 3 * self.template.joints.len();
            match dna {
                None => Ok(None),
                Some(_) if !self.info.dna => Err(Error::Invalid(
                    "this conditional network takes no Motion DNA (its manifest does not say dna); \
                     method generator does"
                        .into(),
                )),
                Some(d) => Ok(Some(DnaPoses {
                    flat: crate::motion::dna_input(d, p, self.scale as f32)?,
                    k: d.len(),
                })),
            }
        }

        /// The network's DNA inputs for a pass of `frames` frames (`dna`
        /// [1, k, 3J], `dna_w` [1, k, frames] by
        /// [`crate::motion::dna::frame_weights`] with the manifest's
        /// `dna_window`), or one zero pose at weight 0 for none; `None` for a
        /// network without DNA input.
        fn dna_feeds(
            &self,
            dna: Option<&DnaPoses>,
            frames: usize,
        ) -> Result<Option<(TensorF32, TensorF32)>> {
            if !self.info.dna {
                return Ok(None);
            }
            let p = 3 * self.template.joints.len();
            let (flat, w, k) = match dna {
                Some(d) => {
                    // window 0: every pose on every frame, which the network averages
                    let w = if self.dna_window == 0 {
                        vec![1.0; d.k * frames]
                    } else {
                        crate::motion::dna::frame_weights(d.k, frames, self.dna_window)
                    };
                    (d.flat.clone(), w, d.k)
                }
                None => (vec![0.0; p], vec![0.0; frames], 1),
            };
            Ok(Some((
                TensorF32::new(flat, vec![1, k, p])?,
                TensorF32::new(w, vec![1, k, frames])?,
            )))
        }

        /// One pass of the network over the whole request.
        fn synthesize_flat(
            &self,
            keys: &[Keyframe],
            frames: usize,
            variation: f32,
            seed: Option<u64>,
            rate: usize,
            dna: Option<&DnaPoses>,
        ) -> Result<Motion> {
            let joints = self.template.joints.len();
            let classes: Vec<KeyClass> = keys
                .iter()
                .enumerate()
                .map(|(i, k)| {
                    classify(k).ok_or_else(|| {
                        Error::Invalid(format!(
                            "the conditional network takes whole poses, root positions and 2-D keys of every joint; \
                             key {i} (frame {}) gives something else (the generator takes it: method generator)",
                            k.frame
                        ))
                    })
                })
                .collect::<Result<_>>()?;
            let n = frames;
            let (k, j) = (self.rotating.len(), joints);
            let all: Vec<usize> = (0..keys.len()).collect();
            let pk: Vec<usize> = all
                .iter()
                .copied()
                .filter(|i| classes[*i] == KeyClass::Pose)
                .collect();
            let xk: Vec<usize> = all
                .iter()
                .copied()
                .filter(|i| classes[*i] != KeyClass::Root)
                .collect();
            let any_x = classes.contains(&KeyClass::Xy);
            // the canonical frame: the first key's root x/z removed, and its
            // heading when it is a pose and no key is 2-D
            let k0 = &keys[0];
            let c = match (&k0.rotations, classes[0]) {
                (Some(r), KeyClass::Pose) if !any_x => rot_y(-r[0][0][2].atan2(r[0][2][2])),
                _ => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            };
            let ct = transpose(&c);
            let off = [k0.positions[0] as f64, 0.0, k0.positions[2] as f64];
            let canon_root = |key: &Keyframe| -> V3 {
                let p = &key.positions;
                apply(
                    &c,
                    [
                        p[0] as f64 - off[0],
                        p[1] as f64 - off[1],
                        p[2] as f64 - off[2],
                    ],
                )
            };
            let frames_of = |ix: &[usize]| ix.iter().map(|&i| keys[i].frame).collect::<Vec<_>>();
            let (gf, pf) = (self.gate_frames, self.phase_frames / rate as f64);
            let ph_all = group_phase(&frames_of(&all), n, gf, pf);
            let ph_p = group_phase(&frames_of(&pk), n, gf, pf);
            let ph_x = group_phase(&frames_of(&xk), n, gf, pf);
            let roots: Vec<V3> = keys.iter().map(canon_root).collect();
            let mut base_root: Vec<V3> = (0..n)
                .map(|t| {
                    let (a, b) = ph_all.ab[t];
                    let s = ph_all.ph[t][0];
                    std::array::from_fn(|i| roots[a][i] + s * (roots[b][i] - roots[a][i]))
                })
                .collect();
            // base rotations on every joint (identity where a joint has no channels)
            let eye: Mat3<f64> = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
            let mut base_rot: Vec<Vec<Mat3<f64>>> = if pk.is_empty() {
                let mut pose = vec![eye; j];
                for (s, &jt) in self.rotating.iter().enumerate() {
                    pose[jt] = self.prior[s];
                }
                vec![pose; n]
            } else {
                let pose_keys: Vec<Keyframe> = pk.iter().map(|&i| keys[i].clone()).collect();
                let mut r = slerp_lerp(&pose_keys, n)?.rotations;
                for f in r.iter_mut() {
                    f[0] = mul(&c, &f[0]);
                }
                r
            };
            if self.context_base {
                self.hermite_base(keys, &classes, &roots, &c, &mut base_root, &mut base_rot)?;
            }
            let gate_rot: Vec<f64> = if pk.is_empty() {
                vec![1.0; n]
            } else {
                ph_p.ph.iter().map(|p| p[3]).collect()
            };
            // keyed x/y per 2-D or pose key: root-relative, in the canonical frame
            let xy: Vec<Vec<[f64; 2]>> = xk
                .iter()
                .map(|&i| {
                    let p = &keys[i].positions;
                    (0..j)
                        .map(|jt| {
                            if jt == 0 {
                                return [0.0, 0.0];
                            }
                            let v = apply(&c, std::array::from_fn(|q| p[3 * jt + q] as f64));
                            [v[0] / self.scale, v[1] / self.scale]
                        })
                        .collect()
                })
                .collect();
            let cin = self.input_channels();
            let mut x = vec![0f32; cin * n];
            let mut put = |ch: usize, t: usize, v: f64| x[ch * n + t] = v as f32;
            let flag_p = if pk.is_empty() { 0.0 } else { 1.0 };
            let flag_x = if xk.is_empty() { 0.0 } else { 1.0 };
            let o_ph = 3 + 6 * k;
            let o_xy = o_ph + 4 + 1 + 4 + 1 + 4;
            let o_z = o_xy + 2 * j;
            let noise: Vec<f64> = match seed {
                Some(s) => {
                    let mut rng = crate::rng::Rng::new(s);
                    (0..self.noise).map(|_| rng.normal()).collect()
                }
                None => vec![0.0; self.noise],
            };
            for t in 0..n {
                for i in 0..3 {
                    put(i, t, base_root[t][i] / self.scale);
                }
                for (s, &jt) in self.rotating.iter().enumerate() {
                    for (q, v) in sixd(&base_rot[t][jt]).iter().enumerate() {
                        put(3 + 6 * s + q, t, *v);
                    }
                }
                for q in 0..4 {
                    put(o_ph + q, t, ph_p.ph[t][q]);
                    put(o_ph + 5 + q, t, ph_all.ph[t][q]);
                    put(o_ph + 10 + q, t, ph_x.ph[t][q]);
                }
                put(o_ph + 4, t, flag_p);
                put(o_ph + 9, t, flag_x);
                for (q, z) in noise.iter().enumerate() {
                    put(o_z + q, t, *z);
                }
                if !xk.is_empty() {
                    let (a, b) = ph_x.ab[t];
                    let s = ph_x.ph[t][0];
                    for jt in 0..j {
                        for q in 0..2 {
                            let v = xy[a][jt][q] + s * (xy[b][jt][q] - xy[a][jt][q]);
                            put(o_xy + 2 * jt + q, t, v);
                        }
                    }
                }
            }
            let x = TensorF32::new(x, vec![1, cin, n])?;
            let out = match self.dna_feeds(dna, n)? {
                Some((d, w)) => self.net.run(&[x, d, w])?,
                None => self.net.run(&[x])?,
            };
            let res = out
                .into_iter()
                .next()
                .ok_or_else(|| Error::Model("the conditional network gave no output".into()))?;
            let cout = 3 + 6 * k;
            if res.shape != [1, cout, n] {
                return Err(Error::Model(format!(
                    "conditional network output {:?}, expected [1, {cout}, {n}]",
                    res.shape
                )));
            }
            crate::error::check_finite("conditional network output", &res.data)?;
            let r = |ch: usize, t: usize| res.data[ch * n + t] as f64;
            let v = variation as f64;
            let mut m = Motion {
                root: Vec::with_capacity(n),
                rotations: Vec::with_capacity(n),
            };
            for (t, frame) in base_rot.iter_mut().enumerate() {
                let g = v * ph_all.ph[t][3];
                let moved: V3 = std::array::from_fn(|i| base_root[t][i] + g * r(i, t) * self.scale);
                let back = apply(&ct, moved);
                m.root.push(std::array::from_fn(|i| back[i] + off[i]));
                let w = v * gate_rot[t];
                for (s, &jt) in self.rotating.iter().enumerate() {
                    if w != 0.0 {
                        let b6 = sixd(&frame[jt]);
                        let six: [f64; 6] =
                            std::array::from_fn(|q| b6[q] + w * r(3 + 6 * s + q, t));
                        frame[jt] = from_sixd(&six).ok_or_else(|| Error::Degenerate {
                            what: "conditional network 6D output".into(),
                            index: t,
                        })?;
                    }
                }
                frame[0] = mul(&ct, &frame[0]);
            }
            m.rotations = base_rot;
            Ok(m)
        }
    }
}
