//! Retargeting motion between humanoid skeletons.
//!
//! A humanoid's joints are found by role ([`Role`]: hips, spine, chest,
//! neck, head, and per side collar, upper arm, forearm, hand, buttock,
//! thigh, shin, foot, toe). [`find_roles`] finds them from the names of the
//! common families (the model's Daz-style `hip/abdomen/lThigh`,
//! MotionBuilder/3ds Max-style `Hips/LeftUpLeg/LowerBack/Spine1` and
//! `LeftHip/LeftKnee/LeftAnkle`, iClone `CC_Base_*`, Mixamo's `mixamorig:`,
//! VRM humanoid names, Blender/Unreal `thigh.L`/`thigh_l` suffixes) and from
//! the tree: the chest is where the two arms meet, the spine the joint
//! below it, a collar the joint between the chest and an upper arm. An
//! explicit map ([`RoleMap::with_overrides`]) replaces any of them.
//!
//! [`Retarget`] carries motion from one skeleton to another:
//! - **rest alignment per bone**: for each pair of mapped joints, the
//!   rotation `A` that turns the target's rest bone directions into the
//!   source's (towards the nearest mapped joints below it; a best fit over
//!   several branches, Horn's quaternion method), so a T-pose and an
//!   A-pose, or bones along other axes, line up;
//! - **rotations as world-space changes from the rest pose**: a mapped
//!   target joint's global rotation is the source joint's times `A`, so
//!   every mapped bone points where the source's points;
//! - **root translation scaled by leg length** (the hips' rest distance
//!   from the ankles, [`hip_height`]);
//! - **feet placed**: each ankle where the source's is, scaled like the
//!   root, by two-bone IK on thigh and shin ([`super::two_bone`]), so that
//!   planted feet stay planted on other proportions; in a clip
//!   ([`Retarget::clip`]), while a source foot is in contact and its scaled
//!   ankle lies beyond the leg's reach, the hips come down until it does not;
//! - **unmapped joints** (fingers, eyes, twist bones) stay at rest, or keep
//!   their values from a clip on the target skeleton ([`Retarget::clip`]'s
//!   `carry`: the way back onto a user's own skeleton).
//!
//! Both skeletons are taken as Y-up with BVH's rest convention (every
//! rotation channel zero is the rest pose). The frame rate is kept;
//! [`super::resample`] changes it.

mod fit;
pub mod roles;

pub use roles::{find_roles, parse_map, Role, RoleMap, Side};

use super::bvh::Bvh;
use super::pose::{offset, Pose};
use crate::error::{Error, Result};
use crate::rotation::{from_glam_f64, to_glam_f64};
use fit::best_rotation;
use glam::{DMat3, DQuat, DVec3};
use roles::{ancestors, is_ancestor, SIDES};
use std::collections::BTreeMap;

/// A position (glam's double-precision vector).
pub type Vec3 = DVec3;

/// Every joint's position in the rest pose (all channels zero).
pub fn rest_positions(bvh: &Bvh) -> Vec<DVec3> {
    let mut p: Vec<DVec3> = Vec::with_capacity(bvh.joints.len());
    for j in &bvh.joints {
        let base = j.parent.map(|q| p[q]).unwrap_or(DVec3::ZERO);
        p.push(base + offset(j));
    }
    p
}

/// The longest bone retargeting accepts, in hips-to-feet heights.
pub const MAX_BONE_OVER_LEGS: f64 = 100.0;

/// Rest-pose distances below this count as the same place.
const NEAR: f64 = 1e-6;

/// Motion carried from a source skeleton onto a target skeleton.
#[derive(Clone, Debug)]
pub struct Retarget {
    /// Per target joint: the source joint it follows and the rest alignment
    /// `A` (target rest directions → source rest directions).
    follow: Vec<Option<(usize, DMat3)>>,
    /// Target hips, source hips.
    hips: (usize, usize),
    /// Root translation scale: the target's [`hip_height`] over the source's.
    pub scale: f64,
    /// The mapped pairs, role → (target joint, source joint).
    pub pairs: BTreeMap<Role, (usize, usize)>,
    /// Per leg whose thigh, shin and foot are mapped with the foot a child
    /// of the shin and the shin of the thigh on the target: the three
    /// (target joint, source joint) pairs.
    legs: Vec<[(usize, usize); 3]>,
    /// The source's [`hip_height`] (contacts are judged against it).
    src_leg: f64,
}

/// The hips' distance from the ankles in the rest pose (legs straight in
/// every family's rest pose), averaged over the legs: what the root path is
/// scaled by, so that the scaled hips leave the feet within reach. A
/// distance, not a height: some files' rest poses are Z-up under a rotated
/// root.
pub fn hip_height(map: &RoleMap, rest: &[DVec3]) -> f64 {
    let hips = rest[map.joints[&Role::Hips]];
    SIDES
        .iter()
        .map(|&s| hips.distance(rest[map.joints[&Role::Foot(s)]]))
        .sum::<f64>()
        / 2.0
}

