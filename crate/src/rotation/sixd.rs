//! The continuous 6D and 5D representations of SO(3).
//!
//! - 6D (Case 3 for n = 3; eq. 4.5–4.7, C.1–C.3): the first two columns of
//!   the matrix; decoding is a Gram-Schmidt step plus a cross product.
//! - 5D (Case 4 for n = 3; eq. 4.8–4.11): the 6D vector with its last four
//!   entries `[γ3, a2]` passed through the normalized projection `P`.

use super::son::{normalized_projection, unprojection};
use super::{col, cross, dot, from_cols, norm, Mat3, Real, Vec3};
use crate::error::{Error, Result};

/// g_GS (eq. C.1): the first two columns, flattened `[a1; a2]`.
pub fn matrix_to_6d<T: Real>(m: &Mat3<T>) -> [T; 6] {
    let a1 = col(m, 0);
    let a2 = col(m, 1);
    [a1[0], a1[1], a1[2], a2[0], a2[1], a2[2]]
}

fn normalize<T: Real>(v: &Vec3<T>, what: &str) -> Result<Vec3<T>> {
    let n = norm(v);
    if !(n > T::tiny().sqrt()) {
        return Err(Error::Degenerate {
            what: what.to_string(),
            index: 0,
        });
    }
    Ok([v[0] / n, v[1] / n, v[2] / n])
}

/// f_GS (eq. C.2–C.3): `b1 = N(a1)`, `b2 = N(a2 − (b1·a2) b1)`, `b3 = b1 × b2`.
///
/// Errors with [`Error::Degenerate`] when `a1` is zero or `a2` is parallel to
/// `a1` (the set D of Sec. 4.3.2). A non-finite input is an error too.
pub fn sixd_to_matrix<T: Real>(r: &[T; 6]) -> Result<Mat3<T>> {
    if r.iter().any(|x| !x.is_finite()) {
        return Err(Error::NotFinite {
            what: "6D rotation".into(),
            index: 0,
        });
    }
    let a1 = [r[0], r[1], r[2]];
    let a2 = [r[3], r[4], r[5]];
    let b1 = normalize(&a1, "6D rotation: first column is zero")?;
    let d = dot(&b1, &a2);
    let u = [a2[0] - d * b1[0], a2[1] - d * b1[1], a2[2] - d * b1[2]];
    // Relative test: a2 parallel to a1 up to rounding is degenerate too.
    if !(norm(&u) > T::tiny().sqrt() * (T::one() + norm(&a2))) {
        return Err(Error::Degenerate {
            what: "6D rotation: second column is parallel to the first".into(),
            index: 0,
        });
    }
    let b2 = normalize(&u, "6D rotation")?;
    let b3 = cross(&b1, &b2);
    Ok(from_cols(b1, b2, b3))
}

/// g_P for n = 3 (eq. 4.10): `[γ1, γ2, P(γ3, γ4, γ5, γ6)]`.
pub fn matrix_to_5d<T: Real>(m: &Mat3<T>) -> Result<[T; 5]> {
    let g = matrix_to_6d(m);
    let mut p = [T::zero(); 3];
    normalized_projection(&g[2..6], &mut p)?;
    Ok([g[0], g[1], p[0], p[1], p[2]])
}

/// f_P for n = 3 (eq. 4.11): `f_GS([u1, u2, Q(u3, u4, u5)])`.
pub fn fived_to_matrix<T: Real>(u: &[T; 5]) -> Result<Mat3<T>> {
    if u.iter().any(|x| !x.is_finite()) {
        return Err(Error::NotFinite {
            what: "5D rotation".into(),
            index: 0,
        });
    }
    let mut q = [T::zero(); 4];
    unprojection(&u[2..5], &mut q)?;
    sixd_to_matrix(&[u[0], u[1], q[0], q[1], q[2], q[3]])
}
