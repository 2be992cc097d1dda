//! In-betweening: dense input, baselines, post-processing, the model
//! pipeline and tract parity on the exported models.

use deeprep::motion::baseline::{slerp_lerp, zero_velocity};
use deeprep::motion::dense::{dense_input, Norm};
use deeprep::motion::feet::FootLock;
use deeprep::motion::pipeline::{Request, TweenModels};
use deeprep::motion::post::{make_keys_exact, scale_root_deviation};
use deeprep::motion::{Keyframe, Motion};
use deeprep::rng::Rng;
use deeprep::rotation::sample::uniform_so3;
use deeprep::rotation::{geodesic_distance, Mat3};
use deeprep::skeleton::Bvh;

const NORM: Norm = Norm {
    scale: 100.0,
    dt_norm: 60.0,
    dt_clip: 600.0,
};

use crate::common;
use common::root;

fn key(frame: usize, vals: &[f32], mask: &[bool]) -> Keyframe {
    Keyframe {
        frame,
        positions: vals.to_vec(),
        mask: mask.to_vec(),
        rotations: None,
    }
}

#[test]
fn dense_input_copies_the_nearest_key_and_its_distance() {
    // One joint (3 coordinates), keys at frames 2 and 6, 8 frames.
    let a = key(2, &[100.0, 50.0, 300.0], &[true, true, true]);
    let b = key(6, &[300.0, 70.0, 100.0], &[true, false, true]);
    let d = dense_input(&[a, b], 8, &NORM);
    let (n, p) = (8, 3);
    let v = |c: usize, t: usize| d[c * n + t];
    let dt = |c: usize, t: usize| d[(p + c) * n + t];
    // Root x/z are taken relative to the mean key x/z: (200, 200).
    let xs: Vec<f32> = (0..8).map(|t| v(0, t)).collect();
    assert_eq!(xs, [-1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0]); // frame 4 ties -> earlier key
    let ds: Vec<f32> = (0..8).map(|t| dt(0, t) * 60.0).collect();
    assert_eq!(ds, [2.0, 1.0, 0.0, 1.0, 2.0, 1.0, 0.0, 1.0]);
    // y is only given by the first key: copied everywhere, distance grows.
    assert!((0..8).all(|t| (v(1, t) - 0.5).abs() < 1e-6));
    assert!((dt(1, 7) * 60.0 - 5.0).abs() < 1e-4);
    // A coordinate no key gives: 0, and the clipped distance.
    let c = key(3, &[0.0, 0.0, 0.0], &[false, false, false]);
    let d = dense_input(&[c], 4, &NORM);
    assert!(d[..12].iter().all(|x| *x == 0.0) && d[12..].iter().all(|x| (*x - 10.0).abs() < 1e-6));
}

fn rot_key(frame: usize, rng: &mut Rng, joints: usize) -> Keyframe {
    let mut positions = vec![0.0f32; 3 * joints];
    positions[0] = rng.normal() as f32 * 50.0;
    positions[1] = 90.0;
    positions[2] = rng.normal() as f32 * 50.0;
    Keyframe {
        frame,
        mask: vec![true; 3 * joints],
        positions,
        rotations: Some((0..joints).map(|_| uniform_so3::<f64>(rng)).collect()),
    }
}

#[test]
fn slerp_lerp_hits_keys_and_interpolates_between() {
    let mut rng = Rng::new(1);
    let keys = vec![rot_key(3, &mut rng, 4), rot_key(13, &mut rng, 4)];
    let m = slerp_lerp(&keys, 20).unwrap();
    assert_eq!(m.len(), 20);
    for k in &keys {
        for j in 0..4 {
            assert!(
                geodesic_distance(&m.rotations[k.frame][j], &k.rotations.as_ref().unwrap()[j])
                    < 1e-9
            );
        }
    }
    // Midway: the root is the average, each rotation halfway along the arc.
    let mid = &m.root[8];
    assert!((mid[0] - (keys[0].positions[0] + keys[1].positions[0]) as f64 / 2.0).abs() < 1e-4);
    for j in 0..4 {
        let (a, b) = (
            &keys[0].rotations.as_ref().unwrap()[j],
            &keys[1].rotations.as_ref().unwrap()[j],
        );
        let (da, db) = (
            geodesic_distance(&m.rotations[8][j], a),
            geodesic_distance(&m.rotations[8][j], b),
        );
        assert!((da - db).abs() < 1e-6, "{da} vs {db}");
    }
    // Outside the keys, the nearest key is held; zero-velocity holds the last key.
    assert_eq!(m.root[0], m.root[3]);
    assert_eq!(m.root[19], m.root[13]);
    let z = zero_velocity(&keys, 20).unwrap();
    assert_eq!(z.root[12], z.root[3]);
}

