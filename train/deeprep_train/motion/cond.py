"""One conditional in-betweening network for every kind of key (issue 47).

The whole-pose residual network (motion/residual.py) corrects SLERP+LERP of
whole-pose keys. This network takes keys of any kind, per key:

- **P**, a whole pose (root position and every joint's rotation),
- **R**, the root's position only (a root path),
- **X**, the root's position and every joint's x and y (a 2-D sketch in the
  front view, depth unknown),

mixed freely within a window, and reads per frame (channels in this order):

1. the base root (3, / SCALE): LERP of the keys' root positions (every kind
   gives it);
2. the base rotations (6K): SLERP between the previous and next P keys,
   held before the first and after the last; the training takes' mean pose
   (the *prior*) where the window has no P key;
3. the P keys' phase (4: s, frames since the previous / 60, to the next /
   60, gate) - channels 1-3 are exactly the whole-pose network's input, so
   that network's weights start this one (`--init`), new channels at zero;
4. a P-keys flag (1), the phase of all keys (4), an X-or-P-keys flag (1)
   and their phase (4);
5. each joint's root-relative x and y (2J, / SCALE), LERP between the keys
   that give them (X and P keys), zero where none does;
6. Z noise channels, constant over a window (the input a diversity loss
   will use; at zero weight until then).

The output is the whole-pose network's: a residual on the base root and
6D rotations, the root's gated by the distance to the nearest key (every
key pins the root) and the rotations' by the distance to the nearest P key
(1 everywhere when there is none), so P keys and root positions are exact
by construction; X keys are pinned after synthesis (crate motion::xy).

The canonical frame: the first key's root x/z removed, and its heading too
when that key is a P key and no key in the window is an X key (an X key's
x and y are in the world's front view, which a turn would mix with the
unknown depth). Windows are turned about the vertical at random, so a
world-frame window may head anywhere.

Training is the whole-pose recipe's supervised stage (motion/residual.py's
losses: positions, 6D, root, velocities, joint speed, L2P, foot contact,
short-time spectra); the adversarial stage and the diversity term come
after it.

  train/.venv/bin/python -m deeprep_train.motion.cond train --init checkpoints/tween_resid_w128b.pt --minutes 150
  train/.venv/bin/python -m deeprep_train.motion.cond train --resume --minutes 150
  train/.venv/bin/python -m deeprep_train.motion.cond eval --kind root --ckpt cache/cond/gen_N.pt
  train/.venv/bin/python -m deeprep_train.motion.cond portable
  train/.venv/bin/python -m deeprep_train.motion.cond export --ckpt cache/cond/gen_N.pt

`export` writes models/onnx/tween_cond.onnx (float16 weights), its manifest
(with the prior pose, so the runtime builds the same input) and two
fixtures: the network's (onnxruntime's output for one input) and
fixtures/runtime/tween_cond_motion.json (keys of every kind and the motion this module's
`features` and `apply` make from them with the exported network), which
crate/src/motion/cond.rs must reproduce.
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

from deeprep_train.paths import ROOT, CACHE
from deeprep_train.motion.eval import npss
from deeprep_train.motion import dna as dna_rule
from deeprep_train.motion.residual import (
    GATE_FRAMES, PHASE_FRAMES, SCALE, Clips, ResidualTween, Skeleton, arch, fk, from_sixd, key_phase, l2p_sd,
    mirror, quat_to_mat, rot_y, sample_keys, fill_keys, add_fill_args, fill_band, sixd, slerp, supervised, upsample2)
from deeprep_train.motion.residual_adv import quat_mul

OUT = os.path.join(CACHE, "cond")
PORTABLE = os.path.join(ROOT, "train", "checkpoints", "tween_cond.pt")
P, R, X = 0, 1, 2
KIND_NAMES = {"pose": P, "root": R, "xy": X}
Z = 8  # noise channels


def extra_channels(J):
    """Input channels beyond the whole-pose network's 3 + 6K + 4."""
    return 1 + 4 + 1 + 4 + 2 * J + Z


# ---------------------------------------------------------------- keys and features

def group_phase(group, n, rate=1):
    """Phase [n, 4] (s, frames since the previous key / 60, to the next /
    60, gate) of the frames of an n-frame window towards the keys `group`
    (`rate`: the window's frames are `rate` frames of the 60 fps motion apart,
    the hierarchy's coarse pass; the distances are then in 60 fps frames,
    so the phase's slope tells the network the frame rate; the gate stays
    in the window's frames)
    (sorted frame indices), and the previous / next key per frame (a, b).
    Between the first and last key exactly `residual.key_phase`'s; before the
    first key a = b = the first (s = 0), after the last a = b = the last
    (s = 1), both distances the distance to it. No key: zeros, a = b = 0."""
    t = torch.arange(n)
    if not group:
        z = torch.zeros(n, dtype=torch.long)
        return torch.zeros(n, 4), z, z
    if len(group) == 1:
        k = group[0]
        a = b = torch.full((n,), k)
        s = (t > k).float()
    else:
        a, b, s = key_phase(group, n)
        before, after = t < group[0], t > group[-1]
        a = torch.where(before, group[0], torch.where(after, group[-1], a))
        b = torch.where(before, group[0], torch.where(after, group[-1], b))
        s = torch.where(before, 0.0, torch.where(after, 1.0, s))
    dp, dn = (t - a).abs().float(), (b - t).abs().float()
    gate = 1 - torch.exp(-torch.minimum(dp, dn) / GATE_FRAMES)
    return torch.stack([s, dp * rate / PHASE_FRAMES, dn * rate / PHASE_FRAMES, gate], -1), a, b


def turn(root, quat, phi):
    """The window turned about the vertical through the origin by phi."""
    qy = torch.tensor([math.cos(phi / 2), 0.0, math.sin(phi / 2), 0.0])
    r = root @ rot_y(torch.tensor(phi)).T
    q = quat.clone()
    q[:, 0] = quat_mul(qy.expand_as(q[:, 0]), q[:, 0])
    return r, q


def canonical_frame(root, quat, keys, kinds):
    """The window's canonical frame (module docstring): the rotation C about
    the vertical and the offset off, so that a world point p is C @ (p - off)
    there. The first key's root x/z is removed, and its heading too when it
    is a P key and no key is an X key."""
    k0 = keys[0]
    if kinds[0] == P and X not in kinds:
        f = quat_to_mat(quat[k0, 0])[:, 2]
        C = rot_y(-torch.atan2(f[0], f[2]))
    else:
        C = torch.eye(3)
    return C, torch.stack([root[k0, 0], torch.zeros(()), root[k0, 2]])


def context_spans(keys, kinds):
    """Gaps with context (issue 50): consecutive keys a < b - 1, both whole
    poses, with a whole pose at a - 1 or at b + 1. Returns (a, b, prev,
    next), prev / next None where that frame is not a whole-pose key."""
    pose = {k for k, c in zip(keys, kinds) if c == P}
    out = []
    for (a, ca), (b, cb) in zip(zip(keys, kinds), zip(keys[1:], kinds[1:])):
        if ca == P and cb == P and b > a + 1:
            p = a - 1 if a - 1 in pose else None
            q = b + 1 if b + 1 in pose else None
            if p is not None or q is not None:
                out.append((a, b, p, q))
    return out


def _qconj(q):
    return q * torch.tensor([1.0, -1.0, -1.0, -1.0], dtype=q.dtype)


def _step(x, y):
    """The rotation from x to y as a scaled axis (the short arc), [..., 3]."""
    y = torch.where((x * y).sum(-1, keepdim=True) < 0, -y, y)
    d = quat_mul(_qconj(x), y)
    d = d / d.norm(dim=-1, keepdim=True)
    v = d[..., 1:]
    sv = v.norm(dim=-1, keepdim=True)
    angle = 2 * torch.atan2(sv, d[..., :1].clamp(min=0))
    return torch.where(sv > 1e-12, v / sv.clamp(min=1e-12) * angle, 2 * v)


