//! The photo path (Sec. 3.2.1): a hair orientation field from an image and
//! a hair mask, with an oriented filter bank (Gabor kernels, as Paris et al.
//! [93] use): at each hair pixel the strand direction is the orientation
//! whose filter answers most strongly. The result is the network's input
//! layout (see [`super::render`]): orientation in channels 0–1, the mask in
//! channel 2 (hair 1, body 0.5, background 0).

use crate::error::{Error, Result};

/// Filter bank settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gabor {
    /// Number of orientations in [0, π).
    pub orientations: usize,
    /// Gaussian width across the strand (pixels).
    pub sigma_across: f32,
    /// Gaussian width along the strand (pixels).
    pub sigma_along: f32,
    /// Wavelength across the strand (pixels).
    pub wavelength: f32,
}

impl Default for Gabor {
    fn default() -> Self {
        Gabor {
            orientations: 24,
            sigma_across: 1.8,
            sigma_along: 2.4,
            wavelength: 4.0,
        }
    }
}

impl Gabor {
    /// The zero-mean kernel for strands along angle `theta` (radians, image
    /// coordinates with y down): it oscillates across the strand.
    pub fn kernel(&self, theta: f32) -> (Vec<f32>, usize) {
        let r = (3.0 * self.sigma_across.max(self.sigma_along)).ceil() as isize;
        let side = (2 * r + 1) as usize;
        let (s, c) = theta.sin_cos();
        let mut k = Vec::with_capacity(side * side);
        for y in -r..=r {
            for x in -r..=r {
                let (x, y) = (x as f32, y as f32);
                let along = x * c + y * s;
                let across = -x * s + y * c;
                let g = (-(across * across) / (2.0 * self.sigma_across.powi(2))
                    - (along * along) / (2.0 * self.sigma_along.powi(2)))
                .exp();
                k.push(g * (std::f32::consts::TAU * across / self.wavelength).cos());
            }
        }
        let mean = k.iter().sum::<f32>() / k.len() as f32;
        k.iter_mut().for_each(|v| *v -= mean);
        (k, side)
    }

    /// Orientation (radians in [0, π), y down) and filter response at every
    /// pixel where `mask` is set (`NaN` elsewhere) of a `w` × `h` grey image.
    pub fn orientations(
        &self,
        grey: &[f32],
        mask: &[bool],
        w: usize,
        h: usize,
    ) -> Result<(Vec<f32>, Vec<f32>)> {
        let px = w.checked_mul(h);
        if px.is_none() || Some(grey.len()) != px || Some(mask.len()) != px || w == 0 || h == 0 {
            return Err(Error::Shape {
                what: "orientation image".into(),
                expected: format!("{w} × {h} grey values and mask flags"),
                found: format!("{} and {}", grey.len(), mask.len()),
            });
        }
        if self.orientations < 2 {
            return Err(Error::Invalid(
                "the filter bank needs at least 2 orientations".into(),
            ));
        }
        crate::error::check_finite("orientation image", grey)?;
        let kernels: Vec<(Vec<f32>, usize)> = (0..self.orientations)
            .map(|k| self.kernel(std::f32::consts::PI * k as f32 / self.orientations as f32))
            .collect();
        let mut theta = vec![f32::NAN; w * h];
        let mut strength = vec![0.0f32; w * h];
        let mut resp = vec![0.0f32; self.orientations];
        for y in 0..h {
            for x in 0..w {
                if !mask[y * w + x] {
                    continue;
                }
                for (k, (kern, side)) in kernels.iter().enumerate() {
                    let r = (*side / 2) as isize;
                    let mut acc = 0.0f32;
                    for dy in -r..=r {
                        let yy = (y as isize + dy).clamp(0, h as isize - 1) as usize;
                        let row = &kern[((dy + r) as usize) * side..];
                        for dx in -r..=r {
                            let xx = (x as isize + dx).clamp(0, w as isize - 1) as usize;
                            acc += row[(dx + r) as usize] * grey[yy * w + xx];
                        }
                    }
                    resp[k] = acc.abs();
                }
                let (best, &max) = resp
                    .iter()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(b.1))
                    .unwrap_or((0, &0.0));
                // parabolic refinement between the neighbouring orientations
                let n = self.orientations;
                let (l, r) = (resp[(best + n - 1) % n], resp[(best + 1) % n]);
                let den = l - 2.0 * max + r;
                let off = if den.abs() > 1e-12 {
                    (0.5 * (l - r) / den).clamp(-0.5, 0.5)
                } else {
                    0.0
                };
                theta[y * w + x] = ((best as f32 + off) * std::f32::consts::PI / n as f32)
                    .rem_euclid(std::f32::consts::PI);
                strength[y * w + x] = max;
            }
        }
        Ok((theta, strength))
    }
}

