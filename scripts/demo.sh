#!/usr/bin/env bash
# Builds the wasm package (optimized) and serves web/ on http://127.0.0.1:${PORT:-8080}/
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build-wasm.sh --opt

# The server serves the repository root: the page is /web/, the models /models/onnx/.
exec node scripts/serve.mjs . "${PORT:-8080}"
