"""Motion DNA's representative frames (thesis Sec. 5.2.5), once for the
training side: the frames of largest joint-rotation change from their two
neighbours, at least MIN_SPACING apart. The crate's
`motion::dna::representative_frames` is the same rule, checked against this
by tests/parity/test_dna.py on tests/fixtures/dna_native.json. numpy only."""
import numpy as np

from deeprep_train.bvh import local_fk

#: training's representative-frame count: one per this many frames
FRAMES_PER_DNA = 180
#: minimum spacing of representative frames, in frames
MIN_SPACING = 30


def dna_count(frames):
    """How many DNA frames training uses for a window of `frames` frames."""
    return max(1, frames // FRAMES_PER_DNA)


def representative_frames(features, count, spacing=MIN_SPACING, exclude=()):
    """The `count` frames of largest change of `features` ([N, D], one row
    per frame) between their two neighbours, at least `spacing` apart, in
    frame order (fewer when the clip is too short). Ties go to the earlier
    frame, as in the crate. Frames in `exclude` are never picked (training
    leaves out a window's keys)."""
    x = np.asarray(features, dtype=np.float64).reshape(len(features), -1)
    change = np.zeros(len(x))
    if len(x) > 2:
        change[1:-1] = np.linalg.norm(x[2:] - x[:-2], axis=1)
    picked = []
    skip = set(int(v) for v in exclude)
    for i in np.argsort(-change, kind="stable"):
        if len(picked) == count:
            break
        if int(i) not in skip and all(abs(int(i) - j) >= spacing for j in picked):
            picked.append(int(i))
    return sorted(picked)


def rotation_features(bvh):
    """Per frame, the local rotation matrices of every joint but the root,
    flattened: what the crate measures change on (`Keyframe::rotations`)."""
    rot = local_fk(bvh)[1]
    return rot[:, 1:].reshape(len(rot), -1)


def representative_frames_of_clip(bvh, count):
    """representative_frames on a BVH clip (deeprep_train.bvh.read_bvh's
    tuple), measured on local joint rotations like the crate."""
    return representative_frames(rotation_features(bvh), count)
