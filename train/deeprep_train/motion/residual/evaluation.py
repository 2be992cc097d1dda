"""Evaluation of the residual network on windows with keys at 0, g, 2g, the pick rule, and the L2P spread.

Part of deeprep_train.motion.residual (see its package docstring)."""
import json
import os

import numpy as np
import torch

from deeprep_train.paths import CACHE
from deeprep_train.motion.ablation import ratio_to_slerp
from deeprep_train.motion.eval import l2p_stats, npss
from deeprep_train.motion.residual.data import Clips, Skeleton, features
from deeprep_train.motion.residual.net import apply, fk, load_ema


# ---------------------------------------------------------------- evaluation

def evaluate(args):
    """Keys at frames s, s+g, s+2g in every segment (windows of 2g+1 frames,
    stepping by 2g), as issue 19's table: MPJPE (global positions, mean over
    in-between frames and joints), NPSS on root-relative positions, and
    joint speed relative to the root as a share of the truth's."""
    torch.set_num_threads(args.threads)
    d = np.load(args.data)
    skel = Skeleton(d)
    clips = Clips(d, args.split)
    # L2P as motion/eval.py computes it: position errors over each joint
    # coordinate's spread in training windows (the mean cancels); heights
    # weigh about 7x the horizontal coordinates. The canonical frame turns
    # x/z about the vertical, which the nearly equal x and z spreads ignore.
    inv_sd = torch.from_numpy(1.0 / l2p_sd()).float()
    net = load_ema(args.ckpt) if args.ckpt else None
    res = {}
    for g in args.gaps:
        n = 2 * g + 1
        acc = {m: {"mpjpe": [], "l2p": [], "speed": [], "pred": [], "gt": []} for m in ("slerp", "model")}
        gt_speed = []
        for si in range(len(clips.lens)):
            a0 = int(clips.starts[si])
            for s0 in range(0, int(clips.lens[si]) - n + 1, 2 * g):
                root = clips.root[a0 + s0:a0 + s0 + n]
                quat = clips.quat[a0 + s0:a0 + s0 + n]
                keys = [0, g, 2 * g]
                f = features(root, quat, keys)
                base_root, base_rot, gt_root, gt_rot, phase, gate = [x.unsqueeze(0) for x in f]
                offs = skel.offsets.unsqueeze(0)
                gpos = fk(skel, gt_root, gt_rot, offs)[0]
                mid = [t for t in range(n) if t not in keys]
                grel = (gpos - gpos[:, :1])[mid]
                gsp = (gpos - gpos[:, :1]).diff(dim=0).norm(dim=-1)[[t - 1 for t in mid if t > 0]].mean()
                gt_speed.append(float(gsp))
                outs = {"slerp": (base_root, base_rot)}
                if net is not None:
                    with torch.no_grad():
                        outs["model"] = apply(net, base_root, base_rot, phase, gate)
                for m, (r, q) in outs.items():
                    pos = fk(skel, r, q, offs)[0]
                    acc[m]["mpjpe"].append(float((pos - gpos)[mid].norm(dim=-1).mean()))
                    acc[m]["l2p"].append(float(((pos - gpos)[mid].reshape(len(mid), -1) * inv_sd).norm(dim=-1).mean()))
                    rel = (pos - pos[:, :1])
                    acc[m]["speed"].append(float(rel.diff(dim=0).norm(dim=-1)[[t - 1 for t in mid if t > 0]].mean()))
                    acc[m]["pred"].append(rel[mid].reshape(len(mid), -1).numpy())
                    acc[m]["gt"].append(grel.reshape(len(mid), -1).numpy())
        row = {"windows": len(gt_speed)}
        for m, a in acc.items():
            if not a["mpjpe"]:
                continue
            row[m] = {"mpjpe": float(np.mean(a["mpjpe"])), "l2p": float(np.mean(a["l2p"])),
                      "npss": npss(np.stack(a["gt"]), np.stack(a["pred"])),
                      "speed_ratio": float(np.mean(a["speed"]) / np.mean(gt_speed))}
        res[g] = row
        print(g, json.dumps(row), flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"split": args.split, "ckpt": args.ckpt, "gaps": res}, fh, indent=1)
    return res



def pick(args):
    """Chooses among snapshots by their `eval --split train --json` results
    (never validation), by issue 19's targets: among those that beat
    SLERP+LERP on MPJPE, L2P and NPSS at every gap, by at least 10% on NPSS
    at gaps 120 and 300, with joint speed within 30% (less --speed-margin)
    of the truth's at 120 and 300 and an L2P ratio at most 1 - --l2p-margin
    at every gap, the one with the lowest mean L2P ratio; if none meets all of
    that, among those that beat SLERP+LERP everywhere the one whose joint
    speed at 120 and 300 is closest to the truth's; else the lowest mean
    MPJPE ratio. Prints the scores and writes them to --json."""
    rows = []
    for path in args.results:
        r = json.load(open(path))
        g = r["gaps"]
        mpjpe, l2p, npss_r = (ratio_to_slerp(g, k) for k in ("mpjpe", "l2p", "npss"))
        wins = all(v < 1 for v in mpjpe + npss_r + l2p)
        speed = [abs(1 - g[x]["model"]["speed_ratio"]) for x in ("120", "300") if x in g]
        npss_long = ratio_to_slerp({x: g[x] for x in ("120", "300") if x in g}, "npss")
        targets = wins and bool(l2p) and all(v <= 0.9 for v in npss_long) \
            and all(v <= 0.3 - args.speed_margin for v in speed) \
            and all(v <= 1 - args.l2p_margin for v in l2p)
        rows.append({"ckpt": r["ckpt"], "beats_slerp_everywhere": wins, "meets_issue_targets": targets,
                     "mpjpe_ratio": mpjpe, "l2p_ratio": l2p,
                     "npss_ratio": npss_r, "speed_ratio": [g[x]["model"]["speed_ratio"] for x in sorted(g, key=int)],
                     "speed_gap_120_300": float(np.mean(speed)), "mean_mpjpe_ratio": float(np.mean(mpjpe)),
                     "mean_l2p_ratio": float(np.mean(l2p)) if l2p else None})
    met = [r for r in rows if r["meets_issue_targets"]]
    ok = [r for r in rows if r["beats_slerp_everywhere"]]
    if met:
        best = min(met, key=lambda r: r["mean_l2p_ratio"])
    elif ok:
        best = min(ok, key=lambda r: r["speed_gap_120_300"])
    else:
        best = min(rows, key=lambda r: r["mean_mpjpe_ratio"])
    for r in rows:
        print(("* " if r is best else "  ") + json.dumps(r))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"rule": pick.__doc__.split("Prints")[0].strip(), "speed_margin": args.speed_margin,
                       "l2p_margin": args.l2p_margin,
                       "candidates": rows, "picked": best["ckpt"]}, fh, indent=1)
    return best



L2P_SD = os.path.join(CACHE, "l2p_sd.npy")


def l2p_sd():
    """The per-coordinate spread L2P divides by (motion.eval.l2p_stats), from
    train/cache/l2p_sd.npy when present (written on first use), so a machine
    with only resid60.npz (the GPU job) can train with the L2P loss."""
    if os.path.exists(L2P_SD):
        return np.load(L2P_SD)
    sd = l2p_stats()[1]
    os.makedirs(CACHE, exist_ok=True)
    np.save(L2P_SD, sd)
    return sd
