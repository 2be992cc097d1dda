//! Foot locking: a post-processing step (not in the thesis) that removes
//! foot skating from synthesized motion.
//!
//! A foot is in contact where its ankle is near the floor and nearly still.
//! Over each contact, the ankle's horizontal position is pinned, and a
//! two-bone IK on thigh and shin moves the ankle there; the foot keeps its
//! global rotation. The pin blends in and out with smoothstep weights over
//! [`FootLock::blend`] frames. Keyframes stay exact: a contact that holds a
//! key is pinned where that key puts the ankle, and the weight falls to 0
//! at any other key the pin would move (keys with rotations, and partial
//! keys that give the ankle).
//!
//! Legs are found by name: a joint whose name contains `Foot` (and not
//! `Nub`), its parent (shin) and grandparent (thigh). A skeleton without
//! such chains is left as it is.

use super::post::smoothstep;
use super::{Keyframe, Motion};
use crate::rotation::{identity, mul, norm, transpose, Vec3};
use crate::skeleton::two_bone;
use crate::skeleton::Bvh;

/// Contact detection and blending settings, in BVH units and frames.
#[derive(Clone, Debug, PartialEq)]
pub struct FootLock {
    /// An ankle within this height of its floor may be in contact.
    pub height: f64,
    /// Largest horizontal ankle speed (units per frame) of a contact. The
    /// generator's planted feet slide at about 2 units a frame (median), so
    /// the default only leaves out fast swings near the floor.
    pub speed: f64,
    /// Shortest contact, frames.
    pub min_frames: usize,
    /// Frames over which a pin blends in before and out after a contact.
    pub blend: usize,
}

impl Default for FootLock {
    fn default() -> Self {
        // Chosen on training takes (train/deeprep_train/motion/eval.py with EVAL_SPLIT=train,
        // gaps 30 and 120): foot skating 1.59/1.34 -> 1.32/0.83 units/frame
        // for L2P 2.434/6.147 -> 2.456/6.194. Stricter speed limits (0.8, 3)
        // caught fewer contacts; a higher floor band (6) cost more L2P.
        FootLock {
            height: 4.0,
            speed: 10.0,
            min_frames: 6,
            blend: 6,
        }
    }
}

/// What [`lock_feet`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FootLockStats {
    /// Legs found on the skeleton.
    pub legs: usize,
    /// Contacts pinned, over all legs.
    pub contacts: usize,
    /// Frames changed (summed over legs).
    pub frames: usize,
}

fn sub(a: &Vec3<f64>, b: &Vec3<f64>) -> Vec3<f64> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Two-bone IK on one frame ([`crate::skeleton::two_bone`]): moves the
/// ankle of the chain (thigh, shin, foot) to `target`, keeping the knee's
/// bend plane and the foot's global rotation.
fn solve_leg(
    m: &mut Motion,
    f: usize,
    chain: [usize; 3],
    parents: &[Option<usize>],
    offsets: &[Vec3<f64>],
    target: &Vec3<f64>,
) {
    let [hip, knee, ankle] = chain;
    let (rot, pos) = m.global_pose(f, parents, offsets);
    let c = two_bone::Chain {
        h: pos[hip],
        k: pos[knee],
        a: pos[ankle],
        upper: rot[hip],
        lower: rot[knee],
    };
    let Some((thigh_g, shin_g)) = two_bone::solve(&c, target) else {
        return;
    };
    let parent_g = parents[hip].map_or(identity(), |p| rot[p]);
    m.rotations[f][hip] = mul(&transpose(&parent_g), &thigh_g);
    m.rotations[f][knee] = mul(&transpose(&thigh_g), &shin_g);
    m.rotations[f][ankle] = mul(&transpose(&shin_g), &rot[ankle]);
}

/// The legs of a skeleton: (thigh, shin, foot) joint indices.
pub fn legs(skeleton: &Bvh) -> Vec<[usize; 3]> {
    skeleton
        .joints
        .iter()
        .enumerate()
        .filter(|(_, j)| j.name.contains("Foot") && !j.name.contains("Nub"))
        .filter_map(|(i, j)| {
            let shin = j.parent?;
            let thigh = skeleton.joints[shin].parent?;
            Some([thigh, shin, i])
        })
        .collect()
}