impl Retarget {
    /// Retargeting from `src` (roles `src_map`) to `dst` (roles `dst_map`):
    /// the roles both have are followed.
    pub fn new(src: &Bvh, src_map: &RoleMap, dst: &Bvh, dst_map: &RoleMap) -> Result<Retarget> {
        let pairs: BTreeMap<Role, (usize, usize)> = dst_map
            .joints
            .iter()
            .filter_map(|(r, &t)| src_map.joints.get(r).map(|&s| (*r, (t, s))))
            .collect();
        let (rs, rd) = (rest_positions(src), rest_positions(dst));
        let (ls, ld) = (hip_height(src_map, &rs), hip_height(dst_map, &rd));
        if !(ls > NEAR && ld > NEAR && ls.is_finite() && ld.is_finite()) {
            return Err(Error::Invalid(format!(
                "the hips must stand apart from the feet in both rest poses: {ls} (source) and {ld} (target) units"
            )));
        }
        // a bone far longer than the legs is a broken file, not a character
        for (b, rest) in [(src, &rs), (dst, &rd)] {
            let h = if std::ptr::eq(b, src) { ls } else { ld };
            for (j, joint) in b.joints.iter().enumerate() {
                let len = joint.parent.map_or(0.0, |p| rest[j].distance(rest[p]));
                if !len.is_finite() || len > MAX_BONE_OVER_LEGS * h {
                    return Err(Error::Invalid(format!(
                        "joint '{}' is {len:e} units from its parent, over {MAX_BONE_OVER_LEGS} times the hips' height above the feet ({h:.4})",
                        joint.name
                    )));
                }
            }
        }
        let by_target: BTreeMap<usize, usize> = pairs.values().copied().collect();
        let mut follow: Vec<Option<(usize, DMat3)>> = vec![None; dst.joints.len()];
        let dst_children = dst.children();
        let src_children = src.children();
        // parents precede children: a pair with nothing to aim at takes its
        // nearest mapped ancestor's alignment
        for t in 0..dst.joints.len() {
            let Some(&s) = by_target.get(&t) else {
                continue;
            };
            let dirs = aim_pairs(t, s, &by_target, &dst_children, src, &rd, &rs);
            let a = if dirs.len() >= 2 {
                Some(best_rotation(&dirs))
            } else if let Some((a, b)) = dirs.first() {
                Some(DMat3::from_quat(DQuat::from_rotation_arc(*a, *b)))
            } else {
                let dt = mean_below(t, &dst_children, &rd);
                let ds = mean_below(s, &src_children, &rs);
                match (dt, ds) {
                    (Some(a), Some(b)) => Some(DMat3::from_quat(DQuat::from_rotation_arc(a, b))),
                    _ => None,
                }
            };
            let a = a.unwrap_or_else(|| {
                ancestors(dst, t)
                    .into_iter()
                    .skip(1)
                    .find_map(|k| follow[k].map(|(_, a)| a))
                    .unwrap_or(DMat3::IDENTITY)
            });
            follow[t] = Some((s, a));
        }
        let legs = SIDES
            .iter()
            .filter_map(|&s| {
                let p = |r| pairs.get(&r).copied();
                let legs = [p(Role::Thigh(s))?, p(Role::Shin(s))?, p(Role::Foot(s))?];
                let chained = dst.joints[legs[2].0].parent == Some(legs[1].0)
                    && dst.joints[legs[1].0].parent == Some(legs[0].0);
                chained.then_some(legs)
            })
            .collect();
        Ok(Retarget {
            legs,
            follow,
            hips: (dst_map.joints[&Role::Hips], src_map.joints[&Role::Hips]),
            scale: ld / ls,
            src_leg: ls,
            pairs,
        })
    }

    /// Retargeting between two skeletons whose roles are found by name
    /// ([`find_roles`]; `src_overrides` replace the source's).
    pub fn between(
        src: &Bvh,
        dst: &Bvh,
        src_overrides: &BTreeMap<String, Option<String>>,
    ) -> Result<Retarget> {
        let sm = RoleMap::with_overrides(src, src_overrides).map_err(|e| prefix("source", e))?;
        let dm = find_roles(dst).map_err(|e| prefix("target", e))?;
        Retarget::new(src, &sm, dst, &dm)
    }

    /// One frame: the target pose whose mapped bones point where the
    /// source's do. `carry` is a pose on the target skeleton whose unmapped
    /// joints are kept (rest when `None`).
    pub fn pose(&self, src: &Bvh, src_pose: &Pose, dst: &Bvh, carry: Option<&Pose>) -> Pose {
        self.pose_with_contacts(src, src_pose, dst, carry, &[])
    }

