"""`residual pick` (train/deeprep_train/motion/residual.py), the rule that
chooses a snapshot from its training-take `residual eval --json` results:
the ratios it compares are the ablation table's (`ablation.ratio_to_slerp`),
and each branch of the rule (targets met, beats SLERP+LERP only, neither)
picks the snapshot its docstring says. Needs torch (residual.py imports
it), so it runs in the training venv and skips in the test venv."""

import json
from types import SimpleNamespace

import pytest

pytest.importorskip("torch", reason="torch is only in train/.venv (tests never need it)")

GAPS = (30, 60, 120, 300)


def _eval(path, l2p, npss, speed, mpjpe=0.9):
    """A results file: SLERP+LERP scores 1 on every metric, so the model's
    numbers are its ratios. Gaps written out of order on purpose."""
    gaps = {str(g): {"slerp": {"l2p": 1.0, "npss": 1.0, "mpjpe": 1.0},
                     "model": {"l2p": a, "npss": b, "mpjpe": mpjpe, "speed_ratio": c}}
            for g, a, b, c in reversed(list(zip(GAPS, l2p, npss, speed)))}
    path.write_text(json.dumps({"split": "train", "ckpt": path.stem, "gaps": gaps}))
    return str(path)


@pytest.fixture()
def modules(train_import):
    return train_import("deeprep_train.motion.residual"), train_import("deeprep_train.motion.ablation")


def _pick(residual, files, tmp_path, margin=0.10):
    out = tmp_path / "pick.json"
    best = residual.pick(SimpleNamespace(results=files, speed_margin=margin, l2p_margin=margin, json=str(out)))
    return best, json.loads(out.read_text())


def test_ratios_are_in_gap_order_and_shared_with_the_ablation(modules, tmp_path):
    residual, ablation = modules
    f = _eval(tmp_path / "a.json", (0.8, 0.7, 0.6, 0.75), (0.9, 0.8, 0.7, 0.85), (0.9, 0.85, 0.84, 0.9))
    best, written = _pick(residual, [f], tmp_path)
    g = json.load(open(f))["gaps"]
    assert best["l2p_ratio"] == ablation.ratio_to_slerp(g, "l2p") == [0.8, 0.7, 0.6, 0.75]
    assert best["npss_ratio"] == [0.9, 0.8, 0.7, 0.85]
    assert best["speed_ratio"] == [0.9, 0.85, 0.84, 0.9]
    assert written["picked"] == "a" and best["meets_issue_targets"]
    assert best["mean_l2p_ratio"] == pytest.approx(0.7125)


def test_the_lowest_mean_l2p_among_those_that_meet_the_targets(modules, tmp_path):
    residual, _ = modules
    ok = (0.9, 0.85, 0.84, 0.9)
    a = _eval(tmp_path / "a.json", (0.8, 0.7, 0.6, 0.75), (0.9, 0.8, 0.7, 0.85), ok)
    b = _eval(tmp_path / "b.json", (0.8, 0.7, 0.6, 0.70), (0.9, 0.8, 0.7, 0.85), ok)
    # lower still, but joint speed at 120 outside the margin (0.75 < 0.8)
    c = _eval(tmp_path / "c.json", (0.5, 0.5, 0.5, 0.5), (0.9, 0.8, 0.7, 0.85), (0.9, 0.85, 0.75, 0.9))
    # lower still, but NPSS at 300 not 10% below SLERP+LERP's
    d = _eval(tmp_path / "d.json", (0.5, 0.5, 0.5, 0.5), (0.9, 0.8, 0.7, 0.95), ok)
    best, written = _pick(residual, [a, b, c, d], tmp_path)
    assert written["picked"] == "b"
    assert [r["meets_issue_targets"] for r in written["candidates"]] == [True, True, False, False]
    # without the speed margin c meets the targets and is the lowest
    assert _pick(residual, [a, b, c, d], tmp_path, margin=0.0)[1]["picked"] == "c"


def test_without_targets_the_speed_closest_to_the_truth_then_the_lowest_mpjpe(modules, tmp_path):
    residual, _ = modules
    npss = (0.9, 0.8, 0.95, 0.95)  # beats SLERP+LERP, not by 10% at 120 and 300
    a = _eval(tmp_path / "a.json", (0.8, 0.7, 0.6, 0.7), npss, (0.9, 0.9, 0.6, 0.6))
    b = _eval(tmp_path / "b.json", (0.9, 0.9, 0.9, 0.9), npss, (0.9, 0.9, 0.9, 1.1))
    assert _pick(residual, [a, b], tmp_path)[1]["picked"] == "b"
    # neither beats SLERP+LERP everywhere: the lowest mean MPJPE ratio
    c = _eval(tmp_path / "c.json", (1.1, 0.9, 0.9, 0.9), npss, (0.9, 0.9, 0.9, 1.0), mpjpe=0.95)
    d = _eval(tmp_path / "d.json", (0.9, 0.9, 0.9, 1.2), npss, (0.9, 0.9, 0.9, 1.0), mpjpe=0.85)
    assert _pick(residual, [c, d], tmp_path)[1]["picked"] == "d"
