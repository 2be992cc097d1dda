#![allow(clippy::needless_range_loop)]
//! Range-Constrained FK (Sec. 5.2.3, Table D.1).

use deeprep::rcfk::{
    local_frame, local_frame_with, parse_table, FrameRule, RcSkeleton, TABLE_D1_JSON,
};
use deeprep::rng::Rng;
use deeprep::rotation::euler::{matrix_to_euler, EulerOrder};
use deeprep::rotation::{det, mul, transpose, Mat3};
use deeprep::skeleton::{fk, Bvh};
use std::path::PathBuf;

fn standard() -> Option<Bvh> {
    let p =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/cmu-bvh/standard.bvh");
    match std::fs::read_to_string(&p) {
        Ok(t) => Some(Bvh::parse(&t).unwrap()),
        Err(_) => {
            eprintln!("SKIP: ../shared/data/cmu-bvh/standard.bvh is absent");
            None
        }
    }
}

/// A small skeleton of the project's own, with a table of its own.
fn tiny() -> (Bvh, String) {
    let bvh = "HIERARCHY\nROOT hip\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n JOINT spine\n {\n  OFFSET 0 10 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 5 0\n  }\n }\n JOINT arm\n {\n  OFFSET -3 8 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  JOINT fore\n  {\n   OFFSET -6 0 0\n   CHANNELS 3 Zrotation Xrotation Yrotation\n   End Site\n   {\n    OFFSET -5 0 0\n   }\n  }\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n";
    let table = r#"{"joints": [
      {"joint": "hip", "x": [-360, 360], "y": [-360, 360], "z": [-360, 360], "order": "xzy"},
      {"joint": "spine", "x": [-45, 68], "y": [-30, 30], "z": [-45, 45], "order": "xzy"},
      {"joint": "arm", "x": [-90, 135], "y": [-30, 110], "z": [-70, 60], "order": "xzy"},
      {"joint": "fore", "x": [0, 0], "y": [0, 150], "z": [-30, 120], "order": "yxz"}]}"#;
    (Bvh::parse(bvh).unwrap(), table.to_string())
}

#[test]
fn table_d1_is_complete_data() {
    let t = parse_table(TABLE_D1_JSON).unwrap();
    assert_eq!(t.len(), 57);
    let fore = t.iter().find(|r| r.joint == "lForeArm").unwrap();
    assert_eq!(fore.order, "yxz");
    assert_eq!(fore.y, Some([0.0, 150.0]));
    let shin = t.iter().find(|r| r.joint == "rShin").unwrap();
    assert_eq!(
        (shin.x, shin.y, shin.order.as_str()),
        (Some([0.0, 170.0]), Some([0.0, 0.0]), "xzy")
    );
    assert!(t
        .iter()
        .filter(|r| r.x.is_none())
        .all(|r| r.joint.ends_with("_Nub")));
}

#[test]
fn local_frames_are_rotations_with_z_along_the_bone() {
    let mut rng = Rng::new(5);
    for _ in 0..1000 {
        let d = [rng.normal(), rng.normal(), rng.normal()];
        let m = local_frame(d);
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        assert!((det(&m) - 1.0).abs() < 1e-9);
        let mt: Mat3<f64> = mul(&m, &transpose(&m));
        for i in 0..3 {
            assert!((m[i][2] - d[i] / n).abs() < 1e-9, "z is the bone");
            for j in 0..3 {
                assert!((mt[i][j] - if i == j { 1.0 } else { 0.0 }).abs() < 1e-9);
            }
        }
    }
}

