"""Trains the global path predictor, then the local motion generator with its
discriminator (thesis Sec. 5.2.4-5.2.7), on train/cache/motion60.npz (made by
train/deeprep_train/motion/data.py). Checkpoints go to train/cache/tween/*.pt; a JSON
log of losses to train/cache/tween/log.jsonl.

  train/.venv/bin/python -m deeprep_train.motion.train --path-minutes 6 --gen-minutes 50

See train/README.md for the deviations from the thesis.
"""
import argparse
import copy
import json
import math
import os
import shutil
import sys
import time

import numpy as np
import torch

from deeprep_train.bvh import mirror_joints  # noqa: E402
from deeprep_train.motion.dna import representative_frames  # noqa: E402
from deeprep_train.rcfk import RCFK  # noqa: E402
from deeprep_train.rotation import sixd_to_matrix  # noqa: E402
from deeprep_train.motion.nets import (SCALE, GAN_TARGET, Discriminator, Generator, PathPredictor,  # noqa: E402
                                 base_channels, dense_input, path_loss, rc_to_raw, BASES)

from deeprep_train.paths import CACHE, TRAIN  # noqa: E402
# where checkpoints and the log go by default (--out)
OUT = os.path.join(CACHE, "tween")
W = {"recon": 100.0, "vel": 100.0, "acc": 0.0, "spec": 0.0, "rot": 0.0, "path": 0.0, "key": 300.0, "root": 50.0, "gan": 1.0, "br": 5.0,
     "dna1": 50.0, "dna2": 50.0}
# DNA weights can be overridden (--dna-weight): at this training budget the
# thesis' 50 lets the generator flash DNA poses in single frames (run 3).


class Data:
    def __init__(self, path, split):
        d = np.load(path)
        self.local = torch.from_numpy(d[f"{split}_local"])      # [F, J, 3]
        self.root = torch.from_numpy(d[f"{split}_root"])        # [F, 3]
        self.rc = torch.from_numpy(d[f"{split}_rc"])            # [F, 3 + 6 + 3K]
        lens = d[f"{split}_seg_len"]
        self.starts = np.concatenate([[0], np.cumsum(lens)[:-1]])
        self.lens = lens
        self.joints = list(d["joints"])
        self.parents = [None if p < 0 else int(p) for p in d["parents"]]
        self.offsets = d["offsets"].tolist()
        rot = set(d["rotating"])
        self.channel_joints = [i == 0 or n in rot for i, n in enumerate(self.joints)]

    def window(self, n, rng):
        ok = np.nonzero(self.lens >= n)[0]
        s = rng.choice(ok, p=self.lens[ok] / self.lens[ok].sum())
        a = self.starts[s] + rng.integers(0, self.lens[s] - n + 1)
        return slice(int(a), int(a) + n)


def lam(local, r6):
    """Λ: local pose without the root rotation. local [..., J, 3], r6 [..., 6]."""
    r = sixd_to_matrix(r6)
    return local @ r  # rows: p^T R = (R^T p)^T


def rep_frames(rc, k):
    """Representative frames of a window's RC values [N, C] (Sec. 5.2.5):
    motion.dna's rule on the joint angles (the root's 9 values left out)."""
    return representative_frames(rc[:, 9:].detach().cpu().numpy(), k)


def spectral_loss(gen, gt, keysets, min_gap=30):
    """NPSS-style loss (not in the thesis; run 15): LaFAN1's power spectrum
    (real part of the FFT, squared) of every coordinate over each key
    interval of at least min_gap frames, as a cumulative distribution over
    frequency; the earth mover's distance between generated and captured
    motion, weighted by the captured power. gen, gt: [B, N, F]."""
    out = []
    for i, keys in enumerate(keysets):
        for a, z in zip(keys[:-1], keys[1:]):
            if z - a - 1 < min_gap:
                continue
            pg = torch.fft.fft(gen[i, a + 1:z], dim=0).real ** 2
            pt = torch.fft.fft(gt[i, a + 1:z], dim=0).real ** 2
            tg, tt = pg.sum(0), pt.sum(0)
            cg = torch.cumsum(pg / tg.clamp(min=1e-8), 0)
            ct = torch.cumsum(pt / tt.clamp(min=1e-8), 0)
            w = tt / tt.sum()
            # per frame, so gaps of every length weigh alike
            out.append(((cg - ct).abs().sum(0) * w).sum() / (z - a - 1))
    return torch.stack(out).mean() if out else torch.zeros(())


