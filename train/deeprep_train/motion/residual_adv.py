"""The residual network's adversarial stage (issue 19, stage 2; Sec. 5.2.5
and 5.2.7 applied to motion/residual.py's network).

Two pieces on top of the supervised training in `residual train`:

- **Cross-clip keys** (Sec. 5.2.7, rule 2): when a key interval exceeds
  three seconds, with a probability proportional to its length, the next
  key comes from a different clip, turned about the vertical at random and
  placed at a root distance proportional to the interval. Such a window
  has no ground truth between those keys, so it gets no supervised loss,
  only the adversarial one.
- **An LSGAN discriminator** (eq. 5.7-5.8, `motion.nets.Discriminator`, the
  generator's) on root-relative joint positions: real windows of captured
  motion against the network's output, keys included. The network's loss
  asks for the discriminator's eq. 5.8 target, at `--gan-weight` beside the
  supervised terms.
"""
import math

import torch

from deeprep_train.motion.nets import GAN_TARGET, Discriminator
from deeprep_train.rotation import quat_to_matrix

SECONDS = 60  # frames per second of resid60.npz
MIN_CROSS_GAP = 3 * SECONDS
MAX_GAP = 300  # the longest interval residual.sample_keys draws in training


def quat_mul(a, b):
    """Hamilton product of [..., 4] quaternions [w, x, y, z]."""
    aw, ax, ay, az = a.unbind(-1)
    bw, bx, by, bz = b.unbind(-1)
    return torch.stack([aw * bw - ax * bx - ay * by - az * bz,
                        aw * bx + ax * bw + ay * bz - az * by,
                        aw * by - ax * bz + ay * bw + az * bx,
                        aw * bz + ax * by - ay * bx + az * bw], -1)


def cross_clip(root_a, quat_a, root_b, quat_b, keys, rng, p):
    """Rule 2 on a window: for the first key interval of at least three
    seconds that the draw picks (probability p * gap / MAX_GAP), frames from
    that interval's end key on come from window b instead, turned about the
    vertical by a random angle about their first frame and moved so that
    frame's root lies at a random direction from the interval's first key,
    at a distance between 0.5 and 1.5 times what window a's own root
    travelled over the interval (heights stay b's). Returns (root, quat,
    spliced): the windows unchanged and False when no interval was picked.
    root [N,3], quat [N,K,4] [w, x, y, z] with the root joint first."""
    for ka, kb in zip(keys[:-1], keys[1:]):
        g = kb - ka
        if g < MIN_CROSS_GAP or rng.random() >= p * g / MAX_GAP:
            continue
        phi = rng.uniform(-math.pi, math.pi)
        qy = torch.tensor([math.cos(phi / 2), 0.0, math.sin(phi / 2), 0.0])  # [w, x, y, z]
        turn = quat_to_matrix(qy[[1, 2, 3, 0]])
        travelled = float((root_a[kb, [0, 2]] - root_a[ka, [0, 2]]).norm())
        dist = travelled * rng.uniform(0.5, 1.5)
        ang = rng.uniform(-math.pi, math.pi)
        target = root_a[ka].clone()
        target[0] += dist * math.sin(ang)
        target[2] += dist * math.cos(ang)
        rb = (root_b[kb:] - root_b[kb]) @ turn.T
        rb[:, 0] += target[0]
        rb[:, 2] += target[2]
        rb[:, 1] = root_b[kb:, 1]
        qb = quat_b[kb:].clone()
        qb[:, 0] = quat_mul(qy.expand_as(qb[:, 0]), qb[:, 0])
        root = torch.cat([root_a[:kb], rb])
        quat = torch.cat([quat_a[:kb], qb])
        return root, quat, True
    return root_a, quat_a, False


class Adversary:
    """The discriminator, its optimizer and the two LSGAN losses on
    root-relative positions [B, N, J, 3] (already divided by the scale)."""

    def __init__(self, joints, lr, device):
        self.D = Discriminator(joints * 3).to(device)
        self.opt = torch.optim.Adam(self.D.parameters(), lr=lr, betas=(0.5, 0.99))

    @staticmethod
    def _input(rel):
        B, N = rel.shape[:2]
        return rel.reshape(B, N, -1).transpose(1, 2)

    def d_step(self, real_rel, fake_rel):
        """One discriminator update (eq. 5.7: real -> 1, fake -> -1)."""
        ld = ((self.D(self._input(real_rel.detach())) - 1) ** 2).mean() \
            + ((self.D(self._input(fake_rel.detach())) + 1) ** 2).mean()
        self.opt.zero_grad()
        ld.backward()
        self.opt.step()
        return float(ld.detach())

    def g_loss(self, fake_rel):
        """The network's adversarial loss (eq. 5.8's target)."""
        return ((self.D(self._input(fake_rel)) - GAN_TARGET) ** 2).mean()

    def state(self):
        return {"D": self.D.state_dict(), "D_opt": self.opt.state_dict()}

    def load(self, s):
        """Loads a checkpoint's discriminator; False when it has none."""
        if "D" not in s:
            return False
        self.D.load_state_dict(s["D"])
        if "D_opt" in s:
            self.opt.load_state_dict(s["D_opt"])
        return True
