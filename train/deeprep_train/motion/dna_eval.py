"""Motion DNA measured (Sec. 5.3.7, issue 20) on the validation takes.

Each validation clip at 60 fps (its first 2,048 frames at most) gets keys at
random frames 1 to 5 s apart, and the generator (`--method generator`) runs
  - without DNA (the whole-pose keys serve as DNA, the default), and
  - with the clip's own representative frames as DNA (`--dna F1,F2,...`,
    one per 180 frames: the frames of largest rotation change, as in
    training).
For each output, against those representative poses T_j (local joint
positions relative to the root with the root's rotation removed, Λ):
  DNA error 1 (eq. 5.11): the mean over T_j of the distance to the closest
    output frame;
  DNA error 2 (eq. 5.12): in every interval between keys of at least 3 s,
    the floor(seconds / 3) output frames closest to any T_j, their mean
    distance.
Distances are the mean over joints of the Euclidean distance (BVH units;
the thesis reports cm: 8.4 and 6.5). Diversity: three outputs with DNA
drawn from the clip by seeds 1-3 (`--dna CLIP --seed S`), the mean distance
of Λ between every two of them over the in-between frames, beside the
ground truth's own spread (the mean distance of Λ between its frames t and
t + 1 s, the same keys' clip); and NPSS of Λ over the clip against the
truth's, for the seedless output (no DNA) and the seeded ones (issue 47 asks
them within 10%).

  train/.venv/bin/python -m deeprep_train.motion.dna_eval      -> docs/dna_eval.json

`--key-kind root|xy` gives the keys as root positions or 2-D joints
instead of whole poses (the DNA stays whole poses): where the keys leave
the pose open, which is where a style input matters to a user.

Runs at the model's default variation and at 1 (the networks as trained:
the default keeps a quarter of their departure from interpolation, which
also dilutes whatever DNA does).
"""
import itertools
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from deeprep_train.motion.data import DATA
from deeprep_train.bvh import global_fk, read_bvh
from deeprep_train.motion.eval import ROOT, cli, npss, rep_frames
from deeprep_train.motion.table54 import random_keys, validation_clips


def local_poses(bvh):
    """Λ of every frame: joints relative to the root, root rotation removed [F, J, 3]."""
    pos, rot = global_fk(bvh)
    rel = pos - pos[:, :1]
    return np.einsum("fji,fkj->fki", rot[:, 0], rel)  # R0^T (p - p0)


def dist(a, b):
    """Mean over joints of the Euclidean distance; a [..., J, 3], b [..., J, 3]."""
    return np.linalg.norm(a - b, axis=-1).mean(-1)


def dna_errors(out, reps, keys):
    d = np.stack([dist(out, r[None]) for r in reps], 1)  # [F, K]
    e1 = float(d.min(0).mean())
    picked = []
    for a, b in zip(keys[:-1], keys[1:]):
        if b - a >= 180:
            k = (b - a) // 180
            picked.extend(np.sort(d[a + 1:b].min(1))[:k].tolist())
    return e1, (float(np.mean(picked)) if picked else None)


def measure(variation, method="generator", split="val", every=1, key_kind="pose"):
    rows, div, spread = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for label, clip, n in validation_clips(tmp, split=split, every=every):
            gt = read_bvh(clip)
            keys = random_keys(n, 0)
            reps_idx = rep_frames(gt, max(1, keys[-1] // 180))
            lam_gt = local_poses(gt)
            reps = lam_gt[reps_idx]

            def run(extra, tag):
                out = os.path.join(tmp, f"{tag}.bvh")
                r = subprocess.run([cli(), "inbetween", "--from-bvh", clip, "--keys", ",".join(map(str, keys)),
                                    "-o", out, "--method", method, "--key-kind", key_kind] + variation + extra, capture_output=True, text=True, cwd=ROOT)
                if r.returncode:
                    sys.exit(f"{clip}: {r.stderr}")
                return local_poses(read_bvh(out))

            row = {"clip": label, "frames": keys[-1] + 1, "keys": len(keys), "dna_poses": len(reps_idx)}
            truth = lam_gt[:keys[-1] + 1].reshape(1, keys[-1] + 1, -1)
            for tag, extra in (("without_dna", []), ("with_dna", ["--dna", ",".join(map(str, reps_idx))])):
                out = run(extra, tag)[:keys[-1] + 1]
                e1, e2 = dna_errors(out, reps, keys)
                row[tag] = {"dna_error_1": e1, "dna_error_2": e2}
                if tag == "without_dna":
                    row["npss_seedless"] = npss(truth, out.reshape(truth.shape))
            outs = [run(["--dna", clip, "--seed", str(s)], f"seed{s}")[:keys[-1] + 1] for s in (1, 2, 3)]
            row["npss_seeds"] = float(np.mean([npss(truth, o.reshape(truth.shape)) for o in outs]))
            mid = np.setdiff1d(np.arange(keys[-1] + 1), keys)
            for a, b in itertools.combinations(outs, 2):
                div.append(float(dist(a[mid], b[mid]).mean()))
            spread.append(float(dist(lam_gt[60:n], lam_gt[:n - 60]).mean()))
            rows.append(row)
    return rows, div, spread


def main():
    import argparse
    ap = argparse.ArgumentParser(description="Motion DNA measured (Sec. 5.3.7)")
    ap.add_argument("--method", default="generator", help="the CLI's --method (generator, cond)")
    ap.add_argument("--split", choices=["val", "train"], default="val")
    ap.add_argument("--every", type=int, default=1, help="every N-th clip of the split")
    ap.add_argument("--key-kind", choices=["pose", "root", "xy"], default="pose",
                    help="the CLI's --key-kind: what the keys give (the DNA is whole poses either way)")
    ap.add_argument("--json", default=os.path.join(ROOT, "docs", "dna_eval.json"))
    args = ap.parse_args()
    if not os.path.isdir(DATA):
        sys.exit(f"SKIP: {DATA} is absent")
    res = {"thesis_cm": {"dna_error_1": 8.4, "dna_error_2": 6.5}, "method": args.method, "split": args.split,
           "every": args.every, "key_kind": args.key_kind}
    runs = (("default_variation", []), ("variation_1", ["--variation", "1"]))
    for label, variation in runs[:1] if args.method == "cond" else runs:  # cond's default variation is 1
        res[label] = summarize(*measure(variation, args.method, args.split, args.every, args.key_kind))
        print(label, json.dumps({k: v for k, v in res[label].items() if k != "clips"}), flush=True)
    with open(args.json, "w") as f:
        json.dump(res, f, indent=1)


def summarize(rows, div, spread):
    mean = lambda tag, k: float(np.mean([r[tag][k] for r in rows if r[tag][k] is not None]))  # noqa: E731
    return {"without_dna": {k: mean("without_dna", k) for k in ("dna_error_1", "dna_error_2")},
            "with_dna": {k: mean("with_dna", k) for k in ("dna_error_1", "dna_error_2")},
            "diversity_between_seeds": float(np.mean(div)), "ground_truth_spread_1s": float(np.mean(spread)),
            # NPSS of the root-relative joint positions (Λ) over each clip against the truth's: the
            # seedless output's (no DNA) and the three seeded DNA draws' (issue 47: within 10%)
            "npss_seedless": float(np.mean([r["npss_seedless"] for r in rows])),
            "npss_seeds": float(np.mean([r["npss_seeds"] for r in rows])),
            "clips": rows}


if __name__ == "__main__":
    main()
