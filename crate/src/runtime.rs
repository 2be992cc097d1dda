//! The model runtime: ONNX models run by tract, natively and in wasm.
//!
//! A [`Model`] is parsed once. Models with a symbolic axis (for example a
//! frame count) are kept typed but unoptimized; each request fixes the
//! symbols and optimizes a plan for that shape (a few ms), which runs as fast
//! as a model exported with a fixed shape. Plans are cached per shape.

use crate::error::{Error, Result};
use std::collections::HashMap;
use std::sync::Mutex;
use tract_onnx::prelude::*;

type Plan = TypedSimplePlan;

/// A loaded ONNX model.
pub struct Model {
    typed: TypedModel,
    plans: Mutex<HashMap<Vec<Vec<usize>>, std::sync::Arc<Plan>>>,
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
    /// Parses an ONNX model from its bytes.
    pub fn from_onnx_bytes(bytes: &[u8]) -> Result<Self> {
        let typed = guard_tract(|| {
            let mut r = bytes;
            let inference = tract_onnx::onnx()
                .model_for_read(&mut r)
                .map_err(model_err)?;
            inference.into_typed().map_err(model_err)
        })?;
        Ok(Model {
            typed,
            plans: Mutex::new(HashMap::new()),
        })
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
        use tract_onnx::tract_core::framework::Framework;
        let (typed, folded) = guard_tract(|| {
            let onnx = tract_onnx::onnx();
            let mut r = bytes;
            let mut proto = onnx.proto_model_for_read(&mut r).map_err(model_err)?;
            let folded = match proto.graph.as_mut() {
                Some(g) => fold_constant_matmuls(g)?,
                None => 0,
            };
            let inference = onnx.model_for_proto_model(&proto).map_err(model_err)?;
            Ok((inference.into_typed().map_err(model_err)?, folded))
        })?;
        Ok((
            Model {
                typed,
                plans: Mutex::new(HashMap::new()),
            },
            folded,
        ))
    }

    /// Number of inputs.
    pub fn input_count(&self) -> usize {
        self.typed.inputs.len()
    }

    /// Runs the model on f32 inputs; returns every output as f32.
    pub fn run(&self, inputs: &[TensorF32]) -> Result<Vec<TensorF32>> {
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
        let out = plan.run(tv).map_err(model_err)?;
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

    fn plan_for(&self, shapes: &[Vec<usize>]) -> Result<std::sync::Arc<Plan>> {
        if let Some(p) = self.plans.lock().map_err(model_err)?.get(shapes) {
            return Ok(p.clone());
        }
        let mut m = self.typed.clone();
        // Fix every symbolic input dimension from the request's shapes.
        let mut values: HashMap<Symbol, TDim> = HashMap::new();
        for (ix, shape) in shapes.iter().enumerate() {
            let outlet = m.inputs[ix];
            let fact = m.outlet_fact(outlet).map_err(model_err)?.clone();
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
        if !values.is_empty() {
            m = m.set_symbols(&values).map_err(model_err)?;
        }
        let plan = m
            .into_optimized()
            .map_err(model_err)?
            .into_runnable()
            .map_err(model_err)?;
        self.plans
            .lock()
            .map_err(model_err)?
            .insert(shapes.to_vec(), plan.clone());
        Ok(plan)
    }
}

/// The values of a 2-D float initializer, with its shape.
fn matrix(t: &tract_onnx::pb::TensorProto) -> Option<(usize, usize, Vec<f32>)> {
    const FLOAT: i32 = 1;
    if t.data_type != FLOAT || t.dims.len() != 2 || t.dims.iter().any(|&d| d < 0) {
        return None;
    }
    let (r, c) = (t.dims[0] as usize, t.dims[1] as usize);
    let v = initializer_floats(t);
    (v.len() == r * c).then_some((r, c, v))
}

/// The values of an ONNX float initializer, from `raw_data` (little-endian)
/// or `float_data`, whichever the exporter filled.
pub fn initializer_floats(t: &tract_onnx::pb::TensorProto) -> Vec<f32> {
    if !t.raw_data.is_empty() {
        t.raw_data
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    } else {
        t.float_data.clone()
    }
}

/// Replaces `MatMul(A, B)` of two 2-D float initializers by an initializer
/// holding the product; drops factors nothing else reads. Returns the count.
fn fold_constant_matmuls(g: &mut tract_onnx::pb::GraphProto) -> Result<usize> {
    let mut folded = 0;
    let nodes = std::mem::take(&mut g.node);
    let mut kept = Vec::with_capacity(nodes.len());
    for node in nodes {
        if node.op_type == "MatMul" && node.input.len() == 2 && node.output.len() == 1 {
            let find = |name: &str| {
                g.initializer
                    .iter()
                    .find(|t| t.name == name)
                    .and_then(matrix)
            };
            if let (Some((m, k, a)), Some((k2, n, b))) =
                (find(&node.input[0]), find(&node.input[1]))
            {
                if k != k2 {
                    return Err(Error::Model(format!(
                        "MatMul {}: factor shapes {m}×{k} and {k2}×{n} do not chain",
                        node.name
                    )));
                }
                let a = tract_ndarray::Array2::from_shape_vec((m, k), a).map_err(model_err)?;
                let b = tract_ndarray::Array2::from_shape_vec((k, n), b).map_err(model_err)?;
                let w = a.dot(&b);
                g.initializer.push(tract_onnx::pb::TensorProto {
                    name: node.output[0].clone(),
                    dims: vec![m as i64, n as i64],
                    data_type: 1,
                    raw_data: w.iter().flat_map(|v| v.to_le_bytes()).collect(),
                    ..Default::default()
                });
                folded += 1;
                continue;
            }
        }
        kept.push(node);
    }
    g.node = kept;
    let used: std::collections::HashSet<&str> = g
        .node
        .iter()
        .flat_map(|n| n.input.iter().map(|s| s.as_str()))
        .chain(g.output.iter().map(|o| o.name.as_str()))
        .collect::<std::collections::HashSet<_>>();
    let used: std::collections::HashSet<String> = used.into_iter().map(String::from).collect();
    let dropped: std::collections::HashSet<String> = g
        .initializer
        .iter()
        .filter(|t| !used.contains(&t.name))
        .map(|t| t.name.clone())
        .collect();
    g.initializer.retain(|t| !dropped.contains(&t.name));
    // Exports that list initializers as graph inputs too.
    g.input.retain(|i| !dropped.contains(&i.name));
    Ok(folded)
}
