// Mesh autoencoder benchmark in headless Chromium (wasm, one thread): encode
// and decode time per mesh through MeshLab (factored kernels multiplied out
// at load, as natively), plus load time. Needs the robot glTF from the
// shared data set (skips with a message without it). Prints JSON.
// Usage: node tests/web/bench_mesh_page.mjs [--smoke]
import fs from 'node:fs';
import path from 'node:path';
import { withBenchPage, ROOT } from './chromium.mjs';

const GLB = path.resolve(process.env.DEEPREP_DATA || path.join(ROOT, '..', 'shared', 'data'), 'gltf', 'RobotExpressive.glb');
if (!fs.existsSync(GLB)) {
  console.log(JSON.stringify({ bench: 'mesh', skipped: `${GLB} is absent` }));
  process.exit(0);
}
const smoke = process.argv.includes('--smoke');
await withBenchPage(async (page) => {
  const row = await page.evaluate(async ({ reps }) => {
    const m = await import('./pkg/deeprep.js');
    const get = (u) => fetch(u).then((r) => { if (!r.ok) throw new Error(`${u}: ${r.status}`); return r.arrayBuffer(); }).then((b) => new Uint8Array(b));
    let t = performance.now();
    const lab = new m.MeshLab(await get('../shared-data/gltf/RobotExpressive.glb'), await get('../models/onnx/mesh_encoder.onnx'),
      await get('../models/onnx/mesh_decoder.onnx'), await fetch('../models/onnx/mesh_autoencoder.manifest.json').then((r) => r.text()));
    const load = performance.now() - t;
    const pose = lab.clipPose(0, 0.5);
    let codes = lab.encode(pose);
    lab.decode(codes);
    const enc = [], dec = [];
    for (let r = 0; r < reps; r++) {
      t = performance.now(); codes = lab.encode(pose); enc.push(performance.now() - t);
      t = performance.now(); lab.decode(codes); dec.push(performance.now() - t);
    }
    const median = (a) => a.slice().sort((x, y) => x - y)[Math.floor(a.length / 2)];
    return { vertices: lab.vertexCount, load_glb_sample_and_models_ms: load, encode_ms: median(enc), decode_ms: median(dec), reps };
  }, { reps: smoke ? 1 : 20 });
  console.log(JSON.stringify({ bench: 'mesh', target: 'wasm (headless Chromium, 1 thread)', ...row }, null, 1));
});
