//! The model runtime: ONNX models run by tract, natively and in wasm.
//!
//! A [`Model`] is parsed once. Models with a symbolic axis (for example a
//! frame count) are kept typed but unoptimized; each request fixes the
//! symbols and optimizes a plan for that shape (a few ms), which runs as fast
//! as a model exported with a fixed shape. Plans are kept per shape (the
//! [`MAX_SHAPE_PLANS`] most recently used).
//!
//! Optimizing a plan costs more than running it (the in-betweening
//! generator: 40 ms to optimize, 3 ms to run 64 frames natively; in a
//! browser worker, a 60-frame synthesis took 32 ms warm and 300 ms on its
//! first request), so a page's first request of each length would wait for
//! it. [`Model::prepare_any_shape`] builds once a plan optimized with the
//! symbols left free, which then serves every shape: natively it runs
//! 1.3-1.45x the time of a shape's own plan (the generator at 64 to 640
//! frames, `examples/plan_probe.rs`), in the browser worker a 60-frame
//! synthesis took 35 ms against 32 ms. A shape's own plan can still be
//! built later, when the caller is idle ([`Model::prepare_shape`]), and then
//! serves that shape; the residual network's runs 11-18% faster in wasm
//! at 2,048-4,096 frames.

use crate::error::{Error, Result};
use std::collections::HashMap;
use std::sync::Mutex;
use tract_onnx::prelude::*;

pub mod matmul_kernel;
mod profile;
mod proto;

pub use profile::{per_op, NodeTime, OpTime};
use proto::fold_constant_matmuls;
pub use proto::{f16_to_f32, initializer_floats, read_proto};

type Plan = TypedSimplePlan;

/// Clears the upper halves of the x86-64 vector registers (`vzeroupper`)
/// after a tract operator has run. tract 0.23.9's x86-64 matrix kernels
/// (AVX and AVX-512 assembly, `tract-linalg/x86_64/*/postamble.j2`) return
/// without `vzeroupper`, and until one runs, every SSE instruction (our
/// Rust code, built for baseline x86-64, and glibc's `atan2` wrapper) pays
/// the AVX-SSE transition penalty: `Motion::to_bvh` of 2,048 frames
/// (88,064 matrix-to-Euler conversions) took 85-89 ms after one
/// residual-network run by tract directly, against 15 ms before any
/// network and 15 ms after the same run through [`Model::run`] (`cargo run
/// --release --example vector_state`, on an AVX-512 machine). A no-op
/// elsewhere (wasm, other architectures, CPUs without AVX).
#[inline]
fn clear_upper_vector_state() {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: `zeroupper` needs AVX, which the CPU was just found to have.
        unsafe { zeroupper() }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn zeroupper() {
    std::arch::x86_64::_mm256_zeroupper();
}

/// The most plans of particular input shapes a [`Model`] keeps, least
/// recently used dropped first: each holds its own packed copy of the
/// weights (the residual network's is 3.7 MB), so a caller that runs many
/// lengths must not grow memory by one plan per length.
pub const MAX_SHAPE_PLANS: usize = 4;

/// Plans of particular input shapes, the most recently used last.
type ShapePlans = Vec<(Vec<Vec<usize>>, std::sync::Arc<Plan>)>;

/// A loaded ONNX model.
pub struct Model {
    typed: TypedModel,
    plans: Mutex<ShapePlans>,
    /// The plan for any shape ([`Model::prepare_any_shape`]).
    any_shape: Mutex<Option<std::sync::Arc<Plan>>>,
}

fn model_err(e: impl std::fmt::Display) -> Error {
    Error::Model(format!("{e}"))
}

/// Runs tract's ONNX import, turning a panic inside tract (it has some on
/// malformed protobuf, e.g. tract-onnx model.rs:187) into an error.
/// Natively the panic unwinds and is caught here; in wasm (panic = abort)
/// it cannot be caught, which is why the JS client loads models in a
/// worker that it rebuilds after a trap.
fn guard_tract<T>(f: impl FnOnce() -> Result<T>) -> Result<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|p| {
        let what = p
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| p.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        Err(Error::Model(format!(
            "the ONNX file is malformed (tract panicked: {what})"
        )))
    })
}

