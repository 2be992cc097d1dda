#![allow(clippy::needless_range_loop)]
//! Rotation library tests (thesis ch. 4, app. C). Every test states its
//! error bound; each one fails if a formula is wrong.

use deeprep::rng::Rng;
use deeprep::rotation::axis_angle::*;
use deeprep::rotation::batch::{self, Repr};
use deeprep::rotation::euler::*;
use deeprep::rotation::quat::{self, g_q, g_u, matrix_to_quat, quat_to_matrix};
use deeprep::rotation::sample::{uniform_axis_angle, uniform_so3};
use deeprep::rotation::sixd::*;
use deeprep::rotation::son::*;
use deeprep::rotation::*;
use deeprep::Error;

const N: usize = 100_000;

/// Runs `check` on N rotations uniform on SO(3) and N with uniform axis and
/// angle, returning the largest value it reports.
fn worst<T: Real>(seed: u64, mut check: impl FnMut(&Mat3<T>) -> T) -> T {
    let mut rng = Rng::new(seed);
    let mut w = T::zero();
    for i in 0..2 * N {
        let m: Mat3<T> = if i % 2 == 0 {
            uniform_so3(&mut rng)
        } else {
            uniform_axis_angle(&mut rng)
        };
        let e = check(&m);
        assert!(e.is_finite(), "non-finite error at sample {i}");
        w = w.max(e);
    }
    w
}

fn round_trips<T: Real>(bound: f64, gu_bound: f64) {
    let b = T::c(bound);
    let e = worst::<T>(1, |m| {
        max_abs_diff(m, &sixd_to_matrix(&matrix_to_6d(m)).unwrap())
    });
    assert!(e <= b, "6D round trip max error {e:?} > {bound}");
    let e = worst::<T>(2, |m| {
        max_abs_diff(m, &fived_to_matrix(&matrix_to_5d(m).unwrap()).unwrap())
    });
    assert!(e <= b, "5D round trip max error {e:?} > {bound}");
    let e = worst::<T>(3, |m| {
        max_abs_diff(m, &quat_to_matrix(&matrix_to_quat(m)).unwrap())
    });
    assert!(e <= b, "quaternion round trip max error {e:?} > {bound}");
    let e = worst::<T>(4, |m| max_abs_diff(m, &quat_to_matrix(&g_q(m)).unwrap()));
    assert!(
        e <= T::c(gu_bound),
        "g_q (eq. 4.2) round trip max error {e:?} > {gu_bound}"
    );
    let e = worst::<T>(5, |m| max_abs_diff(m, &quat_to_matrix(&g_u(m)).unwrap()));
    assert!(
        e <= T::c(gu_bound),
        "g_u (eq. C.8) round trip max error {e:?} > {gu_bound}"
    );
    let e = worst::<T>(6, |m| {
        max_abs_diff(
            m,
            &axis_angle4_to_matrix(&matrix_to_axis_angle4(m)).unwrap(),
        )
    });
    assert!(e <= b, "axis-angle round trip max error {e:?} > {bound}");
    let e = worst::<T>(7, |m| {
        max_abs_diff(m, &rodrigues_to_matrix(&matrix_to_rodrigues(m)).unwrap())
    });
    assert!(e <= b, "Rodrigues round trip max error {e:?} > {bound}");
    for order in EulerOrder::all() {
        let e = worst::<T>(8, |m| {
            max_abs_diff(m, &euler_to_matrix(&matrix_to_euler(m, order), order))
        });
        assert!(
            e <= b,
            "Euler {} round trip max error {e:?} > {bound}",
            order.name()
        );
    }
}

#[test]
fn round_trips_f32_1e5_rotations() {
    // f32: every map reproduces the matrix to 4e-6 (≈ 30 ulp at 1.0).
    // g_q and g_u take square roots of small differences near 180° and so
    // lose about half the digits: 2e-3 for them.
    round_trips::<f32>(4e-6, 2e-3);
}

#[test]
fn round_trips_f64_1e5_rotations() {
    // f64: 1e-13 for all; g_q and g_u 1e-7 (half the digits, as above).
    round_trips::<f64>(1e-13, 1e-7);
}

