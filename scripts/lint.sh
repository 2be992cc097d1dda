#!/usr/bin/env bash
# Formatting and clippy, natively and for the wasm32 target (the wasm-bindgen
# layer compiles only there). Warnings are errors. Run from anywhere.
#   bash scripts/lint.sh                    fmt, clippy native and wasm32
#   bash scripts/lint.sh --no-native-clippy fmt, clippy wasm32 only: scripts/test.sh
#                                           lints natively while it builds the tests
#                                           (scripts/native-cargo.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
NATIVE=1
for a in "$@"; do
  case "$a" in
    --no-native-clippy) NATIVE=0 ;;
    *) echo "lint.sh: unknown option $a" >&2; exit 2 ;;
  esac
done
cargo fmt --all --check
if [ "$NATIVE" = 1 ]; then cargo clippy --all-targets -q -- -D warnings; fi
# wasm32: Debian's rustc-web with -Zbuild-std, and its clippy (rust-web-clippy,
# installed by scripts/setup.sh); both the CPU-only and the GPU feature sets.
source scripts/wasm-env.sh
if [ ! -x "$SHIM/clippy-driver" ]; then
  echo "lint: SKIP wasm32 clippy: rust-web-clippy is not installed (bash scripts/setup.sh)" >&2
  exit 0
fi
# Clippy is deeprep's compiler here (a workspace wrapper, as `cargo clippy`
# does) but the dependencies are the release build's own, compiled as
# scripts/build-wasm.sh compiles them: `cargo clippy` would check std, tract
# and wgpu a second time in check mode (about two minutes, issue 48).
# -Zno-codegen: lints only, no code (the build compiles the crate itself).
wasm_clippy() {
  RUSTC_WORKSPACE_WRAPPER="$SHIM/clippy-driver" cargo rustc -p deeprep --lib "${WASM_CARGO_FLAGS[@]}" \
    --release "$@" --crate-type lib -q -- -Zno-codegen -D warnings
}
wasm_clippy --no-default-features --features onnx
wasm_clippy
if [ "$NATIVE" = 1 ]; then echo "lint: fmt, clippy (native, wasm32) clean"; else echo "lint: fmt, clippy (wasm32) clean"; fi