#[test]
fn post_processing_makes_keys_exact_and_leaves_smooth_corrections() {
    let mut rng = Rng::new(2);
    let keys = vec![
        rot_key(0, &mut rng, 3),
        rot_key(30, &mut rng, 3),
        rot_key(59, &mut rng, 3),
    ];
    let mut m = Motion {
        root: (0..60).map(|t| [t as f64, 80.0, 0.0]).collect(),
        rotations: (0..60)
            .map(|_| (0..3).map(|_| uniform_so3::<f64>(&mut rng)).collect())
            .collect(),
    };
    let before = m.clone();
    make_keys_exact(&mut m, &keys);
    for k in &keys {
        for c in 0..3 {
            assert!((m.root[k.frame][c] - k.positions[c] as f64).abs() < 1e-9);
        }
        for j in 0..3 {
            assert!(
                geodesic_distance(&m.rotations[k.frame][j], &k.rotations.as_ref().unwrap()[j])
                    < 1e-7
            );
        }
    }
    // The root correction is a smooth blend: its change per frame is bounded
    // by the key errors divided by the gap (smoothstep's slope is 1.5).
    let corr: Vec<f64> = (0..60).map(|t| m.root[t][0] - before.root[t][0]).collect();
    for t in 1..30 {
        let step = (corr[t] - corr[t - 1]).abs();
        assert!(step <= 1.5 * (corr[30] - corr[0]).abs() / 30.0 + 1e-9);
    }
}

#[test]
fn root_variation_scales_the_path_about_the_keys_lerp() {
    // A wavy path; keys give x at 10 and 40, y only at 20 (and z nowhere).
    let path: Vec<[f64; 3]> = (0..60)
        .map(|t| {
            let t = t as f64;
            [t + 5.0 * (t / 4.0).sin(), 80.0 + (t / 3.0).cos(), 2.0 * t]
        })
        .collect();
    let m = [true, false, false];
    let keys = vec![
        key(10, &[0.0, 0.0, 0.0], &m),
        key(20, &[0.0, 70.0, 0.0], &[false, true, false]),
        key(40, &[60.0, 0.0, 0.0], &m),
    ];
    let scaled = |share| {
        let mut p = path.clone();
        scale_root_deviation(&mut p, &keys, share);
        p
    };
    assert_eq!(scaled(1.0), path);
    let lerp = scaled(0.0);
    let half = scaled(0.5);
    for t in 10..=40 {
        let want = 60.0 * (t - 10) as f64 / 30.0;
        assert!((lerp[t][0] - want).abs() < 1e-12, "x at {t}");
        let mid = 0.5 * (path[t][0] + want);
        assert!((half[t][0] - mid).abs() < 1e-12, "half-way x at {t}");
    }
    // Outside the keys the path moves rigidly with the end key (continuous).
    for t in (0..10).chain(41..60) {
        let end = if t < 10 { 10 } else { 40 };
        let shift = lerp[end][0] - path[end][0];
        assert!((lerp[t][0] - path[t][0] - shift).abs() < 1e-12, "x at {t}");
    }
    // A single key pins the coordinate's offset everywhere; z is untouched.
    for t in 0..60 {
        assert!((lerp[t][1] - (path[t][1] - path[20][1] + 70.0)).abs() < 1e-12);
        assert_eq!(lerp[t][2], path[t][2]);
    }
}

#[test]
fn bad_requests_are_clear_errors() {
    let mut rng = Rng::new(3);
    let k = |f| rot_key(f, &mut Rng::new(f as u64), 2);
    assert!(slerp_lerp(&[k(5), k(5)], 10)
        .unwrap_err()
        .to_string()
        .contains("sorted with no duplicates"));
    assert!(slerp_lerp(&[k(5), k(3)], 10).is_err());
    assert!(slerp_lerp(&[k(5), k(12)], 10)
        .unwrap_err()
        .to_string()
        .contains("motion has 10 frames"));
    let mut nan = rot_key(1, &mut rng, 2);
    nan.positions[4] = f32::NAN;
    assert!(slerp_lerp(&[nan], 10)
        .unwrap_err()
        .to_string()
        .contains("not finite"));
    let mut short = rot_key(1, &mut rng, 2);
    short.positions.pop();
    assert!(slerp_lerp(&[short], 10).is_err());
    assert!(slerp_lerp(&[], 10)
        .unwrap_err()
        .to_string()
        .contains("no keyframes"));
    assert!(zero_velocity(&[], 10).is_err());
    let partial = key(1, &[0.0; 6], &[true, true, true, false, false, false]);
    assert!(slerp_lerp(&[partial], 10)
        .unwrap_err()
        .to_string()
        .contains("whole-pose"));
}

