"""The IK test (thesis Sec. 4.4.3 and Table 5.1) on the project's CMU data.

A 4-layer MLP maps the joint positions of a pose (hip at the origin) to one
rotation per joint in a chosen representation; a fixed forward-kinematics
layer turns them back into positions; the loss is L2 on positions with a 10x
weight on the joints next to the hip. Representations compared:

- ``quat``: a unit quaternion per joint (4D, normalized), BVH rest frames;
- ``euler``: vanilla Euler angles per joint in the data's channel order (ZXY), unbounded;
- ``6d``: the continuous 6D representation per joint (eq. C.2-C.3);
- ``rc``: range-constrained Euler angles (Table D.1 through tanh) for the
  non-root joints and 6D for the root: the project's RC-FK layer.

Data: ``train/cache/motion60.npz`` (``train/deeprep_train/motion/data.py``): 59,290 train
frames, 9,451 validation frames from takes never trained on. Training poses
get a random rotation about y; every validation pose is tested under three
fixed random y rotations, as in the thesis.

Usage::

    train/.venv/bin/python -m deeprep_train.ik.train --steps 12000 [--reps quat,euler,6d,rc] [--threads 1]

Writes ``train/cache/ik/<rep>.pt`` and ``docs/ik_test.json``; ``train/deeprep_train/ik/table.py``
turns the JSON into ``docs/ik.md`` and ``docs/ik_percentiles.png``.
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np
import torch

from deeprep_train.paths import ROOT, CACHE  # noqa: E402
from deeprep_train.rcfk import RCFK, _axis_rotation  # noqa: E402
from deeprep_train.rotation import normalize, sixd_to_matrix  # noqa: E402

SCALE = 50.0  # positions are divided by this before entering the network
HIP_NEIGHBOURS = ("abdomen", "rButtock", "lButtock")
FINGERS_AND_EYES = ("Thumb", "Index", "Mid", "Ring", "Pinky", "Eye")
REPS = {"quat": 4, "euler": 3, "6d": 6}


def quat_wxyz_to_matrix(q):
    q = normalize(q)
    w, x, y, z = q.unbind(-1)
    return torch.stack([
        torch.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        torch.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        torch.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


def euler_zxy_to_matrix(a):
    """R = Rz(a0) Rx(a1) Ry(a2): the data's channel order (Zrotation Xrotation Yrotation)."""
    return _axis_rotation(2, a[..., 0]) @ _axis_rotation(0, a[..., 1]) @ _axis_rotation(1, a[..., 2])


class PlainFK(torch.nn.Module):
    """BVH forward kinematics: one local rotation per joint with channels, identity elsewhere."""

    def __init__(self, parents, offsets, channel_joints, rep):
        super().__init__()
        self.parents = list(parents)
        self.rot = [j for j, c in enumerate(channel_joints) if c]
        self.rep = rep
        self.register_buffer("offsets", torch.tensor(offsets, dtype=torch.float32))

    @property
    def output_dim(self):
        return REPS[self.rep] * len(self.rot)

    def matrices(self, raw):
        d = REPS[self.rep]
        x = raw.reshape(*raw.shape[:-1], len(self.rot), d)
        if self.rep == "quat":
            return quat_wxyz_to_matrix(x)
        if self.rep == "euler":
            return euler_zxy_to_matrix(x)
        return sixd_to_matrix(x)

    def forward(self, raw):
        m = self.matrices(raw)
        idx = {j: i for i, j in enumerate(self.rot)}
        n = len(self.parents)
        g_rot, g_pos = [None] * n, [None] * n
        eye = torch.eye(3).expand(*raw.shape[:-1], 3, 3)
        for j in range(n):
            p = self.parents[j]
            local = m[..., idx[j], :, :] if j in idx else eye
            if p < 0:
                g_rot[j] = local
                g_pos[j] = self.offsets[j].expand(*raw.shape[:-1], 3)
            else:
                g_pos[j] = g_pos[p] + (g_rot[p] @ self.offsets[j].unsqueeze(-1)).squeeze(-1)
                g_rot[j] = g_rot[p] @ local
        return torch.stack(g_pos, -2)


class RcFKHead(torch.nn.Module):
    def __init__(self, names, parents, offsets, channel_joints):
        super().__init__()
        self.fk = RCFK(names, [None if p < 0 else int(p) for p in parents], offsets, channel_joints)

    @property
    def output_dim(self):
        return self.fk.output_dim

    def forward(self, raw):
        return self.fk(raw, torch.zeros(*raw.shape[:-1], 3))


class IKNet(torch.nn.Module):
    """4 fully connected layers (3 hidden of `width`, LeakyReLU) from positions to representation values."""

    def __init__(self, joints, out_dim, width):
        super().__init__()
        self.mlp = torch.nn.Sequential(
            torch.nn.Linear(joints * 3, width), torch.nn.LeakyReLU(0.2),
            torch.nn.Linear(width, width), torch.nn.LeakyReLU(0.2),
            torch.nn.Linear(width, width), torch.nn.LeakyReLU(0.2),
            torch.nn.Linear(width, out_dim))

    def forward(self, pos):
        """pos [B, J*3] in data units (hip at the origin) -> representation values [B, out_dim]."""
        return self.mlp(pos / SCALE)


def make_head(rep, d, channel_joints):
    if rep == "rc":
        return RcFKHead(list(d["joints"]), d["parents"], d["offsets"], channel_joints)
    return PlainFK(d["parents"], d["offsets"], channel_joints, rep)


