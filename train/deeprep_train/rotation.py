"""Rotation maps in PyTorch, mirroring crate/src/rotation (thesis ch. 4)."""
import torch


def normalize(v: torch.Tensor, eps: float = 1e-8) -> torch.Tensor:
    """N(v) = v / |v| over the last axis (eps keeps the graph finite)."""
    return v / torch.sqrt((v * v).sum(-1, keepdim=True) + eps * eps)


def sixd_to_matrix(r: torch.Tensor) -> torch.Tensor:
    """f_GS of eq. C.2-C.3. r: [..., 6] = [a1; a2]. Returns [..., 3, 3] (row-major, columns b1 b2 b3)."""
    a1, a2 = r[..., 0:3], r[..., 3:6]
    b1 = normalize(a1)
    b2 = normalize(a2 - (b1 * a2).sum(-1, keepdim=True) * b1)
    b3 = torch.cross(b1, b2, dim=-1)
    return torch.stack([b1, b2, b3], dim=-1)


def matrix_to_6d(m: torch.Tensor) -> torch.Tensor:
    """g_GS of eq. C.1: the first two columns, [a1; a2]."""
    return torch.cat([m[..., :, 0], m[..., :, 1]], dim=-1)


def random_so3(n: int, generator: torch.Generator | None = None) -> torch.Tensor:
    """n rotations uniform on SO(3), from normalized Gaussian quaternions [x, y, z, w]."""
    q = torch.randn(n, 4, generator=generator, dtype=torch.float64)
    q = q / q.norm(dim=-1, keepdim=True)
    return quat_to_matrix(q)


def quat_to_matrix(q: torch.Tensor) -> torch.Tensor:
    """Eq. 4.4 for unit quaternions [x, y, z, w]."""
    x, y, z, w = q.unbind(-1)
    return torch.stack([
        torch.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        torch.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        torch.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


def geodesic(m1: torch.Tensor, m2: torch.Tensor) -> torch.Tensor:
    """Eq. 4.12 in the atan2 form (accurate near 0): the angle of m1 m2^T, radians."""
    r = m1 @ m2.transpose(-1, -2)
    s = torch.stack([r[..., 2, 1] - r[..., 1, 2], r[..., 0, 2] - r[..., 2, 0], r[..., 1, 0] - r[..., 0, 1]], -1)
    return torch.atan2(s.norm(dim=-1) / 2, (r[..., 0, 0] + r[..., 1, 1] + r[..., 2, 2] - 1) / 2)
