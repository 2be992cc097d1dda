#!/usr/bin/env bash
# Builds the deeprep wasm package into web/pkg (wasm-bindgen, --target web).
#   scripts/build-wasm.sh          release build, unoptimized .wasm (fast)
#   scripts/build-wasm.sh --opt    plus wasm-opt -Os (npm binaryen; Debian's is too old)
set -euo pipefail
source "$(dirname "$0")/wasm-env.sh"
cd "$ROOT"
OPT=0; [ "${1:-}" = "--opt" ] && OPT=1
t0=$(date +%s)
cargo build -p deeprep --lib --release "${WASM_CARGO_FLAGS[@]}"
WASM=target/wasm32-unknown-unknown/release/deeprep.wasm
rm -rf web/pkg
wasm-bindgen "$WASM" --out-dir web/pkg --target web --typescript --remove-name-section --remove-producers-section
if [ "$OPT" = 1 ]; then
  node_modules/.bin/wasm-opt web/pkg/deeprep_bg.wasm -Os -o web/pkg/deeprep_bg.wasm \
    --enable-reference-types --enable-bulk-memory --enable-nontrapping-float-to-int \
    --enable-sign-ext --enable-multivalue --enable-mutable-globals
fi
raw=$(stat -c %s web/pkg/deeprep_bg.wasm); gz=$(gzip -9 -c web/pkg/deeprep_bg.wasm | wc -c)
echo "{\"wasm_bytes\": $raw, \"wasm_gzip_bytes\": $gz, \"optimized\": $OPT, \"build_seconds\": $(( $(date +%s) - t0 ))}"
