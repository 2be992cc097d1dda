"""Export (ONNX, manifest, fixture), the portable float16 checkpoint, and pruning to a narrower network.

Part of deeprep_train.motion.residual (see its package docstring)."""
import json
import os

import numpy as np
import torch

from deeprep_train.paths import ROOT
from deeprep_train.motion.residual.data import Clips, GATE_FRAMES, PORTABLE, SCALE, Skeleton, features, fill_band
from deeprep_train.motion.residual.net import arch, build, net_input


def export(args):
    """models/onnx/tween_residual.onnx (the weights' moving average; input
    [1, 3 + 6K + 4, N], N free), its manifest and a parity fixture; with
    --name tween_fill_long --fill-from A --fill-up-to B, the long-gap filling
    network (the same network fine-tuned on gaps in captured motion, issue
    50), which the `model` fill runs on gaps of A-B frames."""
    import onnxruntime as ort
    from deeprep_train.motion.export import fixture
    from deeprep_train.export.util import ONNX_DIR, git_commit, write_json
    s = torch.load(args.ckpt)
    net = build(s)
    net.load_state_dict({k: v.float() for k, v in s["ema"].items()})
    net.eval()
    d = np.load(args.data)
    skel = Skeleton(d)
    gen_manifest = json.load(open(os.path.join(ONNX_DIR, "tween_generator.manifest.json")))
    cin = 3 + 6 * skel.K + 4
    name = args.name
    band = fill_band(args)
    if name != "tween_residual" and not band:
        raise SystemExit(f"--name {name}: only a gap-filling network (--fill-up-to) is exported under another name")
    path = os.path.join(ONNX_DIR, f"{name}.onnx")
    # the fixture's input: a real window's features (first training segment,
    # 65 frames, keys at 0, 30 and 64: an odd length, which a stride-2
    # network pads), so outputs are in their usual range
    clips = Clips(d, "train")
    f = features(clips.root[:65], clips.quat[:65], [0, 30, 64])
    x = net_input(f[0].unsqueeze(0), f[1].unsqueeze(0), f[4].unsqueeze(0))
    torch.onnx.export(net, (x,), path, input_names=["x"], output_names=["residual"], opset_version=17,
                      dynamic_axes={"x": {2: "frames"}, "residual": {2: "frames"}}, dynamo=False)
    with torch.no_grad():
        ref = net(x).numpy()
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    parity = fixture(name, sess, {"x": x.numpy()}, ref)
    description = ("a learned residual on SLERP+LERP in the first key's frame (train/deeprep_train/motion/residual.py; "
                   "issue 19)")
    if band:
        description = (f"the residual network fine-tuned on gaps in captured motion, every context frame a key "
                       f"(train/deeprep_train/motion/residual; issue 50): the `model` fill's network for gaps of "
                       f"{band.get('fill_from', 1)}-{band['fill_up_to']} frames")
    write_json(os.path.join(ONNX_DIR, f"{name}.manifest.json"), {
        "name": name,
        "kind": "residual-tween",
        "description": description,
        **band,
        "inputs": [{"name": "x", "shape": [1, cin, "frames"],
                    "channels": "root position in the first key's frame / scale (3), 6D of each joint with channels "
                                "in file order, the root's in that frame (6K), then s, frames since the previous key / 60, "
                                "frames to the next key / 60, gate"}],
        "outputs": [{"name": "residual", "shape": [1, 3 + 6 * skel.K, "frames"]}],
        "scale": SCALE,
        "gate_frames": GATE_FRAMES,
        "rotating": skel.rotating,
        "skeleton_bvh": gen_manifest["skeleton_bvh"],
        "training": {"steps": int(s["step"]), **net.arch(), "checkpoint": os.path.relpath(args.ckpt, ROOT),
                     **({"recipe": args.recipe} if args.recipe else {})},
        "parity_torch_vs_onnxruntime": parity,
        "training_data": "CMU train takes at 60 fps (59,290 frames, train/deeprep_train/motion/data.py's split and floor filter), mirrored",
        "training_code_commit": git_commit(),
        "exporter": {"torch": torch.__version__, "onnxruntime": ort.__version__, "opset": 17},
    })
    from deeprep_train.export.half_weights import convert
    convert(name)  # the shipped file keeps its weights as float16 (issue 21)
    print(f"exported {path} (step {s['step']}), parity {parity:.2e}")



