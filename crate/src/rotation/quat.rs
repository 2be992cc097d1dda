//! Quaternions `[x, y, z, w]` (thesis eq. 4.2, 4.4 and C.8).
//!
//! Three maps from matrices to quaternions are provided, because the thesis
//! studies them separately:
//! - [`matrix_to_quat`]: the unit quaternion with `w ≥ 0` (one hemisphere),
//!   computed by Shepperd's method, accurate to rounding. Use this one.
//! - [`g_q`]: eq. 4.2, the unnormalized quaternion (scaled by 4w).
//! - [`g_u`]: eq. C.8, the unit quaternion formula of Baker, whose small
//!   components lose precision (they are square roots of small differences).
//!
//! All decode through [`quat_to_matrix`] (eq. 4.4), which normalizes first.

use super::{Mat3, Real};
use crate::error::{Error, Result};

/// A quaternion `[x, y, z, w]`.
pub type Quat<T> = [T; 4];

/// f_q (eq. 4.4): normalizes, then builds the rotation matrix.
/// Errors on a zero or non-finite quaternion.
pub fn quat_to_matrix<T: Real>(q: &Quat<T>) -> Result<Mat3<T>> {
    if q.iter().any(|x| !x.is_finite()) {
        return Err(Error::NotFinite {
            what: "quaternion".into(),
            index: 0,
        });
    }
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    if !(n > T::tiny()) {
        return Err(Error::Degenerate {
            what: "quaternion: zero vector".into(),
            index: 0,
        });
    }
    Ok(quat_to_matrix_unit(&[
        q[0] / n,
        q[1] / n,
        q[2] / n,
        q[3] / n,
    ]))
}

/// Eq. 4.4 for a quaternion already of unit length.
pub fn quat_to_matrix_unit<T: Real>(q: &Quat<T>) -> Mat3<T> {
    let [x, y, z, w] = *q;
    let (one, two) = (T::one(), T::c(2.0));
    [
        [
            one - two * (y * y + z * z),
            two * (x * y - z * w),
            two * (x * z + y * w),
        ],
        [
            two * (x * y + z * w),
            one - two * (x * x + z * z),
            two * (y * z - x * w),
        ],
        [
            two * (x * z - y * w),
            two * (y * z + x * w),
            one - two * (x * x + y * y),
        ],
    ]
}

/// The unit quaternion of a rotation matrix, on the `w ≥ 0` hemisphere
/// (Shepperd's method: the largest of w², x², y², z² is taken from the
/// diagonal, the others from off-diagonal sums). At `w = 0` exactly, the sign
/// is chosen so the first non-zero of x, y, z is positive.
pub fn matrix_to_quat<T: Real>(m: &Mat3<T>) -> Quat<T> {
    let (one, quarter) = (T::one(), T::c(0.25));
    let tr = m[0][0] + m[1][1] + m[2][2];
    let cands = [tr, m[0][0], m[1][1], m[2][2]];
    let mut best = 0;
    for i in 1..4 {
        if cands[i] > cands[best] {
            best = i;
        }
    }
    let mut q = match best {
        0 => {
            let s = (one + tr).sqrt() * T::c(2.0); // 4w
            [
                (m[2][1] - m[1][2]) / s,
                (m[0][2] - m[2][0]) / s,
                (m[1][0] - m[0][1]) / s,
                quarter * s,
            ]
        }
        1 => {
            let s = (one + m[0][0] - m[1][1] - m[2][2]).sqrt() * T::c(2.0); // 4x
            [
                quarter * s,
                (m[0][1] + m[1][0]) / s,
                (m[0][2] + m[2][0]) / s,
                (m[2][1] - m[1][2]) / s,
            ]
        }
        2 => {
            let s = (one + m[1][1] - m[0][0] - m[2][2]).sqrt() * T::c(2.0); // 4y
            [
                (m[0][1] + m[1][0]) / s,
                quarter * s,
                (m[1][2] + m[2][1]) / s,
                (m[0][2] - m[2][0]) / s,
            ]
        }
        _ => {
            let s = (one + m[2][2] - m[0][0] - m[1][1]).sqrt() * T::c(2.0); // 4z
            [
                (m[0][2] + m[2][0]) / s,
                (m[1][2] + m[2][1]) / s,
                quarter * s,
                (m[1][0] - m[0][1]) / s,
            ]
        }
    };
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    for v in q.iter_mut() {
        *v = *v / n;
    }
    canonical_hemisphere(q)
}