def _exp(w):
    """Scaled axis [..., 3] -> unit quaternion [..., 4]."""
    a = w.norm(dim=-1, keepdim=True)
    k = torch.where(a > 1e-12, torch.sin(a / 2) / a.clamp(min=1e-12), 0.5 - a * a / 48)
    return torch.cat([torch.cos(a / 2), w * k], -1)


def hermite_base(spans, root, quat, base_root, base_q):
    """motion::fill::hermite's context-tangent curve on each span of
    `context_spans`, written over base_root [N,3] and base_q [N,K,4] (in
    place): the root and every joint's rotation from a to b with the
    context's velocities as end tangents (the chord's where one side has
    no context frame). root [N,3] and quat [N,K,4] the truth (key frames
    only are read), root in the frame base_root is in."""
    for a, b, p, q in spans:
        n = float(b - a)
        u = torch.arange(1, b - a, dtype=root.dtype) / n
        h00, h10, h01, h11 = (2 * u ** 3 - 3 * u ** 2 + 1, u ** 3 - 2 * u ** 2 + u, -2 * u ** 3 + 3 * u ** 2, u ** 3 - u ** 2)
        pa, pb = root[a], root[b]
        chord = (pb - pa) / n
        va = pa - root[p] if p is not None else chord
        vb = root[q] - pb if q is not None else chord
        base_root[a + 1:b] = (h00[:, None] * pa + (n * h10)[:, None] * va + h01[:, None] * pb
                              + (n * h11)[:, None] * vb)
        qa, qb = quat[a], quat[b]
        w1 = _step(qa, qb)
        t0 = _step(quat[p], qa) if p is not None else w1 / n
        t1 = _step(qb, quat[q]) if q is not None else w1 / n
        w = ((n * h10)[:, None, None] * t0 + h01[:, None, None] * w1 + (n * h11)[:, None, None] * t1)
        r = quat_mul(qa.expand(len(u), -1, -1), _exp(w))
        base_q[a + 1:b] = r / r.norm(dim=-1, keepdim=True)


def features(skel, prior, root, quat, keys, kinds, noise, offsets, context_base=False, rate=1):
    """The network's input pieces for one window. root [N,3], quat [N,K,4]
    (the truth; only key frames are read for the input), keys (sorted frame
    indices), kinds (P/R/X per key), noise [Z], offsets [J,3]. Returns
    (x [C,N], gate_root [N], gate_rot [N], base_root [N,3], base_rot
    [N,K,3,3], gt_root [N,3], gt_rot [N,K,3,3]), all in the canonical frame.
    rate: the window's frames are that many 60 fps frames apart (group_phase)."""
    n = root.shape[0]
    pk = [k for k, c in zip(keys, kinds) if c == P]
    xk = [k for k, c in zip(keys, kinds) if c in (P, X)]
    C, off = canonical_frame(root, quat, keys, kinds)
    gt_root = (root - off) @ C.T
    gt_rot = quat_to_mat(quat)
    gt_rot = torch.cat([(C @ gt_rot[:, 0]).unsqueeze(1), gt_rot[:, 1:]], 1)
    ph_all, a, b = group_phase(keys, n, rate)
    base_root = gt_root[a] + ph_all[:, :1] * (gt_root[b] - gt_root[a])
    ph_p, a, b = group_phase(pk, n, rate)
    if pk:
        base_q = slerp(quat[a], quat[b], ph_p[:, :1].expand(-1, quat.shape[1]))
        if context_base:
            hermite_base(context_spans(keys, kinds), gt_root, quat, base_root, base_q)
        base_rot = quat_to_mat(base_q)
        base_rot = torch.cat([(C @ base_rot[:, 0]).unsqueeze(1), base_rot[:, 1:]], 1)
        gate_rot = ph_p[:, 3]
    else:
        base_rot = quat_to_mat(prior).expand(n, -1, -1, -1)
        gate_rot = torch.ones(n)
    ph_x, a, b = group_phase(xk, n, rate)
    if xk:
        pos = fk(skel, gt_root[None, xk], gt_rot[None, xk], offsets[None])[0]
        xy = (pos - pos[:, :1])[..., :2].reshape(len(xk), -1) / SCALE   # [len(xk), 2J]
        idx = {k: i for i, k in enumerate(xk)}
        ia = torch.tensor([idx[int(v)] for v in a])
        ib = torch.tensor([idx[int(v)] for v in b])
        xy = xy[ia] + ph_x[:, :1] * (xy[ib] - xy[ia])
    else:
        xy = torch.zeros(n, 2 * len(skel.parents))
    flag_p = torch.full((n, 1), float(bool(pk)))
    flag_x = torch.full((n, 1), float(bool(xk)))
    x = torch.cat([base_root / SCALE, sixd(base_rot).reshape(n, -1), ph_p, flag_p, ph_all, flag_x, ph_x, xy,
                   noise.expand(n, -1)], -1).T
    return x, ph_all[:, 3], gate_rot, base_root, base_rot, gt_root, gt_rot


def sample_kinds(keys, rng):
    """What each key gives, drawn as users give keys: all whole poses
    (20%), all root positions (35%), all 2-D (20%) or a mix (25%)."""
    r = rng.random()
    if r < 0.2:
        return [P] * len(keys)
    if r < 0.55:
        return [R] * len(keys)
    if r < 0.75:
        return [X] * len(keys)
    return [int(c) for c in rng.choice([P, R, X], size=len(keys), p=[0.3, 0.4, 0.3])]


def prior_pose(clips):
    """The training takes' mean local rotation per joint (quaternions [K,4],
    sign-aligned to the first frame's), the root's the identity."""
    q = clips.quat
    q = torch.where(((q * q[:1]).sum(-1, keepdim=True) < 0), -q, q)
    m = q.mean(0)
    m = m / m.norm(dim=-1, keepdim=True)
    m[0] = torch.tensor([1.0, 0.0, 0.0, 0.0])
    return m


# ---------------------------------------------------------------- network

