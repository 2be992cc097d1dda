"""The residual network: dilated 1-D convolutional blocks, the stride-2 form and the skip; input, output and FK.

Part of deeprep_train.motion.residual (see its package docstring)."""

import torch
import torch.nn as nn
import torch.nn.functional as F

from deeprep_train.motion.residual.data import SCALE, from_sixd, sixd


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
