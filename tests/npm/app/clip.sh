#!/usr/bin/env bash
# Puts clip.json (and, when ../shared/data is there, a CMU clip as clip.bvh
# and the CC0 RobotExpressive glTF as robot.glb) in the folder the app is
# served from (argument 1).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../../.." && pwd)"
CLIP="$ROOT/../shared/data/cmu-bvh/salsa/01.bvh"
ROBOT="$ROOT/../shared/data/gltf/RobotExpressive.glb"
if [ -f "$CLIP" ] && [ -f "$ROBOT" ]; then
  cp "$CLIP" "$1/clip.bvh"
  cp "$ROBOT" "$1/robot.glb"
  echo '{"clip": "./clip.bvh", "robot": "./robot.glb"}' > "$1/clip.json"
else
  echo "SKIP: ../shared/data is absent; the app runs without a CMU clip and the glTF robot" >&2
  echo '{"clip": null, "robot": null}' > "$1/clip.json"
fi
