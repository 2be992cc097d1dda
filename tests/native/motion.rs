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

mod common;
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
        m.default_for_whole_pose_keys
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
fn the_model_pipeline_hits_keys_exactly_after_post_processing() {
    let Some(m) = models() else { return };
    let j = m.joints();
    // Keys: three poses of the model's own rest skeleton, turned and moved.
    let mut keys = Vec::new();
    for (i, f) in [0usize, 90, 200].iter().enumerate() {
        let mut b: Bvh = m.template.clone();
        let mut ch = vec![0.0f32; b.channel_count()];
        ch[0] = 40.0 * i as f32;
        ch[1] = 85.0;
        ch[3] = 30.0 * i as f32; // Zrotation of the root
        b.motion = ch;
        keys.push(Keyframe::from_bvh(&b, 0, *f).unwrap());
    }
    let req = Request {
        keys: keys.clone(),
        frames: 230,
        dna: None,
        post_process: true,
        foot_lock: Some(FootLock::default()),
        variation: None,
    };
    let out = m.synthesize(&req, &|| 0.0).unwrap();
    assert_eq!(out.motion.len(), 230);
    assert_eq!(out.motion.rotations[0].len(), j);
    assert!(out.key_error.root < 1e-6, "{:?}", out.key_error);
    assert!(out.key_error.local < 1e-3, "{:?}", out.key_error);
    for k in &keys {
        for (a, b) in out.motion.rotations[k.frame]
            .iter()
            .zip(k.rotations.as_ref().unwrap())
        {
            let r: &Mat3<f64> = a;
            assert!(geodesic_distance(r, b) < 1e-6);
        }
    }
    // Every frame is finite and writes as BVH with the requested frame count.
    let bvh = out.motion.to_bvh(&m.template, 1.0 / 60.0).unwrap();
    assert_eq!(Bvh::parse(&bvh.write()).unwrap().frame_count(), 230);
    assert!(bvh.motion.iter().all(|v| v.is_finite()));
    // Bad requests.
    let far = Request {
        keys: vec![
            keys[0].clone(),
            Keyframe {
                frame: 700,
                ..keys[1].clone()
            },
        ],
        frames: 800,
        dna: None,
        post_process: true,
        foot_lock: Some(FootLock::default()),
        variation: None,
    };
    // a 700-frame gap runs hierarchically (Sec. 5.4.3): critical keys
    // inside it, every key exact after post-processing
    let out = m.synthesize(&far, &|| 0.0).unwrap();
    assert_eq!(out.motion.len(), 800);
    assert!(
        !out.critical_frames.is_empty() && out.critical_frames.iter().all(|&f| f > 0 && f < 700)
    );
    assert!(
        out.key_error.root < 1e-6 && out.key_error.local < 1e-3,
        "{:?}",
        out.key_error
    );
    // beyond 3,000 frames: an error that names both limits
    let too_far = Request {
        keys: vec![
            keys[0].clone(),
            Keyframe {
                frame: 3100,
                ..keys[1].clone()
            },
        ],
        frames: 3200,
        ..far.clone()
    };
    let e = m.synthesize(&too_far, &|| 0.0).unwrap_err().to_string();
    assert!(e.contains("600 frames") && e.contains("3000"), "{e}");
    let zero = Request {
        frames: 0,
        ..req.clone()
    };
    assert!(m.synthesize(&zero, &|| 0.0).is_err());
    for v in [f32::NAN, -0.1, 2.5] {
        let bad = Request {
            variation: Some(v),
            ..req.clone()
        };
        let e = m.synthesize(&bad, &|| 0.0).unwrap_err().to_string();
        assert!(e.contains("variation"), "{v}: {e}");
    }
    // Variation 0 is SLERP+LERP: before any post-processing the pose is
    // SLERP between the keys' rotations and the root path the keys' root
    // positions interpolated linearly; both differ from the networks'
    // output, and a half variation lies between them.
    let raw = |variation: f32| {
        m.synthesize(
            &Request {
                variation: Some(variation),
                post_process: false,
                ..req.clone()
            },
            &|| 0.0,
        )
        .unwrap()
    };
    let (base, full, half) = (raw(0.0), raw(1.0), raw(0.5));
    let plain = slerp_lerp(&keys, 230).unwrap();
    for t in 0..230 {
        for jj in 0..j {
            let (b, p) = (&base.motion.rotations[t][jj], &plain.rotations[t][jj]);
            assert!(geodesic_distance(b, p) < 1e-6, "frame {t} joint {jj}");
            let (h, f) = (&half.motion.rotations[t][jj], &full.motion.rotations[t][jj]);
            let (to_plain, to_full) = (geodesic_distance(h, p), geodesic_distance(h, f));
            assert!(
                (to_plain - to_full).abs() < 1e-6,
                "frame {t} joint {jj}: half way"
            );
        }
    }
    let moved = base
        .motion
        .rotations
        .iter()
        .zip(&full.motion.rotations)
        .flat_map(|(a, b)| a.iter().zip(b))
        .map(|(a, b)| geodesic_distance(a, b))
        .fold(0.0f64, f64::max);
    assert!(
        moved > 1e-2,
        "the correction changes the motion ({moved} rad)"
    );
    let (mut lerp_err, mut path_moved) = (0.0f64, 0.0f64);
    for t in 0..=200 {
        let (a, b) = if t <= 90 { (0, 1) } else { (1, 2) };
        let s = (t - keys[a].frame) as f64 / (keys[b].frame - keys[a].frame) as f64;
        for c in 0..3 {
            let want = keys[a].positions[c] as f64 * (1.0 - s) + keys[b].positions[c] as f64 * s;
            lerp_err = lerp_err.max((base.motion.root[t][c] - want).abs());
            path_moved = path_moved.max((full.motion.root[t][c] - want).abs());
        }
    }
    assert!(
        lerp_err < 1e-4,
        "variation 0 root path off the lerp by {lerp_err}"
    );
    assert!(path_moved > 1e-2, "the learned root path is not the lerp");
    // Without a variation the request takes the model's default.
    let dflt = raw(m.default_variation);
    let none = m
        .synthesize(
            &Request {
                variation: None,
                post_process: false,
                ..req.clone()
            },
            &|| 0.0,
        )
        .unwrap();
    assert_eq!(dflt.motion.root, none.motion.root);
    let bad_dna = Request {
        dna: Some(vec![vec![0.0; 5]]),
        ..req
    };
    assert!(m
        .synthesize(&bad_dna, &|| 0.0)
        .unwrap_err()
        .to_string()
        .contains("Motion DNA"));
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

#[test]
fn the_cli_takes_motion_dna_and_variation() {
    let Some(m) = models() else { return };
    let tmp = std::env::temp_dir().join(format!("deeprep_cli_dna_{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    // One DNA pose, the example's first key, as a BVH on the model's skeleton
    // (by default all of the example's whole-pose keys serve as DNA).
    let keys: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("models/examples/keys.json")).unwrap(),
    )
    .unwrap();
    let mut dna = m.template.clone();
    dna.motion = keys["keys"].as_array().unwrap().first().unwrap()["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap() as f32)
        .collect();
    let dna_path = tmp.join("dna.bvh");
    std::fs::write(&dna_path, dna.write()).unwrap();
    let run = |extra: &[&str], out: &str| {
        let out = tmp.join(out);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
            .args([
                "inbetween",
                root().join("models/examples/keys.json").to_str().unwrap(),
            ])
            .args(["--models", root().join("models/onnx").to_str().unwrap()])
            .args(["--frames", "320", "-o", out.to_str().unwrap()])
            .args(extra)
            .output()
            .unwrap();
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stderr).to_string(),
            out,
        )
    };
    let (ok, err, plain) = run(&[], "plain.bvh");
    assert!(ok, "{err}");
    let (ok, err, with_dna) = run(&["--dna", dna_path.to_str().unwrap()], "dna.bvh");
    assert!(ok, "{err}");
    let a = Bvh::parse(&std::fs::read_to_string(&plain).unwrap()).unwrap();
    let b = Bvh::parse(&std::fs::read_to_string(&with_dna).unwrap()).unwrap();
    assert_eq!(b.frame_count(), 320);
    assert!(b.motion.iter().all(|v| v.is_finite()));
    let moved = a
        .motion
        .iter()
        .zip(&b.motion)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0f32, f32::max);
    assert!(
        moved > 1e-3,
        "the DNA changes the motion (max channel change {moved})"
    );
    let (ok, err, _) = run(&["--dna", "no/such.bvh"], "bad.bvh");
    assert!(!ok && err.contains("no/such.bvh"), "{err}");
    let (ok, err, _) = run(&["--dna", "3,4"], "bad.bvh");
    assert!(!ok && err.contains("--from-bvh"), "{err}");
    let (ok, err, _) = run(&["--variation", "5"], "bad.bvh");
    assert!(!ok && err.contains("variation"), "{err}");

    // --seed: DNA drawn from a longer clip (the example's keys joined by
    // linear channel ramps, 400 frames each), repeatable per seed
    let ks: Vec<Vec<f32>> = keys["keys"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| {
            k["channels"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap() as f32)
                .collect()
        })
        .collect();
    let mut clip = m.template.clone();
    clip.motion = ks
        .windows(2)
        .flat_map(|w| {
            (0..400).flat_map(move |t| {
                let s = t as f32 / 400.0;
                w[0].iter()
                    .zip(&w[1])
                    .map(move |(a, b)| a + (b - a) * s)
                    .collect::<Vec<_>>()
            })
        })
        .collect();
    let clip_path = tmp.join("dna_clip.bvh");
    std::fs::write(&clip_path, clip.write()).unwrap();
    let clip_arg = clip_path.to_str().unwrap();
    let seeded: Vec<Vec<f32>> = [1, 1, 2, 3, 4]
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let name = format!("seed{i}.bvh");
            let (ok, err, out) = run(&["--dna", clip_arg, "--seed", &s.to_string()], &name);
            assert!(ok, "{err}");
            Bvh::parse(&std::fs::read_to_string(out).unwrap())
                .unwrap()
                .motion
        })
        .collect();
    assert_eq!(seeded[0], seeded[1], "equal seeds give equal motion");
    assert!(
        seeded[2..].iter().any(|m| *m != seeded[0]),
        "other seeds draw other DNA"
    );
    let (ok, err, _) = run(&["--seed", "1"], "bad.bvh");
    assert!(!ok && err.contains("--dna"), "{err}");
    let (ok, err, _) = run(&["--dna", clip_arg, "--seed", "x"], "bad.bvh");
    assert!(!ok && err.contains("--seed"), "{err}");
    std::fs::remove_dir_all(&tmp).ok();
}

