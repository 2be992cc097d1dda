//! HairNet timings in the style of Table 3.3 (JSON on stdout), natively and
//! with one thread: preprocessing (the Gabor orientation filter on a 256 ×
//! 256 photo with a hair mask), inference (image → strand features), and
//! reconstruction (upsampling, strand MLPs, smoothing and curl restoration)
//! at 1,024, 9,000 and 30,000 strands, plus the model files' sizes.
//! `DEEPREP_BENCH_SMOKE=1` runs each step once.

use deeprep::hair::orientation::{network_input, Gabor};
use deeprep::hair::*;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn time<T>(reps: usize, mut f: impl FnMut() -> T) -> f64 {
    let _ = f();
    median(
        (0..reps)
            .map(|_| {
                let t = Instant::now();
                let _ = f();
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect(),
    )
}

fn main() {
    let smoke = std::env::var("DEEPREP_BENCH_SMOKE").is_ok();
    let reps = if smoke { 1 } else { 5 };
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = root.join("models/onnx");
    let model = HairModel::load_dir(&dir).expect("bundled hair models");
    let body = Body::default();
    let mut rng = deeprep::rng::Rng::new(7);
    let style = Style::random(
        HairClass {
            length: Length::L,
            curl: Curl::Wavy,
        },
        &mut rng,
    );
    let hair = Hair::generate(&style, &Scalp::default(), &body, GRID, &mut rng).unwrap();
    let image = render(&hair.points, &body, &View::default(), 256, &mut rng)
        .unwrap()
        .image;
    // a "photo": the render's hair pixels as stripes of the rendered orientation
    let plane = 256 * 256;
    let grey: Vec<f32> = (0..plane)
        .map(|i| 0.5 + 0.5 * ((i % 256) as f32 * 1.5).sin())
        .collect();
    let mask: Vec<f32> = image[2 * plane..]
        .iter()
        .map(|&v| (v == 1.0) as u8 as f32)
        .collect();
    let pre = time(reps, || {
        network_input(&grey, &mask, None, 256, 256, &Gabor::default()).unwrap()
    });
    let inf = time(reps, || model.features(&image).unwrap());
    let feats = model.features(&image).unwrap();
    let mut recon = serde_json::Map::new();
    for n in [1024usize, 9000, 30000] {
        for (label, opts) in [
            (
                "straight",
                Reconstruct {
                    strands: n,
                    smooth_sigma: 1.5,
                    curl_threshold: f32::INFINITY,
                },
            ),
            (
                "with_curls",
                Reconstruct {
                    strands: n,
                    ..Default::default()
                },
            ),
        ] {
            let ms = time(reps, || model.strands_from_features(&feats, &opts).unwrap());
            recon.insert(format!("{n}_{label}_ms"), serde_json::json!(ms));
        }
    }
    let size = |n: &str| std::fs::metadata(dir.join(n)).map(|m| m.len()).unwrap_or(0);
    println!(
        "{}",
        serde_json::to_string_pretty(&serde_json::json!({
            "bench": "hair", "target": "native (tract, one thread)",
            "preprocessing_gabor_ms": pre, "inference_ms": inf, "reconstruction": recon,
            "storage_bytes": size("hair_features.onnx") + size("hair_strands.onnx"),
            "note": "reconstruction = bilinear feature upsampling + strand MLPs + Gaussian smoothing (+ curl restoration where the predicted curvature asks)",
        }))
        .unwrap()
    );
}
