"""The gap-fill benchmark (issue 50): LaFAN1's protocol (Harvey et al.
2020) at 60 fps on the CMU takes.

For each clip (resampled to 60 fps, motion.data's rule), windows start every
40 frames; each window is 20 known context frames, a transition of L frames
(10, 30, 60, 90) to synthesize, then 1 known frame (table A) or 20 (table
B). Every method fills the transitions with `deeprep inbetween --from-bvh
CLIP --fill S-E ... --context 20,A --method M` (windows close enough to
share frames go to separate runs, so each context is the captured motion).
Scored on the transition's frames with motion.eval's metrics: L2P, L2Q,
NPSS (per window, averaged), foot skating.

Methods: slerp (SLERP+LERP from the last context frame to the target),
zerovel (the last context frame held), hermite (a cubic Hermite curve whose
end tangents are the context's velocities), residual (the network with
every context frame a key), residual-2 (the network with only the last
context frame and the target as keys), fill-mlp (the short-gap fill network), model (the CLI's default for fills:
Hermite up to 45 frames, the network beyond; motion::fill::method_for).
mix:A:B:S (an experiment, not a CLI method): the outputs of methods A and B
(both listed too) mixed joint by joint, weight S on B.

Run: train/.venv/bin/python -m deeprep_train.motion.fill_eval [--split train|val]
Writes docs/fill_eval[_train].json and prints Markdown tables.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from deeprep_train.bvh import global_fk, read_bvh, resample
from deeprep_train.motion.data import DATA, TRUE_FPS, VALIDATION, take_of
from deeprep_train.motion.eval import FEET, blend_fk, cli, l2p_stats, npss, score
from deeprep_train.paths import ROOT

CONTEXT = 20
STRIDE = 40
METHODS = {
    "slerp": ["--method", "slerp"],
    "zerovel": ["--method", "zerovel"],
    "hermite": ["--method", "hermite"],
    # the network alone (the residual network for whole-pose keys), every context frame a key
    "residual": ["--method", "residual"],
    # the network with only the last context frame and the target as keys
    "residual-2": ["--method", "residual", "--context", "1,1"],
    # the conditional network (issue 47), every context frame a whole-pose key
    "cond": ["--method", "cond"],
    # the gap-filling network (models/onnx/tween_fill.onnx, issue 50), every context frame a key
    "fill": ["--method", "fill"],
    # the short-gap fill network (models/onnx/tween_fill_mlp.onnx, motion/fill_mlp.py) on the edges' frames
    "fill-mlp": ["--method", "fill-mlp"],
    # the default: motion::fill::method_for (the gap-filling network on the gaps its manifest
    # gives it where one is bundled, else Hermite up to 45 frames; the residual network beyond)
    "model": ["--method", "model"],
}


def windows(n, length, after):
    """Gap starts: every STRIDE frames with CONTEXT frames before and `after` after."""
    return list(range(CONTEXT, n - length - after + 1, STRIDE))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--split", choices=["train", "val"], default="train")
    ap.add_argument("--lengths", type=lambda s: [int(x) for x in s.split(",")], default=[10, 30, 60, 90])
    ap.add_argument("--after", type=lambda s: [int(x) for x in s.split(",")], default=[1, 20])
    ap.add_argument("--methods", type=lambda s: s.split(","), default=["slerp", "zerovel", "hermite", "residual", "model"])
    ap.add_argument("--every", type=int, default=1, help="every K-th clip of the split (a quicker look)")
    ap.add_argument("--takes", type=lambda s: set(s.split(",")),
                    help="only these takes of the split (motion.data.take_of names, e.g. indian/08,salsa/09)")
    ap.add_argument("--json")
    args = ap.parse_args()
    for m in args.methods:
        parts = m.split(":")
        if m.startswith("mix:") and (len(parts) != 4 or not set(parts[1:3]) <= set(args.methods)):
            sys.exit(f"{m}: expected mix:A:B:S with methods A and B listed too")
        if not m.startswith("mix:") and m not in METHODS:
            sys.exit(f"{m}: unknown method ({', '.join(METHODS)}, mix:A:B:S)")
    if not os.path.isdir(DATA):
        sys.exit(f"SKIP: {DATA} is absent")
    mu, sd = l2p_stats()
    acc = {(m, a, L): {"l2p": [], "l2q": [], "mpjpe": [], "mpjpe_key": [], "gt": [], "pred": [], "skate": [],
                       "accel": [], "speed": [], "gt_speed": []}
           for m in args.methods for a in args.after for L in args.lengths}
    clips = [(cls, name) for cls in sorted(TRUE_FPS) for name in sorted(os.listdir(os.path.join(DATA, cls)))
             if name.endswith(".bvh") and (take_of(cls, int(name[:-4])) in VALIDATION) == (args.split == "val")
             and (args.takes is None or take_of(cls, int(name[:-4])) in args.takes)]
    if not clips:
        sys.exit(f"no clip of the {args.split} split among --takes {sorted(args.takes or [])}")
    with tempfile.TemporaryDirectory() as tmp:
        for cls, name in clips[::args.every]:
            clip = os.path.join(tmp, f"{cls}_{name}")
            n = resample(os.path.join(DATA, cls, name), clip, TRUE_FPS[cls] // 60)
            gpos, grot = global_fk(read_bvh(clip))
            names = read_bvh(clip)[0]
            feet = [names.index(f) for f in FEET]
            floor = np.median(gpos[:, :, 1].min(1))
            for after in args.after:
                for L in args.lengths:
                    starts = windows(n, L, after)
                    phases = -(-(CONTEXT + L + after) // STRIDE)
                    outs = {}
                    for m in sorted(args.methods, key=lambda m: m.startswith("mix:")):
                        for p in range(phases):
                            mine = starts[p::phases]
                            if not mine:
                                continue
                            if m.startswith("mix:"):
                                # mix:A:B:S, the outputs of methods A and B mixed with weight S on B
                                _, a_, b_, w = m.split(":")
                                pred = blend_fk(outs[(a_, p)], outs[(a_, p)], outs[(b_, p)], float(w))
                                for s in mine:
                                    score(acc[(m, after, L)], pred, (gpos, grot), [s - 1, s + L], feet, floor, mu, sd)
                                continue
                            out = os.path.join(tmp, "out.bvh")
                            # a method's own --context comes last and wins
                            extra = METHODS[m]
                            ctx = f"{CONTEXT},{after}"
                            fills = sum((["--fill", f"{s}-{s + L - 1}"] for s in mine), [])
                            r = subprocess.run([cli(), "inbetween", "--from-bvh", clip, "-o", out, "--context", ctx]
                                               + fills + extra, capture_output=True, text=True, cwd=ROOT)
                            if r.returncode != 0:
                                sys.exit(f"{m} on {clip}: {r.stderr}")
                            outs[(m, p)] = read_bvh(out)
                            pred = global_fk(outs[(m, p)])
                            for s in mine:
                                score(acc[(m, after, L)], pred, (gpos, grot), [s - 1, s + L], feet, floor, mu, sd)
            print(f"{cls}/{name}: {n} frames", file=sys.stderr)
    res = {}
    for (m, a, L), x in acc.items():
        res[f"{m}@after{a}@{L}"] = {
            "method": m, "after": a, "transition": L, "windows": len(x["l2p"]),
            "L2P": float(np.mean(x["l2p"])), "L2Q": float(np.mean(x["l2q"])),
            "NPSS": float(np.mean([npss(g[None], q[None]) for g, q in zip(x["gt"], x["pred"])])),
            "foot_skate": float(np.mean(x["skate"])),
            "speed_ratio": float(np.mean(x["speed"]) / max(np.mean(x["gt_speed"]), 1e-12)),
        }
    out_json = args.json or os.path.join(ROOT, "docs", "fill_eval.json" if args.split == "val" else "fill_eval_train.json")
    with open(out_json, "w") as f:
        json.dump(res, f, indent=1)
    for a in args.after:
        print(f"\n{args.split} takes, {CONTEXT} context frames before, {a} after:\n")
        print("| metric | method | " + " | ".join(f"{L} frames" for L in args.lengths) + " |")
        print("|---|---|" + "---|" * len(args.lengths))
        for metric in ["L2P", "L2Q", "NPSS", "foot_skate"]:
            for m in args.methods:
                print(f"| {metric} | {m} | " + " | ".join(f"{res[f'{m}@after{a}@{L}'][metric]:.3f}" for L in args.lengths) + " |")


if __name__ == "__main__":
    main()
