"""Settles the residual network's place (issue 19) on the *training* takes:
its default `variation`, by the rule train/deeprep_train/motion/pick_variation.py uses for the
generator (most cells of the issue's target met against SLERP+LERP, then
the lowest mean ratio), and whether `--method model` runs it for whole-pose
keys: it does when, at that variation, it beats the generator at its own
default on L2P and NPSS at every gap. The validation takes the README
reports are not looked at.

  train/.venv/bin/python -m deeprep_train.motion.pick_residual [V ...]   (default grid below)

Runs train/deeprep_train/motion/eval.py once (--split train) with SLERP+LERP, the
generator at its default and the residual network at each V, writes
docs/inbetween_residual_default_train.json and sets `variation`,
`default_for_whole_pose_keys` and how they were chosen in
models/onnx/tween_residual.manifest.json.
"""
import argparse
import json
import os
import subprocess
import sys

from deeprep_train.export.util import write_json
from deeprep_train.motion.pick_checkpoint import GAPS, best, target_cells

from deeprep_train.paths import ROOT, TRAIN  # noqa: E402
GRID = ["0.75", "1", "1.25"]
MANIFEST = os.path.join(ROOT, "models", "onnx", "tween_residual.manifest.json")


def main():
    ap = argparse.ArgumentParser(description="On training takes: the residual network's default variation and whether it is the model method.")
    ap.add_argument("grid", nargs="*", help=f"variations to try (default: {' '.join(GRID)})")
    grid = ap.parse_args().grid or GRID
    methods = ["slerp", "generator"] + [f"residual-{v}" for v in grid]
    subprocess.run([sys.executable, "-m", "deeprep_train.motion.eval", "--split", "train", "--methods", ",".join(methods)],
                   cwd=TRAIN, check=True)
    res = json.load(open(os.path.join(ROOT, "docs", "inbetween_eval_train.json")))
    scores = {v: target_cells(res, f"residual-{v}") for v in grid}
    for v, s in scores.items():
        print(v, json.dumps(s), flush=True)
    top = best(scores)
    r, g = f"residual-{top}", "generator"
    beats = {f"{metric}@{gap}": res[f"{r}@{gap}"][metric] < res[f"{g}@{gap}"][metric]
             for metric in ("L2P", "NPSS") for gap in GAPS}
    default = all(beats.values())
    print("variation", top, "; beats the generator:", json.dumps(beats), "-> default" if default else "-> not the default")
    write_json(os.path.join(ROOT, "docs", "inbetween_residual_default_train.json"),
               {"variation": float(top), "scores": scores, "beats_generator": beats, "default_for_whole_pose_keys": default,
                "generator": {m: [res[f"generator@{x}"][m] for x in GAPS] for m in ("L2P", "NPSS")},
                "slerp": {m: [res[f"slerp@{x}"][m] for x in GAPS] for m in ("L2P", "NPSS")}})
    manifest = json.load(open(MANIFEST))
    manifest["variation"] = float(top)
    manifest["default_for_whole_pose_keys"] = default
    manifest["chosen_by"] = ("train/deeprep_train/motion/pick_residual.py on training takes: variation by most target cells met against "
                             "SLERP+LERP (NPSS at every gap, L2P at 30/60), then lowest mean ratio, grid "
                             f"{', '.join(grid)}; the model for whole-pose keys when it beats the generator at its "
                             "default on L2P and NPSS at every gap; scores in docs/inbetween_residual_default_train.json")
    write_json(MANIFEST, manifest)


if __name__ == "__main__":
    main()
