// Side by side in one headless Chromium page (one thread, wasm SIMD, the
// same ONNX files and inputs): tract (deeprep's wasm, OnnxModel) against
// onnxruntime-web (its wasm backend, numThreads = 1), on every bundled
// model. Prints JSON: per case the best of 8 rounds, each runner in turn,
// after one warm-up run of each (which builds tract's plan); the ratio
// tract / onnxruntime-web; the largest difference between their outputs;
// and tract's time per operator in this page (OnnxModel.profileInputs:
// every node of its plan timed with performance.now(), top four; matrix
// products per kernel, `kernel`; in the worker's relaxed build where the
// browser has it, `tract_profile_build`).
// `tract_ms` is the page-side package's build (web/pkg, SIMD);
// `tract_relaxed_ms` and `ratio_relaxed` the worker's core build with
// relaxed SIMD (web/pkg-core/deeprep_relaxed_bg.wasm; null where this
// browser lacks relaxed SIMD), the third runner of each round.
// Both builds run products with the matrix kernel runtime::matmul_kernel
// chooses for this host (deeprep's 3x12 on x86-64, tract's 8x8 elsewhere;
// `matmul_kernel` per build); `tract_relaxed_tract_kernel_ms`, the fourth
// runner, is the relaxed build with tract's own 8x8 kernel, side by side.
// Usage: node tests/web/bench_ort_page.mjs [--smoke]
import { withBenchPage } from './chromium.mjs';

