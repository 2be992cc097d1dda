"""The training's NPSS term (residual.npss_loss) against motion.eval's NPSS:
one formula in two libraries. Needs torch, so it runs in the training venv
(`train/.venv/bin/python -m pytest tests/parity`) and skips elsewhere."""
import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="torch is only in train/.venv (tests never need it)")


def test_the_training_term_is_the_evaluations_npss_over_the_frame_count(train_import):
    ev = train_import("deeprep_train.motion.eval")
    losses = train_import("deeprep_train.motion.residual.losses")
    rng = np.random.default_rng(3)
    B, N, F = 3, 50, 7
    t = np.linspace(0, 1, N)[None, :, None]
    gt = np.sin(2 * np.pi * rng.uniform(1, 4, (B, 1, F)) * t) + rng.normal(0, 0.1, (B, N, F)) + 2
    pred = gt + rng.normal(0, 0.5, (B, N, F))
    got = float(losses.npss_loss(torch.tensor(pred), torch.tensor(gt))) * N
    assert abs(got - ev.npss(gt, pred)) < 1e-9 * max(1.0, got)
    assert float(losses.npss_loss(torch.tensor(gt), torch.tensor(gt))) == 0.0
    # it has a gradient towards the truth's spectrum
    p = torch.tensor(pred, requires_grad=True)
    losses.npss_loss(p, torch.tensor(gt)).backward()
    assert torch.isfinite(p.grad).all() and float(p.grad.abs().sum()) > 0
