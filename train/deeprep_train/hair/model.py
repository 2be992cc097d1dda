"""HairNet (thesis Sec. 3.2.3, Table B.1) with channel widths divided by
`div` for CPU training. The network is split as the Rust side needs it:

- `HairEncoderDecoder`: 3 x 256 x 256 orientation image -> strand features
  C x 32 x 32 (encoder convs, 8 x 8 max-pool, tanh, linear decoder, three
  bilinear x2 upsamplings with 3 x 3 convs).
- `StrandHeads`: strand features (C x 32 x 32, or C x K x 1 for any K
  strands) -> positions (300 = 100 points x 3) and curvatures (100), two
  1 x 1-conv MLPs (ReLU, tanh).
"""
import torch
from torch import nn
import torch.nn.functional as F

POINTS = 100
GRID = 32
POS_SCALE = 0.1    # network positions are in decimetres: metres = out * POS_SCALE
CURV_SCALE = 100.0  # network curvatures are per centimetre: 1/m = out * CURV_SCALE
CURV_MAX = 300.0    # curvature targets are clipped here (1/m): kinks where a strand slides
                    # off an ellipsoid give single-sample spikes of 10^3-10^5 / m (radius < 1 mm)


class HairEncoderDecoder(nn.Module):
    def __init__(self, div=8):
        super().__init__()
        c = lambda n: max(4, n // div)
        self.c_feat = c(512)
        self.c_dec = c(256)
        self.enc = nn.Sequential(
            nn.Conv2d(3, c(32), 8, 2, 3), nn.ReLU(),
            nn.Conv2d(c(32), c(64), 8, 2, 3), nn.ReLU(),
            nn.Conv2d(c(64), c(128), 6, 2, 2), nn.ReLU(),
            nn.Conv2d(c(128), c(256), 4, 2, 1), nn.ReLU(),
            nn.Conv2d(c(256), c(256), 3, 1, 1), nn.ReLU(),
            nn.Conv2d(c(256), c(512), 4, 2, 1), nn.ReLU(),
            nn.Conv2d(c(512), c(512), 3, 1, 1), nn.ReLU(),
        )
        self.fc = nn.Sequential(nn.Linear(c(512), c(1024)), nn.ReLU(), nn.Linear(c(1024), self.c_dec * 16), nn.ReLU())
        self.up = nn.ModuleList([
            nn.Conv2d(self.c_dec, c(512), 3, 1, 1),
            nn.Conv2d(c(512), c(512), 3, 1, 1),
            nn.Conv2d(c(512), c(512), 3, 1, 1),
        ])

    def encode(self, img):
        h = self.enc(img)                      # B x C x 8 x 8
        return torch.tanh(F.max_pool2d(h, 8).flatten(1))  # B x C (the hair feature z)

    def decode(self, z):
        h = self.fc(z).reshape(z.shape[0], self.c_dec, 4, 4)
        for conv in self.up:
            h = F.relu(conv(F.interpolate(h, scale_factor=2, mode="bilinear", align_corners=False)))
        return h                               # B x C x 32 x 32

    def forward(self, img):
        return self.decode(self.encode(img))


class StrandHeads(nn.Module):
    def __init__(self, c):
        super().__init__()
        mlp = lambda out: nn.Sequential(nn.Conv2d(c, c, 1), nn.ReLU(), nn.Conv2d(c, c, 1), nn.Tanh(), nn.Conv2d(c, out, 1))
        self.pos = mlp(3 * POINTS)
        self.curv = mlp(POINTS)

    def forward(self, feat):
        return self.pos(feat), self.curv(feat)


class HairNet(nn.Module):
    def __init__(self, div=8):
        super().__init__()
        self.body = HairEncoderDecoder(div)
        self.heads = StrandHeads(self.body.c_feat)

    def forward(self, img):
        f = self.body(img)
        pos, curv = self.heads(f)
        return f, pos, curv


def strands_from(pos):
    """B x 300 x 32 x 32 -> B x 1024 x 100 x 3 (metres, root-relative)."""
    b = pos.shape[0]
    return pos.reshape(b, POINTS, 3, GRID * GRID).permute(0, 3, 1, 2) * POS_SCALE


def curv_from(curv):
    """B x 100 x 32 x 32 -> B x 1024 x 100 (1/m)."""
    b = curv.shape[0]
    return curv.reshape(b, POINTS, GRID * GRID).permute(0, 2, 1) * CURV_SCALE


def collision(abs_pts, centers, radii):
    """Eq. 3.3-3.5: (1/NM) sum_k sum_i sum_j |p_ij - p_ij-1|_1 max(0, Dist_k(p_ij)),
    per batch element. abs_pts: B x N x M x 3 absolute metres."""
    seg = (abs_pts[:, :, 1:] - abs_pts[:, :, :-1]).abs().sum(-1)          # B x N x M-1
    p = abs_pts[:, :, 1:]
    total = 0.0
    for c, r in zip(centers, radii):
        d = 1.0 - (((p - c) / r) ** 2).sum(-1)
        total = total + (seg * d.clamp(min=0)).sum((1, 2))
    n, m = abs_pts.shape[1], abs_pts.shape[2]
    return total / (n * m)