#[test]
fn euler_angles_round_trip_through_angles() {
    // angles -> matrix -> angles -> matrix, in every convention, away from
    // gimbal lock the angles themselves come back (within 1e-9 rad, f64).
    let mut rng = Rng::new(11);
    for order in EulerOrder::all() {
        for _ in 0..2000 {
            let a1 = rng.range(-3.1, 3.1);
            let a3 = rng.range(-3.1, 3.1);
            let a2 = if order.is_proper() {
                rng.range(0.05, 3.09)
            } else {
                rng.range(-1.52, 1.52)
            };
            let ang = [a1, a2, a3];
            let back = matrix_to_euler(&euler_to_matrix(&ang, order), order);
            for k in 0..3 {
                assert!(
                    (back[k] - ang[k]).abs() < 1e-9,
                    "{}: {ang:?} came back as {back:?}",
                    order.name()
                );
            }
        }
    }
}

#[test]
fn euler_gimbal_lock_still_reproduces_the_matrix() {
    let mut rng = Rng::new(12);
    for order in EulerOrder::all() {
        let mids: &[f64] = if order.is_proper() {
            &[0.0, std::f64::consts::PI]
        } else {
            &[std::f64::consts::FRAC_PI_2, -std::f64::consts::FRAC_PI_2]
        };
        for &mid in mids {
            for _ in 0..200 {
                let ang = [rng.range(-3.0, 3.0), mid, rng.range(-3.0, 3.0)];
                let m = euler_to_matrix(&ang, order);
                let m2 = euler_to_matrix(&matrix_to_euler(&m, order), order);
                let e = max_abs_diff(&m, &m2);
                assert!(e < 1e-6, "{} gimbal lock {ang:?}: error {e}", order.name());
            }
        }
    }
}

#[test]
fn intrinsic_is_reversed_extrinsic() {
    let mut rng = Rng::new(13);
    for s in SEQUENCES {
        let i = EulerOrder::parse(s).unwrap();
        let rev: String = s.chars().rev().collect::<String>().to_ascii_lowercase();
        let e = EulerOrder::parse(&rev).unwrap();
        for _ in 0..100 {
            let a = [
                rng.range(-3.0, 3.0),
                rng.range(-1.5, 1.5),
                rng.range(-3.0, 3.0),
            ];
            let m1 = euler_to_matrix(&a, i);
            let m2 = euler_to_matrix(&[a[2], a[1], a[0]], e);
            assert!(max_abs_diff(&m1, &m2) < 1e-12, "{s} vs {rev}");
        }
    }
}

fn axis_quat(axis: Axis, angle: f64) -> [f64; 4] {
    let (s, c) = (angle / 2.0).sin_cos();
    let mut q = [0.0, 0.0, 0.0, c];
    q[axis as usize] = s;
    q
}

#[test]
fn cross_check_euler_matrix_against_quaternion_products() {
    // Independent path: compose axis quaternions with the Hamilton product.
    let mut rng = Rng::new(14);
    for order in EulerOrder::all() {
        for _ in 0..1000 {
            let a = [
                rng.range(-3.2, 3.2),
                rng.range(-3.2, 3.2),
                rng.range(-3.2, 3.2),
            ];
            let q: Vec<[f64; 4]> = (0..3).map(|k| axis_quat(order.axes[k], a[k])).collect();
            let qq = match order.frame {
                Frame::Intrinsic => quat::mul(&quat::mul(&q[0], &q[1]), &q[2]),
                Frame::Extrinsic => quat::mul(&quat::mul(&q[2], &q[1]), &q[0]),
            };
            let e = max_abs_diff(&euler_to_matrix(&a, order), &quat_to_matrix(&qq).unwrap());
            assert!(e < 1e-12, "{}: {e}", order.name());
        }
    }
}

