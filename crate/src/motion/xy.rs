//! 2-D joint keys made exact (Sec. 5.4.2): a key that gives joints' x and
//! y (the front view) but not their depth becomes a whole-pose rotation key
//! for post-processing, so the output passes through it.
//!
//! At the key's frame, the synthesized pose is adjusted joint by joint from
//! the root down: each rotating joint turns so that its children lie at
//! their keyed x and y, at the bone's length, on the side in depth the
//! networks chose (the lifted z). A joint with one keyed child turns by the
//! smallest rotation that takes the bone there; one with several (the
//! hips, the chest) by the rotation that fits all of them best in the least
//! squares sense (Horn's quaternion method), which can leave those
//! children off by a little. A keyed x/y farther from the parent than the
//! bone is long is reached as closely as the bone allows. The resulting
//! local rotations are the key's `rotations`, and
//! [`make_keys_exact`](super::post::make_keys_exact) spreads the
//! correction over the neighbouring frames as for any rotation key.

use super::{Keyframe, Motion};
use crate::rotation::axis_angle::axis_angle_to_matrix;
use crate::rotation::{mul, mul_vec, transpose, Mat3};
use crate::skeleton::Bvh;

/// Whether a key gives some joint's x and y but not its z (a 2-D key).
pub fn is_xy_key(k: &Keyframe) -> bool {
    k.rotations.is_none()
        && (1..k.mask.len() / 3).any(|j| k.mask[3 * j] && k.mask[3 * j + 1] && !k.mask[3 * j + 2])
}

/// `keys` with every 2-D key given the local rotations (on `template`'s
/// joints) that put its joints at their keyed x and y, adjusted from
/// `motion`'s pose at the key's frame. Other keys are returned unchanged.
pub fn pin_xy_keys(motion: &Motion, template: &Bvh, keys: &[Keyframe]) -> Vec<Keyframe> {
    keys.iter()
        .map(|k| {
            let mut k = k.clone();
            if is_xy_key(&k) && k.frame < motion.len() {
                let mut local = motion.rotations[k.frame].clone();
                for _ in 0..PASSES {
                    local = solve(local, template, &k);
                }
                k.rotations = Some(local);
            }
            k
        })
        .collect()
}

type V3 = [f64; 3];

/// Passes of the joint-by-joint fit: each starts from the last one's pose,
/// so the depth sides and the junctions' compromises settle.
const PASSES: usize = 3;

