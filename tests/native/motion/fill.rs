//! Filling gaps in a clip (issue 50): `deeprep inbetween --from-bvh CLIP
//! --fill S-E`, the frames outside the gaps byte for byte the input's, the
//! seams continuous, bad ranges refused, and the Hermite baseline exact on
//! motion it can represent.

use super::*;
use deeprep::motion::fill::{self, Context, Gap};

/// A clip on the model's skeleton written with six decimals (as capture
/// software writes them, unlike the crate's shortest form): the bundled
/// example's first pose (models/examples/keys.json), its root walking at 1
/// unit a frame and every joint the pose bends turning slowly.
pub(crate) fn clip_text(frames: usize) -> String {
    let Some(m) = models() else {
        return String::new();
    };
    let keys: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("models/examples/keys.json")).unwrap(),
    )
    .unwrap();
    let base: Vec<f64> = keys["keys"][0]["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let head = m.template.write();
    let head = &head[..head.find("MOTION").unwrap()];
    let mut s = format!("{head}MOTION\nFrames: {frames}\nFrame Time: 0.016667\n");
    for f in 0..frames {
        let row: Vec<String> = base
            .iter()
            .enumerate()
            .map(|(i, &b)| {
                let v = match i {
                    0 => b + f as f64,
                    1 => b,
                    2 => b + 0.5 * f as f64,
                    _ if b.abs() > 1e-3 => b + 8.0 * (f as f64 * 0.03 + i as f64).sin(),
                    _ => b,
                };
                format!("{v:.6}")
            })
            .collect();
        s += &row.join(" ");
        s.push('\n');
    }
    s
}

/// `deeprep inbetween --from-bvh INPUT --fill G ... --method METHOD` with the
/// models of `lib`, written to `DIR/METHOD.bvh`: (success, that file's text,
/// stderr).
pub(crate) fn fill_with(
    dir: &std::path::Path,
    lib: &std::path::Path,
    input: &std::path::Path,
    gaps: &[&str],
    method: &str,
) -> (bool, String, String) {
    let out = dir.join(format!("{method}.bvh"));
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"));
    cmd.args(["inbetween", "--from-bvh", input.to_str().unwrap()]);
    for g in gaps {
        cmd.args(["--fill", g]);
    }
    let o = cmd
        .args(["--method", method, "-o", out.to_str().unwrap()])
        .args(["--models", lib.to_str().unwrap()])
        .output()
        .unwrap();
    (
        o.status.success(),
        std::fs::read_to_string(&out).unwrap_or_default(),
        String::from_utf8_lossy(&o.stderr).to_string(),
    )
}

/// Frames `frames` of a BVH text's motion, one line each.
fn rows(text: &str, frames: std::ops::RangeInclusive<usize>) -> Vec<String> {
    let first = text
        .lines()
        .position(|l| l.starts_with("Frame Time"))
        .unwrap()
        + 1;
    frames
        .map(|f| text.lines().nth(first + f).unwrap().to_string())
        .collect()
}

fn run(args: &[&str]) -> (bool, String) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
        .args(["inbetween"])
        .args(args)
        .args(["--models", root().join("models/onnx").to_str().unwrap()])
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).to_string(),
    )
}

