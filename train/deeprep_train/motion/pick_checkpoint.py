"""Scores a run's generator snapshots (gen_<steps>.pt, kept while it trains
with `motion/train.py --keep-snapshots`)
on the *training* takes, so a checkpoint is chosen without looking at the
validation takes that the README reports.

  train/.venv/bin/python -m deeprep_train.motion.pick_checkpoint train/cache/run16 [STEPS ...]

For each snapshot: export it (train/deeprep_train/motion/export.py into models/onnx/), then
train/deeprep_train/motion/eval.py with --split train on SLERP+LERP and the model
without foot locking. Prints and writes RUN/pick.json: per snapshot L2P and
NPSS per gap, the cells of the issue's target it meets (NPSS at every gap,
L2P at 30 and 60 frames) and the mean ratio to SLERP+LERP over those cells.
models/onnx/ and docs/ are left changed: `git checkout models/onnx docs`
restores the bundled model, or re-export the chosen one.
"""
import argparse
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

from deeprep_train.paths import ROOT, TRAIN  # noqa: E402
PY = sys.executable
GAPS = [30, 60, 120, 300]


def score(run, ckpt):
    with tempfile.TemporaryDirectory() as tmp:
        for f in ("path.pt", "log.jsonl"):
            shutil.copy(os.path.join(run, f), tmp)
        shutil.copy(ckpt, os.path.join(tmp, "gen.pt"))
        subprocess.run([PY, "-m", "deeprep_train.motion.export", "--run", tmp], cwd=TRAIN, check=True, capture_output=True)
    # "generator": the generator pipeline without foot locking; "model" would
    # run the residual network on these whole-pose keys when it is the default
    subprocess.run([PY, "-m", "deeprep_train.motion.eval", "--split", "train", "--methods", "slerp,generator"], cwd=TRAIN,
                   check=True, capture_output=True)
    return target_cells(json.load(open(os.path.join(ROOT, "docs", "inbetween_eval_train.json"))), "generator")


def target_cells(res, method):
    """method's L2P and NPSS per gap in a motion.eval result, the cells of
    the issue's target it meets against SLERP+LERP (NPSS at every gap, L2P
    at 30 and 60) and its mean ratio to SLERP+LERP over those cells."""
    cells, ratios = 0, []
    for metric, gaps in (("NPSS", GAPS), ("L2P", [30, 60])):
        for g in gaps:
            m, s = res[f"{method}@{g}"][metric], res[f"slerp@{g}"][metric]
            cells += m < s
            ratios.append(m / s)
    return {"L2P": [res[f"{method}@{g}"]["L2P"] for g in GAPS],
            "NPSS": [res[f"{method}@{g}"]["NPSS"] for g in GAPS],
            "cells_met": int(cells), "mean_ratio_to_slerp": sum(ratios) / len(ratios),
            # the root's error at the keys before post-processing (the path predictor's share)
            "root_key_error_before_post": [res[f"{method}@{g}"].get("key_error_before_post", [None])[0] for g in GAPS]}


def best(scores):
    """The key of the best score: most cells met, then lowest mean ratio."""
    return max(scores, key=lambda k: (scores[k]["cells_met"], -scores[k]["mean_ratio_to_slerp"]))


def main():
    ap = argparse.ArgumentParser(description="Score a run's generator snapshots on the training takes and pick one.")
    ap.add_argument("run", help="run folder holding gen_<steps>.pt")
    ap.add_argument("steps", nargs="*", help="only these snapshots (default: all not yet scored)")
    args = ap.parse_args()
    run, want = args.run, set(args.steps)
    snaps = {re.fullmatch(r"gen_(\d+)\.pt", os.path.basename(p))[1]: p for p in glob.glob(os.path.join(run, "gen_*.pt"))}
    out_path = os.path.join(run, "pick.json")
    out = json.load(open(out_path)) if os.path.exists(out_path) else {}
    for steps, p in sorted(snaps.items(), key=lambda kv: int(kv[0])):
        if (want and steps not in want) or steps in out:
            continue
        out[steps] = score(run, p)
        print(steps, json.dumps(out[steps]), flush=True)
        json.dump(out, open(out_path, "w"), indent=1)
    top = best(out)
    print("best on training takes:", top, out[top])


if __name__ == "__main__":
    main()
