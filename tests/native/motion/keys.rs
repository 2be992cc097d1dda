//! Keys of every kind (files and requests), 2-D keys met after post-processing, the DNA fixture, a pose as a BVH row, and the CLI against the request planner.

use super::*;

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
    // motion::dna::frame_weights: which DNA poses steer each frame
    let weights: Vec<serde_json::Value> = [
        (3, 100, 20),
        (4, 41, 5),
        (1, 10, 240),
        (3, 7, 0),
        (6, 50, 3),
    ]
    .iter()
    .map(|&(poses, frames, radius)| {
        serde_json::json!({"poses": poses, "frames": frames, "radius": radius,
                "weights": deeprep::motion::dna::frame_weights(poses, frames, radius)})
    })
    .collect();
    if std::env::var("DEEPREP_WRITE_FIXTURES").is_ok() {
        let doc = serde_json::json!({
            "what": "motion::dna::representative_frames of `bvh` for count = 1..3 (beyond 3 the picks are on the flat part, near-ties), and motion::dna::frame_weights ([poses, frames] row-major) (tests/native/motion/keys.rs)",
            "bvh": text, "min_spacing": deeprep::motion::dna::MIN_SPACING, "picks": picks,
            "dna_window": deeprep::motion::dna::DNA_WINDOW, "frame_weights": weights,
        });
        std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    }
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(doc["bvh"].as_str().unwrap(), text, "the fixture's clip");
    let want: Vec<Vec<usize>> = serde_json::from_value(doc["picks"].clone()).unwrap();
    assert_eq!(picks, want);
    assert_eq!(doc["frame_weights"], serde_json::Value::from(weights));
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
        cond: Some(
            deeprep::motion::cond::info_of_manifest(&read("tween_cond.manifest.json")).unwrap(),
        ),
        cond_dna: None,
        fill: None,
        fill_long: None,
    };
    let tmp = std::env::temp_dir().join(format!("deeprep_cli_plan_{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let clip_path = tmp.join("clip.bvh");
    let clip = crate::common::write_walking_clip(&m.template, &clip_path);
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
            } else if kind != "pose" && loaded.cond.unwrap().default_for_partial_keys {
                Pipeline::Cond
            } else {
                Pipeline::Generator
            };
        assert_eq!(p.pipeline, want_pipeline, "{kind}");
        if variation.is_none() {
            let own = match p.pipeline {
                Pipeline::Residual => loaded.residual.unwrap().variation,
                Pipeline::Cond => loaded.cond.unwrap().variation,
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
