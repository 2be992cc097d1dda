//! Per-strand geometry: curvature per sample, Gaussian smoothing, helical
//! offsets in a frame that follows the strand, and the curl restoration of
//! Sec. 3.2.4 (smooth the network's strand, then add curls where the
//! predicted curvature exceeds the strand's own).

type P = [f32; 3];

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add(a: P, b: P) -> P {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: P, s: f32) -> P {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot(a: P, b: P) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: P, b: P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: P) -> f32 {
    dot(a, a).sqrt()
}
fn unit(a: P) -> P {
    let n = norm(a);
    if n > 1e-12 {
        scale(a, 1.0 / n)
    } else {
        [0.0, -1.0, 0.0]
    }
}

/// Discrete curvature (1 / length) at each sample: the turning angle
/// between the two segments meeting there over their mean length. The two
/// end samples copy their neighbours. Strands of fewer than 3 points get 0.
pub fn curvature(s: &[P]) -> Vec<f32> {
    let m = s.len();
    let mut k = vec![0.0f32; m];
    if m < 3 {
        return k;
    }
    for j in 1..m - 1 {
        let (a, b) = (sub(s[j], s[j - 1]), sub(s[j + 1], s[j]));
        let (la, lb) = (norm(a), norm(b));
        if la < 1e-9 || lb < 1e-9 {
            continue;
        }
        let c = (dot(a, b) / (la * lb)).clamp(-1.0, 1.0);
        k[j] = c.acos() / (0.5 * (la + lb));
    }
    k[0] = k[1];
    k[m - 1] = k[m - 2];
    k
}

/// Total length of a polyline.
pub fn length(s: &[P]) -> f32 {
    s.windows(2).map(|w| norm(sub(w[1], w[0]))).sum()
}

/// Gaussian smoothing along the strand with `sigma` in samples. The ends
/// are extended by odd reflection (p₋ₖ = 2p₀ − pₖ), so straight pieces stay
/// exactly where they are and the tip does not shrink; the root (sample 0)
/// stays fixed.
pub fn smooth(s: &[P], sigma: f32) -> Vec<P> {
    if s.len() < 3 || !(sigma > 0.0) {
        return s.to_vec();
    }
    let m = s.len() as isize;
    let r = ((3.0 * sigma).ceil() as isize).min(m - 1);
    let w: Vec<f32> = (-r..=r)
        .map(|d| (-(d * d) as f32 / (2.0 * sigma * sigma)).exp())
        .collect();
    let tot: f32 = w.iter().sum();
    let at = |k: isize| -> P {
        if k < 0 {
            sub(scale(s[0], 2.0), s[(-k) as usize])
        } else if k >= m {
            sub(
                scale(s[(m - 1) as usize], 2.0),
                s[(2 * (m - 1) - k) as usize],
            )
        } else {
            s[k as usize]
        }
    };
    let mut out = Vec::with_capacity(s.len());
    out.push(s[0]);
    for j in 1..m {
        let mut acc = [0.0f32; 3];
        for d in -r..=r {
            acc = add(acc, scale(at(j + d), w[(d + r) as usize]));
        }
        out.push(scale(acc, 1.0 / tot));
    }
    out
}

/// A frame per sample, transported along the strand: (tangent, n1, n2).
pub fn frames(s: &[P]) -> Vec<(P, P, P)> {
    let m = s.len();
    let mut out = Vec::with_capacity(m);
    if m == 0 {
        return out;
    }
    let tangent = |j: usize| -> P {
        let (a, b) = if m < 2 {
            return [0.0, -1.0, 0.0];
        } else if j + 1 < m {
            (s[j], s[j + 1])
        } else {
            (s[j - 1], s[j])
        };
        unit(sub(b, a))
    };
    let t0 = tangent(0);
    let seed = if t0[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    let mut n1 = unit(cross(t0, seed));
    for j in 0..m {
        let t = tangent(j);
        // project the previous normal onto the new tangent's plane
        n1 = unit(sub(n1, scale(t, dot(n1, t))));
        if !n1.iter().all(|v| v.is_finite()) || norm(n1) < 0.5 {
            let seed = if t[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 0.0, 1.0]
            };
            n1 = unit(cross(t, seed));
        }
        out.push((t, n1, cross(t, n1)));
    }
    out
}

/// Adds a helix around the strand: at sample j an offset of radius
/// `radius[j]` at phase φ_j in the plane normal to the strand, where φ
/// advances by `omega[j]` radians per unit length. The root stays fixed;
/// the radius ramps in over the first `ramp` samples.
pub fn add_helix(s: &[P], radius: &[f32], omega: &[f32], phase: f32, ramp: usize) -> Vec<P> {
    let m = s.len();
    if m < 2 || radius.len() != m || omega.len() != m {
        return s.to_vec();
    }
    let f = frames(s);
    let mut out = Vec::with_capacity(m);
    let mut phi = phase;
    for j in 0..m {
        if j > 0 {
            phi += omega[j] * norm(sub(s[j], s[j - 1]));
        }
        let ramp_w = if ramp == 0 {
            1.0
        } else {
            (j as f32 / ramp as f32).min(1.0)
        };
        let r = radius[j] * ramp_w;
        let (_, n1, n2) = f[j];
        out.push(add(
            s[j],
            add(scale(n1, r * phi.cos()), scale(n2, r * phi.sin())),
        ));
    }
    out
}

/// Helix radius and angular rate (per unit length) that add curvature
/// `kappa` to a straight strand, with the helix at 45° (r·ω = 1): then
/// κ = r ω² / (1 + r² ω²) = ω / 2.
pub fn helix_for_curvature(kappa: f32) -> (f32, f32) {
    if !(kappa > 1e-6) {
        return (0.0, 0.0);
    }
    let omega = 2.0 * kappa;
    (1.0 / omega, omega)
}

/// Sec. 3.2.4's reconstruction of one strand: Gaussian smoothing (`sigma`
/// samples), then, where the predicted curvature exceeds the smoothed
/// strand's by more than `threshold` on average, a helix that adds the
/// missing curvature. Returns the strand and whether curls were added.
pub fn restore(s: &[P], predicted: &[f32], sigma: f32, threshold: f32) -> (Vec<P>, bool) {
    let sm = smooth(s, sigma);
    if predicted.len() != s.len() {
        return (sm, false);
    }
    let have = curvature(&sm);
    let missing: Vec<f32> = predicted
        .iter()
        .zip(&have)
        .map(|(p, h)| (p - h).max(0.0))
        .collect();
    let mean = missing.iter().sum::<f32>() / missing.len().max(1) as f32;
    if !(mean > threshold) {
        return (sm, false);
    }
    let (radius, omega): (Vec<f32>, Vec<f32>) =
        missing.iter().map(|&k| helix_for_curvature(k)).unzip();
    // cap the radius so thin curls on nearly straight strands stay small
    let radius: Vec<f32> = radius.iter().map(|r| r.min(0.03)).collect();
    (add_helix(&sm, &radius, &omega, 0.0, 8), true)
}
