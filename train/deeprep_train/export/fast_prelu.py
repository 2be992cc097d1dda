"""PReLU in the form tract runs fastest (issue 23).

tract lowers ONNX PRelu to a comparison, a select (Iff) and a per-channel
Mul: 51-65% of the in-betweening networks' time in its plan
(`cargo run --release --example profile_models`). A first rewrite,
x + (a - 1)·min(x, 0), fused into a Min+Mul chain, still 36% of tween_path's
time: tract's per-channel broadcast and its min/max by a scalar are not
vectorized. This one uses only kernels tract runs at memory speed, a
LeakyRelu of fixed slope, an elementwise Sub and Add and a depthwise 1x1
convolution for the per-channel factor:

    y = x + k ⊙ (leaky_relu(x, ALPHA) − x),    k = (1 − a) / (1 − ALPHA)

which is x where x > 0 (exactly: the bracket is 0 there, whatever k's
precision) and a·x below. Natively, one thread, 2,048 frames: tween_path
29.5 → 15.6 ms (its PReLUs 14 → 1.1 ms). Exporters call rewrite(); it also
takes files in the first rewrite's form (Min, Sub(a, 1), Mul, Add). On a
bundled file:

  train/.venv/bin/python -m deeprep_train.export.fast_prelu models/onnx/tween_path.onnx ...

`slopes()` reads each PReLU's a back from a rewritten file
(motion/recover_checkpoint.py).
"""
import re

import numpy as np
import onnx
from onnx import helper, numpy_helper

from deeprep_train.export.util import rewrite_cli

ALPHA = 0.01


def _arrays(g):
    """Initializers and what Cast nodes make of them (float16 storage)."""
    arr = {i.name: numpy_helper.to_array(i) for i in g.initializer}
    for n in g.node:
        if n.op_type == "Cast" and n.input[0] in arr:
            arr[n.output[0]] = arr[n.input[0]].astype(np.float32)
    return arr


def _fast(x, a, y, p, g):
    """Nodes for y = prelu(x, a); a [C, 1, ...] per channel or one slope."""
    a = np.asarray(a, np.float64)
    if a.size == 1:
        # one slope: exactly a LeakyRelu (named so slopes() finds it)
        return [helper.make_node("LeakyRelu", [x], [y], name=p + "slope", alpha=float(a.reshape(())))]
    if a.ndim < 2 or a.shape[0] != a.size:
        return None  # not one slope per channel of an NC... tensor: left as it is
    k = ((1 - a) / (1 - ALPHA)).astype(np.float32)
    spatial = max(a.ndim - 1, 1)
    g.initializer.append(numpy_helper.from_array(k.reshape((a.size, 1) + (1,) * spatial), p + "k"))
    return [helper.make_node("LeakyRelu", [x], [p + "leaky"], alpha=ALPHA),
            helper.make_node("Sub", [p + "leaky", x], [p + "diff"]),
            helper.make_node("Conv", [p + "diff", p + "k"], [p + "kdiff"], group=a.size,
                             kernel_shape=[1] * spatial),
            helper.make_node("Add", [x, p + "kdiff"], [y])]


def rewrite(model):
    """Replaces every PReLU of `model` (PRelu nodes, or the first rewrite's
    Min/Sub/Mul/Add) in place; returns how many."""
    g = model.graph
    arr = _arrays(g)
    by_out = {o: n for n in g.node for o in n.output}
    nodes, n = [], 0
    for i, node in enumerate(g.node):
        new = None
        if node.op_type == "PRelu" and node.input[1] in arr:
            x, a = node.input
            new = _fast(x, arr[a], node.output[0], f"{node.name or 'prelu'}_{i}_", g)
        elif node.op_type == "Add" and node.input[1].endswith("_scaled") and node.input[1] in by_out:
            # the first rewrite: Add(x, Mul(Min(x, 0), Sub(a, 1)))
            mul = by_out[node.input[1]]
            sub = by_out.get(mul.input[1])
            if mul.op_type == "Mul" and sub is not None and sub.op_type == "Sub" and sub.input[0] in arr:
                p = node.input[1][:-len("scaled")]
                new = _fast(node.input[0], arr[sub.input[0]], node.output[0], p, g)
        if new is None:
            nodes.append(node)
        else:
            nodes += new
            n += 1
    # what only the replaced nodes read goes too (the first rewrite's Min,
    # Sub and Mul, its constants, Casts of float16 slopes)
    outputs = {o.name for o in g.output}
    while True:
        used = {i for x in nodes for i in x.input} | outputs
        live = [x for x in nodes if set(x.output) & used]
        if len(live) == len(nodes):
            break
        nodes = live
    del g.node[:]
    g.node.extend(nodes)
    keep = [i for i in g.initializer if i.name in used]
    del g.initializer[:]
    g.initializer.extend(keep)
    onnx.checker.check_model(model)
    return n


def slopes(model):
    """{name of the PReLU the exporter wrote: its slopes a} from a rewritten
    model (this form and the first one), names as "<PRelu node>" without
    the rewrite's "_<i>_" suffix."""
    g = model.graph
    arr = _arrays(g)
    out = {}
    for node in g.node:
        if node.op_type == "Conv" and node.input[1].endswith("_k") and node.input[1] in arr:
            m = re.fullmatch(r"(.*)_\d+_k", node.input[1])
            if m:
                k = arr[node.input[1]].astype(np.float64)
                out[m.group(1)] = (1 - k * (1 - ALPHA)).reshape(k.shape[0], *([1] * (k.ndim - 2))).astype(np.float32)
        if node.op_type == "LeakyRelu":
            m = re.fullmatch(r"(.*)_\d+_slope", node.name)
            if m:
                out[m.group(1)] = np.array([next(a.f for a in node.attribute if a.name == "alpha")], np.float32)
        if node.op_type == "Sub" and len(node.input) == 2 and node.input[1] == "prelu_one" and node.input[0] in arr:
            m = re.fullmatch(r"(.*)_\d+_slope1", node.output[0])
            if m:
                out[m.group(1)] = arr[node.input[0]]
    return out


def main():
    rewrite_cli(rewrite, "PReLUs", "x + k * (leaky_relu(x) - x)")


if __name__ == "__main__":
    main()
