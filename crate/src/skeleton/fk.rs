//! Forward kinematics for BVH skeletons.
//!
//! Each joint's local transform is `T(offset + position channels) · R`,
//! where `R` multiplies the rotation channels in file order (intrinsic: a
//! channel list `Zrotation Xrotation Yrotation` is `Rz · Rx · Ry`).

use super::bvh::Bvh;
use super::pose::Pose;
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

pub use super::pose::local_rotation;

/// Forward kinematics of one frame of channel values (a row of `bvh`'s
/// skeleton; [`Pose::from_row`] checks one from elsewhere).
pub fn global_pose(bvh: &Bvh, frame: &[f32]) -> GlobalPose {
    Pose::read(bvh, frame).global(bvh)
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
    Ok(Pose::from_row(bvh, row)?
        .global(bvh)
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

impl LocalTracks {
    /// Empty tracks with room for `frames` frames of `joints` joints.
    pub fn with_capacity(frames: usize, joints: usize) -> LocalTracks {
        LocalTracks {
            translations: Vec::with_capacity(frames * joints * 3),
            quaternions: Vec::with_capacity(frames * joints * 4),
        }
    }

    /// Appends one frame.
    pub fn push(&mut self, pose: &Pose) {
        for (t, r) in pose.translations.iter().zip(&pose.rotations) {
            self.translations
                .extend_from_slice(&[t.x as f32, t.y as f32, t.z as f32]);
            let q = glam::DQuat::from_mat3(r).normalize();
            self.quaternions
                .extend_from_slice(&[q.x as f32, q.y as f32, q.z as f32, q.w as f32]);
        }
    }
}

/// The local tracks of every frame of `bvh`.
pub fn local_tracks(bvh: &Bvh) -> LocalTracks {
    let mut out = LocalTracks::with_capacity(bvh.frame_count(), bvh.joints.len());
    for f in 0..bvh.frame_count() {
        out.push(&Pose::read(bvh, bvh.frame(f)));
    }
    out
}
