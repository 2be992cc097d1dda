"""Writes tests/fixtures/dense_torch.json: keys with partial masks through the
PyTorch dense input (Fig. 5.3) and the interpolated raw channels (every base_channels base), for the
Rust parity test in tests/native/motion.rs. No data needed.
Run: train/.venv/bin/python -m deeprep_train.motion.make_dense_fixture"""
import json
import os

import torch

from deeprep_train.motion.nets import BASES, SCALE, base_channels, dense_input, interp_channels  # noqa: E402

from deeprep_train.paths import ROOT  # noqa: E402


def main():
    g = torch.Generator().manual_seed(4)
    n, J, R = 70, 4, 9
    P = 3 * J
    frames = [3, 20, 21, 47, 66]
    pos = torch.randn(len(frames), P, generator=g) * 40
    mask = torch.rand(len(frames), P, generator=g) > 0.3
    mask[1] = True
    mask[2, 3:] = False  # a root-only key
    raw = torch.randn(len(frames), R, generator=g) * 1.5
    rmask = torch.zeros(len(frames), R, dtype=torch.bool)
    rmask[[0, 1, 4]] = True  # whole-pose keys carry raw values
    # network-space pose: root x/z relative to the mean root x/z of keys giving both
    has = mask[:, 0] & mask[:, 2]
    ref = pos[has][:, [0, 2]].mean(0)
    net = pos.clone()
    net[:, 0] -= ref[0]
    net[:, 2] -= ref[1]
    net /= SCALE
    full = torch.zeros(1, n, P)
    fm = torch.zeros(1, n, P, dtype=torch.bool)
    rv = torch.zeros(1, n, R)
    rm = torch.zeros(1, n, R, dtype=torch.bool)
    for i, f in enumerate(frames):
        full[0, f], fm[0, f], rv[0, f], rm[0, f] = net[i], mask[i], raw[i], rmask[i]
    dense = dense_input(full, fm, n)[0]
    drot = dense_input(rv, rm, n)[0]
    drot[:R] = interp_channels(rv, rm)[0].T
    out = {"frames": n, "joints": J, "raw_width": R,
           "keys": [{"frame": f, "positions": pos[i].tolist(), "mask": mask[i].tolist(),
                     "raw": raw[i].tolist() if bool(rmask[i].all()) else None} for i, f in enumerate(frames)],
           "dense": dense.flatten().tolist(), "dense_rot": drot.flatten().tolist(),
           "bases": {b: base_channels(rv, rm, b)[0].T.flatten().tolist() for b in BASES}}
    json.dump(out, open(os.path.join(ROOT, "tests", "fixtures", "dense_torch.json"), "w"))
    print("wrote tests/fixtures/dense_torch.json")


if __name__ == "__main__":
    main()
