#!/usr/bin/env bash
# Plain esbuild (issue 54): the packed tarball installed into a fresh app,
# bundled with `esbuild main.js --bundle --format=esm`, the README's recipe
# applied (the package's worker.js, core/, lib/ and models/ copied beside the
# bundle), served and run in headless Chromium: tests/npm/esbuild_app/main.js.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
TGZ=$(ls "$ROOT"/pkg/deeprep-*.tgz | head -1)
APP=$(mktemp -d)
trap 'rm -rf "$APP"' EXIT
cd "$APP"
echo '{ "name": "deeprep-esbuild-smoke", "private": true, "type": "module" }' > package.json
npm install --no-audit --no-fund --silent "esbuild@0.28.2" "$TGZ"
cp "$ROOT/tests/npm/esbuild_app/main.js" .
mkdir -p dist
npx esbuild main.js --bundle --format=esm --outfile=dist/main.js --log-level=warning
printf '<!doctype html><meta charset="utf-8"><pre id="out"></pre><script type="module" src="./main.js"></script>\n' > dist/index.html
# the recipe: the worker and what it loads, beside the bundle
mkdir -p dist/deeprep
cp -r node_modules/deeprep/worker.js node_modules/deeprep/core node_modules/deeprep/lib node_modules/deeprep/models dist/deeprep/
echo "esbuild smoke: bundled $(wc -c < dist/main.js) bytes"
# the plain attempt's 404 for dist/worker.js is the expected failure
DEEPREP_EXPECT_404=/worker.js node "$ROOT/tests/npm/run_dist.mjs" "$APP/dist"
