#!/usr/bin/env bash
# Runs cargo for the native target with clippy as the compiler of the
# workspace's own crates (RUSTC_WORKSPACE_WRAPPER=clippy-driver, what
# `cargo clippy` sets up, but here with code generation), so one build both
# lints (warnings are errors) and produces the test binaries: the test run
# needs no separate `cargo clippy` pass over the same code (issue 48).
# Dependencies are compiled by plain rustc, as with `cargo clippy`. Every
# native cargo command in scripts/test.sh goes through this script, so they
# agree on the compiler and nothing is rebuilt between them.
#   bash scripts/native-cargo.sh test --workspace
#   bash scripts/native-cargo.sh test --test native bvh
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
driver="$(rustc --print sysroot)/bin/clippy-driver"
if [ ! -x "$driver" ]; then
  echo "native-cargo.sh: $driver not found (rustup component add clippy)" >&2
  exit 1
fi
export RUSTC_WORKSPACE_WRAPPER="$driver"
# cargo-clippy's encoding of `-- -D warnings`
export CLIPPY_ARGS="-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__"
exec cargo "$@"
