"""The residual network's stride-2 form (issue 23: its blocks at every
second frame, train/deeprep_train/motion/residual.py): the interpolation
back to every frame is aligned with the stride-2 convolution's samples, any
length (odd or even) comes back at that length, and a stride-2 network is
the stride-1 network's blocks run on every second frame. Needs torch, so it
runs in the training venv (`train/.venv/bin/python -m pytest tests/parity`)
and skips in the test venv."""

import pytest

torch = pytest.importorskip("torch", reason="torch is only in train/.venv (tests never need it)")


@pytest.fixture()
def residual(train_import):
    return train_import("deeprep_train.motion.residual")


def test_upsampling_keeps_samples_and_averages_between(residual):
    h = torch.tensor([[[0.0, 2.0, 6.0, 7.0]]])
    assert residual.upsample2(h, 7).tolist() == [[[0.0, 1.0, 2.0, 4.0, 6.0, 6.5, 7.0]]]
    # an even length ends past the last sample: it repeats it
    assert residual.upsample2(h, 8).tolist() == [[[0.0, 1.0, 2.0, 4.0, 6.0, 6.5, 7.0, 7.0]]]


@pytest.mark.parametrize("n", [1, 2, 9, 64, 65])
def test_a_stride_2_network_samples_every_second_frame_and_returns_every_frame(residual, n):
    torch.manual_seed(0)
    one = residual.ResidualTween(2, 8, (1, 2), stride=1)
    two = residual.ResidualTween(2, 8, (1, 2), stride=2)
    for p in (one.out.weight, one.out.bias):
        torch.nn.init.normal_(p)  # the output convolution starts at zero
    two.load_state_dict(one.state_dict())  # the stride adds no weights
    x = torch.randn(1, 3 + 6 * 2 + 4, n)
    with torch.no_grad():
        # the input convolution's samples are the stride-1 one's at frames 0, 2, 4, ...
        assert torch.allclose(two.inp(x), one.inp(x)[..., ::2], atol=1e-6)
        h = two.blocks(one.inp(x)[..., ::2])
        want = one.out(torch.nn.functional.leaky_relu(residual.upsample2(h, n), 0.2))
        got = two(x)
    assert got.shape == (1, 3 + 6 * 2, n)
    assert torch.allclose(got, want, atol=1e-5)


def test_the_stride_is_1_or_2(residual):
    with pytest.raises(ValueError):
        residual.ResidualTween(2, 8, (1,), stride=3)


def test_the_full_rate_skip_starts_at_zero_and_round_trips_through_a_checkpoint(residual):
    torch.manual_seed(0)
    plain = residual.ResidualTween(2, 8, (1, 2), stride=2)
    torch.nn.init.normal_(plain.out.weight)
    skip = residual.ResidualTween(2, 8, (1, 2), stride=2, skip=True)
    added = residual.grow(skip, plain.state_dict(), (1, 2))
    assert sorted(added) == ["skip.bias", "skip.weight"]
    x = torch.randn(1, 3 + 6 * 2 + 4, 33)
    with torch.no_grad():
        assert torch.equal(skip(x), plain(x))  # adding the skip changes nothing until trained
        torch.nn.init.normal_(skip.skip.weight)
        # what a checkpoint carries rebuilds the same network
        again = residual.build({**skip.arch(), "net": None})
        again.load_state_dict(skip.state_dict())
        assert skip.arch() == {"width": 8, "K": 2, "dilations": [1, 2], "stride": 2, "skip": True}
        assert residual.arch(skip.arch()) == skip.arch()
        assert torch.equal(again(x), skip(x))
        assert not torch.equal(skip(x), plain(x))


