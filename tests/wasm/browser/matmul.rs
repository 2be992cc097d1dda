//! deeprep's own wasm matrix kernel (runtime::matmul_kernel) against a naive product and tract's kernel.

use super::*;

/// A product by the naive triple loop: `w` (`m` x `k`) times `x` (`k` x `n`).
fn naive_product(w: &[f32], x: &[f32], m: usize, k: usize, n: usize) -> Vec<f32> {
    let mut y = vec![0.0f32; m * n];
    for r in 0..m {
        for c in 0..n {
            y[r * n + c] = (0..k).map(|i| w[r * k + i] * x[i * n + c]).sum();
        }
    }
    y
}

/// deeprep's wasm matrix kernel (runtime::matmul_kernel) on products whose
/// sizes are not multiples of its 3x12 tile, against the naive product;
/// narrower products (under 64 columns) are left to tract's kernels.
#[wasm_bindgen_test]
fn the_own_matmul_kernel_computes_products_of_any_shape() {
    use deeprep::runtime::matmul_kernel::{
        gemm_plan, plan_kernels, run_gemm, set_policy, Policy, OWN_KERNEL,
    };
    set_policy(Policy::Own);
    let mut ran = Vec::new();
    for (m, k, n) in [
        (1, 1, 12),
        (3, 5, 12),
        (4, 7, 13),
        (7, 33, 25),
        (2, 3, 48),
        (112, 336, 100),
        (5, 4, 11),
        (40, 9, 30),
        (50, 1, 13),
        (200, 1, 64),
        (130, 65, 77),
        (67, 7, 130),
        (100, 19, 65),
    ] {
        let w: Vec<f32> = (0..m * k).map(|i| (i as f32 * 0.37).sin()).collect();
        let x: Vec<f32> = (0..k * n).map(|i| (i as f32 * 0.11).cos()).collect();
        let plan = gemm_plan(&w, m, k, n).unwrap();
        ran.push(((m, k, n), plan_kernels(&plan)));
        let y = run_gemm(&plan, &x, k, n).unwrap();
        let want = naive_product(&w, &x, m, k, n);
        let d = max_abs_diff(&y, &want);
        assert!(d <= 1e-5 * k as f32, "{m}x{k}x{n}: {d}");
    }
    set_policy(Policy::Auto);
    let own = |shape| {
        ran.iter()
            .any(|(s, k)| *s == shape && k.iter().any(|k| k == OWN_KERNEL))
    };
    let ours = ran.iter().filter(|(s, _)| own(*s)).count();
    // ours takes products of 64 columns or more (MIN_COLUMNS), whichever
    // way round tract puts them
    let wanted = [
        (112, 336, 100),
        (200, 1, 64),
        (130, 65, 77),
        (67, 7, 130),
        (100, 19, 65),
    ];
    assert!(
        wanted.iter().all(|s| own(*s)) && ours == wanted.len(),
        "{ran:?}"
    );
}

const MESH_ENCODER: &[u8] = include_bytes!("../../../models/onnx/mesh_encoder.onnx");
const MESH_DECODER: &[u8] = include_bytes!("../../../models/onnx/mesh_decoder.onnx");

/// Every bundled network gives the same outputs with deeprep's matrix kernel
/// as with tract's (their fused bias, activations, residual additions and
/// strided stores included), and runs it where its products are wide.
#[wasm_bindgen_test]
fn both_matmul_kernels_give_the_bundled_networks_the_same_outputs() {
    use deeprep::runtime::matmul_kernel::{set_policy, Policy, OWN_KERNEL};
    let cases: [(&str, &[u8], Vec<Vec<usize>>); 8] = [
        ("ik", IK_MODEL, vec![vec![64, 171]]),
        ("hair_strands", HAIR_STRANDS, vec![vec![1, 64, 128, 1]]),
        ("tween_path", TWEEN_PATH, vec![vec![1, 171, 128]]),
        (
            "tween_generator",
            TWEEN_GENERATOR,
            vec![vec![1, 342, 128], vec![1, 264, 128], vec![1, 2, 171]],
        ),
        ("tween_residual", TWEEN_RESIDUAL, vec![vec![1, 265, 128]]),
        ("hair_features", HAIR_FEATURES, vec![vec![1, 3, 256, 256]]),
        ("mesh_encoder", MESH_ENCODER, vec![vec![1, 1820, 3]]),
        ("mesh_decoder", MESH_DECODER, vec![vec![1, 8, 16]]),
    ];
    for (name, bytes, shapes) in cases {
        let inputs: Vec<TensorF32> = shapes
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let n: usize = s.iter().product();
                let v = (0..n)
                    .map(|j| ((j * 7 + i) as f32 * 0.013).sin() * 0.8)
                    .collect();
                TensorF32::new(v, s.clone()).unwrap()
            })
            .collect();
        let mut outs = Vec::new();
        for policy in [Policy::Tract, Policy::Own] {
            set_policy(policy);
            // the mesh autoencoder's factored weights multiplied out, as MeshCodec runs it
            let model = if name.starts_with("mesh") {
                Model::from_onnx_bytes_folding_factors(bytes).unwrap().0
            } else {
                Model::from_onnx_bytes(bytes).unwrap()
            };
            outs.push(model.run(&inputs).unwrap());
            let shapes: Vec<Vec<usize>> = inputs.iter().map(|t| t.shape.clone()).collect();
            let kernels = model.matmul_kernels(&shapes).unwrap();
            let own = kernels.iter().any(|k| k == OWN_KERNEL);
            // the mesh autoencoder's products are 1-32 columns: tract's kernels
            let wide = !name.starts_with("mesh");
            assert_eq!(own, wide && policy == Policy::Own, "{name}: {kernels:?}");
        }
        for (a, b) in outs[0].iter().zip(&outs[1]) {
            let scale = a.data.iter().fold(1.0f32, |s, v| s.max(v.abs()));
            let d = max_abs_diff(&a.data, &b.data);
            assert!(d <= 1e-5 * scale, "{name}: {d} (largest output {scale})");
        }
    }
    set_policy(Policy::Auto);
}

/// By default deeprep's kernel runs on x86-64 hosts (this machine's kind)
/// and tract's elsewhere; decided once.
#[wasm_bindgen_test]
fn the_matmul_kernel_is_chosen_by_the_host() {
    use deeprep::runtime::matmul_kernel::{
        choose, host_is_x86, set_policy, Policy, OWN_KERNEL, TRACT_KERNEL,
    };
    set_policy(Policy::Auto);
    let c = choose().unwrap();
    let want = if host_is_x86() {
        (OWN_KERNEL, "x86-64 host")
    } else {
        (TRACT_KERNEL, "other host")
    };
    assert_eq!((c.kernel, c.by), want);
    assert_eq!(choose().unwrap(), c, "decided once");
    set_policy(Policy::Tract);
    assert_eq!(choose().unwrap().kernel, TRACT_KERNEL);
    set_policy(Policy::Auto);
}