/// Keys from a clip at another frame rate (JS synthesizeFromBvh): the clip
/// is brought to 60 fps, the span between the keys replaced, and the result
/// returned at the clip's rate and length with the keys' own values; the
/// CLI's form (no resampling) takes the frames as they are.
#[test]
fn clip_keys_resample_and_splice_back() {
    use deeprep::motion::clip::{clip_keys, splice};
    let clip = deeprep::skeleton::Bvh::parse(&clip_fixture(121, 1.0 / 120.0)).unwrap();
    let ck = clip_keys(&clip, &[0, 40, 120], true).unwrap();
    assert_eq!((ck.first, ck.last, ck.frames()), (0, 60, 61));
    assert_eq!(
        ck.keys.iter().map(|k| k.frame).collect::<Vec<_>>(),
        vec![0, 20, 60]
    );
    let m = slerp_lerp(&ck.keys, ck.frames()).unwrap();
    let out = splice(&clip, &ck, &m).unwrap();
    assert_eq!(out.frame_count(), clip.frame_count());
    assert_eq!(out.frame_time, clip.frame_time);
    let c = clip.channel_count();
    for f in [0, 40, 120] {
        assert_eq!(out.frame(f), clip.frame(f), "key frame {f}");
    }
    assert!(
        (1..40).any(|f| out.frame(f) != clip.frame(f)),
        "the span is synthesized"
    );
    let same = clip_keys(&clip, &[0, 40, 120], false).unwrap();
    assert_eq!((same.first, same.last), (0, 120));
    assert_eq!(
        splice(&clip, &same, &slerp_lerp(&same.keys, 121).unwrap())
            .unwrap()
            .motion
            .len(),
        121 * c
    );
    for bad in [&[][..], &[5, 5], &[10, 3], &[0, 500]] {
        assert!(clip_keys(&clip, bad, true).is_err(), "{bad:?}");
    }
    assert!(
        clip_keys(&clip, &[0, 1, 2], true).is_err(),
        "1 and 2 fall on one frame at 60 fps"
    );
}

