// three.js without BVH text: a deeprep synthesis result as a three.js
// Skeleton and AnimationClip (a position and a quaternion track per joint,
// as three's BVHLoader makes them), from the local tracks the worker sends.
//   import { toThree } from 'deeprep/three.js';
//   const { skeleton, clip, root } = toThree(result, client.skeleton);
//   new AnimationMixer(root).clipAction(clip).play();
import { AnimationClip, Bone, QuaternionKeyframeTrack, Skeleton, VectorKeyframeTrack } from 'three';

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
