"""Supervised in-betweening in a key-relative frame (issue 19, stage 1).

A 1-D convolutional network (dilated residual blocks) reads SLERP+LERP of
the keys, expressed in the first key's frame (its root x/z position and
heading removed), with each frame's phase between its keys, and predicts a
residual on it: the root position and a 6D value per joint (Zhou et al.'s
continuous representation, ch. 4), scaled by a gate that is zero at keys, so
keys are exact by construction. Training is supervised only: L1 on global
joint positions (FK), on the 6D values and on the root, plus an L1 on
frame-to-frame joint velocities so the motion keeps its speed. This is the
"supervised stage first" of issue 19; `train --gan-weight W [--cross-clip P]`
adds the adversarial stage (motion/residual_adv.py: an LSGAN discriminator
and cross-clip keys, Sec. 5.2.5 and 5.2.7). Motion DNA is the generator's.

Data: the CMU clips of ../shared/data read here (train/cache/resid60.npz),
at 60 fps with motion/data.py's floor filter and take-wise split;
augmented with left/right mirroring (train --mirror) and random key gaps.

  train/.venv/bin/python -m deeprep_train.motion.residual prepare
  train/.venv/bin/python -m deeprep_train.motion.residual train --minutes 150 [--resume]
  train/.venv/bin/python -m deeprep_train.motion.residual eval [--split train|val] [--ckpt PATH]

Checkpoints: train/cache/resid/ckpt.pt (every --save-every steps, with the
optimizer and the weights' moving average) and snapshots gen_<step>.pt.
`portable` writes train/checkpoints/tween_resid.pt (weights and their moving
average in float16, no optimizer state; committed, so a new machine resumes
with `train --resume`, which falls back to it when train/cache is empty).
"""
import argparse
import copy
import json
import math
import os
import time

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

from deeprep_train.paths import ROOT, CACHE  # noqa: E402
from deeprep_train.motion.data import DATA, TRUE_FPS, VALIDATION, floor_segments, runs, take_of, MIN_SEGMENT  # noqa: E402
from deeprep_train.bvh import fk_from_local, local_fk, mat_to_quat, mirror_joints, read_bvh  # noqa: E402
from deeprep_train.motion.ablation import ratio_to_slerp  # noqa: E402
from deeprep_train.motion.eval import l2p_stats, npss  # noqa: E402
from deeprep_train.motion.residual_adv import MAX_GAP, Adversary, cross_clip  # noqa: E402
from deeprep_train.rotation import matrix_to_6d, quat_to_matrix, sixd_to_matrix  # noqa: E402

OUT = os.path.join(CACHE, "resid")
PORTABLE = os.path.join(ROOT, "train", "checkpoints", "tween_resid.pt")
SCALE = 100.0
GATE_FRAMES = 5.0
# frames per unit of the phase channels "frames since the previous key" and
# "to the next" (one second at 60 fps); crate/src/motion/residual.rs the same
PHASE_FRAMES = 60


# ---------------------------------------------------------------- data

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
            bvh = read_bvh(os.path.join(DATA, cls, name))
            names, parents, offsets, chans, data = bvh
            step = TRUE_FPS[cls] // 60
            bvh = (names, parents, offsets, chans, data[::step])
            trans, loc = local_fk(bvh)
            pos, _ = fk_from_local(bvh, trans, loc)
            if skel is None:
                skel = (names, parents, offsets, chans)
            keep, floor = floor_segments(pos)
            rj = [j for j in range(len(names)) if chans[j]]
            q = mat_to_quat(loc[:, rj]).astype(np.float32)
            root = trans[:, 0].copy()
            root[:, 1] -= floor
            split = "val" if take_of(cls, int(name[:-4])) in VALIDATION else "train"
            for a, b in runs(keep):
                if b - a < MIN_SEGMENT:
                    continue
                store[split]["root"].append(root[a:b].astype(np.float32))
                store[split]["quat"].append(q[a:b])
                store[split]["len"].append(b - a)
                store[split]["name"].append(f"{cls}/{name}@{a}")
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

    def window(self, n, rng):
        ok = np.nonzero(self.lens >= n)[0]
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


# ---------------------------------------------------------------- network

DILATIONS = (1, 2, 4, 8, 16, 32)


def build(s):
    """The network a checkpoint describes (older ones have no "dilations",
    "stride" or "skip")."""
    a = arch(s)
    return ResidualTween(a["K"], a["width"], a["dilations"], a["stride"], a["skip"])


