#!/usr/bin/env bash
# Runs every test: native Rust, Python parity (onnxruntime), wasm in headless
# Chromium (wasm-bindgen-test), and the page in Chromium (Playwright).
# Assumes scripts/setup.sh has run (the README's test command runs both).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
t_start=$(date +%s)
# each section's name and start, for the summary table at the end
names=(); starts=()
section() {
  names+=("$*"); starts+=("$(date +%s)")
  printf '\n==== %s (t+%ss)\n' "$*" "$(( $(date +%s) - t_start ))"
}
summary() {
  local end; end=$(date +%s)
  printf '\n==== summary: seconds per section\n'
  for i in "${!names[@]}"; do
    local next=${starts[$((i + 1))]:-$end}
    printf '%6s  %s\n' "$(( next - starts[i] ))" "${names[$i]:0:70}"
  done
  printf '%6s  total\n' "$(( end - t_start ))"
}
trap summary EXIT

section "lint: cargo fmt, clippy for wasm32 (warnings are errors)"
bash scripts/lint.sh --no-native-clippy

# Natively, clippy is the workspace's compiler (scripts/native-cargo.sh): the
# test build is the lint, with warnings as errors, and every native cargo
# command below shares it.
section "native: clippy and cargo test (every target: lib, CLI, tests, benches, examples)"
bash scripts/native-cargo.sh test --workspace --all-targets --no-run
bash scripts/native-cargo.sh test --workspace

section "fuzz: smoke (10^4 executions per target; full runs: bash scripts/fuzz.sh --runs 1000000)"
# the smoke's build at opt-level 1 without debug info (about 15 s less to
# compile; debug assertions and overflow checks stay on): 10^4 executions
# take seconds either way
CARGO_PROFILE_RELEASE_OPT_LEVEL=1 CARGO_PROFILE_RELEASE_DEBUG=0 bash scripts/fuzz.sh --runs 10000

section "parity: onnxruntime against committed fixtures"
.venv/bin/python -m pytest -q tests/parity

section "wasm: build the package"
bash scripts/build-wasm.sh

section "wasm: wasm-bindgen-test in headless Chromium"
(
  source scripts/wasm-env.sh
  export WASM_BINDGEN_USE_BROWSER=1
  export WASM_BINDGEN_TEST_TIMEOUT=300
  # wasm-bindgen-test-runner reads crate/webdriver.json (cargo runs it in the package root)
  cargo test -p deeprep --release "${WASM_CARGO_FLAGS[@]}" --test wasm_browser
)

section "bench: smoke runs (one 512-frame in-betweening, one mesh encode/decode, one hair reconstruction; full run: bash scripts/bench.sh)"
DEEPREP_BENCH_SMOKE=1 bash scripts/native-cargo.sh test --bench inbetween
node tests/web/bench_page.mjs --smoke
node tests/web/bench_ort_page.mjs --smoke
node tests/web/bench_plans.mjs 256
DEEPREP_BENCH_SMOKE=1 bash scripts/native-cargo.sh test --bench mesh
node tests/web/bench_mesh_page.mjs --smoke
DEEPREP_BENCH_SMOKE=1 bash scripts/native-cargo.sh test --bench hair
node tests/web/bench_hair_page.mjs --smoke

section "npm package: wasm-pack, npm pack, fresh Vite, webpack 5 and esbuild apps, a CDN page, Node, strict types"
bash scripts/build-npm.sh --core-from web/pkg-core
bash tests/npm/vite_smoke.sh
bash tests/npm/webpack_smoke.sh
bash tests/npm/esbuild_smoke.sh
node tests/npm/cdn_smoke.mjs pkg
bash tests/npm/node_smoke.sh
bash tests/npm/types_check.sh

section "static site: web/dist"
bash scripts/build-site.sh

section "web: the page in headless Chromium (Playwright)"
# two test files at a time: each is mostly a browser waiting on its renderer
node --test --test-concurrency=2 tests/web/

trap - EXIT
summary
printf '\nall tests passed\n'
