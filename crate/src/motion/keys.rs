//! The keys file: `{"frames": N, "keys": [{"frame": F, "channels": [...]}, ...]}`,
//! each key a whole pose as one BVH channel row of the model's skeleton
//! (`deeprep inbetween KEYS.json`, `models/examples/keys.json`).
//!
//! Reading is strict: every problem is an error that names the key, and
//! nothing is allocated from a count in the file before the data is there.

use super::Keyframe;
use crate::error::{Error, Result};
use crate::skeleton::Bvh;

/// A parsed keys file.
#[derive(Clone, Debug)]
pub struct KeysFile {
    /// The keys, in file order, on the template skeleton.
    pub keys: Vec<Keyframe>,
    /// The motion length the file asks for (`"frames"`), if it gives one.
    pub frames: Option<usize>,
}

fn bad(msg: String) -> Error {
    Error::Invalid(msg)
}

/// Reads a keys file on `template`'s skeleton (its channel layout).
pub fn from_json(text: &str, template: &Bvh) -> Result<KeysFile> {
    let v: serde_json::Value =
        serde_json::from_str(text).map_err(|e| bad(format!("keys file: {e}")))?;
    let list = v["keys"]
        .as_array()
        .ok_or_else(|| bad("keys file: expected a \"keys\" array".into()))?;
    let c = template.channel_count();
    let mut keys = Vec::with_capacity(list.len());
    for (i, k) in list.iter().enumerate() {
        let frame = k["frame"]
            .as_u64()
            .and_then(|f| usize::try_from(f).ok())
            .ok_or_else(|| {
                bad(format!(
                    "key {i} lacks a \"frame\" (a non-negative integer)"
                ))
            })?;
        let ch = k["channels"]
            .as_array()
            .ok_or_else(|| bad(format!("key {i} lacks \"channels\"")))?;
        if ch.len() != c {
            return Err(bad(format!(
                "key {i} has {} channels; the skeleton has {c}",
                ch.len()
            )));
        }
        let row = ch
            .iter()
            .map(|x| x.as_f64().map(|x| x as f32).filter(|x| x.is_finite()))
            .collect::<Option<Vec<f32>>>()
            .ok_or_else(|| bad(format!("key {i}: channels must be finite numbers")))?;
        let mut one = template.clone();
        one.motion = row;
        keys.push(Keyframe::from_bvh(&one, 0, frame)?);
    }
    let frames = match &v["frames"] {
        serde_json::Value::Null => None,
        f => Some(
            f.as_u64()
                .and_then(|f| usize::try_from(f).ok())
                .ok_or_else(
                    || bad("keys file: \"frames\" must be a non-negative integer".into()),
                )?,
        ),
    };
    Ok(KeysFile { keys, frames })
}
