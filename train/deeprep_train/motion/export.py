"""Exports the in-betweening networks to models/onnx/ with manifests and
parity fixtures:
  tween_generator.onnx   dense [1, 2P, N] (N a multiple of 64), dna [1, K, P] -> raw [1, 6 + 3K', N]
  tween_path.onnx        local positions [1, P, N] -> root velocity [1, 3, N]
Run after motion/train.py:  train/.venv/bin/python -m deeprep_train.motion.export
"""
import argparse
import json
import os

import numpy as np
import onnxruntime as ort
import torch

from deeprep_train.rcfk import RCFK  # noqa: E402
from deeprep_train.motion.nets import DT_CLIP, DT_NORM, GAN_TARGET, SCALE, Generator, PathPredictor  # noqa: E402
from deeprep_train.export.util import ONNX_DIR, git_commit, write_json  # noqa: E402
from deeprep_train.motion.train import OUT, W, Data  # noqa: E402

from deeprep_train.paths import ROOT, CACHE  # noqa: E402


def fixture(name, sess, feeds, torch_out, directory=ONNX_DIR):
    outs = sess.run(None, {k: v for k, v in feeds.items()})
    parity = float(np.abs(outs[0] - torch_out).max())
    os.makedirs(os.path.join(directory, "fixtures"), exist_ok=True)
    write_json(os.path.join(directory, "fixtures", f"{name}.json"), {
        "model": f"{name}.onnx",
        "inputs": {k: {"shape": list(v.shape), "data": [float(x) for x in v.ravel()]} for k, v in feeds.items()},
        "input_order": list(feeds),
        # single-input form read by tests/parity for the first input
        "input_name": list(feeds)[0], "input_shape": list(list(feeds.values())[0].shape),
        "input": [float(x) for x in list(feeds.values())[0].ravel()],
        "output_shape": list(outs[0].shape),
        "output_onnxruntime": [float(x) for x in outs[0].ravel()],
        "onnxruntime_version": ort.__version__,
    })
    return parity


def main(argv=None):
    ap = argparse.ArgumentParser(description="Exports the in-betweening generator and path predictor to ONNX.")
    ap.add_argument("--run", default=OUT, help="training run directory with gen.pt, path.pt and log.jsonl "
                                                "(default train/cache/tween)")
    ap.add_argument("--variation", type=float, default=1.0,
                    help="the manifest's default variation (train/deeprep_train/motion/pick_variation.py chooses it afterwards)")
    ap.add_argument("--only", choices=["both", "path"], default="both",
                    help="path: export the path predictor alone (a --path-only run), leaving the generator's files as they are")
    args = ap.parse_args(argv)
    data = Data(os.path.join(CACHE, "motion60.npz"), "train")
    J = len(data.joints)
    P = 3 * J
    fk = RCFK(data.joints, data.parents, data.offsets, data.channel_joints)
    both = args.only == "both"
    pck = torch.load(os.path.join(args.run, "path.pt"))
    path = PathPredictor(P, **pck.get("config", {}))
    path.load_state_dict(pck["model"])
    path.eval()
    g = torch.Generator().manual_seed(3)
    gpath = os.path.join(ONNX_DIR, "tween_generator.onnx")
    dense = torch.randn(1, 2 * P, 128, generator=g).abs()
    dense_rot = torch.randn(1, 2 * fk.output_dim, 128, generator=g).abs()
    dna = torch.randn(1, 2, P, generator=g) * 0.3
    if both:
        gck = torch.load(os.path.join(args.run, "gen.pt"))
        gen = Generator(P, fk.output_dim, gate_tau=gck["args"].get("gate_tau"), skips=gck["args"].get("skips", 0))
        # the weights' moving average when the run kept one (--ema)
        gen.load_state_dict(gck.get("G_ema", gck["G"]))
        gen.eval()
        torch.onnx.export(gen, (dense, dense_rot, dna), gpath, dynamo=False, opset_version=17,
                          input_names=["dense", "dense_rot", "dna"], output_names=["raw"],
                          dynamic_axes={"dense": {2: "frames"}, "dense_rot": {2: "frames"}, "dna": {1: "dna_frames"},
                                        "raw": {2: "frames"}})
    ppath = os.path.join(ONNX_DIR, "tween_path.onnx")
    local = torch.randn(1, P, 128, generator=g) * 0.3
    torch.onnx.export(path, (local,), ppath, dynamo=False, opset_version=17, input_names=["local"],
                      output_names=["velocity"], dynamic_axes={"local": {2: "frames"}, "velocity": {2: "frames"}})
    with torch.no_grad():
        p_out = path(local).numpy()
    pp = fixture("tween_path", ort.InferenceSession(ppath, providers=["CPUExecutionProvider"]), {"local": local.numpy()}, p_out)
    if both:
        with torch.no_grad():
            g_out = gen(dense, dense_rot, dna).numpy()
        pg = fixture("tween_generator", ort.InferenceSession(gpath, providers=["CPUExecutionProvider"]),
                     {"dense": dense.numpy(), "dense_rot": dense_rot.numpy(), "dna": dna.numpy()}, g_out)
        print(f"parity torch vs onnxruntime: generator {pg:.3g}, path {pp:.3g}")
    else:
        print(f"parity torch vs onnxruntime: path {pp:.3g}")

    std = open(os.path.join(ROOT, "..", "shared", "data", "cmu-bvh", "standard.bvh")).read()
    hierarchy = std[: std.index("MOTION")] + "MOTION\nFrames: 0\nFrame Time: 0.0166667\n"
    log = [json.loads(line) for line in open(os.path.join(args.run, "log.jsonl"))]
    last = [x for x in log if x.get("stage") == "gen"][-1:]
    path_minutes = max([x["sec"] for x in log if x.get("stage") == "path"] or [0]) / 60
    common = {
        "skeleton_bvh": hierarchy,
        "range_table": json.load(open(os.path.join(ROOT, "crate", "data", "table_d1.json")))["joints"],
        "normalization": {"scale": SCALE, "dt_norm": DT_NORM, "dt_clip": DT_CLIP,
                          "pose_layout": "per frame, per joint x y z: joint 0 is the root's global position with x and z "
                                         "relative to the mean key root x/z; other joints relative to the root; all divided by scale"},
        "training_data": "CMU mocap in the thesis skeleton (../shared/data/cmu-bvh, 39 clips), 60 fps, train takes only (train/deeprep_train/motion/data.py)",
        "training_code_commit": git_commit(),
        "exporter": {"torch": torch.__version__, "dynamo": False, "opset": 17},
    }
    if both:
        write_generator_manifest(gck, P, fk, args, last, pg, common)
    write_json(os.path.join(ONNX_DIR, "tween_path.manifest.json"), {
        "name": "tween_path",
        "inputs": [{"name": "local", "shape": [1, P, "frames"], "meaning": "local joint positions (root at 0) divided by scale"}],
        "outputs": [{"name": "velocity", "shape": [1, 3, "frames"], "meaning": "root velocity T[t+1] - T[t], divided by scale"}],
        "training": {"steps": pck["steps"], "minutes": round(pck.get("minutes", path_minutes), 1),
                     "config": pck.get("config", {}), "augment": pck.get("augment", False),
                     **({"trained_in": pck["source"]} if "source" in pck else {}),
                     "table_5_2_validation": pck["table_5_2_val"],
                     **({"table_5_2_train": pck["table_5_2_train"]} if "table_5_2_train" in pck else {})},
        "parity_torch_vs_onnxruntime": pp, **common,
    })
    print("wrote", *( [gpath, ppath] if both else [ppath]))
    return both


