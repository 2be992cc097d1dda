// The model's skeleton on the page: joint names and parents, and forward
// kinematics of a channel row by the core (BvhClip.poseFk), cached.
import { BvhClip } from '../pkg/deeprep.js';
import { state } from './state.js';

const fkCache = new Map();

/** The skeleton of a BVH text (its HIERARCHY; the motion is ignored). */
export function loadSkeleton(bvhText) {
  const header = bvhText.slice(0, bvhText.indexOf('MOTION'));
  const clip = BvhClip.parse(`${header}MOTION\nFrames: 0\nFrame Time: 0.0166667\n`);
  fkCache.clear();
  return { clip, names: clip.jointNames, parents: Array.from(clip.parents), channels: clip.channelCount };
}

/** Global joint positions (joints × 3) of a channel row. */
export function fk(channels) {
  const k = channels.join(' ');
  let p = fkCache.get(k);
  if (!p) {
    p = state.skeleton.clip.poseFk(Float32Array.from(channels));
    if (fkCache.size > 500) fkCache.clear();
    fkCache.set(k, p);
  }
  return p;
}

/** Joint `j` and every joint below it. */
export function subtree(j) {
  const out = [j];
  for (let i = 0; i < out.length; i++) state.skeleton.parents.forEach((p, c) => { if (p === out[i]) out.push(c); });
  return out;
}
