"""The mesh autoencoder's weighted neighbourhood sums as a MatMul (issue 23).

mesh/export.py writes each residual pooling of a block (vdPool's density
weights, the identity skip's averaging) as

    y[b, n, :] = ReduceSum_e( Gather(x, idx)[b, n, e, :] * wts[0, n, e, 0] )

which tract runs as a broadcast Mul and a Reduce<Sum> over the middle axis
(the Reduce<Sum> alone 18-28% of the mesh models' time in tract's plan,
natively and in wasm: `cargo run --release --example profile_models`,
`node tests/web/bench_ort_page.mjs`). This rewrite computes the same sum as
one batched matrix product per vertex,

    y[b, n, :] = Squeeze_2( MatMul(wts'[0, n, 0, :], Gather(x, idx)[b, n, :, :]) )

with wts' the same values reshaped from [1, N, E, 1] to [1, N, 1, E] (no
copy: the moved axis has length 1), so the models' time is tract's matrix
product and its packing (tract 17-30% faster in wasm; onnxruntime-web gains
as much, README "Speed"). Exporters call rewrite(); on bundled files:

  train/.venv/bin/python -m deeprep_train.export.fast_pool models/onnx/mesh_encoder.onnx ...
"""

import onnx
from onnx import numpy_helper

from deeprep_train.export.util import rewrite_cli


def rewrite(model):
    """Rewrites every ReduceSum over axis 2 (axes from an initializer or a
    Constant node) of a Mul by a [1, N, E, 1] initializer (float32, or
    float16 read through a Cast) in place; returns how many. Anything else
    is left as it is."""
    g = model.graph
    init = {t.name: t for t in g.initializer}
    by_out = {o: n for n in g.node for o in n.output}
    readers = {}
    for n in g.node:
        for i in n.input:
            readers[i] = readers.get(i, 0) + 1

    def constant(name):
        if name in init:
            return numpy_helper.to_array(init[name])
        n = by_out.get(name)
        if n is not None and n.op_type == "Constant" and n.attribute and n.attribute[0].name == "value":
            return numpy_helper.to_array(n.attribute[0].t)
        return None

    count = 0
    for node in g.node:
        axes = constant(node.input[1]) if node.op_type == "ReduceSum" and len(node.input) == 2 else None
        if axes is None:
            continue
        axes = axes.ravel().tolist()
        keepdims = next((a.i for a in node.attribute if a.name == "keepdims"), 1)
        mul = by_out.get(node.input[0])
        if axes != [2] or keepdims != 0 or mul is None or mul.op_type != "Mul" or readers[mul.output[0]] != 1:
            continue
        gathered, w = mul.input
        cast = by_out.get(w)
        stored = cast.input[0] if cast is not None and cast.op_type == "Cast" else w
        t = init.get(stored)
        if t is None or len(t.dims) != 4 or t.dims[0] != 1 or t.dims[3] != 1 or readers[w] != 1:
            continue
        t.dims[:] = [1, t.dims[1], 1, t.dims[2]]
        mul.op_type = "MatMul"
        del mul.input[:]
        mul.input.extend([w, gathered])
        node.op_type = "Squeeze"
        del node.attribute[:]
        count += 1
    onnx.checker.check_model(model)
    return count


def main():
    rewrite_cli(rewrite, "weighted sums", "a MatMul (the mesh models' pooling)")


if __name__ == "__main__":
    main()
