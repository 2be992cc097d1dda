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
        let mut r = bytes;
        let inference = tract_onnx::onnx()
            .model_for_read(&mut r)
            .map_err(model_err)?;
        let typed = inference.into_typed().map_err(model_err)?;
        Ok(Model {
            typed,
            plans: Mutex::new(HashMap::new()),
        })
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