/// A three-joint clip with smooth motion: root moving along x, the joints
/// turning at different speeds.
fn clip_fixture(frames: usize, frame_time: f64) -> String {
    let mut s = String::from("HIERARCHY\nROOT hip\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n  JOINT a\n  {\n    OFFSET 0 10 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {\n      OFFSET 0 5 0\n    }\n  }\n}\nMOTION\n");
    s.push_str(&format!("Frames: {frames}\nFrame Time: {frame_time}\n"));
    for f in 0..frames {
        let t = f as f32 * frame_time as f32;
        let v = [
            100.0 * t,
            90.0,
            0.0,
            20.0 * t,
            5.0,
            40.0 * t,
            60.0 * t,
            -30.0 * t,
            10.0,
        ];
        let row: Vec<String> = v.iter().map(|x| x.to_string()).collect();
        s.push_str(&row.join(" "));
        s.push('\n');
    }
    s
}

#[test]
fn the_plan_for_any_length_gives_each_length_s_own_result() {
    // What a page's worker does after loading (Inbetweener.prepareAnyLength):
    // one plan for every length instead of one per length.
    let (Some(own), Some(any)) = (models(), models()) else {
        return;
    };
    assert!(any.prepare_any_length().unwrap());
    assert!(!any.prepare_any_length().unwrap(), "prepared twice");
    let mut rng = Rng::new(17);
    for (frames, gap) in [(91usize, 60usize), (250, 120), (700, 300)] {
        let keys: Vec<Keyframe> = [0, gap, frames - 1]
            .iter()
            .map(|&f| rot_key(f, &mut rng, own.joints()))
            .collect();
        let req = Request {
            keys,
            frames,
            dna: None,
            post_process: true,
            foot_lock: None,
            variation: Some(1.0),
        };
        let a = own.synthesize(&req, &|| 0.0).unwrap().motion;
        let b = any.synthesize(&req, &|| 0.0).unwrap().motion;
        let mut worst = 0.0f64;
        for t in 0..frames {
            for k in 0..3 {
                worst = worst.max((a.root[t][k] - b.root[t][k]).abs());
            }
            for (x, y) in a.rotations[t].iter().zip(&b.rotations[t]) {
                for (p, q) in x.as_slice().iter().zip(y.as_slice()) {
                    for (u, v) in p.iter().zip(q) {
                        worst = worst.max((u - v).abs());
                    }
                }
            }
        }
        assert!(
            worst < 1e-3,
            "{frames} frames: the any-length plan differs by {worst}"
        );
    }
}

