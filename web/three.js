// three.js without BVH text: a deeprep synthesis result as a three.js
// Skeleton and AnimationClip (a position and a quaternion track per joint,
// as three's BVHLoader makes them), from the local tracks the worker sends.
//   import { toThree } from 'deeprep/three.js';
//   const { skeleton, clip, root } = toThree(result, client.skeleton);
//   new AnimationMixer(root).clipAction(clip).play();
// And your own character (issue 53): a rigged three.js object's clip as BVH
// text on its own skeleton, which synthesizeFromBvh retargets onto the
// model's and back; the result as an AnimationClip for that character.
//   const character = new Character(gltf.scene);   // before playing anything: reads the rest pose
//   const r = await client.synthesizeFromBvh(character.toBvh(gltf.animations[0]), { keys: [0, 12, 23] });
//   new AnimationMixer(gltf.scene).clipAction(character.clipFrom(r)).play();
import {
  AnimationClip, AnimationMixer, Bone, Euler, LoopOnce, Matrix4, Quaternion, QuaternionKeyframeTrack, Skeleton,
  Vector3, VectorKeyframeTrack,
} from 'three';
import { DeeprepError } from './client.js';

/**
 * @param result a synthesis result: `frames`, `frameTime`, `translations`
 *   (frames x joints x 3) and `quaternions` (frames x joints x 4, [x, y, z, w]).
 * @param skeleton `client.skeleton`: `names`, `parents` (-1 for the root), `offsets` (joints x 3).
 * @returns `{ skeleton, clip, root, bones }`; End Sites are bones without tracks.
 */
export function toThree(result, skeleton, { name = 'deeprep' } = {}) {
  const { names, parents, offsets } = skeleton;
  const J = names.length;
  const { frames, translations, quaternions } = result;
  if (translations.length !== frames * J * 3 || quaternions.length !== frames * J * 4) {
    throw new Error(`toThree: the result has ${translations.length / 3 / Math.max(frames, 1)} joints per frame, the skeleton ${J}`);
  }
  const dt = result.frameTime ?? 1 / 60;
  const times = Float32Array.from({ length: frames }, (_, f) => f * dt);
  const bones = names.map((n, j) => {
    const b = new Bone();
    b.name = n;
    b.position.set(offsets[3 * j], offsets[3 * j + 1], offsets[3 * j + 2]);
    return b;
  });
  const children = names.map(() => 0);
  parents.forEach((p, j) => { if (p >= 0) { bones[p].add(bones[j]); children[p]++; } });
  const tracks = [];
  for (let j = 0; j < J; j++) {
    // End Sites (leaves named <parent>_Nub) carry no motion, as in BVHLoader.
    if (children[j] === 0 && names[j].endsWith('_Nub')) continue;
    const pos = new Float32Array(frames * 3), rot = new Float32Array(frames * 4);
    for (let f = 0; f < frames; f++) {
      pos.set(translations.subarray((f * J + j) * 3, (f * J + j) * 3 + 3), f * 3);
      rot.set(quaternions.subarray((f * J + j) * 4, (f * J + j) * 4 + 4), f * 4);
    }
    tracks.push(new VectorKeyframeTrack(`${names[j]}.position`, times, pos));
    tracks.push(new QuaternionKeyframeTrack(`${names[j]}.quaternion`, times, rot));
  }
  const root = bones[parents.indexOf(-1)];
  return { skeleton: new Skeleton(bones), clip: new AnimationClip(name, -1, tracks), root, bones };
}

/** Names the BVH text can hold: the glTF node's own name (GLTFLoader keeps it in
 *  userData.name; three's sanitized name drops the dots of `Foot.L`), no spaces, unique. */
function bvhNames(bones) {
  const seen = new Set();
  return bones.map((b) => {
    const base = String(b.userData?.name || b.name || 'bone').replace(/\s+/g, '_').replace(/[{}]/g, '') || 'bone';
    let n = base;
    for (let k = 2; seen.has(n); k++) n = `${base}_${k}`;
    seen.add(n);
    return n;
  });
}

/** Tips of chains: for a bone without child bones, where a child object named like an end
 *  (`LowerLeg.L_end`, `Head_End`, `lFoot_Nub`) sits, in world space. */
