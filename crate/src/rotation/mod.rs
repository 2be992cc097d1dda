//! Rotation representations of thesis chapter 4 and appendix C.
//!
//! Every map comes in a pair: `g` (from a rotation matrix to the
//! representation) and `f` (back to the matrix), with `f(g(M)) = M`.
//! All functions are generic over [`Real`] (`f32` and `f64`).
//!
//! Conventions:
//! - [`Mat3`] is row-major, `m[row][col]`; rotations act on column vectors.
//! - Quaternions are `[x, y, z, w]`, as in eq. 4.4.
//! - The 6D representation is the first two *columns* `[a1; a2]` (eq. 4.5).
//!
//! Sub-modules:
//! - [`sixd`]: 6D (eq. 4.5–4.7, C.1–C.3) and 5D (eq. 4.8–4.11) for SO(3).
//! - [`son`]: general SO(n), O(n) and Sim(n) (Case 3 and 4, Fig. 4.4).
//! - [`quat`]: quaternions (eq. 4.2, 4.4, C.8).
//! - [`axis_angle`]: axis-angle and Rodrigues vectors.
//! - [`euler`]: Euler angles in all 12 orders, intrinsic and extrinsic.
//! - [`batch`]: conversions over flat `f32` slices (the JS-facing API).

pub mod axis_angle;
pub mod batch;
pub mod curves;
pub mod euler;
pub mod quat;
pub mod sixd;
pub mod son;

use num_traits::{Float, FloatConst};
use std::fmt::Debug;

/// Scalar type of the rotation library: implemented for `f32` and `f64`.
pub trait Real: Float + FloatConst + Debug + Default + Send + Sync + 'static {
    /// Converts an `f64` constant.
    fn c(x: f64) -> Self;
    /// Threshold under which a norm counts as zero for this precision.
    fn tiny() -> Self;
}

impl Real for f32 {
    fn c(x: f64) -> Self {
        x as f32
    }
    fn tiny() -> Self {
        1e-12
    }
}

impl Real for f64 {
    fn c(x: f64) -> Self {
        x
    }
    fn tiny() -> Self {
        1e-24
    }
}

/// A 3-vector.
pub type Vec3<T> = [T; 3];
/// A 3×3 matrix, row-major: `m[row][col]`.
pub type Mat3<T> = [[T; 3]; 3];

/// The identity matrix.
pub fn identity<T: Real>() -> Mat3<T> {
    let (o, z) = (T::one(), T::zero());
    [[o, z, z], [z, o, z], [z, z, o]]
}

