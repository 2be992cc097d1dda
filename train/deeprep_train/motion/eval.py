"""Evaluates in-betweening on the validation takes (never trained on), at
gaps of 30, 60, 120 and 300 frames (60 fps), for the model and two
baselines computed on the same windows: zero-velocity and SLERP+LERP.

Each validation clip is resampled to 60 fps (train/deeprep_train/motion/data.py's rule),
then `deeprep inbetween --from-bvh CLIP --keys s, s+g, s+2g, ...` is run for
every method, so every interval of g frames is one evaluation window.

Metrics, on the frames strictly between keys:
  L2P   LaFAN1's: global positions (each window re-centred on its first
        key's root x/z) normalized by the per-coordinate mean and std of
        training windows centred the same way, L2 norm per frame, averaged.
  L2Q   LaFAN1's: global joint quaternions (sign matched to the ground
        truth), L2 norm per frame, averaged.
  NPSS  LaFAN1's normalized power spectrum similarity on the global
        quaternions of each window (an earth mover's distance summed over
        frequencies, so it grows with the window length: compare methods at
        one gap, not gaps with each other).
  foot skating: mean horizontal foot speed (units/frame) while the foot is
        within 5 units of the clip's floor.
  acceleration: mean norm of the second difference of global joint
        positions (units/frame^2) on the frames between keys; the ground
        truth's is printed beside it. Far above it means jitter, far below
        means motion smoother (stiffer) than captured motion.
  key alignment: the model's mean key errors before/after post-processing.

Writes docs/inbetween_eval.json and docs/inbetween_eval.png and prints a
Markdown table.  Run: train/.venv/bin/python -m deeprep_train.motion.eval

Options (--help): --gaps, --methods, --split train (training takes, for
choosing settings), --dna-gt (a diagnostic). With --hybrids it also scores
the model's output with one channel group (root position, root rotation,
all joints, spine, arms, hands or legs) replaced by SLERP+LERP's, and
writes docs/inbetween_hybrids.json instead: which part of the model gains
or loses against interpolation. Two more diagnostics write the same file:
--blend w1,w2,... (the model's local pose blended towards SLERP+LERP's by
each weight) and --cubic (Catmull-Rom splines through the keys, and the
model with the spline's root position).
"""
import argparse
import datetime
import json
import os
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field

import numpy as np

from deeprep_train.bvh import axis_rot, fk_from_local, global_fk, local_fk, mat_to_quat, read_bvh, resample  # noqa: E402,F401
from deeprep_train.motion.dna import representative_frames_of_clip  # noqa: E402
from deeprep_train.motion.data import DATA, TRUE_FPS, VALIDATION, cli, take_of  # noqa: E402

from deeprep_train.paths import ROOT, CACHE  # noqa: E402
# Methods: "zerovel", "slerp", "model" (CLI defaults), and the names below.
FIXED_ARGS = {
    # the model with post-processing that makes keys exact but leaves the
    # feet as synthesized (CLI --no-foot-lock), or with foot locking
    "model-nolock": ["--method", "model", "--no-foot-lock"],
    "model-lock": ["--method", "model", "--foot-lock"],
    # diagnostic: the same without post-processing (keys not made exact)
    "model-nopost": ["--method", "model", "--no-post"],
    # the supervised residual on SLERP+LERP (issue 19, stage 1; train/deeprep_train/motion/residual.py)
    "residual": ["--method", "residual"],
    # the Generative Tweening generator whatever the residual manifest says
    "generator": ["--method", "generator", "--no-foot-lock"],
    # the networks from partial keys taken from the clip (issue 20): the root's
    # position alone (Sec. 5.4.1), or every joint's x and y plus the root (Sec. 5.4.2)
    "keys-root": ["--method", "model", "--key-kind", "root"],
    "keys-xy": ["--method", "model", "--key-kind", "xy"],
    # the conditional network (issue 47) on the same keys, named explicitly
    "cond-root": ["--method", "cond", "--key-kind", "root"],
    "cond-xy": ["--method", "cond", "--key-kind", "xy"],
    "cond-pose": ["--method", "cond", "--key-kind", "pose"],
}