function tipOf(bone) {
  for (const c of bone.children) {
    const n = String(c.userData?.name || c.name || '');
    if (!c.isBone && /(_end|_nub|end)$/i.test(n)) return c.getWorldPosition(new Vector3());
  }
  return null;
}

const fmt = (v) => (Math.abs(v) < 5e-7 ? '0' : v.toFixed(6).replace(/\.?0+$/, ''));

/**
 * A rigged three.js character (a glTF scene from GLTFLoader, or any object with Bones under it)
 * as a BVH skeleton deeprep can retarget: every bone a joint, in rest frames aligned with the
 * world (a bone's motion is its world-space change from the rest pose, so bone axes and the
 * armature's own rotation and scale do not matter). A bone that an IK rig hangs elsewhere but
 * whose rest position is the tip of another chain (RobotExpressive's `Foot.L` under the root,
 * at the end of `LowerLeg.L`) joins that chain. Construct it while the character is at rest:
 * the bones' current pose is taken as the rest pose.
 */
export class Character {
  constructor(root) {
    if (!root || typeof root.traverse !== 'function') throw new DeeprepError('E_BAD_INPUT', 'Character: expected a three.js Object3D (a glTF scene) with bones under it');
    this.root = root;
    root.updateMatrixWorld(true);
    const bones = [];
    root.traverse((o) => { if (o.isBone) bones.push(o); });
    if (bones.length < 2) throw new DeeprepError('E_BAD_INPUT', `Character: ${bones.length} bones under the object; a humanoid rig has dozens`);
    const index = new Map(bones.map((b, i) => [b, i]));
    const boneParent = (b) => { for (let p = b.parent; p; p = p.parent) if (index.has(p)) return index.get(p); return -1; };
    const parent = bones.map(boneParent);
    const restPos = bones.map((b) => b.getWorldPosition(new Vector3()));
    this.restQuat = bones.map((b) => b.getWorldQuaternion(new Quaternion()));
    this.restScale = bones.map((b) => new Vector3().setFromMatrixScale(b.matrixWorld));
    this.restLocal = bones.map((b) => ({ p: b.position.clone(), q: b.quaternion.clone(), s: b.scale.clone() }));
    // the rig's size: the largest distance of a bone from the first one
    const size = Math.max(...restPos.map((p) => p.distanceTo(restPos[0])), 1e-9);
    const childCount = bones.map(() => 0);
    parent.forEach((p) => { if (p >= 0) childCount[p]++; });
    const tips = bones.map((b, i) => (childCount[i] === 0 ? tipOf(b) : null));
    const below = (a, j) => { for (let k = j; k >= 0; k = parent[k]) if (k === a) return true; return false; };
    // bones an IK rig detached from their chain: joined to the chain whose tip they sit on
    this.joined = [];
    for (let i = 0; i < bones.length; i++) {
      const t = tips.findIndex((tip, k) => tip && k !== i && !below(i, k) && !below(k, i) && tip.distanceTo(restPos[i]) < 1e-4 * size);
      if (t >= 0) { parent[i] = t; this.joined.push(i); }
    }
    const roots = parent.map((p, i) => (p < 0 ? i : -1)).filter((i) => i >= 0);
    if (roots.length !== 1) throw new DeeprepError('E_BAD_INPUT', `Character: the bones form ${roots.length} trees (${roots.map((i) => bones[i].name).join(', ')}); a skeleton has one root`);
    this.bones = bones;
    this.names = bvhNames(bones);
    this.parent = parent;
    this.restPos = restPos;
    this.tips = tips;
    // BVH file order: depth first from the root, an End Site after each leaf
    const kids = bones.map(() => []);
    parent.forEach((p, i) => { if (p >= 0) kids[p].push(i); });
    this.order = [];   // per BVH joint: a bone index, or -1 for an End Site
    const walk = (i) => { this.order.push(i); if (kids[i].length) kids[i].forEach(walk); else this.order.push(-1); };
    walk(roots[0]);
    this.kids = kids;
    this.top = roots[0];
    // each bone's real parent (its parent object) as a bone index, -1 where it is not a bone,
    // and the parents' world matrices at rest, for those that are not
    this.realParent = bones.map((b) => (b.parent && index.has(b.parent) ? index.get(b.parent) : -1));
    this.parentRest = bones.map((b) => (b.parent ? b.parent.matrixWorld.clone() : new Matrix4()));
  }

