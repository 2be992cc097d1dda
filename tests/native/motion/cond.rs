//! The conditional network (issue 47): tract against onnxruntime, and the
//! whole request (features, network, output) against the Python training
//! code's on the keys of `models/onnx/fixtures/runtime/tween_cond_motion.json` (not a network fixture: tests/parity reads only the top folder).

use crate::common::{self, doubles, root};
use deeprep::motion::cond::{classify, CondModel, KeyClass};
use deeprep::motion::Keyframe;
use deeprep::rotation::Mat3;

fn model() -> Option<CondModel> {
    let dir = root().join("models/onnx");
    if !dir.join("tween_cond.onnx").exists() {
        eprintln!("SKIP: models/onnx/tween_cond.onnx is not exported yet");
        return None;
    }
    Some(CondModel::load_dir(&dir).unwrap())
}

fn sixd(m: &Mat3<f64>) -> [f64; 6] {
    [m[0][0], m[1][0], m[2][0], m[0][1], m[1][1], m[2][1]]
}

/// A fixture key as the CLI's `--key-kind` makes it from a clip's frame.
fn key(m: &CondModel, k: &serde_json::Value) -> Keyframe {
    let joints = m.template.joints.len();
    let frame = k["frame"].as_u64().unwrap() as usize;
    let r = doubles(&k["root"]);
    let mut positions: Vec<f32> = doubles(&k["positions"]).iter().map(|&v| v as f32).collect();
    positions[..3].copy_from_slice(&[r[0] as f32, r[1] as f32, r[2] as f32]);
    let rotating: Vec<usize> = (0..joints)
        .filter(|&j| !m.template.joints[j].channels.is_empty())
        .collect();
    let eye: Mat3<f64> = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut rotations = vec![eye; joints];
    for (s, row) in k["rotations"].as_array().unwrap().iter().enumerate() {
        let v = doubles(row);
        rotations[rotating[s]] = std::array::from_fn(|a| std::array::from_fn(|b| v[3 * a + b]));
    }
    let whole = Keyframe {
        frame,
        mask: vec![true; positions.len()],
        positions,
        rotations: Some(rotations),
    };
    let kind = deeprep::motion::keys::KeyKind::parse(k["kind"].as_str().unwrap()).unwrap();
    kind.of(&whole).unwrap()
}

#[test]
fn tract_matches_onnxruntime_on_the_conditional_network() {
    if model().is_none() {
        return;
    }
    // float32 noise through a dilated network whose outputs reach about 150
    // (tract 1.5e-4 from onnxruntime for the network bundled 2026-12-07)
    common::fixture_parity("tween_cond", 2e-4);
}

/// The bundled DNA network (`tween_cond_dna`, for requests with Motion DNA):
/// tract against onnxruntime on its fixture, and its manifest takes DNA.
#[test]
fn tract_matches_onnxruntime_on_the_dna_network() {
    let dir = root().join("models/onnx");
    if !dir.join("tween_cond_dna.onnx").exists() {
        eprintln!("SKIP: models/onnx/tween_cond_dna.onnx is not bundled");
        return;
    }
    assert!(
        CondModel::load_named(&dir, "tween_cond_dna")
            .unwrap()
            .info()
            .dna
    );
    common::fixture_parity("tween_cond_dna", 2e-4);
}

/// Every case of the fixture: the same motion as cond.py's features and
/// apply with the same network, within float32 noise through a network
/// (6D and root in units of the output's size); the last case is a coarse
/// pass (frames 3 apart, `synthesize_at_rate`: the phase in 60 fps frames).
#[test]
fn the_conditional_network_reproduces_the_training_code() {
    let Some(m) = model() else { return };
    replay(&m, &common::fixture("runtime/tween_cond_motion"));
}