/// Reads `dir/name` (a model or manifest file), naming the path in the
/// error; the models' `load_dir` functions share it.
pub fn read_file(dir: &std::path::Path, name: &str) -> Result<Vec<u8>> {
    std::fs::read(dir.join(name))
        .map_err(|e| Error::Invalid(format!("{}: {e}", dir.join(name).display())))
}

/// A dense f32 tensor: data plus shape.
#[derive(Clone, Debug, PartialEq)]
pub struct TensorF32 {
    /// Row-major data.
    pub data: Vec<f32>,
    /// Shape.
    pub shape: Vec<usize>,
}

impl TensorF32 {
    /// Builds a tensor, checking that the data fits the shape.
    pub fn new(data: Vec<f32>, shape: Vec<usize>) -> Result<Self> {
        let n: usize = shape.iter().product();
        if n != data.len() {
            return Err(Error::Shape {
                what: "tensor".into(),
                expected: format!("{n} numbers for shape {shape:?}"),
                found: format!("{}", data.len()),
            });
        }
        Ok(TensorF32 { data, shape })
    }
}

impl Model {
    /// Parses an ONNX model from its bytes. Weights stored as float16 behind
    /// a `Cast` to float (how the bundled models ship, see
    /// [`read_proto`]) are widened to float32 first.
    pub fn from_onnx_bytes(bytes: &[u8]) -> Result<Self> {
        Self::from_proto_with(bytes, |_| Ok(0)).map(|(m, _)| m)
    }

    /// Parses an ONNX model and multiplies out every `MatMul` of two 2-D
    /// float initializers, so the product is a constant of the model. This
    /// is for weights exported in factored form (the mesh autoencoder's
    /// vcConv kernels W = A·B, Sec. 2.2.2: small to download, large once
    /// multiplied). tract itself keeps such a product unfolded, since it is
    /// larger than its factors, and recomputes it on every run; folding
    /// trades that time for the product's memory. Returns the model and the
    /// number of products folded.
    pub fn from_onnx_bytes_folding_factors(bytes: &[u8]) -> Result<(Self, usize)> {
        Self::from_proto_with(bytes, fold_constant_matmuls)
    }

    /// [`read_proto`], then `edit` on the graph, then tract's import.
    fn from_proto_with(
        bytes: &[u8],
        edit: impl FnOnce(&mut tract_onnx::pb::GraphProto) -> Result<usize>,
    ) -> Result<(Self, usize)> {
        use tract_onnx::tract_core::framework::Framework;
        let (typed, n) = guard_tract(|| {
            let mut proto = read_proto(bytes)?;
            let n = match proto.graph.as_mut() {
                Some(g) => edit(g)?,
                None => 0,
            };
            let inference = tract_onnx::onnx()
                .model_for_proto_model(&proto)
                .map_err(model_err)?;
            Ok((inference.into_typed().map_err(model_err)?, n))
        })?;
        Ok((
            Model {
                typed,
                plans: Mutex::new(Vec::new()),
                any_shape: Mutex::new(None),
            },
            n,
        ))
    }

    /// Optimizes, once, a plan with the model's symbolic dimensions left
    /// free, which then runs every request, so that a new shape does not
    /// wait for a plan of its own (see the module's docs). For long-lived
    /// users (a page's worker); a process that runs one request, or one
    /// long shape many times, does better without it.
    /// Does nothing for a model without symbols. Returns whether a plan
    /// was built by this call.
    pub fn prepare_any_shape(&self) -> Result<bool> {
        let mut slot = self.any_shape.lock().map_err(model_err)?;
        if slot.is_some() || self.typed.symbols.all_symbols().is_empty() {
            return Ok(false);
        }
        matmul_kernel::choose()?;
        let plan = guard_tract(|| {
            self.typed
                .clone()
                .into_optimized()
                .map_err(model_err)?
                .into_runnable()
                .map_err(model_err)
        })?;
        *slot = Some(plan);
        Ok(true)
    }

    /// The matrix kernels (tract-linalg's names) the plan that runs inputs
    /// of these shapes uses, building it if needed: for benchmarks and tests
    /// of [`matmul_kernel`].
    pub fn matmul_kernels(&self, shapes: &[Vec<usize>]) -> Result<Vec<String>> {
        let plan = self.plan_for(shapes)?;
        Ok(matmul_kernel::plan_kernels(&plan))
    }