def method_args(m):
    """The CLI arguments of method m. Besides FIXED_ARGS: "variation-V" (the
    model without foot locking at --variation V, the share of the networks'
    departure from SLERP+LERP kept; 0 is SLERP+LERP itself), "generator-V"
    and "residual-V" (those networks at variation V); any other name is
    passed as --method."""
    if m in FIXED_ARGS:
        return FIXED_ARGS[m]
    if m.startswith("cond-") and m.count("-") == 2:  # cond-KIND-V: the conditional network at variation V
        _, kind, v = m.split("-")
        return ["--method", "cond", "--key-kind", kind, "--variation", v]
    kind, _, v = m.partition("-")
    if v and kind == "variation":
        return ["--method", "model", "--no-foot-lock", "--variation", v]
    if v and kind == "generator":
        return ["--method", "generator", "--no-foot-lock", "--variation", v]
    if v and kind == "residual":
        return ["--method", "residual", "--variation", v]
    return ["--method", m]


def runs_model(m):
    """Whether method m runs a pipeline whose key errors before and after
    post-processing the CLI reports (--method model, generator or cond)."""
    return method_args(m)[1] in ("model", "generator", "cond")


HYBRID_GROUPS = ["root position", "root height", "root rotation", "joints", "spine", "arms", "hands", "legs"]


@dataclass
class Config:
    """What one evaluation run scores (see parse_args for each option)."""
    gaps: list = field(default_factory=lambda: [30, 60, 120, 300])
    methods: list = field(default_factory=lambda: "zerovel,slerp,model,model-lock,variation-1,generator,residual,residual-1".split(","))
    split: str = "val"
    dna_gt: bool = False
    hybrids: dict = field(default_factory=dict)
    blends: dict = field(default_factory=dict)
    cubic: list = field(default_factory=list)
    hybrid_base: str = None
    json: str = None

    @property
    def diagnostics(self):
        """every diagnostic row, in print order"""
        return list(self.hybrids) + list(self.blends) + self.cubic


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ints = lambda s: [int(x) for x in s.split(",") if x]  # noqa: E731
    names = lambda s: [x for x in s.split(",") if x]  # noqa: E731
    d = Config()
    ap.add_argument("--gaps", type=ints, default=d.gaps, help="gaps in frames at 60 fps (default 30,60,120,300)")
    ap.add_argument("--methods", type=names, default=d.methods, help="comma-separated methods (see method_args)")
    ap.add_argument("--split", choices=["val", "train"], default="val",
                    help="train: score training takes instead (for choosing settings without looking at "
                         "validation takes), written to docs/inbetween_eval_train.json")
    ap.add_argument("--dna-gt", action="store_true",
                    help="diagnostic, leaks the ground truth: the model methods get the clip's own representative "
                         "frames as Motion DNA, as in training, instead of none; never a result to report")
    ap.add_argument("--hybrids", action="store_true",
                    help="also score the model's output with one channel group taken from SLERP+LERP's")
    ap.add_argument("--blend", type=names, default=[],
                    help="weights w: also score the model's output blended towards SLERP+LERP's by w "
                         "(0 = model, 1 = SLERP+LERP)")
    ap.add_argument("--cubic", action="store_true",
                    help="also score Catmull-Rom splines through the keys, and the model with the spline's root position")
    ap.add_argument("--hybrid-of", default=None, help="the method the hybrids start from (default: the first model method)")
    ap.add_argument("--json", default=None, help="write the results here instead of docs/inbetween_eval*.json (no plot)")
    a = ap.parse_args(argv)
    return Config(
        gaps=a.gaps, methods=a.methods, split=a.split, dna_gt=a.dna_gt,
        hybrids={f"model, slerp {g}": g for g in HYBRID_GROUPS} if a.hybrids else {},
        blends={f"model, blend {w}": float(w) for w in a.blend},
        cubic=["cubic", "model, cubic root position"] if a.cubic else [],
        hybrid_base=a.hybrid_of or next((m for m in a.methods if m.startswith("model")), None),
        json=a.json,
    )


FEET = ["lFoot", "rFoot", "lFoot_Nub", "rFoot_Nub"]


def accel(pos):
    """Mean norm of the second difference of global joint positions [T, J, 3]."""
    return float(np.linalg.norm(pos[2:] - 2 * pos[1:-1] + pos[:-2], axis=-1).mean())


