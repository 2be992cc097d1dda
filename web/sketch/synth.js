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

/**
 * DNA poses as one flat channel array: the selected library poses, or
 * seeded frames of an imported clip; with `fallbackToPool`, seeded library
 * poses when there is neither. Without DNA, whole-pose keys go to the
 * default network (the residual network when its manifest says so, which
 * has no DNA input).
 */
export function dnaChannels(seed = Number($('seed').value), { fallbackToPool = false } = {}) {
  const selected = [...$('dna').selectedOptions].map((o) => state.library[Number(o.value)].channels);
  if (selected.length) return selected.flat();
  if (state.dnaClip) {
    const c = state.skeleton.channels, m = state.dnaClip.motion;
    return Array.from(dnaFramesOfClip(state.skeleton.clip, m, state.length, seed)).flatMap((i) => Array.from(m.subarray(i * c, (i + 1) * c)));
  }
  if (!fallbackToPool || !state.library.length) return [];
  return Array.from(dnaFramesOfPool(state.library.length, state.length, seed)).flatMap((i) => state.library[i].channels);
}

const METHOD_NAMES = { slerp: 'SLERP+LERP interpolation baseline', residual: 'supervised residual network', cond: 'conditional network', 'cond-dna': 'conditional network with Motion DNA' };

/** The page's request for `keys` with `dna` (flat channels), in the form the worker takes. */
function request(keys, length, method, dna) {
  const common = { frames: length, post: $('post').checked, footLock: $('footlock').checked, method,
    // the slider's value once the user has moved it; before, the planner's default for these keys
    ...(state.variationTouched ? { variation: Number($('variation').value) } : {}) };
  const asRequest = (k) => (k.xy ? { frame: k.frame, xy: k.xy, root: k.root }
    : k.root ? { frame: k.frame, root: k.root } : { frame: k.frame, channels: k.channels });
  // the conditional network: the request form, the page's seed as its noise draw, and DNA
  // rows when the network takes them (its manifest's dna)
  if (method === 'cond') {
    return { ...common, keys: keys.map(asRequest), seed: Number($('seed').value) || 0,
      ...(state.client.condDna && dna.length ? { dna: chunk(dna, state.skeleton.channels) } : {}) };
  }
  return keys.some((k) => k.root || k.xy)
    // keys of every kind in the request form (motion::keys), DNA as rows
    ? { ...common, keys: keys.map(asRequest), dna: chunk(dna, state.skeleton.channels) }
    : { ...common, keyFrames: keys.map((k) => k.frame), keyChannels: keys.flatMap((k) => k.channels), dna };
}

/**
 * Motion DNA's variety (Sec. 5.3.7) on the page: the same keys synthesized
 * by the generator with the seed's DNA and with the next seed's (from the
 * DNA source, or the pose library), the second overlaid (drawn like a key,
 * following the frame), and the mean joint distance between the two.
 */
export async function compareSeeds() {
  const m = state.result?.method;
  if (m !== 'model' && m !== 'cond') { setStatus('synthesize with the Generative Tweening model or the conditional network first', true); return; }
  const seed = Number($('seed').value) + 1;
  try {
    const keys = state.keys.filter((k) => k.frame < state.result.frames);
    // the conditional network draws its noise from the seed (and its Motion DNA when it
    // takes DNA); the generator its Motion DNA
    const dnaOf = (s) => (m === 'cond' && !state.client.condDna ? [] : dnaChannels(s, { fallbackToPool: true }));
    const run = (s) => state.client.synthesize({
      ...(m === 'cond' ? { ...request(keys, state.result.frames, 'cond', dnaOf(s)), seed: s }
        : request(keys, state.result.frames, 'model', dnaOf(s))), bvh: false });
    const [first, r] = [await run(seed - 1), await run(seed)];
    const a = first.positions, b = r.positions;
    let d = 0;
    for (let i = 0; i < a.length; i += 3) d += Math.hypot(a[i] - b[i], a[i + 1] - b[i + 1], a[i + 2] - b[i + 2]);
    const mean = d / (a.length / 3);
    state.ghost = { positions: r.positions, frames: r.frames, seed, meanDistance: mean, ran: r.ran };
    $('seed-note').textContent = `seed ${seed} overlaid (pink; ${METHOD_NAMES[r.ran] || 'Generative Tweening model'}): mean joint distance to seed ${seed - 1}'s motion ${mean.toFixed(2)} units`
      + (mean < 1 ? (m === 'cond' ? ' — the bundled conditional network barely uses its noise (README)' : ' — the bundled generator barely uses its DNA (README: Motion DNA measured)') : '');
    document.body.dataset.compared = String(seed);
    draw();
  } catch (e) {
    setStatus(`the second seed failed: ${e.message}`, true);
  }
}

/** Synthesizes the keys at the length in #length with the page's options. */
export async function synthesize() {
  const length = Number($('length').value);
  if (!Number.isInteger(length) || length < 1 || length > 4096) { setStatus('length must be 1..4096 frames', true); return; }
  if (length !== state.length) { pushHistory(); state.length = length; refreshTimeline(); }
  const keys = state.keys.filter((k) => k.frame < length);
  if (!keys.length) { setStatus('add at least one keyframe first', true); return; }
  const partial = keys.some((k) => k.root || k.xy);
  if (partial && (!state.client.hasModel || !['model', 'cond'].includes($('method').value))) {
    setStatus('root-path and 2-D keys need the Generative Tweening model or the conditional network (interpolation needs whole poses)', true);
    return;
  }
  const method = state.client.hasModel ? $('method').value : 'slerp';
  $('synth').disabled = true;
  $('progress').value = 0;
  try {
    const t0 = performance.now();
    // Without its BVH text (a fifth of a long synthesis): the export asks for it (io.js).
    const req = request(keys, length, method, dnaChannels());
    const r = await state.client.synthesize({ ...req, bvh: false });
    state.result = { positions: r.positions, frames: r.frames, bvh: null, request: req, method, times: r.times };
    state.ghost = null;
    $('seed-note').textContent = '';
    // what ran: 'model' is the residual network for whole-pose keys where its manifest says so
    $('method-badge').textContent = METHOD_NAMES[r.ran] || 'Generative Tweening model';
    $('method-badge').classList.toggle('baseline', method === 'slerp');
    if (!state.variationTouched && r.ran !== 'slerp') {
      // show the variation the planner chose for these keys
      $('variation').value = String(r.variation);
      $('variation-value').textContent = r.variation.toFixed(2);
    }
    document.body.dataset.ran = `${r.ran}@${r.variation}`;
    const ms = performance.now() - t0;
    $('timing').textContent = `${r.frames} frames in ${ms.toFixed(0)} ms` + (r.ran === 'generator' ? ` (generator ${r.times[0].toFixed(0)} ms, RC-FK ${r.times[1].toFixed(0)}, path ${r.times[2].toFixed(0)}, post ${r.times[3].toFixed(0)})` : '')
      + (partial && r.keyErrors ? `; keys met within ${r.keyErrors.after.root.toFixed(2)} (root), ${r.keyErrors.after.joints.toFixed(2)} (joints, the coordinates keys give) units; the networks alone missed by ${r.keyErrors.before.root.toFixed(1)}, ${r.keyErrors.before.joints.toFixed(1)}` : '')
      + (r.criticalFrames?.length ? `; hierarchical (Sec. 5.4.3): critical keys made first at frames ${r.criticalFrames.join(', ')}` : '');
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
