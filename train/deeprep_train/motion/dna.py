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


#: how far (in a pass' frames) each DNA pose steers the conditional
#: network's output: half a training window (480 frames), so each frame pools
#: about the 2-3 poses a training window held (train/notes/cond.md)
DNA_WINDOW = 240


def frame_weights(poses, frames, radius=DNA_WINDOW):
    """How much each DNA pose steers each frame of an output of `frames`
    frames: the poses are spread evenly over the output in the order given
    (pose j at frame (2j + 1) * frames / (2 * poses)), each weighing
    1 - distance / radius on the frames within `radius` of its place (a tent,
    so the code changes smoothly from frame to frame), normalized to sum 1 on
    every frame; a frame no tent reaches takes its nearest pose (the earlier
    on a tie). Returns float32 [poses, frames]. The crate's
    `motion::dna::frame_weights` is the same rule (tests/parity/test_dna.py)."""
    w = np.zeros((poses, frames), np.float64)
    if poses == 0 or frames == 0:
        return w.astype(np.float32)
    t = np.arange(frames, dtype=np.float64)
    at = (2 * np.arange(poses, dtype=np.float64) + 1) * frames / (2 * poses)
    d = np.abs(t[None, :] - at[:, None])
    if radius > 0:
        w = np.maximum(0.0, 1.0 - d / radius)
    total = np.zeros(frames)
    for j in range(poses):   # in order, as the crate sums
        total += w[j]
    none = total == 0
    w[np.argmin(d, axis=0)[none], np.arange(frames)[none]] = 1.0
    total[none] = 1.0
    return (w / total).astype(np.float32)
