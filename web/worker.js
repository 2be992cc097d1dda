// deeprep synthesis worker: loads the wasm package and the in-betweening
// models off the main thread, and answers requests with progress events.
//   -> {type: 'init', modelBase}
//   <- {type: 'ready', skeletonBvh, hasModel, defaultVariation, modelError}
//   -> {type: 'synthesize', id, keyFrames, keyChannels, frames, post, dna, method, variation, footLock}
//   <- {type: 'progress', id, stage, fraction}  ...  {type: 'result', id, ...} | {type: 'error', id, message}
//   -> {type: 'rcAngles', id, channels, joint} / {type: 'setRcAngles', id, channels, joint, angles}
//   -> {type: 'ik', id, positions, frames}   (IK from joint positions; the IK model loads on first use)
import init, { Inbetweener, IkSolver } from './pkg/deeprep.js';

let model = null;
let modelBase = null;
let ik = null;

async function fetchBytes(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${url}: HTTP ${r.status}`);
  return new Uint8Array(await r.arrayBuffer());
}

async function handleInit(msg) {
  await init();
  const base = msg.modelBase;
  modelBase = base;
  try {
    const [g, p, m] = await Promise.all([
      fetchBytes(`${base}/tween_generator.onnx`), fetchBytes(`${base}/tween_path.onnx`),
      fetch(`${base}/tween_generator.manifest.json`).then((r) => { if (!r.ok) throw new Error(`manifest: HTTP ${r.status}`); return r.text(); }),
    ]);
    model = new Inbetweener(g, p, m);
    postMessage({ type: 'ready', skeletonBvh: model.skeletonBvh, hasModel: true, defaultVariation: model.defaultVariation });
  } catch (e) {
    postMessage({ type: 'ready', skeletonBvh: null, hasModel: false, modelError: String(e.message || e) });
  }
}

async function handleIk(msg) {
  const { id } = msg;
  if (!ik) {
    postMessage({ type: 'progress', id, stage: 'loading the IK model', fraction: 0.1 });
    const [bytes, manifest] = await Promise.all([
      fetchBytes(`${modelBase}/ik.onnx`),
      fetch(`${modelBase}/ik.manifest.json`).then((r) => { if (!r.ok) throw new Error(`ik manifest: HTTP ${r.status}`); return r.text(); }),
    ]);
    ik = new IkSolver(bytes, manifest);
  }
  postMessage({ type: 'progress', id, stage: 'solving IK', fraction: 0.5 });
  const r = ik.solve(new Float32Array(msg.positions), msg.frames);
  const positions = r.positions;
  const channels = r.channels;
  postMessage({ type: 'result', id, bvh: r.bvh, channels, positions, meanError: r.meanError, maxError: r.maxError },
              [positions.buffer, channels.buffer]);
  r.free();
}

function handle(msg) {
  const { id } = msg;
  if (!model) throw new Error('the in-betweening models are not loaded');
  if (msg.type === 'synthesize') {
    postMessage({ type: 'progress', id, stage: msg.method === 'slerp' ? 'interpolating' : 'generator, RC-FK, path, post-processing', fraction: 0.1 });
    const kf = new Uint32Array(msg.keyFrames);
    const kc = new Float32Array(msg.keyChannels);
    const r = msg.method === 'slerp'
      ? model.interpolate(kf, kc, msg.frames)
      : model.synthesize(kf, kc, msg.frames, msg.post, new Float32Array(msg.dna || []), msg.variation, msg.footLock);
    postMessage({ type: 'progress', id, stage: 'writing BVH', fraction: 0.9 });
    const positions = r.positions;
    postMessage({ type: 'result', id, method: msg.method, bvh: r.bvh, frames: r.frames, times: Array.from(r.times),
                  keyError: Array.from(r.keyError), positions }, [positions.buffer]);
    r.free();
  } else if (msg.type === 'rcAngles') {
    postMessage({ type: 'result', id, angles: Array.from(model.rcAngles(new Float32Array(msg.channels), msg.joint)) });
  } else if (msg.type === 'setRcAngles') {
    postMessage({ type: 'result', id, channels: Array.from(model.setRcAngles(new Float32Array(msg.channels), msg.joint, new Float64Array(msg.angles))) });
  } else {
    throw new Error(`unknown request '${msg.type}'`);
  }
}

onmessage = async (e) => {
  const msg = e.data;
  try {
    if (msg.type === 'init') await handleInit(msg);
    else if (msg.type === 'ik') await handleIk(msg);
    else handle(msg);
  } catch (err) {
    postMessage({ type: 'error', id: msg.id, message: String(err && err.message ? err.message : err) });
  }
};