    /// Number of inputs.
    pub fn input_count(&self) -> usize {
        self.typed.inputs.len()
    }

    /// Runs the model on f32 inputs; returns every output as f32.
    pub fn run(&self, inputs: &[TensorF32]) -> Result<Vec<TensorF32>> {
        let (out, _) = self.run_plan(inputs, None)?;
        out.iter()
            .map(|v| {
                let t = v.cast_to::<f32>().map_err(model_err)?;
                let view = t.to_plain_array_view::<f32>().map_err(model_err)?;
                Ok(TensorF32 {
                    shape: view.shape().to_vec(),
                    data: view.iter().copied().collect(),
                })
            })
            .collect()
    }

    /// What [`Model::run`] and [`Model::profile`] share: the inputs checked
    /// (count, finite values), then what `plan.run` does (tract's own `eval`
    /// on each node in plan order), with the vector state cleared after each
    /// node (see `clear_upper_vector_state`; a no-op off x86-64) and, with a
    /// `clock` (milliseconds), each node timed.
    fn run_plan(
        &self,
        inputs: &[TensorF32],
        clock: Option<&dyn Fn() -> f64>,
    ) -> Result<(TVec<TValue>, Vec<NodeTime>)> {
        if inputs.len() != self.typed.inputs.len() {
            return Err(Error::Shape {
                what: "model inputs".into(),
                expected: format!("{} tensors", self.typed.inputs.len()),
                found: format!("{}", inputs.len()),
            });
        }
        for (i, t) in inputs.iter().enumerate() {
            crate::error::check_finite(&format!("model input {i}"), &t.data)?;
        }
        let (plan, tv) = self.plan_and_values(inputs)?;
        let mut times = Vec::new();
        let out = tract_onnx::tract_core::plan::SimpleState::new(&plan)
            .and_then(|mut state| {
                state.run_plan_with_eval(tv, |ctx, op_state, node, input| {
                    let t0 = clock.map(|c| c());
                    let r = tract_onnx::tract_core::plan::eval(ctx, op_state, node, input);
                    clear_upper_vector_state();
                    if let (Some(c), Some(t0)) = (clock, t0) {
                        let ms = c() - t0;
                        times.push(NodeTime {
                            node: node.name.clone(),
                            op: node.op().name().to_string(),
                            kernel: matmul_kernel::node_kernel(node),
                            ms,
                        });
                    }
                    r
                })
            })
            .map_err(model_err)?;
        Ok((out, times))
    }

    /// The plan for `inputs`' shapes and the inputs as tract values.
    fn plan_and_values(
        &self,
        inputs: &[TensorF32],
    ) -> Result<(std::sync::Arc<Plan>, TVec<TValue>)> {
        let key: Vec<Vec<usize>> = inputs.iter().map(|t| t.shape.clone()).collect();
        let plan = self.plan_for(&key)?;
        let tv: TVec<TValue> = inputs
            .iter()
            .map(|t| {
                Tensor::from_shape(&t.shape, &t.data)
                    .map(|t| t.into_tvalue())
                    .map_err(model_err)
            })
            .collect::<Result<_>>()?;
        Ok((plan, tv))
    }

    /// One run on `inputs` with every node timed by `clock` (milliseconds),
    /// in plan order: tract's own plan, evaluated node by node through
    /// `run_plan_with_eval` (what tract's profiler does), so the times add up
    /// to about one [`Model::run`].
    pub fn profile(&self, inputs: &[TensorF32], clock: &dyn Fn() -> f64) -> Result<Vec<NodeTime>> {
        self.run_plan(inputs, Some(clock)).map(|(_, times)| times)
    }

