"""Table 5.4's keyframe alignment on the validation takes (issue 20): outputs
of up to 2,048 frames (the validation clips at 60 fps have 1,102-1,872
frames, so each whole clip is one output) with keys at random frames 1 to 5 s
apart, and the networks' mean key errors before post-processing (root
position, and local joint positions) and after it. The thesis reports
10.0 cm (root) and 3.5 cm (joints) before post-processing.

  train/.venv/bin/python -m deeprep_train.motion.table54 [--seeds N]

Writes docs/table54.json. Needs the release CLI and ../shared/data.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

from deeprep_train.motion.data import DATA, TRUE_FPS, VALIDATION, take_of
from deeprep_train.bvh import resample
from deeprep_train.motion.eval import ROOT, cli

PAIR = re.compile(r"root ([0-9.]+), joints ([0-9.]+)")


def validation_clips(tmp, max_frames=2048, split="val", every=1):
    """(class/name, path of the clip at 60 fps in tmp, frames used: at most
    max_frames) for every validation take (split "train": every `every`-th
    clip of the training takes instead)."""
    i = 0
    for cls in sorted(TRUE_FPS):
        for name in sorted(os.listdir(os.path.join(DATA, cls))):
            if (take_of(cls, int(name[:-4])) in VALIDATION) == (split == "val"):
                i += 1
                if (i - 1) % every:
                    continue
                clip = os.path.join(tmp, f"{cls}_{name}")
                n = resample(os.path.join(DATA, cls, name), clip, TRUE_FPS[cls] // 60)
                yield f"{cls}/{name}", clip, min(n, max_frames)


def random_keys(n, seed):
    """Keys from frame 0 at random steps of 1 to 5 s (60 to 300 frames), inside n frames."""
    rng = np.random.default_rng(seed)
    keys, t = [0], 0
    while True:
        t += int(rng.integers(60, 301))
        if t >= n:
            return keys
        keys.append(t)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=5, help="random key sets per clip")
    ap.add_argument("--max-frames", type=int, default=2048)
    args = ap.parse_args()
    if not os.path.isdir(DATA):
        sys.exit(f"SKIP: {DATA} is absent")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, clip, n in validation_clips(tmp, args.max_frames):
            for seed in range(args.seeds):
                keys = random_keys(n, seed)
                out = os.path.join(tmp, "out.bvh")
                for method in ("generator", "model"):
                    r = subprocess.run([cli(), "inbetween", "--from-bvh", clip, "--keys", ",".join(map(str, keys)),
                                        "-o", out, "--method", method], capture_output=True, text=True, cwd=ROOT)
                    if r.returncode:
                        sys.exit(f"{clip}: {r.stderr}")
                    pairs = [tuple(map(float, p)) for p in PAIR.findall(r.stderr)]
                    rows.append({"clip": label, "frames": keys[-1] + 1, "keys": len(keys), "method": method,
                                 "before": pairs[0] if pairs else None, "after": pairs[1] if len(pairs) > 1 else None,
                                 "log": r.stderr.strip()[:200]})
    res = {}
    for method in ("generator", "model"):
        rs = [r for r in rows if r["method"] == method and r["before"]]
        if rs:
            res[method] = {"outputs": len(rs), "mean_frames": float(np.mean([r["frames"] for r in rs])),
                           "root_before_post": float(np.mean([r["before"][0] for r in rs])),
                           "joints_before_post": float(np.mean([r["before"][1] for r in rs])),
                           "root_after_post": float(np.mean([r["after"][0] for r in rs])),
                           "joints_after_post": float(np.mean([r["after"][1] for r in rs]))}
    res["thesis"] = {"root_before_post_cm": 10.0, "joints_before_post_cm": 3.5}
    res["rows"] = rows
    with open(os.path.join(ROOT, "docs", "table54.json"), "w") as f:
        json.dump(res, f, indent=1)
    for k, v in res.items():
        if k != "rows":
            print(k, json.dumps(v))


if __name__ == "__main__":
    main()
