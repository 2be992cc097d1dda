"""Does a root path in a straight line give walking? (issue 47, item 4)

Root-only keys every 60 frames along a straight line on the floor at a walking
pace, synthesized by the CLI with a network (`--method cond` with seeds 0-2,
`--method generator`), against a captured walk on the model's skeleton
(cmu-extra's 02_01, retargeted by `motion.extra` into cache/extra60): joint
speed, foot contacts (an ankle within 2 units/frame of still and below the
clip's 10th-percentile ankle height + 5 units), how often the planted foot
changes (steps per second), and the share of frames with exactly one foot
planted.

    python -m deeprep_train.motion.straight_walk [--json OUT]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from deeprep_train.bvh import global_fk, read_bvh
from deeprep_train.motion.eval import cli
from deeprep_train.paths import CACHE, ROOT

WALK = os.path.join(CACHE, "extra60", "cmu-hips", "walk", "02_01.bvh")
ANKLES = ["lFoot", "rFoot"]


def gait(bvh):
    """Joint speed (units/frame, root-relative), steps per second and the share of frames
    with one foot planted, from a BVH read by read_bvh at 60 fps."""
    pos, _ = global_fk(bvh)
    names = bvh[0]
    rel = pos - pos[:, :1]
    speed = float(np.linalg.norm(np.diff(rel, axis=0), axis=-1).mean())
    feet = pos[:, [names.index(a) for a in ANKLES]]                 # [N, 2, 3]
    v = np.linalg.norm(np.diff(feet[..., [0, 2]], axis=0), axis=-1)  # horizontal, [N-1, 2]
    low = feet[1:, :, 1] < np.percentile(feet[:, :, 1], 10) + 5.0
    planted = (v < 2.0) & low
    one = planted.sum(1) == 1
    # the planted foot's side on frames with one foot down; a step is a change of side
    side = np.where(planted[:, 0] & ~planted[:, 1], 0, np.where(planted[:, 1] & ~planted[:, 0], 1, -1))
    sides = side[side >= 0]
    steps = int((np.diff(sides) != 0).sum()) if len(sides) > 1 else 0
    seconds = (pos.shape[0] - 1) / 60.0
    hips_speed = float(np.linalg.norm(np.diff(pos[:, 0, [0, 2]], axis=0), axis=-1).mean() * 60)
    return {"joint_speed": round(speed, 4), "steps_per_s": round(steps / seconds, 2),
            "one_foot_planted": round(float(one.mean()), 3), "hips_speed_units_per_s": round(hips_speed, 1)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json")
    ap.add_argument("--frames", type=int, default=361)
    args = ap.parse_args()
    if not os.path.exists(WALK):
        sys.exit(f"SKIP: {WALK} is absent (python -m deeprep_train.motion.extra writes it)")
    truth = read_bvh(WALK)
    t = gait(truth)
    pos, _ = global_fk(truth)
    height = float(np.median(pos[:, 0, 1]))
    pace = t["hips_speed_units_per_s"] / 60.0    # units per frame, the captured walk's
    n = args.frames
    keys = [{"frame": f, "root": [pace * f, height, 0.0]} for f in range(0, n, 60)]
    if keys[-1]["frame"] != n - 1:
        keys.append({"frame": n - 1, "root": [pace * (n - 1), height, 0.0]})
    out = {"truth": {"clip": "cmu-extra cmu-hips/walk/02_01 on the model's skeleton", **t},
           "keys": f"root only, every 60 frames on a straight line at {pace * 60:.1f} units/s, hips at {height:.1f}"}
    with tempfile.TemporaryDirectory() as tmp:
        kf = os.path.join(tmp, "keys.json")
        with open(kf, "w") as f:
            json.dump({"keys": keys}, f)
        runs = [("cond", ["--method", "cond", "--seed", str(s)], f"cond seed {s}") for s in range(3)]
        runs.append(("generator", ["--method", "generator"], "generator"))
        for _, flags, label in runs:
            o = os.path.join(tmp, "out.bvh")
            r = subprocess.run([cli(), "inbetween", kf, "--frames", str(n), "-o", o] + flags,
                               capture_output=True, text=True, cwd=ROOT)
            if r.returncode != 0:
                sys.exit(f"{label}: {r.stderr}")
            g = gait(read_bvh(o))
            g["speed_over_truth"] = round(g["joint_speed"] / t["joint_speed"], 2)
            out[label] = g
    print(json.dumps(out, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