// ---------------------------------------------------------------------------
// The exported models (models/onnx/tween_*.onnx).

fn models() -> Option<TweenModels> {
    let dir = root().join("models/onnx");
    if !dir.join("tween_generator.onnx").exists() {
        eprintln!("SKIP: models/onnx/tween_generator.onnx is not exported yet");
        return None;
    }
    Some(TweenModels::load_dir(&dir).unwrap())
}

/// A copy of models/onnx in a new temporary folder (`deeprep_TAG_PID`), for
/// tests that change a manifest or add a stand-in network: (the folder, its
/// models/ subfolder).
fn models_copy(tag: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = std::env::temp_dir().join(format!("deeprep_{tag}_{}", std::process::id()));
    let lib = dir.join("models");
    std::fs::create_dir_all(&lib).unwrap();
    for e in std::fs::read_dir(root().join("models/onnx")).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_file() {
            std::fs::copy(e.path(), lib.join(e.file_name())).unwrap();
        }
    }
    (dir, lib)
}

fn fixture_parity(name: &str) {
    if !root()
        .join(format!("models/onnx/fixtures/{name}.json"))
        .exists()
    {
        eprintln!("SKIP: models/onnx/fixtures/{name}.json missing");
        return;
    }
    common::fixture_parity(name, 1e-4);
}

#[test]
fn tract_matches_onnxruntime_on_the_tween_models() {
    fixture_parity("tween_generator");
    fixture_parity("tween_path");
    fixture_parity("tween_residual");
}

/// The bundled residual network, or None (with a SKIP line) before it is exported.
fn residual_model() -> Option<deeprep::motion::residual::ResidualModel> {
    let dir = root().join("models/onnx");
    if !dir.join("tween_residual.onnx").exists() {
        eprintln!("SKIP: models/onnx/tween_residual.onnx is not exported yet");
        return None;
    }
    Some(deeprep::motion::residual::ResidualModel::load_dir(&dir).unwrap())
}

/// Whole-pose keys at `frames`: the template's rest pose moved along x,
/// turned about the root's first channel and bent at one joint, more with
/// each key.
fn posed_keys(template: &Bvh, frames: &[usize]) -> Vec<Keyframe> {
    frames
        .iter()
        .enumerate()
        .map(|(i, &f)| {
            let mut b: Bvh = template.clone();
            let mut ch = vec![0.0f32; b.channel_count()];
            ch[0] = 40.0 * i as f32;
            ch[1] = 85.0;
            ch[3] = 30.0 * i as f32;
            ch[7] = 20.0 - 15.0 * i as f32;
            b.motion = ch;
            Keyframe::from_bvh(&b, 0, f).unwrap()
        })
        .collect()
}

