"""Writes tests/fixtures/rcfk_torch.json: random network outputs through the
PyTorch RC-FK layer, for the Rust parity test (tests/native/rcfk.rs).

Uses the thesis skeleton (../shared/data/cmu-bvh/standard.bvh): its hierarchy
text is stored in the fixture, so the Rust test runs without ../shared.
Run: train/.venv/bin/python -m deeprep_train.motion.make_rcfk_fixture
"""
import json
import os

import torch

from deeprep_train.bvh import read_hierarchy  # noqa: E402
from deeprep_train.rcfk import RCFK  # noqa: E402

from deeprep_train.paths import ROOT  # noqa: E402


def main():
    src = os.path.join(ROOT, "..", "shared", "data", "cmu-bvh", "standard.bvh")
    text = open(src).read()
    hierarchy = text[: text.index("MOTION")]
    names, parents, offsets, channels = read_hierarchy(hierarchy)
    layer = RCFK(names, parents, offsets, [len(c) > 0 for c in channels]).double()
    g = torch.Generator().manual_seed(0)
    frames = 64
    raw = torch.randn(frames, layer.output_dim, generator=g, dtype=torch.float64) * 1.5
    root = torch.randn(frames, 3, generator=g, dtype=torch.float64) * 40
    with torch.no_grad():
        pos = layer(raw, root)
    out = {
        "skeleton_bvh": hierarchy + "MOTION\nFrames: 0\nFrame Time: 0.0166667\n",
        "frames": frames,
        "output_dim": layer.output_dim,
        "raw": [float(x) for x in raw.float().flatten()],
        "root_pos": [float(x) for x in root.float().flatten()],
        "positions_torch": [float(x) for x in pos.flatten()],
        "torch_version": torch.__version__,
    }
    path = os.path.join(ROOT, "tests", "fixtures", "rcfk_torch.json")
    json.dump(out, open(path, "w"))
    print("wrote", path, "positions", tuple(pos.shape))


if __name__ == "__main__":
    main()
