#!/usr/bin/env bash
# Formatting and clippy, natively and for the wasm32 target (the wasm-bindgen
# layer compiles only there). Warnings are errors. Run from anywhere.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
cargo fmt --all --check
cargo clippy --all-targets -q -- -D warnings
# wasm32: Debian's rustc-web with -Zbuild-std, and its clippy (rust-web-clippy,
# installed by scripts/setup.sh); both the CPU-only and the GPU feature sets.
source scripts/wasm-env.sh
if [ ! -x "$SHIM/clippy-driver" ]; then
  echo "lint: SKIP wasm32 clippy: rust-web-clippy is not installed (bash scripts/setup.sh)" >&2
  exit 0
fi
cargo clippy -p deeprep --lib "${WASM_CARGO_FLAGS[@]}" --release -q -- -D warnings
cargo clippy -p deeprep --lib "${WASM_CARGO_FLAGS[@]}" --release --no-default-features --features onnx -q -- -D warnings
echo "lint: fmt, clippy (native, wasm32) clean"
