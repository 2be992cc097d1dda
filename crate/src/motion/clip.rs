//! In-betweening inside a user's clip (`deeprep inbetween --from-bvh CLIP
//! --keys F1,F2,...`, JS `synthesizeFromBvh`): whole-pose keys taken from
//! frames of the clip, the motion between the first and the last key
//! synthesized, everything else copied. Clips at another frame rate are
//! resampled to the model's 60 fps and the result back to theirs. Clips on
//! another humanoid skeleton are retargeted onto the model's ([`OnModel`])
//! and the result back onto theirs.

use super::{Keyframe, Motion};
use crate::error::{Error, Result};
use crate::skeleton::resample::{map_frame, resample};
use crate::skeleton::retarget::{find_roles, Retarget, Role, RoleMap, Side};
use crate::skeleton::Bvh;

/// The networks' frame rate.
pub const MODEL_FPS: f64 = 60.0;

/// Keys taken from a clip, at the model's frame rate.
#[derive(Clone, Debug)]
pub struct ClipKeys {
    /// The clip at [`MODEL_FPS`] (the clip itself when it is at that rate).
    pub clip: Bvh,
    /// Whole-pose keys, frames counted from the first key.
    pub keys: Vec<Keyframe>,
    /// The first and last key's frames in `clip`.
    pub first: usize,
    /// See `first`.
    pub last: usize,
    /// The keys' frames in the user's clip.
    pub clip_frames: Vec<usize>,
}

impl ClipKeys {
    /// Frames to synthesize: the first key to the last, inclusive.
    pub fn frames(&self) -> usize {
        self.last - self.first + 1
    }

    /// The first and last key's frames in the user's clip.
    pub fn span(&self) -> (usize, usize) {
        (
            self.clip_frames[0],
            self.clip_frames[self.clip_frames.len() - 1],
        )
    }
}

/// How far a clip's bone may be from the model's before the clip counts as
/// another skeleton: its length within this factor of the model's either
/// way. CMU conversions of the model's skeleton share its offsets exactly;
/// the networks were trained on those lengths.
pub const BONE_LENGTH_FACTOR: f64 = 1.5;

