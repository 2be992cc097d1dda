#!/usr/bin/env bash
# Builds the in-betweening worker's core wasm (no GPU code) a second time
# with relaxed SIMD (`+relaxed-simd`: our 3x12 matrix kernel, the one place
# that asks for it, then fuses its multiply-adds, f32x4.relaxed_madd), as
# DIR/deeprep_relaxed_bg.wasm beside the plain build in DIR. worker.js loads
# it where the browser validates relaxed SIMD (Chrome 114+) and the plain
# module elsewhere, with one JS glue file: the glue wasm-bindgen makes for
# this build must equal DIR/deeprep.js, or this script fails.
#
# Only the deeprep crate is compiled with the feature (a per-package profile
# rustflag, cargo's -Zprofile-rustflags): the dependencies, std included, are
# the plain build's, in the same target directory, and both deeprep builds
# stay cached side by side (the flag is part of the crate's hash). Building
# everything with RUSTFLAGS instead compiled std and tract a second time
# (issue 48).
#   scripts/build-relaxed-core.sh DIR      (web/pkg-core, pkg/core)
set -euo pipefail
source "$(dirname "$0")/wasm-env.sh"
out="$(cd "${1:?usage: build-relaxed-core.sh DIR}" && pwd)"
cd "$ROOT"
cargo build -p deeprep --lib --release --no-default-features --features onnx "${WASM_CARGO_FLAGS[@]}" \
  -Zprofile-rustflags --config 'profile.release.package.deeprep.rustflags=["-Ctarget-feature=+relaxed-simd"]'
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
wasm-bindgen target/wasm32-unknown-unknown/release/deeprep.wasm --out-dir "$tmp" \
  --target web --remove-name-section --remove-producers-section
if ! cmp -s "$tmp/deeprep.js" "$out/deeprep.js"; then
  echo "build-relaxed-core.sh: the relaxed build's JS glue differs from $out/deeprep.js" >&2
  exit 1
fi
cp "$tmp/deeprep_bg.wasm" "$out/deeprep_relaxed_bg.wasm"
