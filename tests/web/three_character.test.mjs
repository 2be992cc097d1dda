// deeprep/three.js' Character (issue 53): a rigged three.js character's clip as
// BVH on its own skeleton and a result on that skeleton back as an
// AnimationClip. Checked in Node against three.js itself: the clip played by
// AnimationMixer before and after the trip (positions compared in world
// space), on a rig this test builds (an armature rotated and scaled, bone axes
// that are not the world's, a foot an IK rig hangs from the root) and, when
// ../shared/data is there, on the CC0 RobotExpressive glTF, through the CLI's
// retargeting onto the model's skeleton and back.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { execFileSync, spawnSync } from 'node:child_process';
import {
  AnimationClip, Bone, Object3D, Quaternion, QuaternionKeyframeTrack, Vector3, VectorKeyframeTrack,
} from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { Character } from '../../web/three.js';
import { asResult, play } from './three_tracks.mjs';
import { ROOT } from './chromium.mjs';

const CLI = path.join(ROOT, 'target/debug/deeprep');
const ROBOT = path.resolve(ROOT, '../shared/data/gltf/RobotExpressive.glb');

function distances(a, b, keep = () => true) {
  let sum = 0, n = 0, max = 0;
  a.forEach((frame, f) => frame.forEach((p, i) => {
    if (!keep(i)) return;
    const d = p.distanceTo(b[f][i]);
    sum += d; n++; max = Math.max(max, d);
  }));
  return { mean: sum / n, max };
}

/** A small humanoid rig the way exporters make them: an armature rotated -90 degrees
 *  about x and scaled 10, bones whose local axes are not the world's, the legs hanging
 *  from `Body` above the joint named `Hips`, and `Foot.L`/`Foot.R` under the root bone
 *  (an IK rig's control bones) where the shins end. A clip turns the legs and arms,
 *  moves the body and the IK feet. */
function testRig() {
  const scene = new Object3D();
  const armature = new Object3D();
  armature.name = 'Armature';
  armature.rotation.x = -Math.PI / 2;
  armature.scale.setScalar(10);
  scene.add(armature);
  // world rest positions (the rig stands 1.8 high) and a twist per bone
  const at = (x, y, z) => new Vector3(x, y, z);
  const spec = [
    ['Root', null, at(0, 0, 0)], ['Body', 'Root', at(0, 1, 0)], ['Hips', 'Body', at(0, 1.05, 0)],
    ['Chest', 'Hips', at(0, 1.35, 0)], ['Neck', 'Chest', at(0, 1.55, 0)], ['Head', 'Neck', at(0, 1.62, 0)],
  ];
  for (const [s, x] of [['L', 1], ['R', -1]]) {
    spec.push([`UpperArm.${s}`, 'Chest', at(0.18 * x, 1.5, 0)], [`LowerArm.${s}`, `UpperArm.${s}`, at(0.3 * x, 1.25, 0)],
      [`Hand.${s}`, `LowerArm.${s}`, at(0.4 * x, 1.02, 0.02)], [`UpperLeg.${s}`, 'Body', at(0.1 * x, 0.95, 0)],
      [`LowerLeg.${s}`, `UpperLeg.${s}`, at(0.1 * x, 0.5, 0.01)], [`Foot.${s}`, 'Root', at(0.1 * x, 0.08, 0)]);
  }
  const bones = new Map();
  scene.updateMatrixWorld(true);
  spec.forEach(([name, parent, world], k) => {
    const b = new Bone();
    b.name = name.replace('.', '');          // three's sanitized name, as GLTFLoader gives it
    b.userData.name = name;                  // the glTF node's name
    const p = parent ? bones.get(parent) : armature;
    p.add(b);
    p.updateMatrixWorld(true);
    // rest rotation: a bone axis turned by k (not the world's)
    const worldQ = new Quaternion().setFromAxisAngle(new Vector3(1, 2, 3).normalize(), 0.4 * k);
    const parentQ = p.getWorldQuaternion(new Quaternion());
    b.quaternion.copy(parentQ.clone().invert().multiply(worldQ));
    b.position.copy(p.worldToLocal(world.clone()));
    b.updateMatrixWorld(true);
    bones.set(name, b);
  });
  for (const [name, tip] of [['Hand.L', at(0.45, 0.95, 0.03)], ['Hand.R', at(-0.45, 0.95, 0.03)], ['Head', at(0, 1.8, 0)],
    ['LowerLeg.L', at(0.1, 0.08, 0)], ['LowerLeg.R', at(-0.1, 0.08, 0)], ['Foot.L', at(0.1, 0.0, 0.12)], ['Foot.R', at(-0.1, 0.0, 0.12)]]) {
    const end = new Object3D();
    end.name = `${name}_end`;
    bones.get(name).add(end);
    end.position.copy(bones.get(name).worldToLocal(tip));
  }
  scene.updateMatrixWorld(true);
  const times = Float32Array.from({ length: 31 }, (_, f) => f / 30);
  const tracks = [];
  let k = 0;
  for (const name of ['UpperLeg.L', 'LowerLeg.L', 'UpperLeg.R', 'UpperArm.L', 'LowerArm.R', 'Chest', 'Head']) {
    const b = bones.get(name), axis = new Vector3(Math.sin(k), 1, Math.cos(2 * k)).normalize(), values = [];
    for (const t of times) values.push(...b.quaternion.clone().multiply(new Quaternion().setFromAxisAngle(axis, 0.6 * Math.sin(4 * t + k))).toArray());
    tracks.push(new QuaternionKeyframeTrack(`${b.name}.quaternion`, times, values));
    k++;
  }
  for (const name of ['Body', 'Foot.L']) {
    const b = bones.get(name), values = [];
    for (const t of times) values.push(...b.position.clone().add(new Vector3(0.003 * Math.sin(5 * t), 0.002 * t, 0.001)).toArray());
    tracks.push(new VectorKeyframeTrack(`${b.name}.position`, times, values));
  }
  return { scene, clip: new AnimationClip('test', -1, tracks) };
}

