// Forward kinematics checked against an implementation the project did not
// write: three.js' BVHLoader and scene graph (run in Node), on three clips of
// ../shared/data/cmu-bvh, against `deeprep bvh fk` (the native CLI).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { execFileSync } from 'node:child_process';
import { Vector3 } from 'three';
import { BVHLoader } from 'three/examples/jsm/loaders/BVHLoader.js';
import { ROOT } from './chromium.mjs';

const DATA = path.resolve(ROOT, '../shared/data/cmu-bvh');
const CLIPS = ['salsa/01.bvh', 'martial/03.bvh', 'indian/04.bvh'];
const CLI = path.join(ROOT, 'target/debug/deeprep');

function threePositions(result, frame) {
  const bones = result.skeleton.bones;
  const byName = new Map(bones.filter((b) => b.name !== 'ENDSITE').map((b) => [b.name, b]));
  for (const track of result.clip.tracks) {
    const [name, prop] = track.name.split('.');
    const bone = byName.get(name);
    if (prop === 'position') bone.position.fromArray(track.values, frame * 3);
    if (prop === 'quaternion') bone.quaternion.fromArray(track.values, frame * 4);
  }
  bones[0].updateMatrixWorld(true);
  return bones.map((b) => b.getWorldPosition(new Vector3()));
}

for (const clip of CLIPS) {
  test(`FK of ${clip} matches three.js within 1e-3`, { skip: !fs.existsSync(path.join(DATA, clip)) && 'SKIP: ../shared/data/cmu-bvh is absent' }, () => {
    assert.ok(fs.existsSync(CLI), `${CLI} missing: run cargo build first`);
    const file = path.join(DATA, clip);
    const result = new BVHLoader().parse(fs.readFileSync(file, 'utf8'));
    const frames = result.clip.tracks[0].times.length;
    let worst = 0;
    for (const frame of [0, Math.floor(frames / 3), Math.floor((2 * frames) / 3), frames - 1]) {
      const ours = execFileSync(CLI, ['bvh', 'fk', file, '--frame', String(frame)], { encoding: 'utf8' })
        .trim().split('\n').map((l) => l.split(' '));
      const theirs = threePositions(result, frame);
      assert.equal(ours.length, theirs.length, 'joint count (End Sites included)');
      assert.equal(ours.length, 57);
      ours.forEach(([name, x, y, z], i) => {
        if (result.skeleton.bones[i].name !== 'ENDSITE') assert.equal(name, result.skeleton.bones[i].name);
        const d = Math.max(Math.abs(x - theirs[i].x), Math.abs(y - theirs[i].y), Math.abs(z - theirs[i].z));
        worst = Math.max(worst, d);
        assert.ok(d < 1e-3, `${clip} frame ${frame} joint ${name}: deeprep (${x}, ${y}, ${z}) vs three.js ${theirs[i].toArray()}`);
      });
    }
    console.log(`${clip}: max |deeprep − three.js| = ${worst.toExponential(2)}`);
  });
}
