//! Frame-rate conversion of BVH motion: each output frame is the clip at
//! its time, with joint rotations slerped and positions lerped between the
//! two nearest source frames. Used to bring a user's clip to the model's
//! 60 fps and the result back to the clip's rate.

use super::pose::{local_rotation, rotation_order};
use super::Bvh;
use crate::error::{Error, Result};
use crate::rotation::euler::{matrix_to_euler, EulerOrder};
use crate::rotation::quat::{matrix_to_quat, quat_to_matrix_unit, slerp};
use crate::rotation::{from_glam_f64, Mat3};

/// Frames per second accepted by [`resample`]: 1 to 1,000.
pub const FPS_RANGE: std::ops::RangeInclusive<f64> = 1.0..=1000.0;

/// Frames a clip of `frames` frames at `from` fps has at `to` fps (same
/// duration; at least 1 frame for a non-empty clip).
pub fn resampled_len(frames: usize, from: f64, to: f64) -> usize {
    if frames == 0 {
        return 0;
    }
    ((frames - 1) as f64 * to / from + 1e-9).floor() as usize + 1
}

/// The frame of a clip at `from` fps nearest to frame `f` at `to` fps.
pub fn map_frame(f: usize, from: f64, to: f64) -> usize {
    (f as f64 * to / from).round() as usize
}

/// `b` at `fps` frames per second. Joints with three rotation channels are
/// slerped (then written back in their own Euler order); other channels are
/// interpolated linearly. A clip already at `fps` (within 10⁻⁴ relative:
/// "Frame Time: 0.0166667" is 60 fps) is returned
/// unchanged.
pub fn resample(b: &Bvh, fps: f64) -> Result<Bvh> {
    let from = b.fps();
    if !FPS_RANGE.contains(&fps) || !FPS_RANGE.contains(&from) {
        return Err(Error::Invalid(format!(
            "resampling from {from} to {fps} fps: frame rates must be within 1 to 1000 fps"
        )));
    }
    if (from - fps).abs() <= 1e-4 * fps {
        return Ok(b.clone());
    }
    let n = b.frame_count();
    let m = resampled_len(n, from, fps);
    crate::motion::check_frames(m)?;
    let c = b.channel_count();
    let orders: Vec<Option<EulerOrder>> =
        (0..b.joints.len()).map(|j| rotation_order(b, j)).collect();
    let mut out = b.clone();
    out.frame_time = 1.0 / fps;
    out.motion = vec![0.0; m * c];
    for t in 0..m {
        let u = t as f64 * from / fps;
        let i = (u.floor() as usize).min(n - 1);
        let k = (i + 1).min(n - 1);
        let w = u - i as f64;
        let (ra, rb) = (b.frame(i), b.frame(k));
        let row = &mut out.motion[t * c..(t + 1) * c];
        for (j, joint) in b.joints.iter().enumerate() {
            let s = joint.channel_start;
            let e = s + joint.channels.len();
            let angles = orders[j].map(|order| {
                let qa =
                    matrix_to_quat(&from_glam_f64(&local_rotation(&joint.channels, &ra[s..e])));
                let qb =
                    matrix_to_quat(&from_glam_f64(&local_rotation(&joint.channels, &rb[s..e])));
                let r: Mat3<f64> = quat_to_matrix_unit(&slerp(&qa, &qb, w));
                matrix_to_euler(&r, order)
            });
            let mut ri = 0;
            for (q, ch) in joint.channels.iter().enumerate() {
                row[s + q] = match (&angles, ch.is_rotation()) {
                    (Some(a), true) => {
                        ri += 1;
                        a[ri - 1].to_degrees() as f32
                    }
                    _ => (ra[s + q] as f64 * (1.0 - w) + rb[s + q] as f64 * w) as f32,
                };
            }
        }
    }
    Ok(out)
}