#[test]
fn cross_check_axis_angle_and_geodesic() {
    let mut rng = Rng::new(15);
    for _ in 0..N / 10 {
        let m1: Mat3<f64> = uniform_so3(&mut rng);
        let m2: Mat3<f64> = uniform_so3(&mut rng);
        // Geodesic distance vs the quaternion angle 2 acos|q1·q2|.
        let (q1, q2) = (matrix_to_quat(&m1), matrix_to_quat(&m2));
        let d = (q1[0] * q2[0] + q1[1] * q2[1] + q1[2] * q2[2] + q1[3] * q2[3])
            .abs()
            .min(1.0);
        let by_quat = 2.0 * d.acos();
        let g = geodesic_distance(&m1, &m2);
        assert!(
            (g - by_quat).abs() < 1e-7,
            "geodesic {g} vs quaternion angle {by_quat}"
        );
        assert!((g - geodesic_distance_acos(&m1, &m2)).abs() < 1e-6);
        // Axis-angle -> matrix (Rodrigues formula) vs axis-angle -> quaternion -> matrix.
        let (axis, angle) = matrix_to_axis_angle(&m1);
        let (s, c) = (angle / 2.0).sin_cos();
        let q = [axis[0] * s, axis[1] * s, axis[2] * s, c];
        let e = max_abs_diff(
            &axis_angle_to_matrix(&axis, angle),
            &quat_to_matrix(&q).unwrap(),
        );
        assert!(e < 1e-12);
        assert!((0.0..=std::f64::consts::PI + 1e-12).contains(&angle));
    }
    // Exact values: 90° about Z is 90° from the identity.
    let rz = euler_to_matrix(
        &[0.0, 0.0, std::f64::consts::FRAC_PI_2],
        EulerOrder::parse("XYZ").unwrap(),
    );
    assert!((geodesic_distance(&rz, &identity()) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
}

#[test]
fn quaternion_hemisphere_and_elementary_values() {
    let mut rng = Rng::new(16);
    for _ in 0..10_000 {
        let m: Mat3<f64> = uniform_so3(&mut rng);
        assert!(matrix_to_quat(&m)[3] >= 0.0);
        // g_u agrees with the canonical quaternion to half precision.
        let (a, b) = (matrix_to_quat(&m), g_u(&m));
        for k in 0..4 {
            assert!((a[k] - b[k]).abs() < 1e-6, "{a:?} vs {b:?}");
        }
    }
    // 90° about X: q = (sin 45°, 0, 0, cos 45°).
    let m = axis_angle_to_matrix(&[1.0f64, 0.0, 0.0], std::f64::consts::FRAC_PI_2);
    let q = matrix_to_quat(&m);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!(
        (q[0] - h).abs() < 1e-15
            && q[1].abs() < 1e-15
            && q[2].abs() < 1e-15
            && (q[3] - h).abs() < 1e-15
    );
    assert!((m[2][1] - 1.0).abs() < 1e-15, "Rx(90°) maps y to z");
}

#[test]
fn six_d_decodes_any_nondegenerate_vector_to_a_rotation() {
    let mut rng = Rng::new(17);
    for _ in 0..N {
        let r: [f64; 6] = std::array::from_fn(|_| rng.normal() * 3.0);
        let m = sixd_to_matrix(&r).unwrap();
        let mt = mul(&m, &transpose(&m));
        assert!(max_abs_diff(&mt, &identity()) < 1e-12);
        assert!((det(&m) - 1.0).abs() < 1e-12);
        // The first column is the direction of a1 (eq. C.3).
        let n = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        for k in 0..3 {
            assert!((m[k][0] - r[k] / n).abs() < 1e-12);
        }
        let u: [f64; 5] = std::array::from_fn(|_| rng.normal() * 3.0);
        let m = fived_to_matrix(&u).unwrap();
        assert!(max_abs_diff(&mul(&m, &transpose(&m)), &identity()) < 1e-12);
        assert!((det(&m) - 1.0).abs() < 1e-12);
    }
}

#[test]
fn degenerate_and_non_finite_inputs_are_errors() {
    assert!(matches!(
        sixd_to_matrix(&[0.0f32; 6]),
        Err(Error::Degenerate { .. })
    ));
    assert!(matches!(
        sixd_to_matrix(&[1.0f32, 0.0, 0.0, 2.0, 0.0, 0.0]),
        Err(Error::Degenerate { .. })
    ));
    assert!(matches!(
        sixd_to_matrix(&[f32::NAN, 0.0, 0.0, 0.0, 1.0, 0.0]),
        Err(Error::NotFinite { .. })
    ));
    assert!(matches!(
        quat_to_matrix(&[0.0f64; 4]),
        Err(Error::Degenerate { .. })
    ));
    assert!(matches!(
        fived_to_matrix(&[1.0f64, 0.0, 0.0, 0.0, 0.0]),
        Err(Error::Degenerate { .. })
    ));
    assert!(gs_to_matrix(&[1.0f64, 2.0, 3.0], 3).is_err());
}

#[test]
fn so_n_round_trips_up_to_n_6() {
    // Bounds: 1e-12 (f64) and 5e-6 (f32) element-wise, for 10^5 rotations in
    // total, spread over n = 2..6, with every allowed number of projections.
    let mut rng = Rng::new(21);
    let per_n = N / 5;
    for n in 2..=6usize {
        let mut worst64 = 0.0f64;
        let mut worst32 = 0.0f32;
        for _ in 0..per_n {
            let m: MatN<f64> = MatN::random_rotation(n, &mut rng);
            assert!((m.det() - 1.0).abs() < 1e-10);
            let ks = if n >= 3 { 0..=n - 2 } else { 0..=0 };
            for k in ks {
                let r = matrix_to_projected(&m, k).unwrap();
                assert_eq!(r.len(), n * n - n - k);
                worst64 = worst64.max(m.max_abs_diff(&projected_to_matrix(&r, n, k).unwrap()));
                let m32 = MatN {
                    n,
                    data: m.data.iter().map(|x| *x as f32).collect(),
                };
                let r32 = matrix_to_projected(&m32, k).unwrap();
                worst32 = worst32.max(m32.max_abs_diff(&projected_to_matrix(&r32, n, k).unwrap()));
            }
        }
        assert!(worst64 < 1e-12, "SO({n}) f64 round trip error {worst64}");
        assert!(worst32 < 5e-6, "SO({n}) f32 round trip error {worst32}");
    }
    // n²−2n+2 dimensions with n−2 projections.
    for n in 3..=6 {
        assert_eq!(projected_dim(n, n - 2), n * n - 2 * n + 2);
    }
}

#[test]
fn so3_generic_forms_match_the_6d_and_5d_specializations() {
    let mut rng = Rng::new(22);
    for _ in 0..10_000 {
        let m: Mat3<f64> = uniform_so3(&mut rng);
        let mn = MatN {
            n: 3,
            data: m.iter().flatten().copied().collect(),
        };
        assert_eq!(matrix_to_gs(&mn), matrix_to_6d(&m).to_vec());
        let p = matrix_to_projected(&mn, 1).unwrap();
        let p5 = matrix_to_5d(&m).unwrap();
        for k in 0..5 {
            assert!((p[k] - p5[k]).abs() < 1e-15);
        }
        let u: [f64; 6] = std::array::from_fn(|_| rng.normal());
        let a = gs_to_matrix(&u, 3).unwrap();
        let b = sixd_to_matrix(&u).unwrap();
        let b: Vec<f64> = b.iter().flatten().copied().collect();
        for k in 0..9 {
            assert!((a.data[k] - b[k]).abs() < 1e-12);
        }
    }
}

#[test]
fn gram_schmidt_output_is_special_orthogonal_for_arbitrary_inputs() {
    let mut rng = Rng::new(23);
    for n in 2..=6usize {
        for _ in 0..2000 {
            let a: Vec<f64> = (0..n * (n - 1)).map(|_| rng.normal()).collect();
            let m = gs_to_matrix(&a, n).unwrap();
            assert!(m.mul(&m.transpose()).max_abs_diff(&MatN::identity(n)) < 1e-10);
            assert!((m.det() - 1.0).abs() < 1e-10, "det {} for n = {n}", m.det());
        }
    }
}

#[test]
fn orthogonal_and_similarity_round_trips() {
    let mut rng = Rng::new(24);
    for n in 3..=6usize {
        for _ in 0..2000 {
            let mut m: MatN<f64> = MatN::random_rotation(n, &mut rng);
            // A reflection: negate one random column, det becomes −1.
            let c = rng.below(n);
            for i in 0..n {
                m.data[i * n + c] = -m.data[i * n + c];
            }
            assert!((m.det() + 1.0).abs() < 1e-10);
            for k in 0..=n - 2 {
                let r = orthogonal_to_rep(&m, k).unwrap();
                let back = rep_to_orthogonal(&r, n, k).unwrap();
                assert!(m.max_abs_diff(&back) < 1e-12, "O({n}) k={k}");
            }
            let s = Similarity {
                alpha: rng.range(0.1, 10.0),
                rot: m.clone(),
                trans: (0..n).map(|_| rng.normal()).collect(),
            };
            let back = rep_to_similarity(&similarity_to_rep(&s), n).unwrap();
            assert!((back.alpha - s.alpha).abs() < 1e-12);
            assert!(back.rot.max_abs_diff(&s.rot) < 1e-12);
            assert_eq!(back.trans, s.trans);
        }
    }
}

#[test]
fn normalized_projection_lemma_1() {
    // Lemma 1 (App. C.3): if |u_{2:}| = 1 then Q(P(u)) = u.
    let mut rng = Rng::new(25);
    for m in 2..8usize {
        for _ in 0..1000 {
            let mut u: Vec<f64> = (0..m).map(|_| rng.normal()).collect();
            let n = u[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
            for x in u[1..].iter_mut() {
                *x /= n;
            }
            let mut p = vec![0.0; m - 1];
            normalized_projection(&u, &mut p).unwrap();
            let mut q = vec![0.0; m];
            unprojection(&p, &mut q).unwrap();
            for k in 0..m {
                assert!((q[k] - u[k]).abs() < 1e-12, "m={m}: {u:?} -> {q:?}");
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Continuity (appendix C.6): walk the X, Y and Z rotation circles.

const STEPS: usize = 3600; // 0.1° per step

/// Angles (as step indices) where consecutive representations jump by more
/// than `factor` times the step of the matrix itself.
fn jumps(repr: Repr, axis: Axis) -> Vec<usize> {
    let step = std::f64::consts::TAU / STEPS as f64;
    let enc = |i: usize| {
        let m = axis_rotation::<f32>(axis, (i as f64 * step) as f32);
        let mut v = vec![0.0f32; repr.dim()];
        repr.encode(&m, &mut v).unwrap();
        v
    };
    let mut out = Vec::new();
    let mut prev = enc(0);
    for i in 1..=STEPS {
        let cur = enc(i);
        let d = prev
            .iter()
            .zip(&cur)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f32>()
            .sqrt();
        // Continuous maps move O(step) per step (5D's projection at most
        // ~12x); a discontinuity moves O(1).
        if d as f64 > 50.0 * step {
            out.push(i);
        }
        prev = cur;
    }
    out
}

fn near(jumps: &[usize], angle_deg: f64) -> bool {
    let target = (angle_deg * 10.0).round() as i64;
    jumps.iter().any(|&j| (j as i64 - target).abs() <= 1)
}

#[test]
fn continuity_6d_and_5d_never_jump() {
    for axis in [Axis::X, Axis::Y, Axis::Z] {
        for r in [Repr::SixD, Repr::FiveD, Repr::Matrix] {
            let j = jumps(r, axis);
            assert!(
                j.is_empty(),
                "{} jumps on the {axis:?} circle at steps {j:?}",
                r.name()
            );
        }
    }
}

#[test]
fn continuity_quaternion_axis_angle_and_euler_jump_where_they_should() {
    for axis in [Axis::X, Axis::Y, Axis::Z] {
        // Unit quaternions (w ≥ 0, and eq. C.8) flip sign at 180°.
        for r in [Repr::Quat, Repr::QuatGu, Repr::Rodrigues] {
            let j = jumps(r, axis);
            assert!(near(&j, 180.0), "{} on {axis:?}: jumps {j:?}", r.name());
            assert!(
                j.iter().all(|&s| (s as i64 - 1800).abs() <= 1),
                "{} on {axis:?}: extra jumps {j:?}",
                r.name()
            );
        }
        // Axis-angle: the axis flips at 180° and is undefined at the identity.
        let j = jumps(Repr::AxisAngle, axis);
        assert!(near(&j, 180.0), "axis-angle on {axis:?}: {j:?}");
        if axis != Axis::X {
            assert!(
                near(&j, 0.0) || near(&j, 360.0),
                "axis-angle on {axis:?}: {j:?}"
            );
        }
        // Tait-Bryan Euler angles: a rotation about an outer axis wraps at
        // 180°; about the middle axis the middle angle is confined to
        // [−90°, 90°] and the outer ones jump at 90° and 270°.
        for s in ["XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"] {
            for name in [s.to_string(), s.to_ascii_lowercase()] {
                let order = EulerOrder::parse(&name).unwrap();
                let j = jumps(Repr::Euler(order), axis);
                if order.axes[1] == axis {
                    assert!(
                        near(&j, 90.0) && near(&j, 270.0),
                        "euler {name} on {axis:?}: {j:?}"
                    );
                } else {
                    assert!(near(&j, 180.0), "euler {name} on {axis:?}: {j:?}");
                    assert!(
                        j.iter().all(|&s| (s as i64 - 1800).abs() <= 1),
                        "euler {name} on {axis:?}: {j:?}"
                    );
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Batch API.

#[test]
fn batch_conversions_match_single_calls_and_compose() {
    let mut rng = Rng::new(31);
    let mats: Vec<Mat3<f32>> = (0..1000).map(|_| uniform_so3(&mut rng)).collect();
    let flat: Vec<f32> = mats
        .iter()
        .flat_map(|m| m.iter().flatten().copied())
        .collect();
    let names = [
        "matrix",
        "6d",
        "5d",
        "quat",
        "quat_gq",
        "quat_gu",
        "axis_angle",
        "rodrigues",
        "euler:XZY",
        "euler:zxz",
    ];
    for a in names {
        let ra = Repr::parse(a).unwrap();
        assert_eq!(ra.name(), a);
        let va = batch::convert(Repr::Matrix, ra, &flat).unwrap();
        assert_eq!(va.len(), 1000 * ra.dim());
        for b in names {
            let rb = Repr::parse(b).unwrap();
            let vb = batch::convert(ra, rb, &va).unwrap();
            let back = batch::convert(rb, Repr::Matrix, &vb).unwrap();
            let tol = if a.starts_with("quat_g") || b.starts_with("quat_g") {
                2e-3
            } else {
                2e-5
            };
            let e = back
                .iter()
                .zip(&flat)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0f32, f32::max);
            assert!(e < tol, "{a} -> {b} -> matrix: {e}");
        }
    }
    let d = batch::geodesic(Repr::Matrix, &flat, &flat).unwrap();
    assert!(d.iter().all(|x| *x < 1e-3));
}

#[test]
fn batch_errors_are_clear() {
    let e = batch::convert(Repr::SixD, Repr::Quat, &[1.0; 7]).unwrap_err();
    assert!(e.to_string().contains("multiple of 6"), "{e}");
    let mut v = vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    v.extend_from_slice(&[0.0; 6]);
    let e = batch::convert(Repr::SixD, Repr::Quat, &v).unwrap_err();
    assert!(matches!(e, Error::Degenerate { index: 1, .. }), "{e:?}");
    let e = batch::convert(Repr::Quat, Repr::SixD, &[0.0, f32::NAN, 0.0, 1.0]).unwrap_err();
    assert!(matches!(e, Error::NotFinite { index: 1, .. }), "{e:?}");
    let e = Repr::parse("euler:XXY").unwrap_err();
    assert!(e.to_string().contains("Euler order"), "{e}");
    assert!(Repr::parse("quaternion")
        .unwrap_err()
        .to_string()
        .contains("accepted"));
}

// ---------------------------------------------------------------------------
// The fixture that the wasm suite (tests/wasm/browser.rs) compares against:
// inputs and the native outputs of every representation. Regenerate with
// DEEPREP_BLESS=1 cargo test --test native rotation::native_fixture.

pub const FIXTURE_REPRS: [&str; 10] = [
    "matrix",
    "6d",
    "5d",
    "quat",
    "quat_gq",
    "quat_gu",
    "axis_angle",
    "rodrigues",
    "euler:XZY",
    "euler:zyz",
];

#[test]
fn native_fixture_for_the_wasm_suite_is_current() {
    let mut rng = Rng::new(2020);
    let mats: Vec<Mat3<f32>> = (0..256).map(|_| uniform_so3(&mut rng)).collect();
    let flat: Vec<f32> = mats
        .iter()
        .flat_map(|m| m.iter().flatten().copied())
        .collect();
    let mut outputs = serde_json::Map::new();
    for r in FIXTURE_REPRS {
        let v = batch::convert(Repr::Matrix, Repr::parse(r).unwrap(), &flat).unwrap();
        outputs.insert(r.to_string(), serde_json::json!(v));
    }
    let fixture = serde_json::json!({"input_matrices": flat, "outputs": outputs});
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/rotations_native.json");
    if std::env::var("DEEPREP_BLESS").is_ok() {
        std::fs::write(&path, serde_json::to_string(&fixture).unwrap()).unwrap();
    }
    let saved: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(&path).expect("fixture missing: run with DEEPREP_BLESS=1"),
    )
    .unwrap();
    for r in FIXTURE_REPRS {
        let a = saved["outputs"][r].as_array().unwrap();
        let b = fixture["outputs"][r].as_array().unwrap();
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(b) {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!((x - y).abs() < 1e-6, "{r}: saved {x} vs now {y}");
        }
    }
}
