// The keyframe-sketching page (index.html). Synthesis runs in a Web Worker
// (web/client.js); the main thread keeps the keys, draws, and never loses
// them on errors. Modules: state (the keys and history), skeleton (FK by
// the core), view / view2d (the wgpu renderer with its fallbacks), timeline,
// joints (RC-angle sliders, IK drags), synth (synthesis, seeded DNA), io
// (BVH import/export), input (mouse and keys).
import init from '../pkg/deeprep.js';
import { DeeprepClient } from '../client.js';
import { $, setStatus, state } from './state.js';
import { fillLibrary } from './io.js';
import { wireCanvas, wireInput } from './input.js';
import { loadSkeleton } from './skeleton.js';
import { dnaChannels, synthesize } from './synth.js';
import { refreshTimeline, setFrame } from './timeline.js';
import { createView, draw, viewReplacing } from './view.js';

const MODEL_BASE = new URL('../../models/onnx', import.meta.url).href;
const EXAMPLES = new URL('../../models/examples', import.meta.url).href;

async function main() {
  await init();
  await createView(wireCanvas);
  wireInput();
  setStatus('loading models in a worker…');
  state.client = await DeeprepClient.create({
    modelBase: MODEL_BASE,
    onProgress: (m) => { $('progress').value = m.fraction; $('progress-label').textContent = m.stage; },
  });
  if (!state.client.hasModel) throw new Error(`models unavailable (${state.client.modelError})`);
  if (!state.client.hasResidual) $('method').querySelector('option[value="residual"]')?.remove();
  if (!state.client.hasCond) $('method').querySelector('option[value="cond"]')?.remove();
  state.skeleton = loadSkeleton(state.client.skeletonBvh);
  $('variation').value = String(state.client.defaultVariation);
  $('variation-value').textContent = state.client.defaultVariation.toFixed(2);
  const [poses, keys] = await Promise.all([
    fetch(`${EXAMPLES}/poses.json`).then((r) => r.json()),
    fetch(`${EXAMPLES}/keys.json`).then((r) => r.json()),
  ]);
  state.library = poses.poses.map((p) => ({ name: p.name, channels: p.channels }));
  state.keys = keys.keys.map((k) => ({ frame: k.frame, channels: k.channels }));
  state.length = keys.frames;
  $('length').value = String(keys.frames);
  fillLibrary();
  refreshTimeline();
  setFrame(0);
  state.view.frame();
  draw();
  await synthesize();
  // A GPU device that is lost right after its first frames (see view.js)
  // is replaced before the page reports ready.
  await new Promise((r) => setTimeout(r, 200));
  draw();
  await viewReplacing();
  document.body.dataset.ready = '1';
}

main().catch((e) => { setStatus(`error: ${e.message}`, true); console.error(e); });
window.deeprepState = state; // for tests and the console
window.deeprepSketch = { dnaChannels }; // what the next synthesis would send as DNA