class CondTween(nn.Module):
    """[B, 3 + 6K + 4 + extra, N] -> residual [B, 3 + 6K, N]: the whole-pose
    network's blocks with a wider input convolution (and skip)."""

    def __init__(self, K, J, width, dilations, stride=1, skip=False, context_base=False, coarse_rates=False,
                 dna=False):
        super().__init__()
        self.core = ResidualTween(K, width, dilations, stride, skip)
        self.dna = False
        self.K, self.J = K, J
        # trained on the hierarchy's coarse rates too (group_phase's rate; issue 47 item 3)
        self.coarse_rates = bool(coarse_rates)
        # the base over gaps with context frames: motion::fill's Hermite curve (issue 50)
        self.context_base = bool(context_base)
        cin = 3 + 6 * K + 4 + extra_channels(J)
        old = self.core.inp
        self.core.inp = nn.Conv1d(cin, width, 3, padding=1, stride=stride)
        with torch.no_grad():
            self.core.inp.weight.zero_()
            self.core.inp.weight[:, :old.in_channels] = old.weight
            self.core.inp.bias.copy_(old.bias)
        if skip:
            self.core.skip = nn.Conv1d(cin, width, 1)
            nn.init.zeros_(self.core.skip.weight)
            nn.init.zeros_(self.core.skip.bias)
        if dna:
            self.add_dna()

    def add_dna(self):
        """Motion DNA (thesis Sec. 5.2.5): a shared MLP on each representative
        pose (its joints relative to the root, the root's rotation removed,
        / SCALE: the thesis' Lambda), average-pooled, then a linear layer;
        the code w is added to every frame's features after the input
        convolution (the thesis concatenates it to the bottleneck's; this
        network has no bottleneck, and a sum after a convolution is that
        convolution of the concatenation). The linear layer starts at zero,
        so adding DNA to a trained network changes nothing until it learns."""
        self.dna = True
        width = self.core.inp.out_channels
        self.dna_enc = nn.Sequential(nn.Linear(3 * self.J, 256), nn.LeakyReLU(0.2), nn.Linear(256, 256),
                                     nn.LeakyReLU(0.2))
        self.dna_out = nn.Linear(256, width)
        nn.init.zeros_(self.dna_out.weight)
        nn.init.zeros_(self.dna_out.bias)

    def dna_code(self, dna, dna_w):
        """dna [B, k, 3J] poses; dna_w [B, k, N], how much each pose steers
        each frame (motion.dna's frame_weights; what the export takes), or
        [B, k], 1 for a pose given and 0 for padding, on every frame (what
        training feeds): the code [B, width, N] (N = 1 for [B, k]), each
        frame's the mean of its poses' encodings, zero where none is given."""
        if dna_w.dim() == 2:
            dna_w = dna_w[..., None]
        # 2-D through the linear layers, so the export keeps their weights' names (Gemm)
        B, k, p = dna.shape
        e = self.dna_enc(dna.reshape(B * k, p)).reshape(B, k, -1)
        n = dna_w.sum(1)                                                          # [B, N]
        pooled = torch.einsum("bkc,bkn->bnc", e, dna_w) / n.clamp(min=1.0)[..., None]
        N = pooled.shape[1]
        code = self.dna_out(pooled.reshape(B * N, -1)).reshape(B, N, -1) * n.clamp(max=1.0)[..., None]
        return code.transpose(1, 2)

    def forward(self, x, dna=None, dna_w=None):
        if not self.dna or dna is None:
            return self.core(x)
        c = self.core
        code = self.dna_code(dna, dna_w)
        if c.stride > 1:
            # a per-frame code at the input convolution's frames (every stride-th; a
            # pooling of width 1, which tract runs where a strided Slice fails to analyse)
            code = F.max_pool1d(code, 1, c.stride)
        h = c.blocks(c.inp(x) + code)
        if c.stride == 2:
            h = upsample2(h, x.shape[-1])
        if c.skip is not None:
            h = h + c.skip(x)
        return c.out(F.leaky_relu(h, 0.2))

    def arch(self):
        return {**self.core.arch(), "J": self.J, "Z": Z, "context_base": int(self.context_base),
                "coarse_rates": int(self.coarse_rates), "dna": int(self.dna)}


def widen(state, cin):
    """A whole-pose checkpoint's weights with the input (and skip)
    convolution widened to cin input channels, the new ones at zero, under
    CondTween's names."""
    out = {}
    for k, v in state.items():
        v = v.float()
        if k in ("inp.weight", "skip.weight") and v.shape[1] < cin:
            w = torch.zeros(v.shape[0], cin, v.shape[2])
            w[:, :v.shape[1]] = v
            v = w
        out["core." + k] = v
    return out


def build(s):
    a = arch(s)
    return CondTween(a["K"], int(s["J"]), a["width"], a["dilations"], a["stride"], a["skip"],
                     bool(s.get("context_base", 0)), bool(s.get("coarse_rates", 0)), bool(s.get("dna", 0)))


def load_ema(path, device="cpu"):
    s = torch.load(path, map_location="cpu")
    net = build(s)
    net.load_state_dict({k: v.float() for k, v in s["ema"].items()})
    return net.to(device).eval(), s


def apply(net, x, gate_root, gate_rot, base_root, base_rot, dna=None, dna_w=None):
    """The output motion: root [B,N,3], rotations [B,N,K,3,3]."""
    B, N, K = base_rot.shape[:3]
    res = net(x, dna, dna_w).transpose(1, 2)
    root = base_root + res[..., :3] * SCALE * gate_root.unsqueeze(-1)
    r6 = sixd(base_rot).reshape(B, N, K, 6) + res[..., 3:].reshape(B, N, K, 6) * gate_rot[..., None, None]
    return root, from_sixd(r6)


# ---------------------------------------------------------------- training

def spread(d, skel):
    """The per-coordinate spread L2P divides by: residual.l2p_sd (from
    motion/data.py's cache, which needs the CLI built) when that cache
    exists, else the same statistic from resid60.npz's training takes
    (global positions of 300-frame windows every 150 frames, each re-centred
    on its first frame's root x/z)."""
    if os.path.exists(os.path.join(CACHE, "l2p_sd.npy")) or os.path.exists(os.path.join(CACHE, "motion60.npz")):
        return l2p_sd()
    clips = Clips(d, "train")
    chunks = []
    for s0, ln in zip(clips.starts, clips.lens):
        for a in range(int(s0), int(s0 + ln) - 300, 150):
            with torch.no_grad():
                pos = fk(skel, clips.root[None, a:a + 300], quat_to_mat(clips.quat[None, a:a + 300]),
                         skel.offsets[None])[0]
            pos[:, :, [0, 2]] -= pos[0, 0, [0, 2]].clone()
            chunks.append(pos.reshape(300, -1).numpy())
    return np.concatenate(chunks).std(0) + 1e-6


def make_batch(clips, skel, prior, b, n, rng, do_mirror, device, fill_share=0.0, context_base=False,
               extra_share=0.0, fill_gaps=(10, 180), fill_law="log", rate=1, dna_share=0.0):
    """b windows of n frames; `extra_share` of them from cmu-extra's locomotion clips
    (segments named extra/...) where one is at least n frames long. rate > 1:
    every window is n frames taken `rate` apart from n * rate frames (what
    the hierarchy's coarse pass sees), keys as users give them, no fill layouts.
    dna_share of the windows that are not fill layouts get Motion DNA: their
    own representative frames (dna_frames); the batch then ends with their
    indices [B, k] and weights [B, k] (1 a frame, 0 padding)."""
    xs, gr_, gq_, br, bq, tr, tq, offs = [], [], [], [], [], [], [], []
    dna_idx = []
    extra = np.array([str(name).startswith("extra/") for name in clips.names])
    for _ in range(b):
        root, quat = clips.window(n * rate, rng, extra if rng.random() < extra_share else None)
        root, quat = root[::rate], quat[::rate]
        off = skel.offsets
        if do_mirror and rng.random() < 0.5:
            root, quat = mirror(root, quat, skel)
            off = skel.mirror_offsets
        root, quat = turn(root, quat, rng.uniform(-math.pi, math.pi))
        picked = []
        if rate == 1 and rng.random() < fill_share:
            keys = fill_keys(n, rng, fill_gaps, fill_law)
            kinds = [P] * len(keys)
        else:
            # half the windows with intervals of at least 0.5 s (a root path's keys)
            keys = sample_keys(n, rng, lo=30 if rng.random() < 0.5 else 15)
            kinds = sample_kinds(keys, rng)
            if dna_share and rng.random() < dna_share:
                picked = dna_frames(quat, keys)
        dna_idx.append(picked)
        noise = torch.from_numpy(rng.standard_normal(Z)).float()
        f = features(skel, prior, root, quat, keys, kinds, noise, off, context_base, rate)
        for lst, v in zip((xs, gr_, gq_, br, bq, tr, tq), f):
            lst.append(v)
        offs.append(off)
    out = [torch.stack(v).to(device) for v in (xs, gr_, gq_, br, bq, tr, tq, offs)]
    if dna_share:
        k = max(1, max(len(v) for v in dna_idx))
        idx = torch.zeros(b, k, dtype=torch.long)
        wts = torch.zeros(b, k)
        for i, v in enumerate(dna_idx):
            idx[i, :len(v)] = torch.tensor(v, dtype=torch.long)
            wts[i, :len(v)] = 1.0
        out += [idx.to(device), wts.to(device)]
    return out


def dna_weights(poses, frames, window):
    """The exported network's dna_w [poses, frames]: motion.dna.frame_weights
    with the manifest's dna_window, or (window 0) every pose on every frame,
    which the network averages into the one code training used."""
    if window == 0:
        return np.ones((poses, frames), np.float32)
    return dna_rule.frame_weights(poses, frames, window)


