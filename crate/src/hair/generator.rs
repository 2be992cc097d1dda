//! Procedural hairstyles, standing in for the 340 artist-made models of
//! USC-HairSalon (Sec. 3.2.2) that this project cannot use. A style grows
//! one strand per scalp root: a comb direction away from the parting,
//! gravity that takes over from the root's stiffness, helical curls of
//! varying radius and frequency, clumps that pull neighbours together, and
//! collisions resolved against the body's ellipsoids. Styles of one
//! Table 3.1 class blend region by region, and mirror left to right, as the
//! thesis grows its data set.

use super::body::Body;
use super::scalp::Scalp;
use super::strand;
use super::POINTS;
use crate::error::{Error, Result};
use crate::rng::Rng;

type P = [f32; 3];

/// Table 3.1's length classes, from very short to very very long.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Length {
    /// Very short.
    XS,
    /// Short.
    S,
    /// Medium.
    M,
    /// Long.
    L,
    /// Very long.
    XL,
    /// Very very long.
    XXL,
}

/// Table 3.1's curl classes (with wavy between straight and curly).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Curl {
    /// Straight.
    Straight,
    /// Wavy.
    Wavy,
    /// Curly.
    Curly,
}

/// A hair class: length and curliness.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct HairClass {
    /// Length class.
    pub length: Length,
    /// Curl class.
    pub curl: Curl,
}

impl HairClass {
    /// All 18 classes (6 lengths × 3 curls).
    pub fn all() -> Vec<HairClass> {
        let mut v = Vec::new();
        for length in [
            Length::XS,
            Length::S,
            Length::M,
            Length::L,
            Length::XL,
            Length::XXL,
        ] {
            for curl in [Curl::Straight, Curl::Wavy, Curl::Curly] {
                v.push(HairClass { length, curl });
            }
        }
        v
    }

    /// A short name such as "M-curly".
    pub fn name(&self) -> String {
        format!(
            "{:?}-{}",
            self.length,
            format!("{:?}", self.curl).to_lowercase()
        )
    }

    /// Typical strand length in metres.
    pub fn typical_length(&self) -> f32 {
        match self.length {
            Length::XS => 0.04,
            Length::S => 0.1,
            Length::M => 0.19,
            Length::L => 0.3,
            Length::XL => 0.44,
            Length::XXL => 0.6,
        }
    }
}

/// Parameters of one procedural hairstyle.
#[derive(Clone, Debug, PartialEq)]
pub struct Style {
    /// The class it belongs to.
    pub class: HairClass,
    /// Mean strand length (metres).
    pub length: f32,
    /// Relative spread of strand lengths.
    pub length_jitter: f32,
    /// How much longer the back is than the front (relative).
    pub back_longer: f32,
    /// The parting's u on the scalp (0 left ear, 1 right ear), or `None`
    /// for hair combed back from the crown.
    pub parting: Option<f32>,
    /// How strongly strands are combed away from the parting or crown.
    pub comb: f32,
    /// Lift off the scalp (volume), metres of margin.
    pub volume: f32,
    /// Gravity's weight once stiffness has faded (0..1).
    pub gravity: f32,
    /// Fraction of the length over which the root's stiffness fades.
    pub stiffness: f32,
    /// Curl radius (metres) and angular rate (radians per metre).
    pub curl_radius: f32,
    /// Curl angular rate.
    pub curl_omega: f32,
    /// Relative per-strand curl variation.
    pub curl_jitter: f32,
    /// Number of clumps.
    pub clumps: usize,
    /// Clump pull (0..1) at the tips.
    pub clump_strength: f32,
}

impl Style {
    /// A random style of `class`.
    pub fn random(class: HairClass, rng: &mut Rng) -> Style {
        let u = |rng: &mut Rng, a: f32, b: f32| a + (b - a) * rng.uniform() as f32;
        let (curl_radius, curl_omega) = match class.curl {
            Curl::Straight => (0.0, 0.0),
            Curl::Wavy => (u(rng, 0.006, 0.014), u(rng, 25.0, 45.0)),
            Curl::Curly => (u(rng, 0.004, 0.009), u(rng, 80.0, 160.0)),
        };
        let length = class.typical_length() * u(rng, 0.8, 1.2);
        Style {
            class,
            length,
            length_jitter: u(rng, 0.03, 0.12),
            back_longer: u(rng, -0.1, 0.35),
            parting: if rng.uniform() < 0.6 {
                Some(u(rng, 0.3, 0.7))
            } else {
                None
            },
            comb: u(rng, 0.3, 1.0),
            volume: u(rng, 0.002, 0.012),
            gravity: u(rng, 0.5, 0.95),
            stiffness: u(rng, 0.1, 0.45),
            curl_radius,
            curl_omega,
            curl_jitter: u(rng, 0.05, 0.25),
            clumps: 8 + rng.below(40),
            clump_strength: u(rng, 0.0, 0.6),
        }
    }
}

