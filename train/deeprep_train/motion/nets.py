"""Generative Tweening networks (thesis Sec. 5.2), at reduced width for CPU training.

Layouts are [batch, channels, frames]. Positions are divided by SCALE before
entering any network. See train/README.md for every deviation from the thesis.
"""
import math

import torch
import torch.nn as nn
import torch.nn.functional as F

SCALE = 100.0          # BVH units per network unit
DT_NORM = 60.0         # distance transform in seconds (frames / 60) ...
DT_CLIP = 600.0        # ... clipped at 10 s
GAN_TARGET = 0.2361    # eq. 5.8
VCLIP = 3.0            # |v| bound when key rotations are mapped back through tanh


def rc_to_raw(rc, lo, hi):
    """Range-constrained targets [..., 3 + 6 + 3K] (root position, root 6D, angles)
    -> the generator's raw space [..., 6 + 3K]: root 6D, then v = atanh of each
    angle's position in its range (|v| <= VCLIP; 0 for zero-width ranges).
    Mirrors RcSkeleton::raw_from_rotations in crate/src/rcfk.rs."""
    u = rc[..., 9:].reshape(*rc.shape[:-1], -1, 3)
    span = hi - lo
    s = torch.where(span > 0, 2 * (u - lo) / span.clamp(min=1e-9) - 1, torch.zeros_like(u))
    v = torch.atanh(s.clamp(-math.tanh(VCLIP), math.tanh(VCLIP)))
    return torch.cat([rc[..., 3:9], v.reshape(*rc.shape[:-1], -1)], -1)


