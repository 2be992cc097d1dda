"""Writes the bundled examples: models/examples/poses.json (a small pose
library for the page) and models/examples/keys.json (the CLI's default
keys). The poses are single frames of validation takes of the CMU data
(their licence allows use; a handful of poses, not the data set), as BVH
channel rows of the thesis skeleton; root x/z are zeroed so every pose
stands at the origin.
Run: train/.venv/bin/python -m deeprep_train.motion.make_examples
"""
import json
import os
import sys

from deeprep_train.motion.data import DATA  # noqa: E402

from deeprep_train.paths import ROOT  # noqa: E402
# (clip, frames per 60 fps frame, frame at 60 fps, name)
PICKS = [("salsa/04.bvh", 1, 400, "salsa step"), ("salsa/04.bvh", 1, 1100, "salsa turn"),
         ("salsa/19.bvh", 1, 700, "salsa partner"), ("martial/10.bvh", 2, 300, "martial guard"),
         ("martial/10.bvh", 2, 1000, "martial kick"), ("indian/15.bvh", 2, 900, "indian dance")]


def frame_row(path, step, frame60):
    text = open(os.path.join(DATA, path)).read()
    lines = [x for x in text.split("MOTION", 1)[1].strip().splitlines()[2:] if x.strip()]
    row = [float(v) for v in lines[frame60 * step].split()]
    row[0] = 0.0
    row[2] = 0.0
    return row


def main():
    if not os.path.isdir(DATA):
        sys.exit(f"SKIP: {DATA} is absent")
    poses = [{"name": n, "source": f"CMU {p} frame {f} at 60 fps", "channels": frame_row(p, s, f)} for p, s, f, n in PICKS]
    out = os.path.join(ROOT, "models", "examples")
    os.makedirs(out, exist_ok=True)
    json.dump({"about": "Pose library: BVH channel rows of the thesis skeleton (models/onnx/tween_generator.manifest.json).",
               "poses": poses}, open(os.path.join(out, "poses.json"), "w"))
    keys = [{"frame": 0, "channels": poses[0]["channels"]},
            {"frame": 150, "channels": [*([60.0, poses[3]["channels"][1], 40.0]), *poses[3]["channels"][3:]]},
            {"frame": 299, "channels": [*([120.0, poses[1]["channels"][1], 0.0]), *poses[1]["channels"][3:]]}]
    json.dump({"frames": 300, "keys": keys}, open(os.path.join(out, "keys.json"), "w"))
    print("wrote", out)


if __name__ == "__main__":
    main()