def smoothstep_spread(n, frames):
    """[n, len(frames)] weights that spread per-key errors over all frames the
    way post-processing does (crate/src/motion/post.rs): smoothstep between
    consecutive keys, the nearest key's error held outside them."""
    w = torch.zeros(n, len(frames))
    t = torch.arange(n, dtype=torch.float32)
    w[: frames[0] + 1, 0] = 1
    w[frames[-1]:, -1] = 1
    for i, (a, b) in enumerate(zip(frames[:-1], frames[1:])):
        s = (t[a:b + 1] - a) / (b - a)
        s = s * s * (3 - 2 * s)
        w[a:b + 1, i] = 1 - s
        w[a:b + 1, i + 1] = s
    return w


def path_after_post(T, root, mask, keysets):
    """The predicted root path T [B, N, 3] with post-processing's key
    correction applied per coordinate (keys where that root coordinate is
    given), as the pipeline outputs it. Differentiable in T."""
    out = T.clone()
    for i, keys in enumerate(keysets):
        for c in range(3):
            ks = [t for t in keys if mask[i, t, c]]
            if not ks:
                continue
            w = smoothstep_spread(T.shape[1], ks)
            out[i, :, c] = T[i, :, c] + w @ (root[i, ks, c] - T[i, ks, c])
    return out


def sample_keys(n, rng, gaps="uniform"):
    """Key frames in a window of n: intervals drawn from [8, 300), uniformly
    or log-uniformly (gaps="loguniform", --gaps)."""
    keys, t = [], int(rng.integers(0, 16))
    while t < n:
        keys.append(t)
        if gaps == "loguniform":
            t += int(math.exp(rng.uniform(math.log(8), math.log(300))))
        else:
            t += int(rng.integers(8, 300))
    if keys[-1] < n - 40 and rng.random() < 0.7:
        keys.append(n - 1 - int(rng.integers(0, 16)))
    return keys


