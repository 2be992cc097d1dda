"""Motion DNA's representative frames: the training side's one
implementation (train/deeprep_train/motion/dna.py) against the crate's
`motion::dna::representative_frames`, on the fixture the crate writes and
checks (tests/fixtures/dna_native.json, tests/native/motion.rs)."""
import json
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_training_dna_frames_match_the_crate(tmp_path, monkeypatch):
    # deeprep_train is not installed in this venv; these modules need numpy only
    monkeypatch.syspath_prepend(os.path.join(ROOT, "train"))
    for m in [m for m in sys.modules if m.startswith("deeprep_train")]:
        monkeypatch.delitem(sys.modules, m)
    from deeprep_train.bvh import read_bvh
    from deeprep_train.motion import dna

    f = json.load(open(os.path.join(ROOT, "tests", "fixtures", "dna_native.json")))
    assert f["min_spacing"] == dna.MIN_SPACING
    path = tmp_path / "clip.bvh"
    path.write_text(f["bvh"])
    clip = read_bvh(str(path))
    for count, want in enumerate(f["picks"], start=1):
        assert dna.representative_frames_of_clip(clip, count) == want, count
    # which DNA poses steer each frame of the conditional network's output
    assert f["dna_window"] == dna.DNA_WINDOW
    for c in f["frame_weights"]:
        got = dna.frame_weights(c["poses"], c["frames"], c["radius"])
        want = np.array(c["weights"], np.float32)
        assert np.array_equal(got.reshape(-1), want), c


def test_spacing_and_ties():
    sys.path.insert(0, os.path.join(ROOT, "train"))
    try:
        from deeprep_train.motion.dna import representative_frames
    finally:
        sys.path.pop(0)
    flat = [[0.0]] * 100
    # no change anywhere: ties go to the earliest frames, spaced 30 apart
    assert representative_frames(flat, 3) == [0, 30, 60]
    # too short to space them: fewer than asked
    assert representative_frames([[0.0], [1.0], [3.0]], 2) == [1]