def portable(args):
    """The running checkpoint's weights and moving average in float16, to
    train/checkpoints/tween_resid_w128b.pt (or --to)."""
    s = torch.load(args.ckpt or os.path.join(args.out, "ckpt.pt"), map_location="cpu")
    half = {k: {n: v.half() for n, v in s[k].items()} for k in ("net", "ema")}
    to = args.to or PORTABLE
    os.makedirs(os.path.dirname(os.path.abspath(to)), exist_ok=True)
    torch.save({**half, "step": s["step"], **arch(s)}, to)
    print(f"wrote {to} (step {s['step']}, {os.path.getsize(to) / 1e6:.1f} MB)")


def prune(args):
    """A narrower network from a trained one (issue 23: the residual network
    is most of the default pipeline's time, which grows with width²): keeps
    the `--width` residual-stream channels with the largest weights into and
    out of the stream, and in each block the `--width` hidden channels with
    the largest c1-out x c2-in weights; writes DIR/ckpt.pt (no optimizer
    state) for `train --resume --out DIR --width W` to fine-tune."""
    s = torch.load(args.ckpt or PORTABLE, map_location="cpu")
    w = args.width
    out = {"step": s["step"], **arch(s), "width": w,
           "pruned_from": {"ckpt": args.ckpt or PORTABLE, "width": s["width"], "step": s["step"]}}
    for part in ("net", "ema"):
        p = {k: v.float() for k, v in s[part].items()}
        blocks = sorted({int(k.split(".")[1]) for k in p if k.startswith("blocks.")})
        # residual stream: what writes it (inp, each c2) and reads it (each c1, out)
        score = p["inp.weight"].pow(2).sum((1, 2)) + p["out.weight"].pow(2).sum((0, 2))
        if "skip.weight" in p:  # the full-rate skip writes the stream too
            score += p["skip.weight"].pow(2).sum((1, 2))
        for b in blocks:
            score += p[f"blocks.{b}.c2.weight"].pow(2).sum((1, 2)) + p[f"blocks.{b}.c1.weight"].pow(2).sum((0, 2))
        keep = torch.argsort(score, descending=True)[:w].sort().values
        q = {"inp.weight": p["inp.weight"][keep], "inp.bias": p["inp.bias"][keep],
             "out.weight": p["out.weight"][:, keep], "out.bias": p["out.bias"]}
        if "skip.weight" in p:
            q["skip.weight"], q["skip.bias"] = p["skip.weight"][keep], p["skip.bias"][keep]
        for b in blocks:
            c1w, c1b = p[f"blocks.{b}.c1.weight"], p[f"blocks.{b}.c1.bias"]
            c2w, c2b = p[f"blocks.{b}.c2.weight"], p[f"blocks.{b}.c2.bias"]
            h = (c1w.pow(2).sum((1, 2)) * c2w.pow(2).sum((0, 2))).sqrt()
            hk = torch.argsort(h, descending=True)[:w].sort().values
            q[f"blocks.{b}.c1.weight"] = c1w[hk][:, keep]
            q[f"blocks.{b}.c1.bias"] = c1b[hk]
            q[f"blocks.{b}.c2.weight"] = c2w[keep][:, hk]
            q[f"blocks.{b}.c2.bias"] = c2b[keep]
        out[part] = q
    os.makedirs(args.out, exist_ok=True)
    torch.save(out, os.path.join(args.out, "ckpt.pt"))
    n = sum(v.numel() for v in out["net"].values())
    print(f"pruned width {s['width']} -> {w} at step {s['step']}: {n:,} parameters -> {args.out}/ckpt.pt")
