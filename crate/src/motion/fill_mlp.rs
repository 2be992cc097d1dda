//! The short-gap fill network (issue 50; `train/deeprep_train/motion/fill_mlp.py`,
//! whose docstring defines the layout): an MLP that reads the known frames
//! at a gap's two edges and corrects [`super::fill::hermite_curve`] across it.
//!
//! - Its input is up to `context` frames before the gap and `after` frames
//!   after it (fewer are padded with the outermost known one; the input
//!   says how many are known): every rotating joint's rotation as a scaled
//!   axis in the tangent space of that joint's rotation at the last frame
//!   before the gap, the root's offset from that frame's in its heading
//!   frame (the hips' forward axis turned into +z about the vertical), then
//!   the gap's length / `t_norm` and the known frames' shares.
//! - Its output is `terms` sine coefficients per channel (3 per rotating
//!   joint, then 3 for the root): the correction at gap frame `f` of `T` is
//!   the sum over `m` of `coef[m] sin(pi m f / (T + 1))`, added to the
//!   Hermite curve in the same coordinates. It is zero at both edges, so the
//!   seams are the curve's.
//!
//! The `model` fill runs it on the gaps its manifest's band gives it
//! ([`super::fill::method_for`]); `--method fill-mlp` runs it on any gap.

use super::clip::ClipKeys;
use super::fill::{gap_of, hermite_curve, known_frame, span_motion, step, HermiteEnds};
use super::Motion;
use crate::error::{Error, Result};
use crate::runtime::{Model, TensorF32};
use crate::skeleton::Bvh;
use glam::{DMat3, DQuat, DVec3};
use serde::Deserialize;

#[derive(Deserialize)]
struct Manifest {
    kind: String,
    context: usize,
    after: usize,
    terms: usize,
    t_norm: f64,
    /// The longest gap it was trained on: longer ones are refused.
    longest_gap: usize,
    inputs_len: usize,
    channels: usize,
    joints: Vec<String>,
    #[serde(default)]
    fill_from: Option<usize>,
    #[serde(default)]
    fill_up_to: Option<usize>,
}

impl Manifest {
    fn parse(json: &str) -> Result<Manifest> {
        let bad = |e: String| Error::Invalid(format!("short-gap fill manifest: {e}"));
        let m: Manifest = serde_json::from_str(json).map_err(|e| bad(e.to_string()))?;
        if m.kind != "fill-mlp" {
            return Err(bad(format!("kind '{}', expected 'fill-mlp'", m.kind)));
        }
        let k = m.joints.len();
        // bounds on the layout, so a bad manifest cannot size an allocation
        if !(1..=64).contains(&m.context)
            || !(1..=64).contains(&m.after)
            || !(1..=256).contains(&m.terms)
            || k == 0
            || k > 1024
            || m.channels != 3 * k + 3
            || m.inputs_len != (m.context + m.after) * m.channels + 3
            || !(m.t_norm > 0.0 && m.t_norm.is_finite())
        {
            return Err(bad(format!(
                "inconsistent layout: context {}, after {}, terms {}, {} joints, channels {} (3 per joint + 3), inputs_len {} ((context + after) x channels + 3)",
                m.context, m.after, m.terms, k, m.channels, m.inputs_len
            )));
        }
        Ok(m)
    }

    /// Its band, which this network must give, within the gaps it was
    /// trained on.
    fn band(&self) -> Result<(usize, usize)> {
        let bad = |e: String| Error::Invalid(format!("short-gap fill manifest: {e}"));
        let (lo, hi) = super::fill::band(self.fill_from, self.fill_up_to)
            .map_err(|e| bad(e.to_string()))?
            .ok_or_else(|| bad("it gives no band (fill_from, fill_up_to)".into()))?;
        if hi > self.longest_gap {
            return Err(bad(format!(
                "fill_up_to {hi} is beyond the longest gap it was trained on ({})",
                self.longest_gap
            )));
        }
        Ok((lo, hi))
    }
}

/// The band (`fill_from..=fill_up_to`) a short-gap fill manifest's text
/// gives its network, checked with the rest of the manifest, without
/// loading the network.
pub fn band_of_manifest(json: &str) -> Result<(usize, usize)> {
    Manifest::parse(json)?.band()
}

