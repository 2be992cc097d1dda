"""The short-gap fill network's layout (train/deeprep_train/motion/fill_mlp.py,
issue 50): with a zero output it gives the context-tangent Hermite curve
back, its correction is zero at the gap's edges, and frames not known are
padded with the outermost known one. Needs torch, so it runs in the
training venv (`train/.venv/bin/python -m pytest tests/parity`) and skips
in the test venv."""

import pytest

torch = pytest.importorskip("torch", reason="torch is only in train/.venv (tests never need it)")


@pytest.fixture()
def fm(train_import):
    return train_import("deeprep_train.motion.fill_mlp")


def window(fm, T, k=4, seed=0):
    """A smooth random window: root along a curve, joints turning slowly."""
    g = torch.Generator().manual_seed(seed)
    n = fm.CTX + T + fm.AFT
    t = torch.arange(n, dtype=torch.float64)[:, None]
    root = torch.cat([t * 0.7, 90 + torch.sin(t / 9), t * 0.2], 1)
    axis = torch.randn(k, 3, generator=g, dtype=torch.float64)
    axis = axis / axis.norm(dim=-1, keepdim=True)
    ang = 0.3 + 0.02 * t[:, :, None] * torch.randn(1, k, 1, generator=g, dtype=torch.float64)
    quat = torch.cat([torch.cos(ang / 2), torch.sin(ang / 2) * axis], -1)
    return root, quat


@pytest.mark.parametrize("T,c,A", [(10, 8, 1), (23, 3, 8), (40, 1, 2)])
def test_a_zero_output_is_the_hermite_curve(fm, train_import, T, c, A):
    cond = train_import("deeprep_train.motion.cond")
    root, quat = window(fm, T)
    x, hw, hr, frame = fm.window_features(root, quat, T, c, A)
    r, q = fm.decode(torch.zeros(1, fm.M, 3 * quat.shape[1] + 3, dtype=torch.float64), hw[None], hr[None],
                     tuple(f[None] for f in frame))
    a, b = fm.CTX - 1, fm.CTX + T
    br, bq = root.clone(), quat.clone()
    cond.hermite_base([(a, b, a - 1 if c >= 2 else None, b + 1 if A >= 2 else None)], root, quat, br, bq)
    assert torch.allclose(r[0], br[a + 1:b], atol=1e-9)
    dot = (q[0] * bq[a + 1:b]).sum(-1).abs()
    assert torch.allclose(dot, torch.ones_like(dot), atol=1e-9)


def test_the_correction_vanishes_at_the_edges(fm):
    T = 17
    f = torch.tensor([0.0, T + 1.0])[:, None]
    m = torch.arange(1, fm.M + 1, dtype=torch.float64)[None]
    assert torch.sin(torch.pi * m * f / (T + 1)).abs().max() < 1e-12
    # inside, the basis is the same formula
    assert torch.allclose(fm.basis(T, torch.float64)[0], torch.sin(torch.pi * m[0] / (T + 1)))


def test_frames_not_known_are_padded_with_the_outermost_known_one(fm):
    T, k = 12, 4
    root, quat = window(fm, T, k)
    x, *_ = fm.window_features(root, quat, T, 1, 1)
    per = 3 * k
    w = x[:(fm.CTX + fm.AFT) * per].view(fm.CTX + fm.AFT, k, 3)
    r = x[(fm.CTX + fm.AFT) * per:-3].view(fm.CTX + fm.AFT, 3)
    # one known frame before (a itself: zero tangent, zero offset) and one after
    assert w[:fm.CTX].abs().max() < 1e-12 and r[:fm.CTX].abs().max() < 1e-12
    assert torch.allclose(w[fm.CTX:], w[fm.CTX:fm.CTX + 1].expand(fm.AFT, -1, -1))
    assert x[-3:].tolist() == pytest.approx([T / fm.T_NORM, 1 / fm.CTX, 1 / fm.AFT])
