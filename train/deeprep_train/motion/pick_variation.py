"""Chooses the bundled in-betweening model's default `variation` (the share
of the learned departure from interpolation kept, in the pose and the root
path) on the *training* takes, by the rule train/deeprep_train/motion/pick_checkpoint.py uses for
snapshots: most cells of the issue's target met against SLERP+LERP, then the
lowest mean ratio to it. The validation takes the README reports are not
looked at.

  train/.venv/bin/python -m deeprep_train.motion.pick_variation [V ...]   (default grid below)

Runs train/deeprep_train/motion/eval.py once (--split train) with SLERP+LERP and the
generator pipeline without foot locking at each V (`generator-V`), writes docs/inbetween_variation_train.json
and sets `variation` (and how it was chosen) in
models/onnx/tween_generator.manifest.json. Needs the release CLI
(cargo build --release --bin deeprep) and train/cache/motion60.npz.
"""
import argparse
import json
import os
import subprocess
import sys

from deeprep_train.export.util import write_json
from deeprep_train.motion.pick_checkpoint import best, target_cells

from deeprep_train.paths import ROOT, TRAIN  # noqa: E402
GRID = ["0.15", "0.2", "0.25", "0.3", "0.4", "0.5", "1"]
MANIFEST = os.path.join(ROOT, "models", "onnx", "tween_generator.manifest.json")


def main():
    ap = argparse.ArgumentParser(description="On training takes: the generator's default variation.")
    ap.add_argument("grid", nargs="*", help=f"variations to try (default: {' '.join(GRID)})")
    grid = ap.parse_args().grid or GRID
    # generator-V: the generator pipeline at V whatever the residual manifest
    # says ("variation-V" runs --method model, the residual network on these keys)
    methods = ["slerp"] + [f"generator-{v}" for v in grid]
    subprocess.run([sys.executable, "-m", "deeprep_train.motion.eval", "--split", "train", "--methods", ",".join(methods)],
                   cwd=TRAIN, check=True)
    res = json.load(open(os.path.join(ROOT, "docs", "inbetween_eval_train.json")))
    scores = {v: target_cells(res, f"generator-{v}") for v in grid}
    for v, s in scores.items():
        print(v, json.dumps(s), flush=True)
    top = best(scores)
    print("best on training takes: variation", top, scores[top])
    write_json(os.path.join(ROOT, "docs", "inbetween_variation_train.json"),
               {"chosen": float(top), "scores": scores,
                "slerp": {m: [res[f"slerp@{g}"][m] for g in (30, 60, 120, 300)] for m in ("L2P", "NPSS")}})
    manifest = json.load(open(MANIFEST))
    manifest["variation"] = float(top)
    manifest["variation_chosen_by"] = ("train/deeprep_train/motion/pick_variation.py on training takes: most target cells met against "
                                       "SLERP+LERP (NPSS at 30/60/120/300, L2P at 30/60), then lowest mean ratio; "
                                       f"grid {', '.join(grid)}; scores in docs/inbetween_variation_train.json")
    write_json(MANIFEST, manifest)


if __name__ == "__main__":
    main()
