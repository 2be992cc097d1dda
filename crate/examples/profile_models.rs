//! Where tract spends its time (issue 23): every bundled model on the
//! side-by-side bench's inputs (tests/web/bench_ort_page.mjs), each node of
//! tract's optimized plan timed natively (`runtime::Model::profile`), summed
//! per operator over 5 runs after a warm-up, printed as JSON.
//!
//!   cargo run --release --example profile_models [--runs N] [--models DIR]

use deeprep::rng::Rng;
use deeprep::runtime::{per_op, Model, TensorF32};
use std::path::Path;
use std::time::Instant;

/// [label, file, fold mesh factors, inputs (shape, value range)]
type Case = (
    &'static str,
    &'static str,
    bool,
    Vec<(Vec<usize>, f32, f32)>,
);

fn cases() -> Vec<Case> {
    vec![
        (
            "rot6d_autoencoder",
            "rot6d_autoencoder",
            false,
            vec![(vec![64, 9], -1.0, 1.0)],
        ),
        (
            "ik, batch 64",
            "ik",
            false,
            vec![(vec![64, 171], -1.0, 1.0)],
        ),
        (
            "hair_features, 256x256",
            "hair_features",
            false,
            vec![(vec![1, 3, 256, 256], 0.0, 1.0)],
        ),
        (
            "hair_strands, 1,024 strands",
            "hair_strands",
            false,
            vec![(vec![1, 64, 1024, 1], -1.0, 1.0)],
        ),
        (
            "mesh_encoder",
            "mesh_encoder",
            true,
            vec![(vec![1, 1820, 3], -1.0, 1.0)],
        ),
        (
            "mesh_decoder",
            "mesh_decoder",
            true,
            vec![(vec![1, 8, 16], -1.0, 1.0)],
        ),
        (
            "tween_path, 2048 frames",
            "tween_path",
            false,
            vec![(vec![1, 171, 2048], -1.0, 1.0)],
        ),
        (
            "tween_generator, 2048 frames",
            "tween_generator",
            false,
            vec![
                (vec![1, 342, 2048], -1.0, 1.0),
                (vec![1, 264, 2048], -1.0, 1.0),
                (vec![1, 11, 171], -1.0, 1.0),
            ],
        ),
        (
            "tween_residual, 2048 frames",
            "tween_residual",
            false,
            vec![(vec![1, 265, 2048], -1.0, 1.0)],
        ),
    ]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let runs: usize = args
        .iter()
        .position(|a| a == "--runs")
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(5);
    // --models DIR: profile the files of that folder instead (a graph rewrite
    // under test); models missing there are skipped
    let dir = args
        .iter()
        .position(|a| a == "--models")
        .and_then(|i| args.get(i + 1))
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/onnx"));
    let start = Instant::now();
    let clock = || start.elapsed().as_secs_f64() * 1e3;
    let mut rows = Vec::new();
    for (label, file, fold, inputs) in cases() {
        let Ok(bytes) = std::fs::read(dir.join(format!("{file}.onnx"))) else {
            continue;
        };
        let model = if fold {
            Model::from_onnx_bytes_folding_factors(&bytes)
                .expect("model")
                .0
        } else {
            Model::from_onnx_bytes(&bytes).expect("model")
        };
        let mut rng = Rng::new(7);
        let tensors: Vec<TensorF32> = inputs
            .iter()
            .map(|(shape, lo, hi)| {
                let n = shape.iter().product();
                let data = (0..n)
                    .map(|_| rng.range(*lo as f64, *hi as f64) as f32)
                    .collect();
                TensorF32::new(data, shape.clone()).expect("tensor")
            })
            .collect();
        model.run(&tensors).expect("warm-up");
        let mut runs_times = Vec::new();
        let mut best_run = f64::MAX;
        for _ in 0..runs {
            let t0 = clock();
            runs_times.push(model.profile(&tensors, &clock).expect("profile"));
            best_run = best_run.min(clock() - t0);
        }
        let ops = per_op(&runs_times);
        let total: f64 = ops.iter().map(|o| o.ms).sum();
        let top: Vec<String> = ops
            .iter()
            .take(6)
            .map(|o| {
                format!(
                    "{{\"op\": \"{}\", \"ms\": {:.3}, \"share\": {:.3}, \"nodes\": {}}}",
                    o.op, o.ms, o.share, o.nodes
                )
            })
            .collect();
        rows.push(format!(
            "  {{\"model\": \"{label}\", \"nodes_total_ms\": {total:.3}, \"best_profiled_run_ms\": {best_run:.3}, \"ops\": [{}]}}",
            top.join(", ")
        ));
    }
    println!(
        "{{\"profile\": \"tract 0.23.9, native, one thread, per operator (mean of {runs} runs)\", \"rows\": [\n{}\n]}}",
        rows.join(",\n")
    );
}
