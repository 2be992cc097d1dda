//! Batch conversions over flat `f32` slices: the API that JS typed arrays
//! pass through (one call per batch, no per-element copies across the wasm
//! boundary).
//!
//! A batch of `count` rotations in representation `r` is a slice of
//! `count * r.dim()` numbers. Every conversion goes through the rotation
//! matrix; decoding errors name the index of the offending rotation.

use super::axis_angle::{
    axis_angle4_to_matrix, matrix_to_axis_angle4, matrix_to_rodrigues, rodrigues_to_matrix,
};
use super::euler::{euler_to_matrix, matrix_to_euler, EulerOrder};
use super::quat::{g_q, g_u, matrix_to_quat, quat_to_matrix};
use super::sixd::{fived_to_matrix, matrix_to_5d, matrix_to_6d, sixd_to_matrix};
use super::{geodesic_distance, Mat3};
use crate::error::{Error, Result};

/// A rotation representation of SO(3).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Repr {
    /// 3×3 matrix, 9 numbers, row-major.
    Matrix,
    /// Continuous 6D: the first two columns (eq. 4.5).
    SixD,
    /// Continuous 5D: 6D with one normalized projection (eq. 4.10).
    FiveD,
    /// Unit quaternion `[x, y, z, w]` with `w ≥ 0`.
    Quat,
    /// Eq. 4.2's unnormalized quaternion (encoding only differs).
    QuatGq,
    /// Eq. C.8's unit quaternion (encoding only differs).
    QuatGu,
    /// Axis-angle `[ω, θ]`, 4 numbers.
    AxisAngle,
    /// Rodrigues vector `ωθ`, 3 numbers.
    Rodrigues,
    /// Euler angles in radians, in the given convention.
    Euler(EulerOrder),
}

impl Repr {
    /// Numbers per rotation.
    pub fn dim(&self) -> usize {
        match self {
            Repr::Matrix => 9,
            Repr::SixD => 6,
            Repr::FiveD => 5,
            Repr::Quat | Repr::QuatGq | Repr::QuatGu | Repr::AxisAngle => 4,
            Repr::Rodrigues | Repr::Euler(_) => 3,
        }
    }

    /// Parses a name: `matrix`, `6d`, `5d`, `quat`, `quat_gq`, `quat_gu`,
    /// `axis_angle`, `rodrigues`, or `euler:XZY` (upper case intrinsic,
    /// lower case extrinsic, any of the 12 orders).
    pub fn parse(name: &str) -> Result<Self> {
        Ok(match name {
            "matrix" => Repr::Matrix,
            "6d" => Repr::SixD,
            "5d" => Repr::FiveD,
            "quat" => Repr::Quat,
            "quat_gq" => Repr::QuatGq,
            "quat_gu" => Repr::QuatGu,
            "axis_angle" => Repr::AxisAngle,
            "rodrigues" => Repr::Rodrigues,
            _ => match name.strip_prefix("euler:") {
                Some(o) => Repr::Euler(EulerOrder::parse(o)?),
                None => {
                    return Err(Error::UnknownName {
                        kind: "rotation representation".into(),
                        name: name.to_string(),
                        accepted: "matrix, 6d, 5d, quat, quat_gq, quat_gu, axis_angle, rodrigues, euler:XYZ (any of the 12 orders; upper case intrinsic, lower case extrinsic)".into(),
                    })
                }
            },
        })
    }

    /// The name accepted by [`Repr::parse`].
    pub fn name(&self) -> String {
        match self {
            Repr::Matrix => "matrix".into(),
            Repr::SixD => "6d".into(),
            Repr::FiveD => "5d".into(),
            Repr::Quat => "quat".into(),
            Repr::QuatGq => "quat_gq".into(),
            Repr::QuatGu => "quat_gu".into(),
            Repr::AxisAngle => "axis_angle".into(),
            Repr::Rodrigues => "rodrigues".into(),
            Repr::Euler(o) => format!("euler:{}", o.name()),
        }
    }

