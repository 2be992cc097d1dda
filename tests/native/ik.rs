//! IK from joint positions (Sec. 4.4.3): the bundled network in tract
//! against onnxruntime, the Rust decoder against the PyTorch FK layer, and
//! the solver's contract.

use deeprep::ik::IkModel;
use deeprep::skeleton::{fk, Bvh};

use crate::common;
use common::{floats, root};

fn fixture() -> serde_json::Value {
    common::fixture("ik")
}

fn model() -> IkModel {
    IkModel::load_dir(&root().join("models/onnx")).expect("the bundled IK model loads")
}

fn max_diff(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

#[test]
fn tract_matches_onnxruntime_and_the_decoder_matches_pytorch() {
    let m = model();
    let f = fixture();
    let x = floats(&f["input"]);
    let frames = f["input_shape"][0].as_u64().unwrap() as usize;
    let raw = m.run_raw(&x, frames).unwrap();
    let d = max_diff(&raw, &floats(&f["output_onnxruntime"]));
    assert!(d <= 1e-4, "tract vs onnxruntime: {d}");
    // The poses of the fixture have their hips at the origin, so the
    // solver's reconstruction is directly comparable with PyTorch's FK.
    let sol = m.solve(&x, frames).unwrap();
    let d = max_diff(&sol.positions, &floats(&f["reconstructed_positions_torch"]));
    assert!(d <= 2e-3, "Rust decode + FK vs PyTorch FK layer: {d} units");
}

#[test]
fn the_solution_sits_at_the_input_hips_and_reports_its_error() {
    let m = model();
    let f = fixture();
    let x = floats(&f["input"]);
    let frames = f["input_shape"][0].as_u64().unwrap() as usize;
    let j = m.joints();
    let at_origin = m.solve(&x, frames).unwrap();
    let shift = [120.0f32, 3.0, -75.0];
    let moved: Vec<f32> = x
        .iter()
        .enumerate()
        .map(|(i, v)| v + shift[i % 3])
        .collect();
    let sol = m.solve(&moved, frames).unwrap();
    for f in 0..frames {
        for a in 0..3 {
            assert!((sol.motion.root[f][a] as f32 - moved[f * j * 3 + a]).abs() < 1e-4);
        }
    }
    let back: Vec<f32> = sol
        .positions
        .iter()
        .enumerate()
        .map(|(i, v)| v - shift[i % 3])
        .collect();
    assert!(
        max_diff(&back, &at_origin.positions) < 1e-3,
        "translation changes the pose"
    );
    // The reported error is the mean joint distance, and it is not zero
    // (the network is not exact) but small against the skeleton's size.
    let mut sum = 0.0f64;
    for (a, b) in sol.positions.chunks(3).zip(moved.chunks(3)) {
        sum +=
            (((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)) as f64).sqrt();
    }
    let mean = sum / (frames * j) as f64;
    assert!((mean - sol.mean_error).abs() < 1e-6 * mean.max(1.0));
    assert!(sol.mean_error > 0.0 && sol.max_error >= sol.mean_error);
    // The BVH it writes reproduces the reconstruction.
    let bvh = m.solve_to_bvh(&moved, frames, 1.0 / 30.0).unwrap();
    assert_eq!(bvh.frame_count(), frames);
    let p = fk::positions(&Bvh::parse(&bvh.write()).unwrap(), 0, frames).unwrap();
    assert!(max_diff(&p, &sol.positions) < 1e-2);
}

#[test]
fn bad_inputs_are_clear_errors() {
    let m = model();
    let j = m.joints();
    let e = m.solve(&[], 0).unwrap_err().to_string();
    assert!(e.contains("no frames"), "{e}");
    let e = m.solve(&vec![0.0; j * 3 - 1], 1).unwrap_err().to_string();
    assert!(e.contains("IK positions"), "{e}");
    let mut x = vec![0.0; j * 3];
    x[7] = f32::NAN;
    let e = m.solve(&x, 1).unwrap_err().to_string();
    assert!(
        e.to_lowercase().contains("nan") || e.contains("finite"),
        "{e}"
    );
    let e = IkModel::new(&[1, 2, 3], "{}")
        .err()
        .expect("bad manifest")
        .to_string();
    assert!(e.contains("IK manifest"), "{e}");
}

/// On a validation take (never trained on): the solver's mean joint error
/// stays near the validation figure in the manifest.
#[test]
fn ik_on_a_validation_take() {
    let p = root().join("../shared/data/cmu-bvh/salsa/04.bvh");
    let Ok(text) = std::fs::read_to_string(&p) else {
        eprintln!("SKIP: ../shared/data/cmu-bvh/salsa/04.bvh is absent");
        return;
    };
    let clip = Bvh::parse(&text).unwrap();
    let m = model();
    let frames: Vec<usize> = (0..clip.frame_count()).step_by(25).collect();
    let mut x = Vec::new();
    for &f in &frames {
        x.extend(fk::positions(&clip, f, f + 1).unwrap());
    }
    let sol = m.solve(&x, frames.len()).unwrap();
    let manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("models/onnx/ik.manifest.json")).unwrap(),
    )
    .unwrap();
    let reported = manifest["training"]["validation"]["mean"].as_f64().unwrap();
    eprintln!(
        "salsa/04, {} frames: mean {:.2}, max {:.2} units (manifest: mean {reported:.2})",
        frames.len(),
        sol.mean_error,
        sol.max_error
    );
    assert!(
        sol.mean_error < 2.0 * reported + 0.5,
        "mean {:.2} vs validation {reported:.2}",
        sol.mean_error
    );
}
