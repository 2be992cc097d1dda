"""The residual network's data: the 60 fps cache, skeleton, clips, rotations, keys and the SLERP+LERP base in the first key's frame.

Part of deeprep_train.motion.residual (see its package docstring)."""
import math
import os
import sys

import numpy as np
import torch

from deeprep_train.paths import ROOT, CACHE
from deeprep_train.motion.data import DATA, TRUE_FPS, VALIDATION, floor_segments, runs, take_of, MIN_SEGMENT
from deeprep_train.bvh import fk_from_local, local_fk, mat_to_quat, mirror_joints, read_bvh
from deeprep_train.motion.residual_adv import MAX_GAP
from deeprep_train.rotation import matrix_to_6d, quat_to_matrix, sixd_to_matrix


OUT = os.path.join(CACHE, "resid")
PORTABLE = os.path.join(ROOT, "train", "checkpoints", "tween_resid_w128b.pt")
SCALE = 100.0
GATE_FRAMES = 5.0
# frames per unit of the phase channels "frames since the previous key" and
# "to the next" (one second at 60 fps); crate/src/motion/residual.rs the same
PHASE_FRAMES = 60


# ---------------------------------------------------------------- data

def add_clip(store, split, name, bvh):
    """Drops a 60 fps clip's under-floor frames (motion.data's rule) and adds
    its segments' root positions and local joint quaternions to store[split]."""
    names, _, _, chans, _ = bvh
    trans, loc = local_fk(bvh)
    pos, _ = fk_from_local(bvh, trans, loc)
    keep, floor = floor_segments(pos)
    rj = [j for j in range(len(names)) if chans[j]]
    q = mat_to_quat(loc[:, rj]).astype(np.float32)
    root = trans[:, 0].copy()
    root[:, 1] -= floor
    for a, b in runs(keep):
        if b - a < MIN_SEGMENT:
            continue
        store[split]["root"].append(root[a:b].astype(np.float32))
        store[split]["quat"].append(q[a:b])
        store[split]["len"].append(b - a)
        store[split]["name"].append(f"{name}@{a}")