fn norm(a: V3) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// The rotation (a unit quaternion `[w, x, y, z]`) that best takes each
/// unit vector `from[i]` to `to[i]` (Horn 1987): the eigenvector of the
/// largest eigenvalue of the 4 × 4 matrix built from their correlations,
/// by power iteration on the matrix shifted to be positive definite.
fn fit_rotation(from: &[V3], to: &[V3]) -> [f64; 4] {
    let mut s = [[0.0f64; 3]; 3];
    for (a, b) in from.iter().zip(to) {
        for i in 0..3 {
            for j in 0..3 {
                s[i][j] += a[i] * b[j];
            }
        }
    }
    let [[sxx, sxy, sxz], [syx, syy, syz], [szx, szy, szz]] = s;
    let n = [
        [sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
        [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
        [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
        [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz],
    ];
    // eigenvalues lie in [-k, k] with k = the vectors' count: shift by k
    let shift = from.len() as f64 + 1.0;
    let mut q = [1.0, 0.0, 0.0, 0.0];
    for _ in 0..200 {
        let mut next = [0.0; 4];
        for (i, row) in n.iter().enumerate() {
            next[i] = shift * q[i] + (0..4).map(|j| row[j] * q[j]).sum::<f64>();
        }
        let len = next.iter().map(|v| v * v).sum::<f64>().sqrt();
        if len < 1e-300 {
            break;
        }
        let next = next.map(|v| v / len);
        let change: f64 = (0..4).map(|i| (next[i] - q[i]).abs()).sum();
        q = next;
        if change < 1e-13 {
            break;
        }
    }
    q
}

fn quat_matrix(q: [f64; 4]) -> Mat3<f64> {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// Refines a joint's global rotation `g` (at `origin`, root-relative) so
/// that its children (offset, keyed x/y) meet their x/y in the least
/// squares sense: the 3-D fit above chose their depths from the networks'
/// pose, which a rigid group (the hips, a hand) cannot always follow, while
/// x and y alone usually can be met. Levenberg-Marquardt on a rotation
/// vector applied on the left, numerical Jacobian.
fn refine_xy(mut g: Mat3<f64>, origin: V3, keyed: &[(V3, [f64; 2])]) -> Mat3<f64> {
    let resid = |m: &Mat3<f64>| xy_residuals(m, origin, keyed);
    let turn = |w: V3| axis_angle_to_matrix(&w, norm(w));
    let cost_of = |m: &Mat3<f64>| resid(m).iter().map(|v| v * v).sum::<f64>();
    let mut lambda = 1e-3;
    for _ in 0..60 {
        let r = resid(&g);
        let cost: f64 = r.iter().map(|v| v * v).sum();
        if cost < 1e-18 {
            break;
        }
        let eps = 1e-7;
        let cols: Vec<Vec<f64>> = (0..3)
            .map(|a| {
                let mut w = [0.0; 3];
                w[a] = eps;
                let ra = resid(&mul(&turn(w), &g));
                ra.iter().zip(&r).map(|(x, y)| (x - y) / eps).collect()
            })
            .collect();
        let mut jtj = [[0.0f64; 3]; 3];
        let mut b = [0.0f64; 3];
        for i in 0..3 {
            for j in 0..3 {
                jtj[i][j] = cols[i].iter().zip(&cols[j]).map(|(x, y)| x * y).sum();
            }
            b[i] = -cols[i].iter().zip(&r).map(|(x, y)| x * y).sum::<f64>();
        }
        // Levenberg-Marquardt: (JᵀJ + λ diag(JᵀJ)) Δ = −Jᵀr, λ grown until
        // the step lowers the cost, shrunk after it does
        let mut improved = false;
        while lambda < 1e8 {
            let mut a = jtj;
            for (i, row) in a.iter_mut().enumerate() {
                row[i] += lambda * (jtj[i][i] + 1e-12);
            }
            if let Some(delta) = solve3(a, b) {
                let next = mul(&turn(delta), &g);
                if cost_of(&next) < cost {
                    g = next;
                    lambda = (lambda * 0.3).max(1e-9);
                    improved = true;
                    break;
                }
            }
            lambda *= 10.0;
        }
        if !improved {
            break;
        }
    }
    g
}

/// The children's x/y misses (two per child) for the joint's global rotation `m`.
fn xy_residuals(m: &Mat3<f64>, origin: V3, keyed: &[(V3, [f64; 2])]) -> Vec<f64> {
    keyed
        .iter()
        .flat_map(|(off, t)| {
            let p = mul_vec(m, off);
            [p[0] + origin[0] - t[0], p[1] + origin[1] - t[1]]
        })
        .collect()
}

fn xy_cost(m: &Mat3<f64>, origin: V3, keyed: &[(V3, [f64; 2])]) -> f64 {
    xy_residuals(m, origin, keyed).iter().map(|v| v * v).sum()
}

/// `a x = b` for a 3 × 3 system by Cramer's rule; None when singular.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    if d.abs() < 1e-300 {
        return None;
    }
    let mut x = [0.0; 3];
    for (c, xc) in x.iter_mut().enumerate() {
        let mut m = a;
        for r in 0..3 {
            m[r][c] = b[r];
        }
        *xc = det(m) / d;
    }
    Some(x)
}

/// The local rotations `local` (one per joint) adjusted to `k`'s x/y.
fn solve(mut local: Vec<Mat3<f64>>, template: &Bvh, k: &Keyframe) -> Vec<Mat3<f64>> {
    let joints = &template.joints;
    let n = joints.len().min(local.len());
    let offsets: Vec<V3> = joints.iter().map(|j| j.offset.map(|v| v as f64)).collect();
    let target = |j: usize| -> Option<[f64; 2]> {
        (3 * j + 1 < k.mask.len() && k.mask[3 * j] && k.mask[3 * j + 1])
            .then(|| [k.positions[3 * j] as f64, k.positions[3 * j + 1] as f64])
    };
    let rotating = |j: usize| {
        joints[j]
            .channels
            .iter()
            .filter(|c| c.is_rotation())
            .count()
            == 3
    };
    let mut global = vec![crate::rotation::identity::<f64>(); n];
    let mut pos = vec![[0.0f64; 3]; n]; // relative to the root
    for j in 0..n {
        let parent = joints[j].parent;
        let base = match parent {
            None => crate::rotation::identity(),
            Some(p) => {
                let t = mul_vec(&global[p], &offsets[j]);
                pos[j] = [pos[p][0] + t[0], pos[p][1] + t[1], pos[p][2] + t[2]];
                global[p]
            }
        };
        let current = mul(&base, &local[j]);
        global[j] = current;
        if !rotating(j) {
            continue;
        }
        // this joint's keyed children: where their bones point now, and
        // where they must point to reach the keyed x/y at the bone's length
        let (mut from, mut to, mut keyed) = (Vec::new(), Vec::new(), Vec::new());
        for c in (j + 1..n).filter(|&c| joints[c].parent == Some(j)) {
            let (Some(t), len) = (target(c), norm(offsets[c])) else {
                continue;
            };
            if len < 1e-9 {
                continue;
            }
            let d = mul_vec(&current, &offsets[c]).map(|v| v / len);
            let mut dxy = [t[0] - pos[j][0], t[1] - pos[j][1]];
            let r = (dxy[0] * dxy[0] + dxy[1] * dxy[1]).sqrt();
            if r > len {
                dxy = dxy.map(|v| v * len / r);
            }
            let dz = (len * len - dxy[0] * dxy[0] - dxy[1] * dxy[1])
                .max(0.0)
                .sqrt();
            let dz = if d[2] < 0.0 { -dz } else { dz };
            from.push(d);
            to.push([dxy[0] / len, dxy[1] / len, dz / len]);
            keyed.push((offsets[c], t));
        }
        if from.is_empty() {
            continue;
        }
        let turn = quat_matrix(fit_rotation(&from, &to));
        global[j] = mul(&turn, &current);
        if keyed.len() > 1 {
            // x/y alone can have a second, depth-flipped fit (a hand seen
            // edge-on): refine from the 3-D fit, from its mirror in depth and
            // from the networks' pose, and keep the best
            let flipped: Vec<V3> = to.iter().map(|t| [t[0], t[1], -t[2]]).collect();
            let starts = [
                global[j],
                mul(&quat_matrix(fit_rotation(&from, &flipped)), &current),
                current,
            ];
            global[j] = starts
                .iter()
                .map(|&g| refine_xy(g, pos[j], &keyed))
                .min_by(|a, b| xy_cost(a, pos[j], &keyed).total_cmp(&xy_cost(b, pos[j], &keyed)))
                .unwrap_or(global[j]);
        }
        local[j] = mul(&transpose(&base), &global[j]);
    }
    local
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sub(a: V3, b: V3) -> V3 {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    #[test]
    fn fits_one_and_several_directions() {
        // one vector: the smallest rotation taking x to y
        let q = fit_rotation(&[[1.0, 0.0, 0.0]], &[[0.0, 1.0, 0.0]]);
        let m = quat_matrix(q);
        let v = mul_vec(&m, &[1.0, 0.0, 0.0]);
        assert!(norm(sub(v, [0.0, 1.0, 0.0])) < 1e-9, "{v:?}");
        // three vectors rotated by a known rotation are fitted exactly
        let r = quat_matrix([0.8f64.cos(), 0.8f64.sin() * 0.6, 0.0, 0.8f64.sin() * 0.8]);
        let from = [[1.0, 0.0, 0.0], [0.0, 0.6, 0.8], [0.0, -1.0, 0.0]];
        let to: Vec<V3> = from.iter().map(|f| mul_vec(&r, f)).collect();
        let m = quat_matrix(fit_rotation(&from, &to));
        for (f, t) in from.iter().zip(&to) {
            assert!(norm(sub(mul_vec(&m, f), *t)) < 1e-9);
        }
    }
}