def npss(gt, pred):
    """LaFAN1's NPSS. gt, pred: [batch, time, features]."""
    gt_p = np.square(np.real(np.fft.fft(gt, axis=1)))
    pr_p = np.square(np.real(np.fft.fft(pred, axis=1)))
    gt_tot = gt_p.sum(1)
    pr_tot = pr_p.sum(1)
    w = gt_tot / gt_tot.sum(1, keepdims=True)
    cdf_gt = np.cumsum(gt_p / np.maximum(gt_tot[:, None, :], 1e-12), 1)
    cdf_pr = np.cumsum(pr_p / np.maximum(pr_tot[:, None, :], 1e-12), 1)
    emd = np.abs(cdf_pr - cdf_gt).sum(1)
    return float(np.average(emd, weights=w))


def heading_free(rot):
    """Global rotations [F, J, 3, 3] with each frame's heading taken out:
    premultiplied by the inverse of the turn about the vertical (y) that
    points the hip's forward axis (its local z) where it points in the
    horizontal plane."""
    f = rot[:, 0, :, 2]
    yaw = np.arctan2(f[:, 0], f[:, 2])
    return np.einsum("fji,fkjl->fkil", axis_rot("Y", yaw), rot)


def score(acc, pred, truth, keys, feet, floor, mu, sd):
    """Appends every key interval's metrics to acc. pred, truth: (global positions, rotations)."""
    ppos, prot = pred
    gpos, grot = truth
    for a, b in zip(keys[:-1], keys[1:]):
        sl = slice(a + 1, b)
        off = gpos[a, 0].copy()
        off[1] = 0
        P = ((ppos[sl] - off).reshape(b - a - 1, -1) - mu) / sd
        G = ((gpos[sl] - off).reshape(b - a - 1, -1) - mu) / sd
        acc["l2p"].append(np.linalg.norm(P - G, axis=1).mean())
        # MPJPE: global joint positions between the keys, and root-relative
        # ones at the interval's first key (what a partial key left to the networks)
        acc["mpjpe"].append(float(np.linalg.norm(ppos[sl] - gpos[sl], axis=-1).mean()))
        acc["mpjpe_key"].append(float(np.linalg.norm((ppos[a] - ppos[a, :1]) - (gpos[a] - gpos[a, :1]), axis=-1).mean()))
        qg, qp = mat_to_quat(grot[sl]), mat_to_quat(prot[sl])
        sign = np.sign((qg * qp).sum(-1, keepdims=True))
        sign[sign == 0] = 1
        qp = qp * sign
        acc["l2q"].append(np.linalg.norm((qp - qg).reshape(b - a - 1, -1), axis=1).mean())
        acc["gt"].append(qg.reshape(b - a - 1, -1))
        acc["pred"].append(qp.reshape(b - a - 1, -1))
        # the same with each frame's heading (the hip's turn about the
        # vertical) taken out of every rotation, the truth's from the truth
        # and the output's from the output: what the body does relative to
        # where it faces, which root-only keys do not say (npss_parts)
        hg, hp = mat_to_quat(heading_free(grot[sl])), mat_to_quat(heading_free(prot[sl]))
        sign = np.sign((hg * hp).sum(-1, keepdims=True))
        sign[sign == 0] = 1
        acc.setdefault("gt_hf", []).append(hg.reshape(b - a - 1, -1))
        acc.setdefault("pred_hf", []).append((hp * sign).reshape(b - a - 1, -1))
        fp = ppos[a:b, feet]
        v = np.linalg.norm(fp[1:, :, [0, 2]] - fp[:-1, :, [0, 2]], axis=-1)
        contact = fp[1:, :, 1] < floor + 5
        acc["skate"].append(float(v[contact].mean()) if contact.any() else 0.0)
        acc["accel"].append(accel(ppos[a:b + 1]))
        # joint speed relative to the root over the in-between frames (issue 19)
        rel = lambda p: p[a:b + 1] - p[a:b + 1, :1]  # noqa: E731
        acc["speed"].append(float(np.linalg.norm(np.diff(rel(ppos), axis=0), axis=-1).mean()))
        acc["gt_speed"].append(float(np.linalg.norm(np.diff(rel(gpos), axis=0), axis=-1).mean()))