/// Checks that `clip` has `skeleton`'s joints and channel layout (names,
/// parents, channels in order) and bones of about its lengths (finite, within
/// [`BONE_LENGTH_FACTOR`] of the model's), naming the first joint that differs.
pub fn check_skeleton(clip: &Bvh, skeleton: &Bvh) -> Result<()> {
    let other = |why: String| {
        Err(Error::Invalid(format!(
            "the clip's skeleton is not the model's (the thesis' CMU skeleton, {} joints): {why}",
            skeleton.joints.len()
        )))
    };
    if clip.joints.len() != skeleton.joints.len() {
        return other(format!(
            "it has {} joints (End Sites included)",
            clip.joints.len()
        ));
    }
    let fmt = |c: &[crate::skeleton::bvh::Channel]| {
        c.iter()
            .map(|c| format!("{c:?}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    for (a, b) in clip.joints.iter().zip(&skeleton.joints) {
        if a.name != b.name {
            return other(format!(
                "joint '{}' where the model has '{}'",
                a.name, b.name
            ));
        }
        if a.parent != b.parent {
            return other(format!("joint '{}' has another parent", a.name));
        }
        if a.channels != b.channels {
            return other(format!(
                "joint '{}' has channels [{}], the model's are [{}]",
                a.name,
                fmt(&a.channels),
                fmt(&b.channels)
            ));
        }
        let len = |o: &[f32; 3]| {
            let v = o.map(|x| x as f64);
            (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
        };
        let (la, lb) = (len(&a.offset), len(&b.offset));
        if !la.is_finite() {
            return other(format!("joint '{}' has a non-finite offset", a.name));
        }
        let off = if a.parent.is_none() {
            // the root's offset only moves the whole motion
            la > 1e5
        } else if lb > 1e-6 {
            la * BONE_LENGTH_FACTOR < lb || la > lb * BONE_LENGTH_FACTOR
        } else {
            la > 1e-3
        };
        if off {
            return other(format!(
                "joint '{}' is {la:.4} units from its parent, the model's {lb:.4}",
                a.name
            ));
        }
    }
    Ok(())
}

/// Whole-pose keys at `frames` of `clip` (its own frame numbers, sorted,
/// distinct), brought to the model's rate when `resample_to_model` (the JS
/// `synthesizeFromBvh`); otherwise the clip's frames are taken as the
/// model's, whatever its header says (the CLI's `--from-bvh`, whose meaning
/// held-out evaluations rely on; the CMU salsa headers say 120 fps for
/// 60 fps captures).
pub fn clip_keys(clip: &Bvh, frames: &[usize], resample_to_model: bool) -> Result<ClipKeys> {
    let n = clip.frame_count();
    if frames.is_empty() {
        return Err(Error::Invalid("no key frames given".into()));
    }
    for (i, &f) in frames.iter().enumerate() {
        if f >= n {
            return Err(Error::Invalid(format!(
                "key {i} is at frame {f}, but the clip has {n} frames"
            )));
        }
        if i > 0 && f <= frames[i - 1] {
            return Err(Error::Invalid(format!(
                "key frames must be sorted and distinct: key {i} (frame {f}) follows frame {}",
                frames[i - 1]
            )));
        }
    }
    let fps = clip.fps();
    let at = if resample_to_model {
        resample(clip, MODEL_FPS)?
    } else {
        clip.clone()
    };
    let mapped: Vec<usize> = frames
        .iter()
        .map(|&f| map_frame(f, fps, at.fps()).min(at.frame_count() - 1))
        .collect();
    for (i, w) in mapped.windows(2).enumerate() {
        if w[1] <= w[0] {
            return Err(Error::Invalid(format!(
                "keys at frames {} and {} fall on the same frame at {MODEL_FPS} fps",
                frames[i],
                frames[i + 1]
            )));
        }
    }
    let (first, last) = (mapped[0], mapped[mapped.len() - 1]);
    let keys = mapped
        .iter()
        .map(|&f| Keyframe::from_bvh(&at, f, f - first))
        .collect::<Result<_>>()?;
    Ok(ClipKeys {
        clip: at,
        keys,
        first,
        last,
        clip_frames: frames.to_vec(),
    })
}

/// The clip with the synthesized frames (`motion`, [`ClipKeys::frames`]
/// long) in place of those between the first and the last key, at the
/// clip's own frame rate.
pub fn splice(clip: &Bvh, ck: &ClipKeys, motion: &Motion) -> Result<Bvh> {
    if motion.len() != ck.frames() {
        return Err(Error::Invalid(format!(
            "{} synthesized frames for a span of {}",
            motion.len(),
            ck.frames()
        )));
    }
    let synth = motion.to_bvh(&ck.clip, ck.clip.frame_time)?;
    let c = clip.channel_count();
    let mut full = ck.clip.clone();
    full.motion[ck.first * c..(ck.last + 1) * c].copy_from_slice(&synth.motion);
    if ck.clip.frame_time == clip.frame_time {
        return Ok(full);
    }
    // Resampled: only the frames between the keys change; the rest, and the
    // keys themselves, keep the clip's own values (the round trip through
    // another frame rate could rewrite an angle as its equivalent ± 360°).
    let back = resample(&full, clip.fps())?;
    let (a, b) = ck.span();
    let b = b.min(back.frame_count() - 1);
    let mut out = clip.clone();
    out.motion[a * c..(b + 1) * c].copy_from_slice(&back.motion[a * c..(b + 1) * c]);
    for &f in &ck.clip_frames {
        out.motion[f * c..(f + 1) * c].copy_from_slice(&clip.motion[f * c..(f + 1) * c]);
    }
    Ok(out)
}

/// Roles the model's motion never rotates: every frame of the CMU data it
/// was trained on holds 0 in the collars' and the buttocks' channels. A
/// retargeted clip that rotated them would be unlike anything the networks
/// saw (the residual network's output on such keys left the key poses by
/// 40 units in one frame, on cmu-extra's cmu-hips 02_01); unmapped, their
/// share goes to the upper arms and the thighs.
pub const MODEL_REST_ROLES: [Role; 4] = [
    Role::Collar(Side::Left),
    Role::Collar(Side::Right),
    Role::Buttock(Side::Left),
    Role::Buttock(Side::Right),
];

/// The humanoid roles of the model's skeleton that retargeting follows
/// (all but [`MODEL_REST_ROLES`]).
pub fn model_roles(skeleton: &Bvh) -> Result<RoleMap> {
    Ok(find_roles(skeleton)?.without(&MODEL_REST_ROLES))
}

/// `src` retargeted onto `target`'s skeleton (`deeprep bvh retarget`, JS
/// `client.retarget`). A skeleton that is the model's (`model`) follows only
/// [`model_roles`]; `overrides` (a `--map` file) replace roles found in
/// `src` by name.
pub fn retarget(
    src: &Bvh,
    target: &Bvh,
    model: Option<&Bvh>,
    overrides: &std::collections::BTreeMap<String, Option<String>>,
) -> Result<(Bvh, Retarget)> {
    let roles = |b: &Bvh, o: &std::collections::BTreeMap<String, Option<String>>| match model {
        Some(m) if o.is_empty() && check_skeleton(b, m).is_ok() => model_roles(b),
        _ => RoleMap::with_overrides(b, o),
    };
    use crate::skeleton::retarget::prefix;
    let sm = roles(src, overrides).map_err(|e| prefix("source", e))?;
    let tm = roles(target, &Default::default()).map_err(|e| prefix("target", e))?;
    let r = Retarget::new(src, &sm, target, &tm)?;
    Ok((r.clip(src, target, None)?, r))
}

/// A user's clip on the model's skeleton: the clip itself when it is on it
/// ([`check_skeleton`]), otherwise retargeted onto it
/// ([`crate::skeleton::retarget`]), with the way back.
#[derive(Clone, Debug)]
pub struct OnModel {
    /// The clip on the model's skeleton, at the user's frame rate and length.
    pub clip: Bvh,
    /// The model's skeleton → the user's, when the clip was retargeted.
    back: Option<Retarget>,
}

impl OnModel {
    /// `user` on `skeleton` (the model's). Errors when the clip is neither
    /// on the model's skeleton nor a humanoid whose roles can be found,
    /// with both reasons.
    pub fn new(user: &Bvh, skeleton: &Bvh) -> Result<OnModel> {
        let Err(not_model) = check_skeleton(user, skeleton) else {
            return Ok(OnModel {
                clip: user.clone(),
                back: None,
            });
        };
        let fail = |e: Error| {
            Error::Invalid(format!(
                "{not_model}; and it cannot be retargeted onto it: {e}"
            ))
        };
        let um = find_roles(user).map_err(fail)?;
        let mm = model_roles(skeleton)?;
        let there = Retarget::new(user, &um, skeleton, &mm).map_err(fail)?;
        let back = Retarget::new(skeleton, &mm, user, &um).map_err(fail)?;
        Ok(OnModel {
            clip: there.clip(user, skeleton, None)?,
            back: Some(back),
        })
    }

    /// True when the clip was retargeted.
    pub fn retargeted(&self) -> bool {
        self.back.is_some()
    }

    /// A result made on [`OnModel::clip`] (the model's skeleton, the
    /// clip's length and rate) on the user's skeleton: retargeted back with
    /// the user's unmapped joints carried (the result itself when the clip
    /// was on the model's skeleton).
    pub fn back_whole(&self, user: &Bvh, result: Bvh) -> Result<Bvh> {
        let Some(r) = &self.back else {
            return Ok(result);
        };
        let mut out = r.clip(&result, user, Some(user))?;
        out.frame_time = user.frame_time;
        Ok(out)
    }

    /// A result made from [`OnModel::clip`] (the model's skeleton, the
    /// clip's length and rate; keys `ck`) on the user's skeleton: retargeted
    /// back with the user's unmapped joints (fingers, twist bones) carried
    /// from their clip, and the frames outside the keys' span and the keys
    /// themselves the user's own rows.
    pub fn back(&self, user: &Bvh, result: Bvh, ck: &ClipKeys) -> Result<Bvh> {
        if self.back.is_none() {
            return Ok(result);
        }
        let mut out = self.back_whole(user, result)?;
        let (a, b) = ck.span();
        keep_rows(&mut out, user, &|f| {
            f < a || f > b || ck.clip_frames.contains(&f)
        });
        Ok(out)
    }
}

/// `out`'s rows of the frames where `keep(f)` holds replaced by `user`'s
/// (same skeleton and frame count): what an edit leaves as the user had it.
pub fn keep_rows(out: &mut Bvh, user: &Bvh, keep: &dyn Fn(usize) -> bool) {
    let c = user.channel_count();
    for f in (0..user.frame_count().min(out.frame_count())).filter(|&f| keep(f)) {
        out.motion[f * c..(f + 1) * c].copy_from_slice(&user.motion[f * c..(f + 1) * c]);
    }
}
