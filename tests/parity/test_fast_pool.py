"""export/fast_pool.py: the mesh models' weighted neighbourhood sums as a
MatMul compute what the Mul + ReduceSum form does (onnxruntime, float16
weights behind a Cast as shipped), and the bundled mesh files carry the
rewritten form."""
import os

import numpy as np
import onnx
import onnxruntime as ort
import pytest
from onnx import TensorProto, helper, numpy_helper

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def pooled_graph(n_in=40, n=12, e=5, c=3, half=True, seed=0):
    """x [B, n_in, c] -> ReduceSum_2(Gather(x, idx) * wts), as mesh/export.py writes it."""
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, n_in, size=(n, e)).astype(np.int64)
    wts = rng.random((1, n, e, 1)).astype(np.float32)
    inits = [numpy_helper.from_array(idx, "idx"), numpy_helper.from_array(np.array([2], np.int64), "axes")]
    nodes = [helper.make_node("Gather", ["x", "idx"], ["g"], axis=1)]
    if half:
        inits.append(numpy_helper.from_array(wts.astype(np.float16), "wts::float16"))
        nodes.insert(0, helper.make_node("Cast", ["wts::float16"], ["wts"], to=TensorProto.FLOAT))
    else:
        inits.append(numpy_helper.from_array(wts, "wts"))
    nodes += [helper.make_node("Mul", ["g", "wts"], ["m"]),
              helper.make_node("ReduceSum", ["m", "axes"], ["y"], keepdims=0)]
    graph = helper.make_graph(nodes, "pool", [helper.make_tensor_value_info("x", TensorProto.FLOAT, ["b", n_in, c])],
                              [helper.make_tensor_value_info("y", TensorProto.FLOAT, ["b", n, c])], inits)
    return helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)], ir_version=8)


def run(model, x):
    return ort.InferenceSession(model.SerializeToString(), providers=["CPUExecutionProvider"]).run(None, {"x": x})[0]


@pytest.mark.parametrize("half", [True, False])
def test_rewrite_keeps_the_sum(train_import, half):
    rewrite = train_import("deeprep_train.export.fast_pool").rewrite
    m = pooled_graph(half=half)
    x = np.random.default_rng(1).standard_normal((2, 40, 3)).astype(np.float32)
    ref = run(m, x)
    assert rewrite(m) == 1
    ops = [n.op_type for n in m.graph.node]
    assert "ReduceSum" not in ops and "MatMul" in ops
    np.testing.assert_allclose(run(m, x), ref, atol=1e-6)


def test_other_sums_are_left_alone(train_import):
    rewrite = train_import("deeprep_train.export.fast_pool").rewrite
    m = pooled_graph()
    next(t for t in m.graph.initializer if t.name == "axes").CopyFrom(numpy_helper.from_array(np.array([1], np.int64), "axes"))
    assert rewrite(m) == 0
    assert [n.op_type for n in m.graph.node][-1] == "ReduceSum"


@pytest.mark.parametrize("name", ["mesh_encoder", "mesh_decoder"])
def test_bundled_mesh_models_are_rewritten(name):
    path = os.path.join(ROOT, "models", "onnx", f"{name}.onnx")
    ops = [n.op_type for n in onnx.load(path).graph.node]
    assert "ReduceSum" not in ops, f"{name}.onnx still sums with ReduceSum: run train/.venv/bin/python -m deeprep_train.export.fast_pool {path}"