test('a rig three.js plays comes back from its BVH as it was (world positions within 1e-4 of its size)', () => {
  const { scene, clip } = testRig();
  const character = new Character(scene);
  // the IK feet joined the shins they end on
  assert.deepEqual(character.joined.map((i) => [character.names[i], character.names[character.parent[i]]]),
    [['Foot.L', 'LowerLeg.L'], ['Foot.R', 'LowerLeg.R']]);
  const bvh = character.toBvh(clip, { fps: 30 });
  assert.match(bvh, /^HIERARCHY\nROOT Root\n/);
  assert.match(bvh, /Frames: 31\nFrame Time: 0.033333\n/);
  const times = Array.from({ length: 31 }, (_, f) => f / 30);
  const before = play(character, clip, times);
  const after = play(character, character.clipFrom(asResult(bvh)), times);
  const d = distances(before, after);
  // the rig is 18 units tall in the world (the armature's scale 10)
  assert.ok(d.max < 18e-4, `max ${d.max}`);
  // the motion was there to lose: the hand moves
  const hand = character.names.indexOf('Hand.L');
  assert.ok(before[0][hand].distanceTo(before[15][hand]) > 0.5, 'the clip moves the left hand');
  // and the rig is at rest again afterwards
  const rest = character.bones.map((b) => b.getWorldPosition(new Vector3()));
  rest.forEach((p, i) => assert.ok(p.distanceTo(character.restPos[i]) < 1e-9));
});

test('the test rig maps onto a humanoid: hips above the joint named Hips, the IK feet on the shins', { skip: !fs.existsSync(CLI) && `${CLI} missing: cargo build first` }, () => {
  const { scene, clip } = testRig();
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'deeprep-rig-'));
  const file = path.join(dir, 'rig.bvh');
  fs.writeFileSync(file, new Character(scene).toBvh(clip));
  const roles = JSON.parse(execFileSync(CLI, ['bvh', 'roles', file], { encoding: 'utf8' }));
  assert.equal(roles.hips, 'Body');
  assert.equal(roles.spine, 'Hips');
  assert.equal(roles.leftFoot, 'Foot.L');
  assert.equal(roles.rightHand, 'Hand.R');
});

