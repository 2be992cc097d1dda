//! The body as four ellipsoids (Fig. 3.2: head, neck, shoulders, chest)
//! and the collision error of eq. 3.3–3.5. Units are metres; the head's
//! centre is the origin, y up, the face looking along +z.

/// An axis-aligned ellipsoid: centre and semi-axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipsoid {
    /// Centre (x_k, y_k, z_k).
    pub center: [f32; 3],
    /// Semi-axes (a_k, b_k, c_k).
    pub radii: [f32; 3],
}

impl Ellipsoid {
    /// Eq. 3.5: 1 − Σ ((p − centre) / radius)²; positive inside.
    pub fn dist(&self, p: [f32; 3]) -> f32 {
        1.0 - (0..3)
            .map(|i| ((p[i] - self.center[i]) / self.radii[i]).powi(2))
            .sum::<f32>()
    }

    /// `p` moved onto the ellipsoid grown by `margin` (metres, roughly)
    /// along the ray from the centre, if it is inside; else `p`.
    pub fn push_out(&self, p: [f32; 3], margin: f32) -> [f32; 3] {
        let r = [
            self.radii[0] + margin,
            self.radii[1] + margin,
            self.radii[2] + margin,
        ];
        let d = [
            p[0] - self.center[0],
            p[1] - self.center[1],
            p[2] - self.center[2],
        ];
        let s: f32 = (0..3).map(|i| (d[i] / r[i]).powi(2)).sum();
        if s >= 1.0 {
            return p;
        }
        if s < 1e-12 {
            // At the centre: out through the top.
            return [self.center[0], self.center[1] + r[1], self.center[2]];
        }
        let k = 1.0 / s.sqrt();
        [
            self.center[0] + d[0] * k,
            self.center[1] + d[1] * k,
            self.center[2] + d[2] * k,
        ]
    }

    /// Outward normal direction of the level set through `p`.
    pub fn normal(&self, p: [f32; 3]) -> [f32; 3] {
        let g = [
            (p[0] - self.center[0]) / self.radii[0].powi(2),
            (p[1] - self.center[1]) / self.radii[1].powi(2),
            (p[2] - self.center[2]) / self.radii[2].powi(2),
        ];
        let n = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt().max(1e-12);
        [g[0] / n, g[1] / n, g[2] / n]
    }

    /// Where an orthographic ray `o + t·d` (`d` unit) first enters, as `t`.
    pub fn ray_enter(&self, o: [f32; 3], d: [f32; 3]) -> Option<f32> {
        let oc = [
            (o[0] - self.center[0]) / self.radii[0],
            (o[1] - self.center[1]) / self.radii[1],
            (o[2] - self.center[2]) / self.radii[2],
        ];
        let dd = [
            d[0] / self.radii[0],
            d[1] / self.radii[1],
            d[2] / self.radii[2],
        ];
        let a: f32 = dd.iter().map(|v| v * v).sum();
        let b: f32 = 2.0 * (0..3).map(|i| oc[i] * dd[i]).sum::<f32>();
        let c: f32 = oc.iter().map(|v| v * v).sum::<f32>() - 1.0;
        let disc = b * b - 4.0 * a * c;
        (disc >= 0.0).then(|| (-b - disc.sqrt()) / (2.0 * a))
    }
}

/// The collision body: four ellipsoids.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Head, neck, shoulders, chest.
    pub parts: [Ellipsoid; 4],
}

impl Default for Body {
    fn default() -> Self {
        Body {
            parts: [
                Ellipsoid {
                    center: [0.0, 0.0, 0.0],
                    radii: [0.078, 0.105, 0.097],
                },
                Ellipsoid {
                    center: [0.0, -0.125, -0.012],
                    radii: [0.052, 0.08, 0.055],
                },
                Ellipsoid {
                    center: [0.0, -0.255, -0.02],
                    radii: [0.2, 0.075, 0.1],
                },
                Ellipsoid {
                    center: [0.0, -0.43, -0.015],
                    radii: [0.16, 0.19, 0.11],
                },
            ],
        }
    }
}

impl Body {
    /// Eq. 3.4 summed over the parts (eq. 3.3 without the 1/NM): for each
    /// segment end inside a part, the segment's L1 length times how deep
    /// (eq. 3.5) the end lies. `strands` are absolute positions, `points`
    /// per strand.
    pub fn collision_sum(&self, strands: &[[f32; 3]], points: usize) -> f32 {
        if points < 2 {
            return 0.0;
        }
        let mut total = 0.0f32;
        for s in strands.chunks_exact(points) {
            for j in 1..points {
                let len: f32 = (0..3).map(|i| (s[j][i] - s[j - 1][i]).abs()).sum();
                for e in &self.parts {
                    total += len * e.dist(s[j]).max(0.0);
                }
            }
        }
        total
    }

    /// Eq. 3.3: the collision error, `collision_sum` / (N·M).
    pub fn collision_error(&self, strands: &[[f32; 3]], points: usize) -> f32 {
        let n = strands.len();
        if n == 0 {
            return 0.0;
        }
        self.collision_sum(strands, points) / n as f32
    }

    /// `p` pushed out of every part (grown by `margin`), a few rounds so
    /// that leaving one part does not leave it inside another.
    pub fn push_out(&self, mut p: [f32; 3], margin: f32) -> [f32; 3] {
        for _ in 0..4 {
            let before = p;
            for e in &self.parts {
                p = e.push_out(p, margin);
            }
            if before == p {
                break;
            }
        }
        p
    }

    /// True when `p` is inside no part (eq. 3.5 ≤ 0 for all).
    pub fn is_outside(&self, p: [f32; 3]) -> bool {
        self.parts.iter().all(|e| e.dist(p) <= 0.0)
    }
}

impl Ellipsoid {
    /// A triangle mesh of the ellipsoid (`rings` × `segments` quads), for
    /// drawing: positions and triangle indices.
    pub fn mesh(&self, rings: usize, segments: usize) -> (Vec<[f32; 3]>, Vec<u32>) {
        let (rings, segments) = (rings.max(2), segments.max(3));
        let mut pos = Vec::with_capacity((rings + 1) * (segments + 1));
        for r in 0..=rings {
            let th = std::f32::consts::PI * r as f32 / rings as f32;
            for s in 0..=segments {
                let ph = std::f32::consts::TAU * s as f32 / segments as f32;
                pos.push([
                    self.center[0] + self.radii[0] * th.sin() * ph.cos(),
                    self.center[1] + self.radii[1] * th.cos(),
                    self.center[2] + self.radii[2] * th.sin() * ph.sin(),
                ]);
            }
        }
        let w = (segments + 1) as u32;
        let mut idx = Vec::with_capacity(rings * segments * 6);
        for r in 0..rings as u32 {
            for s in 0..segments as u32 {
                let a = r * w + s;
                let b = a + w;
                idx.extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
            }
        }
        (pos, idx)
    }
}

impl Body {
    /// All four parts as one triangle mesh.
    pub fn mesh(&self) -> (Vec<[f32; 3]>, Vec<u32>) {
        let (mut pos, mut idx) = (Vec::new(), Vec::new());
        for e in &self.parts {
            let (p, i) = e.mesh(16, 24);
            let base = pos.len() as u32;
            pos.extend(p);
            idx.extend(i.iter().map(|v| v + base));
        }
        (pos, idx)
    }
}