#[test]
fn joint_range_editing_reads_sets_and_clamps_one_joint() {
    use deeprep::motion::edit::{joint_angles, set_joint_angles};
    let Some(m) = models() else { return };
    let (rc, tpl) = (&m.rc, &m.template);
    let mut row = vec![0.0f32; tpl.channel_count()];
    row[1] = 90.0;
    // the channel ranges of each joint in the row
    let mut at = 0;
    let spans: Vec<std::ops::Range<usize>> = tpl
        .joints
        .iter()
        .map(|j| {
            at += j.channels.len();
            at - j.channels.len()..at
        })
        .collect();
    let joint = tpl.joints.iter().position(|j| j.name == "lShldr").unwrap();
    let a = joint_angles(rc, tpl, &row, joint).unwrap();
    for (v, [lo, hi]) in a.angles.iter().zip(a.ranges) {
        assert!(lo < hi && (lo - 1e-6..=hi + 1e-6).contains(v), "{a:?}");
    }
    // inside the ranges: read back as set, the other joints untouched
    let want: [f64; 3] = std::array::from_fn(|i| {
        let [lo, hi] = a.ranges[i];
        lo + (hi - lo) * (0.3 + 0.2 * i as f64)
    });
    let set = set_joint_angles(rc, tpl, &row, joint, want).unwrap();
    let got = joint_angles(rc, tpl, &set, joint).unwrap();
    for i in 0..3 {
        assert!(
            (got.angles[i] - want[i]).abs() < 1e-3,
            "{got:?} vs {want:?}"
        );
    }
    for (j, span) in spans.iter().enumerate().filter(|(j, _)| *j != joint) {
        for c in span.clone() {
            assert!(
                (set[c] - row[c]).abs() < 1e-3,
                "joint {j} channel {c} moved"
            );
        }
    }
    assert!(spans[joint].clone().any(|c| (set[c] - row[c]).abs() > 1.0));
    // outside: clamped to the ranges
    let far = set_joint_angles(rc, tpl, &row, joint, [1e3, -1e3, 1e3]).unwrap();
    let got = joint_angles(rc, tpl, &far, joint).unwrap();
    let bound = [a.ranges[0][1], a.ranges[1][0], a.ranges[2][1]];
    for i in 0..3 {
        assert!(
            (got.angles[i] - bound[i]).abs() < 1e-3,
            "{got:?} vs {bound:?}"
        );
    }
    // errors, not panics
    let e = joint_angles(rc, tpl, &row, 0).unwrap_err().to_string();
    assert!(e.contains("not rotated by RC-FK"), "{e}");
    assert!(joint_angles(rc, tpl, &row[1..], joint).is_err());
    let mut nan = row.clone();
    nan[5] = f32::NAN;
    assert!(joint_angles(rc, tpl, &nan, joint).is_err());
    assert!(set_joint_angles(rc, tpl, &row, joint, [0.0, f64::NAN, 0.0]).is_err());
    assert!(set_joint_angles(rc, tpl, &row, tpl.joints.len() + 5, [0.0; 3]).is_err());
}

