#!/usr/bin/env bash
# The packed package in Node 20+ (issue 54): installed into a fresh folder,
# DeeprepClient.create() with no arguments runs its worker on worker_threads
# with the package's wasm and models, in-betweens a clip, and rejects bad
# input with a DeeprepError; the page-side API starts with initSync and the
# package's wasm bytes.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
TGZ=$(ls "$ROOT"/pkg/deeprep-*.tgz | head -1)
APP=$(mktemp -d)
trap 'rm -rf "$APP"' EXIT
cd "$APP"
echo '{ "name": "deeprep-node-smoke", "private": true, "type": "module" }' > package.json
npm install --no-audit --no-fund --silent "$TGZ"
cat > main.mjs <<'JS'
import fs from 'node:fs';
import { createRequire } from 'node:module';
import { initSync, convertRotations, version } from 'deeprep';
import { DeeprepClient, DeeprepError } from 'deeprep/client.js';
const require = createRequire(import.meta.url);
initSync({ module: fs.readFileSync(require.resolve('deeprep/deeprep_bg.wasm')) });
const sixd = convertRotations('quat', '6d', new Float32Array([0, 0, 0, 1]));
const t0 = Date.now();
const client = await DeeprepClient.create();
const head = client.skeletonBvh.replace(/MOTION[\s\S]*/, '');
const n = client.skeletonBvh.split('CHANNELS').slice(1).reduce((a, s) => a + Number(s.trim().split(/\s+/)[0]), 0);
const rows = Array.from({ length: 121 }, (_, f) => Array.from({ length: n }, (_, i) => (i === 0 ? f : i === 1 ? 90 : i === 7 ? 20 * Math.sin(f / 20) : 0)).join(' '));
const r = await client.synthesizeFromBvh(`${head}MOTION\nFrames: 121\nFrame Time: 0.0166667\n${rows.join('\n')}\n`, { keys: [0, 60, 120] });
if (r.frames !== 121 || r.ran !== 'residual' || !r.bvh.startsWith('HIERARCHY')) throw new Error(`synthesizeFromBvh: ${r.frames} frames by ${r.ran}`);
// the DNA network, fetched on the first request with Motion DNA (method 'cond')
const pose = (f) => Array.from({ length: n }, (_, i) => (i === 0 ? f : i === 1 ? 90 : i === 7 ? 20 * Math.sin(f / 20) : 0));
const d = await client.synthesize({ method: 'cond', frames: 121, keys: [0, 60, 120].map((f) => ({ frame: f, root: [f, 90, 0] })), dna: [pose(30), pose(90)] });
if (!client.condDna || d.ran !== 'cond-dna' || d.frames !== 121) throw new Error(`Motion DNA with method cond: ${d.frames} frames by ${d.ran}`);
const bad = await client.synthesize({ keyFrames: [5, 1], keyChannels: [], frames: 10 }).then(() => null, (e) => e);
if (!(bad instanceof DeeprepError) || !bad.code) throw new Error(`a bad request rejected with ${bad}`);
client.terminate();
console.log(`node smoke: deeprep ${version()} in Node ${process.versions.node}: 6d ${Array.from(sixd)}; create() and a 121-frame in-betweening (${r.ran}) in ${Date.now() - t0} ms; DNA by ${d.ran}; worker wasm ${client.wasm}; bad keys -> ${bad.code}`);
JS
timeout 300 node main.mjs