  /** The clip's frames at `fps` (default 30) as BVH text on this character's skeleton.
   *  The character is left at rest afterwards. */
  toBvh(clip, { fps = 30 } = {}) {
    if (!(clip instanceof AnimationClip)) throw new DeeprepError('E_BAD_INPUT', 'Character.toBvh: expected a three.js AnimationClip');
    if (!(fps > 0 && fps <= 1000)) throw new DeeprepError('E_BAD_INPUT', `Character.toBvh: fps must be in (0, 1000], found ${fps}`);
    const frames = Math.max(1, Math.floor(clip.duration * fps + 1e-6) + 1);
    if (frames > 1e6) throw new DeeprepError('E_BAD_INPUT', `Character.toBvh: ${frames} frames is too many`);
    const B = this.bones.length;
    // position channels: the root, joined bones, and bones the clip moves
    const moved = new Set(clip.tracks.filter((t) => t.name.endsWith('.position')).map((t) => t.name.slice(0, -'.position'.length)));
    const hasPos = this.bones.map((b, i) => i === this.top || this.joined.includes(i) || moved.has(b.name) || moved.has(b.uuid));
    const mixer = new AnimationMixer(this.root);
    const action = mixer.clipAction(clip);
    action.setLoop(LoopOnce, 1);
    action.clampWhenFinished = true;
    action.play();
    const rows = [];
    const wq = new Quaternion(), wp = new Vector3(), e = new Euler();
    const G = Array.from({ length: B }, () => new Quaternion()), P = Array.from({ length: B }, () => new Vector3());
    const inv = this.restQuat.map((q) => q.clone().invert());
    try {
      for (let f = 0; f < frames; f++) {
        mixer.setTime(Math.min(f / fps, clip.duration));
        this.root.updateMatrixWorld(true);
        for (let i = 0; i < B; i++) {
          this.bones[i].getWorldQuaternion(wq);
          G[i].copy(wq).multiply(inv[i]);      // world-space change from the rest pose
          this.bones[i].getWorldPosition(P[i]);
        }
        const row = [];
        for (const i of this.order) {
          if (i < 0) continue;
          const p = this.parent[i];
          const local = p < 0 ? G[i].clone() : G[p].clone().invert().multiply(G[i]);
          if (hasPos[i]) {
            // offset plus channels = the position in the parent's (world-aligned) frame
            const at = p < 0 ? P[i].clone() : wp.copy(P[i]).sub(P[p]).applyQuaternion(G[p].clone().invert());
            const off = p < 0 ? this.restPos[i] : this.restPos[i].clone().sub(this.restPos[p]);
            row.push(at.x - off.x, at.y - off.y, at.z - off.z);
          }
          e.setFromQuaternion(local, 'ZXY');
          row.push(e.z * 180 / Math.PI, e.x * 180 / Math.PI, e.y * 180 / Math.PI);
        }
        rows.push(row.map(fmt).join(' '));
      }
    } finally {
      action.stop();
      mixer.uncacheRoot(this.root);
      this.rest();
    }
    return `${this.#hierarchy(hasPos)}MOTION\nFrames: ${frames}\nFrame Time: ${fmt(1 / fps)}\n${rows.join('\n')}\n`;
  }

