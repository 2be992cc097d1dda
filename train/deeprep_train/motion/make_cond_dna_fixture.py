"""A small conditional network with a Motion DNA input, random weights, for
the runtime's DNA path (tests/native/motion/cond.rs): the bundled
tween_cond.onnx has no DNA input, so without this the per-frame `dna_w`
(motion::dna::frame_weights) would only be tested when a DNA network is
bundled. Writes tests/fixtures/cond_dna/: tween_cond.onnx (width 16, the
bundled architecture's stride 2 and skip), its manifest and the motion
fixture's DNA case (root-only keys over 500 frames, the window's own
representative poses as DNA, what cond.py computes with onnxruntime).

  train/.venv/bin/python -m deeprep_train.motion.make_cond_dna_fixture
"""
import os

import numpy as np
import torch

from deeprep_train.motion import cond
from deeprep_train.paths import CACHE, ROOT

OUT = os.path.join(ROOT, "tests", "fixtures", "cond_dna")


def main():
    torch.manual_seed(5)
    d = np.load(os.path.join(CACHE, "resid60.npz"))
    skel = cond.Skeleton(d)
    J, K = len(skel.parents), skel.K
    net = cond.CondTween(K, J, 16, [1, 2, 4], stride=2, skip=True, dna=True)
    with torch.no_grad():
        for p in net.parameters():
            p.normal_(0.0, 0.05)
        # the residual small enough that the 6D stays well conditioned, the DNA code large enough to matter
        net.core.out.weight.mul_(0.2)
        net.dna_out.weight.normal_(0.0, 0.3)
    prior = cond.prior_pose(cond.Clips(d, "train"))
    ck = os.path.join(CACHE, "cond_dna_fixture.pt")
    state = {k: v.clone() for k, v in net.state_dict().items()}
    torch.save({"net": state, "ema": state, "prior": prior, "step": 0, "J": J, **net.arch()}, ck)
    os.makedirs(OUT, exist_ok=True)
    cond.main(["export", "--ckpt", ck, "--out-dir", OUT, "--dna-case-only"])
    # the network's own input/output fixture is not needed here (the motion fixture checks it through tract)
    os.remove(os.path.join(OUT, "fixtures", "tween_cond.json"))
    os.remove(ck)


if __name__ == "__main__":
    main()
