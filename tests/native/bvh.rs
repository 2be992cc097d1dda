//! BVH reader/writer and forward kinematics.

use deeprep::skeleton::{fk, Bvh, Channel};
use deeprep::Error;
use std::path::PathBuf;

use crate::common;
mod retarget;

/// A small skeleton the project makes itself: a 6-channel root, two
/// branches, mixed channel orders, a joint with position channels, and End
/// Sites. Values are deterministic functions of (frame, channel).
fn fixture(frames: usize) -> String {
    let mut s = String::from(
        "HIERARCHY\nROOT hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n  JOINT spine\n  {\n    OFFSET 0 10 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    JOINT head\n    {\n      OFFSET 0 5.5 1.25\n      CHANNELS 3 Xrotation Yrotation Zrotation\n      End Site\n      {\n        OFFSET 0 3 0\n      }\n    }\n  }\n  JOINT leg\n  {\n    OFFSET -2 -1 0\n    CHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation Zrotation\n    End Site\n    {\n      OFFSET 0 -9 0\n    }\n  }\n}\nMOTION\n",
    );
    s.push_str(&format!("Frames: {frames}\nFrame Time: 0.0166667\n"));
    for f in 0..frames {
        let vals: Vec<String> = (0..18)
            .map(|c| {
                format!(
                    "{}",
                    ((f * 31 + c * 17) % 360) as f32 * 0.5 - 90.0 + 0.125 * c as f32
                )
            })
            .collect();
        s.push_str(&vals.join(" "));
        s.push('\n');
    }
    s
}

fn shared() -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/cmu-bvh");
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("SKIP: ../shared/data/cmu-bvh is absent; shared-data checks skipped");
        None
    }
}

#[test]
fn parses_the_fixture() {
    let b = Bvh::parse(&fixture(4)).unwrap();
    let names: Vec<&str> = b.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(
        names,
        ["hips", "spine", "head", "head_Nub", "leg", "leg_Nub"]
    );
    assert_eq!(b.joints[4].parent, Some(0));
    assert_eq!(b.joints[3].parent, Some(2));
    assert!(b.joints[3].end_site && b.joints[3].channels.is_empty());
    assert_eq!(b.channel_count(), 18);
    assert_eq!(b.frame_count(), 4);
    assert_eq!(b.joints[4].channels[3], Channel::Yrotation);
    assert_eq!(b.joints[4].channel_start, 12);
    assert!((b.fps() - 60.0).abs() < 1e-3);
    assert_eq!(b.joints[2].offset, [0.0, 5.5, 1.25]);
}

#[test]
fn write_then_read_is_exact() {
    let b = Bvh::parse(&fixture(50)).unwrap();
    let again = Bvh::parse(&b.write()).unwrap();
    assert_eq!(b, again);
    // And a second write is byte-identical.
    assert_eq!(b.write(), again.write());
}

#[test]
fn shared_clips_round_trip() {
    let Some(dir) = shared() else { return };
    for f in ["standard.bvh", "salsa/01.bvh", "martial/03.bvh"] {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        let b = Bvh::parse(&text).unwrap();
        assert_eq!(
            b.joints.len(),
            57,
            "{f}: the thesis skeleton has 57 joints counting End Sites"
        );
        let again = Bvh::parse(&b.write()).unwrap();
        assert_eq!(b, again, "{f}");
    }
}

