"""The residual network's batches and losses: supervised terms (positions, 6D, root, velocities, joint speed, L2P, foot contact, short-time spectra), distillation and the adversarial view.

Part of deeprep_train.motion.residual (see its package docstring)."""

import torch

from deeprep_train.motion.residual_adv import cross_clip
from deeprep_train.motion.residual.data import PHASE_FRAMES, SCALE, features, fill_keys, mirror, sample_keys, sixd
from deeprep_train.motion.residual.net import apply, fk


# ---------------------------------------------------------------- training

def make_batch(clips, skel, b, n, rng, do_mirror, cross_p=0.0, regular=0.0, fill_share=0.0, fill_gaps=(10, 180),
               fill_law="log"):
    """b windows of n frames with random keys: the stacked features and
    offsets, the key lists, and which windows have a ground truth (False
    where `cross_p` spliced in keys from another clip, residual_adv.cross_clip;
    a cross-clip window keeps the first window's offsets). A `fill_share` of
    the windows are laid out as gaps in captured motion (data.fill_keys: every
    context frame a key, gaps of `fill_gaps` frames; issue 50), never cross-clip."""
    br, bq, gr, gq, ph, gt, offs, keysets, sup = [], [], [], [], [], [], [], [], []
    for _ in range(b):
        root, quat = clips.window(n, rng)
        off = skel.offsets
        if do_mirror and rng.random() < 0.5:
            root, quat = mirror(root, quat, skel)
            off = skel.mirror_offsets
        gap_fill = fill_share > 0 and rng.random() < fill_share
        keys = fill_keys(n, rng, fill_gaps, fill_law) if gap_fill else sample_keys(n, rng, regular=regular)
        spliced = False
        if cross_p > 0 and not gap_fill:
            root_b, quat_b = clips.window(n, rng)
            root, quat, spliced = cross_clip(root, quat, root_b, quat_b, keys, rng, cross_p)
        f = features(root, quat, keys)
        for lst, v in zip((br, bq, gr, gq, ph, gt), f):
            lst.append(v)
        offs.append(off)
        keysets.append(keys)
        sup.append(not spliced)
    st = [torch.stack(x) for x in (br, bq, gr, gq, ph, gt, offs)]
    return st, keysets, torch.tensor(sup)


def losses(net, skel, batch, w, sup=None, adv=None, gan_min_gap=0, teacher=None):
    """The training losses. `sup` [B] marks the windows with a ground truth
    (the supervised terms use only those); `adv` (residual_adv.Adversary)
    adds the adversarial term on every window, whose gradient skips the
    frames of intervals shorter than `gan_min_gap` frames (there the
    supervised terms alone train the output); `teacher` (a trained network,
    frozen) adds "distill" on every window: the supervised "pos", "rot" and
    "root" terms with the teacher's output as the truth, and with a
    "distill_speed" weight its "speed" term the same way. Returns the terms,
    their weighted "total", and the output's root-relative positions under
    "_rel" with the truth's (supervised windows) under "_grel", for the
    discriminator's update."""
    base_root, base_rot, gt_root, gt_rot, phase, gate, offs = batch
    root, rot = apply(net, base_root, base_rot, phase, gate)
    pos = fk(skel, root, rot, offs) / SCALE
    out, private = {}, {}
    if teacher is not None:
        # in the motion's terms, not the residual's: the 6D residual's length
        # along the base rotation's columns is free (Gram-Schmidt drops it),
        # and trained networks use that freedom (mean |6D residual| ~ 9)
        with torch.no_grad():
            t_root, t_rot = apply(teacher, base_root, base_rot, phase, gate)
            t_pos = fk(skel, t_root, t_rot, offs) / SCALE
        d = supervised(skel, root, rot, pos, t_root, t_rot, t_pos, {"speed": w.get("distill_speed")})
        out["distill"] = d["pos"] + d["rot"] + d["root"]
        if w.get("distill_speed"):
            # the teacher's joint speeds on every window, cross-clip ones too:
            # an L1 on positions to a target the narrower network cannot match
            # in detail favours smoother (slower) motion
            out["distill_speed"] = d["speed"]
    if adv is not None:
        rel = adversarial_view(pos - pos[:, :, :1], phase, gan_min_gap)
        gan = adv.g_loss(rel)
        private["_rel"] = rel.detach()
    S = torch.arange(pos.shape[0]) if sup is None else sup.nonzero().squeeze(1)
    if len(S):
        S = S.to(pos.device)
        gpos = fk(skel, gt_root[S], gt_rot[S], offs[S]) / SCALE
        out.update(supervised(skel, root[S], rot[S], pos[S], gt_root[S], gt_rot[S], gpos, w))
        if adv is not None:
            private["_grel"] = (gpos - gpos[:, :, :1]).detach()
    if adv is not None:
        out["gan"] = gan
    out["total"] = sum(w[k] * v for k, v in out.items() if w.get(k))
    return {**out, **private}