/// Bilinear resampling of a `w` × `h` single-channel image to `s` × `s`.
pub fn resample(src: &[f32], w: usize, h: usize, s: usize) -> Vec<f32> {
    let mut out = vec![0.0f32; s * s];
    if w == 0 || h == 0 || w.checked_mul(h) != Some(src.len()) {
        return out;
    }
    for y in 0..s {
        for x in 0..s {
            let fx = ((x as f32 + 0.5) * w as f32 / s as f32 - 0.5).clamp(0.0, (w - 1) as f32);
            let fy = ((y as f32 + 0.5) * h as f32 / s as f32 - 0.5).clamp(0.0, (h - 1) as f32);
            let (x0, y0) = (fx.floor() as usize, fy.floor() as usize);
            let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
            let (ax, ay) = (fx - x0 as f32, fy - y0 as f32);
            let v = |xx: usize, yy: usize| src[yy * w + xx];
            out[y * s + x] = (1.0 - ay) * ((1.0 - ax) * v(x0, y0) + ax * v(x1, y0))
                + ay * ((1.0 - ax) * v(x0, y1) + ax * v(x1, y1));
        }
    }
    out
}

/// The largest photo side [`network_input`] accepts, in pixels.
pub const MAX_PHOTO_SIDE: usize = 8192;

/// The network input (3 × 256 × 256) from a photo: `grey` (`w` × `h`, any
/// scale), `hair` and optional `body` masks (values > 0.5 are set). The
/// image is resampled to 256 × 256 first, as the thesis crops and scales
/// the portrait to the network's input.
pub fn network_input(
    grey: &[f32],
    hair: &[f32],
    body: Option<&[f32]>,
    w: usize,
    h: usize,
    bank: &Gabor,
) -> Result<Vec<f32>> {
    if w == 0 || h == 0 || w > MAX_PHOTO_SIDE || h > MAX_PHOTO_SIDE {
        return Err(Error::Invalid(format!(
            "photo: {w} × {h} pixels; each side must be in 1..={MAX_PHOTO_SIDE}"
        )));
    }
    // w × h ≤ 2^26 now, so the product cannot wrap even on 32-bit targets.
    if grey.len() != w * h || hair.len() != w * h || body.is_some_and(|b| b.len() != w * h) {
        return Err(Error::Shape {
            what: "photo".into(),
            expected: format!("{w} × {h} values for the image and each mask"),
            found: format!("{} (image), {} (hair mask)", grey.len(), hair.len()),
        });
    }
    const S: usize = 256;
    let g = resample(grey, w, h, S);
    let hm: Vec<bool> = resample(hair, w, h, S).iter().map(|v| *v > 0.5).collect();
    let bm: Vec<bool> = match body {
        Some(b) => resample(b, w, h, S).iter().map(|v| *v > 0.5).collect(),
        None => vec![false; S * S],
    };
    if !hm.iter().any(|&m| m) {
        return Err(Error::Invalid("the hair mask is empty".into()));
    }
    let (theta, _) = bank.orientations(&g, &hm, S, S)?;
    let plane = S * S;
    let mut out = vec![0.0f32; 3 * plane];
    for i in 0..plane {
        if hm[i] {
            out[i] = ((2.0 * theta[i]).cos() + 1.0) / 2.0;
            out[plane + i] = ((2.0 * theta[i]).sin() + 1.0) / 2.0;
            out[2 * plane + i] = 1.0;
        } else if bm[i] {
            out[2 * plane + i] = 0.5;
        }
    }
    Ok(out)
}
