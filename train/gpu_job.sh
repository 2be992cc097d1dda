#!/usr/bin/env bash
# Issue 19, item 5: one training of the residual in-betweening network on a
# lent GPU machine (an H200 with PyTorch preinstalled and no package
# registries), resumed from the committed checkpoint, its result brought
# back through $OUT. CI never runs this.
#
# When a session's device `status` shows a machine:
#   1. here (CPU), once: the training arrays and the L2P spread
#        train/.venv/bin/python -m deeprep_train.motion.residual prepare   # train/cache/resid60.npz
#        train/.venv/bin/python -c "from deeprep_train.motion.residual import l2p_sd; l2p_sd()"
#   2. the device tool's run, with
#        command: bash train/gpu_job.sh
#        carry:   ["train/cache/resid60.npz", "train/cache/l2p_sd.npy"]
#        timeout_s: 600
#      (the tracked tree is about 38 MB, resid60.npz 19.5 MB: under the
#      64 MiB that travels)
#   3. here: the files come back under the reply's files_at:
#        resid_gpu.pt  float16 weights and moving average (train/checkpoints/
#                      tween_resid.pt's format: copy it there to resume on
#                      the CPU, or score it with `residual eval --ckpt`)
#        log.jsonl     the losses every 50 steps
#
# The width is the committed checkpoint's. Settings (environment): MINUTES (default 8, inside the 10-minute limit
# with start-up and the write-back), BATCH (64), DEVICE (cuda), PORTABLE (the
# committed checkpoint to start from, default checkpoints/tween_resid.pt, e.g.
# checkpoints/tween_resid_s2_skip.pt) and EXTRA (more `residual train` flags,
# e.g. "--gan-weight 0.15 --gan-min-gap 60 --cross-clip 0.5 --regular-keys 0.3"),
# with the loss weights of run G. Try it on the CPU first:
#   OUT=/tmp/gpu_try DEVICE=cpu MINUTES=0.2 BATCH=2 bash train/gpu_job.sh
set -euo pipefail
cd "$(dirname "$0")"
OUT=${OUT:?set by the device tool: the folder whose files come back}
MINUTES=${MINUTES:-8}
BATCH=${BATCH:-64}
DEVICE=${DEVICE:-cuda}
PY=${PY:-python3}
PORTABLE=${PORTABLE:-checkpoints/tween_resid.pt}
EXTRA=${EXTRA:-}
[ -x .venv/bin/python ] && [ "$DEVICE" = cpu ] && PY=.venv/bin/python
export PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}" PYTHONUNBUFFERED=1
for f in cache/resid60.npz cache/l2p_sd.npy; do
  [ -f "$f" ] || { echo "gpu_job: train/$f is missing: carry it (see the header)" >&2; exit 2; }
done
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
"$PY" -m deeprep_train.motion.residual train --resume --device "$DEVICE" --out "$RUN" \
  --batch "$BATCH" --minutes "$MINUTES" --threads 8 \
  --dilations 1,2,4,8,16,32,64 --speed-weight 10 --foot-weight 2 --l2p-weight 1 --spectral-weight 5 \
  --frames 480 --lr 3e-4 --save-every 200 --snapshot-every 1000000 --portable "$PORTABLE" $EXTRA
"$PY" -m deeprep_train.motion.residual portable --out "$RUN" --to "$OUT/resid_gpu.pt"
mv "$RUN/log.jsonl" "$OUT/log.jsonl"
rm -rf "$RUN"   # ckpt.pt (Adam state, about 30 MB) is over the 16 MiB a file may bring back
ls -la "$OUT"
