//! One frame of a skeleton in local form, and the one place a BVH channel
//! row is interpreted.
//!
//! A BVH row holds, per joint in file order, that joint's channels: position
//! channels add to the joint's offset, rotation channels multiply in file
//! order (intrinsic: `Zrotation Xrotation Yrotation` is `Rz · Rx · Ry`).
//! [`Pose::from_row`] reads that once; FK, RC-FK's inverse, the key
//! extraction of the in-betweening and the local animation tracks all start
//! from a [`Pose`]. [`Pose::to_row`] writes one back in each joint's own
//! channel order.

use super::bvh::{Bvh, Channel};
use super::fk::GlobalPose;
use crate::error::{Error, Result};
use crate::rotation::euler::{matrix_to_euler, Axis, EulerOrder, Frame};
use crate::rotation::from_glam_f64;
use glam::{DMat3, DVec3};

/// Every joint's local transform in one frame: `T(translation) · R(rotation)`
/// relative to its parent (the root's relative to the world).
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    /// Per joint: its offset plus its position channels.
    pub translations: Vec<DVec3>,
    /// Per joint: its rotation channels multiplied in file order (identity
    /// for joints without rotation channels, End Sites among them).
    pub rotations: Vec<DMat3>,
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

/// The intrinsic Euler order of a joint with exactly three rotation
/// channels, in file order; `None` for fewer (or repeated) axes.
pub fn rotation_order(bvh: &Bvh, joint: usize) -> Option<EulerOrder> {
    let axes: Vec<Axis> = bvh.joints[joint]
        .channels
        .iter()
        .filter(|c| c.is_rotation())
        .map(|c| [Axis::X, Axis::Y, Axis::Z][c.axis()])
        .collect();
    (axes.len() == 3)
        .then(|| EulerOrder::new([axes[0], axes[1], axes[2]], Frame::Intrinsic).ok())
        .flatten()
}

/// The axes of a joint's rotation channels, in file order.
fn rotation_axes(joint: &super::bvh::Joint) -> Vec<Axis> {
    joint
        .channels
        .iter()
        .filter(|c| c.is_rotation())
        .map(|c| [Axis::X, Axis::Y, Axis::Z][c.axis()])
        .collect()
}

/// The angle (radians) of `m`'s twist about one coordinate axis: its
/// rotation about that axis with the swing about the other two removed
/// (exact when `m` turns about that axis alone).
fn twist_angle(m: &crate::rotation::Mat3<f64>, axis: Axis) -> f64 {
    let q = crate::rotation::quat::matrix_to_quat(m); // [x, y, z, w]
    let a = 2.0 * q[axis as usize].atan2(q[3]);
    if a > std::f64::consts::PI {
        a - 2.0 * std::f64::consts::PI
    } else if a < -std::f64::consts::PI {
        a + 2.0 * std::f64::consts::PI
    } else {
        a
    }
}

/// Angles (radians) for a joint whose rotation channels are not one of the
/// twelve three-axis orders: one channel or two (the parser refuses a
/// repeated channel). Two axes `a, b` are the first two angles of the
/// intrinsic order `a b c` (`c` the third axis): exact for every rotation
/// the two channels can express. Otherwise each channel in turn takes the
/// twist about its axis of what the channels before it left: exact for one
/// channel, the closest turn about it for any other rotation.
fn partial_angles(axes: &[Axis], m: &crate::rotation::Mat3<f64>) -> Vec<f64> {
    if let [a, b] = axes {
        if a != b {
            let c = [Axis::X, Axis::Y, Axis::Z]
                .into_iter()
                .find(|c| c != a && c != b)
                .unwrap_or(Axis::X);
            if let Ok(order) = EulerOrder::new([*a, *b, c], Frame::Intrinsic) {
                let e = matrix_to_euler(m, order);
                return vec![e[0], e[1]];
            }
        }
    }
    let mut rest = *m;
    axes.iter()
        .map(|&axis| {
            let angle = twist_angle(&rest, axis);
            let undo = crate::rotation::euler::axis_rotation(axis, -angle);
            rest = crate::rotation::mul(&undo, &rest);
            angle
        })
        .collect()
}

/// [`rotation_order`] of every joint.
pub fn rotation_orders(bvh: &Bvh) -> Vec<Option<EulerOrder>> {
    (0..bvh.joints.len())
        .map(|j| rotation_order(bvh, j))
        .collect()
}