/// Flips a quaternion onto the `w ≥ 0` hemisphere (the constraint of
/// Kendall et al., "quaternions constrained to one hemisphere", App. C.7.2).
pub fn canonical_hemisphere<T: Real>(q: Quat<T>) -> Quat<T> {
    let flip = if q[3] != T::zero() {
        q[3] < T::zero()
    } else {
        q[..3]
            .iter()
            .find(|v| **v != T::zero())
            .is_some_and(|v| *v < T::zero())
    };
    if flip {
        [-q[0], -q[1], -q[2], -q[3]]
    } else {
        q
    }
}

/// g_q (eq. 4.2–4.3): the simple, unnormalized quaternion of Case 2,
/// `[M32−M23, M13−M31, M21−M12, t]` with `t = tr M + 1` (this is
/// `4w · [x, y, z, w]`), and a special form at 180° (`t = 0`; here `t ≤ 4ε`,
/// the rounding floor).
///
/// At 180°, `M = 2nnᵀ − I`, so `√(Mii + 1) = √2 |n_i|` as eq. 4.2 says. The
/// sign rule of eq. 4.3 as printed (`c_i = sign(M_i1 + M_i2)`) does not
/// recover the signs of the axis in general; this function follows the
/// evident intent instead: the largest `|n_k|` is taken positive and the
/// others get the signs of `M_ik = 2 n_i n_k`.
pub fn g_q<T: Real>(m: &Mat3<T>) -> Quat<T> {
    let t = m[0][0] + m[1][1] + m[2][2] + T::one();
    // Below t = 4ε the first form has lost more digits than the second form
    // errs by assuming exactly 180° (both errors are about √ε).
    if t > T::c(4.0) * T::epsilon() {
        return [m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1], t];
    }
    let mut k = 0;
    for i in 1..3 {
        if m[i][i] > m[k][k] {
            k = i;
        }
    }
    let sq = |v: T| (v + T::one()).max(T::zero()).sqrt();
    let c = |i: usize| {
        if i == k || m[i][k] >= T::zero() {
            T::one()
        } else {
            -T::one()
        }
    };
    [
        c(0) * sq(m[0][0]),
        c(1) * sq(m[1][1]),
        c(2) * sq(m[2][2]),
        T::zero(),
    ]
}

/// g_u (eq. C.8): the unit quaternion by Baker's formula,
/// `x = copysign(½√(1+M11−M22−M33), M32−M23)`, …, `w = ½√(1+tr M)`.
/// Negative radicands from rounding are clamped to 0.
pub fn g_u<T: Real>(m: &Mat3<T>) -> Quat<T> {
    let h = T::c(0.5);
    let r = |v: T| h * v.max(T::zero()).sqrt();
    let cs = |a: T, b: T| if b < T::zero() { -a } else { a };
    [
        cs(r(T::one() + m[0][0] - m[1][1] - m[2][2]), m[2][1] - m[1][2]),
        cs(r(T::one() - m[0][0] + m[1][1] - m[2][2]), m[0][2] - m[2][0]),
        cs(r(T::one() - m[0][0] - m[1][1] + m[2][2]), m[1][0] - m[0][1]),
        r(T::one() + m[0][0] + m[1][1] + m[2][2]),
    ]
}

/// Hamilton product `a ⊗ b` (the rotation `b` first, then `a`).
pub fn mul<T: Real>(a: &Quat<T>, b: &Quat<T>) -> Quat<T> {
    let [ax, ay, az, aw] = *a;
    let [bx, by, bz, bw] = *b;
    [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}

/// Conjugate (the inverse of a unit quaternion).
pub fn conjugate<T: Real>(q: &Quat<T>) -> Quat<T> {
    [-q[0], -q[1], -q[2], q[3]]
}

/// Spherical linear interpolation between unit quaternions along the
/// shorter arc, `t` in [0, 1].
pub fn slerp<T: Real>(a: &Quat<T>, b: &Quat<T>, t: T) -> Quat<T> {
    let mut d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    let mut b = *b;
    if d < T::zero() {
        d = -d;
        b = [-b[0], -b[1], -b[2], -b[3]];
    }
    let (wa, wb) = if d > T::c(0.9995) {
        (T::one() - t, t)
    } else {
        let th = d.min(T::one()).acos();
        let s = th.sin();
        (((T::one() - t) * th).sin() / s, (t * th).sin() / s)
    };
    let mut q = [T::zero(); 4];
    for i in 0..4 {
        q[i] = wa * a[i] + wb * b[i];
    }
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}