    /// [`Retarget::pose`], with `contact[i]` true where leg `i`'s source
    /// foot is on the floor: there, when the scaled ankle lies beyond the
    /// leg's reach (a source whose legs reach further from its hips than
    /// the target's), the hips come down until it does not, so a planted
    /// foot stays planted.
    fn pose_with_contacts(
        &self,
        src: &Bvh,
        src_pose: &Pose,
        dst: &Bvh,
        carry: Option<&Pose>,
        contact: &[bool],
    ) -> Pose {
        let g = src_pose.global(src);
        let n = dst.joints.len();
        let mut global: Vec<DMat3> = Vec::with_capacity(n);
        let mut rotations = Vec::with_capacity(n);
        let mut translations: Vec<DVec3> = dst.joints.iter().map(offset).collect();
        let hips_line = ancestors(dst, self.hips.0);
        for (t, joint) in dst.joints.iter().enumerate() {
            let parent = joint.parent.map(|p| global[p]).unwrap_or(DMat3::IDENTITY);
            let above_hips = t != self.hips.0 && hips_line.contains(&t);
            let gt = match (self.follow[t], carry) {
                (Some((s, a)), _) => g.rotations[s] * a,
                (None, Some(c)) if !above_hips => parent * c.rotations[t],
                _ => parent,
            };
            if let (None, Some(c)) = (self.follow[t], carry) {
                if !above_hips {
                    translations[t] = c.translations[t];
                }
            }
            rotations.push(parent.transpose() * gt);
            global.push(gt);
        }
        // the hips where the source's are, scaled; joints above them at rest
        let want = g.positions[self.hips.1] * self.scale;
        let rest = rest_positions(dst);
        let root = hips_line.last().copied().unwrap_or(self.hips.0);
        translations[root] = want - rest[self.hips.0] + offset(&dst.joints[root]);
        let mut pose = Pose {
            translations,
            rotations,
        };
        let gt = pose.global(dst);
        let drop = self
            .legs
            .iter()
            .zip(contact)
            .filter(|(_, &c)| c)
            .map(|(&[(thigh, _), (shin, _), (foot, sf)], _)| {
                let h = gt.positions[thigh];
                // the longest reach two-bone IK gives (two_bone::solve's bound)
                let reach = (gt.positions[shin] - h).length()
                    + (gt.positions[foot] - gt.positions[shin]).length()
                    - 1e-4;
                let d = g.positions[sf] * self.scale - h;
                let across = d.x * d.x + d.z * d.z;
                if d.length() <= reach || across >= reach * reach {
                    return 0.0;
                }
                // lower the hips by t: |d + t ŷ| = reach
                (-d.y - (reach * reach - across).sqrt()).max(0.0)
            })
            .fold(0.0f64, f64::max);
        pose.translations[root].y -= drop;
        // each ankle where the source's is, scaled
        for &[(thigh, _), (shin, _), (foot, sf)] in &self.legs {
            let gt = pose.global(dst);
            let to = |v: DVec3| [v.x, v.y, v.z];
            let chain = super::two_bone::Chain {
                h: to(gt.positions[thigh]),
                k: to(gt.positions[shin]),
                a: to(gt.positions[foot]),
                upper: from_glam_f64(&gt.rotations[thigh]),
                lower: from_glam_f64(&gt.rotations[shin]),
            };
            let target = to(g.positions[sf] * self.scale);
            let Some((upper, lower)) = super::two_bone::solve(&chain, &target) else {
                continue;
            };
            let (upper, lower) = (to_glam_f64(&upper), to_glam_f64(&lower));
            let parent = dst.joints[thigh]
                .parent
                .map(|p| gt.rotations[p])
                .unwrap_or(DMat3::IDENTITY);
            pose.rotations[thigh] = parent.transpose() * upper;
            pose.rotations[shin] = upper.transpose() * lower;
            pose.rotations[foot] = lower.transpose() * gt.rotations[foot];
        }
        pose
    }

