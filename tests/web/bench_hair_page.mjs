// HairNet timings in headless Chromium (wasm, one thread), Table 3.3's
// columns: preprocessing (Gabor orientation filter), inference (image ->
// strand features), reconstruction at 1,024 / 9,000 / 30,000 strands.
// Prints JSON. Usage: node tests/web/bench_hair_page.mjs [--smoke]
import { withBenchPage } from './chromium.mjs';

const smoke = process.argv.includes('--smoke');
await withBenchPage(async (page) => {
  const row = await page.evaluate(async ({ reps }) => {
    const m = await import('./pkg/deeprep.js');
    const get = (u) => fetch(u).then((r) => { if (!r.ok) throw new Error(`${u}: ${r.status}`); return r.arrayBuffer(); }).then((b) => new Uint8Array(b));
    const lab = new m.HairLab(await get('../models/onnx/hair_features.onnx'), await get('../models/onnx/hair_strands.onnx'),
      await fetch('../models/onnx/hair_features.manifest.json').then((r) => r.text()));
    const median = (a) => a.slice().sort((x, y) => x - y)[Math.floor(a.length / 2)];
    const time = (f) => { f(); const t = []; for (let r = 0; r < reps; r++) { const t0 = performance.now(); f(); t.push(performance.now() - t0); } return median(t); };
    const image = lab.testImage('L-wavy', 7, 0);
    const plane = 256 * 256;
    const grey = new Float32Array(plane).map((_, i) => 0.5 + 0.5 * Math.sin((i % 256) * 1.5));
    const mask = new Float32Array(plane).map((_, i) => (image[2 * plane + i] === 1 ? 1 : 0));
    const out = { preprocessing_gabor_ms: time(() => lab.photoInput(grey, mask, new Float32Array(0), 256, 256)),
                  inference_ms: time(() => lab.features(image)) };
    const f = lab.features(image);
    for (const n of [1024, 9000, 30000]) {
      out[`reconstruction_${n}_straight_ms`] = time(() => lab.strands(f, n, 1.5, Infinity));
      out[`reconstruction_${n}_with_curls_ms`] = time(() => lab.strands(f, n, 1.5, 15));
    }
    return out;
  }, { reps: smoke ? 1 : 3 });
  console.log(JSON.stringify({ bench: 'hair', target: 'wasm (headless Chromium, 1 thread)', ...row }, null, 1));
});
