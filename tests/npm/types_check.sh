#!/usr/bin/env bash
# The package's .d.ts files type-check under `strict` without skipLibCheck,
# with lib ["es2023", "dom"] (issue 54): a fresh project installs the packed
# tarball and TypeScript and compiles a file that uses the client's API.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
TGZ=$(ls "$ROOT"/pkg/deeprep-*.tgz | head -1)
APP=$(mktemp -d)
trap 'rm -rf "$APP"' EXIT
cd "$APP"
echo '{ "name": "deeprep-types", "private": true, "type": "module" }' > package.json
npm install --no-audit --no-fund --silent "typescript@5.9.3" "@types/three@0.180.0" "@webgpu/types@0.1.66" "three@0.187.0" "$TGZ"
cat > tsconfig.json <<'JSON'
{ "compilerOptions": { "strict": true, "skipLibCheck": false, "noEmit": true, "target": "es2022",
  "module": "esnext", "moduleResolution": "bundler", "lib": ["es2023", "dom"] }, "files": ["main.ts"] }
JSON
cat > main.ts <<'TS'
// three's own types need @webgpu/types (deeprep's do not)
/// <reference types="@webgpu/types" />
import init, { convertRotations } from 'deeprep';
import { DeeprepClient, DeeprepError } from 'deeprep/client.js';
import { toThree } from 'deeprep/three.js';
export async function run(text: string): Promise<number> {
  await init();
  const q: Float32Array = convertRotations('quat', '6d', new Float32Array([0, 0, 0, 1]));
  const c = await DeeprepClient.create({ onProgress: (p) => console.log(p.stage) });
  const r = await c.synthesizeFromBvh(text, { keys: [0, 60] });
  const f = await c.fillGaps(text, [{ start: 10, end: 20 }], { method: 'hermite' });
  const on: string = await c.retarget(text, { to: 'model', map: { leftShin: 'Knee_L', leftToe: null } });
  const three = toThree(r, c.skeleton);
  try { await c.importBvh(new Uint8Array(0)); } catch (e) { if (e instanceof DeeprepError) return e.code.length; }
  return q.length + r.frames + f.frames + on.length + three.clip.duration;
}
TS
npx tsc -p tsconfig.json
echo "types check: strict, lib es2023 + dom, no skipLibCheck: clean"
