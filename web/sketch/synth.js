// Synthesis in the worker (web/client.js), with Motion DNA drawn by the
// core's seeded generator: from the last imported clip exactly as
// `deeprep inbetween --dna CLIP.bvh --seed S` draws it, else from the pose
// library (motion::dna::pick_from_pool). Failures leave the keys as they were.
import { dnaFramesOfClip, dnaFramesOfPool } from '../pkg/deeprep.js';
import { $, setStatus, state } from './state.js';
import { pushHistory } from './history.js';
import { refreshTimeline } from './timeline.js';
import { draw } from './view.js';

const chunk = (flat, n) => Array.from({ length: flat.length / n }, (_, i) => flat.slice(i * n, (i + 1) * n));

/** DNA poses as one flat channel array: the selected library poses, or seeded ones. */
export function dnaChannels() {
  const selected = [...$('dna').selectedOptions].map((o) => state.library[Number(o.value)].channels);
  if (selected.length) return selected.flat();
  const seed = Number($('seed').value);
  if (state.dnaClip) {
    const c = state.skeleton.channels, m = state.dnaClip.motion;
    return Array.from(dnaFramesOfClip(state.skeleton.clip, m, state.length, seed)).flatMap((i) => Array.from(m.subarray(i * c, (i + 1) * c)));
  }
  if (!state.library.length) return [];
  return Array.from(dnaFramesOfPool(state.library.length, state.length, seed)).flatMap((i) => state.library[i].channels);
}

const METHOD_NAMES = { slerp: 'SLERP+LERP interpolation baseline', residual: 'supervised residual network' };

/** Synthesizes the keys at the length in #length with the page's options. */
export async function synthesize() {
  const length = Number($('length').value);
  if (!Number.isInteger(length) || length < 1 || length > 4096) { setStatus('length must be 1..4096 frames', true); return; }
  if (length !== state.length) { pushHistory(); state.length = length; refreshTimeline(); }
  const keys = state.keys.filter((k) => k.frame < length);
  if (!keys.length) { setStatus('add at least one keyframe first', true); return; }
  const partial = keys.some((k) => k.root || k.xy);
  if (partial && (!state.client.hasModel || $('method').value !== 'model')) {
    setStatus('root-path and 2-D keys need the Generative Tweening model (interpolation needs whole poses)', true);
    return;
  }
  const method = state.client.hasModel ? $('method').value : 'slerp';
  $('synth').disabled = true;
  $('progress').value = 0;
  try {
    const t0 = performance.now();
    const dna = dnaChannels();
    const common = { frames: length, post: $('post').checked, footLock: $('footlock').checked, method, variation: Number($('variation').value) };
    const asRequest = (k) => (k.xy ? { frame: k.frame, xy: k.xy, root: k.root }
      : k.root ? { frame: k.frame, root: k.root } : { frame: k.frame, channels: k.channels });
    const r = partial
      // keys of every kind in the request form (motion::keys), DNA as rows
      ? await state.client.synthesize({ ...common, keys: keys.map(asRequest), dna: chunk(dna, state.skeleton.channels) })
      : await state.client.synthesize({ ...common, keyFrames: keys.map((k) => k.frame), keyChannels: keys.flatMap((k) => k.channels), dna });
    state.result = { positions: r.positions, frames: r.frames, bvh: r.bvh, method, times: r.times };
    $('method-badge').textContent = METHOD_NAMES[method] || 'Generative Tweening model';
    $('method-badge').classList.toggle('baseline', method === 'slerp');
    const ms = performance.now() - t0;
    $('timing').textContent = `${r.frames} frames in ${ms.toFixed(0)} ms` + (method === 'model' ? ` (generator ${r.times[0].toFixed(0)} ms, RC-FK ${r.times[1].toFixed(0)}, path ${r.times[2].toFixed(0)}, post ${r.times[3].toFixed(0)})` : '')
      + (partial && r.keyErrors ? `; keys met within ${r.keyErrors.after.root.toFixed(2)} (root), ${r.keyErrors.after.joints.toFixed(2)} (joints, the coordinates keys give) units; the networks alone missed by ${r.keyErrors.before.root.toFixed(1)}, ${r.keyErrors.before.joints.toFixed(1)}` : '')
      + (r.criticalFrames?.length ? `; hierarchical (a gap over 600 frames): critical keys made first at frames ${r.criticalFrames.join(', ')}` : '');
    $('progress').value = 1;
    $('progress-label').textContent = 'done';
    document.body.dataset.synthesized = String(r.frames);
    setStatus('ready');
    draw();
  } catch (e) {
    setStatus(`synthesis failed: ${e.message} (your keys are unchanged)`, true);
    $('progress-label').textContent = '';
  } finally {
    $('synth').disabled = false;
  }
}