#[test]
fn keys_files_take_root_only_and_2d_keys() {
    use deeprep::motion::keys::{from_json, KeyKind};
    let Some(m) = models() else { return };
    let tpl = &m.template;
    let j = tpl.joints.len();
    // a whole pose, a root-only key and a 2-D key (joint 0's x and y stand
    // for the root's, joint 5 given, the rest unknown)
    let mut row = vec![0.0f32; tpl.channel_count()];
    row[1] = 56.0;
    let mut xy = vec![serde_json::Value::Null; j];
    xy[0] = serde_json::json!([30.0, 55.0]);
    xy[5] = serde_json::json!([31.0, 110.0]);
    let text = serde_json::json!({"frames": 200, "keys": [
        {"frame": 0, "channels": row},
        {"frame": 90, "root": [20.0, 56.0, 60.0]},
        {"frame": 199, "xy": xy, "root": null},
    ]})
    .to_string();
    let f = from_json(&text, tpl).unwrap();
    assert!(f.keys[0].is_whole_pose() && f.keys[0].rotations.is_some());
    let r = &f.keys[1];
    assert_eq!(&r.positions[..3], &[20.0, 56.0, 60.0]);
    assert_eq!(r.mask.iter().filter(|m| **m).count(), 3);
    assert!(r.rotations.is_none());
    let x = &f.keys[2];
    assert_eq!((x.mask[0], x.mask[1], x.mask[2]), (true, true, false));
    assert_eq!(
        (x.positions[15], x.positions[16]),
        (1.0, 55.0),
        "joint 5 relative to the root"
    );
    assert_eq!(x.mask.iter().filter(|m| **m).count(), 4);
    // the in-betweening runs on mixed keys; post-processing puts the root
    // exactly on every coordinate the keys give
    let req = Request {
        keys: f.keys.clone(),
        frames: 200,
        dna: None,
        post_process: true,
        foot_lock: None,
        variation: None,
    };
    let out = m.synthesize(&req, &|| 0.0).unwrap().motion;
    for k in &f.keys {
        for c in (0..3).filter(|&c| k.mask[c]) {
            let d = (out.root[k.frame][c] - k.positions[c] as f64).abs();
            assert!(d < 1e-4, "key at {} coordinate {c}: off by {d}", k.frame);
        }
    }
    // from a whole pose: the root alone, or every joint's global x and y
    let whole = &f.keys[0];
    let root = KeyKind::Root.of(whole).unwrap();
    assert_eq!(&root.positions[..3], &whole.positions[..3]);
    let front = KeyKind::Xy.of(whole).unwrap();
    for jj in 1..j {
        for c in 0..2 {
            assert!((front.positions[3 * jj + c] - whole.positions[3 * jj + c]).abs() < 1e-4);
        }
        assert!(!front.mask[3 * jj + 2], "depth stays unknown");
    }
    assert!(KeyKind::parse("depth").is_err());
    // bad keys name the key
    for (bad, says) in [
        (
            serde_json::json!({"frame": 3, "root": [0.0, 1.0]}),
            "key 0: \"root\"",
        ),
        (
            serde_json::json!({"frame": 3, "xy": [[0.0, 1.0]]}),
            "key 0: \"xy\" must list",
        ),
        (serde_json::json!({"frame": 3}), "key 0 has none of"),
    ] {
        let e = from_json(&serde_json::json!({"keys": [bad]}).to_string(), tpl)
            .unwrap_err()
            .to_string();
        assert!(e.contains(says), "{e}");
    }
}