/// A hair model: `n × n` strands of [`POINTS`] points, grown from the scalp
/// grid's roots (row after row), in absolute coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Hair {
    /// Grid side.
    pub n: usize,
    /// Roots, one per strand.
    pub roots: Vec<P>,
    /// Points, strand after strand.
    pub points: Vec<P>,
    /// The class.
    pub class: HairClass,
}

fn lerp(a: P, b: P, t: f32) -> P {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
    ]
}

fn normalize(a: P) -> P {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if n > 1e-9 {
        [a[0] / n, a[1] / n, a[2] / n]
    } else {
        [0.0, -1.0, 0.0]
    }
}

impl Hair {
    /// Grows `style` on an `n × n` scalp grid. Deterministic for a seed.
    pub fn generate(
        style: &Style,
        scalp: &Scalp,
        body: &Body,
        n: usize,
        rng: &mut Rng,
    ) -> Result<Hair> {
        if n == 0 || !(style.length > 0.0) {
            return Err(Error::Invalid(
                "hair: grid side and length must be positive".into(),
            ));
        }
        let roots_normals = scalp.grid_roots(n);
        let m = POINTS;
        let mut points = Vec::with_capacity(n * n * m);
        for (idx, &(root, normal)) in roots_normals.iter().enumerate() {
            let (u, v) = Scalp::cell_uv(idx % n, idx / n, n);
            let len = style.length
                * (1.0 + style.back_longer * (v - 0.3)).max(0.3)
                * (1.0 + style.length_jitter * rng.normal() as f32).clamp(0.5, 1.5);
            // comb direction: away from the parting (sideways) or back from the crown
            let comb = match style.parting {
                Some(pu) => {
                    let side = if u < pu { -1.0 } else { 1.0 };
                    // sideways from the parting, and back off the forehead
                    [side, -0.2, -0.3 - 0.6 * (1.0 - v)]
                }
                None => [0.3 * (u - 0.5), -0.2, -1.0],
            };
            // grow along the scalp in the comb direction, lifted off it a
            // little (more for less combed styles), so the front hair goes
            // back over the head rather than down the face
            let cn = comb[0] * normal[0] + comb[1] * normal[1] + comb[2] * normal[2];
            let tangent = normalize([
                comb[0] - cn * normal[0],
                comb[1] - cn * normal[1],
                comb[2] - cn * normal[2],
            ]);
            let lift = 0.1 + 0.3 * (1.0 - style.comb);
            let mut d = normalize([
                lift * normal[0] + tangent[0],
                lift * normal[1] + tangent[1],
                lift * normal[2] + tangent[2],
            ]);
            let step = len / (m - 1) as f32;
            let margin = style.volume;
            let mut s = Vec::with_capacity(m);
            s.push(root);
            let mut p = root;
            for k in 1..m {
                let t = k as f32 / (m - 1) as f32;
                let g = style.gravity * (t / style.stiffness.max(1e-3)).min(1.0).powi(2);
                d = normalize(lerp(d, [0.0, -1.0, 0.0], g * 0.12));
                let q = body.push_out(
                    [p[0] + d[0] * step, p[1] + d[1] * step, p[2] + d[2] * step],
                    margin,
                );
                d = normalize([q[0] - p[0], q[1] - p[1], q[2] - p[2]]);
                p = q;
                s.push(p);
            }
            if style.curl_radius > 0.0 {
                let j = 1.0 + style.curl_jitter * rng.normal() as f32;
                let r = (style.curl_radius * j).max(0.0);
                let w = style.curl_omega * (1.0 + style.curl_jitter * rng.normal() as f32);
                let radius: Vec<f32> = (0..m)
                    .map(|k| r * (0.4 + 0.6 * k as f32 / (m - 1) as f32))
                    .collect();
                let omega = vec![w; m];
                let phase = rng.uniform() as f32 * std::f32::consts::TAU;
                s = strand::add_helix(&s, &radius, &omega, phase, 12);
            }
            points.extend(s);
        }
        let mut hair = Hair {
            n,
            roots: roots_normals.iter().map(|r| r.0).collect(),
            points,
            class: style.class,
        };
        hair.clump(style.clumps, style.clump_strength, rng);
        hair.resolve(body, 0.0);
        Ok(hair)
    }

    /// Strand `i`'s points.
    pub fn strand(&self, i: usize) -> &[P] {
        &self.points[i * POINTS..(i + 1) * POINTS]
    }

    /// Number of strands.
    pub fn strands(&self) -> usize {
        self.roots.len()
    }

