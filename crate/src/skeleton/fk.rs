//! Forward kinematics for BVH skeletons.
//!
//! Each joint's local transform is `T(offset + position channels) · R`,
//! where `R` multiplies the rotation channels in file order (intrinsic: a
//! channel list `Zrotation Xrotation Yrotation` is `Rz · Rx · Ry`).

use super::bvh::{Bvh, Channel};
use crate::error::{Error, Result};
use glam::{DMat3, DVec3};

/// Global rotation and position of every joint in one frame.
#[derive(Clone, Debug)]
pub struct GlobalPose {
    /// Global rotation matrix per joint.
    pub rotations: Vec<DMat3>,
    /// Global position per joint.
    pub positions: Vec<DVec3>,
}

/// The local rotation of a joint from its channel values (degrees).
pub fn local_rotation(channels: &[Channel], values: &[f32]) -> DMat3 {
    let mut r = DMat3::IDENTITY;
    for (c, v) in channels.iter().zip(values) {
        let a = (*v as f64).to_radians();
        r *= match c {
            Channel::Xrotation => DMat3::from_rotation_x(a),
            Channel::Yrotation => DMat3::from_rotation_y(a),
            Channel::Zrotation => DMat3::from_rotation_z(a),
            _ => DMat3::IDENTITY,
        };
    }
    r
}

/// Forward kinematics of one frame of channel values.
pub fn global_pose(bvh: &Bvh, frame: &[f32]) -> GlobalPose {
    let n = bvh.joints.len();
    let mut rotations = Vec::with_capacity(n);
    let mut positions = Vec::with_capacity(n);
    for j in &bvh.joints {
        let vals = &frame[j.channel_start..j.channel_start + j.channels.len()];
        let mut t = DVec3::new(j.offset[0] as f64, j.offset[1] as f64, j.offset[2] as f64);
        for (c, v) in j.channels.iter().zip(vals) {
            if !c.is_rotation() {
                t[c.axis()] += *v as f64;
            }
        }
        let r = local_rotation(&j.channels, vals);
        match j.parent {
            None => {
                rotations.push(r);
                positions.push(t);
            }
            Some(p) => {
                let pr: DMat3 = rotations[p];
                let pp: DVec3 = positions[p];
                positions.push(pp + pr * t);
                rotations.push(pr * r);
            }
        }
    }
    GlobalPose {
        rotations,
        positions,
    }
}

/// Global joint positions for frames `[start, end)`, flat
/// `frames × joints × 3` (`f32`, the file's units).
pub fn positions(bvh: &Bvh, start: usize, end: usize) -> Result<Vec<f32>> {
    let frames = bvh.frame_count();
    if start > end || end > frames {
        return Err(Error::Invalid(format!(
            "frame range {start}..{end} is outside the clip's {frames} frames"
        )));
    }
    let mut out = Vec::with_capacity((end - start) * bvh.joints.len() * 3);
    for f in start..end {
        let g = global_pose(bvh, bvh.frame(f));
        for p in g.positions {
            out.extend_from_slice(&[p.x as f32, p.y as f32, p.z as f32]);
        }
    }
    Ok(out)
}

/// Global joint positions of one channel row on `bvh`'s skeleton, flat
/// `joints × 3` (`f32`): FK of a pose that is not one of the clip's frames
/// (a key being edited). The row must have the skeleton's channel count.
pub fn pose_positions(bvh: &Bvh, row: &[f32]) -> Result<Vec<f32>> {
    let c = bvh.channel_count();
    if row.len() != c {
        return Err(Error::Invalid(format!(
            "a pose has {c} channel values on this skeleton, found {}",
            row.len()
        )));
    }
    if let Some(i) = row.iter().position(|v| !v.is_finite()) {
        return Err(Error::Invalid(format!(
            "channel value {i} of the pose is not finite"
        )));
    }
    Ok(global_pose(bvh, row)
        .positions
        .iter()
        .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
        .collect())
}

/// Every joint's local transform in every frame, the form animation
/// systems take (three.js `AnimationClip` tracks, glTF channels).
#[derive(Clone, Debug, PartialEq)]
pub struct LocalTracks {
    /// `frames × joints × 3`: offset plus position channels.
    pub translations: Vec<f32>,
    /// `frames × joints × 4`: the local rotation as a unit quaternion
    /// `[x, y, z, w]` (identity for joints without rotation channels).
    pub quaternions: Vec<f32>,
}

/// The local tracks of every frame of `bvh`.
pub fn local_tracks(bvh: &Bvh) -> LocalTracks {
    let (n, j) = (bvh.frame_count(), bvh.joints.len());
    let mut out = LocalTracks {
        translations: Vec::with_capacity(n * j * 3),
        quaternions: Vec::with_capacity(n * j * 4),
    };
    for f in 0..n {
        let row = bvh.frame(f);
        for joint in &bvh.joints {
            let vals = &row[joint.channel_start..joint.channel_start + joint.channels.len()];
            let mut t = joint.offset;
            for (c, v) in joint.channels.iter().zip(vals) {
                if !c.is_rotation() {
                    t[c.axis()] += *v;
                }
            }
            out.translations.extend_from_slice(&t);
            let q = glam::DQuat::from_mat3(&local_rotation(&joint.channels, vals)).normalize();
            out.quaternions
                .extend_from_slice(&[q.x as f32, q.y as f32, q.z as f32, q.w as f32]);
        }
    }
    out
}