/// The frames at a gap's edges, as the network reads them: the root and
/// the rotating joints' rotations of each known frame.
pub struct Edges {
    /// Known frames before the gap, in order (the last is the frame just
    /// before it); at least one.
    pub before: Vec<(DVec3, Vec<DQuat>)>,
    /// Known frames after the gap, in order (the first is the frame just
    /// after it); at least one.
    pub after: Vec<(DVec3, Vec<DQuat>)>,
}

/// The short-gap fill network.
pub struct FillMlp {
    net: Model,
    m: Manifest,
    band: (usize, usize),
}

impl FillMlp {
    /// Loads the network (the bytes of `tween_fill_mlp.onnx`) and its manifest.
    pub fn new(onnx: &[u8], manifest_json: &str) -> Result<Self> {
        let m = Manifest::parse(manifest_json)?;
        let band = m.band()?;
        Ok(FillMlp {
            net: Model::from_onnx_bytes(onnx)?,
            m,
            band,
        })
    }

    /// Loads `NAME.onnx` and `NAME.manifest.json` from a folder.
    pub fn load_named(dir: &std::path::Path, name: &str) -> Result<Self> {
        let read = |n: &str| crate::runtime::read_file(dir, n);
        let manifest = String::from_utf8(read(&format!("{name}.manifest.json"))?)
            .map_err(|e| Error::Invalid(e.to_string()))?;
        Self::new(&read(&format!("{name}.onnx"))?, &manifest)
    }

    /// The gap lengths the `model` fill gives it.
    pub fn band(&self) -> (usize, usize) {
        self.band
    }

    /// The rotating joints' names, in the order [`Edges`] gives them.
    pub fn joints(&self) -> &[String] {
        &self.m.joints
    }

    /// The gap's `t` frames: each root position and the rotating joints'
    /// rotations, the Hermite curve between the edges corrected by the
    /// network.
    pub fn correct(&self, e: &Edges, t: usize) -> Result<Vec<(DVec3, Vec<DQuat>)>> {
        let k = self.m.joints.len();
        let (ctx, aft) = (self.m.context, self.m.after);
        let ok = |f: &(DVec3, Vec<DQuat>)| f.1.len() == k;
        if e.before.is_empty() || e.after.is_empty() || t == 0 {
            return Err(Error::Invalid(
                "the short-gap fill network needs a gap and a known frame on each side".into(),
            ));
        }
        if t > self.m.longest_gap {
            return Err(Error::Invalid(format!(
                "a gap of {t} frames: the short-gap fill network (method fill-mlp) fills gaps of up to {} frames, the longest it was trained on; method model chooses a network by the gap's length",
                self.m.longest_gap
            )));
        }
        if !e.before.iter().chain(&e.after).all(ok) {
            return Err(Error::Invalid(format!(
                "the short-gap fill network reads {k} rotating joints (the model's skeleton)"
            )));
        }
        let c = e.before.len().min(ctx);
        let a_n = e.after.len().min(aft);
        let before = &e.before[e.before.len() - c..];
        let after = &e.after[..a_n];
        let (ra, qa) = (before[c - 1].0, &before[c - 1].1);
        let (rb, qb) = (after[0].0, &after[0].1);
        // the heading frame at a: the hips' forward axis (local z) turned into +z
        let f = DMat3::from_quat(qa[0]).z_axis;
        let heading = DMat3::from_rotation_y(-f.x.atan2(f.z));
        // the known frames, padded with the outermost known one
        let frames = (0..ctx)
            .map(|i| &before[(i + c).saturating_sub(ctx)])
            .chain((0..aft).map(|i| &after[i.min(a_n - 1)]));
        let mut x = Vec::with_capacity(self.m.inputs_len);
        let mut roots = Vec::with_capacity(ctx + aft);
        for (r, q) in frames {
            for (j, qj) in q.iter().enumerate() {
                x.extend(step(qa[j], *qj).to_array().map(|v| v as f32));
            }
            roots.push(heading * (*r - ra));
        }
        for r in roots {
            x.extend(r.to_array().map(|v| v as f32));
        }
        x.extend([
            (t as f64 / self.m.t_norm) as f32,
            (c as f64 / ctx as f64) as f32,
            (a_n as f64 / aft as f64) as f32,
        ]);
        crate::error::check_finite("the short-gap fill network's input", &x)?;
        let n = self.m.inputs_len;
        let out = self.net.run(&[TensorF32::new(x, vec![1, n])?])?;
        let (terms, ch) = (self.m.terms, self.m.channels);
        let coef = out
            .first()
            .filter(|o| o.data.len() == terms * ch)
            .ok_or_else(|| Error::Shape {
                what: "the short-gap fill network's output".into(),
                expected: format!("{terms} x {ch}"),
                found: format!("{:?}", out.first().map(|o| &o.shape)),
            })?;
        crate::error::check_finite("the short-gap fill network's output", &coef.data)?;
        let ends = HermiteEnds {
            root: [ra, rb],
            rot: [qa, qb],
            prev: (c >= 2).then(|| (before[c - 2].0, before[c - 2].1.as_slice())),
            next: (a_n >= 2).then(|| (after[1].0, after[1].1.as_slice())),
        };
        let curve = hermite_curve(&ends, t + 1);
        let back = heading.transpose();
        Ok(curve
            .into_iter()
            .enumerate()
            .map(|(i, (p, qs))| {
                let u = (i + 1) as f64 / (t + 1) as f64;
                let basis: Vec<f64> = (1..=terms)
                    .map(|m| (std::f64::consts::PI * m as f64 * u).sin())
                    .collect();
                let res = |c: usize| -> f64 {
                    basis
                        .iter()
                        .enumerate()
                        .map(|(m, b)| b * coef.data[m * ch + c] as f64)
                        .sum()
                };
                let rot = qs
                    .iter()
                    .enumerate()
                    .map(|(j, q)| {
                        let w = step(qa[j], *q)
                            + DVec3::new(res(3 * j), res(3 * j + 1), res(3 * j + 2));
                        (qa[j] * DQuat::from_scaled_axis(w)).normalize()
                    })
                    .collect();
                let r = heading * (p - ra) + DVec3::new(res(3 * k), res(3 * k + 1), res(3 * k + 2));
                (back * r + ra, rot)
            })
            .collect())
    }