    /// Pulls strands towards `count` clump centres (random strands), more
    /// towards the tips, in root-relative coordinates.
    fn clump(&mut self, count: usize, strength: f32, rng: &mut Rng) {
        let ns = self.strands();
        if count == 0 || strength <= 0.0 || ns == 0 {
            return;
        }
        let centers: Vec<usize> = (0..count.min(ns)).map(|_| rng.below(ns)).collect();
        let old = self.points.clone();
        for i in 0..ns {
            let r = self.roots[i];
            let c = *centers
                .iter()
                .min_by(|&&a, &&b| {
                    let da = dist2(self.roots[a], r);
                    let db = dist2(self.roots[b], r);
                    da.total_cmp(&db)
                })
                .unwrap_or(&i);
            if c == i {
                continue;
            }
            let rc = self.roots[c];
            for k in 1..POINTS {
                let w = strength * (k as f32 / (POINTS - 1) as f32).powi(2);
                let own = old[i * POINTS + k];
                let guide = old[c * POINTS + k];
                let target = [
                    guide[0] - rc[0] + r[0],
                    guide[1] - rc[1] + r[1],
                    guide[2] - rc[2] + r[2],
                ];
                self.points[i * POINTS + k] = lerp(own, target, w);
            }
        }
    }

    /// Pushes every point but the roots out of the body (grown by `margin`).
    pub fn resolve(&mut self, body: &Body, margin: f32) {
        for (idx, p) in self.points.iter_mut().enumerate() {
            if idx % POINTS != 0 {
                *p = body.push_out(*p, margin);
                if !body.is_outside(*p) {
                    // rounding at the surface: nudge out
                    *p = body.push_out(*p, margin + 1e-4);
                }
            }
        }
    }

    /// The left–right mirror image (x → −x), strands re-indexed so that the
    /// strand of cell (i, j) grows from that cell's root.
    pub fn mirrored(&self) -> Hair {
        let n = self.n;
        let mut points = Vec::with_capacity(self.points.len());
        let mut roots = Vec::with_capacity(self.roots.len());
        for j in 0..n {
            for i in 0..n {
                let src = j * n + (n - 1 - i);
                roots.push(flip(self.roots[src]));
                points.extend(self.strand(src).iter().map(|&p| flip(p)));
            }
        }
        Hair {
            n,
            roots,
            points,
            class: self.class,
        }
    }

    /// Sec. 3.2.2's blend of two hairs on the same grid: the scalp splits
    /// into five regions (crown, left, right, front, back); `mask` bit r
    /// takes region r from `a`, the others from `b`, with soft borders.
    /// Root-relative shapes are blended and collisions resolved again.
    pub fn blend(a: &Hair, b: &Hair, mask: u8, body: &Body) -> Result<Hair> {
        if a.n != b.n || a.points.len() != b.points.len() {
            return Err(Error::Invalid(
                "hair blend: the two hairs need the same grid".into(),
            ));
        }
        const CENTERS: [(f32, f32); 5] = [
            (0.5, 0.5),
            (0.15, 0.5),
            (0.85, 0.5),
            (0.5, 0.12),
            (0.5, 0.88),
        ];
        let n = a.n;
        let mut points = Vec::with_capacity(a.points.len());
        for i in 0..a.strands() {
            let (u, v) = Scalp::cell_uv(i % n, i / n, n);
            let (mut wa, mut tot) = (0.0f32, 0.0f32);
            for (r, c) in CENTERS.iter().enumerate() {
                let phi = (-((u - c.0).powi(2) + (v - c.1).powi(2)) / 0.02).exp();
                tot += phi;
                if mask >> r & 1 == 1 {
                    wa += phi;
                }
            }
            let w = if tot > 0.0 { wa / tot } else { 0.5 };
            let (ra, rb) = (a.roots[i], b.roots[i]);
            for k in 0..POINTS {
                let pa = a.points[i * POINTS + k];
                let pb = b.points[i * POINTS + k];
                let la = [pa[0] - ra[0], pa[1] - ra[1], pa[2] - ra[2]];
                let lb = [pb[0] - rb[0], pb[1] - rb[1], pb[2] - rb[2]];
                let l = lerp(lb, la, w);
                points.push([ra[0] + l[0], ra[1] + l[1], ra[2] + l[2]]);
            }
        }
        let mut h = Hair {
            n,
            roots: a.roots.clone(),
            points,
            class: a.class,
        };
        h.resolve(body, 0.0);
        Ok(h)
    }

    /// Root-relative positions (the network's target), strand after strand.
    pub fn local(&self) -> Vec<P> {
        self.points
            .iter()
            .enumerate()
            .map(|(idx, p)| {
                let r = self.roots[idx / POINTS];
                [p[0] - r[0], p[1] - r[1], p[2] - r[2]]
            })
            .collect()
    }

    /// Curvature of every sample, strand after strand.
    pub fn curvatures(&self) -> Vec<f32> {
        self.points
            .chunks_exact(POINTS)
            .flat_map(strand::curvature)
            .collect()
    }
}

fn dist2(a: P, b: P) -> f32 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
}

fn flip(p: P) -> P {
    [-p[0], p[1], p[2]]
}
