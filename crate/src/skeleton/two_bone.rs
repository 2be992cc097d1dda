//! Two-bone IK (thigh and shin, upper arm and forearm): the rotations that
//! put the chain's end at a target while keeping the middle joint's bend
//! plane. Foot locking ([`crate::motion::feet`]) and retargeting's foot
//! placement ([`super::retarget`]) use it.

use crate::rotation::axis_angle::axis_angle_to_matrix;
use crate::rotation::{cross, dot, identity, mul, mul_vec, norm, Mat3, Vec3};

fn sub(a: &Vec3<f64>, b: &Vec3<f64>) -> Vec3<f64> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add(a: &Vec3<f64>, b: &Vec3<f64>) -> Vec3<f64> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// The rotation taking direction `u` to direction `v` (shortest arc).
pub fn rotation_between(u: &Vec3<f64>, v: &Vec3<f64>) -> Mat3<f64> {
    let (nu, nv) = (norm(u), norm(v));
    if nu < 1e-12 || nv < 1e-12 {
        return identity();
    }
    let axis = cross(u, v);
    let s = norm(&axis);
    let c = dot(u, v) / (nu * nv);
    if s < 1e-12 {
        return identity(); // parallel (the antiparallel case cannot occur for a small swing)
    }
    let a = [axis[0] / s, axis[1] / s, axis[2] / s];
    axis_angle_to_matrix(&a, (s / (nu * nv)).atan2(c))
}

/// A chain's joints' global positions (root `h`, middle `k`, end `a`) and
/// the two bones' global rotations.
pub struct Chain {
    /// Root joint's position (hip, shoulder).
    pub h: Vec3<f64>,
    /// Middle joint's position (knee, elbow).
    pub k: Vec3<f64>,
    /// End joint's position (ankle, wrist).
    pub a: Vec3<f64>,
    /// First bone's global rotation.
    pub upper: Mat3<f64>,
    /// Second bone's global rotation.
    pub lower: Mat3<f64>,
}

/// New global rotations `(upper, lower)` that move the chain's end to
/// `target` (clamped to the chain's reach), bending in the middle joint's
/// current plane (a straight chain bends about the upper bone's x axis).
/// `None` for a degenerate chain (a bone of zero length).
pub fn solve(c: &Chain, target: &Vec3<f64>) -> Option<(Mat3<f64>, Mat3<f64>)> {
    let la = norm(&sub(&c.k, &c.h));
    let lb = norm(&sub(&c.a, &c.k));
    if la < 1e-9 || lb < 1e-9 {
        return None;
    }
    let reach = norm(&sub(target, &c.h)).clamp((la - lb).abs() + 1e-4, la + lb - 1e-4);
    // middle joint: bend so that |end - root| = reach
    let u = sub(&c.h, &c.k);
    let w = sub(&c.a, &c.k);
    let mut n = cross(&u, &w);
    if norm(&n) < 1e-9 {
        n = mul_vec(&c.upper, &[1.0, 0.0, 0.0]);
    }
    let nn = norm(&n);
    let n = [n[0] / nn, n[1] / nn, n[2] / nn];
    let cur = (dot(&u, &w) / (la * lb)).clamp(-1.0, 1.0).acos();
    let want = ((la * la + lb * lb - reach * reach) / (2.0 * la * lb))
        .clamp(-1.0, 1.0)
        .acos();
    let bend = axis_angle_to_matrix(&n, want - cur);
    let lower = mul(&bend, &c.lower);
    let a1 = add(&c.k, &mul_vec(&bend, &w));
    // root: swing the chain so that its end points at the target
    let swing = rotation_between(&sub(&a1, &c.h), &sub(target, &c.h));
    Some((mul(&swing, &c.upper), mul(&swing, &lower)))
}