class ModResConv(nn.Module):
    """The modified residual convolution of eq. 5.6:
    x' = conv(x); residual = PReLU(affine(x')) + sqrt(1-s) x; y = sqrt(s) residual + sqrt(1-s) x."""

    def __init__(self, ch: int, sigma: float, k: int = 3):
        super().__init__()
        self.conv = nn.Conv1d(ch, ch, k, padding=k // 2)
        self.scale = nn.Parameter(torch.ones(1, ch, 1))
        self.bias = nn.Parameter(torch.zeros(1, ch, 1))
        self.act = nn.PReLU(ch)
        self.s = sigma
        self.last = None  # x' kept for the batch regularization loss (eq. 5.9)

    def forward(self, x):
        xp = self.conv(x)
        self.last = xp
        res = self.act(xp * self.scale + self.bias) + math.sqrt(1 - self.s) * x
        return math.sqrt(self.s) * res + math.sqrt(1 - self.s) * x


def down(cin, cout):
    return nn.Sequential(nn.Conv1d(cin, cout, 4, stride=2, padding=1), nn.PReLU(cout))


def up(cin, cout):
    return nn.Sequential(nn.ConvTranspose1d(cin, cout, 4, stride=2, padding=1), nn.PReLU(cout))


class DnaEncoder(nn.Module):
    """Shared MLP over representative frames, average pooling, a linear layer (Sec. 5.2.5)."""

    def __init__(self, pose_dim: int, hidden: int, out: int):
        super().__init__()
        self.mlp = nn.Sequential(nn.Linear(pose_dim, hidden), nn.PReLU(), nn.Linear(hidden, hidden), nn.PReLU())
        self.lin = nn.Linear(hidden, out)

    def forward(self, frames):  # [B, K, pose_dim]
        return self.lin(self.mlp(frames).mean(dim=1))


class Generator(nn.Module):
    """Dense keyframe input [B, 2P, N], dense key rotations [B, 2R, N] (R = out_dim,
    in the raw RC-FK space) and DNA frames [B, K, P] -> raw RC-FK values [B, R, N].
    The value half of dense_rot holds the keys' raw values linearly interpolated
    between keys (interp_channels); the output is that plus a learned correction.
    Encoder: an input conv and 6 stride-2 convs with modified residual convs;
    decoder: 6 transposed convs with modified residual convs, then an output conv."""

    def __init__(self, pose_dim: int, out_dim: int, widths=(96, 128, 160, 192, 224, 256), dna_dim: int = 64,
                 gate_tau: float | None = None, skips: int = 0):
        super().__init__()
        w0 = widths[0]
        # Key gate (not in the thesis, run 13): the correction is scaled by
        # 1 - exp(-(d / tau)^2), d the distance to the nearest whole-pose key
        # in seconds (dense_rot's first distance channel), tau learned. The
        # bottleneck is 64 frames coarse, so near keys and in short gaps the
        # correction cannot be placed precisely and made the output worse
        # than its own base (train/README.md, runs 9-11).
        self.log_tau = nn.Parameter(torch.tensor(math.log(gate_tau))) if gate_tau else None
        self.out_dim = out_dim
        self.inp = nn.Sequential(nn.Conv1d(2 * pose_dim + 2 * out_dim, w0, 3, padding=1), nn.PReLU(w0))
        enc, cin = [], w0
        sig_e = [0.5] * 6
        for i, w in enumerate(widths):
            enc += [down(cin, w), ModResConv(w, sig_e[i])]
            cin = w
        self.enc = nn.Sequential(*enc)
        self.dna = DnaEncoder(pose_dim, 128, dna_dim)
        dec = []
        cin = widths[-1] + dna_dim
        outs = list(widths[::-1][1:]) + [w0]
        sig_d = [0.5, 0.45, 0.4, 0.3, 0.2, 0.1]  # decreasing residual ratio towards the output
        for i, w in enumerate(outs):
            dec += [up(cin, w), ModResConv(w, sig_d[i])]
            cin = w
        self.dec = nn.Sequential(*dec)
        # U-Net skips (not in the thesis, run 16): the input conv's and the
        # first encoder blocks' features are added, through zero-initialized
        # 1x1 convs, to the decoder's last `skips` levels (same resolution,
        # before their residual convs), so corrections can be placed at
        # 1, 2, 4... frame precision. Zero init: a generator without skips
        # continues unchanged.
        enc_ch = [w0] + list(widths[:-1])
        self.skip = nn.ModuleList()
        for i in range(skips):
            c = nn.Conv1d(enc_ch[i], outs[len(outs) - 1 - i], 1)
            nn.init.zeros_(c.weight)
            nn.init.zeros_(c.bias)
            self.skip.append(c)
        self.out = nn.Conv1d(cin, out_dim, 3, padding=1)
        nn.init.zeros_(self.out.bias)
        self.out.weight.data *= 0.1

    def forward(self, dense, dense_rot, dna_frames):
        z = self.inp(torch.cat([dense, dense_rot], dim=1))
        feats = [z]
        for i in range(0, len(self.enc), 2):
            z = self.enc[i + 1](self.enc[i](z))
            feats.append(z)
        w = self.dna(dna_frames)
        z = torch.cat([z, w.unsqueeze(-1).expand(-1, -1, z.shape[-1])], dim=1)
        levels = len(self.dec) // 2
        for i in range(levels):
            z = self.dec[2 * i](z)
            k = levels - 1 - i  # this level's resolution is the input conv's / 2^k
            if k < len(self.skip):
                z = z + self.skip[k](feats[k])
            z = self.dec[2 * i + 1](z)
        corr = self.out(z)
        if self.log_tau is not None:
            d = dense_rot[:, self.out_dim: self.out_dim + 1]
            corr = corr * (1 - torch.exp(-(d / torch.exp(self.log_tau)) ** 2))
        return dense_rot[:, : self.out_dim] + corr

    def resconvs(self):
        return [m for m in self.modules() if isinstance(m, ModResConv)]


class Discriminator(nn.Module):
    """Local motion [B, P, N] -> N/64 scores: 6 downsampling convs and 1 at the same resolution."""

    def __init__(self, pose_dim: int, widths=(64, 96, 128, 128, 160, 160)):
        super().__init__()
        layers, cin = [], pose_dim
        for w in widths:
            layers += [nn.Conv1d(cin, w, 4, stride=2, padding=1), nn.LeakyReLU(0.2)]
            cin = w
        self.body = nn.Sequential(*layers)
        self.head = nn.Conv1d(cin, 1, 3, padding=1)

    def forward(self, x):
        return self.head(self.body(x)).squeeze(1)


class PathPredictor(nn.Module):
    """Local joint positions [B, P, N] -> root velocity [B, 3, N] (Sec. 5.2.4), fully convolutional.
    Kernel-5 convolutions whose dilations cycle through `dilations`; the
    receptive field is 1 + 4 * sum of the layers' dilations, plus 2 for the head."""

    def __init__(self, pose_dim: int, width: int = 128, layers: int = 6, dilations=(1, 2, 3)):
        super().__init__()
        mods, cin = [], pose_dim
        for i in range(layers):
            d = dilations[i % len(dilations)]
            mods += [nn.Conv1d(cin, width, 5, padding=2 * d, dilation=d), nn.PReLU(width)]
            cin = width
        self.body = nn.Sequential(*mods)
        self.head = nn.Conv1d(cin, 3, 3, padding=1)

    def forward(self, local):
        return self.head(self.body(local))


def path_loss(vel_pred, vel_true):
    """Eq. 5.5: mean displacement error over n-frame intervals, n = 1, 2, 4, ..., 128. [B, 3, N]."""
    cp = torch.cumsum(vel_pred, dim=-1)
    ct = torch.cumsum(vel_true, dim=-1)
    total, count = 0.0, 0
    for k in range(8):
        n = 2 ** k
        if n >= vel_pred.shape[-1]:
            break
        dp = cp[..., n:] - cp[..., :-n]
        dt = ct[..., n:] - ct[..., :-n]
        total = total + (dp - dt).norm(dim=1).mean()
        count += 1
    return total / count


def dense_input(pose, mask, n_frames):
    """The dense keyframe format (Fig. 5.3), with a per-coordinate mask for partial keys.
    pose: [B, N, P] values (anything where mask is 0), mask: [B, N, P] bool.
    Each frame gets, per coordinate, the value of the nearest frame where that
    coordinate is specified (ties go to the earlier frame) and the distance to
    it (frames / DT_NORM, clipped at DT_CLIP). Unspecified coordinates: 0 and DT_CLIP.
    Returns [B, 2P, N]. Mirrors crate/src/motion (dense_input)."""
    B, N, P = pose.shape
    idx = torch.arange(N).view(1, N, 1).expand(B, N, P)
    big = 10 ** 9
    # nearest specified frame at or before t, and at or after t
    prev = torch.where(mask, idx, torch.full_like(idx, -big))
    prev = torch.cummax(prev, dim=1).values
    nxt = torch.where(mask, idx, torch.full_like(idx, big))
    nxt = torch.flip(torch.cummin(torch.flip(nxt, [1]), dim=1).values, [1])
    dprev = idx - prev
    dnext = nxt - idx
    use_prev = dprev <= dnext
    src = torch.where(use_prev, prev, nxt).clamp(0, N - 1)
    dist = torch.minimum(dprev, dnext).float().clamp(max=DT_CLIP)
    val = torch.gather(pose, 1, src)
    none = ~mask.any(dim=1, keepdim=True).expand(B, N, P)
    val = torch.where(none, torch.zeros_like(val), val)
    dist = torch.where(none, torch.full_like(dist, DT_CLIP), dist)
    return torch.cat([val, dist / DT_NORM], dim=2).transpose(1, 2)


def _given_around(mask):
    """Per frame and channel: the nearest frame at or before / at or after it
    where the channel is given (-10^9 / 10^9 where none). mask: [B, N, R]."""
    B, N, R = mask.shape
    idx = torch.arange(N).view(1, N, 1).expand(B, N, R)
    big = 10 ** 9
    prev = torch.cummax(torch.where(mask, idx, torch.full_like(idx, -big)), dim=1).values
    nxt = torch.flip(torch.cummin(torch.flip(torch.where(mask, idx, torch.full_like(idx, big)), [1]), dim=1).values, [1])
    return idx, prev, nxt


def interp_channels(values, mask):
    """Per channel, linear interpolation between the previous and the next
    frame where the channel is given (held before the first and after the
    last; 0 where never given). values, mask: [B, N, R] -> [B, N, R].
    Mirrors interp_channels in crate/src/motion/dense.rs."""
    N = values.shape[1]
    idx, prev, nxt = _given_around(mask)
    has_p, has_n = prev >= 0, nxt < N
    pa, nb = prev.clamp(0, N - 1), nxt.clamp(0, N - 1)
    va, vb = torch.gather(values, 1, pa), torch.gather(values, 1, nb)
    span = (nb - pa).clamp(min=1).float()
    w = ((idx - pa).float() / span).clamp(0, 1)
    both = has_p & has_n & (nb > pa)
    out = torch.where(both, va + w * (vb - va), torch.where(has_p, va, torch.where(has_n, vb, torch.zeros_like(va))))
    return out


def spline_channels(values, mask):
    """Per channel, a cubic Hermite spline through the frames where the channel
    is given, with finite-difference tangents (p[k+1] - p[k-1]) / (t[k+1] - t[k-1])
    (the secant at the first and last given frame): uniform Catmull-Rom when
    the keys are evenly spaced, C1 otherwise. Held before the first and after
    the last given frame; 0 where never given. values, mask: [B, N, R] -> [B, N, R].
    Mirrors spline_channels in crate/src/motion/dense.rs."""
    N = values.shape[1]
    big = 10 ** 9
    idx, prev, nxt = _given_around(mask)
    # the given frame strictly before / after each frame
    prev_s = torch.cat([torch.full_like(prev[:, :1], -big), prev[:, :-1]], dim=1)
    nxt_s = torch.cat([nxt[:, 1:], torch.full_like(nxt[:, :1], big)], dim=1)
    has_p, has_n = prev >= 0, nxt < N
    a, b = prev.clamp(0, N - 1), nxt.clamp(0, N - 1)
    pa = torch.gather(prev_s, 1, a)  # key before a
    nb = torch.gather(nxt_s, 1, b)   # key after b
    has_pa, has_nb = pa >= 0, nb < N
    pa, nb = pa.clamp(0, N - 1), nb.clamp(0, N - 1)
    va, vb = torch.gather(values, 1, a), torch.gather(values, 1, b)
    vpa, vnb = torch.gather(values, 1, pa), torch.gather(values, 1, nb)
    h = (b - a).clamp(min=1).float()
    sec = (vb - va) / h
    ma = torch.where(has_pa, (vb - vpa) / (b - pa).clamp(min=1).float(), sec)
    mb = torch.where(has_nb, (vnb - va) / (nb - a).clamp(min=1).float(), sec)
    s = ((idx - a).float() / h).clamp(0, 1)
    s2, s3 = s * s, s * s * s
    cur = (2 * s3 - 3 * s2 + 1) * va + (s3 - 2 * s2 + s) * h * ma + (-2 * s3 + 3 * s2) * vb + (s3 - s2) * h * mb
    both = has_p & has_n & (b > a)
    return torch.where(both, cur, torch.where(has_p, va, torch.where(has_n, vb, torch.zeros_like(va))))


BASES = ("linear", "spline", "angle-linear", "angle-spline")


def base_channels(values, mask, base="linear"):
    """What the generator corrects between whole-pose keys (motion.train --base):
    the keys' raw RC-FK values interpolated linearly (interp_channels) or on a
    spline (spline_channels), either in the raw space itself ("linear",
    "spline") or, for the Euler channels after the root 6D, in range position
    tanh(v), i.e. linearly in angle ("angle-linear", "angle-spline"), then
    mapped back (|v| <= VCLIP). [B, N, R] -> [B, N, R]. Mirrors base_channels
    in crate/src/motion/dense.rs."""
    if base not in BASES:
        raise ValueError(f"unknown base {base!r}; one of {BASES}")
    between = spline_channels if base.endswith("spline") else interp_channels
    if not base.startswith("angle"):
        return between(values, mask)
    lim = math.tanh(VCLIP)
    v = torch.cat([values[..., :6], torch.tanh(values[..., 6:])], -1)
    out = between(v, mask)
    return torch.cat([out[..., :6], torch.atanh(out[..., 6:].clamp(-lim, lim))], -1)
