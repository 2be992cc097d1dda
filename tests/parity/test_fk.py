"""The training code's BVH reader and FK (train/deeprep_train/bvh.py)
against the crate's, on the fixture the crate writes and checks
(tests/fixtures/fk_native.json, tests/native/bvh.rs)."""
import json
import os

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def load_bvh_module():
    # deeprep_train is a package under train/, not installed in this venv;
    # its bvh module needs numpy only
    import importlib.util
    spec = importlib.util.spec_from_file_location("deeprep_bvh", os.path.join(ROOT, "train", "deeprep_train", "bvh.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_training_fk_matches_the_crate(tmp_path):
    bvh = load_bvh_module()
    f = json.load(open(os.path.join(ROOT, "tests", "fixtures", "fk_native.json")))
    path = tmp_path / "clip.bvh"
    path.write_text(f["bvh"])
    clip = bvh.read_bvh(str(path))
    assert len(clip[0]) == f["joints"]
    pos, rot = bvh.global_fk(clip)
    want = np.asarray(f["positions"]).reshape(f["frames"], f["joints"], 3)
    assert pos.shape == want.shape
    assert float(np.abs(pos - want).max()) < 1e-4
    # rotations are orthonormal
    eye = np.einsum("fjik,fjlk->fjil", rot, rot)
    assert float(np.abs(eye - np.eye(3)).max()) < 1e-9