def load_ema(path, device="cpu"):
    """The weights' moving average of a checkpoint (a snapshot, `ckpt.pt` or
    a portable one) as a network in eval mode."""
    s = torch.load(path, map_location="cpu")
    net = build(s)
    net.load_state_dict({k: v.float() for k, v in s["ema"].items()})
    return net.to(device).eval()


def arch(s):
    """The fields of a checkpoint (or `state`-like dict) that describe its
    network, as `build` reads them: what every saved file carries."""
    return {"width": int(s["width"]), "K": int(s["K"]), "dilations": list(s.get("dilations", DILATIONS)),
            "stride": int(s.get("stride", 1)), "skip": bool(s.get("skip", False))}


def grow(net, state, dilations):
    """Loads `state` into `net`, whose blocks extend the saved ones: the new
    blocks' last convolution starts at zero, so each is the identity and the
    grown network computes exactly what the saved one did."""
    own = net.state_dict()
    missing = [k for k in own if k not in state]
    own.update({k: v.float() for k, v in state.items()})
    net.load_state_dict(own)
    with torch.no_grad():
        for k in missing:
            if ".c2." in k:
                dict(net.named_parameters())[k].zero_()
    # the output convolution comes after the blocks: same keys, same shapes
    return missing


class Block(nn.Module):
    def __init__(self, w, d):
        super().__init__()
        self.c1 = nn.Conv1d(w, w, 3, padding=d, dilation=d)
        self.c2 = nn.Conv1d(w, w, 3, padding=d, dilation=d)

    def forward(self, x):
        return x + self.c2(F.leaky_relu(self.c1(F.leaky_relu(x, 0.2)), 0.2))


def upsample2(h, n):
    """[B, C, M] at every second frame (frames 0, 2, 4, ...) -> [B, C, n] at
    every frame, M = ceil(n / 2): even frames as given, odd frames the mean of
    their two neighbours (the last odd frame, past the last sample, repeats
    it). Linear interpolation aligned with a stride-2 convolution's samples."""
    nxt = torch.cat([h[..., 1:], h[..., -1:]], -1)
    return torch.stack([h, 0.5 * (h + nxt)], -1).flatten(2)[..., :n]


class ResidualTween(nn.Module):
    """[B, 3 + 6K + 4, N] (base root / SCALE, base 6D, phase) -> residual [B, 3 + 6K, N].

    With `stride` 2 (issue 23) the input convolution samples every second
    frame, the blocks run at 30 fps (each dilation spans twice the time), and
    their output is interpolated back to every frame before the output
    convolution: the blocks' arithmetic, most of the network's, halves."""

    def __init__(self, K, width=192, dilations=DILATIONS, stride=1, skip=False):
        super().__init__()
        if stride not in (1, 2):
            raise ValueError(f"stride {stride}: 1 or 2")
        self.K = K
        self.dilations = tuple(dilations)
        self.stride = stride
        cin = 3 + 6 * K + 4
        self.inp = nn.Conv1d(cin, width, 3, padding=1, stride=stride)
        self.blocks = nn.Sequential(*[Block(width, d) for d in dilations])
        # `skip`: a 1x1 convolution of the input at every frame added to the
        # blocks' (upsampled) output, so the output convolution sees each
        # frame's own phase and base pose, not only the 30 fps samples';
        # zero at first, so adding it to a trained network changes nothing
        self.skip = nn.Conv1d(cin, width, 1) if skip else None
        if skip:
            nn.init.zeros_(self.skip.weight)
            nn.init.zeros_(self.skip.bias)
        self.out = nn.Conv1d(width, 3 + 6 * K, 3, padding=1)
        nn.init.zeros_(self.out.weight)
        nn.init.zeros_(self.out.bias)

    def forward(self, x):
        h = self.blocks(self.inp(x))
        if self.stride == 2:
            h = upsample2(h, x.shape[-1])
        if self.skip is not None:
            h = h + self.skip(x)
        return self.out(F.leaky_relu(h, 0.2))

    def arch(self):
        """The fields `build` reads (`arch` of a checkpoint)."""
        return {"width": self.inp.out_channels, "K": self.K, "dilations": list(self.dilations),
                "stride": self.stride, "skip": self.skip is not None}


def net_input(base_root, base_rot, phase):
    """Batched [B,N,3], [B,N,K,3,3], [B,N,4] -> [B, C, N]."""
    B, N = base_root.shape[:2]
    x = torch.cat([base_root / SCALE, sixd(base_rot).reshape(B, N, -1), phase], -1)
    return x.transpose(1, 2)


