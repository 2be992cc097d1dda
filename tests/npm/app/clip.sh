#!/usr/bin/env bash
# Puts clip.json (and, when ../shared/data is there, a CMU clip as clip.bvh)
# in the folder the app is served from (argument 1).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../../.." && pwd)"
CLIP="$ROOT/../shared/data/cmu-bvh/salsa/01.bvh"
if [ -f "$CLIP" ]; then
  cp "$CLIP" "$1/clip.bvh"
  echo '{"clip": "./clip.bvh"}' > "$1/clip.json"
else
  echo "SKIP: ../shared/data is absent; the app runs without a CMU clip" >&2
  echo '{"clip": null}' > "$1/clip.json"
fi
