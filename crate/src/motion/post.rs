//! Post-processing that makes keyframes exact (thesis Sec. 5.2.6): the
//! error at each key is spread over the neighbouring frames with smoothstep
//! weights, so the correction is smooth and zero-velocity at keys.
//! - Root: per coordinate given by the key, the position offset is blended
//!   between consecutive keys.
//! - Rotations (keys that carry them): the per-joint correction
//!   `Δ = R_key · R_outᵀ` is slerped between consecutive keys and applied on
//!   the left.
//!
//! Before the first and after the last key, the nearest key's correction
//! is held.
//!
//! [`scale_root_deviation`] is the root half of the pipeline's `variation`:
//! it scales how far the root path strays from the keys' linear
//! interpolation (SLERP+LERP's root).

use super::{Keyframe, Motion};
use crate::rotation::quat::{matrix_to_quat, quat_to_matrix_unit, slerp};
use crate::rotation::{mul, transpose};

/// Smoothstep on [0, 1] (clamped outside): 0 and 1 with zero slope at the ends.
pub(super) fn smoothstep(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// Bracketing keys (indices into `frames`) and smoothstep weight for frame t.
fn bracket(frames: &[usize], t: usize) -> (usize, usize, f64) {
    let (a, b, s) = bracket_linear(frames, t);
    (a, b, smoothstep(s))
}

/// Bracketing keys (indices into `frames`) and linear weight for frame t;
/// the first or last key alone, weight 0, outside them.
fn bracket_linear(frames: &[usize], t: usize) -> (usize, usize, f64) {
    let n = frames.len();
    if t <= frames[0] {
        return (0, 0, 0.0);
    }
    if t >= frames[n - 1] {
        return (n - 1, n - 1, 0.0);
    }
    let b = frames.partition_point(|&f| f <= t);
    let a = b - 1;
    let s = (t - frames[a]) as f64 / (frames[b] - frames[a]) as f64;
    (a, b, s)
}

/// The keys inside the motion that give root coordinate `c`.
fn keys_giving(keys: &[Keyframe], c: usize, frames: usize) -> Vec<&Keyframe> {
    keys.iter()
        .filter(|k| k.mask[c] && k.frame < frames)
        .collect()
}

/// Scales the root path's deviation from the keys' root positions
/// interpolated linearly by `share`, per coordinate given by keys:
/// `root + (share − 1)·(root − lerp(keys))` between the first and last key
/// that give the coordinate; outside them the path moves by the same amount
/// as at the nearest such key, so it stays continuous. `share` 1
/// leaves the path as it is; 0 makes it the linear interpolation between
/// keys (what SLERP+LERP does with the root).
pub fn scale_root_deviation(root: &mut [[f64; 3]], keys: &[Keyframe], share: f64) {
    if share == 1.0 {
        return;
    }
    let frames = root.len();
    for c in 0..3 {
        let ks = keys_giving(keys, c, frames);
        if ks.is_empty() {
            continue;
        }
        let fr: Vec<usize> = ks.iter().map(|k| k.frame).collect();
        let val: Vec<f64> = ks.iter().map(|k| k.positions[c] as f64).collect();
        let (first, last) = (fr[0], fr[fr.len() - 1]);
        // Deviation from the lerp, held at the end keys' outside them.
        let dev: Vec<f64> = (0..frames)
            .map(|t| {
                let t = t.clamp(first, last);
                let (a, b, s) = bracket_linear(&fr, t);
                root[t][c] - (val[a] * (1.0 - s) + val[b] * s)
            })
            .collect();
        for (r, d) in root.iter_mut().zip(dev) {
            r[c] += (share - 1.0) * d;
        }
    }
}

/// Applies the correction in place.
pub fn make_keys_exact(motion: &mut Motion, keys: &[Keyframe]) {
    let frames = motion.len();
    // Root, per coordinate.
    for c in 0..3 {
        let ks = keys_giving(keys, c, frames);
        if ks.is_empty() {
            continue;
        }
        let fr: Vec<usize> = ks.iter().map(|k| k.frame).collect();
        let err: Vec<f64> = ks
            .iter()
            .map(|k| k.positions[c] as f64 - motion.root[k.frame][c])
            .collect();
        for t in 0..frames {
            let (a, b, w) = bracket(&fr, t);
            motion.root[t][c] += err[a] * (1.0 - w) + err[b] * w;
        }
    }
    // Rotations.
    let ks: Vec<&Keyframe> = keys
        .iter()
        .filter(|k| k.rotations.is_some() && k.frame < frames)
        .collect();
    if ks.is_empty() {
        return;
    }
    let fr: Vec<usize> = ks.iter().map(|k| k.frame).collect();
    let joints = motion.rotations[0].len();
    let deltas: Vec<Vec<[f64; 4]>> = ks
        .iter()
        .map(|k| {
            let r = k.rotations.as_ref().expect("filtered");
            (0..joints)
                .map(|j| matrix_to_quat(&mul(&r[j], &transpose(&motion.rotations[k.frame][j]))))
                .collect()
        })
        .collect();
    for t in 0..frames {
        let (a, b, w) = bracket(&fr, t);
        for j in 0..joints {
            let d = quat_to_matrix_unit(&slerp(&deltas[a][j], &deltas[b][j], w));
            motion.rotations[t][j] = mul(&d, &motion.rotations[t][j]);
        }
    }
}
