//! HairNet's bundled model: parity with onnxruntime, decoding, upsampling, the CLI.

use super::*;
use deeprep::hair::{HairModel, Reconstruct};

fn model() -> HairModel {
    HairModel::load_dir(&common::root().join("models/onnx")).expect("bundled hair models")
}

/// `deeprep hair reconstruct` is the library's `HairJob`: the CLI's
/// float32 strands are the job's, bit for bit, and the summary says so.
#[test]
fn the_cli_reconstruction_is_the_hair_job() {
    use deeprep::hair::{HairInput, HairJob, TestHair};
    let tmp = std::env::temp_dir().join(format!("deeprep-hair-cli-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let out = tmp.join("s.f32");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
        .args([
            "hair",
            "reconstruct",
            "--class",
            "m-curly",
            "--seed",
            "3",
            "--yaw",
            "20",
        ])
        .args(["--strands", "300", "--out", out.to_str().unwrap()])
        .current_dir(common::root())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["strands"], 300);
    let bytes = std::fs::read(&out).unwrap();
    let job = HairJob {
        input: HairInput::Test {
            hair: TestHair::named("M-curly", 3).unwrap(),
            yaw_deg: 20.0,
        },
        reconstruct: Reconstruct {
            strands: 300,
            ..Default::default()
        },
    };
    let r = job.run(&model(), &Body::default()).unwrap();
    let want: Vec<u8> = r
        .strands
        .points
        .iter()
        .flat_map(|p| p.iter().flat_map(|v| v.to_le_bytes()))
        .collect();
    assert_eq!(bytes, want);
    let e = summary["collision_error"].as_f64().unwrap();
    assert!(
        (e - r.collision_error as f64).abs() <= 1e-6 * (1.0 + e.abs()),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&tmp);
}

/// tract matches onnxruntime on both graphs, and the Rust decoding reads
/// the strand heads' output layout as the export wrote it.
#[test]
fn hair_graphs_match_onnxruntime_and_decode_in_layout() {
    common::fixture_parity("hair_features", 1e-4);
    common::fixture_parity("hair_strands", 1e-4);
    let m = model();
    let f = common::fixture("hair_strands");
    let shape = common::sizes(&f["input_shape"]);
    let (c, k) = (shape[1], shape[2]);
    assert_eq!(c, m.channels());
    let chw = common::floats(&f["input"]);
    let mut feats = vec![0.0f32; k * c];
    for i in 0..k {
        for ch in 0..c {
            feats[i * c + ch] = chw[ch * k + i];
        }
    }
    let (pts, curv) = m.decode(&feats, k).unwrap();
    assert_eq!(pts.len(), k * POINTS);
    assert_eq!(curv.len(), k * POINTS);
    let ort = common::floats(&f["output_onnxruntime"]);
    let manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(common::root().join("models/onnx/hair_features.manifest.json"))
            .unwrap(),
    )
    .unwrap();
    let scale = manifest["decoding"]["pos_scale"].as_f64().unwrap() as f32;
    for i in 0..k {
        for j in 0..POINTS {
            for a in 0..3 {
                let want = ort[(3 * j + a) * k + i] * scale;
                assert!(
                    (pts[i * POINTS + j][a] - want).abs() < 1e-4,
                    "strand {i} point {j} axis {a}"
                );
            }
        }
    }
    assert!(m.decode(&feats[1..], k).is_err());
    assert!(m.features(&[0.0; 10]).is_err());
}

/// Upsampled features at the grid's own cell centres give the grid's
/// strands; 30K strands decode to finite points on the scalp.
#[test]
fn upsampling_agrees_with_the_grid_and_scales_to_30k_strands() {
    let m = model();
    let mut rng = Rng::new(4);
    let st = Style::random(
        HairClass {
            length: Length::L,
            curl: Curl::Wavy,
        },
        &mut rng,
    );
    let body = Body::default();
    let h = Hair::generate(&st, &Scalp::default(), &body, GRID, &mut rng).unwrap();
    let img = render(&h.points, &body, &View::default(), 256, &mut rng)
        .unwrap()
        .image;
    let feats = m.features(&img).unwrap();
    let raw = Reconstruct {
        strands: GRID * GRID,
        smooth_sigma: 0.0,
        curl_threshold: f32::INFINITY,
    };
    let grid = m.strands_from_features(&feats, &raw).unwrap();
    let uv: Vec<(f32, f32)> = (0..GRID * GRID)
        .map(|i| Scalp::cell_uv(i % GRID, i / GRID, GRID))
        .collect();
    let up = upsample::upsample(&feats, m.channels(), GRID, &uv).unwrap();
    let (local, _) = m.decode(&up, uv.len()).unwrap();
    for (i, &(u, v)) in uv.iter().enumerate() {
        let (root, _) = m.scalp().root(u, v);
        for j in [0, 50, 99] {
            let p = grid.points[i * POINTS + j];
            let q = local[i * POINTS + j];
            for a in 0..3 {
                assert!((p[a] - (q[a] + root[a])).abs() < 1e-5);
            }
        }
    }
    let dense = m
        .strands_from_features(&feats, &Reconstruct::default())
        .unwrap();
    assert_eq!(dense.points.len(), 30_000 * POINTS);
    assert!(dense.points.iter().all(|p| p.iter().all(|v| v.is_finite())));
    assert!(m
        .strands_from_features(
            &feats,
            &Reconstruct {
                strands: 0,
                ..Default::default()
            }
        )
        .is_err());
    let b = deeprep::hair::blend_features(&feats, &vec![0.0; feats.len()], 0.5).unwrap();
    assert!((b[7] - 0.5 * feats[7]).abs() < 1e-7);
}

