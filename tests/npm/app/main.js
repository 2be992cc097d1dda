// The app that tests/npm/vite_smoke.sh and webpack_smoke.sh build against
// the packed tarball and run in headless Chromium (tests/npm/run_dist.mjs):
// DeeprepClient.create() with no arguments (the models shipped in the
// package), a BVH parsed in the worker, a synthesis, a 120 fps clip
// in-betweened, the three.js helper against BVHLoader, a glTF character's clip
// in-betweened on its own skeleton (the CC0 robot, when ../shared is there),
// and a coded error.
// It sets body[data-done], or body[data-error] with the reason.
import init, { convertRotations, BvhClip, version } from 'deeprep';
import { DeeprepClient } from 'deeprep/client.js';
import { Character, toThree } from 'deeprep/three.js';
import { AnimationMixer, LoopOnce, Quaternion, Vector3 } from 'three';
import { BVHLoader } from 'three/examples/jsm/loaders/BVHLoader.js';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
try {
  // when each start-up stage began (ms from navigation), for the bench
  const stageAt = {};
  // the worker's start-up first (the npm README's advice), the page-side wasm beside it
  const starting = DeeprepClient.create({ onProgress: (p) => { stageAt[p.stage] ??= Math.round(performance.now()); } });
  await init();
  const sixd = convertRotations('quat', '6d', new Float32Array([0, 0, 0, 1]));
  const client = await starting;
  // the bundler shipped the relaxed-SIMD twin of the worker's wasm, and this Chromium runs it
  if (client.wasm !== 'relaxed-simd') throw new Error(`the worker runs the ${client.wasm} build, not relaxed-simd`);
  stageAt.ready = Math.round(performance.now());
  document.body.dataset.stages = JSON.stringify(stageAt);
  const skel = BvhClip.parse(client.skeletonBvh);
  const row = Array.from({ length: skel.channelCount }, (_, i) => (i === 1 ? 90 : 0));
  const clip = await client.importBvh(new TextEncoder().encode(
    `${client.skeletonBvh.replace(/MOTION[\s\S]*/, '')}MOTION\nFrames: 2\nFrame Time: 0.0166667\n${row.join(' ')}\n${row.join(' ')}\n`));
  const t1 = performance.now();
  const r = await client.synthesize({ keyFrames: [0, 59], keyChannels: [...row, ...row], frames: 60, post: true });
  // time to first result, from navigation (performance.now() counts from it)
  document.body.dataset.firstResultMs = String(performance.now());
  // the first synthesis against the same one again (warm)
  document.body.dataset.firstSynthesisMs = String(performance.now() - t1);
  const t2 = performance.now();
  await client.synthesize({ keyFrames: [0, 59], keyChannels: [...row, ...row], frames: 60, post: true });
  document.body.dataset.warmSynthesisMs = String(performance.now() - t2);
  // whole-pose keys ran the residual network; once idle, the worker built its plan for
  // 60 frames (prepareWhenIdle), which makes the same motion as the any-length plan
  if (r.ran !== 'residual') throw new Error(`whole-pose keys ran '${r.ran}', not the residual network`);
  await new Promise((done) => setTimeout(done, 200));
  const own = await client.synthesize({ keyFrames: [0, 59], keyChannels: [...row, ...row], frames: 60, post: true, bvh: false });
  let planGap = 0;
  for (let i = 0; i < own.positions.length; i++) planGap = Math.max(planGap, Math.abs(own.positions[i] - r.positions[i]));
  if (!(planGap < 1e-3)) throw new Error(`the length's own plan and the any-length plan differ by ${planGap}`);
  // a 120 fps clip of 121 frames on the model's skeleton, keys at its frames 0, 60 and 120:
  // synthesized at 60 fps and returned at 120 fps with the clip's length
  const head = client.skeletonBvh.replace(/MOTION[\s\S]*/, '');
  const rows = Array.from({ length: 121 }, (_, f) => row.map((v, i) => (i === 0 ? f * 0.5 : i === 7 ? 20 * Math.sin(f / 20) : v)).join(' '));
  const fromClip = await client.synthesizeFromBvh(`${head}MOTION\nFrames: 121\nFrame Time: 0.00833333\n${rows.join('\n')}\n`, { keys: [0, 60, 120] });
  if (fromClip.frames !== 121 || !/Frame Time: 0.00833333/.test(fromClip.bvh)) throw new Error(`synthesizeFromBvh: ${fromClip.frames} frames`);
  // the planner (motion::plan) chooses as for the CLI's --from-bvh: whole-pose keys, the residual network
  if (fromClip.ran !== 'residual' || fromClip.variation !== r.variation) {
    throw new Error(`synthesizeFromBvh ran '${fromClip.ran}' at variation ${fromClip.variation}, synthesize '${r.ran}' at ${r.variation}`);
  }
  // a gap filled (issue 50): frames 30-60 synthesized, every other line of the text as it was,
  // and a reversed range refused
  const filled = await client.fillGaps(fromClip.bvh, [{ start: 30, end: 60 }]);
  {
    const [a, b] = [fromClip.bvh.split('\n'), filled.bvh.split('\n')];
    const row0 = a.findIndex((l) => l.startsWith('Frame Time')) + 1;
    const changed = a.map((l, i) => (l !== b[i] ? i - row0 : null)).filter((f) => f !== null);
    if (filled.frames !== 121 || a.length !== b.length || changed.some((f) => f < 30 || f > 60) || changed.length < 20) {
      throw new Error(`fillGaps: ${filled.frames} frames, changed frames ${changed.slice(0, 5)}...`);
    }
  }
  // the network whose band (client.fillBands, in its order) holds a gap's length, fetched on its first use
  const bandFor = (len) => Object.entries(client.fillBands).find(([, b]) => b && len >= b[0] && len <= b[1])?.[0];
  // a 31-frame gap
  if (bandFor(31) && filled.ran !== bandFor(31)) throw new Error(`fillGaps ran '${filled.ran}' on a 31-frame gap, '${bandFor(31)}' claims it`);
  if (client.hasFill && !bandFor(31)) throw new Error(`no band holds a 31-frame gap: ${JSON.stringify(client.fillBands)}`);
  // a 61-frame gap: the long-gap filling network where the package has it
  const longFill = bandFor(61) ? await client.fillGaps(fromClip.bvh, [{ start: 30, end: 90 }]) : null;
  if (client.hasFillLong && longFill?.ran !== 'fill-long') throw new Error(`fillGaps ran '${longFill?.ran}' on a 61-frame gap with the long-gap network bundled`);
  const reversed = await client.fillGaps(fromClip.bvh, [{ start: 60, end: 30 }]).then(() => null, (e) => e);
  if (reversed?.code !== 'E_BAD_INPUT' || !/reversed/.test(reversed.message)) throw new Error(`a reversed gap: ${reversed?.code} ${reversed?.message}`);
  // by the conditional network, which the worker loads on this first use
  const byCond = await client.fillGaps(fromClip.bvh, [{ start: 30, end: 60 }], { method: 'cond' });
  if (byCond.ran !== 'cond' || byCond.frames !== 121) throw new Error(`fillGaps by cond: ran '${byCond.ran}', ${byCond.frames} frames`);
  // another humanoid skeleton (MotionBuilder names, A-pose arms, a fifth of the model's size):
  // the clip retargeted onto it, in-betweened there (retargeted onto the model's skeleton and
  // back), and a skeleton without legs refused with the missing roles named
  const other = otherSkeleton();
  const onOther = await client.retarget(fromClip.bvh, { to: other });
  if (!/^HIERARCHY\s+ROOT Hips/.test(onOther) || !/Frames: 121/.test(onOther)) throw new Error(`retarget: ${onOther.slice(0, 80)}`);
  const otherResult = await client.synthesizeFromBvh(onOther, { keys: [0, 60, 120] });
  if (otherResult.frames !== 121 || !/ROOT Hips/.test(otherResult.bvh) || !/JOINT LeftUpLeg/.test(otherResult.bvh)) {
    throw new Error(`synthesizeFromBvh on another skeleton: ${otherResult.frames} frames, ${otherResult.bvh.slice(0, 60)}`);
  }
  const legless = other.replace(/LeftLeg/g, 'LeftLimb');
  const noLegs = await client.retarget(onOther, { to: legless }).then(() => null, (e) => e);
  if (noLegs?.code !== 'E_BAD_BVH' || !/leftShin/.test(noLegs.message)) throw new Error(`a legless skeleton: ${noLegs?.code} ${noLegs?.message}`);
  // three.js without text: the same tracks as BVHLoader on the BVH text, and the clip plays
  const three = toThree(r, client.skeleton);
  const ref = new BVHLoader().parse(r.bvh);
  let worst = 0, compared = 0;
  for (const t of ref.clip.tracks) {
    const mine = three.clip.tracks.find((x) => x.name === t.name);
    if (!mine) throw new Error(`toThree lacks track ${t.name}`);
    const q = t.name.endsWith('.quaternion');
    for (let i = 0; i < t.values.length; i += q ? 4 : 3) {
      const sign = q && (t.values[i] * mine.values[i] + t.values[i + 1] * mine.values[i + 1] + t.values[i + 2] * mine.values[i + 2] + t.values[i + 3] * mine.values[i + 3]) < 0 ? -1 : 1;
      for (let k = 0; k < (q ? 4 : 3); k++) worst = Math.max(worst, Math.abs(t.values[i + k] - sign * mine.values[i + k]));
    }
    compared++;
  }
  if (compared < 40 || worst > 2e-3) throw new Error(`toThree vs BVHLoader: ${compared} tracks, max difference ${worst}`);
  const mixer = new AnimationMixer(three.root);
  mixer.clipAction(three.clip).play();
  mixer.update(0.5);
  const bone = three.bones[1], track = three.clip.tracks.find((x) => x.name === `${bone.name}.quaternion`);
  const want = new Quaternion().fromArray(track.values, 30 * 4);
  if (Math.abs(Math.abs(bone.quaternion.dot(want)) - 1) > 1e-4) throw new Error('the clip did not play');
  // typed errors, progress and cancellation: models that are not there reject create()
  // with E_MODEL_LOAD (the 404s of ./no-models/ are expected by run_dist.mjs); an aborted
  // synthesis settles its promise with E_ABORTED, and the next call still works
  const missing = await DeeprepClient.create({ modelBase: './no-models/' }).then(() => null, (e) => e.code);
  if (missing !== 'E_MODEL_LOAD') throw new Error(`create() with missing models: ${missing}`);
  const stages = new Set();
  const c2 = await DeeprepClient.create({ wasm: 'simd128', onProgress: (p) => stages.add(p.stage) });
  if (c2.wasm !== 'simd128') throw new Error(`create({ wasm: 'simd128' }) runs ${c2.wasm}`);
  for (const s of ['compiling wasm', 'downloading models']) if (!stages.has(s)) throw new Error(`no '${s}' progress: ${[...stages]}`);
  const ac = new AbortController();
  const long = c2.synthesize({ keyFrames: [0, 599], keyChannels: [...row, ...row], frames: 600, signal: ac.signal });
  await new Promise((r) => setTimeout(r, 30)); // in flight: the worker is replaced
  ac.abort();
  const aborted = await long.then(() => 'resolved', (e) => e.code);
  if (aborted !== 'E_ABORTED' || c2.restarts !== 1) throw new Error(`aborted synthesis: ${aborted}, ${c2.restarts} restarts`);
  const early = await c2.synthesize({ keyFrames: [0, 29], keyChannels: [...row, ...row], frames: 30, signal: AbortSignal.abort() })
    .then(() => 'resolved', (e) => e.code);
  if (early !== 'E_ABORTED') throw new Error(`an already aborted signal: ${early}`);
  const after = await c2.synthesize({ keyFrames: [0, 29], keyChannels: [...row, ...row], frames: 30 });
  if (after.frames !== 30) throw new Error('no synthesis after an abort');
  // the plain and the relaxed-SIMD builds agree (fused multiply-adds round differently)
  const turned = row.map((v, i) => (i === 0 ? 40 : i > 2 && i % 5 === 0 ? 25 : v));
  const ask = { keyFrames: [0, 89], keyChannels: [...row, ...turned], frames: 90 };
  const [fast, plain] = await Promise.all([client.synthesize(ask), c2.synthesize({ ...ask, bvh: false })]);
  if (plain.bvh !== '' || !fast.bvh.startsWith('HIERARCHY')) throw new Error('bvh: false did not leave the text out, or a result lacks it');
  let gap = 0;
  for (let i = 0; i < fast.positions.length; i++) gap = Math.max(gap, Math.abs(fast.positions[i] - plain.positions[i]));
  if (!(gap < 0.05)) throw new Error(`relaxed-SIMD and plain builds differ by ${gap} in joint positions`);
  c2.terminate();
  // a CMU clip of ../shared (salsa/01, served beside the app by the test scripts when the
  // data is there): keys at 0, 120 and 240 of its frames, the whole clip back
  const cfg = await (await fetch('./clip.json')).json();
  let cmu = 'no CMU clip (../shared absent)';
  if (cfg.clip) {
    const text = await (await fetch(cfg.clip)).text();
    const n = Number(/Frames:\s*(\d+)/.exec(text)[1]);
    const out = await client.synthesizeFromBvh(text, { keys: [0, 120, 240] });
    if (out.frames !== n) throw new Error(`synthesizeFromBvh on ${cfg.clip}: ${out.frames} frames, the clip has ${n}`);
    cmu = `CMU ${cfg.clip} (${n} frames) in-betweened`;
  }
  // your own character (issue 53): the CC0 robot's glTF Walking clip, keys at three of its
  // frames, in-betweened on the model's skeleton and back onto the robot's, played on the
  // robot by AnimationMixer: at the keys the bones are where the robot's own clip puts them,
  // between them the limbs move
  let robot = 'no glTF robot (../shared absent)';
  if (cfg.robot) {
    const gltf = await new GLTFLoader().loadAsync(cfg.robot);
    const character = new Character(gltf.scene);
    const walk = gltf.animations.find((a) => a.name === 'Walking');
    const out = await client.synthesizeFromBvh(character.toBvh(walk, { fps: 30 }), { keys: [0, 14, 28] });
    if (out.frames !== 29 || !/ROOT Bone/.test(out.bvh)) {
      throw new Error(`the robot: ${out.frames} frames, ${out.bvh.slice(0, 40)}`);
    }
    const played = character.clipFrom(out, { name: 'walk, in-betweened' });
    const at = (clip, frames) => {
      const mixer = new AnimationMixer(gltf.scene);
      const action = mixer.clipAction(clip);
      action.setLoop(LoopOnce, 1);
      action.clampWhenFinished = true;
      action.play();
      const poses = frames.map((f) => {
        mixer.setTime(f / 30);
        gltf.scene.updateMatrixWorld(true);
        return character.bones.map((b) => b.getWorldPosition(new Vector3()));
      });
      action.stop();
      return poses;
    };
    const frames = [0, 7, 14, 21, 28];
    const [theirs, ours] = [at(walk, frames), at(played, frames)];
    character.rest();
    let keyGap = 0;
    for (const k of [0, 2, 4]) theirs[k].forEach((p, i) => { keyGap = Math.max(keyGap, p.distanceTo(ours[k][i])); });
    // the robot stands about 4 units tall: within 2e-3 of the robot's own clip at the keys
    if (!(keyGap < 2e-3)) throw new Error(`the robot at its keys: ${keyGap} from its own clip`);
    const hand = character.names.indexOf('Palm2.L');
    const swing = ours[1][hand].distanceTo(ours[0][hand]) + ours[3][hand].distanceTo(ours[2][hand]);
    if (!(swing > 0.05)) throw new Error(`the robot's hand moves ${swing} between its keys`);
    robot = `the glTF robot's Walking in-betweened on its own skeleton (${character.bones.length} bones, keys within ${keyGap.toExponential(1)}, the hand swings ${swing.toFixed(2)})`;
  }
  // keys of other kinds (issue 20): a path of root-only keys after a whole pose; the
  // output's root passes through each, and a bad key is an error that names it
  const path = [[0, 56, 0], [40, 56, 60], [100, 56, 90]];
  const rootKeys = await client.synthesize({ frames: 181, keys: [
    { frame: 0, channels: row.map((v, i) => (i === 1 ? 56 : v)) },
    ...path.slice(1).map((root, i) => ({ frame: 90 * (i + 1), root })) ] });
  for (const [i, p] of path.entries()) {
    const at = rootKeys.positions.subarray(90 * i * 3 * client.skeleton.names.length, 90 * i * 3 * client.skeleton.names.length + 3);
    if (Math.hypot(at[0] - p[0], at[1] - p[1], at[2] - p[2]) > 1e-3) throw new Error(`root key ${i}: ${Array.from(at)} vs ${p}`);
  }
  // a 1,500-frame gap (over the networks' 600): hierarchical, critical keys first (Sec. 5.4.3)
  const longGap = await client.synthesize({ keyFrames: [0, 1500], keyChannels: [...row, ...row.map((v, i) => (i === 0 ? 400 : v))], frames: 1501, post: true });
  if (longGap.keyErrors.after.root > 1e-6 || longGap.stages.generatorMs !== longGap.times[0]) throw new Error(`named results: ${JSON.stringify(longGap.keyErrors)}`);
  if (longGap.frames !== 1501 || !longGap.criticalFrames.length || Math.abs(longGap.positions[1500 * 3 * client.skeleton.names.length] - 400) > 1e-3) {
    throw new Error(`a 1,500-frame gap: ${longGap.frames} frames, critical keys ${longGap.criticalFrames}, root x at 1500: ${longGap.positions[1500 * 3 * client.skeleton.names.length]}, at 0: ${longGap.positions[0]}`);
  }
  const badKey = await client.synthesize({ frames: 60, keys: [{ frame: 0, root: [0, 56] }] }).then(() => null, (e) => e);
  if (badKey?.code !== 'E_BAD_KEYS' || !/key 0/.test(badKey.message)) throw new Error(`a bad root key: ${badKey?.code} ${badKey?.message}`);
  let code = null;
  await client.importBvh(new TextEncoder().encode('HIERARCHY\nnot a bvh')).catch((e) => { code = e.code; });
  if (r.frames !== 60 || clip.frameCount !== 2 || code !== 'E_BAD_BVH') throw new Error(`unexpected: ${r.frames} ${clip.frameCount} ${code}`);
  document.getElementById('out').textContent = `deeprep ${version()} 6d ${Array.from(sixd)}; synthesized ${r.frames} frames; a 120 fps clip in-betweened (${fromClip.frames} frames), also on another skeleton, and a gap filled (by ${filled.ran}${longFill ? `; a 61-frame one by ${longFill.ran}` : ''}); ${cmu}; ${robot}; three.js: ${compared} tracks as BVHLoader's (max difference ${worst.toExponential(1)}), played; root-only keys hit; a 1,500-frame gap via critical keys at ${longGap.criticalFrames.join(', ')}; bad BVH -> ${code}; missing models -> ${missing}; abort -> ${aborted}, then ${after.frames} frames; worker wasm ${client.wasm}, within ${gap.toExponential(1)} of simd128`;
  document.body.dataset.done = '1';
} catch (e) {
  document.body.dataset.error = `${e.code || ''} ${e.message}`;
}

