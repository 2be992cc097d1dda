#!/usr/bin/env bash
# Builds the deeprep wasm package into web/pkg (wasm-bindgen, --target web),
# and the same without the GPU code (no wgpu: the viewer and HairNet's WebGPU
# decoder) into web/pkg-core, which the in-betweening worker loads (a smaller
# download), with a relaxed-SIMD twin of its .wasm (scripts/build-relaxed-core.sh).
# All three share one target directory and one build of std and the
# dependencies: only the crate is compiled three times.
#   scripts/build-wasm.sh              release build, unoptimized .wasm (fast)
#   scripts/build-wasm.sh --opt        plus wasm-opt -Os (npm binaryen; Debian's is too old)
#   scripts/build-wasm.sh --pages-only only web/pkg, one build (the demo's): the worker's core
#                                      is then served from it (scripts/serve.mjs), plain SIMD
set -euo pipefail
source "$(dirname "$0")/wasm-env.sh"
cd "$ROOT"
OPT=0; PAGES_ONLY=0
for a in "$@"; do
  case "$a" in
    --opt) OPT=1 ;;
    --pages-only) PAGES_ONLY=1 ;;
    *) echo "build-wasm.sh: unknown option $a" >&2; exit 2 ;;
  esac
done
t0=$(date +%s)
WASM=target/wasm32-unknown-unknown/release/deeprep.wasm
# the full package last: target/ then holds its build, which the wasm tests and
# build-npm.sh's wasm-pack (same features) find fresh
outs=(pkg-core pkg)
if [ "$PAGES_ONLY" = 1 ]; then outs=(pkg); rm -rf web/pkg-core; fi
for out in "${outs[@]}"; do
  if [ "$out" = pkg ]; then features=(); else features=(--no-default-features --features onnx); fi
  cargo build -p deeprep --lib --release "${features[@]}" "${WASM_CARGO_FLAGS[@]}"
  rm -rf "web/$out"
  wasm-bindgen "$WASM" --out-dir "web/$out" --target web --typescript --remove-name-section --remove-producers-section
  if [ "$OPT" = 1 ]; then
    node_modules/.bin/wasm-opt "web/$out/deeprep_bg.wasm" -Os -o "web/$out/deeprep_bg.wasm" \
      --enable-reference-types --enable-bulk-memory --enable-nontrapping-float-to-int \
      --enable-sign-ext --enable-multivalue --enable-mutable-globals
  fi
  # the core again with relaxed SIMD: web/pkg-core/deeprep_relaxed_bg.wasm
  if [ "$out" = pkg-core ]; then bash scripts/build-relaxed-core.sh web/pkg-core; fi
done
if [ "$PAGES_ONLY" = 1 ]; then
  echo "{\"pages_only\": 1, \"build_seconds\": $(( $(date +%s) - t0 ))}"
  exit 0
fi
size() { echo "\"$1_bytes\": $(stat -c %s "web/$2"), \"$1_gzip_bytes\": $(gzip -9 -c "web/$2" | wc -c)"; }
echo "{$(size wasm pkg/deeprep_bg.wasm), $(size core_wasm pkg-core/deeprep_bg.wasm), $(size core_relaxed_wasm pkg-core/deeprep_relaxed_bg.wasm), \"optimized\": $OPT, \"build_seconds\": $(( $(date +%s) - t0 ))}"
