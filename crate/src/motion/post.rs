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

use super::{Keyframe, Motion};
use crate::rotation::quat::{matrix_to_quat, quat_to_matrix_unit, slerp};
use crate::rotation::{mul, transpose};

/// Smoothstep on [0, 1] (clamped outside): 0 and 1 with zero slope at the ends.
pub(super) fn smoothstep(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// Bracketing keys (indices into `idx`) and weight for frame t.
fn bracket(frames: &[usize], t: usize) -> (usize, usize, f64) {
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
    (a, b, smoothstep(s))
}

/// Applies the correction in place.
pub fn make_keys_exact(motion: &mut Motion, keys: &[Keyframe]) {
    let frames = motion.len();
    // Root, per coordinate.
    for c in 0..3 {
        let ks: Vec<&Keyframe> = keys
            .iter()
            .filter(|k| k.mask[c] && k.frame < frames)
            .collect();
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
