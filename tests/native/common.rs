//! Helpers shared by the native tests: the repository root and the ONNX
//! fixtures written by the export scripts (train/export_*.py).
#![allow(dead_code)]

use deeprep::runtime::{Model, TensorF32};
use std::path::PathBuf;

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A JSON array of numbers as f32.
pub fn floats(v: &serde_json::Value) -> Vec<f32> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap() as f32)
        .collect()
}

/// A JSON array of numbers as f64.
pub fn doubles(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// A JSON array of non-negative integers (a shape).
pub fn sizes(v: &serde_json::Value) -> Vec<usize> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as usize)
        .collect()
}

/// `models/onnx/fixtures/<name>.json`, which must exist.
pub fn fixture(name: &str) -> serde_json::Value {
    let p = root().join(format!("models/onnx/fixtures/{name}.json"));
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_str(&text).unwrap()
}

/// Runs `models/onnx/<fixture model>` in tract on the fixture's inputs (the
/// multi-input `inputs` object, or the single `input`) and asserts that the
/// first output is within `tol` of onnxruntime's, with the shape's own
/// plan and with the plan for any shape. For outputs far above 1 the bound
/// is one millionth of the largest expected value when that is larger (a
/// float32 sum in another order differs by a few ulps of what it sums, and
/// an ulp grows with the value: 1.5e-5 at 130, where the residual network's
/// outputs reach, so the bound there is about 8 ulps); every fixture but
/// tween_residual's stays below 5, where `tol` is the bound.
pub fn fixture_parity(name: &str, tol: f32) {
    let f = fixture(name);
    let inputs: Vec<TensorF32> = match f["inputs"].as_object() {
        // in the graph's order (`input_order`; serde_json's map is sorted)
        Some(m) => match f["input_order"].as_array() {
            Some(order) => order
                .iter()
                .map(|n| &m[n.as_str().unwrap()])
                .collect::<Vec<_>>(),
            None => m.values().collect(),
        }
        .into_iter()
        .map(|v| TensorF32::new(floats(&v["data"]), sizes(&v["shape"])).unwrap())
        .collect(),
        None => vec![TensorF32::new(floats(&f["input"]), sizes(&f["input_shape"])).unwrap()],
    };
    let path = root()
        .join("models/onnx")
        .join(f["model"].as_str().unwrap());
    let bytes = std::fs::read(path).unwrap();
    let expected = floats(&f["output_onnxruntime"]);
    let tol = tol.max(1e-6 * expected.iter().fold(0.0f32, |m, x| m.max(x.abs())));
    let max_diff = |out: &[TensorF32]| {
        out[0]
            .data
            .iter()
            .zip(&expected)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max)
    };
    let model = Model::from_onnx_bytes(&bytes).unwrap();
    let diff = max_diff(&model.run(&inputs).unwrap());
    assert!(diff <= tol, "{name}: tract vs onnxruntime {diff}");
    // The plan optimized for any shape (what a page's worker prepares at
    // start); tests/native/motion.rs runs it on several lengths.
    let model = Model::from_onnx_bytes(&bytes).unwrap();
    if model.prepare_any_shape().unwrap() {
        let diff = max_diff(&model.run(&inputs).unwrap());
        assert!(diff <= tol, "{name}: any-shape plan vs onnxruntime {diff}");
    }
}

/// A 200-frame clip on `template` that walks along x at hip height 90 with
/// every joint swinging (the CLI tests' `--from-bvh` input), written to
/// `path` and returned.
pub fn write_walking_clip(
    template: &deeprep::skeleton::bvh::Bvh,
    path: &std::path::Path,
) -> deeprep::skeleton::bvh::Bvh {
    let mut clip = template.clone();
    let c = clip.channel_count();
    clip.motion = (0..200 * c)
        .map(|i| match i % c {
            0 => (i / c) as f32 * 0.5,
            1 => 90.0,
            k if k > 5 => ((i / c) as f32 / 20.0 + k as f32).sin() * 10.0,
            _ => 0.0,
        })
        .collect();
    std::fs::write(path, clip.write()).unwrap();
    clip
}
