"""Exports the best IK network of train/deeprep_train/ik/train.py to models/onnx/ik.onnx,
with its manifest and a parity fixture.

  ik.onnx   positions [batch, J*3] (hip at the origin, BVH units) -> values [batch, D]

The fixture's inputs are poses the project makes itself (random range-
constrained angles through RC-FK on the thesis skeleton), so the tests need
no data. Besides onnxruntime's outputs it stores the positions that the
PyTorch FK layer reconstructs from them, which the Rust decoder must match.

Run after ik/train.py:  train/.venv/bin/python -m deeprep_train.ik.export [--rep rc|6d|quat|euler]
"""
import argparse
import json
import os

import numpy as np
import onnxruntime as ort
import torch

from deeprep_train.paths import ROOT, CACHE  # noqa: E402
from deeprep_train.export.util import ONNX_DIR, git_commit, write_json  # noqa: E402
from deeprep_train.ik.train import SCALE, IKNet, RcFKHead, load, make_head  # noqa: E402



def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rep", default=None, help="representation to export (default: lowest mean error in docs/ik_test.json)")
    args = ap.parse_args()
    results = json.load(open(os.path.join(ROOT, "docs", "ik_test.json")))
    reps = [k for k in results if not k.startswith("_")]
    rep = args.rep or min(reps, key=lambda k: results[k]["all"]["mean"])
    ck = torch.load(os.path.join(CACHE, "ik", f"{rep}.pt"), weights_only=False)
    d, channel_joints = load(os.path.join(CACHE, "motion60.npz"))
    names = list(d["joints"])
    J = len(names)
    head = make_head(rep, d, channel_joints)
    net = IKNet(J, head.output_dim, ck["width"])
    net.load_state_dict(ck["net"])
    net.eval()

    # Inputs: poses from random range-constrained angles (hip at the origin).
    g = torch.Generator().manual_seed(11)
    rc = RcFKHead(names, d["parents"], d["offsets"], channel_joints)
    raw = torch.randn(16, rc.output_dim, generator=g) * 0.7
    with torch.no_grad():
        x = rc(raw).reshape(16, J * 3)
        values = net(x)
        rec = head(values).reshape(16, J * 3)
    path = os.path.join(ONNX_DIR, "ik.onnx")
    torch.onnx.export(net, (x,), path, dynamo=False, opset_version=17, input_names=["positions"], output_names=["values"],
                      dynamic_axes={"positions": {0: "batch"}, "values": {0: "batch"}})
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    out = sess.run(None, {"positions": x.numpy()})[0]
    parity = float(np.abs(out - values.numpy()).max())
    print(f"{rep}: parity torch vs onnxruntime {parity:.3g}")
    write_json(os.path.join(ONNX_DIR, "fixtures", "ik.json"), {
        "model": "ik.onnx",
        "input_name": "positions", "input_shape": list(x.shape), "input": [float(v) for v in x.numpy().ravel()],
        "output_shape": list(out.shape), "output_onnxruntime": [float(v) for v in out.ravel()],
        "reconstructed_positions_torch": [float(v) for v in rec.numpy().ravel()],
        "onnxruntime_version": ort.__version__,
    })
    std = open(os.path.join(ROOT, "..", "shared", "data", "cmu-bvh", "standard.bvh")).read()
    hierarchy = std[: std.index("MOTION")] + "MOTION\nFrames: 0\nFrame Time: 0.0166667\n"
    meaning = {
        "rc": "root 6D, then for each rotating joint of the range table three values v mapped through tanh onto Table D.1's ranges (RC-FK)",
        "6d": "6D (eq. C.2) per joint with rotation channels, in BVH joint order",
        "quat": "quaternion [w, x, y, z] per joint with rotation channels (normalized before use)",
        "euler": "Euler angles (radians) a, b, c per joint with rotation channels: R = Rz(a) Rx(b) Ry(c)",
    }[rep]
    manifest = {
        "name": "ik",
        "representation": rep,
        "inputs": [{"name": "positions", "shape": ["batch", J * 3],
                    "meaning": f"global joint positions of the skeleton below with the hip at the origin, BVH units (the graph divides by {SCALE})"}],
        "outputs": [{"name": "values", "shape": ["batch", head.output_dim], "meaning": meaning}],
        "training": {"script": "train/deeprep_train/ik/train.py", "steps": ck["steps"], "width": ck["width"], "batch": 64,
                     "loss": "L2 on joint positions, 10x weight on abdomen, rButtock, lButtock; random rotation about y",
                     "validation": ck["result"]["all"], "validation_body_joints": ck["result"]["body"]},
        "parity_torch_vs_onnxruntime": parity,
        "skeleton_bvh": hierarchy,
        "training_data": "CMU mocap in the thesis skeleton (../shared/data/cmu-bvh), 60 fps, train takes only (train/deeprep_train/motion/data.py)",
        "training_code_commit": git_commit(),
        "exporter": {"torch": torch.__version__, "dynamo": False, "opset": 17},
    }
    if rep == "rc":
        manifest["range_table"] = json.load(open(os.path.join(ROOT, "crate", "data", "table_d1.json")))["joints"]
    write_json(os.path.join(ONNX_DIR, "ik.manifest.json"), manifest)
    print("wrote", path)


if __name__ == "__main__":
    main()
    # the shipped files keep their weights as float16 (issue 21)
    from deeprep_train.export.half_weights import convert
    for name in ("ik",):
        convert(name)
