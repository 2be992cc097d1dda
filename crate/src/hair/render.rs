//! The network's input (Sec. 3.2.1): a 3 × S × S image seen by a fixed
//! orthographic camera after the hair and body are turned by a random view.
//! Channels 0 and 1 hold the undirected 2-D strand orientation θ (mod π)
//! colour-coded as ((cos 2θ + 1)/2, (sin 2θ + 1)/2) on hair pixels and 0
//! elsewhere; channel 2 is the segmentation (hair 1, body 0.5, background
//! 0). Every strand sample also gets a visibility flag for eq. 3.2.

use super::body::Body;
use super::POINTS;
use crate::error::{Error, Result};
use crate::rng::Rng;

type P = [f32; 3];

/// A view: the hair and body turned by yaw (about y), pitch (about x) and
/// roll (about the view axis), then shifted in the image plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Radians.
    pub yaw: f32,
    /// Radians.
    pub pitch: f32,
    /// Radians.
    pub roll: f32,
    /// Image-plane shift (metres).
    pub shift: [f32; 2],
    /// Standard deviation of the orientation noise (radians).
    pub noise: f32,
}

impl Default for View {
    fn default() -> Self {
        View {
            yaw: 0.0,
            pitch: 0.0,
            roll: 0.0,
            shift: [0.0, 0.0],
            noise: 0.0,
        }
    }
}

impl View {
    /// Sec. 3.2.2's random view: yaw in ±90°, pitch and roll in ±15°, a
    /// small shift, and orientation noise.
    pub fn random(rng: &mut Rng) -> View {
        let u = |rng: &mut Rng, a: f32| a * (2.0 * rng.uniform() as f32 - 1.0);
        View {
            yaw: u(rng, 90f32.to_radians()),
            pitch: u(rng, 15f32.to_radians()),
            roll: u(rng, 15f32.to_radians()),
            shift: [u(rng, 0.03), u(rng, 0.03)],
            noise: 0.15,
        }
    }

    /// World → camera rotation (row-major 3 × 3).
    pub fn rotation(&self) -> [[f32; 3]; 3] {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        let (sr, cr) = self.roll.sin_cos();
        let ry = [[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]];
        let rx = [[1.0, 0.0, 0.0], [0.0, cp, -sp], [0.0, sp, cp]];
        let rz = [[cr, -sr, 0.0], [sr, cr, 0.0], [0.0, 0.0, 1.0]];
        mul(rz, mul(rx, ry))
    }
}

