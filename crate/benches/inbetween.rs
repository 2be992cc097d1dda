//! In-betweening benchmark: time per stage (generator, RC-FK, path,
//! post-processing with foot locking) for 512, 1024, 2048 and 4096 frames,
//! the residual network (the default for these whole-pose keys, at its
//! default variation, keys exact, no foot locking as in the page's bench)
//! when it is exported, and the SLERP+LERP baseline, printed as JSON beside
//! thesis Table 5.3.
//!
//!   cargo bench --bench inbetween                      full run
//!   DEEPREP_BENCH_SMOKE=1 cargo test --bench inbetween one 512-frame run (CI)

use deeprep::motion::baseline::slerp_lerp;
use deeprep::motion::pipeline::{Request, TweenModels};
use deeprep::motion::residual::ResidualModel;
use deeprep::motion::Keyframe;
use std::path::Path;
use std::time::Instant;

fn keys(m: &TweenModels, frames: usize) -> Vec<Keyframe> {
    // A key every 240 frames (4 s), from the rest pose turned and moved.
    let mut out = Vec::new();
    let mut f = 0;
    let mut i = 0;
    while f < frames {
        let mut b = m.template.clone();
        let mut ch = vec![0.0f32; b.channel_count()];
        ch[0] = 30.0 * i as f32;
        ch[1] = 85.0;
        ch[3] = 20.0 * i as f32;
        b.motion = ch;
        out.push(Keyframe::from_bvh(&b, 0, f).expect("rest pose"));
        f += 240;
        i += 1;
    }
    out
}

fn main() {
    let smoke = std::env::var("DEEPREP_BENCH_SMOKE").is_ok();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/onnx");
    if !dir.join("tween_generator.onnx").exists() {
        println!("{{\"skipped\": \"models/onnx/tween_generator.onnx is not exported\"}}");
        return;
    }
    let models = TweenModels::load_dir(&dir).expect("models load");
    let residual = dir
        .join("tween_residual.onnx")
        .exists()
        .then(|| ResidualModel::load_dir(&dir).expect("residual model loads"));
    let sizes: &[usize] = if smoke {
        &[512]
    } else {
        &[512, 1024, 2048, 4096]
    };
    let reps = if smoke { 1 } else { 3 };
    let mut rows = Vec::new();
    for &n in sizes {
        let req = Request {
            keys: keys(&models, n),
            frames: n,
            dna: None,
            post_process: true,
            foot_lock: Some(deeprep::motion::feet::FootLock::default()),
            variation: None,
        };
        // The first call at a length also optimizes tract's plan for it.
        let (first_ms, total_best, b) = first_and_best(reps, |start| {
            let clock = || start.elapsed().as_secs_f64() * 1e3;
            models.synthesize(&req, &clock).expect("synthesize").times
        });
        let t = Instant::now();
        for _ in 0..reps {
            slerp_lerp(&req.keys, n).expect("baseline");
        }
        let slerp_ms = t.elapsed().as_secs_f64() * 1e3 / reps as f64;
        // the residual network: first call at this length, then the best of reps
        let res = residual.as_ref().map(|r| {
            let v = r.info().variation;
            let (first, best, ()) = first_and_best(reps, |_| {
                r.synthesize(&req.keys, n, v).expect("residual");
            });
            format!(", \"residual_ms\": {best:.2}, \"residual_first_call_ms\": {first:.2}")
        });
        rows.push(format!(
            "{{\"frames\": {n}, \"generator_ms\": {:.2}, \"rcfk_ms\": {:.2}, \"path_ms\": {:.2}, \"post_ms\": {:.2}, \"total_ms\": {:.2}, \"first_call_ms\": {:.2}, \"slerp_lerp_ms\": {:.3}{}}}",
            b.generator_ms, b.rcfk_ms, b.path_ms, b.post_ms, total_best, first_ms, slerp_ms,
            res.unwrap_or_default()
        ));
    }
    println!(
        "{{\"bench\": \"inbetween\", \"target\": \"native\", \"threads\": 1, \"rows\": [\n  {}\n],\n \"thesis_table_5_3\": \"see README: the thesis reports GPU timings for its full-width model\"}}",
        rows.join(",\n  ")
    );
}

/// Times `run` once (the first call at a length, which also optimizes tract's plan
/// for it), then `reps` more times; returns the first call's milliseconds, the best
/// repeat's and that repeat's output. `run` gets the instant its call started.
fn first_and_best<T>(reps: usize, mut run: impl FnMut(Instant) -> T) -> (f64, f64, T) {
    let t = Instant::now();
    let mut best_out = run(t);
    let first = t.elapsed().as_secs_f64() * 1e3;
    let mut best = f64::MAX;
    for _ in 0..reps.max(1) {
        let t = Instant::now();
        let out = run(t);
        let ms = t.elapsed().as_secs_f64() * 1e3;
        if ms < best {
            best = ms;
            best_out = out;
        }
    }
    (first, best, best_out)
}