/// Pins feet in contact (see the module docs). Run it after the keys were
/// made exact; it keeps them exact.
pub fn lock_feet(
    m: &mut Motion,
    skeleton: &Bvh,
    keys: &[Keyframe],
    cfg: &FootLock,
) -> FootLockStats {
    let frames = m.len();
    let legs = legs(skeleton);
    let mut stats = FootLockStats {
        legs: legs.len(),
        ..Default::default()
    };
    if frames < 3 || legs.is_empty() || m.rotations[0].len() != skeleton.joints.len() {
        return stats;
    }
    let parents: Vec<Option<usize>> = skeleton.joints.iter().map(|j| j.parent).collect();
    let offsets: Vec<Vec3<f64>> = skeleton
        .joints
        .iter()
        .map(|j| j.offset.map(|v| v as f64))
        .collect();
    // Ankle tracks of every leg, from one FK pass (the legs do not move each
    // other's ankles, so locking one leaves the others' tracks valid).
    let mut tracks: Vec<Vec<Vec3<f64>>> = vec![Vec::with_capacity(frames); legs.len()];
    for f in 0..frames {
        let (_, pos) = m.global_pose(f, &parents, &offsets);
        for (track, chain) in tracks.iter_mut().zip(&legs) {
            track.push(pos[chain[2]]);
        }
    }
    for (chain, track) in legs.into_iter().zip(tracks) {
        let ankle = chain[2];
        // Keys that fix this ankle: whole poses, and partial keys that give
        // any of its coordinates.
        let key_frames: Vec<usize> = keys
            .iter()
            .filter(|k| k.frame < frames)
            .filter(|k| k.rotations.is_some() || k.mask.iter().skip(3 * ankle).take(3).any(|m| *m))
            .map(|k| k.frame)
            .collect();
        // The ankle's floor: a low percentile of its height.
        let mut hs: Vec<f64> = track.iter().map(|p| p[1]).collect();
        hs.sort_by(|a, b| a.total_cmp(b));
        let floor = hs[frames / 20];
        let speed = |f: usize| {
            let (a, b) = (f.saturating_sub(1), (f + 1).min(frames - 1));
            let d = sub(&track[b], &track[a]);
            (d[0] * d[0] + d[2] * d[2]).sqrt() / (b - a) as f64
        };
        let contact: Vec<bool> = (0..frames)
            .map(|f| track[f][1] < floor + cfg.height && speed(f) < cfg.speed)
            .collect();
        // Per frame: the strongest pin (weight, x, z).
        let mut pin: Vec<(f64, f64, f64)> = vec![(0.0, 0.0, 0.0); frames];
        let mut f = 0;
        while f < frames {
            if !contact[f] {
                f += 1;
                continue;
            }
            let s = f;
            while f < frames && contact[f] {
                f += 1;
            }
            let e = f; // contact over [s, e)
            if e - s < cfg.min_frames {
                continue;
            }
            stats.contacts += 1;
            let mid = (s + e) / 2;
            let at = key_frames
                .iter()
                .copied()
                .filter(|k| (s..e).contains(k))
                .min_by_key(|k| k.abs_diff(mid))
                .unwrap_or_else(|| {
                    (s..e)
                        .min_by(|a, b| speed(*a).total_cmp(&speed(*b)))
                        .unwrap_or(mid)
                });
            let (px, pz) = (track[at][0], track[at][2]);
            // Keys the pin would move stay as they are.
            let moved: Vec<usize> = key_frames
                .iter()
                .copied()
                .filter(|&k| (track[k][0] - px).hypot(track[k][2] - pz) > 1e-6)
                .collect();
            let lo = s.saturating_sub(cfg.blend);
            let hi = (e + cfg.blend).min(frames);
            for (t, slot) in pin.iter_mut().enumerate().take(hi).skip(lo) {
                let mut w = if t < s {
                    smoothstep((t + cfg.blend + 1 - s) as f64 / (cfg.blend + 1) as f64)
                } else if t >= e {
                    smoothstep((e + cfg.blend - t) as f64 / (cfg.blend + 1) as f64)
                } else {
                    1.0
                };
                for &k in &moved {
                    w *= smoothstep(k.abs_diff(t) as f64 / (cfg.blend + 1) as f64);
                }
                if w > slot.0 {
                    *slot = (w, px, pz);
                }
            }
        }
        for (t, &(w, px, pz)) in pin.iter().enumerate() {
            if w <= 0.0 {
                continue;
            }
            let p = track[t];
            let target = [p[0] + w * (px - p[0]), p[1], p[2] + w * (pz - p[2])];
            if norm(&sub(&target, &p)) < 1e-9 {
                continue;
            }
            solve_leg(m, t, chain, &parents, &offsets, &target);
            stats.frames += 1;
        }
    }
    stats
}