/// The residual network (issue 19, stage 1): keys exact by construction,
/// variation 0 is SLERP+LERP exactly, frames outside the keys hold them,
/// and bad variations are errors.
#[test]
fn the_residual_model_keeps_keys_and_scales_by_variation() {
    let Some(m) = residual_model() else { return };
    let keys = posed_keys(&m.template, &[10, 70, 250]);
    // when its manifest makes it the default for whole-pose keys, it serves
    // them without DNA and with gaps the generator reaches directly; longer
    // gaps go to the generator's hierarchical synthesis
    let mut far = keys.clone();
    far[2].frame = 10 + 1 + deeprep::motion::MAX_GAP + 70;
    use deeprep::motion::plan::{plan, Ask, Loaded, Pipeline};
    let loaded = Loaded {
        generator: Some(0.25),
        residual: Some(m.info()),
        cond: None,
        cond_dna: None,
        fill: None,
        fill_long: None,
    };
    let model = |keys: &[Keyframe], dna: bool| {
        let ask = Ask {
            method: "model",
            keys,
            dna,
            post_process: true,
            variation: None,
        };
        plan(&ask, &loaded).unwrap().pipeline
    };
    assert_eq!(
        model(&far, false),
        Pipeline::Generator,
        "a gap over MAX_GAP"
    );
    assert_eq!(model(&keys, true), Pipeline::Generator, "DNA asked for");
    assert_eq!(
        model(&keys, false) == Pipeline::Residual,
        m.info().default_for_whole_pose_keys
    );
    let frames = 280;
    let out = m.synthesize(&keys, frames, 1.0).unwrap();
    let plain = slerp_lerp(&keys, frames).unwrap();
    assert_eq!(out.len(), frames);
    for k in &keys {
        for (a, b) in out.rotations[k.frame].iter().zip(&plain.rotations[k.frame]) {
            assert!(geodesic_distance(a, b) < 1e-9, "key {}", k.frame);
        }
        assert_eq!(out.root[k.frame], plain.root[k.frame]);
    }
    for t in (0..10).chain(251..frames) {
        assert_eq!(out.root[t], plain.root[t], "frame {t} holds its key");
    }
    let moved = (11..250)
        .map(|t| geodesic_distance(&out.rotations[t][1], &plain.rotations[t][1]))
        .fold(0.0, f64::max);
    assert!(
        moved > 1e-4,
        "the network changes the in-betweens ({moved})"
    );
    assert!(out.root.iter().flatten().all(|v| v.is_finite()));
    let zero = m.synthesize(&keys, frames, 0.0).unwrap();
    assert_eq!(zero.root, plain.root);
    assert_eq!(zero.rotations, plain.rotations);
    assert!(m.synthesize(&keys, frames, 2.5).is_err());
    assert!(m.synthesize(&keys, frames, f32::NAN).is_err());
}

/// `key` turned by `r` (a rotation about the vertical) about the origin,
/// then moved by `dx`, `dz` on the floor: root position and root rotation
/// turned, the other joints' root-relative world positions turned.
fn turned(key: &Keyframe, r: &Mat3<f64>, dx: f64, dz: f64) -> Keyframe {
    use deeprep::rotation::mul_vec;
    let mut k = key.clone();
    for (j, p) in k.positions.chunks_mut(3).enumerate() {
        let mut w = mul_vec(r, &[p[0] as f64, p[1] as f64, p[2] as f64]);
        if j == 0 {
            w[0] += dx;
            w[2] += dz;
        }
        for (a, b) in p.iter_mut().zip(w) {
            *a = b as f32;
        }
    }
    if let Some(rot) = k.rotations.as_mut() {
        rot[0] = deeprep::rotation::mul(r, &rot[0]);
    }
    k
}

/// Issue 19, item 1's "random rotation about the vertical axis and random
/// translation": the residual network sees its input in the first key's
/// frame, so turning and moving every key turns and moves the output the
/// same way (no augmentation needed; train/README.md's ablation table).
#[test]
fn the_residual_model_turns_and_moves_with_its_keys() {
    let Some(m) = residual_model() else { return };
    let keys = posed_keys(&m.template, &[0, 90, 240]);
    let frames = 260;
    let base = m.synthesize(&keys, frames, 1.0).unwrap();
    let (dx, dz) = (350.0, -120.0);
    let r = deeprep::rotation::axis_angle::axis_angle_to_matrix(&[0.0, 1.0, 0.0], 2.1f64);
    let moved: Vec<_> = keys.iter().map(|k| turned(k, &r, dx, dz)).collect();
    let out = m.synthesize(&moved, frames, 1.0).unwrap();
    let (mut root_err, mut rot_err) = (0.0f64, 0.0f64);
    for t in 0..frames {
        let mut want = deeprep::rotation::mul_vec(&r, &base.root[t]);
        want[0] += dx;
        want[2] += dz;
        for (a, b) in out.root[t].iter().zip(want) {
            root_err = root_err.max((a - b).abs());
        }
        let want0 = deeprep::rotation::mul(&r, &base.rotations[t][0]);
        rot_err = rot_err.max(geodesic_distance(&out.rotations[t][0], &want0));
        for (a, b) in out.rotations[t].iter().zip(&base.rotations[t]).skip(1) {
            rot_err = rot_err.max(geodesic_distance(a, b));
        }
    }
    // the network runs in float32 on inputs that differ by rounding only
    assert!(root_err < 1e-3, "root off by {root_err} units");
    assert!(rot_err < 1e-4, "rotations off by {rot_err} rad");
    // and the test is not vacuous: the turn moved the output
    assert!(out.root[150][0] - base.root[150][0] > 1.0);
}