def rot_y(theta):
    c, s = torch.cos(theta), torch.sin(theta)
    o, z = torch.ones_like(theta), torch.zeros_like(theta)
    return torch.stack([torch.stack([c, z, s], -1), torch.stack([z, o, z], -1), torch.stack([-s, z, c], -1)], -2)


def load(path):
    d = np.load(path)
    rot = set(d["rotating"])
    channel_joints = [i == 0 or n in rot for i, n in enumerate(d["joints"])]
    return d, channel_joints


def validation_set(d, seed=0):
    """Every validation pose under three fixed random rotations about y: [3F, J, 3]."""
    v = torch.tensor(d["val_local"])
    g = torch.Generator().manual_seed(seed)
    th = torch.rand(3, v.shape[0], generator=g) * 2 * math.pi
    return torch.cat([torch.einsum("fij,fkj->fki", rot_y(th[i]), v) for i in range(3)])


def evaluate(net, head, val, chunk=4096):
    errs = []
    with torch.no_grad():
        for a in range(0, len(val), chunk):
            x = val[a:a + chunk]
            p = head(net(x.reshape(len(x), -1)))
            errs.append((p - x).norm(dim=-1))
    return torch.cat(errs)  # [N, J]


def stats(e):
    e = e.flatten().double()
    q = torch.quantile(e[torch.randperm(len(e), generator=torch.Generator().manual_seed(0))[:2_000_000]],
                       torch.tensor([0.5, 0.9, 0.99, 0.999], dtype=torch.float64))
    return {"mean": e.mean().item(), "max": e.max().item(), "std": e.std().item(),
            "p50": q[0].item(), "p90": q[1].item(), "p99": q[2].item(), "p99.9": q[3].item()}


def train(rep, d, channel_joints, steps, width, batch, seed, log):
    torch.manual_seed(seed)
    head = make_head(rep, d, channel_joints)
    net = IKNet(len(d["joints"]), head.output_dim, width)
    names = list(d["joints"])
    w = torch.ones(len(names))
    for n in HIP_NEIGHBOURS:
        w[names.index(n)] = 10.0
    w = w / w.mean()
    opt = torch.optim.Adam(net.parameters(), lr=1e-3)
    sched = torch.optim.lr_scheduler.CosineAnnealingLR(opt, steps, eta_min=1e-5)
    data = torch.tensor(d["train_local"])
    g = torch.Generator().manual_seed(seed)
    t0 = time.time()
    for step in range(1, steps + 1):
        idx = torch.randint(0, len(data), (batch,), generator=g)
        th = torch.rand(batch, generator=g) * 2 * math.pi
        x = torch.einsum("bij,bkj->bki", rot_y(th), data[idx])
        p = head(net(x.reshape(batch, -1)))
        loss = ((((p - x) / SCALE) ** 2).sum(-1) * w).mean()
        opt.zero_grad()
        loss.backward()
        opt.step()
        sched.step()
        if step % 500 == 0 or step == steps:
            log({"rep": rep, "step": step, "loss": loss.item(), "sec": round(time.time() - t0, 1)})
    return net, head, time.time() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=os.path.join(CACHE, "motion60.npz"))
    ap.add_argument("--steps", type=int, default=12000)
    ap.add_argument("--width", type=int, default=1024, help="hidden width (thesis: 1024)")
    ap.add_argument("--batch", type=int, default=64)
    ap.add_argument("--reps", default="quat,euler,6d,rc")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "ik_test.json"))
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    if not os.path.exists(args.data):
        sys.exit(f"{args.data} is missing: run train/deeprep_train/motion/data.py first")
    d, channel_joints = load(args.data)
    names = list(d["joints"])
    body = [i for i, n in enumerate(names) if not any(f in n for f in FINGERS_AND_EYES)]
    val = validation_set(d)
    ck_dir = os.path.join(CACHE, "ik")
    os.makedirs(ck_dir, exist_ok=True)
    results = json.load(open(args.out)) if os.path.exists(args.out) else {}
    # The floor of RC-FK: the data's own RC values (clamped into Table D.1) through RC-FK.
    rc = RcFKHead(names, d["parents"], d["offsets"], channel_joints)
    rc.fk.angles = lambda u: u  # the cache stores the clamped angles u themselves, not the pre-tanh values
    with torch.no_grad():
        floor = (rc(torch.tensor(d["val_rc"][:, 3:])) - torch.tensor(d["val_local"])).norm(dim=-1)  # columns 0-2: root position
    results["_rc_floor"] = {"all": stats(floor), "body": stats(floor[:, body])}
    results["_meta"] = {"steps": args.steps, "width": args.width, "batch": args.batch, "train_frames": int(len(d["train_local"])),
                        "val_poses": int(len(val)), "body_joints": [names[i] for i in body], "units": "BVH units (centimetre-like)",
                        "command": " ".join(["train/.venv/bin/python", "-m", "deeprep_train.ik.train"] + sys.argv[1:])}
    for rep in args.reps.split(","):
        net, head, sec = train(rep, d, channel_joints, args.steps, args.width, args.batch, args.seed, lambda x: print(json.dumps(x), flush=True))
        e = evaluate(net, head, val)
        results[rep] = {"all": stats(e), "body": stats(e[:, body]), "train_seconds": round(sec, 1),
                        "percentile_curve": torch.quantile(e.flatten()[::7], torch.linspace(0, 1, 101)).tolist()}
        torch.save({"net": net.state_dict(), "rep": rep, "width": args.width, "steps": args.steps, "joints": names,
                    "result": results[rep]}, os.path.join(ck_dir, f"{rep}.pt"))
        print(json.dumps({"rep": rep, **results[rep]["all"]}), flush=True)
        with open(args.out, "w") as f:
            json.dump(results, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