def adversarial_view(rel, phase, min_gap):
    """rel [B,N,J,3] as the adversary sees it: detached (no gradient) at the
    frames of intervals shorter than `min_gap` frames (phase [B,N,4]: frames
    since the previous key / 60 plus frames to the next / 60 is the
    interval's length); unchanged when `min_gap` is 0."""
    if min_gap <= 0:
        return rel
    short = ((phase[..., 1] + phase[..., 2]) * PHASE_FRAMES < min_gap - 0.5)[..., None, None]
    return torch.where(short, rel.detach(), rel)


def supervised(skel, root, rot, pos, gt_root, gt_rot, gpos, w):
    """The supervised terms on windows with a ground truth: the output's
    root, rotations and positions (/ SCALE) against the truth's."""
    out = {
        "pos": (pos - gpos).abs().mean(),
        "rot": (sixd(rot) - sixd(gt_rot)).abs().mean(),
        "root": ((root - gt_root) / SCALE).abs().mean(),
        "vel": ((pos[:, 1:] - pos[:, :-1]) - (gpos[:, 1:] - gpos[:, :-1])).abs().mean() * 10,
    }
    if w.get("speed"):
        # per-frame speed of each joint relative to the root, magnitude only:
        # where the direction of motion is uncertain, L1 on velocity vectors
        # favours standing still; this term asks for the truth's energy
        rel, grel = pos - pos[:, :, :1], gpos - gpos[:, :, :1]
        sp = (rel[:, 1:] - rel[:, :-1]).norm(dim=-1)
        gsp = (grel[:, 1:] - grel[:, :-1]).norm(dim=-1)
        out["speed"] = (sp - gsp).abs().mean() * 10
    if w.get("l2p"):
        # the position error in L2P's units (each joint coordinate over its
        # spread in training windows): heights count about 7x more than in
        # "pos", as they do in the evaluation
        B, N = pos.shape[:2]
        out["l2p"] = ((pos - gpos).reshape(B, N, -1).abs() * skel.inv_sd * SCALE).mean()
    if w.get("foot"):
        # contact-aware foot velocity: where the truth's foot or toe is near
        # the window's floor and nearly still, the output's should be still
        f = skel.feet
        fp, gfp = pos[:, :, f], gpos[:, :, f]
        gv = (gfp[:, 1:] - gfp[:, :-1])[..., [0, 2]].norm(dim=-1)
        floor = gpos[:, :, f, 1].amin(dim=(1, 2), keepdim=True)
        contact = ((gfp[:, 1:, :, 1] < floor + 5 / SCALE) & (gv < 1 / SCALE)).float()
        v = (fp[:, 1:] - fp[:, :-1])[..., [0, 2]].norm(dim=-1)
        out["foot"] = (v * contact).sum() / contact.sum().clamp(min=1) * 10
    if w.get("spectral"):
        # short-time spectra of the root-relative positions (64-frame Hann
        # windows, hop 16): NPSS compares power spectra of short windows, and
        # an L1 on positions alone lets the output be smoother than the truth
        out["spectral"] = spectral_l1(pos - pos[:, :, :1], gpos - gpos[:, :, :1])
    if w.get("npss"):
        # the evaluation's NPSS on the whole window's root-relative positions:
        # where and how much the body moves, not only how fast (issue 47:
        # root-only keys' arms, train/notes/cond.md)
        B, N = pos.shape[:2]
        out["npss"] = npss_loss((pos - pos[:, :, :1]).reshape(B, N, -1), (gpos - gpos[:, :, :1]).reshape(B, N, -1))
    return out


def npss_loss(a, b):
    """motion.eval's NPSS (LaFAN1's) as a loss: a, b [B, N, F] the output's
    and the truth's features over N frames; each window's earth mover's
    distance between the normalized cumulative power spectra per feature,
    weighted by the truth's power, averaged over the windows. On the
    window's frames at once (the evaluation scores each key interval); it
    grows with N, so it is divided by N here."""
    pa = torch.fft.fft(a, dim=1).real ** 2
    pb = torch.fft.fft(b, dim=1).real ** 2
    ta, tb = pa.sum(1), pb.sum(1)
    w = tb / tb.sum(1, keepdim=True).clamp(min=1e-12)
    ca = torch.cumsum(pa / ta.clamp(min=1e-12)[:, None], 1)
    cb = torch.cumsum(pb / tb.clamp(min=1e-12)[:, None], 1)
    return ((ca - cb).abs().sum(1) * w).sum(1).mean() / a.shape[1]


def spectral_l1(a, b, n_fft=64, hop=16):
    """Mean L1 between the short-time magnitude spectra of a and b
    [B,N,J,3] along N, in the signals' units (magnitudes over n_fft/2)."""
    B, N = a.shape[:2]
    win = torch.hann_window(n_fft, device=a.device)

    def mag(x):
        x = x.reshape(B, N, -1).transpose(1, 2).reshape(-1, N)
        return torch.stft(x, n_fft, hop, window=win, center=False, return_complex=True).abs()

    return (mag(a) - mag(b)).abs().mean() / (n_fft / 2) * 10
