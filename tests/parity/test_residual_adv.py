"""Cross-clip keys for the residual network's adversarial stage
(train/deeprep_train/motion/residual_adv.py, Sec. 5.2.7 rule 2): the
spliced window keeps the first clip up to the interval's end key, then the
second clip turned about the vertical and moved, its own motion otherwise
intact. Needs torch, so it runs in the training venv
(`train/.venv/bin/python -m pytest tests/parity`) and skips in the test venv."""

import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="torch is only in train/.venv (tests never need it)")


@pytest.fixture()
def adv(train_import):
    return train_import("deeprep_train.motion.residual_adv")


@pytest.fixture()
def rot(train_import):
    """[..., 4] quaternions [w, x, y, z] -> rotation matrices."""
    to_matrix = train_import("deeprep_train.rotation").quat_to_matrix
    return lambda q: to_matrix(q[..., [1, 2, 3, 0]])


def window(n, k, seed):
    g = torch.Generator().manual_seed(seed)
    root = torch.cumsum(torch.randn(n, 3, generator=g), 0)
    root[:, 1] = 90 + torch.randn(n, generator=g)
    q = torch.randn(n, k, 4, generator=g)
    return root, q / q.norm(dim=-1, keepdim=True)


def test_a_long_interval_takes_its_end_key_from_the_other_clip(adv, rot):
    n, k = 400, 5
    ra, qa = window(n, k, 1)
    rb, qb = window(n, k, 2)
    keys = [0, 40, 300, 399]  # 260 frames between 40 and 300: over three seconds
    root, quat, spliced = adv.cross_clip(ra, qa, rb, qb, keys, np.random.default_rng(0), p=10.0)
    assert spliced
    assert torch.equal(root[:300], ra[:300]) and torch.equal(quat[:300], qa[:300])
    # heights and the other joints' rotations are the second clip's
    assert torch.allclose(root[300:, 1], rb[300:, 1])
    assert torch.allclose(quat[300:, 1:], qb[300:, 1:])
    # its root path is turned and moved rigidly: step lengths are kept
    assert torch.allclose((root[301:] - root[300:-1]).norm(dim=-1), (rb[301:] - rb[300:-1]).norm(dim=-1), atol=1e-4)
    # the end key lies 0.5-1.5x the first clip's own travel from the interval's first key
    travelled = (ra[300, [0, 2]] - ra[40, [0, 2]]).norm()
    d = (root[300, [0, 2]] - ra[40, [0, 2]]).norm()
    assert 0.5 * travelled - 1e-4 <= d <= 1.5 * travelled + 1e-4
    # the root's rotation turns by the same angle about the vertical at every frame
    rel = rot(quat[300:, 0]) @ rot(qb[300:, 0]).transpose(-1, -2)
    assert torch.allclose(rel, rel[:1].expand_as(rel), atol=1e-5)
    assert torch.allclose(rel[0, 1], torch.tensor([0.0, 1.0, 0.0]), atol=1e-5)


def test_short_intervals_and_zero_probability_keep_the_window(adv):
    ra, qa = window(200, 3, 1)
    rb, qb = window(200, 3, 2)
    rng = np.random.default_rng(0)
    for keys, p in (([0, 100, 199], 10.0), ([0, 199], 0.0)):
        root, quat, spliced = adv.cross_clip(ra, qa, rb, qb, keys, rng, p)
        assert not spliced and root is ra and quat is qa