fn mul(a: [[f32; 3]; 3], b: [[f32; 3]; 3]) -> [[f32; 3]; 3] {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

fn apply(r: &[[f32; 3]; 3], p: P) -> P {
    [
        r[0][0] * p[0] + r[0][1] * p[1] + r[0][2] * p[2],
        r[1][0] * p[0] + r[1][1] * p[1] + r[1][2] * p[2],
        r[2][0] * p[0] + r[2][1] * p[1] + r[2][2] * p[2],
    ]
}

/// The camera's window: centre (x, y) and half-width, in metres.
pub const WINDOW: ([f32; 2], f32) = ([0.0, -0.1], 0.45);
const CAMERA_Z: f32 = 10.0;
/// Samples this far behind the front-most surface at their pixel still
/// count as visible (strands have thickness).
pub const VISIBLE_DEPTH: f32 = 0.01;

/// A rendered input image with per-sample visibility.
#[derive(Clone, Debug, PartialEq)]
pub struct Render {
    /// Side in pixels.
    pub size: usize,
    /// 3 × size × size, channel after channel.
    pub image: Vec<f32>,
    /// One flag per strand sample (strand after strand).
    pub visible: Vec<bool>,
}

/// The largest image side [`render`] and the photo input accept, in pixels.
pub const MAX_IMAGE_SIZE: usize = 4096;

/// Renders strands (absolute points, [`POINTS`] per strand) and the body
/// seen from `view` at `size` × `size` pixels (at most [`MAX_IMAGE_SIZE`]).
pub fn render(
    points: &[P],
    body: &Body,
    view: &View,
    size: usize,
    rng: &mut Rng,
) -> Result<Render> {
    if !(8..=MAX_IMAGE_SIZE).contains(&size) || !points.len().is_multiple_of(POINTS) {
        return Err(Error::Invalid(format!(
            "hair render: size {size} must be in 8..={MAX_IMAGE_SIZE} and points ({}) a multiple of {POINTS}",
            points.len()
        )));
    }
    let r = view.rotation();
    let ([cx, cy], half) = WINDOW;
    let px_per_m = size as f32 / (2.0 * half);
    let to_px = |q: P| -> (f32, f32, f32) {
        let x = (q[0] - cx - view.shift[0]) * px_per_m + size as f32 / 2.0;
        let y = size as f32 / 2.0 - (q[1] - cy - view.shift[1]) * px_per_m;
        (x, y, CAMERA_Z - q[2])
    };
    // body depth per pixel: a ray per pixel centre, in world coordinates
    let rt = [
        [r[0][0], r[1][0], r[2][0]],
        [r[0][1], r[1][1], r[2][1]],
        [r[0][2], r[1][2], r[2][2]],
    ];
    let dir = apply(&rt, [0.0, 0.0, -1.0]);
    let mut body_depth = vec![f32::INFINITY; size * size];
    for yy in 0..size {
        for xx in 0..size {
            let x = (xx as f32 + 0.5 - size as f32 / 2.0) / px_per_m + cx + view.shift[0];
            let y = (size as f32 / 2.0 - yy as f32 - 0.5) / px_per_m + cy + view.shift[1];
            let o = apply(&rt, [x, y, CAMERA_Z]);
            for e in &body.parts {
                if let Some(t) = e.ray_enter(o, dir) {
                    if t > 0.0 && t < body_depth[yy * size + xx] {
                        body_depth[yy * size + xx] = t;
                    }
                }
            }
        }
    }
    // hair: splat segments densely, nearest wins
    let cam: Vec<(f32, f32, f32)> = points.iter().map(|&p| to_px(apply(&r, p))).collect();
    let mut hair_depth = vec![f32::INFINITY; size * size];
    let mut hair_theta = vec![0.0f32; size * size];
    for s in cam.chunks_exact(POINTS) {
        for w in s.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let len = (dx * dx + dy * dy).sqrt();
            if len < 1e-6 {
                continue;
            }
            let theta = dy.atan2(dx).rem_euclid(std::f32::consts::PI);
            let steps = (len * 2.0).ceil() as usize + 1;
            for k in 0..=steps {
                let t = k as f32 / steps as f32;
                let (x, y, z) = (a.0 + dx * t, a.1 + dy * t, a.2 + (b.2 - a.2) * t);
                if x < 0.0 || y < 0.0 || x >= size as f32 || y >= size as f32 {
                    continue;
                }
                let idx = y as usize * size + x as usize;
                if z < hair_depth[idx] {
                    hair_depth[idx] = z;
                    hair_theta[idx] = theta;
                }
            }
        }
    }
    let plane = size * size;
    let mut image = vec![0.0f32; 3 * plane];
    for idx in 0..plane {
        if hair_depth[idx] < body_depth[idx] {
            let th = hair_theta[idx] + view.noise * rng.normal() as f32;
            image[idx] = ((2.0 * th).cos() + 1.0) / 2.0;
            image[plane + idx] = ((2.0 * th).sin() + 1.0) / 2.0;
            image[2 * plane + idx] = 1.0;
        } else if body_depth[idx].is_finite() {
            image[2 * plane + idx] = 0.5;
        }
    }
    let visible = cam
        .iter()
        .map(|&(x, y, z)| {
            if x < 0.0 || y < 0.0 || x >= size as f32 || y >= size as f32 {
                return false;
            }
            let idx = y as usize * size + x as usize;
            z <= hair_depth[idx].min(body_depth[idx]) + VISIBLE_DEPTH
        })
        .collect();
    Ok(Render {
        size,
        image,
        visible,
    })
}
