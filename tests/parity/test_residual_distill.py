"""Distillation in `residual train --teacher` (issue 23: a narrower network
learns a wider one's output, train/deeprep_train/motion/residual.py
`losses`): "distill" and "distill_speed" measure the output against the
teacher's on every window, ground truth or not; they vanish where the
teacher is the network itself, and "distill_speed" is there only when it has
a weight. Needs torch, so it runs in the training venv
(`train/.venv/bin/python -m pytest tests/parity`) and skips in the test venv."""

import copy

import pytest

torch = pytest.importorskip("torch", reason="torch is only in train/.venv (tests never need it)")

NAMES = ["Hips", "Spine", "LeftFoot", "RightFoot"]


@pytest.fixture()
def residual(train_import):
    return train_import("deeprep_train.motion.residual")


def windows(residual):
    """A four-joint skeleton, a small network with a nonzero output and a
    batch of two 32-frame windows whose gate is open between the ends."""
    import numpy as np
    d = {"names": np.array(NAMES), "parents": np.array([-1, 0, 0, 0]),
         "offsets": np.array([[0, 0, 0], [0, 10, 0], [5, -40, 0], [-5, -40, 0]], dtype=np.float32),
         "rotating": np.array([0, 1, 2, 3])}
    skel = residual.Skeleton(d)
    torch.manual_seed(0)
    net = residual.ResidualTween(skel.K, 8, (1, 2), stride=1)
    torch.nn.init.normal_(net.out.weight, std=0.1)  # the output convolution starts at zero
    B, N, K = 2, 32, skel.K
    rot = residual.from_sixd(torch.randn(B, N, K, 6))
    root = torch.randn(B, N, 3) * 20
    phase = torch.rand(B, N, 4)
    gate = torch.ones(B, N)
    gate[:, 0] = gate[:, -1] = 0
    offs = skel.offsets.expand(B, -1, -1)
    batch = [root, rot, root.clone(), rot.clone(), phase, gate, offs]
    return skel, net, batch


def test_a_teacher_identical_to_the_network_costs_nothing(residual):
    skel, net, batch = windows(residual)
    w = {"distill": 1.0, "distill_speed": 1.0}
    sup = torch.zeros(2, dtype=torch.bool)  # no ground truth: only the teacher's terms
    with torch.no_grad():
        out = residual.losses(net, skel, batch, w, sup, teacher=copy.deepcopy(net).eval())
    assert float(out["distill"]) == pytest.approx(0, abs=1e-6)
    assert float(out["distill_speed"]) == pytest.approx(0, abs=1e-6)


def test_another_teacher_pulls_the_network_by_its_speeds_only_with_a_weight(residual):
    skel, net, batch = windows(residual)
    teacher = copy.deepcopy(net)
    with torch.no_grad():
        teacher.out.weight.mul_(3)  # the same direction, larger: faster motion
    teacher.eval()
    sup = torch.zeros(2, dtype=torch.bool)
    out = residual.losses(net, skel, batch, {"distill": 1.0, "distill_speed": 1.0}, sup, teacher=teacher)
    assert out["distill_speed"].item() > 1e-3
    net.zero_grad()
    out["distill_speed"].backward()
    assert net.out.weight.grad.abs().sum() > 0
    with torch.no_grad():
        plain = residual.losses(net, skel, batch, {"distill": 1.0}, sup, teacher=teacher)
    assert "distill_speed" not in plain
    assert float(plain["distill"]) == pytest.approx(out["distill"].item(), rel=1e-6)
