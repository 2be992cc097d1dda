//! The scalp parameterization (Sec. 3.2.3): the unit square maps onto a cap
//! of the head ellipsoid (tilted back, so it reaches the nape and stops at
//! the hairline above the forehead), sampled at a 32 × 32 grid's centres.
//! Any (u, v) in the square maps to a root, which is what upsampling needs.

use super::body::Ellipsoid;

/// The scalp: the head ellipsoid and the cap's extent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scalp {
    /// The head.
    pub head: Ellipsoid,
    /// Polar angle of the cap's rim, radians from the cap's axis.
    pub rim: f32,
    /// Backward tilt of the cap's axis from +y, radians.
    pub tilt: f32,
}

impl Default for Scalp {
    fn default() -> Self {
        Scalp {
            head: super::body::Body::default().parts[0],
            rim: 96f32.to_radians(),
            tilt: 24f32.to_radians(),
        }
    }
}

impl Scalp {
    /// Unit direction from the head's centre for scalp coordinates (u, v)
    /// in [0, 1]²: the square is mapped onto a disk (Shirley–Chiu's
    /// concentric map, continuous and area-preserving), the disk's radius
    /// becomes the polar angle up to `rim`, and the cap is tilted back.
    /// u runs from the left ear to the right, v from the front to the back.
    pub fn direction(&self, u: f32, v: f32) -> [f32; 3] {
        let (a, b) = (2.0 * u.clamp(0.0, 1.0) - 1.0, 2.0 * v.clamp(0.0, 1.0) - 1.0);
        let (r, phi) = if a == 0.0 && b == 0.0 {
            (0.0, 0.0)
        } else if a.abs() > b.abs() {
            (a, std::f32::consts::FRAC_PI_4 * (b / a))
        } else {
            (
                b,
                std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (a / b),
            )
        };
        let (dx, dz) = (r * phi.cos(), r * phi.sin()); // disk point, x right, z back
        let rr = (dx * dx + dz * dz).sqrt();
        let theta = rr * self.rim;
        let (sx, sz) = if rr > 0.0 {
            (dx / rr, dz / rr)
        } else {
            (0.0, 0.0)
        };
        // cap around +y; z in the disk points back (−z of the face)
        let d = [theta.sin() * sx, theta.cos(), -theta.sin() * sz];
        // tilt back: rotate about x so +y leans towards −z
        let (s, c) = self.tilt.sin_cos();
        [d[0], d[1] * c + d[2] * s, -d[1] * s + d[2] * c]
    }

    /// The root on the head's surface for (u, v), and the surface normal.
    pub fn root(&self, u: f32, v: f32) -> ([f32; 3], [f32; 3]) {
        let d = self.direction(u, v);
        let h = &self.head;
        // the ray from the centre along d meets the ellipsoid at t
        let s: f32 = (0..3).map(|i| (d[i] / h.radii[i]).powi(2)).sum();
        let t = 1.0 / s.sqrt();
        let p = [
            h.center[0] + d[0] * t,
            h.center[1] + d[1] * t,
            h.center[2] + d[2] * t,
        ];
        (p, h.normal(p))
    }

    /// (u, v) of grid cell (i, j)'s centre on an n × n grid; i is the column.
    pub fn cell_uv(i: usize, j: usize, n: usize) -> (f32, f32) {
        ((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32)
    }

    /// Roots and normals of an n × n grid, row after row (j outer, i inner).
    pub fn grid_roots(&self, n: usize) -> Vec<([f32; 3], [f32; 3])> {
        let mut out = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let (u, v) = Self::cell_uv(i, j, n);
                out.push(self.root(u, v));
            }
        }
        out
    }
}
