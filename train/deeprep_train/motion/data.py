"""The motion data pipeline (issue 3, thesis Sec. 5.3 and D.2).

Reads ../shared/data/cmu-bvh through the crate's own BVH reader, FK and RC-FK
inverse map (`deeprep bvh export`, one implementation for Rust and Python),
then:
  1. resamples to 60 fps: the salsa clips were captured at 60 fps although
     their headers say 120 (kept frame for frame); indian and martial are
     120 fps and are decimated by 2;
  2. drops frames where the body is under the floor (D.2, noise type 1): the
     lowest joint, averaged over a 0.25 s window, more than FLOOR_DROP units
     below the clip's floor (the median of the per-frame lowest joint); the
     clip is split at dropped frames, and pieces shorter than MIN_SEGMENT
     frames are dropped too; heights are then measured from that floor;
  3. produces the network's representations: local joint positions relative
     to the root (world orientation), the root trajectory, and the RC-Euler
     targets (root 6D + clamped Table D.1 angles, radians);
  4. splits train / validation by take (salsa NN and NN+15 are one couple
     take and stay together);
  5. caches everything in train/cache/motion60.npz and prints a summary.

Run: train/.venv/bin/python -m deeprep_train.motion.data   (needs `cargo build`)
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from deeprep_train.paths import ROOT, CACHE  # noqa: E402
DATA = os.path.join(ROOT, "..", "shared", "data", "cmu-bvh")
TRUE_FPS = {"salsa": 60, "indian": 120, "martial": 120}
FLOOR_DROP = 8.0  # units (the data's centimetre-like units) below the clip's floor
FLOOR_WINDOW = 15  # frames at 60 fps = 0.25 s
MIN_SEGMENT = 64
# Validation takes, never trained on: one indian, one martial, two salsa couple takes.
VALIDATION = {"indian/15", "martial/10", "salsa/04", "salsa/19", "salsa/12", "salsa/27"}


def take_of(cls: str, num: int) -> str:
    if cls == "salsa" and num > 15:
        num -= 15
    return f"{cls}/{num:02d}"


def cli() -> str:
    for p in ("target/release/deeprep", "target/debug/deeprep"):
        if os.path.exists(os.path.join(ROOT, p)):
            return os.path.join(ROOT, p)
    sys.exit("build the CLI first: cargo build --release --bin deeprep")


def export(path: str, tmp: str):
    prefix = os.path.join(tmp, os.path.basename(path)[:-4])
    subprocess.run([cli(), "bvh", "export", path, "--out", prefix], check=True, cwd=ROOT)
    meta = json.load(open(prefix + ".json"))
    f, j = meta["frames"], len(meta["joints"])
    pos = np.fromfile(prefix + ".positions.f32", dtype="<f4").reshape(f, j, 3)
    rc = np.fromfile(prefix + ".rc.f32", dtype="<f4").reshape(f, meta["rc_width"])
    return meta, pos, rc


def floor_segments(pos: np.ndarray):
    """Boolean keep-mask and the floor height of a 60 fps clip."""
    lowest = pos[:, :, 1].min(1)
    floor = float(np.median(lowest))
    kernel = np.ones(FLOOR_WINDOW) / FLOOR_WINDOW
    avg = np.convolve(np.pad(lowest, FLOOR_WINDOW // 2, mode="edge"), kernel, mode="valid")[: len(lowest)]
    return avg >= floor - FLOOR_DROP, floor


def runs(mask: np.ndarray):
    out, start = [], None
    for i, k in enumerate(list(mask) + [False]):
        if k and start is None:
            start = i
        elif not k and start is not None:
            out.append((start, i))
            start = None
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(CACHE, "motion60.npz"))
    args = ap.parse_args()
    if not os.path.isdir(DATA):
        sys.exit(f"SKIP: {DATA} is absent")
    os.makedirs(CACHE, exist_ok=True)
    store = {s: {"local": [], "root": [], "rc": [], "seg": []} for s in ("train", "val")}
    summary = {}
    meta0 = None
    with tempfile.TemporaryDirectory() as tmp:
        for cls in sorted(TRUE_FPS):
            for name in sorted(os.listdir(os.path.join(DATA, cls))):
                if not name.endswith(".bvh"):
                    continue
                num = int(name[:-4])
                take = take_of(cls, num)
                split = "val" if take in VALIDATION else "train"
                meta, pos, rc = export(os.path.join(DATA, cls, name), tmp)
                meta0 = meta0 or meta
                step = TRUE_FPS[cls] // 60
                pos, rc = pos[::step], rc[::step]
                keep, floor = floor_segments(pos)
                pos = pos.copy()
                pos[:, :, 1] -= floor
                rc = rc.copy()
                rc[:, 1] -= floor
                s = summary.setdefault((cls, split), {"clips": 0, "frames_in": 0, "frames_under_floor": 0, "frames_short": 0, "frames": 0, "segments": 0})
                s["clips"] += 1
                s["frames_in"] += len(pos)
                s["frames_under_floor"] += int((~keep).sum())
                for a, b in runs(keep):
                    if b - a < MIN_SEGMENT:
                        s["frames_short"] += b - a
                        continue
                    root = pos[a:b, 0, :]
                    store[split]["local"].append(pos[a:b] - root[:, None, :])
                    store[split]["root"].append(root)
                    store[split]["rc"].append(rc[a:b])
                    store[split]["seg"].append((f"{cls}/{name}", a * step, b - a))
                    s["frames"] += b - a
                    s["segments"] += 1
    arrays = {}
    for split, d in store.items():
        arrays[f"{split}_local"] = np.concatenate(d["local"]).astype(np.float32)
        arrays[f"{split}_root"] = np.concatenate(d["root"]).astype(np.float32)
        arrays[f"{split}_rc"] = np.concatenate(d["rc"]).astype(np.float32)
        arrays[f"{split}_seg_len"] = np.array([x[2] for x in d["seg"]], dtype=np.int64)
        arrays[f"{split}_seg_name"] = np.array([x[0] for x in d["seg"]])
        arrays[f"{split}_seg_start"] = np.array([x[1] for x in d["seg"]], dtype=np.int64)
    arrays["joints"] = np.array(meta0["joints"])
    arrays["parents"] = np.array(meta0["parents"], dtype=np.int64)
    arrays["offsets"] = np.array(meta0["offsets"], dtype=np.float32)
    arrays["rotating"] = np.array(meta0["rotating"])
    np.savez_compressed(args.out, **arrays)
    print(f"cached {args.out}")
    print(f"{'class':<8} {'split':<5} {'clips':>5} {'frames in (60 fps)':>18} {'under floor':>11} {'short':>6} {'kept':>7} {'segments':>8}")
    tot = {}
    for (cls, split), s in sorted(summary.items()):
        print(f"{cls:<8} {split:<5} {s['clips']:>5} {s['frames_in']:>18} {s['frames_under_floor']:>11} {s['frames_short']:>6} {s['frames']:>7} {s['segments']:>8}")
        tot[split] = tot.get(split, 0) + s["frames"]
    print("kept frames per split:", tot, f"({sum(tot.values()) / 60 / 60:.1f} min at 60 fps)")


if __name__ == "__main__":
    main()