test('bad input to Character is an error with a code', () => {
  assert.throws(() => new Character(new Object3D()), (e) => e.code === 'E_BAD_INPUT' && /bones/.test(e.message));
  assert.throws(() => new Character(null), (e) => e.code === 'E_BAD_INPUT');
  const { scene, clip } = testRig();
  const c = new Character(scene);
  assert.throws(() => c.toBvh({ tracks: [] }), (e) => e.code === 'E_BAD_INPUT' && /AnimationClip/.test(e.message));
  assert.throws(() => c.toBvh(clip, { fps: 0 }), (e) => e.code === 'E_BAD_INPUT' && /fps/.test(e.message));
  const r = asResult(c.toBvh(clip));
  assert.throws(() => c.clipFrom({ ...r, translations: r.translations.subarray(3) }), (e) => e.code === 'E_BAD_INPUT' && /joints per frame/.test(e.message));
});

test('RobotExpressive: each clip to the model skeleton and back (CLI), mapped bones within 1 model unit where only the hips translate',
  { skip: (!fs.existsSync(ROBOT) && 'SKIP: ../shared/data/gltf is absent') || (!fs.existsSync(CLI) && `${CLI} missing: cargo build first`) }, async () => {
    const buf = fs.readFileSync(ROBOT);
    const gltf = await new Promise((ok, no) => new GLTFLoader().parse(buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength), '', ok, no));
    const character = new Character(gltf.scene);
    assert.deepEqual(character.joined.map((i) => character.names[i]), ['Foot.L', 'Foot.R']);
    const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'deeprep-robot-'));
    const [src, onModel, back] = ['robot.bvh', 'model.bvh', 'back.bvh'].map((f) => path.join(dir, f));
    const rows = [];
    let mapped = null, scale = null;
    for (const clip of gltf.animations) {
      fs.writeFileSync(src, character.toBvh(clip, { fps: 30 }));
      if (!mapped) {
        const roles = JSON.parse(execFileSync(CLI, ['bvh', 'roles', src], { encoding: 'utf8' }));
        // the model's collars and buttocks are not followed (docs/retarget.md)
        mapped = new Set(Object.entries(roles).filter(([r]) => !/Collar|Buttock/.test(r)).map(([, n]) => character.names.indexOf(n)));
      }
      const run = spawnSync(CLI, ['bvh', 'retarget', src, '--to', 'model', '-o', onModel], { encoding: 'utf8' });
      assert.equal(run.status, 0, run.stderr);
      scale ??= Number(/scaled by ([\d.]+)/.exec(run.stdout + run.stderr)[1]);
      execFileSync(CLI, ['bvh', 'retarget', onModel, '--to', src, '-o', back], { stdio: 'pipe' });
      const result = asResult(fs.readFileSync(back, 'utf8'));
      const times = Array.from({ length: result.frames }, (_, f) => f / 30);
      const d = distances(play(character, clip, times), play(character, character.clipFrom(result), times), (i) => mapped.has(i));
      // other bones that translate (the collars in Death and Punch) have no place on the model's skeleton
      const moved = clip.tracks.some((t) => t.name.endsWith('.position') && !/^(Body|FootL|FootR|PoleTarget[LR])\./.test(t.name));
      rows.push({ clip: clip.name, frames: result.frames, mean_model_units: +(d.mean * scale).toFixed(3), max_model_units: +(d.max * scale).toFixed(3), other_bones_translate: moved });
      if (!moved) assert.ok(d.mean * scale < 1, `${clip.name}: ${d.mean * scale} model units`);
    }
    console.log(JSON.stringify({ robot_round_trip: rows, model_units_per_robot_unit: scale }));
  });
