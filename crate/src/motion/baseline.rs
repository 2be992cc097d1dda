//! Interpolation baselines on whole-pose keys with rotations: SLERP+LERP
//! (per-joint local rotations slerped, root position lerped) and
//! zero-velocity (hold the last key). Frames before the first key hold the
//! first key, frames after the last key hold the last.

use super::{Keyframe, Motion};
use crate::error::{Error, Result};
use crate::rotation::quat::{matrix_to_quat, quat_to_matrix_unit, slerp};
use crate::rotation::Mat3;

fn rotations(k: &Keyframe, i: usize) -> Result<&Vec<Mat3<f64>>> {
    k.rotations.as_ref().ok_or_else(|| {
        Error::Invalid(format!(
            "keyframe {i} has no rotations: interpolation baselines need whole-pose keys"
        ))
    })
}

fn root(k: &Keyframe) -> [f64; 3] {
    [
        k.positions[0] as f64,
        k.positions[1] as f64,
        k.positions[2] as f64,
    ]
}

/// Validates the keys, then gives each frame the index of the most recent
/// key at or before it (0 before the first key).
fn last_key_per_frame(keys: &[Keyframe], frames: usize) -> Result<Vec<usize>> {
    let joints = keys.first().map_or(0, |k| k.positions.len() / 3);
    super::validate_keys(keys, frames, joints)?;
    let mut seg = 0;
    Ok((0..frames)
        .map(|t| {
            while seg + 1 < keys.len() && keys[seg + 1].frame <= t {
                seg += 1;
            }
            seg
        })
        .collect())
}

/// SLERP+LERP between consecutive keys.
pub fn slerp_lerp(keys: &[Keyframe], frames: usize) -> Result<Motion> {
    let segs = last_key_per_frame(keys, frames)?;
    let quats: Vec<Vec<[f64; 4]>> = keys
        .iter()
        .enumerate()
        .map(|(i, k)| Ok(rotations(k, i)?.iter().map(matrix_to_quat).collect()))
        .collect::<Result<_>>()?;
    let mut m = Motion {
        root: Vec::with_capacity(frames),
        rotations: Vec::with_capacity(frames),
    };
    for (t, &seg) in segs.iter().enumerate() {
        let a = &keys[seg];
        if t <= a.frame || seg + 1 == keys.len() {
            m.root.push(root(a));
            m.rotations.push(rotations(a, seg)?.clone());
            continue;
        }
        let b = &keys[seg + 1];
        let s = (t - a.frame) as f64 / (b.frame - a.frame) as f64;
        let (ra, rb) = (root(a), root(b));
        m.root.push([0, 1, 2].map(|i| ra[i] + s * (rb[i] - ra[i])));
        m.rotations.push(
            quats[seg]
                .iter()
                .zip(&quats[seg + 1])
                .map(|(qa, qb)| quat_to_matrix_unit(&slerp(qa, qb, s)))
                .collect(),
        );
    }
    Ok(m)
}

/// Zero-velocity: every frame holds the most recent key.
pub fn zero_velocity(keys: &[Keyframe], frames: usize) -> Result<Motion> {
    let segs = last_key_per_frame(keys, frames)?;
    let mut m = Motion {
        root: Vec::with_capacity(frames),
        rotations: Vec::with_capacity(frames),
    };
    for seg in segs {
        m.root.push(root(&keys[seg]));
        m.rotations.push(rotations(&keys[seg], seg)?.clone());
    }
    Ok(m)
}