def test_the_adversarial_gradient_skips_frames_of_short_intervals(residual):
    """--gan-min-gap: the adversary's loss moves only frames of intervals at
    least that long (the phase's frames since / to the keys give the length)."""
    n, keys = 41, [0, 10, 40]  # a 10-frame and a 30-frame interval
    phase = torch.zeros(1, n, 4)
    for a, b in zip(keys[:-1], keys[1:]):
        for t in range(a, b + 1):
            phase[0, t, 1], phase[0, t, 2] = (t - a) / 60, (b - t) / 60
    rel = torch.randn(1, n, 3, 3, requires_grad=True)
    grad = {g: torch.autograd.grad(residual.adversarial_view(rel, phase, g).pow(2).sum(), rel)[0] for g in (0, 20, 31)}
    assert torch.equal(grad[0], 2 * rel.detach())
    assert grad[20][0, 1:10].abs().sum() == 0  # inside the 10-frame interval: none
    assert torch.equal(grad[20][0, 11:40], grad[0][0, 11:40])  # the 30-frame one keeps it
    assert grad[31].abs().sum() == 0


def test_regular_keys_repeat_one_interval_and_end_on_the_last_frame(residual):
    import numpy as np
    rng = np.random.default_rng(0)
    for _ in range(200):
        keys = residual.sample_keys(480, rng, regular=1.0)
        gaps = np.diff(keys)
        assert keys[0] == 0 and keys[-1] == 479
        assert len(set(gaps[:-1].tolist())) <= 1 and gaps.min() >= 15
        assert gaps[-1] < 2 * 15 + gaps[0]  # the rest went to the last interval
        free = residual.sample_keys(480, rng)
        assert free[0] == 0 and free[-1] == 479 and np.diff(free).min() >= 1


def test_prune_keeps_the_channels_that_carry_the_output_skip_included(residual, tmp_path):
    """`residual prune` to a narrower width: where the dropped stream and
    hidden channels carry nothing (zero weights in and out), the narrower
    network computes what the wider one does, the full-rate skip's rows
    pruned with the stream's."""
    import argparse

    torch.manual_seed(0)
    wide = residual.ResidualTween(2, 8, (1, 2), stride=2, skip=True)
    with torch.no_grad():
        for p in wide.parameters():
            torch.nn.init.normal_(p, std=0.3)
        dead = slice(2, 4)  # stream channels 2 and 3, hidden channels 2 and 3 of each block
        for m in (wide.inp, wide.skip):
            m.weight[dead] = 0
            m.bias[dead] = 0
        wide.out.weight[:, dead] = 0
        for b in wide.blocks:
            b.c1.weight[:, dead] = 0  # reads nothing from the dead stream channels
            b.c1.weight[dead] = 0  # the dead hidden channels: zero in ...
            b.c1.bias[dead] = 0
            b.c2.weight[:, dead] = 0  # ... and zero out
            b.c2.weight[dead] = 0  # writes nothing to the dead stream channels
            b.c2.bias[dead] = 0
    sd = wide.state_dict()
    torch.save({"step": 7, **wide.arch(), "net": sd, "ema": sd}, tmp_path / "wide.pt")
    residual.prune(argparse.Namespace(ckpt=str(tmp_path / "wide.pt"), width=6, out=str(tmp_path / "p")))
    s = torch.load(tmp_path / "p" / "ckpt.pt")
    assert (s["width"], s["skip"], s["step"]) == (6, True, 7)
    narrow = residual.build(s)
    narrow.load_state_dict(s["ema"])
    assert sum(p.numel() for p in narrow.parameters()) < sum(p.numel() for p in wide.parameters())
    x = torch.randn(1, 3 + 6 * 2 + 4, 41)
    with torch.no_grad():
        assert torch.allclose(narrow(x), wide(x), atol=1e-5)


def test_fill_layouts_keep_twenty_context_frames_and_gaps_in_range(residual):
    # residual train --fill-share and cond train --fill-share draw one layout (issue 50)
    import numpy as np
    rng = np.random.default_rng(1)
    for law in ("log", "inverse"):
        for _ in range(200):
            keys = residual.fill_keys(480, rng, (40, 120), law)
            gaps = np.diff(keys) - 1  # unknown frames between consecutive keys
            assert keys[:20] == list(range(20)) and keys[-1] == 479
            inner = gaps[(gaps > 0)][:-1]  # the last gap may be cut by the window's end
            assert inner.size == 0 or (inner.min() >= 39 and inner.max() <= 120)
