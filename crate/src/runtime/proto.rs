//! ONNX protobuf surgery before tract sees a model: float16 weights widened
//! to float32, and constant matrix products folded once at load.

use super::{guard_tract, model_err};
use crate::error::{Error, Result};
use tract_onnx::prelude::tract_ndarray;

/// Parses ONNX bytes into their protobuf and widens float16 weights: every
/// `Cast(to = FLOAT)` whose input is a FLOAT16 initializer becomes a float32
/// initializer named after the cast's output (and the half-precision copy
/// is dropped when nothing else reads it). The bundled models store their
/// weights this way (train/deeprep_train/export/half_weights.py) to halve the download; any ONNX
/// runtime runs them as they are, and after this pass the rest of the crate
/// (tract, the factor folding, the hair heads' weight lookup) sees the
/// float32 model the weights were rounded from.
pub fn read_proto(bytes: &[u8]) -> Result<tract_onnx::pb::ModelProto> {
    use tract_onnx::tract_core::framework::Framework;
    let mut proto = guard_tract(|| {
        let mut r = bytes;
        tract_onnx::onnx()
            .proto_model_for_read(&mut r)
            .map_err(model_err)
    })?;
    if let Some(g) = proto.graph.as_mut() {
        widen_half_weights(g)?;
    }
    Ok(proto)
}

const FLOAT: i32 = 1;
const FLOAT16: i32 = 10;

/// See [`read_proto`]. Returns the number of initializers widened.
fn widen_half_weights(g: &mut tract_onnx::pb::GraphProto) -> Result<usize> {
    let nodes = std::mem::take(&mut g.node);
    let mut kept = Vec::with_capacity(nodes.len());
    let mut widened = 0;
    for node in nodes {
        let to_float = node.op_type == "Cast"
            && node.input.len() == 1
            && node.output.len() == 1
            && node
                .attribute
                .iter()
                .any(|a| a.name == "to" && a.i == FLOAT as i64);
        let half = to_float
            .then(|| {
                g.initializer
                    .iter()
                    .find(|t| t.name == node.input[0] && t.data_type == FLOAT16)
            })
            .flatten();
        match half {
            Some(t) => {
                let values = half_values(t)?;
                g.initializer.push(tract_onnx::pb::TensorProto {
                    name: node.output[0].clone(),
                    dims: t.dims.clone(),
                    data_type: FLOAT,
                    float_data: values,
                    ..Default::default()
                });
                widened += 1;
            }
            None => kept.push(node),
        }
    }
    g.node = kept;
    let read = read_names(g);
    g.initializer
        .retain(|t| t.data_type != FLOAT16 || read.contains(&t.name));
    Ok(widened)
}

/// The names the graph's nodes take as inputs, and its outputs: what an
/// initializer must be called to be used.
fn read_names(g: &tract_onnx::pb::GraphProto) -> std::collections::HashSet<String> {
    g.node
        .iter()
        .flat_map(|n| n.input.iter().cloned())
        .chain(g.output.iter().map(|o| o.name.clone()))
        .collect()
}

/// The values of a FLOAT16 initializer as f32, from `raw_data` (2 bytes
/// each, little-endian) or `int32_data` (one half per entry, ONNX's rule).
/// The count must match the dims.
fn half_values(t: &tract_onnx::pb::TensorProto) -> Result<Vec<f32>> {
    let bits: Vec<u16> = if !t.raw_data.is_empty() {
        t.raw_data
            .chunks_exact(2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]))
            .collect()
    } else {
        t.int32_data.iter().map(|&v| v as u16).collect()
    };
    let want = t.dims.iter().try_fold(1usize, |n, &d| {
        usize::try_from(d).ok().and_then(|d| n.checked_mul(d))
    });
    if want != Some(bits.len()) || !t.raw_data.len().is_multiple_of(2) {
        return Err(Error::Model(format!(
            "float16 initializer '{}': {} values for dims {:?}",
            t.name,
            bits.len(),
            t.dims
        )));
    }
    Ok(bits.into_iter().map(f16_to_f32).collect())
}

/// IEEE 754 binary16 to binary32, exact (subnormals, infinities, NaN kept).
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = ((h as u32) & 0x8000) << 16;
    let exp = ((h >> 10) & 0x1f) as u32;
    let man = (h & 0x3ff) as u32;
    let bits = match (exp, man) {
        (0, 0) => sign,
        (0, m) => {
            // subnormal: m * 2^-24
            let v = m as f32 * (1.0 / 16_777_216.0);
            return if sign != 0 { -v } else { v };
        }
        (0x1f, m) => sign | 0x7f80_0000 | (m << 13),
        (e, m) => sign | ((e + 112) << 23) | (m << 13),
    };
    f32::from_bits(bits)
}