    /// Checks the request's shapes against the inputs' (ranks, fixed
    /// sizes) and returns the values they give the symbols.
    fn check_shapes(&self, shapes: &[Vec<usize>]) -> Result<HashMap<Symbol, TDim>> {
        // Fix every symbolic input dimension from the request's shapes.
        let mut values: HashMap<Symbol, TDim> = HashMap::new();
        for (ix, shape) in shapes.iter().enumerate() {
            let outlet = self.typed.inputs[ix];
            let fact = self.typed.outlet_fact(outlet).map_err(model_err)?.clone();
            if fact.rank() != shape.len() {
                return Err(Error::Shape {
                    what: format!("model input {ix}"),
                    expected: format!("rank {} ({:?})", fact.rank(), fact.shape),
                    found: format!("{shape:?}"),
                });
            }
            for (d, want) in fact.shape.iter().zip(shape) {
                match d.to_i64() {
                    Ok(v) if v as usize != *want => {
                        return Err(Error::Shape {
                            what: format!("model input {ix}"),
                            expected: format!("{:?}", fact.shape),
                            found: format!("{shape:?}"),
                        })
                    }
                    Ok(_) => {}
                    Err(_) => {
                        for s in d.symbols() {
                            values.insert(s, TDim::Val(*want as i64));
                        }
                    }
                }
            }
        }
        Ok(values)
    }

    /// Optimizes and keeps the plan of one set of input shapes, which then
    /// runs requests of those shapes instead of the plan for any shape
    /// ([`Model::prepare_any_shape`]). With concrete shapes tract picks
    /// kernels it cannot for a symbolic length: in wasm the residual
    /// network's dilated convolutions read their input in place (tract's
    /// lazy im2col) instead of copying it out first, 11-18% faster at 2,048
    /// and 4,096 frames in headless Chromium (0-13% at 1,024, where part of
    /// it stays eager), but the plan costs 100-360 ms
    /// to build there: a worker builds it when idle, after a request of that
    /// length. A new plan then runs once on zeros: in wasm the kernels it
    /// picks for these shapes may not have run yet, and V8 runs a function's
    /// first calls on its baseline compiler's code, so the first real
    /// request on a plan took up to 2x the next ones (1,024 frames in headless
    /// Chromium: 116-154 ms against 55-79). Returns whether a plan was built
    /// (false when it is kept already). At most [`MAX_SHAPE_PLANS`] are kept.
    pub fn prepare_shape(&self, shapes: &[Vec<usize>]) -> Result<bool> {
        if self.cached_plan(shapes)?.is_some() {
            return Ok(false);
        }
        self.build_plan(shapes)?;
        let zeros = shapes
            .iter()
            .map(|s| {
                let n = s.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
                let n = n.ok_or_else(|| Error::Invalid(format!("input shape {s:?} overflows")))?;
                TensorF32::new(vec![0.0; n], s.clone())
            })
            .collect::<Result<Vec<_>>>()?;
        self.run(&zeros)?;
        Ok(true)
    }

    /// The kept plan of these shapes, marked most recently used.
    fn cached_plan(&self, shapes: &[Vec<usize>]) -> Result<Option<std::sync::Arc<Plan>>> {
        let mut plans = self.plans.lock().map_err(model_err)?;
        let Some(i) = plans.iter().position(|(k, _)| k.as_slice() == shapes) else {
            return Ok(None);
        };
        let hit = plans.remove(i);
        let plan = hit.1.clone();
        plans.push(hit);
        Ok(Some(plan))
    }

    fn plan_for(&self, shapes: &[Vec<usize>]) -> Result<std::sync::Arc<Plan>> {
        if let Some(p) = self.cached_plan(shapes)? {
            return Ok(p);
        }
        if let Some(plan) = self.any_shape.lock().map_err(model_err)?.as_ref() {
            self.check_shapes(shapes)?;
            return Ok(plan.clone());
        }
        self.build_plan(shapes)
    }

    /// Optimizes and caches the plan of one shape.
    fn build_plan(&self, shapes: &[Vec<usize>]) -> Result<std::sync::Arc<Plan>> {
        let values = self.check_shapes(shapes)?;
        matmul_kernel::choose()?;
        let mut m = self.typed.clone();
        if !values.is_empty() {
            m = m.set_symbols(&values).map_err(model_err)?;
        }
        let plan = m
            .into_optimized()
            .map_err(model_err)?
            .into_runnable()
            .map_err(model_err)?;
        let mut plans = self.plans.lock().map_err(model_err)?;
        if plans.len() >= MAX_SHAPE_PLANS {
            plans.remove(0);
        }
        plans.push((shapes.to_vec(), plan.clone()));
        Ok(plan)
    }
}

