"""PReLU in the form tract runs fastest (issue 23).

tract lowers ONNX PRelu to a comparison, a select (Iff) and a per-channel
Mul: 51-65% of the in-betweening networks' time in its plan
(`cargo run --release --example profile_models`). The same function as
    y = x + (a - 1) * min(x, 0)
becomes one fused Min+Mul chain and an Add: measured side by side (best of
10, native, one thread, 2048 frames) tween_path 29-31 ms against 39-48 and
tween_generator 45-47 against 61-70. Outputs move by at most 4e-7
(onnxruntime). Exporters call rewrite(); run on a bundled file:

  train/.venv/bin/python -m deeprep_train.export.fast_prelu models/onnx/tween_path.onnx ...
"""
import argparse

import numpy as np
import onnx
from onnx import helper, numpy_helper


def rewrite(model):
    """Replaces every PRelu node of `model` (in place); returns how many."""
    g = model.graph
    have = {i.name for i in g.initializer}
    for name, v in (("prelu_zero", 0.0), ("prelu_one", 1.0)):
        if name not in have:
            g.initializer.append(numpy_helper.from_array(np.array(v, dtype=np.float32), name))
    nodes, n = [], 0
    for i, node in enumerate(g.node):
        if node.op_type != "PRelu":
            nodes.append(node)
            continue
        x, a = node.input
        y, p = node.output[0], f"{node.name or 'prelu'}_{i}_"
        nodes += [helper.make_node("Min", [x, "prelu_zero"], [p + "neg"]),
                  helper.make_node("Sub", [a, "prelu_one"], [p + "slope1"]),
                  helper.make_node("Mul", [p + "neg", p + "slope1"], [p + "scaled"]),
                  helper.make_node("Add", [x, p + "scaled"], [y])]
        n += 1
    del g.node[:]
    g.node.extend(nodes)
    if n == 0:  # nothing used the constants
        keep = [i for i in g.initializer if i.name not in ("prelu_zero", "prelu_one")]
        del g.initializer[:]
        g.initializer.extend(keep)
    onnx.checker.check_model(model)
    return n


def main():
    ap = argparse.ArgumentParser(description="Rewrite PRelu nodes as x + (a - 1) * min(x, 0), in place.")
    ap.add_argument("models", nargs="+", help="ONNX files to rewrite")
    for path in ap.parse_args().models:
        m = onnx.load(path)
        n = rewrite(m)
        onnx.save(m, path)
        print(f"{path}: {n} PRelu nodes rewritten")


if __name__ == "__main__":
    main()
