//! The rotation that best turns one set of directions into another
//! (Horn's closed form), for the rest alignment of a bone with several
//! branches.

use glam::{DMat3, DQuat, DVec3};

/// The rotation `R` that best turns each `a` into its `b` (unit vectors;
/// Horn's closed form through the largest eigenvector of a 4×4 matrix).
pub(super) fn best_rotation(pairs: &[(DVec3, DVec3)]) -> DMat3 {
    let mut s = [[0.0f64; 3]; 3];
    for (a, b) in pairs {
        let (a, b) = (a.to_array(), b.to_array());
        for i in 0..3 {
            for k in 0..3 {
                s[i][k] += a[i] * b[k];
            }
        }
    }
    let (xx, xy, xz) = (s[0][0], s[0][1], s[0][2]);
    let (yx, yy, yz) = (s[1][0], s[1][1], s[1][2]);
    let (zx, zy, zz) = (s[2][0], s[2][1], s[2][2]);
    let n = [
        [xx + yy + zz, yz - zy, zx - xz, xy - yx],
        [yz - zy, xx - yy - zz, xy + yx, zx + xz],
        [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
        [xy - yx, zx + xz, yz + zy, -xx - yy + zz],
    ];
    let q = largest_eigenvector(n);
    DMat3::from_quat(DQuat::from_xyzw(q[1], q[2], q[3], q[0]).normalize())
}

/// The eigenvector of the largest eigenvalue of a symmetric 4×4 matrix
/// (cyclic Jacobi rotations).
fn largest_eigenvector(mut a: [[f64; 4]; 4]) -> [f64; 4] {
    let mut v = [[0.0f64; 4]; 4];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _ in 0..64 {
        let off: f64 = (0..4)
            .flat_map(|i| (0..4).filter(move |&k| k != i).map(move |k| (i, k)))
            .map(|(i, k)| a[i][k] * a[i][k])
            .sum();
        if off < 1e-30 {
            break;
        }
        for p in 0..3 {
            for q in p + 1..4 {
                if a[p][q].abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..4 {
                    let (akp, akq) = (a[k][p], a[k][q]);
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for k in 0..4 {
                    let (apk, aqk) = (a[p][k], a[q][k]);
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    let best = (0..4)
        .max_by(|&i, &k| a[i][i].total_cmp(&a[k][k]))
        .unwrap_or(0);
    [v[0][best], v[1][best], v[2][best], v[3][best]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn best_rotation_recovers_a_rotation() {
        let r = DMat3::from_quat(DQuat::from_euler(glam::EulerRot::ZXY, 0.7, -1.1, 2.5));
        let dirs = [
            DVec3::X,
            DVec3::new(0.2, 1.0, -0.3).normalize(),
            DVec3::new(-1.0, 0.1, 0.5).normalize(),
        ];
        let pairs: Vec<_> = dirs.iter().map(|&a| (a, r * a)).collect();
        let got = best_rotation(&pairs);
        for (a, b) in got.to_cols_array().iter().zip(r.to_cols_array()) {
            assert!((a - b).abs() < 1e-9, "{got:?} vs {r:?}");
        }
        // two directions fix it too
        let got2 = best_rotation(&pairs[..2]);
        assert!((got2 - r).to_cols_array().iter().all(|v| v.abs() < 1e-9));
    }
}
