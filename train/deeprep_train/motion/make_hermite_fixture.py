"""Writes tests/fixtures/hermite_torch.json: cond.py's `hermite_base` (the
conditional network's base over gaps with context, issue 50) on three gaps
of a training take, for the native test that checks its Rust twin
(`motion::fill::hermite_curve`, which `motion::cond` builds the same base
with) against it.

    python -m deeprep_train.motion.make_hermite_fixture
"""
import json
import os

import numpy as np
import torch

from deeprep_train.motion.cond import hermite_base
from deeprep_train.motion.residual.data import CACHE, Clips
from deeprep_train.paths import ROOT


def main():
    clips = Clips(np.load(os.path.join(CACHE, "resid60.npz")), "train")
    out = []
    # (first frame of the take's window, a, b, context before, context after)
    for start, a, b, prev, nxt in [(500, 5, 25, True, True), (2000, 3, 40, True, False), (4000, 4, 14, False, True)]:
        root = clips.root[start:start + b + 2].double()
        quat = clips.quat[start:start + b + 2].double()
        base_root = torch.zeros_like(root)
        base_q = quat.clone()
        hermite_base([(a, b, a - 1 if prev else None, b + 1 if nxt else None)], root, quat, base_root, base_q)
        frames = [f for f in (a - 1 if prev else None, a, b, b + 1 if nxt else None) if f is not None]
        out.append({
            "a": a, "b": b, "prev": prev, "next": nxt,
            "keys": {str(f): {"root": root[f].tolist(), "quat_wxyz": quat[f].tolist()} for f in frames},
            "root": base_root[a + 1:b].tolist(),
            "quat_wxyz": base_q[a + 1:b].tolist(),
        })
    path = os.path.join(ROOT, "tests", "fixtures", "hermite_torch.json")
    with open(path, "w") as f:
        json.dump({"about": __doc__.split("\n\n")[0], "gaps": out}, f)
    print(f"wrote {os.path.relpath(path, ROOT)} ({os.path.getsize(path) / 1e3:.0f} kB)")


if __name__ == "__main__":
    main()
