#!/usr/bin/env bash
# One training of the conditional in-betweening network (motion/cond.py,
# issue 47) on a lent GPU machine (an H200 or H100 with PyTorch preinstalled
# and no package registries), resumed from the committed checkpoint, its
# result brought back through $OUT. CI never runs this.
#
# When a session's device `status` shows a machine:
#   1. here (CPU), once: the training arrays and the L2P spread, cmu-extra's
#      walks first (EXTRA's --extra-share stops without them)
#        cargo build --release --bin deeprep
#        train/.venv/bin/python -m deeprep_train.motion.extra              # train/cache/extra60
#        train/.venv/bin/python -m deeprep_train.motion.residual prepare   # train/cache/resid60.npz
#      (cond.py computes the spread from resid60.npz when cache/l2p_sd.npy
#      is absent; carry that file too where it exists)
#   2. the device tool's run, with
#        command: bash train/gpu_job.sh
#        carry:   ["train/cache/resid60.npz"]
#        timeout_s: 600
#      (the tracked tree is about 20 MB, resid60.npz 19.5 MB: under the
#      64 MiB that travels)
#   3. here: the files come back under the reply's files_at:
#        cond_gpu.pt   float16 weights, moving average and prior pose
#                      (checkpoints/tween_cond.pt's format: copy it there
#                      to resume on the CPU, or score it with `cond eval --ckpt`)
#        log.jsonl     the losses every 50 steps
#
# Settings (environment): MINUTES (default 8, inside the 10-minute limit with
# start-up and the write-back), BATCH (64), DEVICE (cuda), PORTABLE (the
# committed checkpoint to start from, default checkpoints/tween_cond_coarse.pt,
# the bundled network's line; checkpoints/tween_cond.pt is the adversarial
# run's; INIT=checkpoints/tween_resid_w128b.pt starts a new one from the
# whole-pose network instead) and EXTRA (more `cond train` flags; default the
# bundled line's next stage: --coarse-every 2 --short-every 3 --extra-share
# 0.5; the adversarial run's were --gan-weight 0.1 --div-weight 1 --div-tau
# 0.06 --fill-share 0.2 --context-base 1 --short-every 3 --extra-share 0.5,
# a new discriminator each run since the portable file carries none). Try it
# on the CPU first:
#   OUT=/tmp/gpu_try DEVICE=cpu MINUTES=0.2 BATCH=2 bash train/gpu_job.sh
set -euo pipefail
cd "$(dirname "$0")"
OUT=${OUT:?set by the device tool: the folder whose files come back}
MINUTES=${MINUTES:-8}
BATCH=${BATCH:-64}
DEVICE=${DEVICE:-cuda}
PY=${PY:-python3}
PORTABLE=${PORTABLE:-checkpoints/tween_cond_coarse.pt}
INIT=${INIT:-}
# the stage the CPU run is in (notes/cond.md): the bundled network's line, with
# every second batch at the hierarchy's coarse rates and every third batch of
# 150-frame windows, half of them from cmu-extra's walks and runs
EXTRA=${EXTRA:---coarse-every 2 --short-every 3 --extra-share 0.5}
[ -x .venv/bin/python ] && [ "$DEVICE" = cpu ] && PY=.venv/bin/python
export PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}" PYTHONUNBUFFERED=1
[ -f cache/resid60.npz ] || { echo "gpu_job: train/cache/resid60.npz is missing: carry it (see the header)" >&2; exit 2; }
"$PY" - "$DEVICE" <<'PY'
import sys, torch
dev = sys.argv[1]
print("torch", torch.__version__, "cuda", torch.cuda.is_available(),
      torch.cuda.get_device_name(0) if torch.cuda.is_available() else "")
if dev.startswith("cuda") and not torch.cuda.is_available():
    sys.exit("gpu_job: no CUDA device here")
PY
RUN="$OUT/run"
mkdir -p "$RUN"
if [ -n "$INIT" ]; then start=(--init "$INIT"); else start=(--resume --portable "$PORTABLE"); fi
"$PY" -m deeprep_train.motion.cond train "${start[@]}" --device "$DEVICE" --out "$RUN" \
  --batch "$BATCH" --minutes "$MINUTES" --threads 8 --lr 3e-4 --save-every 200 --snapshot-every 1000000 $EXTRA
"$PY" -m deeprep_train.motion.cond portable --out "$RUN" --to "$OUT/cond_gpu.pt"
mv "$RUN/log.jsonl" "$OUT/log.jsonl"
rm -rf "$RUN"   # ckpt.pt (Adam state) is over what a file may bring back
ls -la "$OUT"
