#!/usr/bin/env bash
# Writes web/dist/: the pages, the wasm package and the models, laid out so
# any static file server (or an offline copy) serves it:
#   web/dist/index.html -> web/, web/dist/web/* (three.js under web/vendor/three), web/dist/models/{onnx,examples},
#   web/dist/shared-data/gltf/ (the CC0 robot and its licence, when ../shared/data has them)
#   scripts/build-site.sh           uses the current web/pkg (builds it if missing)
#   scripts/build-site.sh --opt     rebuilds web/pkg with wasm-opt first
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--opt" ] || [ ! -f web/pkg/deeprep_bg.wasm ] || [ ! -f web/pkg-core/deeprep_bg.wasm ]; then bash scripts/build-wasm.sh ${1:-}; fi
rm -rf web/dist
mkdir -p web/dist/web web/dist/models/onnx web/dist/models/examples
cp web/*.html web/*.js web/dist/web/
cp -r web/lib web/sketch web/dist/web/
cp -r web/pkg web/dist/web/pkg
cp -r web/pkg-core web/dist/web/pkg-core
# three.js (MIT) for the sketching page's glTF import, loaded only when a .glb is imported
for f in build/three.module.js build/three.core.js examples/jsm/loaders/GLTFLoader.js \
         examples/jsm/utils/BufferGeometryUtils.js examples/jsm/utils/SkeletonUtils.js LICENSE; do
  mkdir -p "web/dist/web/vendor/three/$(dirname "$f")"
  cp "node_modules/three/$f" "web/dist/web/vendor/three/$f"
done
cp models/onnx/*.onnx models/onnx/*.manifest.json web/dist/models/onnx/
cp models/examples/*.json web/dist/models/examples/
# the mesh page's robot (CC0, with its licence) where the shared data is
# beside the repository; without it that page asks the visitor for a file
GLTF="${DEEPREP_DATA:-../shared/data}/gltf"
if [ -f "$GLTF/RobotExpressive.glb" ]; then
  mkdir -p web/dist/shared-data/gltf
  cp "$GLTF/RobotExpressive.glb" web/dist/shared-data/gltf/
  [ -f "$GLTF/RobotExpressive.README.md" ] && cp "$GLTF/RobotExpressive.README.md" web/dist/shared-data/gltf/
else
  echo "build-site: $GLTF/RobotExpressive.glb is absent; the mesh page will ask for a .glb" >&2
fi
# the JavaScript API reference, from the package's type declarations
node scripts/api-docs.mjs web/dist/api.html
cat > web/dist/index.html <<'HTML'
<!doctype html><meta charset="utf-8"><title>deeprep</title><link rel="icon" href="data:,">
<meta http-equiv="refresh" content="0; url=web/index.html"><a href="web/index.html">deeprep</a>
HTML
echo "web/dist: $(du -sh web/dist | cut -f1) in $(find web/dist -type f | wc -l) files"
