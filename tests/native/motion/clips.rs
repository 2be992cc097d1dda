//! The CLI with Motion DNA, keys from a clip at another frame rate, plans for any length, joint-range editing.

use super::*;

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