/** A MotionBuilder-style humanoid (cmu-extra's cmu-hips names), arms 30 degrees below
 *  horizontal, about a fifth of the model's size, with one frame at rest. */
function otherSkeleton() {
  const rot = 'CHANNELS 3 Zrotation Yrotation Xrotation';
  const joint = (name, o, body) => `JOINT ${name}\n{\nOFFSET ${o.join(' ')}\n${rot}\n${body}}\n`;
  const end = (o) => `End Site\n{\nOFFSET ${o.join(' ')}\n}\n`;
  let legs = '', arms = '';
  for (const [side, x] of [['Left', 1], ['Right', -1]]) {
    legs += joint(`${side}UpLeg`, [1.3 * x, -1.8, 0.8], joint(`${side}Leg`, [1.5 * x, -7, 0],
      joint(`${side}Foot`, [0.5, -7, 0], joint(`${side}ToeBase`, [0, -0.4, 2.3], end([0, 0, 0.8])))));
    const [c, d] = [Math.cos(Math.PI / 6), -Math.sin(Math.PI / 6)];
    arms += joint(`${side}Shoulder`, [0, 0, 0], joint(`${side}Arm`, [3.3 * x, 1.2, -0.3],
      joint(`${side}ForeArm`, [5 * c * x, 5 * d, 0], joint(`${side}Hand`, [3.5 * c * x, 3.5 * d, 0], end([0.7 * c * x, 0.7 * d, 0])))));
  }
  const spine = joint('Spine', [0, 2, -0.2], joint('Spine1', [0, 2, 0],
    joint('Neck', [0, 1.7, 0.2], joint('Head', [0, 1.7, -0.1], end([0, 1.6, 0]))) + arms));
  const channels = 6 + 3 * (2 * 4 + 2 * 4 + 4);
  return `HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n${legs}${spine}}\n`
    + `MOTION\nFrames: 1\nFrame Time: 0.0083333\n${Array(channels).fill(0).join(' ')}\n`;
}
