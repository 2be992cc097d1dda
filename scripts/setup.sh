#!/usr/bin/env bash
# Installs everything deeprep needs on a fresh Debian 12 machine, from the
# package registries only. Idempotent: a second run checks and skips.
set -euo pipefail
cd "$(dirname "$0")/.."
SUDO=""; [ "$(id -u)" = 0 ] || SUDO=sudo
export PATH="$HOME/.cargo/bin:$PATH"
step() { printf '\n== setup: %s\n' "$*"; }

APT_PKGS=(rustc-web cargo-web rust-web-src rust-web-clippy lld binaryen chromium chromium-driver mesa-vulkan-drivers libvulkan1)
step "Debian packages: ${APT_PKGS[*]}"
if ! dpkg -s "${APT_PKGS[@]}" >/dev/null 2>&1; then
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q "${APT_PKGS[@]}"
fi
/usr/bin/rustc --version

# Host tools, built with the rustup toolchain. wasm-bindgen-cli must match
# the wasm-bindgen version in Cargo.lock exactly. Unlocked installs: the
# registry mirror lacks one of their pinned dependencies.
WB_VERSION=$(awk '/^name = "wasm-bindgen"$/{getline; gsub(/version = |"/,""); print; exit}' Cargo.lock)
WASM_PACK_VERSION=0.15.1
step "wasm-bindgen-cli $WB_VERSION, wasm-pack $WASM_PACK_VERSION"
if ! wasm-bindgen --version 2>/dev/null | grep -q "$WB_VERSION"; then
  cargo install wasm-bindgen-cli --version "=$WB_VERSION" --force
fi
if ! wasm-pack --version 2>/dev/null | grep -q "$WASM_PACK_VERSION"; then
  cargo install wasm-pack --version "=$WASM_PACK_VERSION" --force
fi

step "npm dev dependencies (playwright-core drives /usr/bin/chromium; no browser download)"
export PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1
if [ ! -d node_modules/playwright-core ] || [ package-lock.json -nt node_modules/.package-lock.json ]; then
  npm ci --no-audit --no-fund
fi

step "Python venv for the parity tests (.venv: numpy, onnx, onnxruntime, pytest; no torch)"
if [ ! -x .venv/bin/python ]; then python3 -m venv .venv; fi
if ! .venv/bin/python -c "import numpy, onnx, onnxruntime, pytest" 2>/dev/null; then
  .venv/bin/pip install -q -r requirements-test.txt
fi
step "done"
