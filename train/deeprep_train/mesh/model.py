"""The fully convolutional mesh autoencoder's layers (thesis Sec. 2.2),
over the padded neighbourhood tables that `deeprep mesh topology` writes
(Appendix A.1.1: an N x max(E_i) index table and its mask).

- VcConv (eq. 2.2-2.3): y_i = sum_j W_ij x_ij + b with W_ij = sum_k a_ijk B_k;
  the same class is vcTransConv when given an up-sampling table.
- VdPool (eq. 2.4): y_i = sum_j rho'_ij x_ij, rho' = |rho| / sum |rho|.
- VdRes (eq. 2.5): y_i = sum_j rho'_ij C x_ij (C = identity when sizes match).
- ResBlock (Fig. 2.2): ELU(vcConv(x)) + vdRes(x).
"""
import json

import torch
from torch import nn


class Table(nn.Module):
    """Holds one neighbourhood table as buffers."""

    def __init__(self, t):
        super().__init__()
        idx = torch.tensor(t["indices"], dtype=torch.long).reshape(t["rows"], t["width"])
        mask = torch.tensor(t["mask"], dtype=torch.float32).reshape(t["rows"], t["width"])
        self.register_buffer("idx", idx)
        self.register_buffer("mask", mask)

    @property
    def rows(self):
        return self.idx.shape[0]

    @property
    def width(self):
        return self.idx.shape[1]

    def gather(self, x):
        """x [B, N_in, C] -> [B, N_out, E, C] (masked entries zero)."""
        return x[:, self.idx] * self.mask[None, :, :, None]


class VcConv(nn.Module):
    def __init__(self, table, cin, cout, m):
        super().__init__()
        self.t = table
        n, e = table.rows, table.width
        self.A = nn.Parameter(torch.randn(n, e, m) / m ** 0.5)
        self.B = nn.Parameter(torch.randn(m, cout, cin) * (1.0 / (cin * table.mask.sum(1).mean().item())) ** 0.5)
        self.b = nn.Parameter(torch.zeros(cout))

    def forward(self, x):
        g = self.t.gather(x)                                   # [B, N, E, I]
        z = torch.einsum("nem,bnei->bnmi", self.A * self.t.mask[..., None], g)
        return torch.einsum("bnmi,moi->bno", z, self.B) + self.b

    def kernels(self):
        """W [N, E, O, I] (eq. 2.2, precomputed for inference)."""
        return torch.einsum("nem,moi->neoi", self.A * self.t.mask[..., None], self.B)


def density(rho, mask):
    a = rho.abs() * mask
    return a / a.sum(1, keepdim=True).clamp(min=1e-8)


class VdPool(nn.Module):
    def __init__(self, table):
        super().__init__()
        self.t = table
        self.rho = nn.Parameter(torch.ones(table.rows, table.width))

    def weights(self):
        return density(self.rho, self.t.mask)

    def forward(self, x):
        return torch.einsum("ne,bnec->bnc", self.weights(), self.t.gather(x))


class VdRes(VdPool):
    def __init__(self, table, cin, cout):
        super().__init__(table)
        self.C = None if cin == cout else nn.Linear(cin, cout, bias=False)

    def forward(self, x):
        y = super().forward(x)
        return y if self.C is None else self.C(y)


class AvgPool(nn.Module):
    """Ablation: plain average over the neighbourhood instead of vdPool."""

    def __init__(self, table, cin, cout):
        super().__init__()
        self.t = table
        self.C = None if cin == cout else nn.Linear(cin, cout, bias=False)

    def forward(self, x):
        w = self.t.mask / self.t.mask.sum(1, keepdim=True)
        y = torch.einsum("ne,bnec->bnc", w, self.t.gather(x))
        return y if self.C is None else self.C(y)


class Block(nn.Module):
    """Fig. 2.2: ELU(vcConv(x)) + vdRes(x); `residual` = "vd", "avg" or None (ablations)."""

    def __init__(self, table, cin, cout, m, residual="vd", act=True):
        super().__init__()
        self.conv = VcConv(table, cin, cout, m)
        self.act = act
        self.res = {"vd": lambda: VdRes(table, cin, cout), "avg": lambda: AvgPool(table, cin, cout), None: lambda: None}[residual]()

    def forward(self, x):
        y = self.conv(x)
        if self.act:
            y = torch.nn.functional.elu(y)
        return y if self.res is None else y + self.res(x)


class MeshAE(nn.Module):
    """Encoder: down blocks level 0 -> L; decoder: up blocks L -> 0."""

    def __init__(self, topology, widths=(3, 16, 32, 64, 16), m=None, residual="vd"):
        super().__init__()
        levels = topology["levels"]
        assert len(widths) == len(levels) + 1, (widths, len(levels))
        self.down_t = nn.ModuleList(Table(l["down"]) for l in levels)
        self.up_t = nn.ModuleList(Table(l["up"]) for l in levels)
        mm = lambda t: m or max(1, round(t.mask.sum(1).mean().item()))
        self.enc = nn.ModuleList(Block(t, widths[k], widths[k + 1], mm(t), residual, act=k + 1 < len(levels))
                                 for k, t in enumerate(self.down_t))
        dec = []
        for k in reversed(range(len(levels))):
            t = self.up_t[k]
            dec.append(Block(t, widths[k + 1], widths[k] if k > 0 else widths[1], mm(t), residual, act=True))
        self.dec = nn.ModuleList(dec)
        self.out = nn.Linear(widths[1], 3)

    def encode(self, x):
        for b in self.enc:
            x = b(x)
        return x

    def decode(self, z):
        for b in self.dec:
            z = b(z)
        return self.out(z)

    def forward(self, x):
        return self.decode(self.encode(x))


def load_topology(path):
    return json.load(open(path))