/// The values of a 2-D float initializer, with its shape.
fn matrix(t: &tract_onnx::pb::TensorProto) -> Option<(usize, usize, Vec<f32>)> {
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
pub(super) fn fold_constant_matmuls(g: &mut tract_onnx::pb::GraphProto) -> Result<usize> {
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
    let used = read_names(g);
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

#[cfg(test)]
mod half_tests {
    use super::*;
    use crate::runtime::*;

    #[test]
    fn half_to_float_is_exact() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x7bff), 65504.0);
        assert_eq!(f16_to_f32(0x3555), 0.333_251_95);
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(f16_to_f32(0x8000).to_bits(), (-0.0f32).to_bits());
        assert_eq!(f16_to_f32(0x7c00), f32::INFINITY);
        assert!(f16_to_f32(0x7e00).is_nan());
    }

    fn cast_graph(half: tract_onnx::pb::TensorProto) -> tract_onnx::pb::GraphProto {
        tract_onnx::pb::GraphProto {
            initializer: vec![half],
            node: vec![tract_onnx::pb::NodeProto {
                op_type: "Cast".into(),
                input: vec!["w::float16".into()],
                output: vec!["w".into()],
                attribute: vec![tract_onnx::pb::AttributeProto {
                    name: "to".into(),
                    i: FLOAT as i64,
                    ..Default::default()
                }],
                ..Default::default()
            }],
            ..Default::default()
        }
    }

    #[test]
    fn half_weights_become_float_initializers() {
        let mut g = cast_graph(tract_onnx::pb::TensorProto {
            name: "w::float16".into(),
            dims: vec![2],
            data_type: FLOAT16,
            raw_data: vec![0x00, 0x3c, 0x00, 0xc0],
            ..Default::default()
        });
        assert_eq!(widen_half_weights(&mut g).unwrap(), 1);
        assert!(g.node.is_empty());
        assert_eq!(g.initializer.len(), 1);
        assert_eq!(g.initializer[0].name, "w");
        assert_eq!(initializer_floats(&g.initializer[0]), vec![1.0, -2.0]);
    }

    #[test]
    fn a_half_initializer_of_the_wrong_length_is_an_error() {
        let mut g = cast_graph(tract_onnx::pb::TensorProto {
            name: "w::float16".into(),
            dims: vec![1_000_000_000],
            data_type: FLOAT16,
            raw_data: vec![0x00, 0x3c],
            ..Default::default()
        });
        let e = widen_half_weights(&mut g).unwrap_err().to_string();
        assert!(e.contains("float16 initializer 'w::float16'"), "{e}");
    }

    #[test]
    fn shape_plans_serve_their_shape_and_the_least_recently_used_goes() {
        let Some(m) = bundled_tween_path() else {
            return;
        };
        assert!(m.prepare_any_shape().unwrap());
        let shape = |n: usize| vec![vec![1, 171, n]];
        let x = |n: usize| {
            let v = (0..171 * n).map(|i| (i as f32 * 0.37).sin()).collect();
            [TensorF32::new(v, vec![1, 171, n]).unwrap()]
        };
        let any = m.run(&x(40)).unwrap();
        assert!(m.prepare_shape(&shape(40)).unwrap());
        assert!(!m.prepare_shape(&shape(40)).unwrap(), "kept");
        let own = m.run(&x(40)).unwrap();
        let diff = any[0]
            .data
            .iter()
            .zip(&own[0].data)
            .map(|(a, b)| (a - b).abs())
            .fold(0f32, f32::max);
        assert!(diff < 1e-4, "own plan vs any-shape plan: {diff}");
        for n in 41..41 + MAX_SHAPE_PLANS {
            assert!(m.prepare_shape(&shape(n)).unwrap());
        }
        // the kept plans' lengths, least recently used first
        let kept = || -> Vec<usize> {
            m.plans
                .lock()
                .unwrap()
                .iter()
                .map(|(k, _)| k[0][2])
                .collect()
        };
        assert_eq!(kept(), (41..41 + MAX_SHAPE_PLANS).collect::<Vec<_>>());
        // using a plan makes it the most recently used
        m.run(&x(41)).unwrap();
        assert!(m.prepare_shape(&shape(40)).unwrap(), "40 was dropped");
        assert_eq!(kept(), vec![43, 44, 41, 40]);
        assert!(
            m.prepare_shape(&[vec![1, 170, 40]]).is_err(),
            "fixed axis checked"
        );
    }

    #[test]
    fn the_bundled_models_load_without_half_precision_left() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/onnx");
        let bytes = match std::fs::read(dir.join("rot6d_autoencoder.onnx")) {
            Ok(b) => b,
            Err(_) => return eprintln!("SKIP: models/onnx/rot6d_autoencoder.onnx missing"),
        };
        let p = read_proto(&bytes).unwrap();
        let g = p.graph.unwrap();
        assert!(g.initializer.iter().all(|t| t.data_type != FLOAT16));
        assert!(g.node.iter().all(|n| n.op_type != "Cast"));
    }
}