/// The WGSL compute decoder agrees with tract on 30K upsampled strands
/// (Vulkan through Mesa's lavapipe in CI).
#[test]
fn gpu_decode_matches_the_cpu() {
    let m = model();
    let mut h = deeprep::viewer::headless::Headless::new_compute()
        .expect("a wgpu adapter (setup.sh installs Mesa's lavapipe)");
    let gpu = match deeprep::hair::gpu::GpuStrandDecoder::new(h.device(), m.head_weights()) {
        Ok(g) => g,
        Err(e) => {
            eprintln!("SKIP: {e} (adapter {})", h.adapter);
            return;
        }
    };
    let _ = &mut h;
    let mut rng = Rng::new(9);
    let st = Style::random(
        HairClass {
            length: Length::M,
            curl: Curl::Curly,
        },
        &mut rng,
    );
    let body = Body::default();
    let hair = Hair::generate(&st, &Scalp::default(), &body, GRID, &mut rng).unwrap();
    let img = render(&hair.points, &body, &View::default(), 256, &mut rng)
        .unwrap()
        .image;
    let feats = m.features(&img).unwrap();
    let uv = HairModel::strand_uv(30_000);
    let up = upsample::upsample(&feats, m.channels(), GRID, &uv).unwrap();
    let t0 = std::time::Instant::now();
    let (cpu_p, cpu_c) = m.decode(&up, uv.len()).unwrap();
    let cpu_ms = t0.elapsed().as_secs_f64() * 1e3;
    let t1 = std::time::Instant::now();
    let (pos, curv) = gpu
        .decode_blocking(h.device(), h.queue(), &up, uv.len())
        .unwrap();
    let gpu_ms = t1.elapsed().as_secs_f64() * 1e3;
    let (gpu_p, gpu_c) = m.outputs_to_strands(&pos, &curv, uv.len()).unwrap();
    let dp = cpu_p
        .iter()
        .zip(&gpu_p)
        .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0f32, f32::max))
        .fold(0.0f32, f32::max);
    let dc = cpu_c
        .iter()
        .zip(&gpu_c)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    eprintln!("30K strands: CPU (tract) {cpu_ms:.0} ms, GPU ({}) {gpu_ms:.0} ms; max difference {dp:.2e} m, {dc:.2e} 1/m", h.adapter);
    assert!(dp < 1e-4, "positions differ by {dp} m");
    assert!(dc < 1e-2, "curvatures differ by {dc} / m");
    assert!(gpu
        .dispatch(h.device(), h.queue(), &up[1..], uv.len())
        .is_err());
}

/// The bundled model on fresh procedural hairs (seeds never generated
/// for training): strands land closer to the truth than two baselines,
/// all points at their roots, and the mean training-style hair shape
/// (straight down from each root for the class' typical length).
#[test]
fn the_bundled_model_beats_simple_baselines() {
    let m = model();
    let body = Body::default();
    let opts = Reconstruct {
        strands: GRID * GRID,
        smooth_sigma: 0.0,
        curl_threshold: f32::INFINITY,
    };
    let (mut model_d, mut root_d, mut down_d, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for (k, class) in [
        (Length::S, Curl::Straight),
        (Length::M, Curl::Wavy),
        (Length::L, Curl::Curly),
        (Length::XL, Curl::Straight),
    ]
    .into_iter()
    .enumerate()
    {
        let class = HairClass {
            length: class.0,
            curl: class.1,
        };
        let mut rng = Rng::new(1_000_003 + k as u64);
        let st = Style::random(class, &mut rng);
        let h = Hair::generate(&st, &Scalp::default(), &body, GRID, &mut rng).unwrap();
        let img = render(&h.points, &body, &View::random(&mut rng), 256, &mut rng)
            .unwrap()
            .image;
        let r = m.reconstruct(&img, &opts).unwrap();
        let len = class.typical_length();
        for (i, (p, q)) in r.points.iter().zip(&h.points).enumerate() {
            let root = h.roots[i / POINTS];
            let j = (i % POINTS) as f32 / (POINTS - 1) as f32;
            let d = |a: [f32; 3]| (0..3).map(|c| (a[c] - q[c]).powi(2)).sum::<f32>().sqrt() as f64;
            model_d += d(*p);
            root_d += d(root);
            down_d += d([root[0], root[1] - j * len, root[2]]);
            n += 1;
        }
    }
    let (md, rd, dd) = (model_d / n as f64, root_d / n as f64, down_d / n as f64);
    eprintln!(
        "mean distance to the truth: model {:.2} cm, roots only {:.2} cm, straight down {:.2} cm",
        md * 100.0,
        rd * 100.0,
        dd * 100.0
    );
    assert!(
        md < 0.6 * rd && md < 0.8 * dd,
        "model {md}, roots {rd}, down {dd}"
    );
}