    /// Every frame of `src` on `dst`'s skeleton, at `src`'s frame rate.
    /// `carry`, a clip on `dst`'s skeleton with the same frame count, gives
    /// the unmapped joints their values (the way back onto a user's own
    /// skeleton); without it they stay at rest.
    pub fn clip(&self, src: &Bvh, dst: &Bvh, carry: Option<&Bvh>) -> Result<Bvh> {
        let frames = src.frame_count();
        if let Some(c) = carry {
            if c.frame_count() != frames || c.channel_count() != dst.channel_count() {
                return Err(Error::Invalid(format!(
                    "the clip whose unmapped joints are kept has {} frames of {} channels; {frames} of {} expected",
                    c.frame_count(),
                    c.channel_count(),
                    dst.channel_count()
                )));
            }
        }
        let orders = super::pose::rotation_orders(dst);
        // contacts: a source foot within 5% of the source's leg length of its
        // lowest height in the clip
        let feet: Vec<Vec<f64>> = (0..frames)
            .map(|f| {
                let g = Pose::read(src, src.frame(f)).global(src);
                self.legs.iter().map(|l| g.positions[l[2].1].y).collect()
            })
            .collect();
        let leg = self.src_leg;
        let floor: Vec<f64> = (0..self.legs.len())
            .map(|i| feet.iter().map(|f| f[i]).fold(f64::INFINITY, f64::min))
            .collect();
        let mut motion = Vec::with_capacity(frames * dst.channel_count());
        for (f, heights) in feet.iter().enumerate() {
            let sp = Pose::read(src, src.frame(f));
            let cp = carry.map(|c| Pose::read(dst, c.frame(f)));
            let contact: Vec<bool> = heights
                .iter()
                .zip(&floor)
                .map(|(y, lo)| *y < lo + 0.05 * leg)
                .collect();
            let p = self.pose_with_contacts(src, &sp, dst, cp.as_ref(), &contact);
            motion.extend(p.to_row_with_orders(dst, &orders)?);
        }
        if let Some(i) = motion.iter().position(|v| !v.is_finite()) {
            return Err(Error::Invalid(format!(
                "retargeting gave a non-finite value at frame {}",
                i / dst.channel_count().max(1)
            )));
        }
        Ok(Bvh {
            joints: dst.joints.clone(),
            frame_time: src.frame_time,
            motion,
        })
    }

    /// Target joints that follow a source joint.
    pub fn mapped_targets(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self.pairs.values().map(|p| p.0).collect();
        v.sort_unstable();
        v
    }
}

/// `e` with the skeleton it is about ("source" or "target") in front.
pub(crate) fn prefix(which: &str, e: Error) -> Error {
    match e {
        Error::Invalid(m) => Error::Invalid(format!("{which} skeleton: {m}")),
        other => other,
    }
}

/// The directions a pair aims at: for each nearest mapped pair below the
/// target joint (and below the source joint), the two rest directions; a
/// pair at the same rest place on either side is looked through.
fn aim_pairs(
    t: usize,
    s: usize,
    by_target: &BTreeMap<usize, usize>,
    dst_children: &[Vec<usize>],
    src: &Bvh,
    rd: &[DVec3],
    rs: &[DVec3],
) -> Vec<(DVec3, DVec3)> {
    let mut out = Vec::new();
    let mut stack: Vec<usize> = dst_children[t].clone();
    while let Some(k) = stack.pop() {
        match by_target.get(&k) {
            Some(&ks) if is_ancestor(src, s, ks) && ks != s => {
                let (a, b) = (rd[k] - rd[t], rs[ks] - rs[s]);
                if a.length() > NEAR && b.length() > NEAR {
                    out.push((a.normalize(), b.normalize()));
                } else {
                    stack.extend(dst_children[k].iter().copied());
                }
            }
            _ => stack.extend(dst_children[k].iter().copied()),
        }
    }
    out
}

/// The mean rest direction from `j` to every joint below it (`None` when
/// they all sit at `j`).
fn mean_below(j: usize, children: &[Vec<usize>], rest: &[DVec3]) -> Option<DVec3> {
    let mut stack = children[j].clone();
    let (mut sum, mut n) = (DVec3::ZERO, 0usize);
    while let Some(k) = stack.pop() {
        sum += rest[k] - rest[j];
        n += 1;
        stack.extend(children[k].iter().copied());
    }
    let d = sum / n.max(1) as f64;
    (d.length() > NEAR).then(|| d.normalize())
}

/// Mean distance between `a`'s and `b`'s global positions of the joints
/// `joints` (same skeleton, same frame count), in the skeleton's units.
pub fn mean_position_error(a: &Bvh, b: &Bvh, joints: &[usize]) -> Result<f64> {
    if a.frame_count() != b.frame_count() || a.channel_count() != b.channel_count() {
        return Err(Error::Invalid(
            "the two clips differ in frames or channels".into(),
        ));
    }
    let (mut sum, mut n) = (0.0, 0usize);
    for f in 0..a.frame_count() {
        let (pa, pb) = (
            Pose::read(a, a.frame(f)).global(a),
            Pose::read(b, b.frame(f)).global(b),
        );
        for &j in joints {
            sum += pa.positions[j].distance(pb.positions[j]);
            n += 1;
        }
    }
    Ok(sum / n.max(1) as f64)
}