def window_dna(skel, f, quat, keys):
    """A window's own Motion DNA poses [k, J, 3] in BVH units (Λ of its
    dna_frames; the middle frame when none can be drawn), from features'
    output f (its truth root and rotations)."""
    idx = dna_frames(quat, keys) or [len(quat) // 2]
    gpos = fk(skel, f[5][None], f[6][None], skel.offsets[None])[0]
    return lam(gpos, f[6])[idx]


def dna_frames(quat, keys):
    """A window's Motion DNA frames as training draws them: motion.dna's
    representative frames (largest local-rotation change, 30 frames apart,
    one per 180 frames) among the frames that are not keys."""
    feat = quat_to_mat(quat[:, 1:]).reshape(len(quat), -1).numpy()
    return dna_rule.representative_frames(feat, dna_rule.dna_count(len(quat)), exclude=keys)


def lam(pos, rot):
    """The thesis' Lambda: joints relative to the root with the root's
    rotation removed. pos [..., J, 3], rot [..., K, 3, 3] -> [..., J, 3]."""
    return torch.einsum("...ji,...kj->...ki", rot[..., 0, :, :], pos - pos[..., :1, :])


def dna_losses(out_lam, reps, wts, x, longest=180):
    """Eqs. 5.11 and 5.12 (squared distances, mean over joints): every
    representative pose near some output frame; in every key interval of at
    least 3 s, floor(length / 3 s) output frames near one of them. out_lam
    [B, N, J, 3], reps [B, k, J, 3], wts [B, k]; x the input (its all-keys
    phase gives the intervals)."""
    d = ((out_lam[:, :, None] - reps[:, None]) ** 2).sum(-1).mean(-1)   # [B, N, k]
    has = wts.sum(1) > 0
    l1 = (d.min(1).values * wts).sum() / wts.sum().clamp(min=1.0)
    K = (x.shape[1] - 3 - 4 - extra_channels((out_lam.shape[2]))) // 6
    i = 3 + 6 * K + 5  # all keys' phase: s, since / PHASE_FRAMES, to / PHASE_FRAMES, gate
    span = ((x[:, i + 1] + x[:, i + 2]) * PHASE_FRAMES).round()   # in 60 fps frames
    near = d.masked_fill(wts[:, None] == 0, float("inf")).min(2).values   # [B, N]
    picked = []
    for b in torch.nonzero(has).flatten().tolist():
        long = span[b] >= longest
        if not bool(long.any()):
            continue
        # key frames: no frame since the previous key or none to the next (the last key)
        edges = torch.nonzero((x[b, i + 1] == 0) | (x[b, i + 2] == 0)).flatten().tolist()
        for a, e in zip(edges[:-1], edges[1:]):
            if e - a >= longest:
                m = (e - a) // longest
                picked.append(near[b, a + 1:e].topk(m, largest=False).values)
    l2 = torch.cat(picked).mean() if picked else out_lam.sum() * 0
    return l1, l2


def short_gap_l1(x, pos, gpos, K, longest=45, ref=30.0, cap=4.0):
    """Position L1 on the frames of key intervals of at most `longest`
    frames, each frame weighted by ref / (its interval's length), at most
    `cap`, over the weights' sum (issue 50); intervals between two
    whole-pose keys only (a root-only key says nothing of the pose). The supervised terms average
    over every frame, where long gaps' errors (which grow with the gap)
    outweigh short ones': in its own training layouts the gap-filling
    network added error to its base at 8-12-frame gaps (0.73 against 0.62
    units, train/notes/cond.md). x: the input [B, C, N] (the phase of all
    keys after the base, the pose keys' phase and flag), pos, gpos [B, N, J, 3]."""
    i = 3 + 6 * K  # group_phase of the whole-pose keys (s, since, to, gate), its flag, then all keys'
    span = (x[:, i + 1] + x[:, i + 2]) * PHASE_FRAMES
    span_all = (x[:, i + 6] + x[:, i + 7]) * PHASE_FRAMES
    # intervals between two whole-pose keys with no other key between them
    between = (span > 0) & (span <= longest) & ((span - span_all).abs() < 1e-3)
    m = (ref / span.clamp(min=1.0)).clamp(max=cap) * between
    err = (pos - gpos).abs().sum(-1).mean(-1)
    return (err * m).sum() / m.sum().clamp(min=1.0)


def losses(net, skel, batch, w, adv=None, tau=0.1):
    """The supervised terms (the whole-pose recipe's); with `adv`
    (residual_adv.Adversary) the LSGAN term on root-relative positions;
    with w["div"] a diversity-sensitive term (Mao et al. 2019, DSGAN): each
    window runs again with a second noise draw, and the mean distance
    between the two outputs' root-relative positions per unit of noise
    distance, capped at `tau`, is rewarded. The supervised terms see the
    first draw; the discriminator sees both. Private entries (leading _)
    carry the positions the discriminator's own step needs."""
    x, g_root, g_rot, base_root, base_rot, gt_root, gt_rot, offs = batch[:8]
    gpos = fk(skel, gt_root, gt_rot, offs) / SCALE
    dna = dna_w = reps = None
    if len(batch) > 8 and net.dna:
        # Motion DNA: the window's own representative poses (Lambda / SCALE)
        idx, dna_w = batch[8:]
        B, k = idx.shape
        J = gpos.shape[2]
        reps = torch.gather(lam(gpos, gt_rot), 1, idx[:, :, None, None].expand(-1, -1, J, 3))
        dna = reps.reshape(B, k, 3 * J)
    root, rot = apply(net, x, g_root, g_rot, base_root, base_rot, dna, dna_w)
    pos = fk(skel, root, rot, offs) / SCALE
    out = supervised(skel, root, rot, pos, gt_root, gt_rot, gpos, w)
    if w.get("short"):
        out["short"] = short_gap_l1(x, pos, gpos, rot.shape[2])
    if dna is not None and w.get("dna1"):
        out["dna1"], out["dna2"] = dna_losses(lam(pos, rot), reps, dna_w, x)
    rel = pos - pos[:, :, :1]
    fakes = [rel]
    if w.get("div"):
        B, _, N = x.shape
        z2 = torch.randn(B, Z, 1, device=x.device)
        x2 = x.clone()
        x2[:, -Z:] = z2.expand(-1, -1, N)
        root2, rot2 = apply(net, x2, g_root, g_rot, base_root, base_rot, dna, dna_w)
        pos2 = fk(skel, root2, rot2, offs) / SCALE
        rel2 = pos2 - pos2[:, :, :1]
        d_out = (rel - rel2).norm(dim=-1).mean((1, 2))
        d_z = (x[:, -Z:, 0] - z2[:, :, 0]).abs().mean(1).clamp(min=1e-3)
        out["div"] = -(d_out / d_z).clamp(max=tau).mean()
        out["_spread"] = d_out.mean().detach() * SCALE  # units, for the log
        fakes.append(rel2)
    private = {}
    if adv is not None:
        fake = torch.cat(fakes)
        out["gan"] = adv.g_loss(fake)
        private = {"_rel": fake.detach(), "_grel": (gpos - gpos[:, :, :1]).detach()}
    out["total"] = sum(w[k] * v for k, v in out.items() if w.get(k))
    return {**out, **private}


def train(args):
    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    rng = np.random.default_rng(args.seed)
    d = np.load(args.data)
    skel = Skeleton(d)
    clips = Clips(d, "train")
    J = len(skel.parents)
    dev = torch.device(args.device)
    ck = os.path.join(args.out, "ckpt.pt")
    os.makedirs(args.out, exist_ok=True)
    src = None
    if args.resume:
        src = ck if os.path.exists(ck) else args.portable if os.path.exists(args.portable) else None
        if src is None:
            raise SystemExit(f"--resume: neither {ck} nor {args.portable} exists (start with --init)")
    step, opt_state = 0, None
    if src:
        s = torch.load(src, map_location="cpu")
        net = build(s)
        net.load_state_dict({k: v.float() for k, v in s["net"].items()})
        ema = build(s)
        ema.load_state_dict({k: v.float() for k, v in s["ema"].items()})
        prior = s["prior"].float()
        step, opt_state = s["step"], s.get("opt")
        rng = np.random.default_rng(args.seed + step)
        print(f"resumed {src} at step {step}", flush=True)
    elif args.init:
        s = torch.load(args.init, map_location="cpu")
        a = arch(s)
        net = CondTween(a["K"], J, a["width"], a["dilations"], a["stride"], a["skip"])
        cin = net.core.inp.in_channels
        net.load_state_dict(widen(s["ema"], cin))
        ema = copy.deepcopy(net)
        prior = prior_pose(clips)
        print(f"started from {args.init} (whole-pose network, step {s['step']}; {cin - 3 - 6 * a['K'] - 4} "
              "new input channels at zero)", flush=True)
    else:
        raise SystemExit("train needs --init WHOLE_POSE_CHECKPOINT or --resume")
    if args.context_base >= 0:
        if bool(args.context_base) != net.context_base:
            print(f"the base over gaps with context: {'Hermite' if args.context_base else 'SLERP+LERP'} from now on",
                  flush=True)
        net.context_base = ema.context_base = bool(args.context_base)
    if args.coarse_every > 0 and not net.coarse_rates:
        print(f"coarse-rate windows from now on (rates {args.coarse_rates}): the manifest will say coarse_rates",
              flush=True)
        net.coarse_rates = ema.coarse_rates = True
    if args.extra_share > 0 and not any(str(name).startswith("extra/") for name in clips.names):
        raise SystemExit(f"--extra-share {args.extra_share}: {args.data} holds no cmu-extra clip (extra/...): "
                         "run `python -m deeprep_train.motion.extra`, then `python -m deeprep_train.motion.residual "
                         "prepare`")
    if args.dna_share > 0 and not net.dna:
        net.add_dna()
        ema.add_dna()
        ema.dna_enc.load_state_dict(net.dna_enc.state_dict())
        print("Motion DNA input from now on (its code at zero): the manifest will say dna", flush=True)
    net.to(dev)
    ema.to(dev)
    # the DNA encoder's parameters in a group of their own, so a checkpoint
    # from before it keeps its optimizer state
    base = [p for n, p in net.named_parameters() if not n.startswith("dna_")]
    extra = [p for n, p in net.named_parameters() if n.startswith("dna_")]
    opt = torch.optim.Adam(base, lr=args.lr)
    if extra and opt_state is not None and len(opt_state["param_groups"]) == 2:
        opt.add_param_group({"params": extra})
        opt.load_state_dict(opt_state)
    else:
        if opt_state is not None:
            opt.load_state_dict(opt_state)
        if extra:
            opt.add_param_group({"params": extra})
    for g in opt.param_groups:
        g["lr"] = args.lr
    print(f"parameters: {sum(p.numel() for p in net.parameters()):,}", flush=True)
    w = {"pos": 1.0, "rot": 0.5, "root": 1.0, "vel": 1.0, "speed": args.speed_weight, "foot": args.foot_weight,
         "l2p": args.l2p_weight, "spectral": args.spectral_weight, "gan": args.gan_weight, "div": args.div_weight,
         "npss": args.npss_weight, "short": args.short_gap_weight, "dna1": args.dna_weight, "dna2": args.dna_weight}
    adv = None
    if args.gan_weight > 0:
        from deeprep_train.motion.residual_adv import Adversary
        adv = Adversary(J, args.lr_d, dev)
        if src and adv.load(s):
            print("resumed the discriminator", flush=True)
        else:
            print("a new discriminator", flush=True)
    skel.inv_sd = torch.from_numpy(1.0 / spread(d, skel)).float().to(dev)
    log = open(os.path.join(args.out, "log.jsonl"), "a")
    t0, last, acc = time.time(), time.time(), {}

    def save():
        state = {"net": net.state_dict(), "ema": ema.state_dict(), "opt": opt.state_dict(), "step": step,
                 "prior": prior, **net.arch(), **(adv.state() if adv is not None else {})}
        torch.save(state, ck + ".tmp")
        os.replace(ck + ".tmp", ck)

    while time.time() - t0 < args.minutes * 60:
        # every short_every-th batch: shorter windows (cmu-extra's walks and runs are 67-299
        # frames long, never a whole 480-frame window), as many frames in all
        short = args.short_every > 0 and step % args.short_every == 0
        # every coarse_every-th batch (after the short ones): the hierarchy's coarse pass,
        # windows of coarse_frames frames each `rate` frames of the motion apart
        coarse = not short and args.coarse_every > 0 and step % args.coarse_every == 1 % args.coarse_every
        rate = int(rng.choice(args.coarse_rates)) if coarse else 1
        n = args.short_frames if short else args.coarse_frames if coarse else args.frames
        batch = make_batch(clips, skel, prior, max(1, args.batch * args.frames // n), n, rng, args.mirror, dev,
                           args.fill_share, net.context_base, args.extra_share if short else 0.0,
                           args.fill_gaps, args.fill_law, rate, args.dna_share)
        out = losses(net, skel, batch, w, adv, args.div_tau)
        opt.zero_grad()
        out["total"].backward()
        if adv is not None:
            out["D"] = torch.tensor(adv.d_step(out.pop("_grel"), out.pop("_rel")))
        torch.nn.utils.clip_grad_norm_(net.parameters(), 1.0)
        opt.step()
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
                torch.save({"ema": ema.state_dict(), "step": step, "prior": prior, **net.arch()},
                           os.path.join(args.out, f"gen_{step}.pt"))
    save()
    print(f"done at step {step}", flush=True)


# ---------------------------------------------------------------- evaluation

def evaluate(args):
    """Keys of one kind (--kind) at frames s, s+g, s+2g of every segment
    (windows of 2g+1 frames stepping by 2g, as residual.evaluate): MPJPE,
    NPSS on root-relative positions, joint speed relative to the root as a
    share of the truth's, the root-relative position error at the key
    frames, and foot skating (mean horizontal speed of a foot or toe within 5
    units of the window's floor, per frame) against the truth's."""
    torch.set_num_threads(args.threads)
    d = np.load(args.data)
    skel = Skeleton(d)
    clips = Clips(d, args.split)
    net, s = load_ema(args.ckpt)
    prior = s["prior"].float()
    kind = KIND_NAMES[args.kind]
    noise = torch.zeros(Z)
    res = {}
    for g in args.gaps:
        n = 2 * g + 1
        keys = [0, g, 2 * g]
        mid = [t for t in range(n) if t not in keys]
        acc = {"mpjpe": [], "key_err": [], "speed": [], "gt_speed": [], "skate": [], "gt_skate": [], "pred": [],
               "gt": [], "spread": [], "seeded": []}
        gen = torch.Generator().manual_seed(1234 + g)
        for si in range(len(clips.lens)):
            a0 = int(clips.starts[si])
            for s0 in range(0, int(clips.lens[si]) - n + 1, 2 * g):
                root = clips.root[a0 + s0:a0 + s0 + n]
                quat = clips.quat[a0 + s0:a0 + s0 + n]
                f = features(skel, prior, root, quat, keys, [kind] * 3, noise, skel.offsets, net.context_base)
                x, g_root, g_rot, base_root, base_rot, gt_root, gt_rot = [v.unsqueeze(0) for v in f]
                offs = skel.offsets.unsqueeze(0)
                with torch.no_grad():
                    # --variation scales the residual (0: the base; with pose keys SLERP+LERP)
                    r, q = apply(net, x, g_root * args.variation, g_rot * args.variation, base_root, base_rot)
                pos = fk(skel, r, q, offs)[0]
                gpos = fk(skel, gt_root, gt_rot, offs)[0]
                rel, grel = pos - pos[:, :1], gpos - gpos[:, :1]
                acc["mpjpe"].append(float((pos - gpos)[mid].norm(dim=-1).mean()))
                acc["key_err"].append(float((rel - grel)[keys].norm(dim=-1).mean()))
                acc["speed"].append(float(rel.diff(dim=0).norm(dim=-1).mean()))
                acc["gt_speed"].append(float(grel.diff(dim=0).norm(dim=-1).mean()))
                for p_, k_ in ((pos, "skate"), (gpos, "gt_skate")):
                    fp = p_[:, skel.feet]
                    low = fp[1:, :, 1] < fp[..., 1].min() + 5
                    v = fp.diff(dim=0)[..., [0, 2]].norm(dim=-1)
                    acc[k_].append(float((v * low).sum() / max(1, int(low.sum()))))
                acc["pred"].append(rel[mid].reshape(len(mid), -1).numpy())
                acc["gt"].append(grel[mid].reshape(len(mid), -1).numpy())
                if args.seeds > 1:
                    # the same keys with `seeds` noise draws: mean distance between
                    # each pair's global joint positions between the keys
                    outs = []
                    for _ in range(args.seeds):
                        z = torch.randn(Z, generator=gen)
                        xz = x.clone()
                        xz[:, -Z:] = z[None, :, None]
                        with torch.no_grad():
                            r2, q2 = apply(net, xz, g_root, g_rot, base_root, base_rot)
                        outs.append(fk(skel, r2, q2, offs)[0])
                    d = [float((outs[i] - outs[j])[mid].norm(dim=-1).mean())
                         for i in range(len(outs)) for j in range(i + 1, len(outs))]
                    acc["spread"].append(float(np.mean(d)))
                    acc["seeded"].append((outs[0] - outs[0][:, :1])[mid].reshape(len(mid), -1).numpy())
        row = {"windows": len(acc["mpjpe"]), "mpjpe": float(np.mean(acc["mpjpe"])),
               "key_err": float(np.mean(acc["key_err"])),
               "speed_ratio": float(np.mean(acc["speed"]) / np.mean(acc["gt_speed"])),
               "skate_ratio": float(np.mean(acc["skate"]) / max(1e-9, np.mean(acc["gt_skate"]))),
               "npss": npss(np.stack(acc["gt"]), np.stack(acc["pred"]))}
        if args.seeds > 1:
            row["seed_spread"] = float(np.mean(acc["spread"]))
            row["npss_seeded"] = npss(np.stack(acc["gt"]), np.stack(acc["seeded"]))
        res[g] = row
        print(args.kind, g, json.dumps(row), flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"split": args.split, "kind": args.kind, "ckpt": args.ckpt, "step": int(s["step"]),
                       "gaps": res}, fh, indent=1)
    return res


def portable(args):
    """The running checkpoint's weights and moving average in float16 (with
    the prior pose), to train/checkpoints/tween_cond.pt (or --to)."""
    s = torch.load(args.ckpt or os.path.join(args.out, "ckpt.pt"), map_location="cpu")
    half = {k: {n: v.half() for n, v in s[k].items()} for k in ("net", "ema")}
    to = args.to or PORTABLE
    os.makedirs(os.path.dirname(os.path.abspath(to)), exist_ok=True)
    torch.save({**half, "step": s["step"], "prior": s["prior"], **arch(s), "J": s["J"], "Z": s["Z"],
                "context_base": int(s.get("context_base", 0)), "coarse_rates": int(s.get("coarse_rates", 0)),
                "dna": int(s.get("dna", 0))}, to)
    print(f"wrote {to} (step {s['step']}, {os.path.getsize(to) / 1e6:.1f} MB)")


def recover(args):
    """The bundled network (models/onnx/tween_cond.onnx: float16 weights, the
    moving average of the step its manifest names) back as a snapshot that
    `eval --ckpt` and `export --ckpt` read (--to, default
    cache/cond/gen_<step>_onnx.pt), checked against its parity fixture: the
    rule of train/notes/cond.md compares new snapshots with it, also on a
    machine that never held cache/cond."""
    import onnx
    import onnxruntime as ort
    from deeprep_train.export.util import ONNX_DIR, initializer_arrays
    man = json.load(open(os.path.join(ONNX_DIR, "tween_cond.manifest.json")))
    t = man["training"]
    s = {"width": t["width"], "K": t["K"], "dilations": t["dilations"], "stride": t["stride"], "skip": t["skip"],
         "J": t["J"], "Z": t["Z"], "context_base": int(man.get("context_base") == "hermite"),
         "coarse_rates": int(bool(man.get("coarse_rates", False))), "dna": int(bool(man.get("dna", False)))}
    net = build(s)
    arrays = initializer_arrays(onnx.load(os.path.join(ONNX_DIR, "tween_cond.onnx")))
    state = {k: torch.from_numpy(np.array(arrays[k], dtype=np.float32)) for k in net.state_dict()}
    net.load_state_dict(state)
    fix = json.load(open(os.path.join(ONNX_DIR, "fixtures", "tween_cond.json")))
    feeds = {k: np.array(v["data"], dtype=np.float32).reshape(v["shape"]) for k, v in fix["inputs"].items()}
    order = fix.get("input_order", list(feeds))
    with torch.no_grad():
        mine = net(*[torch.from_numpy(feeds[k]) for k in order]).numpy()
    want = ort.InferenceSession(os.path.join(ONNX_DIR, "tween_cond.onnx"),
                                providers=["CPUExecutionProvider"]).run(None, feeds)[0]
    # relative to the output's size (float32 sums in another order: about 1e-5)
    off = float(np.abs(mine - want).max() / np.abs(want).max())
    if off > 1e-4:
        raise SystemExit(f"recover: the rebuilt network is {off} (relative) from onnxruntime's output")
    from deeprep_train.bvh import mat_to_quat
    prior_m = np.array(man["prior"], dtype=np.float64).reshape(-1, 3, 3)
    prior = torch.from_numpy(mat_to_quat(prior_m)).float()   # [K, 4], w first, as prior_pose gives
    if float(np.abs(quat_to_mat(prior).double().numpy() - prior_m).max()) > 1e-4:
        raise SystemExit("recover: the manifest's prior pose is not a set of rotations")
    to = args.to or os.path.join(OUT, f"gen_{t['steps']}_onnx.pt")
    os.makedirs(os.path.dirname(os.path.abspath(to)), exist_ok=True)
    torch.save({"ema": net.state_dict(), "step": t["steps"], "prior": prior, **net.arch()}, to)
    print(f"wrote {to} (step {t['steps']}; within {off:.1e} of onnxruntime's output on the fixture, relative)")


# ---------------------------------------------------------------- export

FIXTURE_CASES = [
    # (frames, keys, kinds): the first key a whole pose (heading removed);
    # a root path (heading kept); 2-D keys with a pose; a window whose frames
    # run past its first and last key
    (41, [0, 20, 40], [P, R, P]),
    (41, [0, 17, 40], [R, R, R]),
    (41, [0, 25, 40], [X, P, R]),
    (47, [4, 22, 40], [R, X, R]),
    # a gap with context (issue 50): three whole poses before it, one after;
    # motion::fill's Hermite base where the manifest's context_base says so
    (41, [0, 1, 2, 30, 31, 40], [P, P, P, P, R, P]),
    # the hierarchy's coarse pass: 41 frames, each 3 frames of the motion apart
    # (the phase in 60 fps frames, group_phase's rate)
    (41, [0, 20, 40], [R, P, X], 3),
]
# a network with DNA input: root-only keys over 500 frames, DNA the window's own poses
DNA_FIXTURE_CASE = (500, [0, 250, 499], [R, R, R])


def captured_speed(skel, clips):
    """The training takes' mean joint speed relative to the root (units per
    frame at 60 fps, every joint but the root, windows of 300 frames every
    300): what a page test compares a synthesized motion's limbs with."""
    tot, n = 0.0, 0
    for s0, ln in zip(clips.starts, clips.lens):
        for a in range(int(s0), int(s0 + ln) - 300, 300):
            with torch.no_grad():
                pos = fk(skel, clips.root[None, a:a + 300], quat_to_mat(clips.quat[None, a:a + 300]),
                         skel.offsets[None])[0]
            rel = pos[:, 1:] - pos[:, :1]
            tot += float(rel.diff(dim=0).norm(dim=-1).sum())
            n += rel.shape[1] * 299
    return {"value": tot / n, "what": "the training takes' mean joint speed relative to the root, units per frame "
                                      "at 60 fps (motion/cond.py captured_speed)"}


def export(args):
    """models/onnx/NAME.onnx (--name, default tween_cond; the moving average
    of --ckpt), its manifest and the network's parity fixture, and for
    tween_cond the motion fixture. A gap-filling network (--name tween_fill)
    carries --fill-from and --fill-up-to in its manifest: the shortest and
    longest gap the `model` fill gives it (motion::fill::method_for)."""
    import onnxruntime as ort
    from deeprep_train.motion.export import fixture
    from deeprep_train.export.util import ONNX_DIR, git_commit, write_json
    from deeprep_train.export.half_weights import convert
    net, s = load_ema(args.ckpt)
    prior = s["prior"].float()
    d = np.load(args.data)
    skel = Skeleton(d)
    J, K = len(skel.parents), skel.K
    cin = net.core.inp.in_channels
    clips = Clips(d, "train")
    gen_manifest = json.load(open(os.path.join(ONNX_DIR, "tween_generator.manifest.json")))
    name = args.name
    out_dir = args.out_dir or ONNX_DIR
    path = os.path.join(out_dir, f"{name}.onnx")
    noise = torch.zeros(Z)

    def window(case_index, n, rate=1):
        a = 200 + 300 * case_index
        return clips.root[a:a + n * rate:rate], clips.quat[a:a + n * rate:rate]

    n0, keys0, kinds0 = FIXTURE_CASES[2][:3]
    f = features(skel, prior, *window(2, n0), keys0, kinds0, noise, skel.offsets, net.context_base)
    x = f[0].unsqueeze(0)
    if net.dna:
        # the fixture's DNA: the window's own representative poses
        poses = window_dna(skel, f, window(2, n0)[1], keys0)
        dna = (poses / SCALE).reshape(1, len(poses), -1)
        # which poses each frame pools (motion.dna.frame_weights; --dna-window 0: every pose, every frame)
        dna_w = torch.from_numpy(dna_weights(len(poses), n0, args.dna_window))[None]
        feeds = {"x": x, "dna": dna, "dna_w": dna_w}
        axes = {"x": {2: "frames"}, "dna": {1: "poses"}, "dna_w": {1: "poses", 2: "frames"},
                "residual": {2: "frames"}}
    else:
        feeds, axes = {"x": x}, {"x": {2: "frames"}, "residual": {2: "frames"}}
    torch.onnx.export(net, tuple(feeds.values()), path, input_names=list(feeds), output_names=["residual"],
                      opset_version=17, dynamic_axes=axes, dynamo=False)
    with torch.no_grad():
        ref = net(*feeds.values()).numpy()
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    parity = fixture(name, sess, {k: v.numpy() for k, v in feeds.items()}, ref, out_dir)
    prior_m = quat_to_mat(prior)
    fill = fill_band(args)
    write_json(os.path.join(out_dir, f"{name}.manifest.json"), {
        "name": name,
        "kind": "cond-tween",
        "description": ("the conditional network fine-tuned on gaps in captured motion, whole-pose keys around "
                        f"gaps (train/deeprep_train/motion/cond.py; issue 50): the `model` fill's network for gaps "
                        f"of {args.fill_from or 1}-{args.fill_up_to} frames" if fill else
                        "one conditional in-betweening network for whole-pose, root-only and 2-D keys "
                        "(train/deeprep_train/motion/cond.py; issue 47)"),
        "inputs": [{"name": "x", "shape": [1, cin, "frames"],
                    "channels": "base root / scale (3), base 6D per rotating joint (6K), whole-pose keys' phase (4: "
                                "s, since / 60, to / 60, gate), whole-pose flag (1), all keys' phase (4), 2-D-or-pose "
                                "flag (1), their phase (4), each joint's root-relative x, y / scale lerped between them "
                                "(2J), noise (Z, zero at inference); in the first key's frame (motion/cond.py's "
                                "docstring)"}] + ([
                       {"name": "dna", "shape": [1, "poses", 3 * J],
                        "channels": "Motion DNA poses: each joint relative to the root, the root's rotation removed, "
                                    "/ scale (a zero pose when none is given)"},
                       {"name": "dna_w", "shape": [1, "poses", "frames"],
                        "channels": "how much each DNA pose steers each frame (motion::dna::frame_weights with "
                                    "dna_window, or 1 everywhere for dna_window 0; all 0 when no pose is given)"}]
                       if net.dna else []),
        "outputs": [{"name": "residual", "shape": [1, 3 + 6 * K, "frames"]}],
        "scale": SCALE,
        "gate_frames": GATE_FRAMES,
        "phase_frames": PHASE_FRAMES,
        "noise_channels": Z,
        "joints": J,
        "rotating": skel.rotating,
        "prior": [[float(v) for v in m.reshape(-1)] for m in prior_m],
        "skeleton_bvh": gen_manifest["skeleton_bvh"],
        "training": {"steps": int(s["step"]), **net.arch(), "checkpoint": os.path.relpath(args.ckpt, ROOT)},
        "parity_torch_vs_onnxruntime": parity,
        "training_data": "CMU train takes at 60 fps with cmu-extra's locomotion clips retargeted onto the model's "
                         "skeleton (train/deeprep_train/motion/extra.py), mirrored and turned",
        "training_code_commit": git_commit(),
        "exporter": {"torch": torch.__version__, "onnxruntime": ort.__version__, "opset": 17},
        "default_for_partial_keys": bool(args.default_for_partial_keys),
        "default_for_long_gaps": bool(args.default_for_long_gaps),
        "default_for_root_keys": bool(args.default_for_root_keys),
        "default_for_dna": bool(args.default_for_dna),
        "context_base": "hermite" if net.context_base else "slerp",
        "coarse_rates": net.coarse_rates,
        "dna": net.dna,
        **({"dna_window": args.dna_window} if net.dna else {}),
        "captured_joint_speed": captured_speed(skel, clips),
        **fill,
    })
    convert(name, out_dir)
    if name != "tween_cond":
        print(f"exported {path} (step {s['step']}), parity {parity:.2e}")
        return
    # the motion fixture, from the float16 file as shipped
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    cases = []
    # a network with DNA input: one more case, root-only keys over 500 frames with the window's own
    # representative poses as DNA, long enough that frames pool different poses (frame_weights)
    all_cases = FIXTURE_CASES + ([DNA_FIXTURE_CASE] if net.dna else [])
    for ci, (n, keys, kinds, *rate) in enumerate(all_cases):
        if args.dna_case_only and ci < len(FIXTURE_CASES):
            continue
        rate = rate[0] if rate else 1
        root, quat = window(ci, n, rate)
        f = features(skel, prior, root, quat, keys, kinds, noise, skel.offsets, net.context_base, rate)
        xin, g_root, g_rot, base_root, base_rot = [v.unsqueeze(0) for v in f[:5]]
        feeds = {"x": xin.numpy()}
        dna_rows, every = None, 1
        if net.dna and ci == len(FIXTURE_CASES):
            poses = window_dna(skel, f, quat, keys)   # BVH units; the runtime divides by the scale
            dna_rows = [[float(v) for v in p.reshape(-1)] for p in poses]
            feeds.update(dna=(poses / SCALE).reshape(1, len(poses), -1).numpy(),
                         dna_w=dna_weights(len(poses), n, args.dna_window)[None])
            every = 25
        elif net.dna:
            # without DNA: one zero pose at weight 0 on every frame (what the runtime feeds)
            feeds.update(dna=np.zeros((1, 1, 3 * J), np.float32), dna_w=np.zeros((1, 1, n), np.float32))
        res = torch.from_numpy(sess.run(None, feeds)[0])
        # apply() with the exported network's output, then back to the world
        B, N = 1, n
        r_root = base_root + res.transpose(1, 2)[..., :3] * SCALE * g_root.unsqueeze(-1)
        r6 = sixd(base_rot).reshape(B, N, K, 6) + res.transpose(1, 2)[..., 3:].reshape(B, N, K, 6) *             g_rot[..., None, None]
        rot = from_sixd(r6)[0]
        C, off = canonical_frame(root, quat, keys, kinds)
        w_root = r_root[0] @ C + off
        rot[:, 0] = C.T @ rot[:, 0]
        gpos = fk(skel, root[None], quat_to_mat(quat)[None], skel.offsets[None])[0]
        key_rows = []
        for k, c in zip(keys, kinds):
            rel = gpos[k] - gpos[k, :1]
            key_rows.append({"frame": k, "kind": ["pose", "root", "xy"][c],
                             "root": [float(v) for v in root[k]],
                             "positions": [float(v) for v in rel.reshape(-1)],
                             "rotations": [[float(v) for v in m.reshape(-1)] for m in quat_to_mat(quat[k])]})
        case = {"frames": n, "rate": rate, "keys": key_rows,
                "root": [[round(float(v), 5) for v in r] for r in w_root[::every]],
                "sixd": [[round(float(v), 6) for v in sixd(m).reshape(-1)] for m in rot[::every]]}
        if dna_rows is not None:
            # root and sixd of every `every`-th frame only (the fixture's size)
            case.update(dna=dna_rows, every=every)
        cases.append(case)
    os.makedirs(os.path.join(out_dir, "fixtures", "runtime"), exist_ok=True)
    write_json(os.path.join(out_dir, "fixtures", "runtime", "tween_cond_motion.json"), {
        "model": "tween_cond.onnx",
        "about": "keys (root: global; positions: joint positions relative to the root, world axes, every joint; "
                 "rotations: local rotation matrices of the rotating joints, row-major) and the motion "
                 "motion/cond.py makes from them with tween_cond.onnx (onnxruntime): root positions and the "
                 "rotating joints' 6D (first two columns of each matrix); a case with `dna` (poses: joints relative "
                 "to the root, the root's rotation removed, BVH units) gives every `every`-th frame",
        "cases": cases})
    print(f"exported {path} (step {s['step']}), parity {parity:.2e}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cmd", choices=["train", "eval", "portable", "export", "recover"])
    ap.add_argument("--data", default=os.path.join(CACHE, "resid60.npz"))
    ap.add_argument("--out", default=OUT)
    ap.add_argument("--init", help="train: the whole-pose checkpoint this network starts from")
    ap.add_argument("--resume", action="store_true")
    ap.add_argument("--portable", default=PORTABLE)
    ap.add_argument("--to")
    ap.add_argument("--minutes", type=float, default=60)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--device", default="cpu")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--batch", type=int, default=8)
    ap.add_argument("--frames", type=int, default=480)
    ap.add_argument("--lr", type=float, default=2e-4)
    ap.add_argument("--ema", type=float, default=0.999)
    ap.add_argument("--mirror", type=int, default=1)
    ap.add_argument("--speed-weight", type=float, default=15.0)
    ap.add_argument("--foot-weight", type=float, default=2.0)
    ap.add_argument("--l2p-weight", type=float, default=1.0)
    ap.add_argument("--spectral-weight", type=float, default=5.0)
    ap.add_argument("--short-gap-weight", type=float, default=0.0,
                    help="train: weight of short_gap_l1 (position L1 on intervals of at most 45 frames, "
                         "short ones weighted up)")
    ap.add_argument("--npss-weight", type=float, default=0.0,
                    help="train: weight of the NPSS term (residual.npss_loss on each window's root-relative positions)")
    ap.add_argument("--dna-share", type=float, default=0.0,
                    help="train: share of windows (not fill layouts) given their own representative poses as "
                         "Motion DNA (adds the DNA input to a network without it)")
    ap.add_argument("--dna-weight", type=float, default=0.0,
                    help="train: weight of each DNA loss (eqs. 5.11, 5.12) on those windows")
    ap.add_argument("--gan-weight", type=float, default=0.0,
                    help="the adversarial stage: LSGAN discriminator on root-relative positions (residual_adv)")
    ap.add_argument("--lr-d", type=float, default=1e-4)
    ap.add_argument("--div-weight", type=float, default=0.0,
                    help="diversity-sensitive term: two noise draws per window kept apart (issue 47, item 2)")
    ap.add_argument("--div-tau", type=float, default=0.1,
                    help="cap on the rewarded output distance per unit of noise distance (positions / SCALE)")
    ap.add_argument("--context-base", type=int, default=-1,
                    help="1: over gaps with a whole-pose context frame, motion::fill's context-tangent Hermite curve "
                         "as the base (0: SLERP+LERP; default: the checkpoint's)")
    ap.add_argument("--name", default="tween_cond",
                    help="export: the file name under models/onnx (tween_fill: the gap-filling network)")
    add_fill_args(ap, "tween_fill")
    ap.add_argument("--short-every", type=int, default=0,
                    help="every K-th batch of --short-frames windows (0: never), as many frames in all")
    ap.add_argument("--short-frames", type=int, default=150)
    ap.add_argument("--extra-share", type=float, default=0.0,
                    help="share of a short batch's windows from cmu-extra's locomotion clips")
    ap.add_argument("--coarse-every", type=int, default=0,
                    help="every K-th batch (0: never) of windows at the hierarchy's coarse rates (issue 47 item 3)")
    ap.add_argument("--coarse-rates", type=lambda v: [int(x) for x in v.split(",")], default=[2, 3, 4, 5],
                    help="the rates (60 fps frames per window frame) --coarse-every's windows are drawn at")
    ap.add_argument("--coarse-frames", type=int, default=300,
                    help="frames of a coarse window (the coarse pass' longest gap is 300)")
    ap.add_argument("--save-every", type=int, default=250)
    ap.add_argument("--snapshot-every", type=int, default=1000)
    ap.add_argument("--split", default="train")
    ap.add_argument("--kind", choices=sorted(KIND_NAMES), default="root")
    ap.add_argument("--ckpt")
    ap.add_argument("--gaps", type=lambda s: [int(x) for x in s.split(",")], default=[60, 120, 300])
    ap.add_argument("--json")
    ap.add_argument("--variation", type=float, default=1.0,
                    help="eval: share of the residual kept (0: the base, SLERP+LERP for whole-pose keys)")
    ap.add_argument("--seeds", type=int, default=0,
                    help="eval: also run each window with this many noise draws: their mean pairwise distance "
                         "(seed_spread, units) and the first draw's NPSS (npss_seeded)")
    ap.add_argument("--out-dir", help="export: where the model, manifest and fixtures go (default models/onnx)")
    ap.add_argument("--dna-case-only", action="store_true",
                    help="export: the motion fixture's DNA case only (a test network's fixture)")
    ap.add_argument("--dna-window", type=int, default=dna_rule.DNA_WINDOW,
                    help="export: each DNA pose steers the frames within this many frames of its place "
                         "(motion.dna.frame_weights); 0: every pose every frame (one code, the thesis' form)")
    ap.add_argument("--default-for-long-gaps", type=int, default=0,
                    help="export: 1 makes the manifest name this network the `model` method's for whole-pose keys "
                         "with a gap over 600 frames (its hierarchy; motion::plan)")
    ap.add_argument("--default-for-root-keys", type=int, default=0,
                    help="export: 1 makes it the `model` method's network for root positions, alone or with whole "
                         "poses (manifest default_for_root_keys; motion::plan)")
    ap.add_argument("--default-for-dna", type=int, default=0,
                    help="export: 1 makes the `model` method send requests with Motion DNA to this network "
                         "(export it --name tween_cond_dna, the DNA network; manifest default_for_dna; motion::plan)")
    ap.add_argument("--default-for-partial-keys", type=int, default=0,
                    help="export: 1 makes the manifest name this network the `model` method's for root-only and "
                         "2-D keys (only after it beat the generator by the rule in train/notes/cond.md)")
    args = ap.parse_args(argv)
    {"train": train, "eval": evaluate, "portable": portable, "export": export, "recover": recover}[args.cmd](args)


if __name__ == "__main__":
    main()