    /// One gap's key span (`ck` on `clip`, as [`super::fill::fill`] gives
    /// it): the context frames as they are, the gap's frames by
    /// [`FillMlp::correct`].
    pub fn fill(&self, clip: &Bvh, ck: &ClipKeys) -> Result<Motion> {
        let rotating: Vec<usize> = (0..clip.joints.len())
            .filter(|&j| !clip.joints[j].channels.is_empty())
            .collect();
        if rotating.len() != self.m.joints.len()
            || rotating
                .iter()
                .zip(&self.m.joints)
                .any(|(&j, n)| clip.joints[j].name != *n)
        {
            return Err(Error::Invalid(
                "the short-gap fill network reads the model's skeleton: its joints with channels differ"
                    .into(),
            ));
        }
        let (at, a, b) = gap_of(ck)?;
        let frames = &ck.clip_frames;
        let lo = (at + 1).saturating_sub(self.m.context);
        let hi = (at + 1 + self.m.after).min(frames.len());
        let read = |fs: &[usize]| -> Result<Vec<(DVec3, Vec<DQuat>)>> {
            fs.iter().map(|&f| known_frame(clip, f)).collect()
        };
        let (before, after) = (read(&frames[lo..=at])?, read(&frames[at + 1..hi])?);
        let rotating_only = |fs: &[(DVec3, Vec<DQuat>)]| -> Vec<(DVec3, Vec<DQuat>)> {
            fs.iter()
                .map(|(p, q)| (*p, rotating.iter().map(|&j| q[j]).collect()))
                .collect()
        };
        let edges = Edges {
            before: rotating_only(&before),
            after: rotating_only(&after),
        };
        // joints without channels keep frame a's rotation (the identity: a
        // BVH joint without channels never turns)
        let at_a = &before[before.len() - 1].1;
        let gap = self
            .correct(&edges, b - a - 1)?
            .into_iter()
            .map(|(p, qs)| {
                let mut q = at_a.clone();
                for (&j, qj) in rotating.iter().zip(qs) {
                    q[j] = qj;
                }
                (p, q)
            })
            .collect();
        span_motion(clip, ck, (a, b), gap)
    }
}