/// The bundled path predictor (input [1, 171, frames]) for the tests that
/// run a real model; `None`, with a SKIP line, where models/ is absent.
#[cfg(test)]
fn bundled_tween_path() -> Option<Model> {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/onnx/tween_path.onnx");
    match std::fs::read(&path) {
        Ok(bytes) => Some(Model::from_onnx_bytes(&bytes).unwrap()),
        Err(_) => {
            eprintln!("SKIP: models/onnx/tween_path.onnx missing");
            None
        }
    }
}

#[cfg(test)]
mod profile_tests {
    use super::*;

    #[test]
    fn per_op_averages_runs_and_sorts_slowest_first() {
        let t = |node: &str, op: &str, ms: f64| NodeTime {
            node: node.into(),
            op: op.into(),
            kernel: None,
            ms,
        };
        let runs = vec![
            vec![
                t("a", "MatMul", 3.0),
                t("b", "Add", 1.0),
                t("c", "MatMul", 1.0),
            ],
            vec![
                t("a", "MatMul", 5.0),
                t("b", "Add", 1.0),
                t("c", "MatMul", 1.0),
            ],
        ];
        let ops = per_op(&runs);
        assert_eq!(ops.len(), 2);
        assert_eq!(
            (ops[0].op.as_str(), ops[0].ms, ops[0].nodes),
            ("MatMul", 5.0, 2)
        );
        assert_eq!(
            (ops[1].op.as_str(), ops[1].ms, ops[1].nodes),
            ("Add", 1.0, 1)
        );
        assert!((ops[0].share - 5.0 / 6.0).abs() < 1e-12);
        assert!(per_op(&[]).is_empty());
    }

    #[test]
    fn per_op_counts_products_on_different_kernels_apart() {
        let t = |op: &str, kernel: Option<&str>, ms: f64| NodeTime {
            node: String::new(),
            op: op.into(),
            kernel: kernel.map(str::to_string),
            ms,
        };
        let ops = per_op(&[vec![
            t("OptMatMul", Some("wasm_f32_8x8"), 1.0),
            t("OptMatMul", Some("deeprep_wasm_f32_3x12"), 4.0),
            t("OptMatMul", Some("wasm_f32_8x8"), 2.0),
            t("Add", None, 1.0),
        ]]);
        let got: Vec<_> = ops
            .iter()
            .map(|o| (o.op.as_str(), o.kernel.as_deref(), o.ms, o.nodes))
            .collect();
        assert_eq!(
            got,
            [
                ("OptMatMul", Some("deeprep_wasm_f32_3x12"), 4.0, 1),
                ("OptMatMul", Some("wasm_f32_8x8"), 3.0, 2),
                ("Add", None, 1.0, 1),
            ]
        );
        let json = serde_json::to_string(&ops[2]).unwrap();
        assert!(!json.contains("kernel"), "{json}");
    }

    #[test]
    fn profile_times_every_node_of_the_plan() {
        let Some(m) = bundled_tween_path() else {
            return;
        };
        let v: Vec<f32> = (0..171 * 32).map(|i| (i as f32 * 0.37).sin()).collect();
        let x = [TensorF32::new(v, vec![1, 171, 32]).unwrap()];
        let start = std::time::Instant::now();
        let clock = || start.elapsed().as_secs_f64() * 1e3;
        let times = m.profile(&x, &clock).unwrap();
        let plan = m.plan_for(&[vec![1, 171, 32]]).unwrap();
        let nodes = &plan.model().nodes;
        for t in &times {
            assert!(nodes.iter().any(|n| n.name == t.node), "{t:?}");
            assert!(t.ms >= 0.0 && t.ms.is_finite(), "{t:?}");
            // a kernel named exactly on the products
            assert_eq!(t.kernel.is_some(), t.op == "OptMatMul", "{t:?}");
        }
        assert!(times.iter().any(|t| t.kernel.is_some()), "no product timed");
        for &ix in plan.order_without_consts() {
            assert!(
                times.iter().any(|t| t.node == nodes[ix].name),
                "{} not timed",
                nodes[ix].name
            );
        }
        // the same checks as `run`
        assert!(m.profile(&[], &clock).is_err(), "input count");
        let mut bad = x[0].data.clone();
        bad[5] = f32::NAN;
        let bad = [TensorF32::new(bad, vec![1, 171, 32]).unwrap()];
        let e = m.profile(&bad, &clock).unwrap_err().to_string();
        assert!(e.contains("model input 0"), "{e}");
    }
}