fn parse_err(text: &str) -> (usize, String) {
    match Bvh::parse(text) {
        Err(Error::Parse { line, message }) => (line, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn malformed_files_name_the_line_and_what_was_expected() {
    let good = fixture(3);
    let lines: Vec<&str> = good.lines().collect();
    let with = |i: usize, repl: &str| {
        let mut l = lines.clone();
        l[i] = repl;
        l.join("\n")
    };
    let (line, msg) = parse_err(&with(0, "HIERARCHIE"));
    assert_eq!(line, 1);
    assert!(msg.contains("expected HIERARCHY"), "{msg}");
    let (line, msg) = parse_err(&with(3, "  OFFSET 0 zero 0"));
    assert_eq!(line, 4);
    assert!(msg.contains("number") && msg.contains("zero"), "{msg}");
    let (line, msg) = parse_err(&with(
        4,
        "  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Wrotation",
    ));
    assert_eq!(line, 5);
    assert!(msg.contains("unknown channel 'Wrotation'"), "{msg}");
    let (line, msg) = parse_err(&with(
        4,
        "  CHANNELS 5 Xposition Yposition Zposition Zrotation Yrotation Xrotation",
    ));
    assert_eq!(line, 5);
    assert!(msg.contains("says 5 channels"), "{msg}");
    let n = lines.len();
    let (line, msg) = parse_err(&with(n - 2, "1 2 3"));
    assert_eq!(line, n - 1);
    assert!(msg.contains("has 3 values; expected 18"), "{msg}");
    let (line, msg) = parse_err(&with(
        n - 1,
        "1 2 3 nan 5 6 7 8 9 10 11 12 13 14 15 16 17 18",
    ));
    assert_eq!(line, n);
    assert!(msg.contains("'nan'"), "{msg}");
    let truncated: String = lines[..n - 1].join("\n");
    let (_, msg) = parse_err(&truncated);
    assert!(
        msg.contains("ends after 2 frames; the header says 3"),
        "{msg}"
    );
    let (_, msg) = parse_err(&format!("{good}1 2 3\n"));
    assert!(msg.contains("unexpected data after"), "{msg}");
    let (line, msg) = parse_err(&with(6, "    OFFSET 0 10 0"));
    assert_eq!(line, 7);
    assert!(msg.contains("expected '{'"), "{msg}");
}

#[test]
fn every_truncation_is_an_error_never_a_panic() {
    let good = fixture(3);
    for cut in 0..good.len() {
        if !good.is_char_boundary(cut) {
            continue;
        }
        let r = Bvh::parse(&good[..cut]);
        // A cut inside the last number can still parse; anything else errs.
        if let Ok(b) = r {
            assert_eq!(b.frame_count(), 3, "cut at {cut}");
        }
    }
    assert!(Bvh::parse("").is_err());
    assert!(Bvh::parse_bytes(&[0xff, 0xfe, 0x00]).is_err());
}

#[test]
fn a_100k_frame_file_parses_in_one_pass() {
    let text = fixture(100_000);
    let b = Bvh::parse(&text).unwrap();
    assert_eq!(b.frame_count(), 100_000);
    assert_eq!(b.motion.len(), 1_800_000);
}

#[test]
fn fk_matches_hand_computed_positions() {
    let text = "HIERARCHY\nROOT r\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n JOINT c\n {\n  OFFSET 1 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 2 0\n  }\n }\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n1 2 3 90 0 0 0 0 0\n0 0 0 0 0 0 0 90 0\n";
    let b = Bvh::parse(text).unwrap();
    let p = fk::positions(&b, 0, 2).unwrap();
    let close = |a: &[f32], e: [f32; 3]| a.iter().zip(e).all(|(x, y)| (x - y).abs() < 1e-5);
    // Frame 0: root at (1,2,3), turned 90° about Z: +X becomes +Y.
    assert!(close(&p[0..3], [1.0, 2.0, 3.0]));
    assert!(close(&p[3..6], [1.0, 3.0, 3.0]), "{:?}", &p[3..6]);
    assert!(close(&p[6..9], [-1.0, 3.0, 3.0]), "{:?}", &p[6..9]);
    // Frame 1: the child turns 90° about X: its +Y end goes to +Z.
    assert!(close(&p[9..12], [0.0, 0.0, 0.0]));
    assert!(close(&p[12..15], [1.0, 0.0, 0.0]));
    assert!(close(&p[15..18], [1.0, 0.0, 2.0]), "{:?}", &p[15..18]);
    // Channel order matters: Zrotation then Xrotation is Rz·Rx.
    assert!(fk::positions(&b, 1, 3).is_err());
}

#[test]
fn fk_of_one_row_matches_the_clip_and_checks_the_row() {
    let b = Bvh::parse(&fixture(4)).unwrap();
    for f in 0..4 {
        let whole = fk::positions(&b, f, f + 1).unwrap();
        assert_eq!(fk::pose_positions(&b, b.frame(f)).unwrap(), whole);
    }
    let short = fk::pose_positions(&b, &[0.0; 17]).unwrap_err().to_string();
    assert!(
        short.contains("18 channel values") && short.contains("17"),
        "{short}"
    );
    let mut row = b.frame(0).to_vec();
    row[5] = f32::NAN;
    let nan = fk::pose_positions(&b, &row).unwrap_err().to_string();
    assert!(nan.contains("channel value 5"), "{nan}");
}

#[test]
fn fk_keeps_bone_lengths() {
    let b = Bvh::parse(&fixture(20)).unwrap();
    let p = fk::positions(&b, 0, 20).unwrap();
    let nj = b.joints.len();
    for f in 0..20 {
        for (i, j) in b.joints.iter().enumerate() {
            // Joints with position channels move away from their offset.
            if j.channels.contains(&Channel::Xposition) {
                continue;
            }
            if let Some(par) = j.parent {
                let a = &p[(f * nj + i) * 3..(f * nj + i) * 3 + 3];
                let c = &p[(f * nj + par) * 3..(f * nj + par) * 3 + 3];
                let len =
                    ((a[0] - c[0]).powi(2) + (a[1] - c[1]).powi(2) + (a[2] - c[2]).powi(2)).sqrt();
                let off = j.offset.iter().map(|x| x * x).sum::<f32>().sqrt();
                assert!(
                    (len - off).abs() < 1e-4,
                    "frame {f} joint {}: {len} vs {off}",
                    j.name
                );
            }
        }
    }
}

/// Frame-rate conversion: identity at the same rate, half the frames from
/// 120 to 60 fps with the values of the even frames, and a slerped
/// rotation between frames (one joint turning at constant speed).
#[test]
fn resampling_keeps_time_and_slerps_rotations() {
    use deeprep::skeleton::resample::resample;
    let mut b = Bvh::parse(&fixture(9)).unwrap();
    b.frame_time = 1.0 / 120.0;
    assert_eq!(resample(&b, 120.0).unwrap(), b);
    let half = resample(&b, 60.0).unwrap();
    assert_eq!(half.frame_count(), 5);
    assert!((half.fps() - 60.0).abs() < 1e-9);
    for f in 0..5 {
        let (got, want) = (half.frame(f), b.frame(2 * f));
        for (c, (g, w)) in got.iter().zip(want).enumerate() {
            // the same rotation, perhaps as another Euler triple
            let joint = b
                .joints
                .iter()
                .find(|j| (j.channel_start..j.channel_start + j.channels.len()).contains(&c))
                .unwrap();
            if !joint.channels[c - joint.channel_start].is_rotation() {
                assert!((g - w).abs() < 1e-4, "frame {f} channel {c}: {g} vs {w}");
            }
        }
        let a = fk::positions(&half, f, f + 1).unwrap();
        let e = fk::positions(&b, 2 * f, 2 * f + 1).unwrap();
        let d = a
            .iter()
            .zip(&e)
            .map(|(x, y)| (x - y).abs())
            .fold(0f32, f32::max);
        assert!(d < 1e-3, "frame {f}: FK differs by {d}");
    }
    // a spine turning 0, 10, 20 ... degrees about z: at 240 fps the frame
    // between two source frames is at the mid angle
    let mut turn = Bvh::parse(&fixture(4)).unwrap();
    turn.frame_time = 1.0 / 60.0;
    let c = turn.channel_count();
    for f in 0..4 {
        for v in &mut turn.motion[f * c..(f + 1) * c] {
            *v = 0.0;
        }
        turn.motion[f * c + 6] = 10.0 * f as f32; // spine Zrotation
    }
    let fine = resample(&turn, 240.0).unwrap();
    assert_eq!(fine.frame_count(), 13);
    for (t, want) in [(1, 2.5f32), (2, 5.0), (6, 15.0), (12, 30.0)] {
        let got = fine.frame(t)[6];
        assert!((got - want).abs() < 1e-3, "frame {t}: {got} vs {want}");
    }
    assert!(resample(&turn, 0.0).is_err() && resample(&turn, f64::NAN).is_err());
}

/// The local tracks (three.js' form): translations are offset plus
/// position channels, quaternions rotate like the channels' matrices.
#[test]
fn local_tracks_match_the_channels() {
    let b = Bvh::parse(&fixture(5)).unwrap();
    let t = fk::local_tracks(&b);
    let j = b.joints.len();
    assert_eq!(t.translations.len(), 5 * j * 3);
    assert_eq!(t.quaternions.len(), 5 * j * 4);
    for f in 0..5 {
        let row = b.frame(f);
        for (i, joint) in b.joints.iter().enumerate() {
            let vals = &row[joint.channel_start..joint.channel_start + joint.channels.len()];
            let m = fk::local_rotation(&joint.channels, vals);
            let q = &t.quaternions[(f * j + i) * 4..(f * j + i) * 4 + 4];
            let qm = glam::DMat3::from_quat(glam::DQuat::from_xyzw(
                q[0] as f64,
                q[1] as f64,
                q[2] as f64,
                q[3] as f64,
            ));
            let d = (qm - m)
                .to_cols_array()
                .iter()
                .fold(0f64, |a, x| a.max(x.abs()));
            assert!(d < 1e-6, "frame {f} joint {i}: {d}");
            let tr = &t.translations[(f * j + i) * 3..(f * j + i) * 3 + 3];
            let mut want = joint.offset;
            for (c, v) in joint.channels.iter().zip(vals) {
                if !c.is_rotation() {
                    want[c.axis()] += v;
                }
            }
            assert_eq!(tr, want);
        }
    }
}

/// The FK fixture the training code checks its own FK against
/// (tests/parity/test_fk.py): this file's mixed-order skeleton, 5 frames.
/// `DEEPREP_WRITE_FIXTURES=1` rewrites it; otherwise this checks it.
#[test]
fn fk_fixture_shared_with_the_training_code() {
    let path = common::root().join("tests/fixtures/fk_native.json");
    let text = fixture(5);
    let b = Bvh::parse(&text).unwrap();
    let positions = fk::positions(&b, 0, 5).unwrap();
    if std::env::var("DEEPREP_WRITE_FIXTURES").is_ok() {
        let doc = serde_json::json!({
            "what": "global joint positions (frames x joints x 3) of `bvh` by the crate's FK (tests/native/bvh.rs)",
            "bvh": text, "frames": 5, "joints": b.joints.len(), "positions": positions,
        });
        std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    }
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(doc["bvh"].as_str().unwrap(), text, "the fixture's clip");
    let want: Vec<f64> = doc["positions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(want.len(), positions.len());
    for (a, b) in positions.iter().zip(&want) {
        assert!((*a as f64 - b).abs() < 1e-4, "{a} vs {b}");
    }
}

/// docs/cli.md holds `deeprep --help` word for word, so the CLI reference
/// cannot drift from the binary (issue 52).
#[test]
fn the_cli_reference_is_the_help() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
        .arg("--help")
        .output()
        .unwrap();
    assert!(o.status.success());
    let help = String::from_utf8(o.stdout).unwrap();
    let doc = std::fs::read_to_string(common::root().join("docs/cli.md")).unwrap();
    let block = doc
        .split("```text\n")
        .nth(1)
        .and_then(|s| s.split("```").next())
        .expect("docs/cli.md has a ```text block");
    assert_eq!(
        block, help,
        "docs/cli.md is not `deeprep --help`: regenerate it (see its first lines)"
    );
    for cmd in [
        "bvh retarget",
        "bvh roles",
        "inbetween --from-bvh",
        "--fill",
        "mesh topology",
        "hair reconstruct",
    ] {
        assert!(help.contains(cmd), "the help lacks {cmd}");
    }
}