def write_generator_manifest(gck, P, fk, args, last, pg, common):
    write_json(os.path.join(ONNX_DIR, "tween_generator.manifest.json"), {
        "name": "tween_generator",
        "inputs": [{"name": "dense", "shape": [1, 2 * P, "frames"], "meaning": "dense keyframe input (Fig. 5.3): pose copies then distance transforms; frames a multiple of 64"},
                   {"name": "dense_rot", "shape": [1, 2 * fk.output_dim, "frames"], "meaning": "the same dense format for whole-pose keys' raw RC-FK values (root 6D, atanh of range position, |v| <= 3), the values interpolated between keys as `base` says; the output adds to them"},
                   {"name": "dna", "shape": [1, "dna_frames", P], "meaning": "Motion DNA: representative local poses without root rotation, divided by scale"}],
        "base": gck["args"].get("base", "linear"),
        # the default share of the learned departure from interpolation;
        # train/deeprep_train/motion/pick_variation.py chooses it on training takes afterwards
        "variation": args.variation,
        "outputs": [{"name": "raw", "shape": [1, fk.output_dim, "frames"], "meaning": "root 6D, then tanh-ranged Euler values per rotating joint (RC-FK)"}],
        "training": {"steps": gck["steps"], "batch": gck["args"]["batch"], "frames": gck["args"]["frames"],
                     "loss_weights": gck.get("weights", W), "gan_target": GAN_TARGET, "last_log": last},
        "parity_torch_vs_onnxruntime": pg, **common,
    })


if __name__ == "__main__":
    both = main()
    # PReLU in the form tract runs fastest (issue 23, train/deeprep_train/export/fast_prelu.py),
    # then float16 weights (issue 21), which re-runs the fixtures
    import onnx
    from deeprep_train.export.fast_prelu import rewrite
    from deeprep_train.export.half_weights import convert
    for name in ("tween_generator", "tween_path") if both else ("tween_path",):
        path = os.path.join(ONNX_DIR, f"{name}.onnx")
        m = onnx.load(path)
        rewrite(m)
        onnx.save(m, path)
        convert(name)
