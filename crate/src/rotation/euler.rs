//! Euler angles in all 12 axis orders (6 Tait-Bryan, 6 proper Euler), both
//! intrinsic (rotations about the moving axes) and extrinsic (about the fixed
//! axes).
//!
//! Angles `[a1, a2, a3]` go with the order's axes in sequence:
//! - intrinsic `XZY` (written in upper case): `R = Rx(a1) · Rz(a2) · Ry(a3)`;
//! - extrinsic `xzy` (lower case): `R = Ry(a3) · Rz(a2) · Rx(a1)`.
//!
//! The names follow SciPy's convention (upper case intrinsic, lower case
//! extrinsic). The thesis' "X1Z2Y3" (Table D.1) is intrinsic `XZY`; a BVH
//! channel list `Zrotation Xrotation Yrotation` is intrinsic `ZXY`.
//!
//! Matrix → angles goes through the quaternion with the general method of
//! Bernardes & Viollet (2022), which handles all 12 orders in one routine.

use super::quat::{matrix_to_quat, Quat};
use super::{mul, Mat3, Real, Vec3};
use crate::error::{Error, Result};

/// A coordinate axis.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The X axis.
    X = 0,
    /// The Y axis.
    Y = 1,
    /// The Z axis.
    Z = 2,
}

impl Axis {
    fn index(self) -> usize {
        self as usize
    }
    fn letter(self) -> char {
        ['X', 'Y', 'Z'][self.index()]
    }
}

/// Whether the rotations are about moving (intrinsic) or fixed (extrinsic) axes.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Frame {
    /// About the rotating body's axes: `R = R1 · R2 · R3`.
    Intrinsic,
    /// About the fixed world axes: `R = R3 · R2 · R1`.
    Extrinsic,
}

/// One of the 24 Euler conventions: an axis order and a frame.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct EulerOrder {
    /// The three axes, in the order their angles are given.
    pub axes: [Axis; 3],
    /// Intrinsic or extrinsic.
    pub frame: Frame,
}

/// The 12 valid axis sequences.
pub const SEQUENCES: [&str; 12] = [
    "XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX", "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ",
];

impl EulerOrder {
    /// Builds an order, checking that consecutive axes differ.
    pub fn new(axes: [Axis; 3], frame: Frame) -> Result<Self> {
        if axes[0] == axes[1] || axes[1] == axes[2] {
            return Err(Error::Invalid(format!(
                "Euler order {}{}{}: consecutive axes must differ",
                axes[0].letter(),
                axes[1].letter(),
                axes[2].letter()
            )));
        }
        Ok(EulerOrder { axes, frame })
    }

    /// Intrinsic order from a 3-letter sequence such as `"XZY"`.
    pub fn intrinsic(seq: &str) -> Result<Self> {
        Self::parse(&seq.to_ascii_uppercase())
    }

    /// Parses `"XZY"` (intrinsic) or `"xzy"` (extrinsic).
    pub fn parse(s: &str) -> Result<Self> {
        let bad = || {
            Error::UnknownName {
            kind: "Euler order".into(),
            name: s.to_string(),
            accepted: "one of XYZ XZY YXZ YZX ZXY ZYX XYX XZX YXY YZY ZXZ ZYZ; upper case is intrinsic, lower case extrinsic".into(),
        }
        };
        let chars: Vec<char> = s.chars().collect();
        if chars.len() != 3 {
            return Err(bad());
        }
        let upper = chars.iter().all(|c| c.is_ascii_uppercase());
        let lower = chars.iter().all(|c| c.is_ascii_lowercase());
        if !(upper || lower) {
            return Err(bad());
        }
        let mut axes = [Axis::X; 3];
        for (a, c) in axes.iter_mut().zip(&chars) {
            *a = match c.to_ascii_uppercase() {
                'X' => Axis::X,
                'Y' => Axis::Y,
                'Z' => Axis::Z,
                _ => return Err(bad()),
            };
        }
        let frame = if upper {
            Frame::Intrinsic
        } else {
            Frame::Extrinsic
        };
        Self::new(axes, frame).map_err(|_| bad())
    }

    /// The name: upper case for intrinsic, lower case for extrinsic.
    pub fn name(&self) -> String {
        let s: String = self.axes.iter().map(|a| a.letter()).collect();
        match self.frame {
            Frame::Intrinsic => s,
            Frame::Extrinsic => s.to_ascii_lowercase(),
        }
    }