def hybrid_columns(bvh, group):
    """Motion columns of one channel group: "root position", "root height" (its
    y position alone), "root rotation", "joints" (every non-root joint), or a
    body part ("spine", "arms": collars to forearms, "hands": hands and
    fingers, "legs")."""
    names, _, _, chans, _ = bvh
    legs = ("Buttock", "Thigh", "Shin", "Foot")
    arms = ("Collar", "Shldr", "ForeArm")
    hands = ("Hand", "Thumb", "Index", "Mid", "Ring", "Pinky")
    cols, col = [], 0
    for j, (name, ch) in enumerate(zip(names, chans)):
        for c in ch:
            if j == 0:
                take = (group in ("root position", "root height") if c == "Yposition"
                        else group == "root position" if c.endswith("position") else group == "root rotation")
            else:
                part = ("legs" if any(x in name for x in legs) else "arms" if any(x in name for x in arms)
                        else "hands" if any(x in name for x in hands) else "spine")
                take = group in ("joints", part)
            if take:
                cols.append(col)
            col += 1
    return cols


def quat_to_mat(q):
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def blend_fk(bvh, a, b, w):
    """Global positions and rotations of the blend of two clips' local poses
    (quaternion nlerp per joint, lerp of the translations, i.e. the root
    position) by weight w."""
    ta, qa = local_fk(a)
    tb, qb = local_fk(b)
    qa, qb = mat_to_quat(qa), mat_to_quat(qb)
    qb = qb * np.sign((qa * qb).sum(-1, keepdims=True) + 1e-12)
    q = (1 - w) * qa + w * qb
    loc = quat_to_mat(q / np.linalg.norm(q, axis=-1, keepdims=True))
    return fk_from_local(bvh, (1 - w) * ta + w * tb, loc)


def rep_frames(bvh, k):
    """Motion DNA frames of a clip as the crate picks them (motion.dna:
    largest local-rotation change, >= 30 frames apart)."""
    return representative_frames_of_clip(bvh, k)


def cubic_fk(bvh, keys):
    """Diagnostic baseline: uniform Catmull-Rom splines through the keys'
    root positions and (sign-aligned, renormalized) local joint quaternions."""
    trans, loc = local_fk(bvh)
    root = trans[:, 0]
    q = mat_to_quat(loc)
    for i in range(1, len(keys)):
        q[keys[i]] *= np.sign((q[keys[i]] * q[keys[i - 1]]).sum(-1, keepdims=True) + 1e-12)
    root_o, q_o = root.copy(), q.copy()
    for i in range(len(keys) - 1):
        a, b = keys[i], keys[i + 1]
        pa, pb = keys[max(i - 1, 0)], keys[min(i + 2, len(keys) - 1)]
        t = (np.arange(a + 1, b) - a) / (b - a)
        for arr, out in ((root, root_o), (q, q_o)):
            p0, p1, p2, p3 = arr[pa], arr[a], arr[b], arr[pb]
            if pa == a:
                p0 = 2 * p1 - p2
            if pb == b:
                p3 = 2 * p2 - p1
            sh = (-1,) + (1,) * (arr.ndim - 1)
            tt = t.reshape(sh)
            out[a + 1:b] = 0.5 * ((2 * p1) + (-p0 + p2) * tt + (2 * p0 - 5 * p1 + 4 * p2 - p3) * tt ** 2
                                  + (-p0 + 3 * p1 - 3 * p2 + p3) * tt ** 3)
    trans[:, 0] = root_o
    loc = quat_to_mat(q_o / np.linalg.norm(q_o, axis=-1, keepdims=True))
    return fk_from_local(bvh, trans, loc)


def l2p_stats():
    """Normalization statistics (LaFAN1's L2P): mean and standard deviation
    of each joint coordinate over the global positions of training windows,
    each re-centred on its first frame's root x/z like the evaluation
    windows. Flat [3J] arrays (joint-major)."""
    d = np.load(os.path.join(CACHE, "motion60.npz"))
    glob = d["train_local"] + d["train_root"][:, None, :]
    starts = np.concatenate([[0], np.cumsum(d["train_seg_len"])[:-1]])
    chunks = []
    for s0, ln in zip(starts, d["train_seg_len"]):
        for a in range(s0, s0 + ln - 300, 150):
            w = glob[a:a + 300].copy()
            w[:, :, [0, 2]] -= glob[a, 0, [0, 2]]
            chunks.append(w.reshape(300, -1))
    flat = np.concatenate(chunks)
    return flat.mean(0), flat.std(0) + 1e-6


