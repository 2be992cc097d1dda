"""Appendix D.2's dataset filter: a local-motion auto-encoder through RC-FK
marks noisy frames of the training takes (issue 19, data).

The thesis removes three kinds of noise from CMU: motion under the floor
(motion/data.py's floor rule already does this), poses outside the body's
range and capture jitter. For the last two it trains "a local motion
auto-encoder with similar architecture to the local motion generator, but
with less layers", whose output passes through RC-FK (so every output pose
is within Table D.1's ranges) and which smooths high frequencies; frames
whose reconstruction error is above a threshold are deleted and their clip
split there.

Here: the auto-encoder reads the local pose without the root's rotation
(Λ, motion/train.py's `lam`) of 256-frame windows, three stride-2
convolutions down and three up (the generator has six levels), and outputs
RC-FK values whose FK is compared with its input (L2 on positions). It is
trained on the training takes only; validation takes are never filtered,
so the README's table stays comparable. The thesis gives no threshold:
frames whose mean joint error is above the median plus `--mads` median
absolute deviations are removed (an outlier rule, reported with the
distribution), then pieces shorter than data.py's MIN_SEGMENT.

  train/.venv/bin/python -m deeprep_train.motion.filter_d2 [--minutes 10] [--mads 8]

Writes train/cache/d2_filter.npz: `keep` (one flag per training frame of
motion60.npz and resid60.npz, which hold the same frames in the same
order), per-frame `error` (units), the threshold and the counts; `residual
train --d2-filter` trains on the kept frames.
"""
import argparse
import json
import os
import time

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

from deeprep_train.paths import CACHE
from deeprep_train.rcfk import RCFK
from deeprep_train.motion.data import MIN_SEGMENT, runs
from deeprep_train.motion.train import Data, lam

OUT = os.path.join(CACHE, "d2_filter.npz")
WINDOW = 256


class LocalAE(nn.Module):
    """Λ [B, P, N] -> RC-FK values [B, 6 + 3K, N]; N a multiple of 8."""

    def __init__(self, pose_dim, out_dim, width=256, code=64):
        super().__init__()
        self.enc = nn.Sequential(
            nn.Conv1d(pose_dim, width, 5, stride=2, padding=2), nn.LeakyReLU(0.2),
            nn.Conv1d(width, width, 5, stride=2, padding=2), nn.LeakyReLU(0.2),
            nn.Conv1d(width, code, 5, stride=2, padding=2))
        self.dec = nn.Sequential(
            nn.ConvTranspose1d(code, width, 4, stride=2, padding=1), nn.LeakyReLU(0.2),
            nn.ConvTranspose1d(width, width, 4, stride=2, padding=1), nn.LeakyReLU(0.2),
            nn.ConvTranspose1d(width, width, 4, stride=2, padding=1), nn.LeakyReLU(0.2),
            nn.Conv1d(width, out_dim, 3, padding=1))

    def forward(self, x):
        return self.dec(self.enc(x))


def local_pose(data, sl):
    """Λ of frames `sl`, [N, J, 3] in units / 100."""
    return lam(data.local[sl], data.rc[sl, 3:9]) / 100.0


def reconstruct(ae, fk, x):
    """x [B, N, J, 3] (units / 100) -> the auto-encoder's FK positions, same shape and scale."""
    B, N, J = x.shape[:3]
    raw = ae(x.reshape(B, N, J * 3).transpose(1, 2)).transpose(1, 2)
    return fk(raw, torch.zeros(B, N, 3)) / 100.0


def train(data, fk, minutes, rng, log):
    J = len(data.joints)
    ae = LocalAE(J * 3, fk.output_dim)
    opt = torch.optim.Adam(ae.parameters(), lr=1e-3)
    t0, step = time.time(), 0
    while time.time() - t0 < minutes * 60:
        x = torch.stack([local_pose(data, data.window(WINDOW, rng)) for _ in range(8)])
        loss = F.mse_loss(reconstruct(ae, fk, x), x)
        opt.zero_grad()
        loss.backward()
        opt.step()
        step += 1
        if step % 200 == 0:
            log({"step": step, "t": round(time.time() - t0), "mse": loss.item()})
    return ae, step


@torch.no_grad()
def frame_errors(ae, fk, data):
    """Mean joint distance (units) between each training frame's Λ and the
    auto-encoder's reconstruction of its segment (padded to a multiple of 8
    by repeating the last frame)."""
    err = np.zeros(len(data.local), np.float32)
    for a, n in zip(data.starts, data.lens):
        a, n = int(a), int(n)
        x = local_pose(data, slice(a, a + n))
        pad = (-n) % 8
        xp = torch.cat([x, x[-1:].expand(pad, -1, -1)]) if pad else x
        rec = reconstruct(ae, fk, xp.unsqueeze(0))[0, :n]
        err[a:a + n] = ((rec - x).norm(dim=-1).mean(-1) * 100.0).numpy()
    return err


def keep_mask(err, starts, lens, mads):
    """Frames under median + mads * MAD, then pieces of at least MIN_SEGMENT
    frames between removed frames; returns (keep, threshold, counts)."""
    med = float(np.median(err))
    mad = float(np.median(np.abs(err - med)))
    thr = med + mads * mad
    keep = err <= thr
    noisy = int((~keep).sum())
    pieces_before = len(lens)
    pieces = 0
    for a, n in zip(starts, lens):
        a, n = int(a), int(n)
        for i, j in runs(keep[a:a + n]):
            if j - i < MIN_SEGMENT:
                keep[a + i:a + j] = False
            else:
                pieces += 1
    counts = {"frames": int(len(err)), "noisy_frames": noisy, "short_piece_frames": int((~keep).sum()) - noisy,
              "removed_frames": int((~keep).sum()), "segments_before": pieces_before, "segments_after": pieces}
    return keep, thr, counts


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", default=os.path.join(CACHE, "motion60.npz"))
    ap.add_argument("--minutes", type=float, default=10)
    ap.add_argument("--mads", type=float, default=8.0, help="threshold: median error + this many MADs")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default=OUT)
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    data = Data(args.data, "train")
    fk = RCFK(data.joints, data.parents, data.offsets, data.channel_joints)
    ae, steps = train(data, fk, args.minutes, np.random.default_rng(args.seed),
                      lambda d: print(json.dumps(d), flush=True))
    err = frame_errors(ae, fk, data)
    keep, thr, counts = keep_mask(err, data.starts, data.lens, args.mads)
    pct = {f"p{q}": float(np.percentile(err, q)) for q in (50, 90, 99, 99.9)}
    summary = {"steps": steps, "threshold": thr, "mads": args.mads, "error_percentiles": pct, **counts}
    np.savez_compressed(args.out, keep=keep, error=err, summary=json.dumps(summary))
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
