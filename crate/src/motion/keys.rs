//! The keys file: `{"frames": N, "keys": [KEY, ...]}` (`deeprep inbetween
//! KEYS.json`, `models/examples/keys.json`; the JS API takes the same keys).
//! Each key is one of:
//! - `{"frame": F, "channels": [...]}`: a whole pose, one BVH channel row of
//!   the model's skeleton;
//! - `{"frame": F, "root": [x, y, z]}`: the root's position only (Sec. 5.4.1);
//! - `{"frame": F, "xy": [[x, y] or null per joint], "root": [x, y, z] or null}`:
//!   global x and y of some joints, the front view (Sec. 5.4.2), in the
//!   skeleton's joint order (`deeprep inbetween --skeleton`).
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

/// What a key gives: a whole pose, the root's position only, or the
/// front view's x and y of every joint with the root (Sec. 5.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KeyKind {
    /// Every joint's position and rotation.
    Pose,
    /// The root's global position only.
    Root,
    /// Every joint's global x and y, and the root's position.
    Xy,
}

impl KeyKind {
    /// The kind named `pose`, `root` or `xy`.
    pub fn parse(name: &str) -> Result<KeyKind> {
        match name {
            "pose" => Ok(KeyKind::Pose),
            "root" => Ok(KeyKind::Root),
            "xy" => Ok(KeyKind::Xy),
            other => Err(bad(format!(
                "unknown key kind '{other}' (pose, root or xy)"
            ))),
        }
    }

    /// What a whole-pose key gives of this kind.
    pub fn of(self, whole: &Keyframe) -> Result<Keyframe> {
        let p = &whole.positions;
        let root = [p[0], p[1], p[2]];
        match self {
            KeyKind::Pose => Ok(whole.clone()),
            KeyKind::Root => Ok(Keyframe::root_only(whole.frame, root, p.len() / 3)),
            KeyKind::Xy => {
                let xy: Vec<Option<[f32; 2]>> = (0..p.len() / 3)
                    .map(|j| match j {
                        0 => Some([root[0], root[1]]),
                        j => Some([p[3 * j] + root[0], p[3 * j + 1] + root[1]]),
                    })
                    .collect();
                Keyframe::xy(whole.frame, &xy, Some(root))
            }
        }
    }
}

/// Length of the warm-up request ([`warm_up_keys`]).
pub const WARM_UP_FRAMES: usize = 512;

/// Spacing of the warm-up keys: 4 s at 60 fps, the benchmarks' spacing.
pub const WARM_UP_SPACING: usize = 240;

