//! Bilinear interpolation of per-strand features on the scalp grid
//! (Sec. 3.2.4, Fig. 3.4): the network predicts C features at each of the
//! n × n grid cells; any scalp point (u, v) gets the bilinear blend of the
//! four nearest cell centres (clamped at the border), so any number of
//! strands can be decoded by the same strand MLP.

use crate::error::{Error, Result};

/// Features at (u, v) from a C × n × n grid (channel-major, row j outer).
pub fn bilinear(features: &[f32], channels: usize, n: usize, u: f32, v: f32) -> Result<Vec<f32>> {
    if n == 0 || features.len() != channels * n * n {
        return Err(Error::Shape {
            what: "strand features".into(),
            expected: format!("{channels} × {n} × {n}"),
            found: format!("{}", features.len()),
        });
    }
    if !(u.is_finite() && v.is_finite()) {
        return Err(Error::Invalid(format!(
            "scalp coordinates ({u}, {v}) must be finite"
        )));
    }
    // cell centres sit at (i + 0.5) / n
    let x = (u.clamp(0.0, 1.0) * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
    let y = (v.clamp(0.0, 1.0) * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
    let (i0, j0) = (x.floor() as usize, y.floor() as usize);
    let (i1, j1) = ((i0 + 1).min(n - 1), (j0 + 1).min(n - 1));
    let (fx, fy) = (x - i0 as f32, y - j0 as f32);
    let plane = n * n;
    Ok((0..channels)
        .map(|c| {
            let f = |i: usize, j: usize| features[c * plane + j * n + i];
            (1.0 - fy) * ((1.0 - fx) * f(i0, j0) + fx * f(i1, j0))
                + fy * ((1.0 - fx) * f(i0, j1) + fx * f(i1, j1))
        })
        .collect())
}

/// Scalp coordinates of about `count` strands spread evenly: a k × k grid
/// with k = ceil(√count), cell centres, cut to `count`.
pub fn dense_uv(count: usize) -> Vec<(f32, f32)> {
    let k = (count as f64).sqrt().ceil() as usize;
    let mut out = Vec::with_capacity(count);
    'outer: for j in 0..k {
        for i in 0..k {
            if out.len() == count {
                break 'outer;
            }
            out.push(((i as f32 + 0.5) / k as f32, (j as f32 + 0.5) / k as f32));
        }
    }
    out
}

/// Features for many scalp points at once: `uv.len()` × C, point after point.
pub fn upsample(
    features: &[f32],
    channels: usize,
    n: usize,
    uv: &[(f32, f32)],
) -> Result<Vec<f32>> {
    let mut out = Vec::with_capacity(uv.len() * channels);
    for &(u, v) in uv {
        out.extend(bilinear(features, channels, n, u, v)?);
    }
    Ok(out)
}