/// The runtime's Motion DNA path, which the bundled network (no DNA input)
/// does not reach: a small random network with a DNA input
/// (`train/deeprep_train/motion/make_cond_dna_fixture.py`) through a
/// 500-frame request with DNA, the poses spread by
/// `motion::dna::frame_weights` (the manifest's `dna_window`), against
/// cond.py with onnxruntime; and DNA changes the output.
#[test]
fn motion_dna_per_frame_weights_reproduce_the_training_code() {
    let dir = root().join("tests/fixtures/cond_dna");
    let m = CondModel::load_dir(&dir).unwrap();
    assert!(m.info().dna);
    let text =
        std::fs::read_to_string(dir.join("fixtures/runtime/tween_cond_motion.json")).unwrap();
    let f: serde_json::Value = serde_json::from_str(&text).unwrap();
    replay(&m, &f);
    let case = &f["cases"][0];
    let keys = keys_of(&m, case);
    let frames = case["frames"].as_u64().unwrap() as usize;
    let (without, _) = m.synthesize_dna(&keys, frames, 1.0, None, None).unwrap();
    let dna = dna_of(case).unwrap();
    let (with, _) = m
        .synthesize_dna(&keys, frames, 1.0, None, Some(&dna))
        .unwrap();
    let moved = (0..frames)
        .map(|t| {
            (0..3)
                .map(|i| (with.root[t][i] - without.root[t][i]).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    assert!(moved > 1e-3, "DNA moved the root by at most {moved}");
}

/// A fixture case's keys.
fn keys_of(m: &CondModel, case: &serde_json::Value) -> Vec<Keyframe> {
    case["keys"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| key(m, k))
        .collect()
}

/// A fixture case's Motion DNA poses, if it gives any.
fn dna_of(case: &serde_json::Value) -> Option<Vec<Vec<f32>>> {
    let poses = case["dna"].as_array()?;
    Some(
        poses
            .iter()
            .map(|p| doubles(p).iter().map(|&v| v as f32).collect())
            .collect(),
    )
}

/// Every case of a motion fixture through `m` (see the callers).
fn replay(m: &CondModel, f: &serde_json::Value) {
    let joints = m.template.joints.len();
    let rotating: Vec<usize> = (0..joints)
        .filter(|&j| !m.template.joints[j].channels.is_empty())
        .collect();
    for (ci, case) in f["cases"].as_array().unwrap().iter().enumerate() {
        let frames = case["frames"].as_u64().unwrap() as usize;
        let keys = keys_of(m, case);
        // a case with a rate is the hierarchy's coarse pass; one with `dna`
        // gives Motion DNA poses (motion::dna::frame_weights spreads them)
        // and every `every`-th frame
        let rate = case["rate"].as_u64().unwrap_or(1) as usize;
        let every = case["every"].as_u64().unwrap_or(1) as usize;
        let out = match dna_of(case) {
            Some(dna) => {
                let (out, critical) = m
                    .synthesize_dna(&keys, frames, 1.0, None, Some(&dna))
                    .unwrap();
                assert!(critical.is_empty(), "case {ci}: one pass");
                out
            }
            None => m
                .synthesize_at_rate(&keys, frames, 1.0, None, rate)
                .unwrap(),
        };
        let (mut d_root, mut d_rot) = (0.0f64, 0.0f64);
        for (i, t) in (0..frames).step_by(every).enumerate() {
            let want = doubles(&case["root"][i]);
            for (o, w) in out.root[t].iter().zip(&want) {
                d_root = d_root.max((o - w).abs());
            }
            let want = doubles(&case["sixd"][i]);
            for (s, &j) in rotating.iter().enumerate() {
                for (q, v) in sixd(&out.rotations[t][j]).iter().enumerate() {
                    d_rot = d_rot.max((v - want[6 * s + q]).abs());
                }
            }
        }
        assert!(
            d_root < 2e-3 && d_rot < 2e-3,
            "case {ci}: root off by {d_root}, 6D by {d_rot}"
        );
        // keys' root positions are exact; pose keys too
        for k in &keys {
            for (o, p) in out.root[k.frame].iter().zip(&k.positions) {
                assert!((o - *p as f64).abs() < 1e-3);
            }
            if classify(k) == Some(KeyClass::Pose) {
                let r = k.rotations.as_ref().unwrap();
                for &j in &rotating {
                    let a = sixd(&out.rotations[k.frame][j]);
                    let b = sixd(&r[j]);
                    assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6));
                }
            }
        }
    }
}

/// Keys it cannot read are errors that say so, and root-only keys give
/// limbs that move (the residual is not zero between keys).
#[test]
fn the_conditional_network_refuses_odd_keys_and_moves_between_root_keys() {
    let Some(m) = model() else { return };
    let joints = m.template.joints.len();
    let mut odd = Keyframe::root_only(30, [0.0, 90.0, 0.0], joints);
    odd.mask[3] = true;
    let keys = [Keyframe::root_only(0, [0.0, 90.0, 0.0], joints), odd];
    let e = m.synthesize(&keys, 61, 1.0, None).unwrap_err().to_string();
    assert!(e.contains("key 1 (frame 30) gives something else"), "{e}");
    let keys: Vec<Keyframe> = (0..3)
        .map(|i| Keyframe::root_only(60 * i, [0.0, 90.0, 150.0 * i as f32], joints))
        .collect();
    let out = m.synthesize(&keys, 121, 1.0, None).unwrap();
    let still = m.synthesize(&keys, 121, 0.0, None).unwrap();
    let moved = knee_turn(&m, &out, 1..121);
    let held = knee_turn(&m, &still, 1..121);
    assert!(held < 1e-9, "variation 0 holds the prior pose: {held}");
    assert!(
        moved > 0.5,
        "the knee turns {moved} rad in total over 2 s of walking"
    );
}

/// The left knee's total rotation from frame to frame over `frames`
/// (each frame against the one before it), radians.
fn knee_turn(
    m: &CondModel,
    motion: &deeprep::motion::Motion,
    frames: std::ops::Range<usize>,
) -> f64 {
    let knee = rotating_knee(m);
    frames
        .map(|t| {
            deeprep::rotation::geodesic_distance(
                &motion.rotations[t][knee],
                &motion.rotations[t - 1][knee],
            )
        })
        .sum()
}

fn rotating_knee(m: &CondModel) -> usize {
    m.template
        .joints
        .iter()
        .position(|j| j.name == "lShin")
        .unwrap()
}

/// A seed draws the noise input: the same seed gives the same motion,
/// another seed another one, no seed the zero-noise output; root keys stay
/// exact whatever the draw. How far apart the draws are is the training's
/// business (README: the conditional network's seed spread), not pinned here.
#[test]
fn the_conditional_network_takes_a_seed_as_its_noise() {
    let Some(m) = model() else { return };
    let joints = m.template.joints.len();
    let keys: Vec<Keyframe> = (0..3)
        .map(|i| Keyframe::root_only(60 * i, [0.0, 90.0, 150.0 * i as f32], joints))
        .collect();
    let run = |seed| m.synthesize(&keys, 121, 1.0, seed).unwrap();
    let (a, a2, b, none) = (run(Some(1)), run(Some(1)), run(Some(2)), run(None));
    let diff = |x: &deeprep::motion::Motion, y: &deeprep::motion::Motion| {
        (0..121)
            .map(|t| deeprep::rotation::geodesic_distance(&x.rotations[t][1], &y.rotations[t][1]))
            .fold(0.0, f64::max)
    };
    assert_eq!(diff(&a, &a2), 0.0);
    assert!(diff(&a, &b) > 0.0 && diff(&a, &none) > 0.0);
    for k in &keys {
        for (o, p) in b.root[k.frame].iter().zip(&k.positions) {
            assert!((o - *p as f64).abs() < 1e-3);
        }
    }
    // the request form reads "seed" and refuses anything but an integer >= 0
    let doc = |seed: &str| {
        deeprep::motion::keys::request_from_json(
            &format!(
                r#"{{"frames": 61, "keys": [{{"frame": 0, "root": [0, 90, 0]}}], "method": "cond", "seed": {seed}}}"#
            ),
            &m.template,
        )
    };
    assert_eq!(doc("7").unwrap().seed, Some(7));
    for bad in ["-1", "1.5", "\"3\""] {
        let e = doc(bad).unwrap_err().to_string();
        assert!(
            e.contains("\"seed\" must be a non-negative integer"),
            "{bad}: {e}"
        );
    }
}

/// Motion DNA reaches the conditional network only when its manifest says
/// `dna` (issue 47): then DNA poses change the in-between frames and leave
/// the keys exact, and a pose of the wrong size is an error; without it,
/// DNA is an error that points to the generator.
#[test]
fn motion_dna_reaches_the_conditional_network_when_its_manifest_says_so() {
    let Some(m) = model() else { return };
    let joints = m.template.joints.len();
    let keys: Vec<Keyframe> = (0..3)
        .map(|i| Keyframe::root_only(60 * i, [0.0, 90.0, 150.0 * i as f32], joints))
        .collect();
    // a DNA pose: the rest pose's joints relative to the root, one knee raised
    let rest = deeprep::motion::Motion {
        root: vec![[0.0; 3]],
        rotations: vec![vec![
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
            joints
        ]],
    };
    let mut pose: Vec<f32> = rest
        .local_positions(0, &m.parents, &m.offsets)
        .iter()
        .flat_map(|p| p.map(|v| v as f32))
        .collect();
    let knee = rotating_knee(&m);
    pose[3 * knee + 1] += 30.0;
    let dna = vec![pose];
    let got = m.synthesize_dna(&keys, 121, 1.0, None, Some(&dna));
    if !m.info().dna {
        let e = got.unwrap_err().to_string();
        assert!(
            e.contains("takes no Motion DNA") && e.contains("generator"),
            "{e}"
        );
        return;
    }
    let (with, _) = got.unwrap();
    let (without, _) = m.synthesize_dna(&keys, 121, 1.0, None, None).unwrap();
    let moved = (0..121)
        .map(|t| {
            deeprep::rotation::geodesic_distance(
                &with.rotations[t][knee],
                &without.rotations[t][knee],
            )
        })
        .fold(0.0, f64::max);
    assert!(moved > 1e-3, "DNA moved the joint by at most {moved} rad");
    for k in &keys {
        for (o, p) in with.root[k.frame].iter().zip(&k.positions) {
            assert!((o - *p as f64).abs() < 1e-3);
        }
    }
    let short = vec![vec![0.0f32; 3 * joints - 1]];
    let e = m
        .synthesize_dna(&keys, 121, 1.0, None, Some(&short))
        .unwrap_err()
        .to_string();
    assert!(e.contains("Motion DNA"), "{e}");
}

/// A manifest that does not fit its network or skeleton is an error that
/// names the field, before any ONNX is read.
#[test]
fn bad_conditional_manifests_are_errors() {
    let dir = root().join("models/onnx");
    let Ok(text) = std::fs::read_to_string(dir.join("tween_cond.manifest.json")) else {
        eprintln!("SKIP: models/onnx/tween_cond.manifest.json is not exported yet");
        return;
    };
    let good: serde_json::Value = serde_json::from_str(&text).unwrap();
    let with = |key: &str, v: serde_json::Value| {
        let mut m = good.clone();
        m[key] = v;
        m.to_string()
    };
    for (manifest, want) in [
        (
            with("kind", "residual-tween".into()),
            "expected 'cond-tween'",
        ),
        (with("joints", 3.into()), "3 joints, the skeleton has"),
        (
            with("prior", serde_json::json!([[1.0]])),
            "'prior' must hold",
        ),
        (with("noise_channels", 1_000_000.into()), "noise channels"),
        (with("scale", 0.into()), "must be positive"),
        (with("variation", 5.into()), "[0, 2]"),
        (
            with("context_base", "cubic".into()),
            "expected 'slerp' or 'hermite'",
        ),
        (
            with("rotating", serde_json::json!([1, 0])),
            "'rotating' must list",
        ),
        (with("fill_from", 21.into()), "fill_from without fill_up_to"),
        (with("fill_up_to", 0.into()), "1 <= fill_from <= fill_up_to"),
    ] {
        let e = CondModel::new(&[], &manifest)
            .err()
            .expect(want)
            .to_string();
        assert!(e.contains(want), "{want}: {e}");
    }
    // the planner's reading of the manifest checks the fill range too
    let mut m = good.clone();
    m["fill_from"] = 46.into();
    m["fill_up_to"] = 45.into();
    let e = deeprep::motion::cond::info_of_manifest(&m.to_string()).unwrap_err();
    assert!(
        e.to_string().contains("fill_from 46 and fill_up_to 45"),
        "{e}"
    );
    m["fill_from"] = 21.into();
    let info = deeprep::motion::cond::info_of_manifest(&m.to_string()).unwrap();
    assert_eq!(info.fill_gaps, Some((21, 45)));
}

/// Keys more than MAX_LONG_GAP (3,000) frames apart are an error, as they
/// are for the generator's hierarchy, not a long computation.
#[test]
fn a_gap_beyond_the_hierarchys_reach_is_an_error() {
    let Some(m) = model() else { return };
    let joints = m.template.joints.len();
    let keys: Vec<Keyframe> = [0usize, 3001]
        .iter()
        .map(|&f| Keyframe::root_only(f, [0.0, 90.0, f as f32], joints))
        .collect();
    let e = m
        .synthesize(&keys, 3002, 1.0, None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("3001 frames apart") && e.contains("3000"), "{e}");
}

/// A gap over HIER_GAP frames runs hierarchically: the keys stay exact and
/// the limbs keep moving in the middle of a 1,000-frame gap (the knee turned
/// 2.8 rad over frames 400-600 here, 0.26 in one pass).
#[test]
fn a_long_gap_keeps_moving() {
    let Some(m) = model() else { return };
    let joints = m.template.joints.len();
    let keys: Vec<Keyframe> = [0usize, 1000]
        .iter()
        .map(|&f| Keyframe::root_only(f, [0.0, 90.0, f as f32], joints))
        .collect();
    let out = m.synthesize(&keys, 1001, 1.0, None).unwrap();
    assert_eq!(out.len(), 1001);
    for k in &keys {
        for (o, p) in out.root[k.frame].iter().zip(&k.positions) {
            assert!((o - *p as f64).abs() < 1e-3, "root at {}", k.frame);
        }
    }
    let turned = knee_turn(&m, &out, 401..600);
    assert!(
        turned > 1.0,
        "the knee turns {turned} rad over frames 400-600"
    );
}

/// With `coarse_rates` in the manifest the hierarchy's coarse pass tells the
/// network its rate: a 1,000-frame gap comes out differently (the critical
/// poses come from another coarse motion) with the keys as exact, and a gap
/// short enough for one pass is unchanged.
#[test]
fn coarse_rates_in_the_manifest_reach_the_coarse_pass_only() {
    if model().is_none() {
        return;
    }
    let dir = root().join("models/onnx");
    let mut manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("tween_cond.manifest.json")).unwrap(),
    )
    .unwrap();
    let mut with_rates = |on: bool| {
        manifest["coarse_rates"] = on.into();
        CondModel::new(
            &std::fs::read(dir.join("tween_cond.onnx")).unwrap(),
            &manifest.to_string(),
        )
        .unwrap()
    };
    let (plain, coarse) = (with_rates(false), with_rates(true));
    let joints = plain.template.joints.len();
    let keys = |last: usize| -> Vec<Keyframe> {
        [0usize, last]
            .iter()
            .map(|&f| Keyframe::root_only(f, [0.0, 90.0, f as f32], joints))
            .collect()
    };
    let (a, b) = (
        plain.synthesize(&keys(1000), 1001, 1.0, None).unwrap(),
        coarse.synthesize(&keys(1000), 1001, 1.0, None).unwrap(),
    );
    let apart = (300..700)
        .map(|t| {
            (0..3)
                .map(|i| (a.root[t][i] - b.root[t][i]).abs())
                .sum::<f64>()
        })
        .fold(0.0, f64::max);
    assert!(apart > 1e-3, "the coarse rate changed nothing ({apart})");
    for k in keys(1000) {
        for (o, p) in b.root[k.frame].iter().zip(&k.positions) {
            assert!((o - *p as f64).abs() < 1e-3, "root at {}", k.frame);
        }
    }
    let (a, b) = (
        plain.synthesize(&keys(200), 201, 1.0, None).unwrap(),
        coarse.synthesize(&keys(200), 201, 1.0, None).unwrap(),
    );
    assert_eq!(a.root, b.root);
    assert_eq!(a.rotations, b.rotations);
}

