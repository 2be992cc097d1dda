//! The short-gap fill network (`motion::fill_mlp`, issue 50): the Rust twin
//! against `train/deeprep_train/motion/fill_mlp.py` on a small network with
//! random weights (tests/fixtures/fill_mlp, `fill_mlp fixture`), whether or
//! not a trained one is bundled; the `model` fill gives it the gaps its
//! manifest claims; bad manifests are clear errors.

use super::*;
use crate::common::doubles;
use deeprep::motion::fill_mlp::{band_of_manifest, Edges, FillMlp};
use glam::{DQuat, DVec3};

fn fixture_dir() -> std::path::PathBuf {
    root().join("tests/fixtures/fill_mlp")
}

/// A fixture frame: (root, quaternions [w, x, y, z] of the rotating joints).
fn frame(v: &serde_json::Value) -> (DVec3, Vec<DQuat>) {
    let r = doubles(&v["root"]);
    let q = v["quat"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| {
            let q = doubles(q);
            DQuat::from_xyzw(q[1], q[2], q[3], q[0])
        })
        .collect();
    (DVec3::new(r[0], r[1], r[2]), q)
}

/// Every fixture case (gaps of 12, 30 and 45 frames with 8 / 3 / 1 frames
/// known before and 1 / 8 / 2 after) through `FillMlp::correct`: root
/// positions and rotations as the training code makes them with the
/// shipped file in onnxruntime.
#[test]
fn the_short_gap_network_reproduces_the_training_code() {
    let net = FillMlp::load_named(&fixture_dir(), "tween_fill_mlp").unwrap();
    let text =
        std::fs::read_to_string(fixture_dir().join("fixtures/runtime/tween_fill_mlp_motion.json"))
            .unwrap();
    let f: serde_json::Value = serde_json::from_str(&text).unwrap();
    let cases = f["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 3);
    let mut moved = 0.0f64;
    for case in cases {
        let t = case["t"].as_u64().unwrap() as usize;
        let edges = Edges {
            before: case["before"]
                .as_array()
                .unwrap()
                .iter()
                .map(frame)
                .collect(),
            after: case["after"]
                .as_array()
                .unwrap()
                .iter()
                .map(frame)
                .collect(),
        };
        let got = net.correct(&edges, t).unwrap();
        assert_eq!(got.len(), t);
        let want_root = case["root"].as_array().unwrap();
        let want_quat = case["quat"].as_array().unwrap();
        let (mut dr, mut dq) = (0.0f64, 0.0f64);
        for (i, (r, qs)) in got.iter().enumerate() {
            let w = doubles(&want_root[i]);
            dr = dr.max((*r - DVec3::new(w[0], w[1], w[2])).abs().max_element());
            let (_, wq) = frame(&serde_json::json!({"root": [0, 0, 0], "quat": want_quat[i]}));
            for (q, p) in qs.iter().zip(&wq) {
                dq = dq.max(1.0 - q.dot(*p).abs());
            }
        }
        // float32 inputs and network against float64 features: the root in
        // the clip's units (a few hundred), rotations within 0.5 degrees
        assert!(dr < 2e-3, "gap of {t}: root {dr}");
        assert!(dq < 1e-5, "gap of {t}: 1 - |dot| {dq}");
        // and the network moved the gap off the curve (the check can fail)
        let (first, last) = (&edges.before[edges.before.len() - 1], &edges.after[0]);
        let mid = &got[t / 2];
        moved = moved.max((mid.0 - (first.0 + last.0) / 2.0).length());
    }
    assert!(moved > 0.0);
}

/// The twin's input checks: no frame on a side, a gap of 0 frames or
/// longer than it trained on, the wrong joint count are errors, not panics.
#[test]
fn the_short_gap_network_refuses_bad_edges() {
    let net = FillMlp::load_named(&fixture_dir(), "tween_fill_mlp").unwrap();
    let k = net.joints().len();
    let pose = (DVec3::ZERO, vec![DQuat::IDENTITY; k]);
    let ok = Edges {
        before: vec![pose.clone()],
        after: vec![pose.clone()],
    };
    assert_eq!(net.correct(&ok, 10).unwrap().len(), 10);
    assert!(net.correct(&ok, 0).is_err());
    // beyond the longest gap it trained on (48 frames): refused, with the way out
    assert_eq!(net.correct(&ok, 48).unwrap().len(), 48);
    let e = net.correct(&ok, 49).unwrap_err().to_string();
    assert!(
        e.contains("up to 48 frames") && e.contains("method model"),
        "{e}"
    );
    let none = Edges {
        before: vec![],
        after: vec![pose.clone()],
    };
    assert!(net.correct(&none, 10).is_err());
    let short = Edges {
        before: vec![(DVec3::ZERO, vec![DQuat::IDENTITY; k - 1])],
        after: vec![pose],
    };
    let e = net.correct(&short, 10).unwrap_err().to_string();
    assert!(e.contains("rotating joints"), "{e}");
}

/// Manifests: the band is required and checked, the layout must be
/// consistent, the kind named.
#[test]
fn a_short_gap_manifest_is_checked() {
    let text = std::fs::read_to_string(fixture_dir().join("tween_fill_mlp.manifest.json")).unwrap();
    assert_eq!(band_of_manifest(&text).unwrap(), (10, 30));
    let m: serde_json::Value = serde_json::from_str(&text).unwrap();
    let err = |edit: &dyn Fn(&mut serde_json::Value)| {
        let mut v = m.clone();
        edit(&mut v);
        band_of_manifest(&v.to_string()).unwrap_err().to_string()
    };
    let e = err(&|v| {
        v.as_object_mut().unwrap().remove("fill_up_to");
        v.as_object_mut().unwrap().remove("fill_from");
    });
    assert!(e.contains("no band"), "{e}");
    let e = err(&|v| v["fill_from"] = 40.into());
    assert!(e.contains("fill_from 40"), "{e}");
    let e = err(&|v| v["fill_up_to"] = 60.into());
    assert!(e.contains("beyond the longest gap"), "{e}");
    let e = err(&|v| v["inputs_len"] = 7.into());
    assert!(e.contains("inconsistent layout"), "{e}");
    let e = err(&|v| v["context"] = 100000000.into());
    assert!(e.contains("inconsistent layout"), "{e}");
    let e = err(&|v| v["kind"] = "residual-tween".into());
    assert!(e.contains("expected 'fill-mlp'"), "{e}");
}

/// The `model` fill gives the short-gap network the gaps its manifest
/// claims, before the other networks' bands, and `--method fill-mlp` names
/// it; its gap differs from the Hermite curve's, and the frames outside
/// the gaps are the input's.
#[test]
fn the_short_gap_network_takes_the_gaps_its_manifest_claims() {
    if models().is_none() {
        return;
    }
    let (dir, lib) = models_copy("fillmlp");
    for f in ["tween_fill_mlp.onnx", "tween_fill_mlp.manifest.json"] {
        std::fs::copy(fixture_dir().join(f), lib.join(f)).unwrap();
    }
    let input = dir.join("in.bvh");
    let text = super::fill::clip_text(300);
    std::fs::write(&input, &text).unwrap();
    // 12 and 30 frames: in its band (10-30); 5: below it, the curve
    let gaps = ["40-51", "100-129", "200-204"];
    let fill = |method: &str| {
        let (ok, text, err) = super::fill::fill_with(&dir, &lib, &input, &gaps, method);
        assert!(ok, "{method}: {err}");
        (text, err)
    };
    let (model, info) = fill("model");
    assert!(
        info.contains("40-51: the short-gap fill network")
            && info.contains("100-129: the short-gap fill network")
            && info.contains("200-204: a cubic Hermite curve"),
        "{info}"
    );
    let (named, _) = fill("fill-mlp");
    let (curve, _) = fill("hermite");
    let lines = |t: &str| t.lines().map(str::to_string).collect::<Vec<_>>();
    let (m, n, c, input_lines) = (lines(&model), lines(&named), lines(&curve), lines(&text));
    let head = input_lines
        .iter()
        .position(|l| l.starts_with("Frame Time"))
        .unwrap()
        + 1;
    let row = |v: &Vec<String>, f: usize| v[head + f].clone();
    for f in 41..=50 {
        assert_eq!(row(&m, f), row(&n, f), "frame {f}");
    }
    assert!(
        (41..=50).any(|f| row(&m, f) != row(&c, f)),
        "the network left the curve as it was"
    );
    for f in (0..300)
        .filter(|f| !(40..=51).contains(f) && !(100..=129).contains(f) && !(200..=204).contains(f))
    {
        assert_eq!(row(&m, f), row(&input_lines, f), "frame {f} changed");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A manifest without a band is refused when the CLI reads it, with the
/// file named.
#[test]
fn a_short_gap_manifest_without_a_band_is_a_clear_cli_error() {
    if models().is_none() {
        return;
    }
    let (dir, lib) = models_copy("fillmlp_noband");
    std::fs::copy(
        fixture_dir().join("tween_fill_mlp.onnx"),
        lib.join("tween_fill_mlp.onnx"),
    )
    .unwrap();
    let mut m: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(fixture_dir().join("tween_fill_mlp.manifest.json")).unwrap(),
    )
    .unwrap();
    m.as_object_mut().unwrap().remove("fill_up_to");
    m.as_object_mut().unwrap().remove("fill_from");
    std::fs::write(lib.join("tween_fill_mlp.manifest.json"), m.to_string()).unwrap();
    let input = dir.join("in.bvh");
    std::fs::write(&input, super::fill::clip_text(120)).unwrap();
    let (ok, _, err) = super::fill::fill_with(&dir, &lib, &input, &["40-51"], "model");
    assert!(!ok);
    assert!(
        err.contains("tween_fill_mlp.manifest.json") && err.contains("no band"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