def main(cfg):
    if not os.path.isdir(DATA):
        sys.exit(f"SKIP: {DATA} is absent")
    mu, sd = l2p_stats()
    GAPS, METHODS, SPLIT, DNA_GT = cfg.gaps, cfg.methods, cfg.split, cfg.dna_gt
    HYBRIDS, BLENDS, CUBIC, HYBRID_BASE, DIAGNOSTICS = cfg.hybrids, cfg.blends, cfg.cubic, cfg.hybrid_base, cfg.diagnostics
    if DIAGNOSTICS and not (HYBRID_BASE and "slerp" in METHODS):
        sys.exit("--hybrids, --blend and --cubic need slerp and model (or model-nolock) in --methods")
    acc = {(m, g): {"l2p": [], "l2q": [], "mpjpe": [], "mpjpe_key": [], "gt": [], "pred": [], "skate": [], "accel": [], "speed": [], "gt_speed": [],
                    "keyraw": [], "key": []}
           for m in METHODS + DIAGNOSTICS for g in GAPS}
    gt_skate, gt_accel = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for cls in sorted(TRUE_FPS):
            for name in sorted(os.listdir(os.path.join(DATA, cls))):
                if (take_of(cls, int(name[:-4])) in VALIDATION) != (SPLIT == "val"):
                    continue
                clip = os.path.join(tmp, f"{cls}_{name}")
                n = resample(os.path.join(DATA, cls, name), clip, TRUE_FPS[cls] // 60)
                gt = read_bvh(clip)
                gpos, grot = global_fk(gt)
                feet = [gt[0].index(f) for f in FEET]
                floor = np.median(gpos[:, :, 1].min(1))
                dna_args = ["--dna", ",".join(map(str, rep_frames(gt, max(1, n // 180))))] if DNA_GT else []
                for g in GAPS:
                    keys = list(range(10, n - 1, g))
                    for m in METHODS:
                        out = os.path.join(tmp, f"out_{m}_{g}.bvh")
                        r = subprocess.run([cli(), "inbetween", "--from-bvh", clip, "--keys", ",".join(map(str, keys)),
                                            "-o", out] + method_args(m)
                                           + (dna_args if method_args(m)[1] in ("model", "generator") else []),
                                           capture_output=True, text=True, cwd=ROOT)
                        if r.returncode != 0:
                            sys.exit(f"{m} on {clip}: {r.stderr}")
                        pairs = re.findall(r"root ([0-9.]+), joints ([0-9.]+)", r.stderr)
                        if runs_model(m) and len(pairs) >= 2:
                            # the generator pipeline's key errors before and after
                            # post-processing (the residual network, which --method
                            # model runs for whole-pose keys when its manifest says
                            # so, meets keys by construction and prints none)
                            acc[(m, g)]["keyraw"].append([float(x) for x in pairs[0]])
                            acc[(m, g)]["key"].append([float(x) for x in pairs[1]])
                        score(acc[(m, g)], global_fk(read_bvh(out)), (gpos, grot), keys, feet, floor, mu, sd)
                    gt_accel.extend(accel(gpos[a:b + 1]) for a, b in zip(keys[:-1], keys[1:]))
                    if DIAGNOSTICS:
                        mb = read_bvh(os.path.join(tmp, f"out_{HYBRID_BASE}_{g}.bvh"))
                        sb = read_bvh(os.path.join(tmp, f"out_slerp_{g}.bvh"))
                    if CUBIC:
                        cpos, crot = cubic_fk(gt, keys)
                        score(acc[("cubic", g)], (cpos, crot), (gpos, grot), keys, feet, floor, mu, sd)
                        # the model with the spline's root position
                        mpos, mrot = global_fk(mb)
                        mpos += cpos[:, :1] - mpos[:, :1]
                        score(acc[("model, cubic root position", g)], (mpos, mrot), (gpos, grot), keys, feet, floor, mu, sd)
                    for h, w in BLENDS.items():
                        score(acc[(h, g)], blend_fk(gt, mb, sb, w), (gpos, grot), keys, feet, floor, mu, sd)
                    for h, group in HYBRIDS.items():
                        cols = hybrid_columns(gt, group)
                        data = mb[4].copy()
                        data[:, cols] = sb[4][:, cols]
                        score(acc[(h, g)], global_fk(mb[:4] + (data,)), (gpos, grot), keys, feet, floor, mu, sd)
                    if g == GAPS[0]:
                        fg = gpos[:, feet]
                        v = np.linalg.norm(fg[1:, :, [0, 2]] - fg[:-1, :, [0, 2]], axis=-1)
                        gt_skate.append(float(v[fg[1:, :, 1] < floor + 5].mean()))
    res = {}
    for (m, g), a in acc.items():
        res[f"{m}@{g}"] = {
            "method": m, "gap": g, "windows": len(a["l2p"]),
            "L2P": float(np.mean(a["l2p"])), "L2Q": float(np.mean(a["l2q"])),
            "MPJPE": float(np.mean(a["mpjpe"])), "MPJPE_at_keys": float(np.mean(a["mpjpe_key"])),
            "NPSS": float(np.mean([npss(x[None], y[None]) for x, y in zip(a["gt"], a["pred"])])),
            # NPSS with each frame's heading taken out of both (heading_free)
            "NPSS_heading_free": float(np.mean([npss(x[None], y[None]) for x, y in zip(a["gt_hf"], a["pred_hf"])])),
            "foot_skate": float(np.mean(a["skate"])),
            "acceleration": float(np.mean(a["accel"])),
            "speed_ratio": float(np.mean(a["speed"]) / max(np.mean(a["gt_speed"]), 1e-12)),
            # the captured motion's mean joint speed relative to the root (units/frame) on these windows
            "truth_speed": float(np.mean(a["gt_speed"])),
        }
        if a["key"]:
            res[f"{m}@{g}"]["key_error_before_post"] = np.mean(a["keyraw"], 0).tolist()
            res[f"{m}@{g}"]["key_error_after_post"] = np.mean(a["key"], 0).tolist()
    res["ground_truth_foot_skate"] = float(np.mean(gt_skate))
    res["measured"] = str(datetime.date.today())
    res["ground_truth_acceleration"] = float(np.mean(gt_accel))
    os.makedirs(os.path.join(ROOT, "docs"), exist_ok=True)
    out_json = cfg.json or os.path.join(ROOT, "docs", "inbetween_hybrids.json" if DIAGNOSTICS else
                                        "inbetween_eval.json" if SPLIT == "val" else "inbetween_eval_train.json")
    with open(out_json, "w") as f:
        json.dump(res, f, indent=1)
    print("| metric | method | " + " | ".join(f"gap {g}" for g in GAPS) + " |")
    print("|---|---|" + "---|" * len(GAPS))
    for metric in ["L2P", "L2Q", "NPSS", "MPJPE", "MPJPE_at_keys", "foot_skate", "acceleration", "speed_ratio"]:
        for m in METHODS + DIAGNOSTICS:
            print(f"| {metric} | {m} | " + " | ".join(f"{res[f'{m}@{g}'][metric]:.3f}" for g in GAPS) + " |")
    print(f"ground-truth foot skating: {res['ground_truth_foot_skate']:.3f} units/frame")
    print(f"ground-truth acceleration: {res['ground_truth_acceleration']:.3f} units/frame^2")
    for g in GAPS:
        r = res.get(f"model@{g}", {})
        if "key_error_before_post" in r:
            print(f"gap {g}: model key error (root, joints) before post {r['key_error_before_post']}, after {r['key_error_after_post']}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 3, figsize=(13, 3.6))
        for i, metric in enumerate(["L2P", "L2Q", "NPSS"]):
            for m in METHODS:
                ax[i].plot(GAPS, [res[f"{m}@{g}"][metric] for g in GAPS], marker="o", label=m)
            ax[i].set_xscale("log")
            ax[i].set_xticks(GAPS, [str(g) for g in GAPS])
            ax[i].set_xlabel("gap (frames at 60 fps)")
            ax[i].set_title(metric + " (lower is better)")
        ax[0].legend()
        fig.tight_layout()
        if not DIAGNOSTICS and SPLIT == "val" and not cfg.json:
            fig.savefig(os.path.join(ROOT, "docs", "inbetween_eval.png"), dpi=110)
    except ImportError:
        print("matplotlib missing: no plot")


if __name__ == "__main__":
    main(parse_args())