def apply(net, base_root, base_rot, phase, gate):
    """The network's output motion: root [B,N,3], rotations [B,N,K,3,3]."""
    B, N, K = base_rot.shape[:3]
    res = net(net_input(base_root, base_rot, phase)).transpose(1, 2) * gate.unsqueeze(-1)
    root = base_root + res[..., :3] * SCALE
    r6 = sixd(base_rot).reshape(B, N, K, 6) + res[..., 3:].reshape(B, N, K, 6)
    return root, from_sixd(r6)


def fk(skel, root, rot, offsets):
    """Global joint positions [B,N,J,3] from root [B,N,3] and local rotations
    of the rotating joints [B,N,K,3,3]; joints without channels keep the
    identity. offsets [B,J,3]."""
    B, N = root.shape[:2]
    eye = torch.eye(3, device=root.device).expand(B, N, 3, 3)
    G, P = [], []
    for j, p in enumerate(skel.parents):
        loc = rot[:, :, skel.slot[j]] if skel.slot[j] >= 0 else eye
        if p < 0:
            G.append(loc)
            P.append(root)
        else:
            P.append(P[p] + torch.einsum("bnij,bj->bni", G[p], offsets[:, j]))
            G.append(G[p] @ loc)
    return torch.stack(P, 2)


# ---------------------------------------------------------------- training

def make_batch(clips, skel, b, n, rng, do_mirror, cross_p=0.0, regular=0.0):
    """b windows of n frames with random keys: the stacked features and
    offsets, the key lists, and which windows have a ground truth (False
    where `cross_p` spliced in keys from another clip, residual_adv.cross_clip;
    a cross-clip window keeps the first window's offsets)."""
    br, bq, gr, gq, ph, gt, offs, keysets, sup = [], [], [], [], [], [], [], [], []
    for _ in range(b):
        root, quat = clips.window(n, rng)
        off = skel.offsets
        if do_mirror and rng.random() < 0.5:
            root, quat = mirror(root, quat, skel)
            off = skel.mirror_offsets
        keys = sample_keys(n, rng, regular=regular)
        spliced = False
        if cross_p > 0:
            root_b, quat_b = clips.window(n, rng)
            root, quat, spliced = cross_clip(root, quat, root_b, quat_b, keys, rng, cross_p)
        f = features(root, quat, keys)
        for lst, v in zip((br, bq, gr, gq, ph, gt), f):
            lst.append(v)
        offs.append(off)
        keysets.append(keys)
        sup.append(not spliced)
    st = [torch.stack(x) for x in (br, bq, gr, gq, ph, gt, offs)]
    return st, keysets, torch.tensor(sup)


def losses(net, skel, batch, w, sup=None, adv=None, gan_min_gap=0, teacher=None):
    """The training losses. `sup` [B] marks the windows with a ground truth
    (the supervised terms use only those); `adv` (residual_adv.Adversary)
    adds the adversarial term on every window, whose gradient skips the
    frames of intervals shorter than `gan_min_gap` frames (there the
    supervised terms alone train the output); `teacher` (a trained network,
    frozen) adds "distill" on every window: the supervised "pos", "rot" and
    "root" terms with the teacher's output as the truth, and with a
    "distill_speed" weight its "speed" term the same way. Returns the terms,
    their weighted "total", and the output's root-relative positions under
    "_rel" with the truth's (supervised windows) under "_grel", for the
    discriminator's update."""
    base_root, base_rot, gt_root, gt_rot, phase, gate, offs = batch
    root, rot = apply(net, base_root, base_rot, phase, gate)
    pos = fk(skel, root, rot, offs) / SCALE
    out, private = {}, {}
    if teacher is not None:
        # in the motion's terms, not the residual's: the 6D residual's length
        # along the base rotation's columns is free (Gram-Schmidt drops it),
        # and trained networks use that freedom (mean |6D residual| ~ 9)
        with torch.no_grad():
            t_root, t_rot = apply(teacher, base_root, base_rot, phase, gate)
            t_pos = fk(skel, t_root, t_rot, offs) / SCALE
        d = supervised(skel, root, rot, pos, t_root, t_rot, t_pos, {"speed": w.get("distill_speed")})
        out["distill"] = d["pos"] + d["rot"] + d["root"]
        if w.get("distill_speed"):
            # the teacher's joint speeds on every window, cross-clip ones too:
            # an L1 on positions to a target the narrower network cannot match
            # in detail favours smoother (slower) motion
            out["distill_speed"] = d["speed"]
    if adv is not None:
        rel = adversarial_view(pos - pos[:, :, :1], phase, gan_min_gap)
        gan = adv.g_loss(rel)
        private["_rel"] = rel.detach()
    S = torch.arange(pos.shape[0]) if sup is None else sup.nonzero().squeeze(1)
    if len(S):
        S = S.to(pos.device)
        gpos = fk(skel, gt_root[S], gt_rot[S], offs[S]) / SCALE
        out.update(supervised(skel, root[S], rot[S], pos[S], gt_root[S], gt_rot[S], gpos, w))
        if adv is not None:
            private["_grel"] = (gpos - gpos[:, :, :1]).detach()
    if adv is not None:
        out["gan"] = gan
    out["total"] = sum(w[k] * v for k, v in out.items() if w.get(k))
    return {**out, **private}