/// Matrix product `a · b`.
pub fn mul<T: Real>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    let mut r = [[T::zero(); 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    r
}

/// Matrix times column vector.
pub fn mul_vec<T: Real>(a: &Mat3<T>, v: &Vec3<T>) -> Vec3<T> {
    [
        a[0][0] * v[0] + a[0][1] * v[1] + a[0][2] * v[2],
        a[1][0] * v[0] + a[1][1] * v[1] + a[1][2] * v[2],
        a[2][0] * v[0] + a[2][1] * v[1] + a[2][2] * v[2],
    ]
}

/// Transpose (the inverse, for a rotation).
pub fn transpose<T: Real>(a: &Mat3<T>) -> Mat3<T> {
    [
        [a[0][0], a[1][0], a[2][0]],
        [a[0][1], a[1][1], a[2][1]],
        [a[0][2], a[1][2], a[2][2]],
    ]
}

/// Determinant.
pub fn det<T: Real>(a: &Mat3<T>) -> T {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// Column `j` of a matrix.
pub fn col<T: Real>(a: &Mat3<T>, j: usize) -> Vec3<T> {
    [a[0][j], a[1][j], a[2][j]]
}

/// Builds a matrix from three columns.
pub fn from_cols<T: Real>(c0: Vec3<T>, c1: Vec3<T>, c2: Vec3<T>) -> Mat3<T> {
    [
        [c0[0], c1[0], c2[0]],
        [c0[1], c1[1], c2[1]],
        [c0[2], c1[2], c2[2]],
    ]
}

/// Dot product.
pub fn dot<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Cross product.
pub fn cross<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Euclidean norm.
pub fn norm<T: Real>(a: &Vec3<T>) -> T {
    dot(a, a).sqrt()
}

/// Largest absolute element-wise difference between two matrices.
pub fn max_abs_diff<T: Real>(a: &Mat3<T>, b: &Mat3<T>) -> T {
    let mut m = T::zero();
    for i in 0..3 {
        for j in 0..3 {
            m = m.max((a[i][j] - b[i][j]).abs());
        }
    }
    m
}

/// The geodesic distance of eq. 4.12–4.13: the angle (radians, in [0, π]) of
/// the rotation `M'' = M M'^T`.
///
/// Eq. 4.12 writes it as `acos((tr M'' − 1) / 2)`. That form loses half the
/// digits near 0 (acos is flat there), so this function evaluates the same
/// angle as `atan2(|vee(M'' − M''^T)| / 2, (tr M'' − 1) / 2)`, which is exact
/// to rounding everywhere. [`geodesic_distance_acos`] is the literal form.
pub fn geodesic_distance<T: Real>(m: &Mat3<T>, m2: &Mat3<T>) -> T {
    let r = mul(m, &transpose(m2));
    let two = T::c(2.0);
    let s = [r[2][1] - r[1][2], r[0][2] - r[2][0], r[1][0] - r[0][1]];
    let sin = norm(&s) / two;
    let cos = (r[0][0] + r[1][1] + r[2][2] - T::one()) / two;
    sin.atan2(cos)
}

/// Eq. 4.12 exactly as printed, with the cosine clamped to [−1, 1].
pub fn geodesic_distance_acos<T: Real>(m: &Mat3<T>, m2: &Mat3<T>) -> T {
    let r = mul(m, &transpose(m2));
    let c = (r[0][0] + r[1][1] + r[2][2] - T::one()) / T::c(2.0);
    c.max(-T::one()).min(T::one()).acos()
}

/// Casts a matrix between precisions.
pub fn cast<A: Real, B: Real>(m: &Mat3<A>) -> Mat3<B> {
    let mut r = [[B::zero(); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = B::c(m[i][j].to_f64().unwrap_or(f64::NAN));
        }
    }
    r
}

/// Converts to a glam matrix (glam is column-major).
pub fn to_glam(m: &Mat3<f32>) -> glam::Mat3 {
    glam::Mat3::from_cols(col(m, 0).into(), col(m, 1).into(), col(m, 2).into())
}

/// Converts from a glam matrix.
pub fn from_glam(m: &glam::Mat3) -> Mat3<f32> {
    from_cols(m.x_axis.into(), m.y_axis.into(), m.z_axis.into())
}

/// Converts to a glam double-precision matrix.
pub fn to_glam_f64(m: &Mat3<f64>) -> glam::DMat3 {
    glam::DMat3::from_cols(col(m, 0).into(), col(m, 1).into(), col(m, 2).into())
}

/// Converts from a glam double-precision matrix.
pub fn from_glam_f64(m: &glam::DMat3) -> Mat3<f64> {
    from_cols(m.x_axis.into(), m.y_axis.into(), m.z_axis.into())
}

/// Sampling of random rotations, for tests and data generation.
pub mod sample {
    use super::*;
    use crate::rng::Rng;

    /// A rotation uniform on SO(3) (Haar measure), from a uniform unit
    /// quaternion (four normals, normalized).
    pub fn uniform_so3<T: Real>(rng: &mut Rng) -> Mat3<T> {
        loop {
            let q = [rng.normal(), rng.normal(), rng.normal(), rng.normal()];
            let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if n > 1e-6 {
                let q = [
                    T::c(q[0] / n),
                    T::c(q[1] / n),
                    T::c(q[2] / n),
                    T::c(q[3] / n),
                ];
                return quat::quat_to_matrix_unit(&q);
            }
        }
    }

    /// A rotation with a uniform random axis and an angle uniform in [0, π]
    /// (the sampling of the thesis' sanity test, Sec. 4.4.1; not uniform on SO(3)).
    pub fn uniform_axis_angle<T: Real>(rng: &mut Rng) -> Mat3<T> {
        let axis = loop {
            let a = [rng.normal(), rng.normal(), rng.normal()];
            let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            if n > 1e-6 {
                break [T::c(a[0] / n), T::c(a[1] / n), T::c(a[2] / n)];
            }
        };
        let angle = T::c(rng.range(0.0, std::f64::consts::PI));
        axis_angle::axis_angle_to_matrix(&axis, angle)
    }
}