#[test]
fn an_explicit_axis_frame_puts_y_on_that_axis() {
    let mut rng = Rng::new(9);
    for _ in 0..1000 {
        let d = [rng.normal(), rng.normal(), rng.normal()];
        let a = [rng.normal(), rng.normal(), rng.normal()];
        let m = local_frame_with(d, FrameRule::AxisY(a));
        assert!((det(&m) - 1.0).abs() < 1e-9);
        let nd = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let y = [m[0][1], m[1][1], m[2][1]];
        // y is a made perpendicular to the bone: y·a = |a - (a·z)z| > 0, and y·z = 0.
        let z = [d[0] / nd, d[1] / nd, d[2] / nd];
        let az = a[0] * z[0] + a[1] * z[1] + a[2] * z[2];
        let ap = [a[0] - az * z[0], a[1] - az * z[1], a[2] - az * z[2]];
        let npar = (ap[0] * ap[0] + ap[1] * ap[1] + ap[2] * ap[2]).sqrt();
        let cos = (y[0] * ap[0] + y[1] * ap[1] + y[2] * ap[2]) / npar;
        assert!(
            (cos - 1.0).abs() < 1e-9,
            "y along the projected axis: cos {cos}"
        );
        for i in 0..3 {
            assert!((m[i][2] - z[i]).abs() < 1e-9, "z is the bone");
        }
    }
    // The JSON form reaches the skeleton, and a malformed rule is an error.
    let (bvh, table) = tiny();
    let with_axis = table.replace(
        r#""order": "yxz"}"#,
        r#""order": "yxz", "frame": {"y": [0, 0, 1]}}"#,
    );
    let sk = RcSkeleton::new(&bvh, &parse_table(&with_axis).unwrap()).unwrap();
    let fore = sk.names.iter().position(|n| n == "fore").unwrap();
    let y = [
        sk.frames[fore][0][1],
        sk.frames[fore][1][1],
        sk.frames[fore][2][1],
    ];
    assert!((y[2] - 1.0).abs() < 1e-9, "{y:?}");
    let bad = table.replace(r#""order": "yxz"}"#, r#""order": "yxz", "frame": "w"}"#);
    let err = RcSkeleton::new(&bvh, &parse_table(&bad).unwrap()).expect_err("unknown rule");
    assert!(err.to_string().contains("unknown frame rule"), "{err}");
}

/// The elbows of the CMU data are hinges about the fitted axes of
/// `table_d1.json` (`train/deeprep_train/motion/fit_frames.py`): the forearms leave Table D.1's
/// ranges by well under a degree on average, on a validation take that the
/// fit never saw.
#[test]
fn cmu_elbows_are_hinges_in_the_fitted_frames() {
    let p =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/cmu-bvh/salsa/04.bvh");
    let Ok(text) = std::fs::read_to_string(&p) else {
        eprintln!("SKIP: ../shared/data/cmu-bvh/salsa/04.bvh is absent");
        return;
    };
    let bvh = Bvh::parse(&text).unwrap();
    let sk = RcSkeleton::thesis(&bvh).unwrap();
    let v = sk.violations(&bvh).unwrap();
    for side in ["lForeArm", "rForeArm"] {
        let mean = v
            .iter()
            .find(|x| x.joint == side)
            .map_or(0.0, |x| x.mean_deg);
        assert!(mean < 0.5, "{side}: mean excess {mean:.2} degrees");
    }
}

/// Writes RC-FK's local rotations into a BVH frame (channels Z X Y).
fn to_channels(sk: &RcSkeleton, bvh: &Bvh, raw: &[f32], root_pos: [f32; 3]) -> Vec<f32> {
    // Recover the local rotations by differencing global ones is overkill:
    // rebuild them the way forward() does, through the public pieces.
    let zxy = EulerOrder::intrinsic("ZXY").unwrap();
    let r6: [f64; 6] = std::array::from_fn(|i| raw[i] as f64);
    let mut out = vec![0.0f32; bvh.channel_count()];
    out[0..3].copy_from_slice(&root_pos);
    let root = deeprep::rotation::sixd::sixd_to_matrix(&r6).unwrap();
    let zyx = EulerOrder::intrinsic("ZYX").unwrap();
    let e = matrix_to_euler(&root, zyx);
    out[3..6].copy_from_slice(&[
        e[0].to_degrees() as f32,
        e[1].to_degrees() as f32,
        e[2].to_degrees() as f32,
    ]);
    for (k, &j) in sk.rotating.iter().enumerate() {
        let o = sk.orders[k];
        let mut u = [0.0f64; 3];
        for a in 0..3 {
            let [lo, hi] = sk.ranges[k][a];
            u[a] = lo + (hi - lo) * ((raw[6 + 3 * k + a] as f64).tanh() + 1.0) / 2.0;
        }
        let seq = [
            u[o.axes[0] as usize],
            u[o.axes[1] as usize],
            u[o.axes[2] as usize],
        ];
        let rl = deeprep::rotation::euler::euler_to_matrix(&seq, o);
        let m = &sk.frames[j];
        let r = mul(&mul(m, &rl), &transpose(m));
        let e = matrix_to_euler(&r, zxy);
        let s = bvh.joints[j].channel_start;
        out[s..s + 3].copy_from_slice(&[
            e[0].to_degrees() as f32,
            e[1].to_degrees() as f32,
            e[2].to_degrees() as f32,
        ]);
    }
    out
}

fn check_forward_inverse(bvh: &Bvh, sk: &RcSkeleton, seed: u64) {
    let mut rng = Rng::new(seed);
    for _ in 0..200 {
        let raw: Vec<f32> = (0..sk.output_dim())
            .map(|_| (rng.normal() * 1.5) as f32)
            .collect();
        let root_pos = [rng.normal() as f32 * 50.0, 90.0, rng.normal() as f32 * 50.0];
        let pos = sk.forward(&raw, root_pos).unwrap();
        // The same pose written as BVH channels and run through plain FK.
        let mut clip = bvh.clone();
        clip.motion = to_channels(sk, bvh, &raw, root_pos);
        let plain = fk::positions(&clip, 0, 1).unwrap();
        let d = pos
            .iter()
            .zip(&plain)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(d < 2e-3, "RC-FK vs BVH FK: {d}");
        // Inverse: the angles come back inside their ranges, no violations,
        // and rebuild the same positions.
        let inv = sk.inverse(&clip, 0).unwrap();
        let worst = inv.excess.iter().flatten().cloned().fold(0.0f64, f64::max);
        assert!(
            worst < 1e-4,
            "an in-range pose reported {worst} rad outside"
        );
        let back = sk.reconstruct(&inv).unwrap();
        let d = back
            .iter()
            .zip(&plain)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(d < 2e-3, "inverse then forward: {d}");
    }
}

#[test]
fn forward_matches_bvh_fk_and_inverse_recovers_the_pose_tiny() {
    let (bvh, table) = tiny();
    let sk = RcSkeleton::new(&bvh, &parse_table(&table).unwrap()).unwrap();
    assert_eq!(sk.output_dim(), 6 + 9);
    check_forward_inverse(&bvh, &sk, 1);
}

#[test]
fn forward_matches_bvh_fk_and_inverse_recovers_the_pose_thesis_skeleton() {
    let Some(bvh) = standard() else { return };
    let sk = RcSkeleton::thesis(&bvh).unwrap();
    assert_eq!(sk.rotating.len(), 42);
    check_forward_inverse(&bvh, &sk, 2);
}

#[test]
fn outputs_stay_in_range_and_bad_input_is_an_error() {
    let (bvh, table) = tiny();
    let sk = RcSkeleton::new(&bvh, &parse_table(&table).unwrap()).unwrap();
    // Extreme raw values saturate at the range ends rather than leave them.
    let mut raw = vec![50.0f32; sk.output_dim()];
    raw[0..6].copy_from_slice(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let mut clip = bvh.clone();
    clip.motion = to_channels(&sk, &bvh, &raw, [0.0; 3]);
    let inv = sk.inverse(&clip, 0).unwrap();
    assert!(inv.excess.iter().flatten().all(|e| *e < 1e-3));
    assert!(sk
        .forward(&raw[1..], [0.0; 3])
        .unwrap_err()
        .to_string()
        .contains("expected 15"));
    raw[7] = f32::NAN;
    assert!(sk.forward(&raw, [0.0; 3]).is_err());
    let e = RcSkeleton::new(&bvh, &parse_table(r#"{"joints": []}"#).unwrap()).unwrap_err();
    assert!(e.to_string().contains("not in the range table"), "{e}");
}

#[test]
fn rust_and_pytorch_rcfk_agree_to_1e_4() {
    // Written by train/deeprep_train/motion/make_rcfk_fixture.py from the PyTorch layer
    // (train/deeprep_train/rcfk.py) on the thesis skeleton.
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/rcfk_torch.json");
    let f: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
    let floats = |k: &str| -> Vec<f32> {
        f[k].as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap() as f32)
            .collect()
    };
    let bvh = Bvh::parse(f["skeleton_bvh"].as_str().unwrap()).unwrap();
    let sk = RcSkeleton::thesis(&bvh).unwrap();
    let dim = f["output_dim"].as_u64().unwrap() as usize;
    assert_eq!(dim, sk.output_dim());
    let (raw, root, expected) = (floats("raw"), floats("root_pos"), floats("positions_torch"));
    let frames = f["frames"].as_u64().unwrap() as usize;
    let nj = bvh.joints.len();
    let mut worst = 0.0f32;
    for t in 0..frames {
        let pos = sk
            .forward(
                &raw[t * dim..(t + 1) * dim],
                [root[3 * t], root[3 * t + 1], root[3 * t + 2]],
            )
            .unwrap();
        for (a, b) in pos.iter().zip(&expected[t * nj * 3..(t + 1) * nj * 3]) {
            worst = worst.max((a - b).abs());
        }
    }
    assert!(
        worst <= 1e-4,
        "Rust vs PyTorch RC-FK max abs diff {worst} (BVH units)"
    );
}

#[test]
fn raw_from_rotations_inverts_local_rotations_within_the_clip() {
    let (bvh, table) = tiny();
    let sk = RcSkeleton::new(&bvh, &parse_table(&table).unwrap()).unwrap();
    let mut rng = Rng::new(9);
    for _ in 0..500 {
        // |v| < 2.5 stays inside the V_CLIP = 3 bound.
        let mut raw: Vec<f32> = (0..sk.output_dim())
            .map(|_| (rng.range(-2.5, 2.5)) as f32)
            .collect();
        let r6 = deeprep::rotation::sixd::matrix_to_6d(&deeprep::rotation::sample::uniform_so3::<
            f64,
        >(&mut rng));
        for i in 0..6 {
            raw[i] = r6[i] as f32;
        }
        let rots = sk.local_rotations(&raw).unwrap();
        let back = sk.raw_from_rotations(&rots);
        for (k, &j) in sk.rotating.iter().enumerate() {
            for a in 0..3 {
                let [lo, hi] = sk.ranges[k][a];
                let i = 6 + 3 * k + a;
                if hi > lo {
                    assert!(
                        (back[i] - raw[i]).abs() < 2e-3,
                        "joint {j} axis {a}: {} vs {}",
                        back[i],
                        raw[i]
                    );
                } else {
                    assert_eq!(back[i], 0.0);
                }
            }
        }
        for i in 0..6 {
            assert!((back[i] - raw[i]).abs() < 1e-5);
        }
    }
}