def adversarial_view(rel, phase, min_gap):
    """rel [B,N,J,3] as the adversary sees it: detached (no gradient) at the
    frames of intervals shorter than `min_gap` frames (phase [B,N,4]: frames
    since the previous key / 60 plus frames to the next / 60 is the
    interval's length); unchanged when `min_gap` is 0."""
    if min_gap <= 0:
        return rel
    short = ((phase[..., 1] + phase[..., 2]) * PHASE_FRAMES < min_gap - 0.5)[..., None, None]
    return torch.where(short, rel.detach(), rel)


def supervised(skel, root, rot, pos, gt_root, gt_rot, gpos, w):
    """The supervised terms on windows with a ground truth: the output's
    root, rotations and positions (/ SCALE) against the truth's."""
    out = {
        "pos": (pos - gpos).abs().mean(),
        "rot": (sixd(rot) - sixd(gt_rot)).abs().mean(),
        "root": ((root - gt_root) / SCALE).abs().mean(),
        "vel": ((pos[:, 1:] - pos[:, :-1]) - (gpos[:, 1:] - gpos[:, :-1])).abs().mean() * 10,
    }
    if w.get("speed"):
        # per-frame speed of each joint relative to the root, magnitude only:
        # where the direction of motion is uncertain, L1 on velocity vectors
        # favours standing still; this term asks for the truth's energy
        rel, grel = pos - pos[:, :, :1], gpos - gpos[:, :, :1]
        sp = (rel[:, 1:] - rel[:, :-1]).norm(dim=-1)
        gsp = (grel[:, 1:] - grel[:, :-1]).norm(dim=-1)
        out["speed"] = (sp - gsp).abs().mean() * 10
    if w.get("l2p"):
        # the position error in L2P's units (each joint coordinate over its
        # spread in training windows): heights count about 7x more than in
        # "pos", as they do in the evaluation
        B, N = pos.shape[:2]
        out["l2p"] = ((pos - gpos).reshape(B, N, -1).abs() * skel.inv_sd * SCALE).mean()
    if w.get("foot"):
        # contact-aware foot velocity: where the truth's foot or toe is near
        # the window's floor and nearly still, the output's should be still
        f = skel.feet
        fp, gfp = pos[:, :, f], gpos[:, :, f]
        gv = (gfp[:, 1:] - gfp[:, :-1])[..., [0, 2]].norm(dim=-1)
        floor = gpos[:, :, f, 1].amin(dim=(1, 2), keepdim=True)
        contact = ((gfp[:, 1:, :, 1] < floor + 5 / SCALE) & (gv < 1 / SCALE)).float()
        v = (fp[:, 1:] - fp[:, :-1])[..., [0, 2]].norm(dim=-1)
        out["foot"] = (v * contact).sum() / contact.sum().clamp(min=1) * 10
    if w.get("spectral"):
        # short-time spectra of the root-relative positions (64-frame Hann
        # windows, hop 16): NPSS compares power spectra of short windows, and
        # an L1 on positions alone lets the output be smoother than the truth
        out["spectral"] = spectral_l1(pos - pos[:, :, :1], gpos - gpos[:, :, :1])
    return out


def spectral_l1(a, b, n_fft=64, hop=16):
    """Mean L1 between the short-time magnitude spectra of a and b
    [B,N,J,3] along N, in the signals' units (magnitudes over n_fft/2)."""
    B, N = a.shape[:2]
    win = torch.hann_window(n_fft, device=a.device)

    def mag(x):
        x = x.reshape(B, N, -1).transpose(1, 2).reshape(-1, N)
        return torch.stft(x, n_fft, hop, window=win, center=False, return_complex=True).abs()

    return (mag(a) - mag(b)).abs().mean() / (n_fft / 2) * 10


