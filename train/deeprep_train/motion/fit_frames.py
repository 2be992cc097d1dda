"""Fits the elbows' hinge axes to the data and writes them into Table D.1's JSON.

Table D.1 lets the forearm bend about one axis only (local x range [0, 0],
flexion about local y in [0, 150], twist about the bone z in [-30, 120]), but
the thesis does not say which axis around the bone is local y. In the CMU
data the elbow is an exact hinge: over the training clips the hand's
direction in the forearm's BVH frame stays within 0.5 degrees of one plane
through the bone. This script finds that plane's normal per side (the
smallest principal axis of the hand directions projected off the bone),
orients it so that flexion is positive (a positive rotation about local y
moves the bone towards local x, where the hand goes), and stores it as the
joint's ``"frame": {"y": [...]}`` in ``crate/data/table_d1.json``, read by
both crate/src/rcfk.rs and train/deeprep_train/rcfk.py.

Usage: ``train/.venv/bin/python -m deeprep_train.motion.fit_frames [--dry-run]``.
Validation takes are not used.
"""
import argparse
import json
import os
import sys

import numpy as np

from deeprep_train.motion.data import DATA, TRUE_FPS, VALIDATION, take_of  # noqa: E402
from deeprep_train.rcfk import TABLE_PATH, local_frame  # noqa: E402
from deeprep_train.bvh import axis_rot, read_bvh  # noqa: E402


def local_rotation(bvh, joint):
    """The joint's BVH rotation matrices [F, 3, 3] (channels applied in file order)."""
    names, _, _, chans, data = bvh
    col = 0
    for j, ch in enumerate(chans):
        r = np.broadcast_to(np.eye(3), (len(data), 3, 3)).copy()
        for c in ch:
            if c.endswith("rotation"):
                r = r @ axis_rot(c[0], np.radians(data[:, col]))
            col += 1
        if names[j] == joint:
            return r
    raise KeyError(joint)


def fit(clips, side):
    dirs, o = [], None
    for path in clips:
        bvh = read_bvh(path)
        names, offsets = bvh[0], bvh[2]
        o = offsets[names.index(side + "Hand")]
        r = local_rotation(bvh, side + "ForeArm")[::2]
        dirs.append(r @ (o / np.linalg.norm(o)))
    d = np.concatenate(dirs)
    m = local_frame(o.tolist(), "z").numpy()
    x0, y0, z = m[:, 0], m[:, 1], m[:, 2]
    q = np.stack([d @ x0, d @ y0], 1)
    _, vecs = np.linalg.eigh(q.T @ q)
    y = vecs[0, 0] * x0 + vecs[1, 0] * y0
    x = np.cross(y, z)
    if (d @ x).mean() < 0:  # flexion must be positive: the hand moves towards +x
        y = -y
    off_plane = np.degrees(np.arcsin(np.clip(np.abs(d @ y), 0, 1)))
    before = np.degrees(np.arcsin(np.clip(np.abs(d @ y0), 0, 1)))
    return y, {"frames": int(len(d)), "off_plane_deg_mean": float(off_plane.mean()), "off_plane_deg_max": float(off_plane.max()),
               "previous_rule_off_plane_deg_mean": float(before.mean())}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dry-run", action="store_true")
    args = ap.parse_args()
    if not os.path.isdir(DATA):
        sys.exit(f"SKIP: {DATA} is absent")
    clips = [os.path.join(DATA, c, n) for c in sorted(TRUE_FPS) for n in sorted(os.listdir(os.path.join(DATA, c)))
             if n.endswith(".bvh") and take_of(c, int(n[:-4])) not in VALIDATION]
    doc = json.load(open(TABLE_PATH))
    for side in "lr":
        y, report = fit(clips, side)
        print(side + "ForeArm", "local y =", np.round(y, 4).tolist(), json.dumps(report))
        for row in doc["joints"]:
            if row["joint"] == side + "ForeArm":
                row["frame"] = {"y": [round(float(v), 4) for v in y]}
    if not args.dry_run:
        with open(TABLE_PATH, "w") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")
        print("wrote", os.path.relpath(TABLE_PATH))


if __name__ == "__main__":
    main()