def prepare(path):
    """Reads every clip, resamples to 60 fps, drops under-floor frames
    (motion.data's rule) and caches root positions and local joint
    quaternions [w, x, y, z] of the joints with channels."""
    store = {s: {"root": [], "quat": [], "len": [], "name": []} for s in ("train", "val")}
    skel = None
    for cls in sorted(TRUE_FPS):
        for name in sorted(os.listdir(os.path.join(DATA, cls))):
            if not name.endswith(".bvh"):
                continue
            names, parents, offsets, chans, data = read_bvh(os.path.join(DATA, cls, name))
            if skel is None:
                skel = (names, parents, offsets, chans)
            split = "val" if take_of(cls, int(name[:-4])) in VALIDATION else "train"
            add_clip(store, split, f"{cls}/{name}", (names, parents, offsets, chans, data[::TRUE_FPS[cls] // 60]))
    # cmu-extra's locomotion retargeted onto the model's skeleton (motion.extra)
    from deeprep_train.motion.extra import OUT as EXTRA60, EXTRA_VALIDATION
    if not os.path.isdir(EXTRA60):
        print(f"prepare: WARNING {EXTRA60} is absent, so cmu-extra's walks and runs are not in this cache "
              "(`cond train --extra-share` then stops): run `python -m deeprep_train.motion.extra` "
              "(needs the CLI built) and prepare again", file=sys.stderr)
    for dirpath, _, files in sorted(os.walk(EXTRA60)):
        for name in sorted(files):
            if not name.endswith(".bvh"):
                continue
            bvh = read_bvh(os.path.join(dirpath, name))
            if bvh[0] != skel[0]:
                sys.exit(f"{dirpath}/{name} is not on the model's skeleton")
            split = "val" if name[:-4] in EXTRA_VALIDATION else "train"
            add_clip(store, split, "extra/" + os.path.relpath(os.path.join(dirpath, name), EXTRA60), bvh)
    names, parents, offsets, chans = skel
    arrays = {"names": np.array(names), "parents": np.array(parents), "offsets": np.array(offsets, np.float32),
              "rotating": np.array([j for j in range(len(names)) if chans[j]])}
    for s, d in store.items():
        arrays[f"{s}_root"] = np.concatenate(d["root"])
        arrays[f"{s}_quat"] = np.concatenate(d["quat"])
        arrays[f"{s}_len"] = np.array(d["len"])
        arrays[f"{s}_name"] = np.array(d["name"])
        print(f"{s}: {len(d['len'])} segments, {sum(d['len'])} frames")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    np.savez_compressed(path, **arrays)


class Skeleton:
    def __init__(self, d):
        self.names = [str(n) for n in d["names"]]
        self.parents = [int(p) for p in d["parents"]]
        self.offsets = torch.from_numpy(d["offsets"]).float()
        self.rotating = [int(j) for j in d["rotating"]]
        self.K = len(self.rotating)
        slot = {j: i for i, j in enumerate(self.rotating)}
        self.slot = [slot.get(j, -1) for j in range(len(self.names))]
        self.feet = [i for i, n in enumerate(self.names) if "Foot" in n or "Toe" in n]
        # left/right mirror: joint order map and the mirrored offsets
        self.mirror_joint = mirror_joints(self.names)
        self.mirror_slot = [slot[self.mirror_joint[j]] for j in self.rotating]
        m = torch.tensor([-1.0, 1.0, 1.0])
        self.mirror_offsets = self.offsets[self.mirror_joint] * m


class Clips:
    def __init__(self, d, split, keep=None):
        """The split's segments; `keep` (one flag per frame, motion/filter_d2.py)
        drops frames and splits segments where they were."""
        self.root = torch.from_numpy(d[f"{split}_root"])
        self.quat = torch.from_numpy(d[f"{split}_quat"])
        self.lens = d[f"{split}_len"]
        self.names = list(d[f"{split}_name"])
        if keep is not None:
            if len(keep) != len(self.root):
                raise SystemExit(f"filter: {len(keep)} flags for {len(self.root)} {split} frames")
            lens, names = [], []
            for a, n, name in zip(np.concatenate([[0], np.cumsum(self.lens)[:-1]]), self.lens, self.names):
                for i, j in runs(keep[a:a + n]):
                    lens.append(j - i)
                    names.append(f"{name}+{i}")
            self.root, self.quat = self.root[torch.from_numpy(keep)], self.quat[torch.from_numpy(keep)]
            self.lens, self.names = np.array(lens), names
        self.starts = np.concatenate([[0], np.cumsum(self.lens)[:-1]])

    def window(self, n, rng, among=None):
        """An n-frame window, segments weighted by length; `among` (a flag
        per segment) limits the draw to the flagged ones where one is long
        enough."""
        ok = np.nonzero(self.lens >= n)[0]
        if among is not None and among[ok].any():
            ok = ok[among[ok]]
        s = rng.choice(ok, p=self.lens[ok] / self.lens[ok].sum())
        a = int(self.starts[s] + rng.integers(0, self.lens[s] - n + 1))
        return self.root[a:a + n], self.quat[a:a + n]


# ---------------------------------------------------------------- rotations

def quat_to_mat(q):
    """[..., 4] unit quaternions [w, x, y, z] (this cache's order) -> [..., 3, 3]."""
    return quat_to_matrix(q[..., [1, 2, 3, 0]])


def slerp(qa, qb, s):
    """Per-element slerp on the short arc. qa, qb [..., 4], s [...]."""
    d = (qa * qb).sum(-1, keepdim=True)
    qb = torch.where(d < 0, -qb, qb)
    d = d.abs().clamp(max=1.0)
    th = torch.acos(d)
    sn = torch.sin(th)
    s = s.unsqueeze(-1)
    lin = sn < 1e-4
    wa = torch.where(lin, 1 - s, torch.sin((1 - s) * th) / sn.clamp(min=1e-8))
    wb = torch.where(lin, s, torch.sin(s * th) / sn.clamp(min=1e-8))
    q = wa * qa + wb * qb
    return q / q.norm(dim=-1, keepdim=True)


sixd = matrix_to_6d          # [..., 3, 3] -> [..., 6], the first two columns
from_sixd = sixd_to_matrix   # Gram-Schmidt back (eq. C.2-C.3)


def rot_y(theta):
    c, s = torch.cos(theta), torch.sin(theta)
    o, z = torch.ones_like(theta), torch.zeros_like(theta)
    return torch.stack([torch.stack([c, z, s], -1), torch.stack([z, o, z], -1), torch.stack([-s, z, c], -1)], -2)


# ---------------------------------------------------------------- keys and base

def key_phase(keys, n):
    """Per frame: the previous key index a, next key b, and s = (t-a)/(b-a)."""
    t = torch.arange(n)
    k = torch.tensor(keys)
    seg = torch.searchsorted(k, t, right=True) - 1
    seg = seg.clamp(0, len(keys) - 2)
    a, b = k[seg], k[seg + 1]
    s = ((t - a).float() / (b - a).float()).clamp(0, 1)
    return a, b, s


def canonical(root, quat, key0):
    """Removes the first key's root x/z and heading: returns root' [N,3],
    root rotation matrices' [N,3,3] and the transform (C, offset)."""
    R0 = quat_to_mat(quat[key0, 0])
    f = R0[:, 2]
    theta = torch.atan2(f[0], f[2])
    C = rot_y(-theta)
    off = torch.stack([root[key0, 0], torch.zeros(()), root[key0, 2]])
    return C, off


def features(root, quat, keys):
    """SLERP+LERP of the keys in the first key's frame, the ground truth in the
    same frame, and per-frame phase features.
    root [N,3], quat [N,K,4] (ground truth; only key frames are read for the base).
    Returns base_root [N,3], base_rot [N,K,3,3], gt_root, gt_rot, phase [N,4], gate [N]."""
    n = root.shape[0]
    a, b, s = key_phase(keys, n)
    C, off = canonical(root, quat, keys[0])
    base_q = slerp(quat[a], quat[b], s.unsqueeze(-1).expand(-1, quat.shape[1]))
    base_root = root[a] + s.unsqueeze(-1) * (root[b] - root[a])
    base_rot = quat_to_mat(base_q)
    gt_rot = quat_to_mat(quat)
    base_rot = torch.cat([(C @ base_rot[:, 0]).unsqueeze(1), base_rot[:, 1:]], 1)
    gt_rot = torch.cat([(C @ gt_rot[:, 0]).unsqueeze(1), gt_rot[:, 1:]], 1)
    base_root = (base_root - off) @ C.T
    gt_root = (root - off) @ C.T
    dp, dn = (torch.arange(n) - a).float(), (b - torch.arange(n)).float()
    d = torch.minimum(dp, dn)
    gate = 1 - torch.exp(-d / GATE_FRAMES)
    phase = torch.stack([s, dp / PHASE_FRAMES, dn / PHASE_FRAMES, gate], -1)
    return base_root, base_rot, gt_root, gt_rot, phase, gate


def mirror(root, quat, skel):
    """Left/right mirror (x -> -x): joints swapped, quaternions (w, x, -y, -z)."""
    q = quat[:, skel.mirror_slot] * torch.tensor([1.0, 1.0, -1.0, -1.0])
    r = root * torch.tensor([-1.0, 1.0, 1.0])
    return r, q


def sample_keys(n, rng, lo=15, hi=MAX_GAP, regular=0.0):
    """Key frames of an n-frame window: 0, n - 1 and between them intervals
    drawn log-uniformly from [lo, hi] frames (the last one absorbs a rest
    shorter than lo); with probability `regular` one interval is drawn and
    repeated (keys at a regular spacing, as animators often set them)."""
    def gap():
        return int(math.exp(rng.uniform(math.log(lo), math.log(hi))))

    if regular > 0 and rng.random() < regular:
        keys = list(range(0, n - 1, gap()))
        if n - 1 - keys[-1] < lo and len(keys) > 1:
            keys.pop()
        return keys + [n - 1]
    keys, t = [0], 0
    while t < n - 1:
        t = min(t + gap(), n - 1)
        if n - 1 - t < lo:
            t = n - 1
        keys.append(t)
    return keys


def fill_keys(n, rng, gaps=(10, 180), law="log"):
    """Every known frame of a window with gaps to fill (issue 50: captured
    motion repaired from the frames around each gap): runs of consecutive
    known frames (20, or 1-40 frames: one known frame after a gap up to the
    next gap's context) between gaps of `gaps` = (lo, hi) frames; the
    window starts with 20 known frames and ends with a known frame. `law`
    "log": gap lengths log-uniform (so the frames in gaps spread evenly over
    the lengths); "inverse": density 1/L^2 (the frames in gaps log-uniform
    over the lengths: as many in gaps of 8-16 frames as of 16-32)."""
    keys, t = list(range(min(20, n))), min(20, n)
    while t < n:
        if law == "inverse":
            t += int(1.0 / rng.uniform(1.0 / gaps[1], 1.0 / gaps[0]))
        else:
            t += int(math.exp(rng.uniform(math.log(gaps[0]), math.log(gaps[1]))))
        if t >= n - 1:
            keys.append(n - 1)
            break
        run = 20 if rng.random() < 0.5 else int(rng.integers(1, 41))
        keys.extend(range(t, min(t + run, n)))
        t += run
    if keys[-1] != n - 1:
        keys.append(n - 1)
    return keys


def add_fill_args(ap, network):
    """The gap-filling arguments both trainers take (issue 50): train's
    --fill-share / --fill-gaps / --fill-law (data.fill_keys' layouts) and
    export's --fill-from / --fill-up-to (the band the `model` fill gives the
    exported network, motion::fill::method_for). `network`: the file a
    gap-filling export is named (--name)."""
    ap.add_argument("--fill-share", type=float, default=0.0,
                    help="train: share of windows laid out as gaps in captured motion: runs of known frames around "
                         "gaps of --fill-gaps frames, every known frame a whole-pose key (fill_keys)")
    ap.add_argument("--fill-gaps", type=lambda v: tuple(int(x) for x in v.split(",")), default=(10, 180),
                    help="LO,HI: the gap lengths of --fill-share's windows (their law: --fill-law)")
    ap.add_argument("--fill-law", choices=["log", "inverse"], default="log",
                    help="the gap lengths' law in fill layouts: log-uniform, or density 1/L^2 (more short gaps)")
    ap.add_argument("--fill-from", type=int, default=0,
                    help="export: the shortest gap the `model` fill gives this network (its manifest's fill_from; "
                         "default 1)")
    ap.add_argument("--fill-up-to", type=int, default=0,
                    help=f"export: the longest gap the `model` fill gives this network (fill_up_to; a gap-filling "
                         f"network, --name {network})")


def fill_band(args):
    """The manifest's band from export's --fill-from / --fill-up-to (added by
    add_fill_args): {"fill_up_to": B[, "fill_from": A]}, or {} for a network
    that is not a gap-filling one; stops on a band motion::fill::band refuses."""
    if args.fill_from and not 1 <= args.fill_from <= args.fill_up_to:
        raise SystemExit("--fill-from needs --fill-up-to and 1 <= FROM <= UP_TO")
    band = {"fill_up_to": args.fill_up_to} if args.fill_up_to else {}
    if args.fill_from:
        band["fill_from"] = args.fill_from
    return band
