"""The rotation autoencoder sanity test (thesis Sec. 4.4.1, Fig. 4.5 a-c, and
App. C.7.2 / Fig. C.3): an MLP encoder (4 fully connected layers, 128
hidden, LeakyReLU) from a rotation matrix to a representation, the fixed map
back to SO(3), and an L2 loss on matrices. Representations: 6D, 5D,
quaternion, quaternion on one hemisphere, axis-angle, Euler angles (XYZ),
Rodrigues vector. Two samplings for training and testing: uniform axis and
angle (the main text's) and uniform on SO(3) (App. C.7.2). Tested on 10^5
rotations: geodesic error mean, max, std and percentiles.

Writes docs/rotation_sanity.json and docs/rotation_sanity.png.
Run: train/.venv/bin/python -m deeprep_train.sanity.rotations --iters 20000
"""
import argparse
import json
import math
import os
import time

import numpy as np
import torch
import torch.nn as nn

from deeprep_train.rotation import geodesic, normalize, quat_to_matrix, random_so3, sixd_to_matrix  # noqa: E402

from deeprep_train.paths import ROOT  # noqa: E402


def axis_angle_matrix(axis, angle):
    """Rodrigues' formula; axis [..., 3] (normalized here), angle [...]."""
    k = normalize(axis)
    x, y, z = k.unbind(-1)
    c, s = torch.cos(angle), torch.sin(angle)
    t = 1 - c
    return torch.stack([
        torch.stack([c + x * x * t, x * y * t - z * s, x * z * t + y * s], -1),
        torch.stack([y * x * t + z * s, c + y * y * t, y * z * t - x * s], -1),
        torch.stack([z * x * t - y * s, z * y * t + x * s, c + z * z * t], -1)], -2)


def unproject(u):
    """Q of eq. 4.9: R^{m-1} -> R^m."""
    n = torch.sqrt((u * u).sum(-1, keepdim=True) + 1e-12)
    return torch.cat([(n * n - 1) / 2, u], -1) / n


def euler_xyz(a):
    def rot(axis, t):
        c, s = torch.cos(t), torch.sin(t)
        o, z = torch.ones_like(t), torch.zeros_like(t)
        m = {0: [[o, z, z], [z, c, -s], [z, s, c]], 1: [[c, z, s], [z, o, z], [-s, z, c]], 2: [[c, -s, z], [s, c, z], [z, z, o]]}[axis]
        return torch.stack([torch.stack(r, -1) for r in m], -2)
    return rot(0, a[..., 0]) @ rot(1, a[..., 1]) @ rot(2, a[..., 2])


DECODERS = {
    "6D": (6, sixd_to_matrix),
    "5D": (5, lambda r: sixd_to_matrix(torch.cat([r[..., :2], unproject(r[..., 2:5])], -1))),
    "Quat": (4, lambda r: quat_to_matrix(normalize(r))),
    "Quat-hemi": (4, lambda r: quat_to_matrix(normalize(torch.cat([r[..., :3], r[..., 3:].abs()], -1)))),
    "AxisA": (4, lambda r: axis_angle_matrix(r[..., :3], r[..., 3])),
    "Euler": (3, euler_xyz),
    "Rodriguez": (3, lambda r: axis_angle_matrix(r, torch.sqrt((r * r).sum(-1) + 1e-12))),
}


def sample(n, kind, g):
    if kind == "so3":
        return random_so3(n, g).float()
    axis = torch.randn(n, 3, generator=g)
    angle = torch.rand(n, generator=g) * math.pi
    return axis_angle_matrix(axis, angle)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--iters", type=int, default=20000)
    ap.add_argument("--threads", type=int, default=1)
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    results = {}
    for kind in ["axis_angle", "so3"]:
        test = sample(100_000, kind, torch.Generator().manual_seed(99))
        for name, (dim, dec) in DECODERS.items():
            torch.manual_seed(0)
            g = torch.Generator().manual_seed(1)
            enc = nn.Sequential(nn.Linear(9, 128), nn.LeakyReLU(), nn.Linear(128, 128), nn.LeakyReLU(),
                                nn.Linear(128, 128), nn.LeakyReLU(), nn.Linear(128, dim))
            opt = torch.optim.Adam(enc.parameters(), lr=1e-3)
            sched = torch.optim.lr_scheduler.CosineAnnealingLR(opt, args.iters)
            t0 = time.time()
            for _ in range(args.iters):
                m = sample(64, kind, g)
                out = dec(enc(m.reshape(-1, 9)))
                loss = ((out - m) ** 2).sum((-1, -2)).mean()
                opt.zero_grad()
                loss.backward()
                opt.step()
                sched.step()
            with torch.no_grad():
                out = dec(enc(test.reshape(-1, 9)))
                err = torch.rad2deg(geodesic(out.double(), test.double())).numpy()
            pct = {str(p): float(np.percentile(err, p)) for p in (50, 90, 99, 99.9, 100)}
            results[f"{name}@{kind}"] = {"representation": name, "sampling": kind, "iterations": args.iters,
                                         "mean_deg": float(err.mean()), "max_deg": float(err.max()), "std_deg": float(err.std()),
                                         "percentiles_deg": pct, "train_seconds": round(time.time() - t0, 1),
                                         "curve": [float(np.percentile(err, p)) for p in np.linspace(0, 100, 101)]}
            r = results[f"{name}@{kind}"]
            print(f"{kind:<10} {name:<10} mean {r['mean_deg']:7.3f}  max {r['max_deg']:8.3f}  std {r['std_deg']:7.3f}", flush=True)
    os.makedirs(os.path.join(ROOT, "docs"), exist_ok=True)
    json.dump(results, open(os.path.join(ROOT, "docs", "rotation_sanity.json"), "w"), indent=1)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(12, 4))
        for i, kind in enumerate(["axis_angle", "so3"]):
            for name in DECODERS:
                ax[i].plot(np.linspace(0, 100, 101), results[f"{name}@{kind}"]["curve"], label=name)
            ax[i].set_yscale("log")
            ax[i].set_xlabel("percentile")
            ax[i].set_ylabel("geodesic error (degrees)")
            ax[i].set_title(f"sanity test, {args.iters} iterations, sampling: {kind}")
        ax[0].legend()
        fig.tight_layout()
        fig.savefig(os.path.join(ROOT, "docs", "rotation_sanity.png"), dpi=100)
    except ImportError:
        pass


if __name__ == "__main__":
    main()