#[test]
fn requests_as_json_carry_method_options_and_dna() {
    use deeprep::motion::keys::request_from_json;
    let Some(m) = models() else { return };
    let tpl = &m.template;
    let row = vec![0.0f32; tpl.channel_count()];
    let doc = request_from_json(
        &serde_json::json!({"frames": 90, "keys": [{"frame": 0, "root": [0.0, 56.0, 0.0]}],
                            "method": "slerp", "post": false, "footLock": true, "variation": 0.5,
                            "dna": [row.clone(), row.clone()]})
        .to_string(),
        tpl,
    )
    .unwrap();
    assert_eq!(doc.file.frames, Some(90));
    assert_eq!(doc.method, "slerp");
    assert!(!doc.post && doc.foot_lock);
    assert_eq!(doc.variation, Some(0.5));
    assert_eq!(doc.dna.as_ref().map(|d| d.len()), Some(2));
    assert_eq!(doc.dna.unwrap()[0].len(), 3 * tpl.joints.len());
    // defaults
    let doc = request_from_json(r#"{"keys": [{"frame": 0, "root": [0, 56, 0]}]}"#, tpl).unwrap();
    assert!(
        doc.method == "model"
            && doc.post
            && !doc.foot_lock
            && doc.variation.is_none()
            && doc.dna.is_none()
    );
    for (bad, says) in [
        (r#"{"keys": [], "method": "fast"}"#, "\"method\""),
        (r#"{"keys": [], "post": 1}"#, "\"post\""),
        (r#"{"keys": [], "variation": "x"}"#, "\"variation\""),
        (r#"{"keys": [], "dna": [[1, 2]]}"#, "\"dna\" pose 0"),
    ] {
        let e = request_from_json(bad, tpl).unwrap_err().to_string();
        assert!(e.contains(says), "{bad}: {e}");
    }
}

#[test]
fn two_d_keys_are_met_in_x_and_y_after_post_processing() {
    use deeprep::motion::keys::{from_json, KeyKind};
    let Some(m) = models() else { return };
    // the example's keys: whole poses at their frames, the middle one given
    // as a 2-D key (every joint's x and y, the root)
    let text = std::fs::read_to_string(root().join("models/examples/keys.json")).unwrap();
    let mut keys = from_json(&text, &m.template).unwrap().keys;
    assert!(keys.len() >= 3);
    let mid = keys.len() / 2;
    keys[mid] = KeyKind::Xy.of(&keys[mid]).unwrap();
    assert!(deeprep::motion::xy::is_xy_key(&keys[mid]));
    let frames = keys.last().unwrap().frame + 1;
    let req = Request {
        keys: keys.clone(),
        frames,
        dna: None,
        post_process: true,
        foot_lock: None,
        variation: None,
    };
    let out = m.synthesize(&req, &|| 0.0).unwrap();
    // the mean error over the keys' given coordinates: the whole poses are
    // exact, the 2-D key's x and y are met to well under a unit (a
    // centimetre) where the networks alone miss by several
    assert!(out.key_error.local < 0.1, "after post: {:?}", out.key_error);
    assert!(
        out.key_error_raw.local > 10.0 * out.key_error.local,
        "before {:?}, after {:?}",
        out.key_error_raw,
        out.key_error
    );
    // and the depth is the networks' (not the truth's): the 2-D key fixes
    // x and y only, so z differs from the original pose somewhere
    let k = &keys[mid];
    let pos = out
        .motion
        .local_positions(k.frame, &m.rc.parents, &m.rc.offsets);
    let (worst, xy_err) = (1..pos.len())
        .map(|j| {
            let e = (pos[j][0] - k.positions[3 * j] as f64)
                .hypot(pos[j][1] - k.positions[3 * j + 1] as f64);
            (j, e)
        })
        .fold((0, 0.0f64), |a, b| if b.1 > a.1 { b } else { a });
    assert!(
        xy_err < 1.0,
        "largest joint x/y error {xy_err} at {}",
        m.rc.names[worst]
    );
    // without post-processing the key is not pinned
    let raw = m
        .synthesize(
            &Request {
                post_process: false,
                ..req
            },
            &|| 0.0,
        )
        .unwrap();
    assert_eq!(raw.key_error.local, raw.key_error_raw.local);
}

/// A clip whose joints turn at a speed with three bumps (frames 60.3, 150.3
/// and 210.3, of decreasing height): its representative frames are the bumps.
fn dna_fixture_clip() -> String {
    let mut s = String::from(
        "HIERARCHY\nROOT hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n  JOINT spine\n  {\n    OFFSET 0 10 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    JOINT head\n    {\n      OFFSET 0 5 1\n      CHANNELS 3 Xrotation Yrotation Zrotation\n      End Site\n      {\n        OFFSET 0 3 0\n      }\n    }\n  }\n}\nMOTION\nFrames: 240\nFrame Time: 0.0166667\n",
    );
    let speed = |t: f64| {
        let bump = |c: f64, h: f64| h * (-((t - c) / 6.0).powi(2)).exp();
        0.5 + bump(60.3, 4.0) + bump(150.3, 3.0) + bump(210.3, 2.0)
    };
    let mut angle = 0.0;
    for f in 0..240 {
        angle += speed(f as f64);
        let (a, b) = (angle, 0.5 * angle);
        // root (position and turn, not measured), spine, head
        #[rustfmt::skip]
        let row = [
            0.5 * f as f64, 90.0, 0.0, 10.0, 0.3 * f as f64, 0.0,
            a * 0.25, b * 0.1, 5.0,
            -a * 0.125, 3.0, b * 0.05,
        ];
        let row: Vec<String> = row.iter().map(|v| format!("{v:.4}")).collect();
        s.push_str(&row.join(" "));
        s.push('\n');
    }
    s
}

/// The representative-frame fixture the training code checks its own pick
/// against (tests/parity/test_dna.py): one implementation of Sec. 5.2.5's
/// DNA frames, in Rust and in `train/deeprep_train/motion/dna.py`.
/// `DEEPREP_WRITE_FIXTURES=1` rewrites it; otherwise this checks it.
#[test]
fn dna_fixture_shared_with_the_training_code() {
    use deeprep::motion::dna::representative_frames;
    let path = root().join("tests/fixtures/dna_native.json");
    let text = dna_fixture_clip();
    let clip = Bvh::parse(&text).unwrap();
    let poses: Vec<Keyframe> = (0..clip.frame_count())
        .map(|f| Keyframe::from_bvh(&clip, f, f).unwrap())
        .collect();
    let picks: Vec<Vec<usize>> = (1..=3)
        .map(|count| representative_frames(&poses, count).unwrap())
        .collect();
    assert_eq!(picks[2], [60, 150, 210], "the three bumps");
    if std::env::var("DEEPREP_WRITE_FIXTURES").is_ok() {
        let doc = serde_json::json!({
            "what": "motion::dna::representative_frames of `bvh` for count = 1..3 (beyond 3 the picks are on the flat part, near-ties) (tests/native/motion.rs)",
            "bvh": text, "min_spacing": deeprep::motion::dna::MIN_SPACING, "picks": picks,
        });
        std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    }
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(doc["bvh"].as_str().unwrap(), text, "the fixture's clip");
    let want: Vec<Vec<usize>> = serde_json::from_value(doc["picks"].clone()).unwrap();
    assert_eq!(picks, want);
}

/// `Motion::poses` are what the motion's BVH reads back as: its FK and local
/// tracks match the BVH's (the wasm result builds positions from it without
/// the Euler round trip).
#[test]
fn a_motions_pose_is_its_bvh_row() {
    use deeprep::skeleton::fk;
    let m: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("models/onnx/tween_generator.manifest.json")).unwrap(),
    )
    .unwrap();
    let tpl = Bvh::parse(m["skeleton_bvh"].as_str().unwrap()).unwrap();
    let mut rng = Rng::new(7);
    let n = 5;
    let motion = Motion {
        root: (0..n)
            .map(|f| [f as f64, 90.0 + rng.uniform(), -(f as f64)])
            .collect(),
        rotations: (0..n)
            .map(|_| {
                (0..tpl.joints.len())
                    .map(|_| {
                        let r: Mat3<f32> = uniform_so3(&mut rng);
                        r.map(|row| row.map(|v| v as f64))
                    })
                    .collect()
            })
            .collect(),
    };
    let bvh = motion.to_bvh(&tpl, 1.0 / 60.0).unwrap();
    let want = fk::positions(&bvh, 0, n).unwrap();
    let tracks = fk::local_tracks(&bvh);
    let mut got = Vec::new();
    let mut got_tracks = fk::LocalTracks::with_capacity(n, tpl.joints.len());
    for p in motion.poses(&tpl).unwrap() {
        got.extend(
            p.global(&tpl)
                .positions
                .iter()
                .flat_map(|v| [v.x as f32, v.y as f32, v.z as f32]),
        );
        got_tracks.push(&p);
    }
    let max = |a: &[f32], b: &[f32]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f32, f32::max)
    };
    assert!(max(&got, &want) < 1e-3, "positions {}", max(&got, &want));
    assert!(max(&got_tracks.translations, &tracks.translations) < 1e-4);
    // quaternions up to sign
    for (a, b) in got_tracks
        .quaternions
        .chunks(4)
        .zip(tracks.quaternions.chunks(4))
    {
        let dot: f32 = a.iter().zip(b).map(|(x, y)| x * y).sum();
        assert!(dot.abs() > 1.0 - 1e-5, "{a:?} vs {b:?}");
    }
}

/// Issue 52: which pipeline runs, and at which variation, is decided once
/// (`motion::plan`). The CLI's `--from-bvh` reports what it planned, and it
/// is what the planner gives for the bundled manifests: whole-pose keys the
/// residual network at its default, root-only and 2-D keys the generator at
/// the generator's own default (not the residual network's), an explicit
/// variation kept. The page and the npm client ask the same planner through
/// the wasm `Inbetweener` (tests/web/sketch.test.mjs, tests/npm/app).
#[test]
fn the_cli_runs_what_the_planner_plans() {
    use deeprep::motion::plan::{Loaded, Pipeline};
    let Some(m) = models() else { return };
    let dir = root().join("models/onnx");
    let read = |n: &str| std::fs::read_to_string(dir.join(n)).unwrap();
    let loaded = Loaded {
        generator: Some(
            deeprep::motion::manifest::parse(&read("tween_generator.manifest.json"))
                .unwrap()
                .variation,
        ),
        residual: Some(
            deeprep::motion::residual::info_of_manifest(&read("tween_residual.manifest.json"))
                .unwrap(),
        ),
    };
    let tmp = std::env::temp_dir().join(format!("deeprep_cli_plan_{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let mut clip = m.template.clone();
    let c = clip.channel_count();
    clip.motion = (0..200 * c)
        .map(|i| match i % c {
            0 => (i / c) as f32 * 0.5,
            1 => 90.0,
            k if k > 5 => ((i / c) as f32 / 20.0 + k as f32).sin() * 10.0,
            _ => 0.0,
        })
        .collect();
    let clip_path = tmp.join("clip.bvh");
    std::fs::write(&clip_path, clip.write()).unwrap();
    let keys = [0usize, 60, 120];
    for (kind, variation) in [
        ("pose", None),
        ("root", None),
        ("xy", None),
        ("root", Some("0.7")),
    ] {
        let out = tmp.join("out.bvh");
        let mut args = vec![
            "inbetween",
            "--from-bvh",
            clip_path.to_str().unwrap(),
            "--keys",
            "0,60,120",
            "--key-kind",
            kind,
            "--models",
            dir.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        if let Some(v) = variation {
            args.extend(["--variation", v]);
        }
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{kind}: {err}");
        // what the planner gives for the same keys
        let ck = deeprep::motion::clip::clip_keys(&clip, &keys, false).unwrap();
        let kk = deeprep::motion::keys::KeyKind::parse(kind).unwrap();
        let ks: Vec<_> = ck.keys.iter().map(|k| kk.of(k).unwrap()).collect();
        let ask = deeprep::motion::plan::Ask {
            method: "model",
            keys: &ks,
            dna: false,
            post_process: true,
            variation: variation.map(|v| v.parse().unwrap()),
        };
        let p = deeprep::motion::plan::plan(&ask, &loaded).unwrap();
        let want_pipeline =
            if kind == "pose" && loaded.residual.unwrap().default_for_whole_pose_keys {
                Pipeline::Residual
            } else {
                Pipeline::Generator
            };
        assert_eq!(p.pipeline, want_pipeline, "{kind}");
        if variation.is_none() {
            let own = match p.pipeline {
                Pipeline::Residual => loaded.residual.unwrap().variation,
                _ => loaded.generator.unwrap(),
            };
            assert_eq!(p.variation, own, "{kind}");
        }
        let said = format!(
            "pipeline {} at variation {:.2}",
            p.pipeline.name(),
            p.variation
        );
        assert!(err.contains(&said), "{kind}: expected '{said}' in {err}");
    }
    std::fs::remove_dir_all(&tmp).ok();
}