def train(args):
    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    if args.cross_clip > 0 and args.gan_weight <= 0:
        raise SystemExit("--cross-clip needs --gan-weight > 0: a cross-clip window has no ground truth, "
                         "only the adversarial loss")
    rng = np.random.default_rng(args.seed)
    d = np.load(args.data)
    skel = Skeleton(d)
    keep = None
    if args.d2_filter:
        f = np.load(args.d2_filter)
        keep = f["keep"]
        print(f"D.2 filter {args.d2_filter}: {json.loads(str(f['summary']))}", flush=True)
    clips = Clips(d, "train", keep)
    dev = torch.device(args.device)
    ck = os.path.join(args.out, "ckpt.pt")
    # what --resume starts from: the run's own checkpoint (with its optimizer
    # state), else the committed float16 one; read once
    src = None
    if args.resume:
        src = ck if os.path.exists(ck) else args.portable if os.path.exists(args.portable) else None
    s = torch.load(src, map_location="cpu") if src else None
    if s is not None and s["width"] != args.width:
        # a resumed run keeps its checkpoint's width (e.g. a pruned network)
        print(f"{src} has width {s['width']}: training at {s['width']}, not --width {args.width}", flush=True)
        args.width = s["width"]
    if args.stride is None:
        # the checkpoint's stride unless one is asked for (a stride-1 network
        # resumed with --stride 2 keeps its weights and learns to run at 30 fps)
        args.stride = s.get("stride", 1) if s is not None else 1
    # --skip adds the full-rate skip to a resumed network; a checkpoint with one keeps it
    args.skip = bool(args.skip or (s is not None and s.get("skip", False)))
    net = ResidualTween(skel.K, args.width, args.dilations, args.stride, args.skip)
    ema = copy.deepcopy(net)
    step, opt_state = 0, None
    os.makedirs(args.out, exist_ok=True)
    if s is not None:
        added = grow(net, s["net"], args.dilations)
        grow(ema, s["ema"], args.dilations)
        opt_state = None if added else s.get("opt")
        step = s["step"]
        rng = np.random.default_rng(args.seed + step)
        fresh = " (fresh optimizer state)" if opt_state is None else ""
        print(f"resumed {src} at step {step}" + (f", {len(added)} new tensors" if added else "") + fresh, flush=True)
    net.to(dev)
    ema.to(dev)
    opt = torch.optim.Adam(net.parameters(), lr=args.lr)
    if opt_state is not None:
        opt.load_state_dict(opt_state)  # moves the state to the parameters' device
    for g in opt.param_groups:
        g["lr"] = args.lr
    print(f"device: {dev}", flush=True)
    print(f"parameters: {sum(p.numel() for p in net.parameters()):,}", flush=True)
    w = {"pos": 1.0, "rot": 0.5, "root": 1.0, "vel": 1.0, "speed": args.speed_weight, "foot": args.foot_weight,
         "l2p": args.l2p_weight, "spectral": args.spectral_weight, "gan": args.gan_weight,
         "distill": args.distill_weight, "distill_speed": args.distill_speed_weight}
    teacher = None
    if args.distill_speed_weight > 0 and not args.teacher:
        raise SystemExit("--distill-speed-weight needs --teacher")
    if args.teacher:
        if args.distill_weight <= 0:
            raise SystemExit("--teacher needs --distill-weight > 0")
        teacher = load_ema(args.teacher, dev)  # run under no_grad in `losses`
        print(f"teacher {args.teacher}: {teacher.arch()}", flush=True)
    skel.inv_sd = torch.from_numpy(1.0 / l2p_sd()).float().to(dev)
    # the adversarial stage (residual_adv): a discriminator, carried in the checkpoint
    adv = Adversary(len(skel.parents), args.lr_d, dev) if args.gan_weight > 0 else None

    def draw():
        return make_batch(clips, skel, args.batch, args.frames, rng, args.mirror, args.cross_clip, args.regular_keys)

    if adv is not None and not (s is not None and adv.load(s)):
        # no discriminator yet: train one against the network as it is first
        for i in range(args.d_warmup):
            batch, _, sup = draw()
            batch = [x.to(dev, non_blocking=True) for x in batch]
            with torch.no_grad():
                o = losses(net, skel, batch, w, sup, adv, args.gan_min_gap)
            ld = adv.d_step(o["_grel"], o["_rel"]) if "_grel" in o else None
            if (i + 1) % 50 == 0:
                print(json.dumps({"d_warmup": i + 1, "D": ld}), flush=True)
    log = open(os.path.join(args.out, "log.jsonl"), "a")
    t0, last = time.time(), time.time()
    acc = {}

    def save():
        state = {"net": net.state_dict(), "ema": ema.state_dict(), "opt": opt.state_dict(), "step": step,
                 **net.arch()}
        if adv is not None:
            state.update(adv.state())
        torch.save(state, ck + ".tmp")
        os.replace(ck + ".tmp", ck)

    while time.time() - t0 < args.minutes * 60:
        batch, _, sup = draw()
        batch = [x.to(dev, non_blocking=True) for x in batch]
        out = losses(net, skel, batch, w, sup, adv, args.gan_min_gap, teacher)
        opt.zero_grad()
        out["total"].backward()
        torch.nn.utils.clip_grad_norm_(net.parameters(), 1.0)
        opt.step()
        if adv is not None and "_grel" in out:
            out["D"] = torch.tensor(adv.d_step(out["_grel"], out["_rel"]))
        out["supervised"] = sup.float().mean()
        for k in [k for k in out if k.startswith("_")]:
            del out[k]
        with torch.no_grad():
            for pe, pn in zip(ema.parameters(), net.parameters()):
                pe.mul_(args.ema).add_(pn, alpha=1 - args.ema)
        step += 1
        for k, v in out.items():
            acc[k] = acc.get(k, 0.0) + float(v.detach())
        if step % 50 == 0:
            rec = {"step": step, "t": round(time.time() - t0), **{k: v / 50 for k, v in acc.items()}}
            log.write(json.dumps(rec) + "\n")
            log.flush()
            acc = {}
            if time.time() - last > 60:
                print(json.dumps(rec), flush=True)
                last = time.time()
        if step % args.save_every == 0:
            save()
            if step % args.snapshot_every == 0:
                torch.save({"ema": ema.state_dict(), "step": step, **net.arch()},
                           os.path.join(args.out, f"gen_{step}.pt"))
    save()
    print(f"done at step {step}", flush=True)


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


