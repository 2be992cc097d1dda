//! The AVX-SSE transition penalty after tract's x86-64 matrix kernels
//! (issue 23, "the native RC-FK anomaly"): `Motion::to_bvh` of the same
//! 2,048 frames (43 rotating joints: 88,064 matrix-to-Euler conversions)
//! timed before any network has run, after the residual network run by tract
//! directly (`SimplePlan::run`, whose AVX/AVX-512 kernels return without
//! `vzeroupper`), and after the same network run by `runtime::Model::run`
//! (which clears the upper vector state after every operator). Best of 5
//! each. Prints JSON.
//!
//!   cargo run --release --example vector_state
use deeprep::motion::baseline::slerp_lerp;
use deeprep::motion::residual::ResidualModel;
use deeprep::motion::{Keyframe, Motion};
use deeprep::skeleton::pose::rotation_order;
use std::path::Path;
use std::time::Instant;
use tract_onnx::prelude::*;

fn main() -> TractResult<()> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/onnx");
    let bytes = std::fs::read(dir.join("tween_residual.onnx"))?;
    let residual = ResidualModel::load_dir(&dir).map_err(|e| TractError::msg(e.to_string()))?;
    let template = &residual.template;
    let n = 2048;
    // whole-pose keys every 240 frames: the rest pose turned and moved
    let keys: Vec<Keyframe> = (0..n)
        .step_by(240)
        .enumerate()
        .map(|(i, f)| {
            let mut b = template.clone();
            let mut ch = vec![0.0f32; b.channel_count()];
            ch[0] = 30.0 * i as f32;
            ch[1] = 85.0;
            ch[3] = 20.0 * i as f32;
            b.motion = ch;
            Keyframe::from_bvh(&b, 0, f).expect("rest pose")
        })
        .collect();
    let motion = slerp_lerp(&keys, n).map_err(|e| TractError::msg(e.to_string()))?;
    // writing a BVH's angles: every rotating joint's matrix to Euler angles
    let to_bvh_ms = |m: &Motion| {
        (0..5)
            .map(|_| {
                let t = Instant::now();
                std::hint::black_box(m.to_bvh(template, 1.0 / 60.0).expect("to_bvh"));
                t.elapsed().as_secs_f64() * 1e3
            })
            .fold(f64::INFINITY, f64::min)
    };
    let before = to_bvh_ms(&motion);
    // tract directly: the residual network's input shape, zeros
    let proto = deeprep::runtime::read_proto(&bytes).map_err(|e| TractError::msg(e.to_string()))?;
    let typed = tract_onnx::onnx()
        .model_for_proto_model(&proto)?
        .into_typed()?;
    let channels = typed.input_fact(0)?.shape[1].to_i64()? as usize;
    let values = typed
        .symbols
        .all_symbols()
        .into_iter()
        .map(|s| (s, TDim::Val(n as i64)))
        .collect();
    let plan = typed
        .set_symbols(&values)?
        .into_optimized()?
        .into_runnable()?;
    let input = Tensor::zero::<f32>(&[1, channels, n])?;
    plan.run(tvec!(input.clone().into_tvalue()))?;
    let after_tract = to_bvh_ms(&motion);
    let model = deeprep::runtime::Model::from_onnx_bytes(&bytes)
        .map_err(|e| TractError::msg(e.to_string()))?;
    let x = deeprep::runtime::TensorF32::new(vec![0.0; channels * n], vec![1, channels, n])
        .map_err(|e| TractError::msg(e.to_string()))?;
    model
        .run(&[x])
        .map_err(|e| TractError::msg(e.to_string()))?;
    let after_model = to_bvh_ms(&motion);
    println!(
        "{{\"conversions\": {}, \"before_any_network_ms\": {before:.2}, \"after_tract_plan_run_ms\": {after_tract:.2}, \"after_model_run_ms\": {after_model:.2}}}",
        motion.rotations.len() * (0..template.joints.len()).filter(|&j| rotation_order(template, j).is_some()).count()
    );
    Ok(())
}
