//! Motion DNA (Sec. 5.2.5): seeded representative frames, drawn as the
//! CLI's `--dna CLIP.bvh --seed S` draws them.

use super::js_err;
use wasm_bindgen::prelude::*;

/// A seed from JS: a non-negative integer up to 2^53 (what a JS number holds exactly).
fn seed(v: f64) -> Result<u64, JsError> {
    if v.is_finite() && v >= 0.0 && v.fract() == 0.0 && v <= 9_007_199_254_740_992.0 {
        Ok(v as u64)
    } else {
        Err(JsError::new(&format!(
            "seed must be an integer in [0, 9007199254740992], found {v}"
        )))
    }
}

/// Seeded Motion DNA (Sec. 5.2.5) for an output of `outFrames` frames,
/// drawn from a clip's frames as `deeprep inbetween --dna CLIP.bvh --seed S`
/// draws them: `motion` holds `frames × channels` values on `skeleton`'s
/// channels. Returns indices into those frames.
#[wasm_bindgen(js_name = dnaFramesOfClip)]
pub fn dna_frames_of_clip(
    skeleton: &super::bvh::BvhClip,
    motion: &[f32],
    out_frames: usize,
    seed_value: f64,
) -> Result<Vec<u32>, JsError> {
    let mut clip = skeleton.bvh().clone();
    let c = clip.channel_count();
    if motion.is_empty() || !motion.len().is_multiple_of(c) {
        return Err(JsError::new(&format!(
            "motion: expected whole frames of {c} channel values, found {} values",
            motion.len()
        )));
    }
    clip.motion = motion.to_vec();
    let picked = crate::motion::dna::pick_from_clip(&clip, out_frames, seed(seed_value)?);
    Ok(picked
        .map_err(js_err)?
        .into_iter()
        .map(|i| i as u32)
        .collect())
}

/// Seeded Motion DNA for an output of `outFrames` frames from a library of
/// `pool` unrelated poses (`motion::dna::pick_from_pool`). Returns indices.
#[wasm_bindgen(js_name = dnaFramesOfPool)]
pub fn dna_frames_of_pool(
    pool: usize,
    out_frames: usize,
    seed_value: f64,
) -> Result<Vec<u32>, JsError> {
    let picked = crate::motion::dna::pick_from_pool(pool, out_frames, seed(seed_value)?);
    Ok(picked
        .map_err(js_err)?
        .into_iter()
        .map(|i| i as u32)
        .collect())
}