def export(args):
    """models/onnx/tween_residual.onnx (the weights' moving average; input
    [1, 3 + 6K + 4, N], N free), its manifest and a parity fixture."""
    import onnxruntime as ort
    from deeprep_train.motion.export import fixture
    from deeprep_train.export.util import ONNX_DIR, git_commit, write_json
    s = torch.load(args.ckpt)
    net = build(s)
    net.load_state_dict({k: v.float() for k, v in s["ema"].items()})
    net.eval()
    d = np.load(args.data)
    skel = Skeleton(d)
    gen_manifest = json.load(open(os.path.join(ONNX_DIR, "tween_generator.manifest.json")))
    cin = 3 + 6 * skel.K + 4
    path = os.path.join(ONNX_DIR, "tween_residual.onnx")
    # the fixture's input: a real window's features (first training segment,
    # 65 frames, keys at 0, 30 and 64: an odd length, which a stride-2
    # network pads), so outputs are in their usual range
    clips = Clips(d, "train")
    f = features(clips.root[:65], clips.quat[:65], [0, 30, 64])
    x = net_input(f[0].unsqueeze(0), f[1].unsqueeze(0), f[4].unsqueeze(0))
    torch.onnx.export(net, (x,), path, input_names=["x"], output_names=["residual"], opset_version=17,
                      dynamic_axes={"x": {2: "frames"}, "residual": {2: "frames"}}, dynamo=False)
    with torch.no_grad():
        ref = net(x).numpy()
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    parity = fixture("tween_residual", sess, {"x": x.numpy()}, ref)
    write_json(os.path.join(ONNX_DIR, "tween_residual.manifest.json"), {
        "name": "tween_residual",
        "kind": "residual-tween",
        "description": "a learned residual on SLERP+LERP in the first key's frame (train/deeprep_train/motion/residual.py; issue 19)",
        "inputs": [{"name": "x", "shape": [1, cin, "frames"],
                    "channels": "root position in the first key's frame / scale (3), 6D of each joint with channels "
                                "in file order, the root's in that frame (6K), then s, frames since the previous key / 60, "
                                "frames to the next key / 60, gate"}],
        "outputs": [{"name": "residual", "shape": [1, 3 + 6 * skel.K, "frames"]}],
        "scale": SCALE,
        "gate_frames": GATE_FRAMES,
        "rotating": skel.rotating,
        "skeleton_bvh": gen_manifest["skeleton_bvh"],
        "training": {"steps": int(s["step"]), **net.arch(), "checkpoint": os.path.relpath(args.ckpt, ROOT),
                     **({"recipe": args.recipe} if args.recipe else {})},
        "parity_torch_vs_onnxruntime": parity,
        "training_data": "CMU train takes at 60 fps (59,290 frames, train/deeprep_train/motion/data.py's split and floor filter), mirrored",
        "training_code_commit": git_commit(),
        "exporter": {"torch": torch.__version__, "onnxruntime": ort.__version__, "opset": 17},
    })
    from deeprep_train.export.half_weights import convert
    convert("tween_residual")  # the shipped file keeps its weights as float16 (issue 21)
    print(f"exported {path} (step {s['step']}), parity {parity:.2e}")


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


