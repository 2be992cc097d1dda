#!/usr/bin/env bash
# npm-package test: pack the package (scripts/build-npm.sh), install the
# tarball into a fresh Vite app made here, `vite build` it, serve dist/ and
# run it in headless Chromium: tests/npm/app/main.js (what it checks is
# written there).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
TGZ=$(ls "$ROOT"/pkg/deeprep-*.tgz | head -1)
APP=$(mktemp -d)
trap 'rm -rf "$APP"' EXIT
cd "$APP"
cat > package.json <<'JSON'
{ "name": "deeprep-vite-smoke", "private": true, "type": "module", "scripts": { "build": "vite build" } }
JSON
npm install --no-audit --no-fund --silent "vite@8.3.4" "three@0.187.0" "$TGZ"
cp "$ROOT/tests/npm/app/index.html" "$ROOT/tests/npm/app/main.js" .
mkdir -p public
bash "$ROOT/tests/npm/app/clip.sh" public
npx vite build --logLevel warn
test -f dist/index.html
ls dist/assets | grep -q '\.wasm$' || { echo "vite build emitted no .wasm asset"; exit 1; }
ls dist/assets | grep -q 'tween_generator.*\.onnx$' || { echo "vite build did not ship the models: $(ls dist/assets)"; exit 1; }
echo "vite smoke: built $(ls dist/assets | wc -l) assets from $(basename "$TGZ")"
# one run here; scripts/bench.sh loads it 5 times for the first-result timing
node "$ROOT/tests/npm/run_dist.mjs" "$APP/dist" --runs "${DEEPREP_NPM_RUNS:-1}"
