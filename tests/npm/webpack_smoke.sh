#!/usr/bin/env bash
# npm-package test with webpack 5: the same app as vite_smoke.sh
# (tests/npm/app/main.js) built by webpack in production mode against the
# packed tarball, served and run in headless Chromium.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
TGZ=$(ls "$ROOT"/pkg/deeprep-*.tgz | head -1)
APP=$(mktemp -d)
trap 'rm -rf "$APP"' EXIT
cd "$APP"
cat > package.json <<'JSON'
{ "name": "deeprep-webpack-smoke", "private": true, "type": "module" }
JSON
npm install --no-audit --no-fund --silent "webpack@5" "webpack-cli@5" "three@0.187.0" "$TGZ"
mkdir -p src dist
cp "$ROOT/tests/npm/app/main.js" src/main.js
bash "$ROOT/tests/npm/app/clip.sh" dist
sed 's#<script type="module" src="/main.js"></script>#<script type="module" src="main.js"></script>#' "$ROOT/tests/npm/app/index.html" > dist/index.html
cat > webpack.config.js <<'JS'
export default {
  mode: 'production',
  entry: './src/main.js',
  output: { path: new URL('./dist', import.meta.url).pathname, filename: 'main.js', module: true, chunkFormat: 'module' },
  experiments: { outputModule: true, topLevelAwait: true },
  performance: { hints: false },
};
JS
npx webpack --config webpack.config.js --no-stats
ls dist | grep -q '\.wasm$' || { echo "webpack emitted no .wasm asset: $(ls dist)"; exit 1; }
ls dist | grep -q '\.onnx$' || { echo "webpack did not ship the models: $(ls dist)"; exit 1; }
echo "webpack smoke: built $(ls dist | wc -l) files from $(basename "$TGZ")"
node "$ROOT/tests/npm/run_dist.mjs" "$APP/dist"
