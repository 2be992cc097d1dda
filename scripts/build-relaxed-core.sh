#!/usr/bin/env bash
# Builds the in-betweening worker's core wasm (no GPU code) a second time
# with relaxed SIMD (`+relaxed-simd`: tract's 8x8 matrix kernel then fuses
# its multiply-adds, f32x4.relaxed_madd), as DIR/deeprep_relaxed_bg.wasm
# beside the plain build in DIR. worker.js loads it where the browser
# validates relaxed SIMD (Chrome 114+) and the plain module elsewhere, with
# one JS glue file: the glue wasm-bindgen makes for this build must equal
# DIR/deeprep.js, or this script fails. Its own target directory, since
# other RUSTFLAGS would rebuild the whole dependency graph in place.
#   scripts/build-relaxed-core.sh DIR      (web/pkg-core, pkg/core)
set -euo pipefail
source "$(dirname "$0")/wasm-env.sh"
out="$(cd "${1:?usage: build-relaxed-core.sh DIR}" && pwd)"
cd "$ROOT"
export CARGO_TARGET_DIR="$ROOT/target/relaxed"
export CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUSTFLAGS="-C target-feature=+simd128,+relaxed-simd"
cargo build -p deeprep --lib --release --no-default-features --features onnx "${WASM_CARGO_FLAGS[@]}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
wasm-bindgen "$CARGO_TARGET_DIR/wasm32-unknown-unknown/release/deeprep.wasm" --out-dir "$tmp" \
  --target web --remove-name-section --remove-producers-section
if ! cmp -s "$tmp/deeprep.js" "$out/deeprep.js"; then
  echo "build-relaxed-core.sh: the relaxed build's JS glue differs from $out/deeprep.js" >&2
  exit 1
fi
cp "$tmp/deeprep_bg.wasm" "$out/deeprep_relaxed_bg.wasm"