/// A joint's offset from its parent, in double precision.
pub fn offset(joint: &super::bvh::Joint) -> DVec3 {
    DVec3::new(
        joint.offset[0] as f64,
        joint.offset[1] as f64,
        joint.offset[2] as f64,
    )
}

impl Pose {
    /// Reads a channel row of `bvh`'s skeleton. Errors when the row's length
    /// is not the skeleton's channel count or a value is not finite.
    pub fn from_row(bvh: &Bvh, row: &[f32]) -> Result<Pose> {
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
        Ok(Pose::read(bvh, row))
    }

    /// Frame `f` of the clip (a frame of a parsed clip has the right length;
    /// the parser rejects non-finite values).
    pub fn of_frame(bvh: &Bvh, f: usize) -> Result<Pose> {
        if f >= bvh.frame_count() {
            return Err(Error::Invalid(format!(
                "frame {f} is outside the clip's {} frames",
                bvh.frame_count()
            )));
        }
        Ok(Pose::read(bvh, bvh.frame(f)))
    }

    /// [`Pose::from_row`] without the checks, for rows known to fit.
    pub(crate) fn read(bvh: &Bvh, row: &[f32]) -> Pose {
        let n = bvh.joints.len();
        let mut translations = Vec::with_capacity(n);
        let mut rotations = Vec::with_capacity(n);
        for j in &bvh.joints {
            let vals = &row[j.channel_start..j.channel_start + j.channels.len()];
            let mut t = offset(j);
            for (c, v) in j.channels.iter().zip(vals) {
                if !c.is_rotation() {
                    t[c.axis()] += *v as f64;
                }
            }
            translations.push(t);
            rotations.push(local_rotation(&j.channels, vals));
        }
        Pose {
            translations,
            rotations,
        }
    }

    /// The local rotations in the crate's matrix type.
    pub fn rotation_matrices(&self) -> Vec<crate::rotation::Mat3<f64>> {
        self.rotations.iter().map(from_glam_f64).collect()
    }

    /// Forward kinematics: every joint's global rotation and position.
    pub fn global(&self, bvh: &Bvh) -> GlobalPose {
        let n = bvh.joints.len();
        let mut rotations: Vec<DMat3> = Vec::with_capacity(n);
        let mut positions: Vec<DVec3> = Vec::with_capacity(n);
        for (j, joint) in bvh.joints.iter().enumerate() {
            let (t, r) = (self.translations[j], self.rotations[j]);
            match joint.parent {
                None => {
                    rotations.push(r);
                    positions.push(t);
                }
                Some(p) => {
                    positions.push(positions[p] + rotations[p] * t);
                    rotations.push(rotations[p] * r);
                }
            }
        }
        GlobalPose {
            rotations,
            positions,
        }
    }

    /// The channel row of this pose on `bvh`'s skeleton: position channels
    /// are `translation − offset`; joints with three rotation channels get
    /// the Euler angles of their rotation in their own order (degrees).
    /// Joints with one or two rotation channels cannot hold every rotation:
    /// their rotation channels get the angles that express the rotation
    /// about those axes (`partial_angles`).
    pub fn to_row(&self, bvh: &Bvh) -> Result<Vec<f32>> {
        self.to_row_with_orders(bvh, &rotation_orders(bvh))
    }

