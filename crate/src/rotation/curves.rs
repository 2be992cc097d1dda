//! The curves of appendix C.6 / Figure C.1: the X, Y and Z rotation circles
//! mapped into a representation, then to 2-D by PCA.

use super::batch::Repr;
use super::euler::{axis_rotation, Axis};
use crate::error::{Error, Result};

/// The most samples [`rotation_circle`] draws.
pub const MAX_STEPS: usize = 1_000_000;
/// The largest row length [`pca_2d`] takes (its covariance is `dim²`).
pub const MAX_PCA_DIM: usize = 1024;

/// Encodes `steps` rotations about `axis` (angles `2π i / steps`) in `repr`.
/// Returns `steps * repr.dim()` numbers; at most [`MAX_STEPS`] steps.
pub fn rotation_circle(repr: Repr, axis: Axis, steps: usize) -> Result<Vec<f32>> {
    if steps > MAX_STEPS {
        return Err(Error::Invalid(format!(
            "rotation circle: {steps} steps; at most {MAX_STEPS}"
        )));
    }
    let d = repr.dim();
    let mut out = vec![0.0f32; steps * d];
    for i in 0..steps {
        let a = std::f64::consts::TAU * i as f64 / steps as f64;
        let m = axis_rotation::<f32>(axis, a as f32);
        repr.encode(&m, &mut out[i * d..(i + 1) * d])?;
    }
    Ok(out)
}

/// Projects `points` (rows of `dim` numbers) onto their top two principal
/// components. Returns `2 * rows` numbers. The components come from power
/// iteration on the covariance matrix (dim ≤ a few dozen), with signs fixed
/// so the largest-magnitude loading is positive (a deterministic picture).
pub fn pca_2d(points: &[f32], dim: usize) -> Result<Vec<f32>> {
    if dim == 0 || dim > MAX_PCA_DIM || !points.len().is_multiple_of(dim) {
        return Err(Error::Invalid(format!(
            "pca2d: {} numbers in rows of {dim}; rows must divide them and have 1 to {MAX_PCA_DIM} numbers",
            points.len()
        )));
    }
    let n = points.len().checked_div(dim).unwrap_or(0);
    if n == 0 {
        return Ok(Vec::new());
    }
    let mut mean = vec![0.0f64; dim];
    for p in points.chunks(dim) {
        for (m, x) in mean.iter_mut().zip(p) {
            *m += *x as f64 / n as f64;
        }
    }
    let mut cov = vec![0.0f64; dim * dim];
    for p in points.chunks(dim) {
        for i in 0..dim {
            let a = p[i] as f64 - mean[i];
            for j in 0..dim {
                cov[i * dim + j] += a * (p[j] as f64 - mean[j]) / n as f64;
            }
        }
    }
    let mut comps: Vec<Vec<f64>> = Vec::new();
    for c in 0..2 {
        let mut v: Vec<f64> = (0..dim)
            .map(|i| 1.0 + (i * 7 + c * 3) as f64 * 0.137)
            .collect();
        for _ in 0..500 {
            let mut w = vec![0.0; dim];
            for i in 0..dim {
                for j in 0..dim {
                    w[i] += cov[i * dim + j] * v[j];
                }
            }
            for u in &comps {
                let d: f64 = w.iter().zip(u).map(|(a, b)| a * b).sum();
                for (wi, ui) in w.iter_mut().zip(u) {
                    *wi -= d * ui;
                }
            }
            let nrm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
            if nrm < 1e-30 {
                break;
            }
            v = w.iter().map(|x| x / nrm).collect();
        }
        let big = v
            .iter()
            .cloned()
            .fold(0.0f64, |m, x| if x.abs() > m.abs() { x } else { m });
        if big < 0.0 {
            v.iter_mut().for_each(|x| *x = -*x);
        }
        comps.push(v);
    }
    let mut out = Vec::with_capacity(2 * n);
    for p in points.chunks(dim) {
        for u in &comps {
            let s: f64 = p
                .iter()
                .zip(&mean)
                .zip(u)
                .map(|((x, m), w)| (*x as f64 - m) * w)
                .sum();
            out.push(s as f32);
        }
    }
    Ok(out)
}
