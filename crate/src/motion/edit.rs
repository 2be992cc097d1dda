//! Joint-range editing: a joint's range-constrained angles (Table D.1,
//! RC-FK, Sec. 5.2.3) read from a pose and written back, clamped to the
//! joint's ranges. The sketch page's joint sliders use it through the wasm
//! layer; it works on one BVH channel row of the model's skeleton.

use crate::error::{Error, Result};
use crate::motion::{Keyframe, Motion};
use crate::rcfk::RcSkeleton;
use crate::skeleton::Bvh;

/// One joint's range-constrained angles and their ranges, in degrees.
#[derive(Clone, Debug, PartialEq)]
pub struct JointAngles {
    /// The angles `[ux, uy, uz]` of the joint's Euler order (Table D.1).
    pub angles: [f64; 3],
    /// `[lo, hi]` per angle.
    pub ranges: [[f64; 2]; 3],
}

/// The index of `joint` among the joints RC-FK rotates; an error for the
/// root and End Sites, which it does not.
fn rotating_index(rc: &RcSkeleton, joint: usize) -> Result<usize> {
    rc.rotating.iter().position(|&j| j == joint).ok_or_else(|| {
        Error::Invalid(format!(
            "joint {joint} is not rotated by RC-FK (the root and End Sites are not)"
        ))
    })
}

/// `template` (the skeleton, no frames) with `channels` as its one frame.
fn one_frame(template: &Bvh, channels: &[f32]) -> Result<Bvh> {
    let mut one = template.clone();
    if channels.len() != one.channel_count() {
        return Err(Error::Shape {
            what: "channel row".into(),
            expected: format!("{} channels", one.channel_count()),
            found: format!("{}", channels.len()),
        });
    }
    crate::error::check_finite("channel row", channels)?;
    one.motion = channels.to_vec();
    Ok(one)
}

/// The range-constrained angles of `joint` in the pose `channels` (one BVH
/// channel row of `template`'s skeleton), with the joint's ranges.
pub fn joint_angles(
    rc: &RcSkeleton,
    template: &Bvh,
    channels: &[f32],
    joint: usize,
) -> Result<JointAngles> {
    let k = rotating_index(rc, joint)?;
    let one = one_frame(template, channels)?;
    let r = rc.inverse(&one, 0)?;
    let deg = |a: f64| a.to_degrees();
    Ok(JointAngles {
        angles: r.angles[k].map(deg),
        ranges: rc.ranges[k].map(|[lo, hi]| [deg(lo), deg(hi)]),
    })
}

/// The pose `channels` with `joint` turned to the range-constrained
/// `angles` (degrees, each clamped to its range); the other joints and the
/// root keep their values (rewritten through the skeleton's Euler orders).
pub fn set_joint_angles(
    rc: &RcSkeleton,
    template: &Bvh,
    channels: &[f32],
    joint: usize,
    angles: [f64; 3],
) -> Result<Vec<f32>> {
    let k = rotating_index(rc, joint)?;
    if let Some(i) = angles.iter().position(|a| !a.is_finite()) {
        return Err(Error::NotFinite {
            what: "joint angles".into(),
            index: i,
        });
    }
    let one = one_frame(template, channels)?;
    let u: [f64; 3] = std::array::from_fn(|a| {
        let [lo, hi] = rc.ranges[k][a];
        angles[a].to_radians().clamp(lo, hi)
    });
    let key = Keyframe::from_bvh(&one, 0, 0)?;
    let mut rots = key.rotations.unwrap_or_default();
    rots[joint] = rc.rotation_for(k, u);
    let p = key.positions;
    let motion = Motion {
        root: vec![[p[0] as f64, p[1] as f64, p[2] as f64]],
        rotations: vec![rots],
    };
    Ok(motion.to_bvh(template, 1.0 / 60.0)?.motion)
}