#[test]
fn the_cli_fills_gaps_and_keeps_every_other_byte() {
    if models().is_none() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("deeprep_fill_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join("in.bvh");
    let text = clip_text(300);
    std::fs::write(&input, &text).unwrap();
    let i = input.to_str().unwrap();
    for method in ["model", "slerp", "hermite"] {
        let out = dir.join(format!("{method}.bvh"));
        let (ok, err) = run(&[
            "--from-bvh",
            i,
            "--fill",
            "100-159",
            "--fill",
            "200-209",
            "--method",
            method,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{method}: {err}");
        let got = std::fs::read_to_string(&out).unwrap();
        let (a, b): (Vec<&str>, Vec<&str>) = (text.lines().collect(), got.lines().collect());
        assert_eq!(a.len(), b.len());
        let first_row = a.iter().position(|l| l.starts_with("Frame Time")).unwrap() + 1;
        for (n, (x, y)) in a.iter().zip(&b).enumerate() {
            let f = n as i64 - first_row as i64;
            let in_gap = (100..=159).contains(&f) || (200..=209).contains(&f);
            if in_gap {
                assert_ne!(x, y, "{method}: frame {f} was not synthesized");
            } else {
                assert_eq!(x, y, "{method}: line {n} (frame {f}) changed");
            }
        }
        // the seams: no joint moves further in one frame than 3 times the input's steps
        let (src, res) = (Bvh::parse(&text).unwrap(), Bvh::parse(&got).unwrap());
        let step = |b: &Bvh, f: usize| {
            let (p, q) = (
                deeprep::skeleton::fk::global_pose(b, b.frame(f)).positions,
                deeprep::skeleton::fk::global_pose(b, b.frame(f + 1)).positions,
            );
            p.iter()
                .zip(&q)
                .map(|(a, b)| a.distance(*b))
                .fold(0.0, f64::max)
        };
        let fastest = (0..299).map(|f| step(&src, f)).fold(0.0, f64::max);
        for f in [99, 159, 199, 209] {
            assert!(
                step(&res, f) <= 3.0 * fastest,
                "{method}: a jump of {} at frame {f} (input's fastest {fastest})",
                step(&res, f)
            );
        }
    }
    // bad ranges: each a clear error
    let out = dir.join("bad.bvh");
    let o = out.to_str().unwrap();
    for (fill, want) in [
        (vec!["160-100"], "reversed"),
        (vec!["250-400"], "outside"),
        (vec!["0-10"], "first frame"),
        (vec!["290-299"], "last frame"),
        (vec!["100-150", "140-160"], "overlap"),
        (vec!["100-150", "151-160"], "touch"),
        (vec!["a-b"], "START-END"),
    ] {
        let mut args = vec!["--from-bvh", i, "-o", o];
        for f in &fill {
            args.extend(["--fill", f]);
        }
        let (ok, err) = run(&args);
        assert!(!ok && err.contains(want), "{fill:?}: {err}");
    }
    let (ok, err) = run(&[
        "--from-bvh",
        i,
        "--fill",
        "100-120",
        "--keys",
        "0,10",
        "-o",
        o,
    ]);
    assert!(!ok && err.contains("--keys"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A gap-filling network (`tween_fill.onnx` with `fill_from` and
/// `fill_up_to` in its manifest) takes the `model` fill's gaps of those
/// lengths, the shorter ones stay with the Hermite curve and the longer ones
/// with the default network, and `--method fill` names it. The
/// stand-in here is the conditional network itself under the fill's name,
/// so on the short gap the `model` fill must write what `--method cond`
/// writes, line for line.
#[test]
fn a_gap_filling_network_takes_the_gaps_its_manifest_claims() {
    if models().is_none() {
        return;
    }
    let (dir, lib) = models_copy("fillnet");
    let src = root().join("models/onnx");
    std::fs::copy(src.join("tween_cond.onnx"), lib.join("tween_fill.onnx")).unwrap();
    let mut manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(src.join("tween_cond.manifest.json")).unwrap(),
    )
    .unwrap();
    manifest["name"] = "tween_fill".into();
    manifest["fill_from"] = 5.into();
    manifest["fill_up_to"] = 45.into();
    std::fs::write(lib.join("tween_fill.manifest.json"), manifest.to_string()).unwrap();
    // without the long-gap network, so that the longer gap goes to the default one
    for f in ["tween_fill_long.onnx", "tween_fill_long.manifest.json"] {
        std::fs::remove_file(lib.join(f)).ok();
    }
    let input = dir.join("in.bvh");
    let text = clip_text(300);
    std::fs::write(&input, &text).unwrap();
    let gaps = ["100-159", "200-209", "250-253"];
    let fill = |method: &str| {
        let (ok, text, err) = fill_with(&dir, &lib, &input, &gaps, method);
        assert!(ok, "{method}: {err}");
        (text, err)
    };
    let (model, info) = fill("model");
    assert!(
        info.contains("200-209: pipeline fill")
            && info.contains("100-159: pipeline residual")
            && info.contains("250-253: a cubic Hermite curve"),
        "{info}"
    );
    let (cond, _) = fill("cond");
    let (by_fill, info) = fill("fill");
    assert!(info.contains("100-159: pipeline fill"), "{info}");
    assert_eq!(rows(&model, 200..=209), rows(&cond, 200..=209));
    assert_eq!(rows(&by_fill, 100..=159), rows(&cond, 100..=159));
    // and the check can fail: the default network's gap differs from it
    assert_ne!(rows(&model, 100..=159), rows(&cond, 100..=159));
    std::fs::remove_dir_all(&dir).ok();
}

/// A long-gap filling network (`tween_fill_long.onnx`: a residual network
/// with `fill_from` and `fill_up_to` in its manifest) takes the `model`
/// fill's gaps in its band, beside the other gap-filling network's, and
/// `--method fill-long` names it. The stand-in is the bundled residual
/// network itself under that name, so on its gap the `model` fill must
/// write what `--method residual` writes, line for line; a manifest whose
/// band is reversed, or that gives none, is a clear error.
#[test]
fn a_long_gap_filling_network_takes_the_gaps_its_manifest_claims() {
    if models().is_none() {
        return;
    }
    let (dir, lib) = models_copy("filllong");
    let src = root().join("models/onnx");
    std::fs::copy(
        src.join("tween_residual.onnx"),
        lib.join("tween_fill_long.onnx"),
    )
    .unwrap();
    let mut manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(src.join("tween_residual.manifest.json")).unwrap(),
    )
    .unwrap();
    manifest["name"] = "tween_fill_long".into();
    manifest["default_for_whole_pose_keys"] = false.into();
    manifest["fill_from"] = 50.into();
    manifest["fill_up_to"] = 70.into();
    let write = |m: &serde_json::Value| {
        std::fs::write(lib.join("tween_fill_long.manifest.json"), m.to_string()).unwrap()
    };
    write(&manifest);
    let input = dir.join("in.bvh");
    std::fs::write(&input, clip_text(300)).unwrap();
    let fill = |method: &str| fill_with(&dir, &lib, &input, &["30-89", "150-229"], method);
    let (ok, model, info) = fill("model");
    assert!(ok, "{info}");
    assert!(
        info.contains("30-89: pipeline fill-long") && info.contains("150-229: pipeline residual"),
        "{info}"
    );
    let (ok, residual, info) = fill("residual");
    assert!(ok && info.contains("30-89: pipeline residual"), "{info}");
    let (ok, _, info) = fill("fill-long");
    assert!(ok && info.contains("150-229: pipeline fill-long"), "{info}");
    assert_eq!(rows(&model, 30..=89), rows(&residual, 30..=89));
    manifest["fill_from"] = 80.into();
    write(&manifest);
    let (ok, _, err) = fill("model");
    assert!(
        !ok && err.contains("tween_fill_long.manifest.json") && err.contains("fill_from 80"),
        "{err}"
    );
    // without a band the `model` fill would never run it: refused, as wasm setFillLong does
    let m = manifest.as_object_mut().unwrap();
    m.remove("fill_from");
    m.remove("fill_up_to");
    write(&manifest);
    let (ok, _, err) = fill("fill-long");
    assert!(
        !ok && err.contains("tween_fill_long.manifest.json") && err.contains("no band"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// On motion a cubic can hold (the root at constant velocity, every joint
/// at a constant angular rate about a fixed axis), the Hermite curve with
/// the context's tangents gives the motion back.
#[test]
fn the_hermite_baseline_is_exact_on_steady_motion() {
    if models().is_none() {
        return;
    }
    let m = models().unwrap();
    let mut b = m.template.clone();
    let c = b.channel_count();
    let frames = 120;
    // one rotation channel per joint moving (a fixed axis), the others 0
    b.motion = (0..frames * c)
        .map(|i| {
            let (f, ch) = ((i / c) as f32, i % c);
            match ch {
                0 => 1.5 * f,
                1 => 88.0,
                2 => -0.5 * f,
                _ if ch % 3 == 0 => 0.4 * f - 20.0,
                _ => 0.0,
            }
        })
        .collect();
    let filled = fill::fill(
        &b,
        &[Gap { start: 40, end: 89 }],
        Context {
            before: 5,
            after: 5,
        },
        &mut |clip, ck, _| fill::hermite(clip, ck),
    )
    .unwrap();
    let mut worst = 0f64;
    for f in 40..=89 {
        let (p, q) = (
            deeprep::skeleton::fk::global_pose(&b, b.frame(f)).positions,
            deeprep::skeleton::fk::global_pose(&filled, filled.frame(f)).positions,
        );
        worst = p
            .iter()
            .zip(&q)
            .map(|(a, b)| a.distance(*b))
            .fold(worst, f64::max);
    }
    assert!(
        worst < 1e-3,
        "Hermite on steady motion is off by {worst} units"
    );
    // and the check can fail: zero velocity (the first end held) is far off
    let held = fill::fill(
        &b,
        &[Gap { start: 40, end: 89 }],
        Context {
            before: 1,
            after: 1,
        },
        &mut |_, ck, _| deeprep::motion::baseline::zero_velocity(&ck.keys, ck.frames()),
    )
    .unwrap();
    let p = deeprep::skeleton::fk::global_pose(&held, held.frame(60)).positions[0];
    let q = deeprep::skeleton::fk::global_pose(&b, b.frame(60)).positions[0];
    assert!(p.distance(q) > 10.0);
}

/// `fill::hermite_curve` against its twin in the training code (cond.py's
/// `hermite_base`, the conditional network's base over gaps with context):
/// three gaps of a training take, with context on both sides, before only
/// and after only (tests/fixtures/hermite_torch.json, written by
/// train/deeprep_train/motion/make_hermite_fixture.py).
#[test]
fn the_hermite_curve_matches_the_training_code() {
    use glam::{DQuat, DVec3};
    let p = root().join("tests/fixtures/hermite_torch.json");
    let f: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
    let v = |x: &serde_json::Value| -> Vec<f64> {
        x.as_array()
            .unwrap()
            .iter()
            .map(|y| y.as_f64().unwrap())
            .collect()
    };
    let quats = |x: &serde_json::Value| -> Vec<DQuat> {
        x.as_array()
            .unwrap()
            .iter()
            .map(|q| {
                let q = v(q);
                DQuat::from_xyzw(q[1], q[2], q[3], q[0])
            })
            .collect()
    };
    let mut checked = 0;
    for gap in f["gaps"].as_array().unwrap() {
        let (a, b) = (
            gap["a"].as_u64().unwrap() as usize,
            gap["b"].as_u64().unwrap() as usize,
        );
        let key = |frame: usize| {
            let k = &gap["keys"][frame.to_string()];
            (DVec3::from_slice(&v(&k["root"])), quats(&k["quat_wxyz"]))
        };
        let (ka, kb) = (key(a), key(b));
        let prev = gap["prev"].as_bool().unwrap().then(|| key(a - 1));
        let next = gap["next"].as_bool().unwrap().then(|| key(b + 1));
        let ends = fill::HermiteEnds {
            root: [ka.0, kb.0],
            rot: [&ka.1, &kb.1],
            prev: prev.as_ref().map(|(r, q)| (*r, q.as_slice())),
            next: next.as_ref().map(|(r, q)| (*r, q.as_slice())),
        };
        let curve = fill::hermite_curve(&ends, b - a);
        let want_root = gap["root"].as_array().unwrap();
        let want_rot = gap["quat_wxyz"].as_array().unwrap();
        assert_eq!(curve.len(), want_root.len());
        for (t, (r, q)) in curve.iter().enumerate() {
            let wr = DVec3::from_slice(&v(&want_root[t]));
            assert!(
                (*r - wr).length() < 1e-9,
                "gap {a}-{b} frame {t}: root {r} vs {wr}"
            );
            for (j, (got, want)) in q.iter().zip(quats(&want_rot[t])).enumerate() {
                // the same rotation (q and -q)
                assert!(
                    got.dot(want).abs() > 1.0 - 1e-12,
                    "gap {a}-{b} frame {t} joint {j}: {got} vs {want}"
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 60, "{checked} frames compared");
}

/// The bundled gap-filling network (models/onnx/tween_fill.onnx): tract
/// against onnxruntime on its fixture, and the `model` fill gives it the
/// gap lengths its manifest claims (`fill_from`..=`fill_up_to`), the curve
/// the shorter ones and the default network the longer ones.
#[test]
fn the_bundled_gap_filling_network_serves_its_band() {
    let dir = root().join("models/onnx");
    if models().is_none() || !dir.join("tween_fill.onnx").exists() {
        eprintln!("SKIP: models/onnx/tween_fill.onnx is not bundled");
        return;
    }
    crate::common::fixture_parity("tween_fill", 2e-4);
    let manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("tween_fill.manifest.json")).unwrap(),
    )
    .unwrap();
    let from = manifest["fill_from"].as_u64().unwrap_or(1) as usize;
    let up_to = manifest["fill_up_to"].as_u64().unwrap() as usize;
    let tmp = std::env::temp_dir().join(format!("deeprep_fill_band_{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let input = tmp.join("in.bvh");
    std::fs::write(&input, clip_text(400)).unwrap();
    // gaps of fill_from and fill_up_to frames, one shorter, one longer
    let longer = up_to + 15;
    let gaps = [(40, from), (100, up_to), (200, from - 1), (280, longer)];
    let specs: Vec<String> = gaps
        .iter()
        .map(|&(s, n)| format!("{s}-{}", s + n - 1))
        .collect();
    let gap_args: Vec<&str> = specs.iter().map(String::as_str).collect();
    let (ok, _, info) = fill_with(&tmp, &dir, &input, &gap_args, "model");
    assert!(ok, "{info}");
    // the longer gap: the long-gap network where its band holds it, else the residual network
    let beyond = match std::fs::read_to_string(dir.join("tween_fill_long.manifest.json")) {
        Ok(t) => {
            let m: serde_json::Value = serde_json::from_str(&t).unwrap();
            let (lo, hi) = (
                m["fill_from"].as_u64().unwrap(),
                m["fill_up_to"].as_u64().unwrap(),
            );
            if (lo..=hi).contains(&(longer as u64)) {
                "pipeline fill-long"
            } else {
                "pipeline residual"
            }
        }
        Err(_) => "pipeline residual",
    };
    for (spec, want) in specs.iter().zip([
        "pipeline fill",
        "pipeline fill",
        "a cubic Hermite curve",
        beyond,
    ]) {
        assert!(info.contains(&format!("{spec}: {want}")), "{spec}: {info}");
    }
    std::fs::remove_dir_all(&tmp).ok();
}

/// The bundled long-gap filling network (models/onnx/tween_fill_long.onnx):
/// tract against onnxruntime on its fixture, and the `model` fill gives it
/// the gap lengths its manifest claims (`fill_from`..=`fill_up_to`) and the
/// residual network the longer ones.
#[test]
fn the_bundled_long_gap_network_serves_its_band() {
    let dir = root().join("models/onnx");
    if models().is_none() || !dir.join("tween_fill_long.onnx").exists() {
        eprintln!("SKIP: models/onnx/tween_fill_long.onnx is not bundled");
        return;
    }
    crate::common::fixture_parity("tween_fill_long", 2e-4);
    let manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("tween_fill_long.manifest.json")).unwrap(),
    )
    .unwrap();
    let from = manifest["fill_from"].as_u64().unwrap() as usize;
    let up_to = manifest["fill_up_to"].as_u64().unwrap() as usize;
    let tmp = std::env::temp_dir().join(format!("deeprep_fill_long_{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let input = tmp.join("in.bvh");
    std::fs::write(&input, clip_text(from + 2 * up_to + 200)).unwrap();
    // gaps of fill_from and fill_up_to frames, and one longer
    let specs: Vec<String> = [
        (40, from),
        (from + 100, up_to),
        (from + up_to + 160, up_to + 10),
    ]
    .iter()
    .map(|&(s, n)| format!("{s}-{}", s + n - 1))
    .collect();
    let gaps: Vec<&str> = specs.iter().map(String::as_str).collect();
    let (ok, _, info) = fill_with(&tmp, &dir, &input, &gaps, "model");
    assert!(ok, "{info}");
    for (spec, want) in specs.iter().zip([
        "pipeline fill-long",
        "pipeline fill-long",
        "pipeline residual",
    ]) {
        assert!(info.contains(&format!("{spec}: {want}")), "{spec}: {info}");
    }
    std::fs::remove_dir_all(&tmp).ok();
}
