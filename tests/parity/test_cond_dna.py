"""Motion DNA in the conditional network's training code (issue 47; thesis
Sec. 5.2.5): the DNA input starts silent, no poses means no code, the DNA
losses are eqs. 5.11 and 5.12, and training draws DNA by motion.dna's rule
away from the keys. Needs torch, so it runs in the training venv
(`train/.venv/bin/python -m pytest tests/parity`) and skips elsewhere."""
import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="torch is only in train/.venv (tests never need it)")


def small_net(cond):
    torch.manual_seed(0)
    net = cond.CondTween(K=3, J=4, width=16, dilations=[1, 2])
    for p in net.parameters():
        torch.nn.init.normal_(p, std=0.1)
    return net.eval()


def test_adding_dna_changes_nothing_until_it_learns_and_no_pose_means_no_code(train_import):
    cond = train_import("deeprep_train.motion.cond")
    net = small_net(cond)
    x = torch.randn(2, net.core.inp.in_channels, 30)
    before = net(x)
    net.add_dna()
    dna, w = torch.randn(2, 3, 12), torch.ones(2, 3)
    assert torch.allclose(net(x, dna, w), before, atol=1e-6)
    torch.nn.init.normal_(net.dna_out.weight, std=0.1)
    torch.nn.init.normal_(net.dna_out.bias, std=0.1)
    assert not torch.allclose(net(x, dna, w), before, atol=1e-4)
    # weight 0: padding and "no DNA" are silent, whatever the pose holds
    assert torch.allclose(net(x, dna, torch.zeros(2, 3)), before, atol=1e-6)
    # a padded pose does not count: [p, q, pad] is [p, q]
    w2 = torch.tensor([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0]])
    assert torch.allclose(net(x, dna, w2), net(x, dna[:, :2], w2[:, :2]), atol=1e-6)


def test_dna_losses_are_eqs_5_11_and_5_12(train_import):
    cond = train_import("deeprep_train.motion.cond")
    J, N = 4, 400
    rng = np.random.default_rng(1)
    out = torch.tensor(rng.normal(size=(1, N, J, 3)), dtype=torch.float32)
    reps = out[:, [50, 300]].clone()
    reps[0, 1] += 0.5   # the second pose 0.5 off in every coordinate: squared distance 0.75 per joint
    w = torch.ones(1, 2)
    # keys at 0 and 399: one interval of 398 in-between frames -> floor(398 / 180) = 2 frames picked
    x = torch.zeros(1, 3 + 6 * 3 + 4 + cond.extra_channels(J), N)
    i = 3 + 6 * 3 + 5
    t = torch.arange(N, dtype=torch.float32)
    x[0, i + 1] = t / cond.PHASE_FRAMES
    x[0, i + 2] = (N - 1 - t) / cond.PHASE_FRAMES
    l1, l2 = cond.dna_losses(out, reps, w, x)
    d = ((out[0, :, None] - reps[0][None]) ** 2).sum(-1).mean(-1)   # [N, 2]
    assert abs(float(l1) - float(d.min(0).values.mean())) < 1e-6
    assert float(d[50, 0]) == 0.0
    want = torch.sort(d.min(1).values[1:N - 1]).values[:2].mean()
    assert abs(float(l2) - float(want)) < 1e-6
    # no DNA given: eq. 5.12 has nothing to pick
    _, none = cond.dna_losses(out, reps, torch.zeros(1, 2), x)
    assert float(none) == 0.0


def test_training_draws_dna_by_the_crates_rule_away_from_the_keys(train_import):
    cond = train_import("deeprep_train.motion.cond")
    dna = train_import("deeprep_train.motion.dna")
    torch.manual_seed(2)
    q = torch.randn(400, 5, 4)
    q = q / q.norm(dim=-1, keepdim=True)
    feat = cond.quat_to_mat(q[:, 1:]).reshape(400, -1).numpy()
    free = dna.representative_frames(feat, dna.dna_count(400))
    assert cond.dna_frames(q, []) == free
    got = cond.dna_frames(q, free)
    assert len(got) == 2 and not set(got) & set(free)
    assert all(abs(a - b) >= dna.MIN_SPACING for a in got for b in got if a != b)


def test_per_frame_dna_weights_pool_what_each_frame_is_given(train_import):
    """The exported form (dna_w [B, k, N], motion.dna.frame_weights): every
    pose on every frame is the one code training used; a frame given only
    pose j gets pose j's code, at the input convolution's frames (stride 2)."""
    cond = train_import("deeprep_train.motion.cond")
    for stride in (1, 2):
        torch.manual_seed(3)
        net = cond.CondTween(K=3, J=4, width=16, dilations=[1, 2], stride=stride)
        net.add_dna()
        for p in net.parameters():
            torch.nn.init.normal_(p, std=0.1)
        net.eval()
        N = 31
        x = torch.randn(1, net.core.inp.in_channels, N)
        dna = torch.randn(1, 3, 12)
        with torch.no_grad():
            glob = net(x, dna, torch.ones(1, 3))
            assert torch.allclose(net(x, dna, torch.ones(1, 3, N)), glob, atol=1e-5)
            # only pose 1 everywhere is the one-pose code
            w = torch.zeros(1, 3, N)
            w[:, 1] = 1.0
            assert torch.allclose(net(x, dna, w), net(x, dna[:, 1:2], torch.ones(1, 1)), atol=1e-5)
            # no pose on any frame: no code
            assert torch.allclose(net(x, dna, torch.zeros(1, 3, N)), net(x), atol=1e-5)
            # per-part weights differ from the one code
            w = torch.from_numpy(train_import("deeprep_train.motion.dna").frame_weights(3, N, 3))[None]
            assert not torch.allclose(net(x, dna, w), glob, atol=1e-4)