  #hierarchy(hasPos) {
    const out = ['HIERARCHY'];
    const rot = 'Zrotation Xrotation Yrotation';
    const walk = (i, depth) => {
      const pad = '  '.repeat(depth);
      const p = this.parent[i];
      const off = p < 0 ? this.restPos[i] : this.restPos[i].clone().sub(this.restPos[p]);
      out.push(`${pad}${p < 0 ? 'ROOT' : 'JOINT'} ${this.names[i]}`, `${pad}{`, `${pad}  OFFSET ${[off.x, off.y, off.z].map(fmt).join(' ')}`,
        `${pad}  CHANNELS ${hasPos[i] ? `6 Xposition Yposition Zposition ${rot}` : `3 ${rot}`}`);
      if (this.kids[i].length) this.kids[i].forEach((k) => walk(k, depth + 1));
      else {
        const tip = this.tips[i] ? this.tips[i].clone().sub(this.restPos[i]) : new Vector3();
        out.push(`${pad}  End Site`, `${pad}  {`, `${pad}    OFFSET ${[tip.x, tip.y, tip.z].map(fmt).join(' ')}`, `${pad}  }`);
      }
      out.push(`${pad}}`);
    };
    walk(this.top, 0);
    return `${out.join('\n')}\n`;
  }

  /** Puts every bone back in its rest pose (as it was when the Character was made). */
  rest() {
    this.bones.forEach((b, i) => { const r = this.restLocal[i]; b.position.copy(r.p); b.quaternion.copy(r.q); b.scale.copy(r.s); });
    this.root.updateMatrixWorld(true);
  }

  /**
   * A result on this character's skeleton (`client.synthesizeFromBvh(character.toBvh(clip), ...)`:
   * `frames`, `frameTime`, and the local `translations` and `quaternions` of its joints, End Sites
   * included, in the BVH's order) as an AnimationClip for the character: a quaternion track per
   * bone, a position track where a bone moves from its rest position (the root, joined bones).
   */
  clipFrom(result, { name = 'deeprep' } = {}) {
    const J = this.order.length, B = this.bones.length;
    const { frames, translations, quaternions } = result || {};
    if (!(frames >= 1) || translations?.length !== frames * J * 3 || quaternions?.length !== frames * J * 4) {
      throw new DeeprepError('E_BAD_INPUT', `Character.clipFrom: the result has ${translations ? translations.length / 3 / Math.max(frames, 1) : 0} joints per frame, this character's BVH ${J}; was it made from this character's toBvh?`);
    }
    const dt = result.frameTime ?? 1 / 30;
    const times = Float32Array.from({ length: frames }, (_, f) => f * dt);
    const rot = this.bones.map(() => new Float32Array(frames * 4)), pos = this.bones.map(() => new Float32Array(frames * 3));
    const moves = this.bones.map(() => false);
    const G = Array.from({ length: B }, () => new Quaternion()), P = Array.from({ length: B }, () => new Vector3());
    const W = Array.from({ length: B }, () => new Matrix4());
    const q = new Quaternion(), t = new Vector3(), m = new Matrix4(), pq = new Quaternion(), pp = new Vector3(), ps = new Vector3();
    for (let f = 0; f < frames; f++) {
      // forward kinematics in the BVH's world-aligned frames
      this.order.forEach((i, j) => {
        if (i < 0) return;
        q.fromArray(quaternions, (f * J + j) * 4);
        t.fromArray(translations, (f * J + j) * 3);
        const p = this.parent[i];
        if (p < 0) { G[i].copy(q); P[i].copy(t); } else { G[i].copy(G[p]).multiply(q); P[i].copy(t).applyQuaternion(G[p]).add(P[p]); }
        // the bone's world transform: its world-space change applied to its rest rotation
        W[i].compose(P[i], q.copy(G[i]).multiply(this.restQuat[i]), this.restScale[i]);
      });
      for (let i = 0; i < B; i++) {
        const real = this.realParent[i];
        const parentWorld = real >= 0 ? W[real] : this.parentRest[i];
        m.copy(parentWorld).invert().multiply(W[i]);
        m.decompose(pp, pq, ps);
        pq.toArray(rot[i], f * 4);
        pp.toArray(pos[i], f * 3);
        if (pp.distanceTo(this.restLocal[i].p) > 1e-5 * Math.max(this.restLocal[i].p.length(), 1e-3)) moves[i] = true;
      }
    }
    const tracks = [];
    this.bones.forEach((b, i) => {
      if (moves[i]) tracks.push(new VectorKeyframeTrack(`${b.name}.position`, times, pos[i]));
      tracks.push(new QuaternionKeyframeTrack(`${b.name}.quaternion`, times, rot[i]));
    });
    return new AnimationClip(name, -1, tracks);
  }
}
