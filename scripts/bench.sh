#!/usr/bin/env bash
# Full benchmarks: in-betweening per stage natively (release) and in headless
# Chromium (wasm), 512-4096 frames, with the SLERP+LERP baseline beside them;
# tract against onnxruntime-web on every bundled model in one page;
# then the mesh autoencoder's encode/decode with tract (native, as exported
# and with its kernels multiplied out at load), onnxruntime, and in Chromium;
# then HairNet's Table 3.3 columns natively and in Chromium; then the npm
# package's time to first result in a Vite production build.
# Prints JSON. Assumes scripts/setup.sh has run.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
cargo bench --bench inbetween
bash scripts/build-wasm.sh >/dev/null
node tests/web/bench_page.mjs
# the residual network's plan for any length against a length's own plan, alternately
node tests/web/bench_plans.mjs
# tract against onnxruntime-web on every bundled model, side by side in one page
node tests/web/bench_ort_page.mjs
# where tract spends its time: every node of each model's plan timed, per operator
cargo run --release --example profile_models
cargo bench --bench mesh
PYTHONPATH=train .venv/bin/python -m deeprep_train.mesh.bench_ort
node tests/web/bench_mesh_page.mjs
cargo bench --bench hair
node tests/web/bench_hair_page.mjs
# The npm package as a web editor ships it: a Vite production build of
# tests/npm/app, time from navigation to the first synthesis result
# (median of 5 loads, each in a fresh browser profile).
bash scripts/build-npm.sh >/dev/null
DEEPREP_NPM_RUNS=5 bash tests/npm/vite_smoke.sh | tail -1
