// docs/robot_retarget.svg: RobotExpressive's Walking (the CC0 glTF in
// ../shared/data/gltf) as the robot plays it, retargeted onto the model's
// skeleton, and back on the robot, side views of four frames each.
//   cargo build --release --bin deeprep && node docs/experiments/robot_retarget_picture.mjs
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { execFileSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { Vector3 } from 'three';
import { BVHLoader } from 'three/examples/jsm/loaders/BVHLoader.js';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { Character } from '../../web/three.js';
import { asResult, play } from '../../tests/web/three_tracks.mjs';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const CLI = path.join(ROOT, 'target/release/deeprep');
const buf = fs.readFileSync(path.resolve(ROOT, '../shared/data/gltf/RobotExpressive.glb'));
const gltf = await new Promise((ok, no) => new GLTFLoader().parse(buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength), '', ok, no));
const character = new Character(gltf.scene);
const walk = gltf.animations.find((a) => a.name === 'Walking');
const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'deeprep-picture-'));
const [src, onModel, back] = ['robot.bvh', 'model.bvh', 'back.bvh'].map((f) => path.join(dir, f));
fs.writeFileSync(src, character.toBvh(walk, { fps: 30 }));
execFileSync(CLI, ['bvh', 'retarget', src, '--to', 'model', '-o', onModel], { stdio: 'pipe' });
execFileSync(CLI, ['bvh', 'retarget', onModel, '--to', src, '-o', back], { stdio: 'pipe' });
const FRAMES = [0, 7, 14, 21];

/** Joint positions and bones (parent, child pairs) of a BVH at the frames, by three's BVHLoader. */
function bvhPoses(text) {
  const r = new BVHLoader().parse(text);
  const bones = r.skeleton.bones;
  const poses = FRAMES.map((f) => {
    for (const t of r.clip.tracks) {
      const [name, prop] = t.name.split('.');
      const b = bones.find((x) => x.name === name);
      if (prop === 'position') b.position.fromArray(t.values, f * 3);
      else b.quaternion.fromArray(t.values, f * 4);
    }
    bones[0].updateMatrixWorld(true);
    return bones.map((b) => b.getWorldPosition(new Vector3()));
  });
  const lines = bones.map((b, i) => [bones.indexOf(b.parent), i]).filter(([p]) => p >= 0);
  return { poses, lines };
}

/** The robot's bones where AnimationMixer puts them. */
function robotPoses(clip) {
  const poses = play(character, clip, FRAMES.map((f) => f / 30));
  // the body's bones: not the root bone's links to the body and the IK pole targets
  const lines = character.parent.map((p, i) => [p, i])
    .filter(([p, i]) => p >= 0 && p !== character.top && !/PoleTarget/.test(character.names[i]));
  return { poses, lines };
}

const result = asResult(fs.readFileSync(back, 'utf8'));

const panels = [
  ['the robot, its own clip', robotPoses(walk)],
  ["on the model's skeleton", bvhPoses(fs.readFileSync(onModel, 'utf8'))],
  ['back on the robot', robotPoses(character.clipFrom(result))],
];
// side views (z right, y up): a row per panel, a column per frame, each row at its own scale
const W = 170, H = 190, pad = 12, left = 200;
let svg = `<svg xmlns="http://www.w3.org/2000/svg" width="${left + FRAMES.length * W}" height="${panels.length * H + 50}" font-family="sans-serif" font-size="13">\n<rect width="100%" height="100%" fill="white"/>\n`;
FRAMES.forEach((f, c) => { svg += `<text x="${left + c * W + W / 2}" y="18" text-anchor="middle">frame ${f}</text>\n`; });
panels.forEach(([title, { poses, lines }], k) => {
  const all = poses.flat();
  const [y0, y1] = [Math.min(...all.map((p) => p.y)), Math.max(...all.map((p) => p.y))];
  const zc = all.reduce((a, p) => a + p.z, 0) / all.length;
  const s = (H - 2 * pad) / (y1 - y0);
  const top = 25 + k * H;
  svg += `<text x="8" y="${top + H / 2}">${title}</text>\n`;
  poses.forEach((pose, c) => {
    const X = (p) => left + c * W + W / 2 + (p.z - zc) * s, Y = (p) => top + H - pad - (p.y - y0) * s;
    const d = lines.map(([a, b]) => `M${X(pose[a]).toFixed(1)} ${Y(pose[a]).toFixed(1)}L${X(pose[b]).toFixed(1)} ${Y(pose[b]).toFixed(1)}`).join('');
    svg += `<path d="${d}" stroke="${['#1f77b4', '#ff7f0e', '#1f77b4'][k]}" stroke-width="2" fill="none"/>\n`;
  });
});
svg += `<text x="8" y="${panels.length * H + 42}" font-size="11">RobotExpressive's Walking (29 frames at 30 fps), side views; node docs/experiments/robot_retarget_picture.mjs</text>\n</svg>\n`;
fs.writeFileSync(path.join(ROOT, 'docs/robot_retarget.svg'), svg);
console.log(`wrote docs/robot_retarget.svg (${svg.length} bytes)`);