def portable(args):
    """The running checkpoint's weights and moving average in float16, to
    train/checkpoints/tween_resid.pt (or --to)."""
    s = torch.load(args.ckpt or os.path.join(args.out, "ckpt.pt"), map_location="cpu")
    half = {k: {n: v.half() for n, v in s[k].items()} for k in ("net", "ema")}
    to = args.to or PORTABLE
    os.makedirs(os.path.dirname(os.path.abspath(to)), exist_ok=True)
    torch.save({**half, "step": s["step"], **arch(s)}, to)
    print(f"wrote {to} (step {s['step']}, {os.path.getsize(to) / 1e6:.1f} MB)")


def prune(args):
    """A narrower network from a trained one (issue 23: the residual network
    is most of the default pipeline's time, which grows with width²): keeps
    the `--width` residual-stream channels with the largest weights into and
    out of the stream, and in each block the `--width` hidden channels with
    the largest c1-out x c2-in weights; writes DIR/ckpt.pt (no optimizer
    state) for `train --resume --out DIR --width W` to fine-tune."""
    s = torch.load(args.ckpt or PORTABLE, map_location="cpu")
    w = args.width
    out = {"step": s["step"], **arch(s), "width": w,
           "pruned_from": {"ckpt": args.ckpt or PORTABLE, "width": s["width"], "step": s["step"]}}
    for part in ("net", "ema"):
        p = {k: v.float() for k, v in s[part].items()}
        blocks = sorted({int(k.split(".")[1]) for k in p if k.startswith("blocks.")})
        # residual stream: what writes it (inp, each c2) and reads it (each c1, out)
        score = p["inp.weight"].pow(2).sum((1, 2)) + p["out.weight"].pow(2).sum((0, 2))
        if "skip.weight" in p:  # the full-rate skip writes the stream too
            score += p["skip.weight"].pow(2).sum((1, 2))
        for b in blocks:
            score += p[f"blocks.{b}.c2.weight"].pow(2).sum((1, 2)) + p[f"blocks.{b}.c1.weight"].pow(2).sum((0, 2))
        keep = torch.argsort(score, descending=True)[:w].sort().values
        q = {"inp.weight": p["inp.weight"][keep], "inp.bias": p["inp.bias"][keep],
             "out.weight": p["out.weight"][:, keep], "out.bias": p["out.bias"]}
        if "skip.weight" in p:
            q["skip.weight"], q["skip.bias"] = p["skip.weight"][keep], p["skip.bias"][keep]
        for b in blocks:
            c1w, c1b = p[f"blocks.{b}.c1.weight"], p[f"blocks.{b}.c1.bias"]
            c2w, c2b = p[f"blocks.{b}.c2.weight"], p[f"blocks.{b}.c2.bias"]
            h = (c1w.pow(2).sum((1, 2)) * c2w.pow(2).sum((0, 2))).sqrt()
            hk = torch.argsort(h, descending=True)[:w].sort().values
            q[f"blocks.{b}.c1.weight"] = c1w[hk][:, keep]
            q[f"blocks.{b}.c1.bias"] = c1b[hk]
            q[f"blocks.{b}.c2.weight"] = c2w[keep][:, hk]
            q[f"blocks.{b}.c2.bias"] = c2b[keep]
        out[part] = q
    os.makedirs(args.out, exist_ok=True)
    torch.save(out, os.path.join(args.out, "ckpt.pt"))
    n = sum(v.numel() for v in out["net"].values())
    print(f"pruned width {s['width']} -> {w} at step {s['step']}: {n:,} parameters -> {args.out}/ckpt.pt")


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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("cmd", choices=["prepare", "train", "eval", "portable", "export", "pick", "prune"])
    ap.add_argument("results", nargs="*", help="pick: eval --json files of the candidates")
    ap.add_argument("--data", default=os.path.join(CACHE, "resid60.npz"))
    ap.add_argument("--out", default=OUT)
    ap.add_argument("--minutes", type=float, default=60)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--device", default="cpu", help="torch device for training (cuda on a lent GPU)")
    ap.add_argument("--to", help="portable: where to write (default train/checkpoints/tween_resid.pt)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--width", type=int, default=192)
    ap.add_argument("--batch", type=int, default=8)
    ap.add_argument("--frames", type=int, default=480)
    ap.add_argument("--lr", type=float, default=5e-4)
    ap.add_argument("--ema", type=float, default=0.999)
    ap.add_argument("--mirror", type=int, default=1)
    ap.add_argument("--speed-weight", type=float, default=0.0)
    ap.add_argument("--foot-weight", type=float, default=0.0)
    ap.add_argument("--l2p-weight", type=float, default=0.0,
                    help="weight of the position loss in L2P's units (per-coordinate spread)")
    ap.add_argument("--spectral-weight", type=float, default=0.0,
                    help="weight of the short-time spectrum loss on root-relative positions (NPSS's view)")
    ap.add_argument("--dilations", type=lambda s: tuple(int(x) for x in s.split(",")), default=DILATIONS,
                    help="one residual block per dilation; resuming with more than saved appends identity blocks")
    ap.add_argument("--speed-margin", type=float, default=0.0,
                    help="pick: ask joint speed within 30%% minus this of the truth's at gaps 120 and 300 on training "
                         "takes (validation has come out lower: run G 0.81 -> 0.74 at 120, 0.76 -> 0.74 at 300)")
    ap.add_argument("--l2p-margin", type=float, default=0.0,
                    help="pick: ask L2P at most 1 minus this of SLERP+LERP's at every gap on training takes (the "
                         "stride-2 networks lost 0.08 of that ratio at gap 30 on validation)")
    ap.add_argument("--d2-filter", help="train: only the training frames motion/filter_d2.py keeps "
                                        "(its .npz, e.g. train/cache/d2_filter.npz)")
    ap.add_argument("--gan-weight", type=float, default=0.0,
                    help="the adversarial stage (residual_adv.py): weight of the network's LSGAN loss; 0 trains "
                         "with supervision only")
    ap.add_argument("--cross-clip", type=float, default=0.0,
                    help="cross-clip keys (Sec. 5.2.7 rule 2): probability scale p; an interval of g >= 180 frames "
                         "takes its end key from another clip with probability p * g / 300 (such windows get only "
                         "the adversarial loss)")
    ap.add_argument("--lr-d", type=float, default=1e-4, help="the discriminator's learning rate (Adam)")
    ap.add_argument("--d-warmup", type=int, default=300,
                    help="discriminator-only steps when the checkpoint has no discriminator")
    ap.add_argument("--regular-keys", type=float, default=0.0,
                    help="train: the share of windows whose keys are evenly spaced (one interval drawn and repeated; "
                         "the rest draw each interval)")
    ap.add_argument("--gan-min-gap", type=int, default=0,
                    help="train: the adversarial loss's gradient skips frames of intervals shorter than this "
                         "(frames); the supervised terms alone train them (issue 19: the adversary cost L2P at gap 30)")
    ap.add_argument("--skip", action="store_true",
                    help="train: add a full-rate 1x1 skip from the input to the output convolution (zero at first; "
                         "for stride 2, issue 19's short gaps); a checkpoint with one keeps it")
    ap.add_argument("--stride", type=int, choices=[1, 2],
                    help="train: 2 runs the blocks at every second frame (half their arithmetic; issue 23); "
                         "default: the resumed checkpoint's, else 1")
    ap.add_argument("--recipe", help="export: how the checkpoint was trained, one sentence for the manifest and the "
                                     "README's models table (checkpoints do not record their training flags)")
    ap.add_argument("--teacher", help="train: a trained checkpoint whose moving average the network learns to "
                    "match (knowledge distillation, e.g. a wider network into a pruned one)")
    ap.add_argument("--distill-weight", type=float, default=0.0,
                    help="train: weight of the L1 distance to --teacher's output (positions, 6D rotations "
                    "and root, as the supervised terms measure them), on every window")
    ap.add_argument("--distill-speed-weight", type=float, default=0.0,
                    help="train: weight of the L1 distance of per-joint speeds (the supervised speed term) to "
                    "--teacher's, on every window")
    ap.add_argument("--resume", action="store_true")
    ap.add_argument("--portable", default=PORTABLE,
                    help="train --resume without a checkpoint in --out starts from this float16 file "
                         "(default train/checkpoints/tween_resid.pt; the pruned one: train/checkpoints/tween_resid_w128.pt)")
    ap.add_argument("--save-every", type=int, default=250)
    ap.add_argument("--snapshot-every", type=int, default=1000)
    ap.add_argument("--split", default="train")
    ap.add_argument("--ckpt")
    ap.add_argument("--gaps", type=lambda s: [int(x) for x in s.split(",")], default=[30, 60, 120, 300])
    ap.add_argument("--json")
    args = ap.parse_args()
    if args.cmd == "prepare":
        prepare(args.data)
    elif args.cmd == "train":
        train(args)
    elif args.cmd == "portable":
        portable(args)
    elif args.cmd == "export":
        export(args)
    elif args.cmd == "pick":
        pick(args)
    elif args.cmd == "prune":
        prune(args)
    else:
        evaluate(args)


if __name__ == "__main__":
    main()