def make_batch(data, b, n, rng, fk, gaps="uniform", base="linear"):
    J = len(data.joints)
    P = J * 3
    R = fk.output_dim
    pose = torch.zeros(b, n, P)
    mask = torch.zeros(b, n, P, dtype=torch.bool)
    rpose = torch.zeros(b, n, R)
    rmask = torch.zeros(b, n, R, dtype=torch.bool)
    local, root, rc, dna, keysets = [], [], [], [], []
    k_dna = max(1, n // 180)
    for i in range(b):
        sl = data.window(n, rng)
        lo, ro, r = data.local[sl], data.root[sl], data.rc[sl]
        keys = sample_keys(n, rng, gaps)
        ref = ro[keys][:, [0, 2]].mean(0)
        frame_pose = lo.clone()
        frame_pose[:, 0, :] = ro
        frame_pose[:, 0, 0] -= ref[0]
        frame_pose[:, 0, 2] -= ref[1]
        frame_pose = frame_pose.reshape(n, P) / SCALE
        raw_gt = rc_to_raw(r, fk.lo, fk.hi)
        for t in keys:
            u = rng.random()
            if u < 0.8:
                m = torch.ones(P, dtype=torch.bool)
                rpose[i, t] = raw_gt[t]
                rmask[i, t] = True
            elif u < 0.9:  # root only
                m = torch.zeros(P, dtype=torch.bool)
                m[:3] = True
            else:  # 2-D keys: x and y of every joint
                m = torch.zeros(J, 3, dtype=torch.bool)
                m[:, :2] = True
                m = m.reshape(P)
            pose[i, t] = frame_pose[t]
            mask[i, t] = m
        local.append(lo)
        root.append(ro - torch.tensor([ref[0], 0.0, ref[1]]))
        rc.append(r)
        idx = rep_frames(r, k_dna)
        dna.append(lam(lo[idx], r[idx, 3:9]).reshape(len(idx), P) / SCALE)
        keysets.append(keys)
    dense_rot = dense_input(rpose, rmask, n)
    dense_rot[:, :R] = base_channels(rpose, rmask, base).transpose(1, 2)
    return (dense_input(pose, mask, n), dense_rot, mask, torch.stack(dna), torch.stack(local),
            torch.stack(root), torch.stack(rc), keysets)


def augment_path_window(local, vel, rng, mirror_map):
    """Issue 19's data augmentation for the path predictor, which maps
    root-relative joint positions (world axes) to root velocity: the same
    window turned about the vertical axis by a random angle and, half the
    time, mirrored left/right (x -> -x, joints swapped). Both are exact
    symmetries of the mapping. local [N, J, 3], vel [N, 3]."""
    t = rng.uniform(0, 2 * math.pi)
    c, s = math.cos(t), math.sin(t)
    r = torch.tensor([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]], dtype=local.dtype)
    if rng.random() < 0.5:
        flip = torch.tensor([-1.0, 1.0, 1.0], dtype=local.dtype)
        local, vel = local[:, mirror_map] * flip, vel * flip
    return local @ r.T, vel @ r.T


def train_path(data, minutes, log, rng, config, decay=False, augment=False):
    """Trains the path predictor on ground-truth windows of 256 frames, batch 8,
    Adam at 1e-3 (cosine-decayed to 1e-5 over the budget when decay); with
    augment, each window turned about the vertical and mirrored at random."""
    net = PathPredictor(len(data.joints) * 3, **config)
    mirror_map = mirror_joints(data.joints)
    opt = torch.optim.Adam(net.parameters(), lr=1e-3)
    t0, step = time.time(), 0
    while time.time() - t0 < minutes * 60:
        if decay:
            f = min(1.0, (time.time() - t0) / (minutes * 60))
            for group in opt.param_groups:
                group["lr"] = 1e-5 + (1e-3 - 1e-5) * 0.5 * (1 + math.cos(math.pi * f))
        xs, vs = [], []
        for _ in range(8):
            sl = data.window(256, rng)
            lo = data.local[sl]
            r = data.root[sl]
            v = torch.zeros_like(r)
            v[:-1] = r[1:] - r[:-1]
            if augment:
                lo, v = augment_path_window(lo, v, rng, mirror_map)
            xs.append(lo.reshape(256, -1).T / SCALE)
            vs.append(v.T / SCALE)
        x, v = torch.stack(xs), torch.stack(vs)
        loss = path_loss(net(x), v)
        opt.zero_grad()
        loss.backward()
        opt.step()
        step += 1
        if step % 200 == 0:
            log({"stage": "path", "step": step, "loss": loss.item(), "sec": time.time() - t0})
    net.eval()
    return net, step