#[test]
fn interpolated_channels_are_linear_between_keys_and_held_outside() {
    use deeprep::motion::dense::interp_channels;
    let rows = vec![
        (2usize, vec![0.0f32, 5.0], vec![true, true]),
        (6, vec![4.0, 9.0], vec![true, false]),
    ];
    let v = interp_channels(&rows, 2, 9);
    assert_eq!(&v[0..9], &[0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0, 4.0]);
    assert!(
        v[9..].iter().all(|x| *x == 5.0),
        "a channel given once is held everywhere"
    );
    let none = interp_channels(&[(0usize, vec![1.0f32], vec![false])], 1, 3);
    assert_eq!(none, vec![0.0; 3]);
}

#[test]
fn dense_inputs_match_the_pytorch_training_code() {
    // Written by train/deeprep_train/motion/make_dense_fixture.py from train/deeprep_train/motion/nets.py.
    use deeprep::motion::dense::{base_channels, dense_channels, interp_channels, Base};
    let p = root().join("tests/fixtures/dense_torch.json");
    let f: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
    let floats = |v: &serde_json::Value| -> Vec<f32> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap() as f32)
            .collect()
    };
    let n = f["frames"].as_u64().unwrap() as usize;
    let r = f["raw_width"].as_u64().unwrap() as usize;
    let mut keys = Vec::new();
    let mut rows = Vec::new();
    for k in f["keys"].as_array().unwrap() {
        let frame = k["frame"].as_u64().unwrap() as usize;
        let mask: Vec<bool> = k["mask"]
            .as_array()
            .unwrap()
            .iter()
            .map(|b| b.as_bool().unwrap())
            .collect();
        keys.push(Keyframe {
            frame,
            positions: floats(&k["positions"]),
            mask,
            rotations: None,
        });
        if !k["raw"].is_null() {
            rows.push((frame, floats(&k["raw"]), vec![true; r]));
        }
    }
    let close = |a: &[f32], b: &[f32], what: &str| {
        assert_eq!(a.len(), b.len(), "{what}");
        let d = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f32, f32::max);
        assert!(d < 1e-5, "{what}: max abs diff {d}");
    };
    close(
        &dense_input(&keys, n, &NORM),
        &floats(&f["dense"]),
        "dense keyframe input",
    );
    let mut drot = dense_channels(&rows, r, n, &NORM);
    drot[..r * n].copy_from_slice(&interp_channels(&rows, r, n));
    close(&drot, &floats(&f["dense_rot"]), "dense key rotations");
    for (name, base) in [
        ("linear", Base::Linear),
        ("spline", Base::Spline),
        ("angle-linear", Base::AngleLinear),
        ("angle-spline", Base::AngleSpline),
    ] {
        close(
            &base_channels(&rows, r, n, base),
            &floats(&f["bases"][name]),
            name,
        );
    }
}

#[test]
fn spline_channels_pass_through_keys_and_keep_linear_data_linear() {
    use deeprep::motion::dense::spline_channels;
    // Unevenly spaced keys on a line: the spline is that line between them.
    let line = |t: usize| 0.5 * t as f32 - 3.0;
    let rows: Vec<_> = [2usize, 5, 17, 40]
        .iter()
        .map(|&t| (t, vec![line(t), (t * t) as f32], vec![true, true]))
        .collect();
    let v = spline_channels(&rows, 2, 45);
    for (t, x) in v.iter().enumerate().take(41).skip(2) {
        assert!((x - line(t)).abs() < 1e-4, "frame {t}: {x} vs {}", line(t));
    }
    assert_eq!(v[0], line(2), "held before the first key");
    assert_eq!(v[44], line(40), "held after the last key");
    // A curved channel: exact at keys, C1 (no kink) across an inner key.
    for &t in &[2usize, 5, 17, 40] {
        assert!((v[45 + t] - (t * t) as f32).abs() < 1e-3);
    }
    // Slope change across key 17 (one-frame differences): the spline's is
    // its curvature, small next to the linear interpolation's kink.
    let lin = deeprep::motion::dense::interp_channels(&rows, 2, 45);
    let jump = |x: &[f32]| (x[45 + 18] - x[45 + 17]) - (x[45 + 17] - x[45 + 16]);
    assert!(
        jump(&v).abs() < 0.2 * jump(&lin).abs(),
        "kink at 17: {} vs linear {}",
        jump(&v),
        jump(&lin)
    );
    // Differs from the linear interpolation on curved data.
    assert!((v[45 + 30] - lin[45 + 30]).abs() > 1.0);
}

