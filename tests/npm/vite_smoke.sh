#!/usr/bin/env bash
# npm-package smoke test: pack the package (scripts/build-npm.sh), install the
# tarball into a fresh Vite project made here, import the API, and build.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
TGZ=$(ls "$ROOT"/pkg/deeprep-*.tgz | head -1)
APP=$(mktemp -d)
trap 'rm -rf "$APP"' EXIT
cd "$APP"
cat > package.json <<'JSON'
{ "name": "deeprep-vite-smoke", "private": true, "type": "module", "scripts": { "build": "vite build" } }
JSON
npm install --no-audit --no-fund --silent "vite@8.3.4" "$TGZ"
cat > index.html <<'HTML'
<!doctype html><html><body><pre id="out"></pre><script type="module" src="/main.js"></script></body></html>
HTML
cat > main.js <<'JS'
import init, { convertRotations, BvhClip, version } from 'deeprep';
import { DeeprepClient } from 'deeprep/client.js';
await init();
const sixd = convertRotations('quat', '6d', new Float32Array([0, 0, 0, 1]));
document.getElementById('out').textContent = `deeprep ${version()} ${Array.from(sixd)} ${typeof BvhClip} ${typeof DeeprepClient}`;
JS
npx vite build --logLevel warn
test -f dist/index.html
ls dist/assets | grep -q '\.wasm$' || { echo "vite build emitted no .wasm asset"; exit 1; }
echo "vite smoke: built $(ls dist/assets | wc -l) assets from $(basename "$TGZ")"
