"""motion.eval's heading-free NPSS (issue 47): the rotations it scores do not
change when the whole body turns about the vertical, and a body that turns
scores as one that does not."""
import numpy as np


def test_heading_free_rotations_ignore_a_turn_about_the_vertical(train_import):
    ev = train_import("deeprep_train.motion.eval")
    rng = np.random.default_rng(0)
    F, J = 40, 4
    rot = ev.axis_rot("X", rng.normal(size=(F, J)) * 0.5) @ ev.axis_rot("Z", rng.normal(size=(F, J)) * 0.5)
    turn = ev.axis_rot("Y", np.linspace(0, 6, F))[:, None]  # a spin of almost a full turn
    free = ev.heading_free(rot)
    assert np.abs(ev.heading_free(turn @ rot) - free).max() < 1e-12
    # what is left has no heading: its hip faces +z in the horizontal plane
    f = free[:, 0, :, 2]
    assert np.abs(f[:, 0]).max() < 1e-12 and (f[:, 2] > 0).all()
    # and it is still a rotation per joint
    eye = np.einsum("fjik,fjlk->fjil", free, free)
    assert np.abs(eye - np.eye(3)).max() < 1e-12


def test_npss_of_a_spinning_body_falls_to_zero_without_the_heading(train_import):
    ev = train_import("deeprep_train.motion.eval")
    F = 60
    still = np.broadcast_to(ev.axis_rot("X", np.full((1, 3), 0.3)), (F, 3, 3, 3)).copy()
    spin = ev.axis_rot("Y", np.linspace(0, 4, F))[:, None] @ still

    def quats(r):
        return ev.mat_to_quat(r).reshape(1, F, -1)

    assert ev.npss(quats(still), quats(spin)) > 0.1
    assert ev.npss(quats(ev.heading_free(still)), quats(ev.heading_free(spin))) < 1e-9
