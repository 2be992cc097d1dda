//! Runs in headless Chromium (wasm-bindgen-test): the rotation library and
//! tract inside the browser, checked against native results.
#![cfg(target_arch = "wasm32")]

use deeprep::rotation::batch::{self, Repr};
use deeprep::runtime::{Model, TensorF32};
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

const ROT_FIXTURE: &str = include_str!("../fixtures/rotations_native.json");
const MODEL: &[u8] = include_bytes!("../../models/onnx/rot6d_autoencoder.onnx");
const MODEL_FIXTURE: &str = include_str!("../../models/onnx/fixtures/rot6d_autoencoder.json");

fn floats(v: &serde_json::Value) -> Vec<f32> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap() as f32)
        .collect()
}

#[wasm_bindgen_test]
fn rotation_batches_match_native_outputs() {
    let f: serde_json::Value = serde_json::from_str(ROT_FIXTURE).unwrap();
    let input = floats(&f["input_matrices"]);
    let outputs = f["outputs"].as_object().unwrap();
    assert!(outputs.len() >= 10);
    for (name, expected) in outputs {
        let got = batch::convert(Repr::Matrix, Repr::parse(name).unwrap(), &input).unwrap();
        let expected = floats(expected);
        assert_eq!(got.len(), expected.len(), "{name}");
        let diff = got
            .iter()
            .zip(&expected)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        // Rounding of sin/cos/atan2 may differ by an ulp between wasm's libm
        // and the native C library.
        assert!(diff < 1e-5, "{name}: wasm vs native max abs diff {diff}");
    }
}

#[wasm_bindgen_test]
fn rotation_errors_surface_in_wasm() {
    let e = batch::convert(Repr::SixD, Repr::Quat, &[0.0; 6]).unwrap_err();
    assert!(e.to_string().contains("degenerate"), "{e}");
    let e = deeprep::wasm::convert_rotations("6d", "nope", &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    assert!(e.is_err());
}

#[wasm_bindgen_test]
fn tract_runs_the_tiny_network_in_the_browser() {
    let f: serde_json::Value = serde_json::from_str(MODEL_FIXTURE).unwrap();
    let input = floats(&f["input"]);
    let shape: Vec<usize> = f["input_shape"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as usize)
        .collect();
    let expected = floats(&f["output_onnxruntime"]);
    let model = Model::from_onnx_bytes(MODEL).unwrap();
    let out = model.run(&[TensorF32::new(input, shape).unwrap()]).unwrap();
    let diff = out[0]
        .data
        .iter()
        .zip(&expected)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(diff <= 1e-5, "tract in Chromium vs onnxruntime: {diff}");
}
