"""RC-FK as a PyTorch layer (thesis Sec. 5.2.3), mirroring crate/src/rcfk.rs.

Ranges, orders and frame rules come from crate/data/table_d1.json, the same
file the Rust crate embeds. A parity test (tests/native/rcfk.rs reading
tests/fixtures/rcfk_torch.json, written by train/deeprep_train/motion/make_rcfk_fixture.py) checks
that both agree to 1e-4 in BVH units.
"""
import json
import math
import os

import torch

from .rotation import sixd_to_matrix

TABLE_PATH = os.path.join(os.path.dirname(__file__), "..", "..", "crate", "data", "table_d1.json")


def load_table(path: str = TABLE_PATH) -> dict:
    return {r["joint"]: r for r in json.load(open(path))["joints"]}


def local_frame(d, rule="x") -> torch.Tensor:
    """M_lw (columns x, y, z) for a joint whose child bones have mean direction d.

    rule: "x" (default), "z", or {"y": [..]}: an explicit local y (a hinge axis
    fitted to the data by train/deeprep_train/motion/fit_frames.py), with x = y cross z."""
    d = torch.tensor(d, dtype=torch.float64)
    n = d.norm()
    if n < 1e-9:
        return torch.eye(3, dtype=torch.float64)
    z = d / n

    def perp(r):
        r = torch.tensor(r, dtype=torch.float64)
        v = r - (r @ z) * z
        return v / v.norm()

    if isinstance(rule, dict):
        y = perp(rule["y"])
        x = torch.linalg.cross(y, z)
        return torch.stack([x, y, z], dim=1)
    if rule == "z" and abs(z[2]) < 0.7:
        x = perp([0.0, 0.0, 1.0])
        y = torch.linalg.cross(z, x)
    elif abs(z[0]) < 0.7:
        x = perp([1.0, 0.0, 0.0])
        y = torch.linalg.cross(z, x)
    else:
        y = perp([0.0, 1.0, 0.0])
        x = torch.linalg.cross(y, z)
    return torch.stack([x, y, z], dim=1)


def _axis_rotation(axis: int, a: torch.Tensor) -> torch.Tensor:
    c, s = torch.cos(a), torch.sin(a)
    o, z = torch.ones_like(a), torch.zeros_like(a)
    if axis == 0:
        rows = [[o, z, z], [z, c, -s], [z, s, c]]
    elif axis == 1:
        rows = [[c, z, s], [z, o, z], [-s, z, c]]
    else:
        rows = [[c, -s, z], [s, c, z], [z, z, o]]
    return torch.stack([torch.stack(r, -1) for r in rows], -2)


class RCFK(torch.nn.Module):
    """raw [..., 6 + 3K] (root 6D, then v per rotating joint) + root position [..., 3]
    -> global joint positions [..., J, 3]."""

    def __init__(self, names, parents, offsets, channel_joints, table=None):
        super().__init__()
        table = table or load_table()
        self.names, self.parents = list(names), list(parents)
        n = len(names)
        offsets = torch.tensor(offsets, dtype=torch.float64)
        children = [[c for c in range(n) if parents[c] == j] for j in range(n)]
        frames = []
        for j in range(n):
            d = offsets[children[j]].mean(0).tolist() if children[j] else [0.0, 0.0, 0.0]
            frames.append(local_frame(d, table.get(names[j], {}).get("frame") or "x"))
        self.rotating = [j for j in range(n) if parents[j] is not None and channel_joints[j]]
        lo, hi, orders = [], [], []
        for j in self.rotating:
            row = table[names[j]]
            lo.append([math.radians(row[a][0]) for a in "xyz"])
            hi.append([math.radians(row[a][1]) for a in "xyz"])
            orders.append(["xyz".index(ch) for ch in row["order"]])
        self.orders = orders
        self.register_buffer("offsets", offsets.float())
        self.register_buffer("frames", torch.stack(frames).float())
        self.register_buffer("lo", torch.tensor(lo, dtype=torch.float32))
        self.register_buffer("hi", torch.tensor(hi, dtype=torch.float32))

    @property
    def output_dim(self) -> int:
        return 6 + 3 * len(self.rotating)

    def angles(self, v: torch.Tensor) -> torch.Tensor:
        """u = lo + (hi - lo)(tanh v + 1)/2: the evident intent of eq. 5.3 (see crate/src/rcfk.rs)."""
        return self.lo + (self.hi - self.lo) * (torch.tanh(v) + 1) / 2

    def local_rotations(self, raw: torch.Tensor):
        k = len(self.rotating)
        return self.rotations_from_angles(raw[..., :6], self.angles(raw[..., 6:].reshape(*raw.shape[:-1], k, 3)))

    def rotations_from_angles(self, r6: torch.Tensor, u: torch.Tensor):
        """Local rotations {joint: [..., 3, 3]} from the root's 6D and the rotating
        joints' Euler angles u [..., K, 3] (radians, already in range)."""
        rots = {0: sixd_to_matrix(r6)}
        for i, j in enumerate(self.rotating):
            r = None
            for ax in self.orders[i]:
                e = _axis_rotation(ax, u[..., i, ax])
                r = e if r is None else r @ e
            m = self.frames[j]
            rots[j] = m @ r @ m.transpose(0, 1)
        return rots

    def _chain(self, rots, root_pos=None):
        """Global rotations (and, given root_pos, positions) of every joint,
        parent before child, from local_rotations' dict."""
        n = len(self.names)
        eye = torch.eye(3, dtype=rots[0].dtype).expand(*rots[0].shape)
        g_rot, g_pos = [None] * n, [None] * n
        for j in range(n):
            p = self.parents[j]
            local = rots.get(j, eye)
            if p is None:
                g_rot[j] = local
                if root_pos is not None:
                    g_pos[j] = self.offsets[j] + root_pos
            else:
                if root_pos is not None:
                    g_pos[j] = g_pos[p] + (g_rot[p] @ self.offsets[j].unsqueeze(-1)).squeeze(-1)
                g_rot[j] = g_rot[p] @ local
        return g_rot, g_pos

    def _stack_rotating(self, g_rot):
        return torch.stack([g_rot[0]] + [g_rot[j] for j in self.rotating], dim=-3)

    def global_rotations(self, rots) -> torch.Tensor:
        """Global rotations [..., 1 + K, 3, 3] of the root and the rotating joints
        (the others only copy their parent's), from local_rotations' dict."""
        return self._stack_rotating(self._chain(rots)[0])

    def pose(self, raw: torch.Tensor, root_pos: torch.Tensor):
        """forward's positions [..., J, 3] and global_rotations' [..., 1 + K, 3, 3]
        from one pass."""
        g_rot, g_pos = self._chain(self.local_rotations(raw), root_pos)
        return torch.stack(g_pos, dim=-2), self._stack_rotating(g_rot)

    def forward(self, raw: torch.Tensor, root_pos: torch.Tensor) -> torch.Tensor:
        return torch.stack(self._chain(self.local_rotations(raw), root_pos)[1], dim=-2)
