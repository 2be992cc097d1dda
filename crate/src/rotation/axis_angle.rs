//! Axis-angle and Rodrigues vectors.
//!
//! - Axis-angle: a unit axis ω and an angle θ ∈ [0, π], stored as `[ω, θ]`
//!   (4 numbers). At θ = 0 the axis is arbitrary and reported as +X.
//! - Rodrigues vector (App. C.7.2): `ωθ`, 3 numbers (the exponential-map
//!   coordinates; the thesis calls this the "3D Rodriguez vector").

use super::quat::matrix_to_quat;
use super::{Mat3, Real, Vec3};
use crate::error::{Error, Result};

/// Rodrigues' rotation formula: the rotation by `angle` about `axis`
/// (normalized here; a zero axis gives the identity).
pub fn axis_angle_to_matrix<T: Real>(axis: &Vec3<T>, angle: T) -> Mat3<T> {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    if !(n > T::tiny()) {
        return super::identity();
    }
    let (x, y, z) = (axis[0] / n, axis[1] / n, axis[2] / n);
    let (s, c) = angle.sin_cos();
    let t = T::one() - c;
    [
        [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
        [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
        [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
    ]
}

/// The axis and angle (θ ∈ [0, π]) of a rotation, through the `w ≥ 0`
/// quaternion: `θ = 2 atan2(|v|, w)`, which is accurate near 0 and π.
pub fn matrix_to_axis_angle<T: Real>(m: &Mat3<T>) -> (Vec3<T>, T) {
    let q = matrix_to_quat(m);
    let s = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
    if !(s > T::zero()) {
        return ([T::one(), T::zero(), T::zero()], T::zero());
    }
    let angle = T::c(2.0) * s.atan2(q[3]);
    ([q[0] / s, q[1] / s, q[2] / s], angle)
}

/// Decodes the 4-number axis-angle `[ω, θ]`. The axis is normalized; a zero
/// axis is degenerate unless θ is 0 (then it is the identity).
pub fn axis_angle4_to_matrix<T: Real>(r: &[T; 4]) -> Result<Mat3<T>> {
    if r.iter().any(|x| !x.is_finite()) {
        return Err(Error::NotFinite {
            what: "axis-angle".into(),
            index: 0,
        });
    }
    let n = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    if !(n > T::tiny()) && r[3] != T::zero() {
        return Err(Error::Degenerate {
            what: "axis-angle: zero axis with a non-zero angle".into(),
            index: 0,
        });
    }
    Ok(axis_angle_to_matrix(&[r[0], r[1], r[2]], r[3]))
}

/// The 4-number axis-angle `[ω, θ]` of a matrix.
pub fn matrix_to_axis_angle4<T: Real>(m: &Mat3<T>) -> [T; 4] {
    let (a, t) = matrix_to_axis_angle(m);
    [a[0], a[1], a[2], t]
}

/// The Rodrigues vector `ωθ` (θ ∈ [0, π]).
pub fn matrix_to_rodrigues<T: Real>(m: &Mat3<T>) -> Vec3<T> {
    let (a, t) = matrix_to_axis_angle(m);
    [a[0] * t, a[1] * t, a[2] * t]
}

/// Decodes a Rodrigues vector `ωθ` (any length; the exponential map).
pub fn rodrigues_to_matrix<T: Real>(r: &Vec3<T>) -> Result<Mat3<T>> {
    if r.iter().any(|x| !x.is_finite()) {
        return Err(Error::NotFinite {
            what: "Rodrigues vector".into(),
            index: 0,
        });
    }
    let t = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    Ok(axis_angle_to_matrix(r, t))
}
