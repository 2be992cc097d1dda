// deeprep mesh worker: the mesh autoencoder (MeshLab) off the main thread.
//   -> {type: 'init', id, glb (ArrayBuffer) | obj (text), modelBase | models: {encoder, decoder (ArrayBuffer), manifest (text)}}
//   <- {type: 'result', id, vertexCount, triangles, hasRig, clipNames, clipDurations, latentVertices, latentNames, latentRegions, latentChannels, trainedOn}
//   -> {type: 'pose', id, clip, time} | {type: 'random', id, seed, degrees}   <- {positions}
//   -> {type: 'encode', id, positions}   <- {codes, recon, encodeMs, decodeMs}
//   -> {type: 'blend', id, a, b, vertex, t}   <- {positions, decodeMs}
//   <- {type: 'progress', id, stage} ... | {type: 'error', id, message}
import init, { MeshLab } from './pkg/deeprep.js';
import { fetchBytes, fetchText } from './lib/fetch.js';

let lab = null;
const ready = init();


async function handle(msg) {
  const { id } = msg;
  await ready;
  if (msg.type === 'init') {
    postMessage({ type: 'progress', id, stage: 'loading the mesh autoencoder' });
    const base = msg.modelBase;
    const [enc, dec, manifest] = msg.models
      ? [new Uint8Array(msg.models.encoder), new Uint8Array(msg.models.decoder), msg.models.manifest]
      : await Promise.all([
        fetchBytes(`${base}/mesh_encoder.onnx`), fetchBytes(`${base}/mesh_decoder.onnx`),
        fetchText(`${base}/mesh_autoencoder.manifest.json`, 'mesh manifest'),
      ]);
    postMessage({ type: 'progress', id, stage: 'reading the mesh and sampling its graph' });
    // the previous mesh and model stay loaded if this fails
    const next = msg.obj != null ? MeshLab.fromObj(msg.obj, enc, dec, manifest) : new MeshLab(new Uint8Array(msg.glb), enc, dec, manifest);
    if (lab) lab.free();
    lab = next;
    return {
      vertexCount: lab.vertexCount, triangles: lab.triangles, hasRig: lab.hasRig, clipNames: lab.clipNames,
      clipDurations: Array.from(lab.clipDurations), latentVertices: Array.from(lab.latentVertices),
      latentNames: lab.latentNames, latentRegions: lab.latentRegions, latentChannels: lab.latentChannels,
    };
  }
  if (!lab) throw new Error('load a mesh first');
  if (msg.type === 'pose') return { positions: lab.clipPose(msg.clip, msg.time) };
  if (msg.type === 'random') return { positions: lab.randomPose(msg.seed >>> 0, msg.degrees) };
  if (msg.type === 'encode') {
    const t0 = performance.now();
    const codes = lab.encode(new Float32Array(msg.positions));
    const t1 = performance.now();
    const recon = lab.decode(codes);
    const t2 = performance.now();
    return { codes, recon, encodeMs: t1 - t0, decodeMs: t2 - t1 };
  }
  if (msg.type === 'blend') {
    const t0 = performance.now();
    const positions = lab.decode(lab.blendOne(new Float32Array(msg.a), new Float32Array(msg.b), msg.vertex, msg.t));
    return { positions, decodeMs: performance.now() - t0 };
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