    /// Encodes one matrix into `out` (`out.len() == self.dim()`).
    pub fn encode(&self, m: &Mat3<f32>, out: &mut [f32]) -> Result<()> {
        match self {
            Repr::Matrix => {
                for i in 0..3 {
                    out[i * 3..i * 3 + 3].copy_from_slice(&m[i]);
                }
            }
            Repr::SixD => out.copy_from_slice(&matrix_to_6d(m)),
            Repr::FiveD => out.copy_from_slice(&matrix_to_5d(m)?),
            Repr::Quat => out.copy_from_slice(&matrix_to_quat(m)),
            Repr::QuatGq => out.copy_from_slice(&g_q(m)),
            Repr::QuatGu => out.copy_from_slice(&g_u(m)),
            Repr::AxisAngle => out.copy_from_slice(&matrix_to_axis_angle4(m)),
            Repr::Rodrigues => out.copy_from_slice(&matrix_to_rodrigues(m)),
            Repr::Euler(o) => out.copy_from_slice(&matrix_to_euler(m, *o)),
        }
        Ok(())
    }

    /// Decodes one rotation (`v.len() == self.dim()`) to a matrix. The matrix
    /// representation is taken as given (it is not re-orthogonalized).
    pub fn decode(&self, v: &[f32]) -> Result<Mat3<f32>> {
        if let Some(index) = v.iter().position(|x| !x.is_finite()) {
            return Err(Error::NotFinite {
                what: self.name(),
                index,
            });
        }
        let a3 = |v: &[f32]| [v[0], v[1], v[2]];
        Ok(match self {
            Repr::Matrix => [a3(&v[0..3]), a3(&v[3..6]), a3(&v[6..9])],
            Repr::SixD => sixd_to_matrix(&[v[0], v[1], v[2], v[3], v[4], v[5]])?,
            Repr::FiveD => fived_to_matrix(&[v[0], v[1], v[2], v[3], v[4]])?,
            Repr::Quat | Repr::QuatGq | Repr::QuatGu => quat_to_matrix(&[v[0], v[1], v[2], v[3]])?,
            Repr::AxisAngle => axis_angle4_to_matrix(&[v[0], v[1], v[2], v[3]])?,
            Repr::Rodrigues => rodrigues_to_matrix(&a3(v))?,
            Repr::Euler(o) => euler_to_matrix(&a3(v), *o),
        })
    }
}

fn batch_count(what: &str, len: usize, dim: usize) -> Result<usize> {
    if !len.is_multiple_of(dim) {
        return Err(Error::Shape {
            what: what.to_string(),
            expected: format!("a multiple of {dim} numbers"),
            found: format!("{len}"),
        });
    }
    Ok(len / dim)
}

fn at_index(e: Error, i: usize) -> Error {
    match e {
        Error::Degenerate { what, .. } => Error::Degenerate { what, index: i },
        Error::NotFinite { what, index } => Error::NotFinite {
            what: format!("{what} (rotation {i})"),
            index,
        },
        other => other,
    }
}

/// Converts a batch from one representation to another. Returns the output
/// (`count * to.dim()` numbers).
pub fn convert(from: Repr, to: Repr, input: &[f32]) -> Result<Vec<f32>> {
    let n = batch_count(&format!("{} batch", from.name()), input.len(), from.dim())?;
    let (df, dt) = (from.dim(), to.dim());
    let mut out = vec![0.0f32; n * dt];
    for i in 0..n {
        let m = from
            .decode(&input[i * df..(i + 1) * df])
            .map_err(|e| at_index(e, i))?;
        to.encode(&m, &mut out[i * dt..(i + 1) * dt])
            .map_err(|e| at_index(e, i))?;
    }
    Ok(out)
}

/// Geodesic distances (eq. 4.12, radians) between two batches in the same
/// representation.
pub fn geodesic(repr: Repr, a: &[f32], b: &[f32]) -> Result<Vec<f32>> {
    let n = batch_count(&format!("{} batch", repr.name()), a.len(), repr.dim())?;
    if a.len() != b.len() {
        return Err(Error::Shape {
            what: "geodesic distance batches".into(),
            expected: format!("equal lengths ({})", a.len()),
            found: format!("{}", b.len()),
        });
    }
    let d = repr.dim();
    (0..n)
        .map(|i| {
            let ma = repr
                .decode(&a[i * d..(i + 1) * d])
                .map_err(|e| at_index(e, i))?;
            let mb = repr
                .decode(&b[i * d..(i + 1) * d])
                .map_err(|e| at_index(e, i))?;
            Ok(geodesic_distance(&ma, &mb))
        })
        .collect()
}
