//! The ONNX path: the tiny rotation network trained by
//! train/deeprep_train/sanity/tiny_rotation_mlp.py runs in tract and matches onnxruntime's saved
//! outputs (max abs diff <= 1e-5).

use deeprep::rotation::{geodesic_distance, Mat3};
use deeprep::runtime::{Model, TensorF32};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn load_fixture() -> (Vec<f32>, Vec<usize>, Vec<f32>, Vec<usize>) {
    let p = root().join("models/onnx/fixtures/rot6d_autoencoder.json");
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let f = |k: &str| -> Vec<f32> {
        v[k].as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap() as f32)
            .collect()
    };
    let s = |k: &str| -> Vec<usize> {
        v[k].as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_u64().unwrap() as usize)
            .collect()
    };
    (
        f("input"),
        s("input_shape"),
        f("output_onnxruntime"),
        s("output_shape"),
    )
}

fn model() -> Model {
    let bytes = std::fs::read(root().join("models/onnx/rot6d_autoencoder.onnx")).unwrap();
    Model::from_onnx_bytes(&bytes).unwrap()
}

#[test]
fn tract_matches_onnxruntime_on_the_tiny_rotation_network() {
    let (input, shape, expected, out_shape) = load_fixture();
    let m = model();
    let out = m.run(&[TensorF32::new(input, shape).unwrap()]).unwrap();
    assert_eq!(out[0].shape, out_shape);
    let diff = out[0]
        .data
        .iter()
        .zip(&expected)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(diff <= 1e-5, "tract vs onnxruntime max abs diff {diff}");
}

#[test]
fn the_tiny_network_is_trained_and_handles_other_batch_sizes() {
    let (input, _, _, _) = load_fixture();
    let m = model();
    // A batch size the fixture does not use exercises the symbolic batch axis.
    let n = 17;
    let x = input[..n * 9].to_vec();
    let out = m
        .run(&[TensorF32::new(x.clone(), vec![n, 9]).unwrap()])
        .unwrap();
    assert_eq!(out[0].shape, vec![n, 9]);
    for i in 0..n {
        let a: Mat3<f32> = std::array::from_fn(|r| std::array::from_fn(|c| x[i * 9 + r * 3 + c]));
        let b: Mat3<f32> =
            std::array::from_fn(|r| std::array::from_fn(|c| out[0].data[i * 9 + r * 3 + c]));
        let deg = geodesic_distance(&a, &b).to_degrees();
        // A trained autoencoder reconstructs within a few degrees; an
        // untrained one is off by tens of degrees.
        assert!(deg < 5.0, "rotation {i}: reconstruction error {deg}°");
    }
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    let m = model();
    let e = m
        .run(&[TensorF32::new(vec![0.0; 8], vec![1, 8]).unwrap()])
        .unwrap_err();
    assert!(e.to_string().contains("input 0"), "{e}");
    let e = m
        .run(&[TensorF32::new(vec![f32::NAN; 9], vec![1, 9]).unwrap()])
        .unwrap_err();
    assert!(e.to_string().contains("not finite"), "{e}");
    assert!(TensorF32::new(vec![0.0; 5], vec![2, 3]).is_err());
    assert!(Model::from_onnx_bytes(b"not an onnx file").is_err());
}