/// With `context_base: hermite` in the manifest (issue 50), a gap between
/// whole poses with context frames starts from the fill's Hermite curve:
/// at variation 0 the output is that curve (fill::hermite_curve on the same
/// keys); the SLERP+LERP base gives another motion.
#[test]
fn a_hermite_context_base_is_the_fill_curve_at_variation_zero() {
    use deeprep::motion::fill;
    use deeprep::rotation::to_glam_f64;
    use glam::{DQuat, DVec3};
    if model().is_none() {
        return;
    }
    let dir = root().join("models/onnx");
    let with_base = |base: &str| {
        let mut manifest: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join("tween_cond.manifest.json")).unwrap(),
        )
        .unwrap();
        manifest["context_base"] = base.into();
        CondModel::new(
            &std::fs::read(dir.join("tween_cond.onnx")).unwrap(),
            &manifest.to_string(),
        )
        .unwrap()
    };
    let (m, slerp) = (with_base("hermite"), with_base("slerp"));
    // a clip on the model's skeleton whose joints turn at varying rates
    let mut b = m.template.clone();
    let c = b.channel_count();
    b.motion = (0..40 * c)
        .map(|i| {
            let (f, ch) = ((i / c) as f32, i % c);
            match ch {
                0 => 1.5 * f,
                1 => 88.0 + (0.2 * f).sin(),
                2 => -0.5 * f,
                _ => 25.0 * (0.05 * f + 0.3 * ch as f32).sin(),
            }
        })
        .collect();
    let keys: Vec<Keyframe> = [0, 1, 2, 30, 31]
        .iter()
        .map(|&f| Keyframe::from_bvh(&b, f, f).unwrap())
        .collect();
    let out = m.synthesize(&keys, 32, 0.0, None).unwrap();
    let root_of = |k: &Keyframe| {
        DVec3::new(
            k.positions[0] as f64,
            k.positions[1] as f64,
            k.positions[2] as f64,
        )
    };
    let quats = |k: &Keyframe| -> Vec<DQuat> {
        k.rotations
            .as_ref()
            .unwrap()
            .iter()
            .map(|r| DQuat::from_mat3(&to_glam_f64(r)).normalize())
            .collect()
    };
    let (q1, q2, q30, q31) = (
        quats(&keys[1]),
        quats(&keys[2]),
        quats(&keys[3]),
        quats(&keys[4]),
    );
    let ends = fill::HermiteEnds {
        root: [root_of(&keys[2]), root_of(&keys[3])],
        rot: [&q2, &q30],
        prev: Some((root_of(&keys[1]), &q1)),
        next: Some((root_of(&keys[4]), &q31)),
    };
    let curve = fill::hermite_curve(&ends, 28);
    let mut apart = 0f64;
    let other = slerp.synthesize(&keys, 32, 0.0, None).unwrap();
    for (i, (p, q)) in curve.iter().enumerate() {
        let t = 3 + i;
        let got = DVec3::from_array(out.root[t]);
        assert!(
            (got - *p).length() < 1e-6,
            "frame {t}: root {got} vs the curve's {p}"
        );
        for (j, want) in q.iter().enumerate() {
            let g = DQuat::from_mat3(&to_glam_f64(&out.rotations[t][j])).normalize();
            assert!(
                g.dot(*want).abs() > 1.0 - 1e-9,
                "frame {t} joint {j}: {g} vs the curve's {want}"
            );
        }
        apart = apart.max((DVec3::from_array(other.root[t]) - *p).length());
    }
    assert!(apart > 0.1, "the SLERP+LERP base is {apart} from the curve");
}

