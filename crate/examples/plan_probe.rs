//! Plan costs of an ONNX model with a symbolic length axis: the time to
//! optimize a plan for one length against one plan for any length
//! (`runtime::Model::prepare_any_shape`), and their run times. Prints JSON.
//!
//!   cargo run --release --example plan_probe -- models/onnx/tween_generator.onnx [FRAMES...]
//!
//! Symbols named `frames` take each probed length; any other symbol
//! (the generator's `dna_frames`) takes 4.
use std::time::Instant;
use tract_onnx::prelude::*;

fn ms(t: Instant) -> f64 {
    (t.elapsed().as_secs_f64() * 1e4).round() / 10.0
}

fn main() -> TractResult<()> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "models/onnx/tween_generator.onnx".into());
    let bytes = std::fs::read(&path)?;
    let proto = deeprep::runtime::read_proto(&bytes).map_err(|e| TractError::msg(e.to_string()))?;
    let typed = tract_onnx::onnx()
        .model_for_proto_model(&proto)?
        .into_typed()?;
    let t = Instant::now();
    let any = typed.clone().into_optimized()?.into_runnable()?;
    let any_ms = ms(t);
    let size = |d: &TDim, n: usize| {
        d.to_i64()
            .map(|v| v as usize)
            .unwrap_or(if format!("{d}") == "frames" { n } else { 4 })
    };
    let mut rows = Vec::new();
    let lengths: Vec<usize> = std::env::args()
        .skip(2)
        .map(|a| {
            a.parse()
                .map_err(|_| TractError::msg(format!("not a frame count: {a}")))
        })
        .collect::<TractResult<_>>()?;
    let lengths = if lengths.is_empty() {
        vec![64, 128, 640]
    } else {
        lengths
    };
    for n in lengths {
        let mut values = std::collections::HashMap::new();
        for s in typed.symbols.all_symbols() {
            let v = if format!("{s}") == "frames" { n } else { 4 };
            values.insert(s, TDim::Val(v as i64));
        }
        let t = Instant::now();
        let own = typed
            .clone()
            .set_symbols(&values)?
            .into_optimized()?
            .into_runnable()?;
        let own_ms = ms(t);
        let inputs: TVec<TValue> = typed
            .inputs
            .iter()
            .map(|o| {
                let f = typed.outlet_fact(*o)?;
                let shape: Vec<usize> = f.shape.iter().map(|d| size(d, n)).collect();
                Ok(Tensor::zero::<f32>(&shape)?.into_tvalue())
            })
            .collect::<TractResult<_>>()?;
        // best of 5 runs each
        let best = |p: &std::sync::Arc<TypedSimplePlan>| -> TractResult<f64> {
            let mut b = f64::MAX;
            for _ in 0..5 {
                let t = Instant::now();
                p.run(inputs.clone())?;
                b = b.min(ms(t));
            }
            Ok(b)
        };
        rows.push(format!(
            "{{\"frames\": {n}, \"optimize_own_ms\": {own_ms}, \"run_own_ms\": {}, \"run_any_ms\": {}}}",
            best(&own)?,
            best(&any)?
        ));
    }
    println!(
        "{{\"bench\": \"plan_probe\", \"model\": {path:?}, \"optimize_any_ms\": {any_ms}, \"lengths\": [{}]}}",
        rows.join(", ")
    );
    Ok(())
}