// ---------------------------------------------------------------------------
// Foot locking.

const LEG_BVH: &str = "HIERARCHY
ROOT hip
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT lThigh
  {
    OFFSET 10 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT lShin
    {
      OFFSET 0 -40 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT lFoot
      {
        OFFSET 0 -40 0
        CHANNELS 3 Zrotation Xrotation Yrotation
        End Site
        {
          OFFSET 0 0 10
        }
      }
    }
  }
}
MOTION
Frames: 1
Frame Time: 0.0166667
0 75 0 0 0 0 0 30 0 0 -60 0 0 30 0
";

/// Global ankle position and foot rotation of the leg skeleton.
fn ankle(m: &Motion, f: usize, b: &Bvh) -> ([f64; 3], Mat3<f64>) {
    let parents: Vec<Option<usize>> = b.joints.iter().map(|j| j.parent).collect();
    let offsets: Vec<[f64; 3]> = b
        .joints
        .iter()
        .map(|j| j.offset.map(|v| v as f64))
        .collect();
    let (rot, pos) = m.global_pose(f, &parents, &offsets);
    (pos[3], rot[3])
}

#[test]
fn foot_locking_pins_a_sliding_foot_and_keeps_keys_exact() {
    let b = Bvh::parse(LEG_BVH).unwrap();
    assert_eq!(deeprep::motion::feet::legs(&b), vec![[1, 2, 3]]);
    // The bent leg's pose, with the hip drifting forward 0.25 units a frame:
    // the foot slides along the floor with it.
    let pose = Keyframe::from_bvh(&b, 0, 0).unwrap();
    let rots = pose.rotations.clone().unwrap();
    let mut m = Motion {
        root: (0..40).map(|t| [0.25 * t as f64, 75.0, 0.0]).collect(),
        rotations: vec![rots.clone(); 40],
    };
    let mut keys = vec![pose.clone()];
    let mut last = pose;
    last.frame = 39;
    last.positions[0] = m.root[39][0] as f32;
    keys.push(last);
    let before = m.clone();
    let cfg = FootLock {
        height: 4.0,
        speed: 1.0,
        min_frames: 4,
        blend: 6,
    };
    let stats = deeprep::motion::feet::lock_feet(&mut m, &b, &keys, &cfg);
    assert_eq!((stats.legs, stats.contacts), (1, 1), "{stats:?}");
    // Keys are untouched.
    for k in &keys {
        for j in 0..4 {
            assert!(
                geodesic_distance(&m.rotations[k.frame][j], &before.rotations[k.frame][j]) < 1e-9
            );
        }
    }
    // The contact holds both keys: the foot is pinned where the key nearest
    // its middle (frame 39) puts it, from the end of the first key's blend
    // window on, its height and global rotation kept.
    let (pin, _) = ankle(&before, 39, &b);
    for f in 7..40 {
        let (a, r) = ankle(&m, f, &b);
        let (a0, r0) = ankle(&before, f, &b);
        assert!(
            (a[0] - pin[0]).abs() < 1e-6 && (a[2] - pin[2]).abs() < 1e-6,
            "frame {f}: {a:?} vs {pin:?}"
        );
        assert!((a[1] - a0[1]).abs() < 1e-6);
        assert!(geodesic_distance(&r, &r0) < 1e-9);
    }
    // ... and released smoothly towards the first key: no frame jumps.
    for f in 1..40 {
        let (a, _) = ankle(&m, f, &b);
        let (p, _) = ankle(&m, f - 1, &b);
        assert!((a[0] - p[0]).abs() < 2.5, "frame {f}");
    }
    // A skeleton without feet is left as it is.
    let none = Bvh::parse(&LEG_BVH.replace("lFoot", "lAnkle")).unwrap();
    let mut m2 = before.clone();
    let s = deeprep::motion::feet::lock_feet(&mut m2, &none, &keys, &cfg);
    assert_eq!(s.legs, 0);
    assert_eq!(m2.rotations, before.rotations);
}

mod clips;
mod cond;
mod fill;
mod fill_mlp;
mod keys;
mod pipeline;
mod retargeted;
