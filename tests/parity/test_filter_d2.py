"""Appendix D.2's filter (train/deeprep_train/motion/filter_d2.py): the
outlier rule removes frames far above the median error and the pieces left
shorter than MIN_SEGMENT, and the residual network's clips split where
frames went (train/deeprep_train/motion/residual.py's Clips). Needs torch,
so it runs in the training venv and skips in the test venv."""

import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="torch is only in train/.venv (tests never need it)")


@pytest.fixture()
def mods(train_import):
    return train_import("deeprep_train.motion.filter_d2"), train_import("deeprep_train.motion.residual")


def test_outliers_and_the_short_pieces_they_leave_are_removed(mods):
    f, _ = mods
    n = f.MIN_SEGMENT
    err = np.ones(5 * n, np.float32) + np.linspace(0, 0.1, 5 * n)
    err[2 * n] = 50.0            # a spike in the first segment: it splits there
    err[3 * n + 10] = 50.0       # a spike 10 frames into the second: the 10 frames before go too
    starts, lens = np.array([0, 3 * n]), np.array([3 * n, 2 * n])
    keep, thr, c = f.keep_mask(err, starts, lens, mads=8)
    assert 1.1 < thr < 50
    assert not keep[2 * n] and not keep[3 * n + 10]
    assert keep[:2 * n].all()
    assert not keep[2 * n + 1:3 * n].any()  # the n - 1 frames after the spike: too short
    assert not keep[3 * n:3 * n + 10].any() and keep[3 * n + 11:].all()
    assert c["noisy_frames"] == 2 and c["short_piece_frames"] == (n - 1) + 10
    assert c["removed_frames"] == int((~keep).sum())
    assert c["segments_before"] == 2 and c["segments_after"] == 2


def test_clips_split_where_frames_were_removed(mods):
    _, r = mods
    lens = np.array([10, 6])
    d = {"train_root": np.arange(16 * 3, dtype=np.float32).reshape(16, 3),
         "train_quat": np.zeros((16, 2, 4), np.float32), "train_len": lens, "train_name": np.array(["a", "b"])}
    keep = np.ones(16, bool)
    keep[[3, 4, 10]] = False
    c = r.Clips(d, "train", keep)
    assert c.lens.tolist() == [3, 5, 5] and c.starts.tolist() == [0, 3, 8]
    assert c.names == ["a+0", "a+5", "b+1"]
    assert c.root[3, 0].item() == 15.0  # frame 5 of the first clip