    /// [`Pose::to_row`] with each joint's Euler order given
    /// ([`rotation_orders`] of `bvh`), for writing many frames.
    pub(crate) fn to_row_with_orders(
        &self,
        bvh: &Bvh,
        orders: &[Option<EulerOrder>],
    ) -> Result<Vec<f32>> {
        let n = bvh.joints.len();
        if self.rotations.len() != n || self.translations.len() != n {
            return Err(Error::Shape {
                what: "pose".into(),
                expected: format!("{n} joints"),
                found: format!("{}", self.rotations.len()),
            });
        }
        let mut row = vec![0.0f32; bvh.channel_count()];
        for (j, joint) in bvh.joints.iter().enumerate() {
            let m = from_glam_f64(&self.rotations[j]);
            let angles = match orders.get(j).copied().flatten() {
                Some(order) => matrix_to_euler(&m, order).to_vec(),
                None => partial_angles(&rotation_axes(joint), &m),
            };
            let mut ri = 0;
            for (k, ch) in joint.channels.iter().enumerate() {
                row[joint.channel_start + k] = if ch.is_rotation() {
                    ri += 1;
                    angles[ri - 1].to_degrees() as f32
                } else {
                    (self.translations[j][ch.axis()] - joint.offset[ch.axis()] as f64) as f32
                };
            }
        }
        Ok(row)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CLIP: &str = "HIERARCHY\nROOT hips\n{\n  OFFSET 1 2 3\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n  JOINT spine\n  {\n    OFFSET 0 10 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {\n      OFFSET 0 3 0\n    }\n  }\n  JOINT leg\n  {\n    OFFSET -2 -1 0\n    CHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation Zrotation\n    End Site\n    {\n      OFFSET 0 -9 0\n    }\n  }\n}\nMOTION\nFrames: 1\nFrame Time: 0.0166667\n5 6 7 10 -20 30 15 25 -35 0.5 0.25 -0.5 40 -50 60\n";

    #[test]
    fn a_row_round_trips_through_a_pose() {
        let b = Bvh::parse(CLIP).unwrap();
        let p = Pose::of_frame(&b, 0).unwrap();
        assert_eq!(p.translations[0], DVec3::new(6.0, 8.0, 10.0));
        assert_eq!(p.translations[3], DVec3::new(-1.5, -0.75, -0.5));
        let row = p.to_row(&b).unwrap();
        for (a, w) in row.iter().zip(b.frame(0)) {
            assert!((a - w).abs() < 1e-4, "{row:?}");
        }
    }

    #[test]
    fn global_is_the_fk_of_the_row() {
        let b = Bvh::parse(CLIP).unwrap();
        let g = Pose::of_frame(&b, 0).unwrap().global(&b);
        // the spine's End Site: root position + R_root · (spine offset + R_spine · end offset)
        let p = Pose::of_frame(&b, 0).unwrap();
        let want = p.translations[0]
            + p.rotations[0] * (p.translations[1] + p.rotations[1] * DVec3::new(0.0, 3.0, 0.0));
        assert!((g.positions[2] - want).length() < 1e-12);
    }

    #[test]
    fn bad_rows_are_errors() {
        let b = Bvh::parse(CLIP).unwrap();
        assert!(Pose::from_row(&b, &[0.0; 3]).is_err());
        let mut row = b.frame(0).to_vec();
        row[4] = f32::NAN;
        assert!(Pose::from_row(&b, &row).is_err());
        assert!(Pose::of_frame(&b, 1).is_err());
    }

    /// A skeleton whose knee has one rotation channel and whose elbow has
    /// two (common in exported rigs), and a frame with angles on both.
    fn partial_rig(channels_knee: &str, channels_elbow: &str, values: &str) -> Bvh {
        let text = format!(
            "HIERARCHY\nROOT hips\n{{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n  JOINT knee\n  {{\n    OFFSET 0 -10 0\n    {channels_knee}\n    End Site\n    {{\n      OFFSET 0 -10 0\n    }}\n  }}\n  JOINT elbow\n  {{\n    OFFSET 10 0 0\n    {channels_elbow}\n    End Site\n    {{\n      OFFSET 10 0 0\n    }}\n  }}\n}}\nMOTION\nFrames: 1\nFrame Time: 0.0166667\n{values}\n"
        );
        Bvh::parse(&text).unwrap()
    }

    #[test]
    fn joints_with_one_or_two_rotation_channels_keep_their_angles() {
        for (knee, elbow, values) in [
            (
                "CHANNELS 1 Xrotation",
                "CHANNELS 2 Zrotation Xrotation",
                "1 2 3 10 20 30 -45 25 -60",
            ),
            (
                "CHANNELS 1 Yrotation",
                "CHANNELS 2 Yrotation Zrotation",
                "0 0 0 0 0 0 170 -35 80",
            ),
            (
                "CHANNELS 1 Zrotation",
                "CHANNELS 2 Xrotation Zrotation",
                "0 0 0 5 5 5 -120 30 40",
            ),
        ] {
            let b = partial_rig(knee, elbow, values);
            let p = Pose::of_frame(&b, 0).unwrap();
            let row = p.to_row(&b).unwrap();
            // the same rotations back, and the same angles
            let q = Pose::from_row(&b, &row).unwrap();
            for (a, w) in q.rotations.iter().zip(&p.rotations) {
                assert!(a.abs_diff_eq(*w, 1e-5), "{elbow}: {row:?}");
            }
            for (a, w) in row.iter().zip(b.frame(0)) {
                assert!(
                    (a - w).abs() < 1e-3,
                    "{knee} / {elbow}: {row:?} vs {:?}",
                    b.frame(0)
                );
            }
        }
    }
}
