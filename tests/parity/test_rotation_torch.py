"""The training side's rotation maps (train/deeprep_train/rotation.py,
PyTorch) against the crate's, on the fixture the crate writes and checks
(tests/fixtures/rotations_native.json, tests/native/rotation.rs): the 6D
map both ways and quaternions to matrices. Needs torch, so it runs in the
training venv (`train/.venv/bin/python -m pytest tests/parity`) and skips in
the test venv, which has none by design."""
import json
import os

import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="torch is only in train/.venv (tests never need it)")

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.fixture()
def rotation(train_import):
    return train_import("deeprep_train.rotation")


def fixture():
    f = json.load(open(os.path.join(ROOT, "tests", "fixtures", "rotations_native.json")))
    mats = torch.tensor(f["input_matrices"], dtype=torch.float64).reshape(-1, 3, 3)
    return mats, {k: torch.tensor(v, dtype=torch.float64) for k, v in f["outputs"].items()}


def test_6d_both_ways_and_quaternions_match_the_crate(rotation):
    mats, out = fixture()
    n = len(mats)
    six = rotation.matrix_to_6d(mats)
    assert float((six - out["6d"].reshape(n, 6)).abs().max()) < 1e-6
    back = rotation.sixd_to_matrix(out["6d"].reshape(n, 6))
    assert float((back - mats).abs().max()) < 1e-5
    q = out["quat"].reshape(n, 4)  # [x, y, z, w], as the crate writes them
    assert float((rotation.quat_to_matrix(q) - mats).abs().max()) < 1e-5


def test_geodesic_is_the_angle_between(rotation):
    mats, _ = fixture()
    a = torch.tensor(np.pi / 3, dtype=torch.float64)
    rz = torch.tensor([[torch.cos(a), -torch.sin(a), 0], [torch.sin(a), torch.cos(a), 0], [0, 0, 1]], dtype=torch.float64)
    d = rotation.geodesic(mats @ rz, mats)
    assert float((d - np.pi / 3).abs().max()) < 1e-6  # the fixture is float32
