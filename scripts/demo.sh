#!/usr/bin/env bash
# Builds what the demo pages load and serves web/ on http://127.0.0.1:${PORT:-8080}/web/
# One wasm build (web/pkg; the in-betweening worker is served from it by
# scripts/serve.mjs, with plain SIMD): about 6-8 minutes the first time on
# 2 cores, seconds after that. `bash scripts/build-wasm.sh` builds the
# worker's smaller core and its relaxed-SIMD twin too (what the npm package
# ships), which the server then serves instead.
set -euo pipefail
cd "$(dirname "$0")/.."
t0=$(date +%s)
bash scripts/setup.sh
if [ ! -f target/wasm32-unknown-unknown/release/deeprep.wasm ]; then
  echo "demo: first build of the wasm package: about 6-8 minutes on 2 cores (later runs take seconds)" >&2
fi
bash scripts/build-wasm.sh --pages-only
echo "demo: ready after $(( $(date +%s) - t0 )) s" >&2

# The server serves the repository root: the page is /web/, the models /models/onnx/.
exec node scripts/serve.mjs . "${PORT:-8080}"