/// `deeprep inbetween` on a generated clip with a copy of the models folder
/// whose conditional network's manifest a test changes (removed on drop).
struct StandIn {
    dir: std::path::PathBuf,
    lib: std::path::PathBuf,
    input: std::path::PathBuf,
    manifest: serde_json::Value,
}

impl StandIn {
    fn new(tag: &str, frames: usize) -> StandIn {
        let (dir, lib) = crate::motion::models_copy(tag);
        let input = dir.join("in.bvh");
        std::fs::write(&input, crate::motion::fill::clip_text(frames)).unwrap();
        let manifest = serde_json::from_str(
            &std::fs::read_to_string(root().join("models/onnx/tween_cond.manifest.json")).unwrap(),
        )
        .unwrap();
        StandIn {
            dir,
            lib,
            input,
            manifest,
        }
    }

    /// Sets a flag of the copy's tween_cond manifest.
    fn set(&mut self, flag: &str, on: bool) {
        self.manifest[flag] = on.into();
        std::fs::write(
            self.lib.join("tween_cond.manifest.json"),
            self.manifest.to_string(),
        )
        .unwrap();
    }

    /// `deeprep inbetween --from-bvh CLIP ARGS -o OUT --models COPY`: its
    /// report (stderr), after checking that it succeeded.
    fn run(&self, args: &[&str]) -> String {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
            .args(["inbetween", "--from-bvh", self.input.to_str().unwrap()])
            .args(args)
            .args(["-o", self.dir.join("out.bvh").to_str().unwrap()])
            .args(["--models", self.lib.to_str().unwrap()])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        assert!(o.status.success(), "{args:?}: {err}");
        err
    }
}