/// Whole-pose keys for warming up a long-lived caller (the npm worker, once
/// after loading): one every [`WARM_UP_SPACING`] frames over
/// [`WARM_UP_FRAMES`] frames on `template`'s skeleton, the root walking
/// forward (+z, 120 units a key) at the height that puts the rest pose's
/// lowest point on the floor, every rotation channel a different sine of at
/// most 25 degrees, other position channels 0.
///
/// The wasm `Inbetweener::warm_up` runs them (why, with its measurements,
/// is written there); natively nothing needs them.
pub fn warm_up_keys(template: &Bvh) -> Result<Vec<Keyframe>> {
    let c = template.channel_count();
    // rest-pose heights: each joint's offset added down the chain
    let mut rest_y: Vec<f32> = Vec::with_capacity(template.joints.len());
    for j in &template.joints {
        let up = j.parent.map_or(0.0, |p| rest_y[p]);
        rest_y.push(up + j.offset[1]);
    }
    let lowest = rest_y.iter().copied().fold(0.0f32, f32::min);
    let mut one = template.clone();
    (0..WARM_UP_FRAMES)
        .step_by(WARM_UP_SPACING)
        .enumerate()
        .map(|(k, frame)| {
            let mut row = vec![0.0f32; c];
            for j in &template.joints {
                for (i, ch) in j.channels.iter().enumerate() {
                    let at = j.channel_start + i;
                    row[at] = if ch.is_rotation() {
                        25.0 * (0.7 * at as f32 + 1.3 * k as f32).sin()
                    } else if j.parent.is_some() {
                        0.0
                    } else {
                        match ch.axis() {
                            1 => -lowest,
                            2 => 120.0 * k as f32,
                            _ => 0.0,
                        }
                    };
                }
            }
            one.motion = row;
            Keyframe::from_bvh(&one, 0, frame)
        })
        .collect()
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
        keys.push(key(i, frame, k, template)?);
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

/// Finite numbers from a JSON array of exactly `n` entries, or `None`.
fn numbers(v: &serde_json::Value, n: usize) -> Option<Vec<f32>> {
    let a = v.as_array().filter(|a| a.len() == n)?;
    a.iter()
        .map(|x| x.as_f64().map(|x| x as f32).filter(|x| x.is_finite()))
        .collect()
}

/// Key `i` of the file (its frame already read), of whichever kind it is.
fn key(i: usize, frame: usize, k: &serde_json::Value, template: &Bvh) -> Result<Keyframe> {
    let has = |name: &str| !k[name].is_null();
    let joints = template.joints.len();
    let root = |what: &str| -> Result<Option<[f32; 3]>> {
        if !has("root") {
            return Ok(None);
        }
        numbers(&k["root"], 3)
            .map(|r| Some([r[0], r[1], r[2]]))
            .ok_or_else(|| bad(format!("key {i}: \"root\" must be [x, y, z], finite{what}")))
    };
    if has("channels") {
        if has("root") || has("xy") {
            return Err(bad(format!(
                "key {i}: a whole pose (\"channels\") takes no \"root\" or \"xy\""
            )));
        }
        let c = template.channel_count();
        let n = k["channels"].as_array().map(|a| a.len());
        if n != Some(c) {
            return Err(bad(match n {
                Some(n) => format!("key {i} has {n} channels; the skeleton has {c}"),
                None => format!("key {i}: \"channels\" must be an array"),
            }));
        }
        let row = numbers(&k["channels"], c)
            .ok_or_else(|| bad(format!("key {i}: channels must be finite numbers")))?;
        let mut one = template.clone();
        one.motion = row;
        return Keyframe::from_bvh(&one, 0, frame);
    }
    if has("xy") {
        let list = k["xy"]
            .as_array()
            .filter(|a| a.len() == joints)
            .ok_or_else(|| {
                bad(format!(
                    "key {i}: \"xy\" must list one [x, y] or null per joint ({joints} joints)"
                ))
            })?;
        let xy = list
            .iter()
            .enumerate()
            .map(|(j, p)| match p {
                serde_json::Value::Null => Ok(None),
                p => numbers(p, 2).map(|v| Some([v[0], v[1]])).ok_or_else(|| {
                    bad(format!(
                        "key {i}: \"xy\" entry {j} must be [x, y], finite, or null"
                    ))
                }),
            })
            .collect::<Result<Vec<_>>>()?;
        return Keyframe::xy(frame, &xy, root(" or null")?)
            .map_err(|e| bad(format!("key {i}: {e}")));
    }
    match root("")? {
        Some(r) => Ok(Keyframe::root_only(frame, r, joints)),
        None => Err(bad(format!(
            "key {i} has none of \"channels\" (a whole pose), \"root\" (the root's position) or \"xy\" (2-D joints)"
        ))),
    }
}

/// A whole in-betweening request as JSON, the form the JS API sends:
/// a keys file (`"frames"`, `"keys"` of any kind) plus
/// `"method"` (`"model"`, the default, or another of
/// [`plan::METHODS`](super::plan::METHODS)),
/// `"post"` (make keys exact; default true), `"footLock"` (default false),
/// `"variation"` (default: the model's), `"dna"` (Motion DNA poses as
/// channel rows of the skeleton; default: the whole-pose keys) and
/// `"seed"` (the conditional network's noise draw; default: none).
#[derive(Clone, Debug)]
pub struct RequestDoc {
    /// The keys and the length.
    pub file: KeysFile,
    /// Which in-betweening runs.
    pub method: String,
    /// Post-processing on.
    pub post: bool,
    /// Foot locking on (with post-processing).
    pub foot_lock: bool,
    /// The variation, if given.
    pub variation: Option<f32>,
    /// Motion DNA poses (`dna_pose` form), if given.
    pub dna: Option<Vec<Vec<f32>>>,
    /// The conditional network's noise draw (`"seed"`, a non-negative
    /// integer), if given.
    pub seed: Option<u64>,
}

/// Reads a [`RequestDoc`] on `template`'s skeleton; every problem is an
/// error that names the field.
pub fn request_from_json(text: &str, template: &Bvh) -> Result<RequestDoc> {
    let file = from_json(text, template)?;
    let v: serde_json::Value =
        serde_json::from_str(text).map_err(|e| bad(format!("request: {e}")))?;
    let flag = |name: &str, default: bool| match &v[name] {
        serde_json::Value::Null => Ok(default),
        serde_json::Value::Bool(b) => Ok(*b),
        _ => Err(bad(format!("request: \"{name}\" must be true or false"))),
    };
    let method = match &v["method"] {
        serde_json::Value::Null => "model".to_string(),
        serde_json::Value::String(s) if super::plan::METHODS.contains(&s.as_str()) => s.clone(),
        m => {
            return Err(bad(format!(
                "request: unknown \"method\" {m} ({})",
                super::plan::METHODS.join(", ")
            )))
        }
    };
    let variation = match &v["variation"] {
        serde_json::Value::Null => None,
        x => Some(
            x.as_f64()
                .map(|x| x as f32)
                .filter(|x| x.is_finite())
                .ok_or_else(|| bad("request: \"variation\" must be a number".into()))?,
        ),
    };
    let dna = match &v["dna"] {
        serde_json::Value::Null => None,
        d => {
            let rows = d
                .as_array()
                .ok_or_else(|| bad("request: \"dna\" must be a list of channel rows".into()))?;
            let c = template.channel_count();
            let mut one = template.clone();
            let poses = rows
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    one.motion = numbers(r, c).ok_or_else(|| {
                        bad(format!(
                            "request: \"dna\" pose {i} must be {c} finite channels"
                        ))
                    })?;
                    Keyframe::from_bvh(&one, 0, 0).map(|k| super::dna_pose(&k))
                })
                .collect::<Result<Vec<_>>>()?;
            (!poses.is_empty()).then_some(poses)
        }
    };
    let seed = match &v["seed"] {
        serde_json::Value::Null => None,
        serde_json::Value::Number(n) if n.as_u64().is_some() => n.as_u64(),
        other => {
            return Err(bad(format!(
                "request: \"seed\" must be a non-negative integer, found {other}"
            )))
        }
    };
    Ok(RequestDoc {
        file,
        method,
        post: flag("post", true)?,
        foot_lock: flag("footLock", false)?,
        variation,
        dna,
        seed,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A root, a spine and a leg whose End Site is 8 below the root's rest
    /// height (2 + -1 + -9).
    const SKELETON: &str = "HIERARCHY\nROOT hips\n{\n  OFFSET 1 2 3\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n  JOINT spine\n  {\n    OFFSET 0 10 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {\n      OFFSET 0 3 0\n    }\n  }\n  JOINT leg\n  {\n    OFFSET -2 -1 0\n    CHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation Zrotation\n    End Site\n    {\n      OFFSET 0 -9 0\n    }\n  }\n}\nMOTION\nFrames: 0\nFrame Time: 0.0166667\n";

    #[test]
    fn warm_up_keys_walk_forward_with_their_lowest_point_on_the_floor() {
        let b = Bvh::parse(SKELETON).unwrap();
        let keys = warm_up_keys(&b).unwrap();
        let frames: Vec<usize> = keys.iter().map(|k| k.frame).collect();
        assert_eq!(frames, vec![0, 240, 480]);
        for (k, key) in keys.iter().enumerate() {
            // root: offset (1, 2, 3) plus (0, 8, 120 k)
            let root = &key.positions[..3];
            assert_eq!(root, &[1.0, 10.0, 3.0 + 120.0 * k as f32][..]);
            assert!(key.mask.iter().all(|&m| m), "whole poses");
            assert!(key.positions.iter().all(|v| v.is_finite()));
            assert!(key.rotations.is_some());
        }
        assert_ne!(
            keys[0].positions[3..],
            keys[1].positions[3..],
            "each key its own pose"
        );
    }
}
