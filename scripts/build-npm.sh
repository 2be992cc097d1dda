#!/usr/bin/env bash
# Builds the npm package `deeprep` with wasm-pack into pkg/ (ESM, --target
# web, TypeScript types), adds the worker-backed client (client.js,
# worker.js, client.d.ts), and packs it: pkg/deeprep-<version>.tgz.
#   scripts/build-npm.sh                      builds everything
#   scripts/build-npm.sh --core-from web/pkg-core
#       takes the core and its relaxed twin from scripts/build-wasm.sh's output
#       of the same sources (scripts/test.sh, one run): switching the crate's
#       features would otherwise recompile it twice more (about a minute).
set -euo pipefail
source "$(dirname "$0")/wasm-env.sh"
cd "$ROOT"
CORE_FROM=
while [ $# -gt 0 ]; do
  case "$1" in
    --core-from) CORE_FROM="$(cd "${2:?--core-from DIR}" && pwd)"; shift 2 ;;
    *) echo "build-npm.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
if [ -n "$CORE_FROM" ] && [ ! -f "$CORE_FROM/deeprep_relaxed_bg.wasm" ]; then
  echo "build-npm.sh: $CORE_FROM has no core build (bash scripts/build-wasm.sh)" >&2; exit 2
fi
rm -rf pkg
wasm-pack build crate --mode force --no-opt --target web --out-dir ../pkg --out-name deeprep --release -- "${WASM_CARGO_FLAGS[@]:2}"
cp web/client.js pkg/client.js
# the worker protocol client.js is built on (shared with the demo pages), and
# the feature probe worker.js picks its wasm build with
mkdir -p pkg/lib && cp web/lib/workers.js web/lib/wasm-features.js pkg/lib/
cp web/three.js pkg/three.js
# DeeprepClient in Node: the worker on worker_threads
cp web/node-worker.js pkg/node-worker.js
sed "s#'./pkg-core/#'./core/#g" web/worker.js > pkg/worker.js
# The worker's package without the GPU code (a smaller download: the in-betweening
# needs no wgpu), in pkg/core/, with its relaxed-SIMD twin
# (deeprep_relaxed_bg.wasm, worker.js picks it where the browser has it).
if [ -n "$CORE_FROM" ]; then
  mkdir -p pkg/core
  for f in deeprep.js deeprep.d.ts deeprep_bg.wasm deeprep_bg.wasm.d.ts deeprep_relaxed_bg.wasm; do
    cp "$CORE_FROM/$f" pkg/core/
  done
else
  cargo build -p deeprep --lib --release --no-default-features --features onnx "${WASM_CARGO_FLAGS[@]:2}" --target wasm32-unknown-unknown
  wasm-bindgen target/wasm32-unknown-unknown/release/deeprep.wasm --out-dir pkg/core --target web --remove-name-section --remove-producers-section
  rm -f pkg/core/.gitignore pkg/core/package.json
  bash scripts/build-relaxed-core.sh pkg/core
fi
# Strip debug sections (the name section alone was 14 MB) with binaryen from
# npm (Debian's wasm-opt is too old for wasm-bindgen's reference types). No
# -Os: it shrinks the raw file but grows the gzip'd download (README, size).
for w in pkg/deeprep_bg.wasm pkg/core/deeprep_bg.wasm pkg/core/deeprep_relaxed_bg.wasm; do
  node_modules/.bin/wasm-opt "$w" -O0 --strip-debug --strip-producers -o "$w" \
    --enable-reference-types --enable-bulk-memory --enable-nontrapping-float-to-int \
    --enable-sign-ext --enable-multivalue --enable-mutable-globals --enable-simd --enable-relaxed-simd
done
# The models the client loads by default, found beside worker.js.
mkdir -p pkg/models
for f in tween_generator.onnx tween_path.onnx tween_generator.manifest.json tween_residual.onnx tween_residual.manifest.json tween_cond.onnx tween_cond.manifest.json tween_cond_dna.onnx tween_cond_dna.manifest.json tween_fill.onnx tween_fill.manifest.json tween_fill_long.onnx tween_fill_long.manifest.json ik.onnx ik.manifest.json; do
  cp "models/onnx/$f" pkg/models/
done
cp npm/README.md pkg/README.md
cp LICENSE-MIT LICENSE-APACHE pkg/
cp web/three.d.ts pkg/three.d.ts
# the client's types are a source file beside it
cp web/client.d.ts pkg/client.d.ts
# wasm-bindgen's classes declare [Symbol.dispose]: name the library that
# defines it, so the types check under lib es2023 without skipLibCheck
for d in pkg/deeprep.d.ts pkg/core/deeprep.d.ts; do
  if [ -f "$d" ] && grep -q 'Symbol.dispose' "$d" && ! grep -q 'esnext.disposable' "$d"; then
    printf '/// <reference lib="esnext.disposable" />\n' | cat - "$d" > "$d.tmp" && mv "$d.tmp" "$d"
  fi
done
node -e '
const fs = require("fs");
const p = JSON.parse(fs.readFileSync("pkg/package.json", "utf8"));
p.name = "deeprep";
p.type = "module";
p.files = [...new Set([...(p.files || []), "core", "lib", "client.js", "client.d.ts", "three.js", "three.d.ts", "worker.js", "node-worker.js", "models", "README.md", "LICENSE-MIT", "LICENSE-APACHE"])];
p.peerDependencies = { three: ">=0.150.0" };
p.peerDependenciesMeta = { three: { optional: true } };
p.license = "MIT OR Apache-2.0";
p.description = p.description || "Deep representations for shapes, structures and motion in the browser: keyframe in-betweening, rotations, HairNet, mesh autoencoders (Rust + WebAssembly)";
p.keywords = ["animation", "motion", "in-betweening", "keyframes", "retargeting", "bvh", "webassembly", "wasm", "rotations", "hair", "mesh"];
p.engines = { node: ">=20" };
p.sideEffects = ["./worker.js", "./node-worker.js"];
// The publisher names the source repository (DEEPREP_REPOSITORY=https://...);
// without it the package has no repository field rather than a made-up one.
delete p.repository;
if (process.env.DEEPREP_REPOSITORY) {
  p.repository = { type: "git", url: process.env.DEEPREP_REPOSITORY };
  p.homepage = process.env.DEEPREP_REPOSITORY.replace(/\.git$/, "") + "#readme";
}
p.exports = { ".": { types: "./deeprep.d.ts", default: "./deeprep.js" }, "./client.js": { types: "./client.d.ts", default: "./client.js" }, "./three.js": { types: "./three.d.ts", default: "./three.js" }, "./worker.js": "./worker.js", "./deeprep_bg.wasm": "./deeprep_bg.wasm" };
fs.writeFileSync("pkg/package.json", JSON.stringify(p, null, 2) + "\n");
'
(cd pkg && npm pack --silent >/dev/null)
ls pkg/*.tgz
