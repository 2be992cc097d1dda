// deeprep hair worker: HairNet and the strand reconstruction off the main thread.
//   -> {type: 'init', id, modelBase}                          <- {classNames, bodyPositions, bodyTriangles}
//   -> {type: 'test', id, cls, seed, yaw}                     <- {image, truth}
//   -> {type: 'photo', id, grey, hair, w, h}                   <- {image, ms}   (Gabor orientation input)
//   -> {type: 'features', id, image}                          <- {features, ms}
//   -> {type: 'strands', id, features, count, smooth, curl, gpu}   <- {points, ms, collision, device}
//      gpu: decode on WebGPU compute (opened on first use); rejects where WebGPU is missing
//   <- {type: 'error', id, message}
import init, { HairLab } from './pkg/deeprep.js';
import { fetchBytes, fetchText } from './lib/fetch.js';

let lab = null;
let gpu = null;
const ready = init();

async function handle(msg) {
  await ready;
  if (msg.type === 'init') {
    const base = msg.modelBase;
    const [f, s, m] = await Promise.all([
      fetchBytes(`${base}/hair_features.onnx`), fetchBytes(`${base}/hair_strands.onnx`),
      fetchText(`${base}/hair_features.manifest.json`, 'hair manifest'),
    ]);
    lab = new HairLab(f, s, m);
    return { classNames: HairLab.classNames(), bodyPositions: lab.bodyPositions(), bodyTriangles: lab.bodyTriangles() };
  }
  if (!lab) throw new Error('the hair model is not loaded');
  if (msg.type === 'test') {
    return { image: lab.testImage(msg.cls, msg.seed >>> 0, msg.yaw), truth: lab.testHair(msg.cls, msg.seed >>> 0) };
  }
  if (msg.type === 'photo') {
    const t0 = performance.now();
    const image = lab.photoInput(new Float32Array(msg.grey), new Float32Array(msg.hair), new Float32Array(0), msg.w, msg.h);
    return { image, ms: performance.now() - t0 };
  }
  if (msg.type === 'features') {
    const t0 = performance.now();
    const features = lab.features(new Float32Array(msg.image));
    return { features, ms: performance.now() - t0 };
  }
  if (msg.type === 'strands') {
    const feats = new Float32Array(msg.features);
    if (msg.gpu && !gpu) gpu = await lab.openGpu();
    const t0 = performance.now();
    const points = msg.gpu ? await gpu.strands(feats, msg.count, msg.smooth, msg.curl) : lab.strands(feats, msg.count, msg.smooth, msg.curl);
    const ms = performance.now() - t0;
    return { points, ms, collision: lab.collisionError(points), device: msg.gpu ? 'webgpu' : 'cpu' };
  }
  throw new Error(`unknown request '${msg.type}'`);
}

onmessage = async (e) => {
  const msg = e.data;
  try {
    postMessage({ type: 'result', id: msg.id, ...(await handle(msg)) });
  } catch (err) {
    // trapped: the wasm instance is unusable; the page's workerClient replaces this worker
    postMessage({ type: 'error', id: msg.id, trapped: err instanceof WebAssembly.RuntimeError,
                  message: String(err && err.message ? err.message : err) });
  }
};
