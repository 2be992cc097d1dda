"""cmu-extra's 25 clips on other skeletons, retargeted onto the model's
(issue 53): `python -m deeprep_train.motion.extra` writes them at 60 fps to
train/cache/extra60/<family>/<group>/<take>.bvh with the CLI's
`deeprep bvh retarget SRC --to model` (crate/src/skeleton/retarget.rs),
then `residual prepare` adds them to the training data (take-wise split:
EXTRA_VALIDATION never trained on; the same CMU take in two families stays
on one side)."""

import os
import subprocess
import sys

from deeprep_train.motion.data import cli
from deeprep_train.paths import ROOT, CACHE

EXTRA = os.path.join(ROOT, "..", "shared", "data", "cmu-extra", "other-skeletons")
OUT = os.path.join(CACHE, "extra60")
# CMU takes kept for validation: a walk, a start-hop-stop and the jumps
EXTRA_VALIDATION = {"07_06", "131_03", "01_01"}


def clips():
    """(family, group, take, path) of every clip, sorted."""
    out = []
    for family in sorted(os.listdir(EXTRA)):
        for group in sorted(os.listdir(os.path.join(EXTRA, family))):
            for name in sorted(os.listdir(os.path.join(EXTRA, family, group))):
                if name.endswith(".bvh"):
                    out.append((family, group, name[:-4], os.path.join(EXTRA, family, group, name)))
    return out


def to_60fps(path):
    """Every k-th frame of a clip at 60k fps, in place (the files are at 60
    or 120 fps)."""
    text = open(path).read()
    head, motion = text.split("MOTION", 1)
    lines = motion.strip().splitlines()
    ft = float(lines[1].split(":")[1])
    step = max(1, round(1.0 / ft / 60.0))
    rows = [x for x in lines[2:] if x.strip()][::step]
    with open(path, "w") as f:
        f.write(head + f"MOTION\nFrames: {len(rows)}\nFrame Time: {1 / 60:.8f}\n" + "\n".join(rows) + "\n")
    return len(rows)


def main():
    if not os.path.isdir(EXTRA):
        sys.exit(f"SKIP: {EXTRA} is absent")
    exe = cli()
    n = 0
    for family, group, take, path in clips():
        dst = os.path.join(OUT, family, group, take + ".bvh")
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        subprocess.run([exe, "bvh", "retarget", path, "--to", "model", "-o", dst], check=True, cwd=ROOT,
                       stderr=subprocess.DEVNULL)
        frames = to_60fps(dst)
        n += 1
        print(f"{family}/{group}/{take}: {frames} frames at 60 fps"
              f"{' (validation)' if take in EXTRA_VALIDATION else ''}")
    print(f"{n} clips in {OUT}")


if __name__ == "__main__":
    main()
