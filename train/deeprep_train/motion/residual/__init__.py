"""Supervised in-betweening in a key-relative frame (issue 19, stage 1).

A 1-D convolutional network (dilated residual blocks) reads SLERP+LERP of
the keys, expressed in the first key's frame (its root x/z position and
heading removed), with each frame's phase between its keys, and predicts a
residual on it: the root position and a 6D value per joint (Zhou et al.'s
continuous representation, ch. 4), scaled by a gate that is zero at keys, so
keys are exact by construction. Training is supervised only: L1 on global
joint positions (FK), on the 6D values and on the root, plus an L1 on
frame-to-frame joint velocities so the motion keeps its speed. This is the
"supervised stage first" of issue 19; `train --gan-weight W [--cross-clip P]`
adds the adversarial stage (motion/residual_adv.py: an LSGAN discriminator
and cross-clip keys, Sec. 5.2.5 and 5.2.7). Motion DNA is the generator's.

Data: the CMU clips of ../shared/data read here (train/cache/resid60.npz),
at 60 fps with motion/data.py's floor filter and take-wise split;
augmented with left/right mirroring (train --mirror) and random key gaps.

  train/.venv/bin/python -m deeprep_train.motion.residual prepare
  train/.venv/bin/python -m deeprep_train.motion.residual train --minutes 150 [--resume]
  train/.venv/bin/python -m deeprep_train.motion.residual eval [--split train|val] [--ckpt PATH]

Checkpoints: train/cache/resid/ckpt.pt (every --save-every steps, with the
optimizer and the weights' moving average) and snapshots gen_<step>.pt.
`portable` writes train/checkpoints/tween_resid_w128b.pt (weights and their moving
average in float16, no optimizer state; committed, so a new machine resumes
with `train --resume`, which falls back to it when train/cache is empty).
"""
from deeprep_train.motion.residual.data import Clips, GATE_FRAMES, OUT, PHASE_FRAMES, PORTABLE, SCALE, Skeleton, canonical, features, from_sixd, key_phase, mirror, prepare, quat_to_mat, rot_y, sample_keys, fill_keys, add_fill_args, fill_band, sixd, slerp  # noqa: E501
from deeprep_train.motion.residual.net import Block, DILATIONS, ResidualTween, apply, arch, build, fk, grow, load_ema, net_input, upsample2  # noqa: E501
from deeprep_train.motion.residual.losses import adversarial_view, losses, make_batch, npss_loss, spectral_l1, supervised  # noqa: E501
from deeprep_train.motion.residual.evaluation import L2P_SD, evaluate, l2p_sd, pick  # noqa: E501
from deeprep_train.motion.residual.training import train  # noqa: E501
from deeprep_train.motion.residual.export import export, portable, prune  # noqa: E501

__all__ = [
    "Clips",
    "GATE_FRAMES",
    "OUT",
    "PHASE_FRAMES",
    "PORTABLE",
    "SCALE",
    "Skeleton",
    "canonical",
    "features",
    "from_sixd",
    "key_phase",
    "mirror",
    "prepare",
    "quat_to_mat",
    "rot_y",
    "sample_keys",
    "fill_keys",
    "add_fill_args",
    "fill_band",
    "sixd",
    "slerp",
    "Block",
    "DILATIONS",
    "ResidualTween",
    "apply",
    "arch",
    "build",
    "fk",
    "grow",
    "load_ema",
    "net_input",
    "upsample2",
    "adversarial_view",
    "losses",
    "make_batch",
    "npss_loss",
    "spectral_l1",
    "supervised",
    "L2P_SD",
    "evaluate",
    "l2p_sd",
    "pick",
    "train",
    "export",
    "portable",
    "prune",
]
