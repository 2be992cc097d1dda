#!/usr/bin/env bash
# npm-package test: pack the package (scripts/build-npm.sh), install the
# tarball into a fresh Vite app made here, `vite build` it, serve dist/ and
# run it in headless Chromium: `DeeprepClient.create()` with no arguments
# (the models shipped in the package, found through import.meta.url), a
# BVH parsed in the worker, and a synthesis between two keys.
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
<!doctype html><html><head><link rel="icon" href="data:,"></head><body><pre id="out"></pre><script type="module" src="/main.js"></script></body></html>
HTML
cat > main.js <<'JS'
import init, { convertRotations, BvhClip, version } from 'deeprep';
import { DeeprepClient } from 'deeprep/client.js';
try {
  await init();
  const sixd = convertRotations('quat', '6d', new Float32Array([0, 0, 0, 1]));
  const client = await DeeprepClient.create();
  const skel = BvhClip.parse(client.skeletonBvh);
  const row = Array.from({ length: skel.channelCount }, (_, i) => (i === 1 ? 90 : 0));
  const clip = await client.importBvh(new TextEncoder().encode(
    `${client.skeletonBvh.replace(/MOTION[\s\S]*/, '')}MOTION\nFrames: 2\nFrame Time: 0.0166667\n${row.join(' ')}\n${row.join(' ')}\n`));
  const r = await client.synthesize({ keyFrames: [0, 59], keyChannels: [...row, ...row], frames: 60, post: true });
  let code = null;
  await client.importBvh(new TextEncoder().encode('HIERARCHY\nnot a bvh')).catch((e) => { code = e.code; });
  if (r.frames !== 60 || clip.frameCount !== 2 || code !== 'E_BAD_BVH') throw new Error(`unexpected: ${r.frames} ${clip.frameCount} ${code}`);
  document.getElementById('out').textContent = `deeprep ${version()} 6d ${Array.from(sixd)}; synthesized ${r.frames} frames (${r.method}); bad BVH -> ${code}`;
  document.body.dataset.done = '1';
} catch (e) {
  document.body.dataset.error = `${e.code || ''} ${e.message}`;
}
JS
npx vite build --logLevel warn
test -f dist/index.html
ls dist/assets | grep -q '\.wasm$' || { echo "vite build emitted no .wasm asset"; exit 1; }
ls dist/assets | grep -q 'tween_generator.*\.onnx$' || { echo "vite build did not ship the models: $(ls dist/assets)"; exit 1; }
echo "vite smoke: built $(ls dist/assets | wc -l) assets from $(basename "$TGZ")"
node "$ROOT/tests/npm/run_dist.mjs" "$APP/dist"
