// Issue 23 experiment (session 27, not part of the package): is tract's
// loss to onnxruntime-web in the convolutions' forms or in the matrix
// product itself? One operator at a time, with the bundled residual
// network's shapes (docs/experiments/gemm_forms.py writes the models:
// 112 x 336 weights against 1,024 columns, 38.5 M multiply-adds each), in one
// headless Chromium page, one thread: tract's page-side build (plain SIMD),
// the worker's relaxed-SIMD build and onnxruntime-web 1.30 (wasm, one
// thread), in turn, best of REPS after a warm-up; GFLOP/s of each; the
// largest difference between tract's and onnxruntime-web's outputs; the top
// of tract's own profile (relaxed build). Prints one JSON line per model.
// Both tract builds run the matrix kernel runtime::matmul_kernel chooses
// (since session 27; docs/experiments/gemm_forms_2026-12-04.jsonl has a run
// from before it and one after).
// Usage: train/.venv/bin/python docs/experiments/gemm_forms.py &&
//        node docs/experiments/bench_gemm_forms.mjs [REPS]
import { withBenchPage } from '../../tests/web/chromium.mjs';
const CASES = [
  ['conv3_d1', { x: [1, 112, 1024] }], ['conv3_d8', { x: [1, 112, 1024] }], ['conv3_d64', { x: [1, 112, 1024] }],
  ['conv1_k336', { x: [1, 336, 1024] }], ['matmul_x_w', { x: [1024, 336] }], ['matmul_w_x', { x: [336, 1024] }],
];
const reps = Number(process.argv[2] || 16);
await withBenchPage(async (page) => {
  const rows = await page.evaluate(async ({ CASES, reps }) => {
    const m = await import('./pkg/deeprep.js');
    const relaxed = await import('./pkg-core/deeprep.js');
    await relaxed.default({ module_or_path: './pkg-core/deeprep_relaxed_bg.wasm' });
    const ort = await import('../node_modules/onnxruntime-web/dist/ort.wasm.min.mjs');
    ort.env.wasm.numThreads = 1;
    ort.env.wasm.wasmPaths = new URL('../node_modules/onnxruntime-web/dist/', location.href).href;
    const out = [];
    for (const [file, inputs] of CASES) {
      const bytes = new Uint8Array(await (await fetch(`../train/cache/gemm/${file}.onnx`)).arrayBuffer());
      const [k, shape] = Object.entries(inputs)[0];
      const n = shape.reduce((a, b) => a * b, 1);
      const v = new Float32Array(n); for (let i = 0; i < n; i++) v[i] = Math.sin(i * 0.37);
      const feeds = { [k]: new ort.Tensor('float32', v, shape) };
      const t1 = new m.OnnxModel(bytes), t2 = new relaxed.OnnxModel(bytes);
      const s = await ort.InferenceSession.create(bytes, { executionProviders: ['wasm'], graphOptimizationLevel: 'all' });
      const fs = [() => t1.run(v, shape), () => t2.run(v, shape), async () => (await s.run(feeds)).y.data];
      const res = []; for (const f of fs) res.push(await f());
      const b = fs.map(() => Infinity);
      for (let r = 0; r < reps; r++) for (let i = 0; i < fs.length; i++) { const t = performance.now(); await fs[i](); b[i] = Math.min(b[i], performance.now() - t); }
      let diff = 0; for (let i = 0; i < res[0].length; i++) diff = Math.max(diff, Math.abs(res[0][i] - res[2][i]));
      const prof = JSON.parse(t2.profileInputs(v, new Uint32Array(shape), new Uint32Array([shape.length]), 4)).slice(0, 3).map((o) => `${o.op} ${o.ms.toFixed(2)}`);
      out.push({ model: file, tract_ms: +b[0].toFixed(2), tract_relaxed_ms: +b[1].toFixed(2), ort_ms: +b[2].toFixed(2),
        ratio: +(b[0] / b[2]).toFixed(2), ratio_relaxed: +(b[1] / b[2]).toFixed(2), gflops: b.map((t) => +(2 * 112 * 336 * 1024 / t / 1e6).toFixed(1)), diff, prof });
      t1.free(); t2.free(); await s.release();
    }
    return out;
  }, { CASES, reps });
  for (const r of rows) console.log(JSON.stringify(r));
});