def path_table(net, data, rng, windows=64, n=512):
    """Table 5.2's columns on held-out windows: mean xz error of the n-frame root displacement (V_n) and y error."""
    errs = {k: [] for k in range(8)}
    yerr = {k: [] for k in range(8)}
    with torch.no_grad():
        for _ in range(windows):
            sl = data.window(n, rng)
            v = net(data.local[sl].reshape(n, -1).T.unsqueeze(0) / SCALE)[0].T * SCALE
            cp = torch.cumsum(v, 0)
            r = data.root[sl]
            for k in range(8):
                m = 2 ** k
                dp = cp[m:] - cp[:-m]
                dt = r[m + 1:] - r[1:-m]
                d = (dp[: len(dt)] - dt)[:, [0, 2]].norm(dim=1)
                errs[k].append(d.mean().item())
                yerr[k].append((dp[: len(dt), 1] - dt[:, 1]).abs().mean().item())
    # Y: the mean y-displacement error over the same intervals.
    return {f"V{2 ** k}": float(np.mean(errs[k])) for k in range(8)} | {"Y": float(np.mean([np.mean(v) for v in yerr.values()]))}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--data", default=os.path.join(CACHE, "motion60.npz"))
    ap.add_argument("--out", default=OUT, help="directory of the checkpoints and log (default train/cache/tween)")
    ap.add_argument("--path-minutes", type=float, default=6)
    ap.add_argument("--path-width", type=int, default=128)
    ap.add_argument("--path-layers", type=int, default=6)
    ap.add_argument("--path-dilations", default="1,2,3", help="dilations the path predictor's layers cycle through")
    ap.add_argument("--path-decay", action="store_true", help="cosine-decay the path predictor's learning rate")
    ap.add_argument("--path-ckpt", default=None, help="reuse a trained path predictor (path.pt) instead of training one")
    ap.add_argument("--path-augment", action="store_true",
                    help="train the path predictor on windows turned about the vertical and mirrored at random (issue 19)")
    ap.add_argument("--path-only", action="store_true",
                    help="train and evaluate the path predictor (path.pt, Table 5.2 on train and val windows), then stop")
    ap.add_argument("--gen-minutes", type=float, default=50)
    ap.add_argument("--frames", type=int, default=512)
    ap.add_argument("--batch", type=int, default=4)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--dna-weight", type=float, default=None, help="weight of each DNA loss (thesis: 50)")
    ap.add_argument("--lr-g", type=float, default=2e-4, help="generator learning rate (Adam)")
    ap.add_argument("--lr-d", type=float, default=1e-4, help="discriminator learning rate (Adam)")
    ap.add_argument("--acc-weight", type=float, default=0.0,
                    help="weight of the acceleration loss (not in the thesis; runs 8-12: jitter, see train/README.md)")
    ap.add_argument("--gan-weight", type=float, default=None, help="weight of the generator's GAN loss (default 1)")
    ap.add_argument("--gaps", choices=["uniform", "loguniform"], default="uniform",
                    help="key interval distribution; loguniform trains short gaps as often as long ones (runs 11-12)")
    ap.add_argument("--gate-tau", type=float, default=None,
                    help="gate the generator's correction by the distance to the nearest key, tau in seconds (run 13)")
    ap.add_argument("--spec-weight", type=float, default=0.0,
                    help="weight of the NPSS-style spectral loss on key intervals (not in the thesis; run 15)")
    ap.add_argument("--skips", type=int, default=0,
                    help="U-Net skips into the decoder's last levels (not in the thesis; run 16)")
    ap.add_argument("--ema", type=float, default=None,
                    help="keep an exponential moving average of the generator's weights with this decay "
                         "(e.g. 0.999; not in the thesis; run 18) and export it")
    ap.add_argument("--keep-snapshots", action="store_true",
                    help="also keep every 500-step checkpoint as gen_<steps>.pt (for train/deeprep_train/motion/pick_checkpoint.py)")
    ap.add_argument("--base", choices=BASES, default="linear",
                    help="what the generator corrects between whole-pose keys (base_channels): their raw RC-FK "
                         "values interpolated linearly (runs 9-19) or on a C1 spline, in raw space or in angle")
    ap.add_argument("--rot-weight", type=float, default=0.0,
                    help="weight of a loss on global joint rotations (squared Frobenius distance to the ground "
                         "truth's through RC-FK; not in the thesis; session 8): what L2Q and NPSS measure")
    ap.add_argument("--y-weight", type=float, default=1.0,
                    help="multiplies the vertical component of the reconstruction loss (not in the thesis; "
                         "session 8): L2P normalizes by per-coordinate spread, which is 7-8x smaller in y")
    ap.add_argument("--path-weight", type=float, default=0.0,
                    help="weight of a loss on the whole root path the pipeline outputs (the path predictor on the "
                         "generated motion, integrated, keys made exact as in post-processing) against the ground "
                         "truth's, per axis as --y-weight; not in the thesis (eq. 5.10 covers keys only); session 8")
    ap.add_argument("--d-warmup", type=int, default=300,
                    help="discriminator-only steps when --resume has no discriminator (a recovered checkpoint)")
    ap.add_argument("--resume", default=None, help="continue from a gen.pt checkpoint (generator and discriminator)")
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    if args.dna_weight is not None:
        W["dna1"] = W["dna2"] = args.dna_weight
    W["acc"] = args.acc_weight
    W["spec"] = args.spec_weight
    W["rot"] = args.rot_weight
    W["path"] = args.path_weight
    axis_w = torch.tensor([1.0, args.y_weight, 1.0])
    if args.gan_weight is not None:
        W["gan"] = args.gan_weight
    rng = np.random.default_rng(args.seed)
    out = args.out
    os.makedirs(out, exist_ok=True)
    logf = open(os.path.join(out, "log.jsonl"), "a")

    def log(d):
        print(json.dumps(d), flush=True)
        logf.write(json.dumps(d) + "\n")
        logf.flush()

    data, val = Data(args.data, "train"), Data(args.data, "val")
    J = len(data.joints)
    P = J * 3
    fk = RCFK(data.joints, data.parents, data.offsets, data.channel_joints)
    path_extra = {}
    if args.path_ckpt:
        ck = torch.load(args.path_ckpt)
        path_config = ck.get("config", {})
        path = PathPredictor(P, **path_config)
        path.load_state_dict(ck["model"])
        path.eval()
        psteps = ck["steps"]
        # how it was trained travels with it into this run's path.pt (and the manifest)
        path_extra = {k: v for k, v in ck.items() if k in ("augment", "minutes", "table_5_2_train")}
        path_extra["source"] = os.path.relpath(args.path_ckpt, TRAIN)
    else:
        path_config = {"width": args.path_width, "layers": args.path_layers,
                       "dilations": [int(x) for x in args.path_dilations.split(",")]}
        path, psteps = train_path(data, args.path_minutes, log, rng, path_config, args.path_decay,
                                  args.path_augment)
    table = path_table(path, val, np.random.default_rng(1))
    log({"stage": "path_eval_val", "steps": psteps, **table})
    if args.path_only:
        # windows of the training takes, for choosing settings without the validation takes
        train_table = path_table(path, data, np.random.default_rng(1))
        log({"stage": "path_eval_train", "steps": psteps, **train_table})
        torch.save({"model": path.state_dict(), "steps": psteps, "table_5_2_val": table,
                    "table_5_2_train": train_table, "config": path_config,
                    "augment": bool(args.path_augment), "minutes": args.path_minutes}, os.path.join(out, "path.pt"))
        return
    for p in path.parameters():
        p.requires_grad_(False)
    torch.save({"model": path.state_dict(), "steps": psteps, "table_5_2_val": table, "config": path_config,
                **path_extra}, os.path.join(out, "path.pt"))

    G = Generator(P, fk.output_dim, gate_tau=args.gate_tau, skips=args.skips)
    D = Discriminator(P)
    step0 = 0
    if args.resume:
        ck = torch.load(args.resume)
        missing, unexpected = G.load_state_dict(ck["G"], strict=False)
        if unexpected or any(k != "log_tau" and not k.startswith("skip.") for k in missing):
            sys.exit(f"--resume {args.resume}: missing {missing}, unexpected {unexpected}")
        if "D" in ck:
            D.load_state_dict(ck["D"])
        step0 = ck["steps"]
    fresh_d = bool(args.resume) and "D" not in ck
    ema = copy.deepcopy(G).requires_grad_(False) if args.ema else None
    if ema is not None and args.resume and "G_ema" in ck:
        ema.load_state_dict(ck["G_ema"])  # the average carries on where the run left it

    def save():
        ck = {"G": G.state_dict(), "D": D.state_dict(), "steps": step, "args": vars(args), "weights": W}
        if ema is not None:
            ck["G_ema"] = ema.state_dict()
        torch.save(ck, os.path.join(out, "gen.pt"))
        if args.keep_snapshots:
            shutil.copy(os.path.join(out, "gen.pt"), os.path.join(out, f"gen_{step}.pt"))

    og = torch.optim.Adam(G.parameters(), lr=args.lr_g, betas=(0.5, 0.99))
    od = torch.optim.Adam(D.parameters(), lr=args.lr_d, betas=(0.5, 0.99))
    n, b = args.frames, args.batch

    def with_keys(gen_s, gt_s, mask):
        """Fake sequences [B, P, N] with the key poses put back (Sec. 5.2.5)."""
        full = mask.reshape(b, n, J, 3).all(-1).all(-1)          # [B, N] frames with full keys
        return torch.where(full[..., None, None], gt_s, gen_s).reshape(b, n, P).transpose(1, 2)

    def d_step(fake):
        """One discriminator update: LSGAN, real -> 1, fake -> -1 (eq. 5.7)."""
        with torch.no_grad():
            real = torch.stack([data.local[data.window(n, rng)] for _ in range(b)]) / SCALE
        ld = ((D(real.reshape(b, n, P).transpose(1, 2)) - 1) ** 2).mean() + ((D(fake.detach()) + 1) ** 2).mean()
        od.zero_grad()
        ld.backward()
        od.step()
        return ld

    if fresh_d:
        # a checkpoint recovered from ONNX (train/deeprep_train/motion/recover_checkpoint.py) has no
        # discriminator: train a fresh one against the frozen generator first
        for i in range(args.d_warmup):
            with torch.no_grad():
                dense, dense_rot, mask, dna, local, root, rc, keysets = make_batch(data, b, n, rng, fk, args.gaps,
                                                                                   args.base)
                gen_s = fk(G(dense, dense_rot, dna).transpose(1, 2), torch.zeros(b, n, 3)) / SCALE
            ld = d_step(with_keys(gen_s, local / SCALE, mask))
            if (i + 1) % 50 == 0:
                log({"stage": "d_warmup", "step": i + 1, "D": ld.item()})
    t0, step = time.time(), step0
    while time.time() - t0 < args.gen_minutes * 60:
        dense, dense_rot, mask, dna, local, root, rc, keysets = make_batch(data, b, n, rng, fk, args.gaps, args.base)
        raw = G(dense, dense_rot, dna).transpose(1, 2)           # [B, N, out]
        gen, r_gen = fk.pose(raw, torch.zeros(b, n, 3))          # [B, N, J, 3] local (root at 0), rotations
        gen_s, gt_s = gen / SCALE, local / SCALE
        losses = {}
        losses["recon"] = (((gen_s - gt_s) ** 2) * axis_w).sum(-1).mean()
        if W["rot"] > 0:
            k = len(fk.rotating)
            u_gt = torch.minimum(torch.maximum(rc[..., 9:].reshape(b, n, k, 3), fk.lo), fk.hi)
            r_gt = fk.global_rotations(fk.rotations_from_angles(rc[..., 3:9], u_gt))
            losses["rot"] = ((r_gen - r_gt) ** 2).sum((-1, -2)).mean()
        else:
            losses["rot"] = torch.zeros(())
        # velocity term (not in the thesis): frame-to-frame motion like the ground truth's
        losses["vel"] = (((gen_s[:, 1:] - gen_s[:, :-1]) - (gt_s[:, 1:] - gt_s[:, :-1])) ** 2).sum(-1).mean() * 25.0
        # acceleration term (not in the thesis): run 7's output had 2.4x the ground truth's
        # frame-to-frame acceleration (jitter), which the discriminator and NPSS both punish
        acc_g = gen_s[:, 2:] - 2 * gen_s[:, 1:-1] + gen_s[:, :-2]
        acc_t = gt_s[:, 2:] - 2 * gt_s[:, 1:-1] + gt_s[:, :-2]
        losses["acc"] = ((acc_g - acc_t) ** 2).sum(-1).mean() * 400.0
        losses["spec"] = spectral_loss(gen_s.reshape(b, n, P), gt_s.reshape(b, n, P), keysets) \
            if W["spec"] > 0 else torch.zeros(())
        kmask = mask.reshape(b, n, J, 3).clone()
        kmask[:, :, 0, :] = False
        losses["key"] = (((gen_s - gt_s) ** 2) * kmask).sum() / kmask.sum().clamp(min=1)
        vel = path(gen_s.reshape(b, n, P).transpose(1, 2)).transpose(1, 2) * SCALE   # [B, N, 3]
        T = torch.cumsum(vel, 1) - vel[:, :1]
        rl = []
        for i, keys in enumerate(keysets):
            ks = [t for t in keys if mask[i, t, 0]]
            if len(ks) < 2:
                continue
            a = T[i, ks] - T[i, ks[0]]
            c = root[i, ks] - root[i, ks[0]]
            rl.append((((a - a.mean(0)) - (c - c.mean(0))) / SCALE).pow(2).sum(-1).mean())
        losses["root"] = torch.stack(rl).mean() if rl else torch.zeros(())
        if W["path"] > 0:
            full_path = path_after_post(T, root, mask, keysets)
            losses["path"] = ((((full_path - root) / SCALE) ** 2) * axis_w).sum(-1).mean()
        else:
            losses["path"] = torch.zeros(())
        fake = with_keys(gen_s, gt_s, mask)
        losses["gan"] = ((D(fake) - GAN_TARGET) ** 2).mean()
        br = [m.last for m in G.resconvs()]
        losses["br"] = sum(((x.mean((0, 2)) ** 2).sum() + (torch.log(x.std((0, 2)) + 1e-6) ** 2).sum()) for x in br) / sum(x.shape[1] for x in br)
        lg = lam(gen_s, raw[..., :6]).reshape(b, n, P)           # [B, N, P]
        d2 = torch.cdist(lg, dna) ** 2                            # [B, N, K]
        losses["dna1"] = d2.min(1).values.mean()
        e = d2.min(2).values                                     # [B, N]
        dl = []
        for i, keys in enumerate(keysets):
            for a, z in zip(keys[:-1], keys[1:]):
                nk = (z - a) // 180
                if nk >= 1:
                    dl.append(torch.topk(e[i, a:z], nk, largest=False).values.mean())
        losses["dna2"] = torch.stack(dl).mean() if dl else torch.zeros(())
        total = sum(W[k] * v for k, v in losses.items())
        og.zero_grad()
        total.backward()
        torch.nn.utils.clip_grad_norm_(G.parameters(), 10.0)
        og.step()
        if ema is not None:
            with torch.no_grad():
                for pe, p in zip(ema.parameters(), G.parameters()):
                    pe.mul_(args.ema).add_(p, alpha=1 - args.ema)
        ld = d_step(fake)
        step += 1
        if step % 50 == 0:
            log({"stage": "gen", "step": step, "sec": round(time.time() - t0), "total": total.item(), "D": ld.item(),
                 **{k: round(v.item(), 6) for k, v in losses.items()}})
        if step % 500 == 0:
            save()
    save()
    log({"stage": "done", "gen_steps": step, "path_steps": psteps})


if __name__ == "__main__":
    main()