impl Drop for StandIn {
    fn drop(&mut self) {
        std::fs::remove_dir_all(&self.dir).ok();
    }
}

/// With `default_for_long_gaps` in its manifest (stand-ins: the bundled
/// network's manifest with the flag off, then on), `deeprep inbetween` with
/// the `model` method sends whole-pose keys 700 frames apart to the
/// conditional network's hierarchy instead of the generator, and keys at
/// most 600 apart stay with the residual network.
#[test]
fn long_whole_pose_gaps_go_where_the_manifest_says() {
    if model().is_none() {
        return;
    }
    let mut cli = StandIn::new("longgap", 801);
    let run = |cli: &StandIn, keys: &str| cli.run(&["--keys", keys]);
    cli.set("default_for_long_gaps", false);
    let before = run(&cli, "0,700");
    assert!(before.contains("pipeline generator"), "{before}");
    cli.set("default_for_long_gaps", true);
    let after = run(&cli, "0,700");
    assert!(after.contains("pipeline cond"), "{after}");
    // its coarse pass runs at 1/3 of the frame rate (700 / 300 rounded
    // up) and gives critical keys at the gap's thirds, on that rate's
    // frames; the CLI reports them as it does the generator's
    assert!(
        after.contains("critical keys made first at frames [234, 468]"),
        "{after}"
    );
    // one long gap among short ones is enough
    let mixed = run(&cli, "0,100,800");
    assert!(mixed.contains("pipeline cond"), "{mixed}");
    let near = run(&cli, "0,300,700");
    assert!(near.contains("pipeline residual"), "{near}");
}