    /// All 24 conventions.
    pub fn all() -> Vec<EulerOrder> {
        let mut v = Vec::with_capacity(24);
        for s in SEQUENCES {
            v.push(Self::parse(s).expect("valid sequence"));
            v.push(Self::parse(&s.to_ascii_lowercase()).expect("valid sequence"));
        }
        v
    }

    /// True for proper Euler orders (first axis = last axis).
    pub fn is_proper(&self) -> bool {
        self.axes[0] == self.axes[2]
    }
}

/// The elementary rotation by `angle` about one axis.
pub fn axis_rotation<T: Real>(axis: Axis, angle: T) -> Mat3<T> {
    let (s, c) = angle.sin_cos();
    let (o, z) = (T::one(), T::zero());
    match axis {
        Axis::X => [[o, z, z], [z, c, -s], [z, s, c]],
        Axis::Y => [[c, z, s], [z, o, z], [-s, z, c]],
        Axis::Z => [[c, -s, z], [s, c, z], [z, z, o]],
    }
}

/// Euler angles → matrix.
pub fn euler_to_matrix<T: Real>(angles: &Vec3<T>, order: EulerOrder) -> Mat3<T> {
    let r: Vec<Mat3<T>> = (0..3)
        .map(|i| axis_rotation(order.axes[i], angles[i]))
        .collect();
    match order.frame {
        Frame::Intrinsic => mul(&mul(&r[0], &r[1]), &r[2]),
        Frame::Extrinsic => mul(&mul(&r[2], &r[1]), &r[0]),
    }
}

/// Matrix → Euler angles. The first and third angles are in (−π, π]; the
/// middle one in [−π/2, π/2] (Tait-Bryan) or [0, π] (proper Euler). At gimbal
/// lock one outer angle (the one applied last in the extrinsic reading) is
/// set to 0; the matrix is still reproduced exactly.
pub fn matrix_to_euler<T: Real>(m: &Mat3<T>, order: EulerOrder) -> Vec3<T> {
    quat_to_euler(&matrix_to_quat(m), order)
}

/// Unit quaternion → Euler angles (Bernardes & Viollet 2022).
pub fn quat_to_euler<T: Real>(q: &Quat<T>, order: EulerOrder) -> Vec3<T> {
    let extrinsic = order.frame == Frame::Extrinsic;
    // The method is written for extrinsic sequences; an intrinsic sequence is
    // the extrinsic one reversed, with the angles reversed.
    let seq = if extrinsic {
        order.axes
    } else {
        [order.axes[2], order.axes[1], order.axes[0]]
    };
    let i = seq[0].index();
    let j = seq[1].index();
    let mut k = seq[2].index();
    let symmetric = i == k;
    if symmetric {
        k = 3 - i - j;
    }
    let sign =
        T::c(((i as i64 - j as i64) * (j as i64 - k as i64) * (k as i64 - i as i64) / 2) as f64);
    let (a, b, c, d) = if symmetric {
        (q[3], q[i], q[j], q[k] * sign)
    } else {
        (
            q[3] - q[j],
            q[i] + q[k] * sign,
            q[j] + q[3],
            q[k] * sign - q[i],
        )
    };
    let two = T::c(2.0);
    let pi = T::PI();
    let mut th2 = two * (c.hypot(d)).atan2(a.hypot(b));
    let eps = T::c(1e-7).max(T::epsilon() * T::c(16.0));
    let degenerate = th2.abs() <= eps || (th2 - pi).abs() <= eps;
    let half_sum = b.atan2(a);
    let half_diff = d.atan2(c);
    let mut th1 = half_sum - half_diff;
    let mut th3 = half_sum + half_diff;
    if !symmetric {
        th3 = th3 * sign;
        th2 = th2 - pi / two;
    }
    if degenerate {
        // Gimbal lock: only th1 + th3 (or th1 − th3) is defined. Set the
        // last extrinsic angle to 0 and solve the first from the matrix:
        // R = R_k(0) R_j(th2) R_i(th1)  =>  R_i(th1) = R_j(th2)ᵀ R.
        th3 = T::zero();
        let r = super::quat::quat_to_matrix_unit(q);
        let aa = mul(&super::transpose(&axis_rotation(seq[1], th2)), &r);
        let ax = seq[0].index();
        let (p1, p2) = ((ax + 1) % 3, (ax + 2) % 3);
        th1 = aa[p2][p1].atan2(aa[p1][p1]);
    }
    if !extrinsic {
        std::mem::swap(&mut th1, &mut th3);
    }
    let wrap = |x: T| {
        if x < -pi {
            x + two * pi
        } else if x > pi {
            x - two * pi
        } else {
            x
        }
    };
    [wrap(th1), wrap(th2), wrap(th3)]
}