const smoke = process.argv.includes('--smoke');
// [name, model file, inputs {name: shape}, input value range, fold factors]
const CASES = [
  ['rot6d_autoencoder', 'rot6d_autoencoder', { matrix_in: [64, 9] }],
  ['ik, batch 64', 'ik', { positions: [64, 171] }],
  ['hair_features, 256x256', 'hair_features', { image: [1, 3, 256, 256] }, [0, 1]],
  ['hair_strands, 1,024 strands', 'hair_strands', { features: [1, 64, 1024, 1] }],
  ['mesh_encoder', 'mesh_encoder', { positions: [1, 1820, 3] }, [-1, 1], true],
  ['mesh_decoder', 'mesh_decoder', { latent: [1, 8, 16] }, [-1, 1], true],
  ['tween_path, 512 frames', 'tween_path', { local: [1, 171, 512] }],
  ['tween_path, 2048 frames', 'tween_path', { local: [1, 171, 2048] }],
  ['tween_generator, 512 frames', 'tween_generator', { dense: [1, 342, 512], dense_rot: [1, 264, 512], dna: [1, 8, 171] }],
  ['tween_generator, 2048 frames', 'tween_generator', { dense: [1, 342, 2048], dense_rot: [1, 264, 2048], dna: [1, 11, 171] }],
  ['tween_residual, 512 frames', 'tween_residual', { x: [1, 265, 512] }],
  ['tween_residual, 2048 frames', 'tween_residual', { x: [1, 265, 2048] }],
];
const cases = smoke ? CASES.filter(([n]) => ['rot6d_autoencoder', 'tween_generator, 512 frames'].includes(n)) : CASES;
await withBenchPage(async (page) => {
  const res = await page.evaluate(async ({ cases, reps }) => {
    const m = await import('./pkg/deeprep.js');
    // the worker's core wasm with relaxed SIMD (web/worker.js picks it where it validates)
    const { hasRelaxedSimd } = await import('./lib/wasm-features.js');
    let relaxed = null;
    if (hasRelaxedSimd()) {
      relaxed = await import('./pkg-core/deeprep.js');
      await relaxed.default({ module_or_path: './pkg-core/deeprep_relaxed_bg.wasm' });
    }
    const kernels = { wasm: JSON.parse(m.OnnxModel.matmulKernel()), relaxed: relaxed && JSON.parse(relaxed.OnnxModel.matmulKernel()) };
    const ort = await import('../node_modules/onnxruntime-web/dist/ort.wasm.min.mjs');
    ort.env.wasm.numThreads = 1;
    ort.env.wasm.wasmPaths = new URL('../node_modules/onnxruntime-web/dist/', location.href).href;
    let seed = 12345;
    const rand = () => { seed = (seed * 1103515245 + 12345) >>> 0; return seed / 2 ** 32; };
    // Each runner once to warm up, then `reps` rounds of all of them in turn (this
    // machine's speed drifts by 2x over minutes: in turn, a slow stretch hits
    // every runner alike); the best time of each.
    const bestInTurn = async (fs) => {
      for (const f of fs) await f();
      const b = fs.map(() => Infinity);
      for (let r = 0; r < reps; r++) {
        for (let i = 0; i < fs.length; i++) { const t = performance.now(); await fs[i](); b[i] = Math.min(b[i], performance.now() - t); }
      }
      return b;
    };
    const out = [];
    for (const [name, file, inputs, range = [-1, 1], fold = false] of cases) {
      const bytes = new Uint8Array(await (await fetch(`../models/onnx/${file}.onnx`)).arrayBuffer());
      const feeds = {}, data = [], shapes = [], ranks = [];
      for (const [k, shape] of Object.entries(inputs)) {
        const n = shape.reduce((a, b) => a * b, 1);
        const v = new Float32Array(n);
        for (let i = 0; i < n; i++) v[i] = range[0] + (range[1] - range[0]) * rand();
        feeds[k] = new ort.Tensor('float32', v, shape);
        data.push(v); shapes.push(...shape); ranks.push(shape.length);
      }
      const flat = new Float32Array(data.reduce((a, v) => a + v.length, 0));
      data.reduce((at, v) => { flat.set(v, at); return at + v.length; }, 0);
      const tract = fold ? m.OnnxModel.withFoldedFactors(bytes) : new m.OnnxModel(bytes);
      const session = await ort.InferenceSession.create(bytes, { executionProviders: ['wasm'], graphOptimizationLevel: 'all' });
      const tractR = relaxed && (fold ? relaxed.OnnxModel.withFoldedFactors(bytes) : new relaxed.OnnxModel(bytes));
      const tractT = relaxed && (fold ? relaxed.OnnxModel.withFoldedFactors(bytes) : new relaxed.OnnxModel(bytes));
      let a, b, c, firstT = true;
      const [tractMs, ortMs, relaxedMs = null, tractKernelMs = null] = await bestInTurn([
        () => { a = tract.runInputs(flat, new Uint32Array(shapes), new Uint32Array(ranks)); },
        async () => { b = (await session.run(feeds))[session.outputNames[0]].data; },
        ...(tractR ? [() => { c = tractR.runInputs(flat, new Uint32Array(shapes), new Uint32Array(ranks)); },
          () => {
            // its plan (built on this first call) with tract's kernel; then back to the host's choice
            if (firstT) relaxed.OnnxModel.setMatmulKernel('tract');
            tractT.runInputs(flat, new Uint32Array(shapes), new Uint32Array(ranks));
            if (firstT) relaxed.OnnxModel.setMatmulKernel('auto');
            firstT = false;
          }] : []),
      ]);
      let diff = 0, diffR = 0;
      for (let i = 0; i < a.length; i++) diff = Math.max(diff, Math.abs(a[i] - b[i]));
      if (c) for (let i = 0; i < c.length; i++) diffR = Math.max(diffR, Math.abs(c[i] - b[i]));
      // where tract spends its time here, in wasm, in the worker's build where this browser
      // has it: its plan's nodes timed, per operator (products per matrix kernel)
      const profiled = tractR || tract;
      const profile = JSON.parse(profiled.profileInputs(flat, new Uint32Array(shapes), new Uint32Array(ranks), reps))
        .slice(0, 4).map((o) => ({ op: o.op, ...(o.kernel ? { kernel: o.kernel } : {}), ms: +o.ms.toFixed(2),
                                   share: +o.share.toFixed(3), nodes: o.nodes }));
      out.push({ model: name, tract_ms: +tractMs.toFixed(2), onnxruntime_web_ms: +ortMs.toFixed(2),
                 ratio: +(tractMs / ortMs).toFixed(2), max_output_difference: diff, outputs: a.length === b.length ? a.length : `${a.length} vs ${b.length}`,
                 tract_relaxed_ms: relaxedMs === null ? null : +relaxedMs.toFixed(2),
                 ratio_relaxed: relaxedMs === null ? null : +(relaxedMs / ortMs).toFixed(2),
                 max_output_difference_relaxed: c ? diffR : null,
                 tract_relaxed_tract_kernel_ms: tractKernelMs === null ? null : +tractKernelMs.toFixed(2),
                 tract_profile_wasm: profile, tract_profile_build: tractR ? 'relaxed-simd' : 'simd128' });
      tract.free();
      tractR?.free();
      tractT?.free();
      await session.release();
    }
    return { rows: out, kernels };
  }, { cases, reps: smoke ? 1 : 8 });
  console.log(JSON.stringify({ bench: 'tract_vs_onnxruntime_web', target: 'headless Chromium, wasm SIMD, one thread',
                               onnxruntime_web: '1.30.0', matmul_kernel: res.kernels, rows: res.rows }, null, 1));
});