/// With `default_for_root_keys` in its manifest (a stand-in: the bundled
/// network's manifest with the flag set), `deeprep inbetween --key-kind
/// root` with the `model` method runs the conditional network instead of the
/// generator; whole-pose and 2-D keys keep their pipelines.
#[test]
fn root_keys_go_where_the_manifest_says() {
    if model().is_none() {
        return;
    }
    let mut cli = StandIn::new("rootkeys", 241);
    let run = |cli: &StandIn, kind: &str| cli.run(&["--keys", "0,120,240", "--key-kind", kind]);
    let before = run(&cli, "root");
    assert!(before.contains("pipeline generator"), "{before}");
    cli.set("default_for_root_keys", true);
    let after = run(&cli, "root");
    assert!(after.contains("pipeline cond"), "{after}");
    let poses = run(&cli, "pose");
    assert!(poses.contains("pipeline residual"), "{poses}");
    let xy = run(&cli, "xy");
    assert!(xy.contains("pipeline generator"), "{xy}");
}

/// The DNA network as a second file (`tween_cond_dna`, beside a
/// conditional network without DNA): `--method cond` runs it for requests
/// with Motion DNA, `--method model` only when its manifest says
/// `default_for_dna`, and a manifest without `dna` under that name is an
/// error. The small random network with a DNA input stands in for it.
#[test]
fn the_cli_runs_the_dna_network_for_requests_with_dna() {
    let models = root().join("models/onnx");
    if !models.join("tween_generator.onnx").exists() || !models.join("tween_cond.onnx").exists() {
        eprintln!("SKIP: models/onnx has no generator or conditional network");
        return;
    }
    let fixture = root().join("tests/fixtures/cond_dna");
    let m = CondModel::load_dir(&fixture).unwrap();
    let tmp = std::env::temp_dir().join(format!("deeprep_cond_dna_{}", std::process::id()));
    let dir = tmp.join("models");
    std::fs::create_dir_all(&dir).unwrap();
    for e in std::fs::read_dir(&models).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_file() {
            std::fs::copy(e.path(), dir.join(e.file_name())).unwrap();
        }
    }
    std::fs::copy(
        fixture.join("tween_cond.onnx"),
        dir.join("tween_cond_dna.onnx"),
    )
    .unwrap();
    let manifest = std::fs::read_to_string(fixture.join("tween_cond.manifest.json")).unwrap();
    let set = |key: &str, value: bool| {
        let mut v: serde_json::Value = serde_json::from_str(&manifest).unwrap();
        v[key] = serde_json::Value::Bool(value);
        std::fs::write(
            dir.join("tween_cond_dna.manifest.json"),
            serde_json::to_string(&v).unwrap(),
        )
        .unwrap();
    };
    let clip_path = tmp.join("clip.bvh");
    crate::common::write_walking_clip(&m.template, &clip_path);
    let out = tmp.join("out.bvh");
    let run = |method: &str, dna: bool| {
        let mut args = vec![
            "inbetween",
            "--from-bvh",
            clip_path.to_str().unwrap(),
            "--keys",
            "0,60,120",
            "--key-kind",
            "root",
            "--method",
            method,
            "--models",
            dir.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        if dna {
            args.extend(["--dna", "30,90"]);
        }
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        (o.status.success(), err)
    };
    let ran = |method: &str, dna: bool| {
        let (ok, err) = run(method, dna);
        assert!(ok, "{method}: {err}");
        err.split("pipeline ")
            .nth(1)
            .and_then(|s| s.split(' ').next())
            .unwrap_or_else(|| panic!("{method}: no pipeline in {err}"))
            .to_string()
    };
    set("default_for_dna", false);
    assert_eq!(ran("cond", true), "cond-dna");
    assert_eq!(ran("cond", false), "cond");
    assert_eq!(ran("model", true), "generator");
    set("default_for_dna", true);
    assert_eq!(ran("model", true), "cond-dna");
    set("dna", false);
    let (ok, err) = run("model", true);
    assert!(
        !ok && err.contains("tween_cond_dna") && err.contains("dna"),
        "{err}"
    );
    std::fs::remove_dir_all(&tmp).ok();
}
