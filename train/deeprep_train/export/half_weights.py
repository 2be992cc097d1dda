"""Stores the bundled models' weights as float16 (issue 21: half the download).

Every float32 initializer of at least MIN_SIZE values (the weights; small
constants such as Resize scales stay float32) becomes a float16 initializer
`<name>::float16` read through a `Cast(to=FLOAT)` whose output keeps the old
name, so the graph computes in float32 on weights rounded to half
precision. Any ONNX runtime runs the result as it is; deeprep's loader
(crate/src/runtime.rs, read_proto) widens the casts back into float32
initializers before tract sees the model.

For each model this rewrites models/onnx/<name>.onnx in place, recomputes
its parity fixture's onnxruntime output on the rounded weights (the fixture
then checks tract against onnxruntime on the shipped file) and records in
the manifest the bytes before and after and how far the rounding moved the
fixture's output. Already converted models are left alone.

  train/.venv/bin/python -m deeprep_train.export.half_weights [NAME ...]
"""
import argparse
import glob
import json
import os

import numpy as np
import onnx
import onnxruntime as ort
from onnx import helper, numpy_helper

from deeprep_train.export.util import HALF_SUFFIX, ONNX_DIR, write_json  # noqa: E402

MIN_SIZE = 64
HALF_MAX = 65504.0


def to_half(model):
    """Rewrites the model's large float32 initializers; returns how many."""
    g = model.graph
    keep, casts, n = [], [], 0
    for t in g.initializer:
        a = numpy_helper.to_array(t)
        if t.data_type != onnx.TensorProto.FLOAT or a.size < MIN_SIZE or np.abs(a).max() > HALF_MAX:
            keep.append(t)
            continue
        keep.append(numpy_helper.from_array(a.astype(np.float16), t.name + HALF_SUFFIX))
        casts.append(helper.make_node("Cast", [t.name + HALF_SUFFIX], [t.name], to=onnx.TensorProto.FLOAT,
                                      name=t.name + "::widen"))
        n += 1
    del g.initializer[:]
    g.initializer.extend(keep)
    nodes = casts + list(g.node)
    del g.node[:]
    g.node.extend(nodes)
    return n


def run(path_or_bytes, fixture):
    sess = ort.InferenceSession(path_or_bytes, providers=["CPUExecutionProvider"])
    if "inputs" in fixture:
        feeds = {k: np.asarray(v["data"], np.float32).reshape(v["shape"]) for k, v in fixture["inputs"].items()}
    else:
        feeds = {fixture["input_name"]: np.asarray(fixture["input"], np.float32).reshape(fixture["input_shape"])}
    return sess.run(None, feeds)[0]


def ik_positions(values):
    """The IK fixture's second check: PyTorch's decoder + FK on the model's
    output (ik/export.py), recomputed for the rounded weights' output."""
    import torch
    from deeprep_train.ik.train import load, make_head
    from deeprep_train.paths import CACHE
    rep = json.load(open(os.path.join(ONNX_DIR, "ik.manifest.json")))["representation"]
    d, channel_joints = load(os.path.join(CACHE, "motion60.npz"))
    head = make_head(rep, d, channel_joints)
    with torch.no_grad():
        rec = head(torch.from_numpy(values)).reshape(values.shape[0], -1)
    return [float(v) for v in rec.numpy().ravel()]


def convert(name, directory=ONNX_DIR):
    """Stores `directory/name.onnx`'s weights as float16 (its fixture and
    manifest there updated when they exist)."""
    path = os.path.join(directory, f"{name}.onnx")
    model = onnx.load(path)
    if any(i.name.endswith(HALF_SUFFIX) for i in model.graph.initializer):
        print(f"{name}: already float16, left alone")
        return
    before = os.path.getsize(path)
    fpath = os.path.join(directory, "fixtures", f"{name}.json")
    fixture = json.load(open(fpath)) if os.path.exists(fpath) else None
    ref = run(path, fixture) if fixture else None
    n = to_half(model)
    onnx.checker.check_model(model)
    data = model.SerializeToString()
    record = {"storage": "float16 weights, cast to float32 when loaded (train/deeprep_train/export/half_weights.py)",
              "initializers": n, "bytes_float32": before, "bytes": len(data)}
    if fixture:
        out = run(data, fixture)
        change = float(np.abs(out - ref).max())
        record["fixture_output_change_max_abs"] = change
        record["fixture_output_max_abs"] = float(np.abs(ref).max())
        fixture["output_onnxruntime"] = [float(x) for x in out.ravel()]
        if "reconstructed_positions_torch" in fixture:
            fixture["reconstructed_positions_torch"] = ik_positions(out)
        fixture["weights"] = "float16"
        write_json(fpath, fixture)
    with open(path, "wb") as fh:
        fh.write(data)
    mpath = os.path.join(directory, f"{name}.manifest.json")
    if os.path.exists(mpath):
        m = json.load(open(mpath))
        m["weights"] = record
        write_json(mpath, m)
    print(f"{name}: {n} initializers, {before:,} -> {len(data):,} bytes" +
          (f", fixture output moved {record['fixture_output_change_max_abs']:.2e} (max |output| "
           f"{record['fixture_output_max_abs']:.3g})" if fixture else ""))


def main():
    ap = argparse.ArgumentParser(description="Store bundled models' weights as float16 behind a Cast.")
    ap.add_argument("names", nargs="*", help="model names in models/onnx (default: all)")
    names = ap.parse_args().names or sorted(os.path.basename(p)[:-5] for p in glob.glob(os.path.join(ONNX_DIR, "*.onnx")))
    for name in names:
        convert(name)


if __name__ == "__main__":
    main()
