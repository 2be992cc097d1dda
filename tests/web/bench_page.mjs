// In-betweening benchmark in headless Chromium (wasm, one thread), 512-4096
// frames, whole-pose keys every 240 frames (4 s), post-processing on. Each
// row's `total_ms` and `first_call_ms` are the default pipeline as the npm
// package runs it (the worker loads the residual network, which serves
// whole-pose keys without Motion DNA: `default_method`); `generator_pipeline`
// holds the generator + path predictor pipeline per stage (the default for
// partial keys, DNA and gaps over 600 frames), with its first call and its
// best again with the models prepared for any length
// (Inbetweener.prepareAnyLength, as the npm worker); and the SLERP+LERP
// baseline on the same keys. Prints JSON. Usage: node tests/web/bench_page.mjs [--smoke]
import { withBenchPage } from './chromium.mjs';

const smoke = process.argv.includes('--smoke');
const sizes = smoke ? [512] : [512, 1024, 2048, 4096];
await withBenchPage(async (page) => {
  const rows = await page.evaluate(async ({ sizes, reps }) => {
    const m = await import('./pkg/deeprep.js');
    const get = (u) => fetch(u).then((r) => r.arrayBuffer()).then((b) => new Uint8Array(b));
    const model = new m.Inbetweener(await get('../models/onnx/tween_generator.onnx'), await get('../models/onnx/tween_path.onnx'),
      await fetch('../models/onnx/tween_generator.manifest.json').then((r) => r.text()));
    // the same models prepared for any length, as the npm worker runs them
    const anyLength = new m.Inbetweener(await get('../models/onnx/tween_generator.onnx'), await get('../models/onnx/tween_path.onnx'),
      await fetch('../models/onnx/tween_generator.manifest.json').then((r) => r.text()));
    anyLength.prepareAnyLength();
    // the default for whole-pose keys: the residual network (as the npm worker loads it)
    const withResidual = new m.Inbetweener(await get('../models/onnx/tween_generator.onnx'), await get('../models/onnx/tween_path.onnx'),
      await fetch('../models/onnx/tween_generator.manifest.json').then((r) => r.text()));
    withResidual.setResidual(await get('../models/onnx/tween_residual.onnx'),
      await fetch('../models/onnx/tween_residual.manifest.json').then((r) => r.text()));
    const residualDefault = withResidual.residualIsDefault;
    const poses = (await fetch('../models/examples/poses.json').then((r) => r.json())).poses;
    const out = [];
    for (const n of sizes) {
      const frames = [], chans = [];
      for (let f = 0, i = 0; f < n; f += 240, i++) { frames.push(f); const c = poses[i % poses.length].channels.slice(); c[0] = 30 * i; chans.push(...c); }
      const kf = new Uint32Array(frames), kc = new Float32Array(chans);
      let t = performance.now();
      model.synthesize(kf, kc, n, { post: true }).free();
      const first = performance.now() - t;
      let best = null, bestTotal = Infinity;
      for (let r = 0; r < reps; r++) {
        t = performance.now();
        const res = model.synthesize(kf, kc, n, { post: true });
        const total = performance.now() - t;
        if (total < bestTotal) { bestTotal = total; best = Array.from(res.times); }
        res.free();
      }
      t = performance.now();
      anyLength.synthesize(kf, kc, n, { post: true }).free();
      const anyFirst = performance.now() - t;
      let anyBest = Infinity;
      for (let r = 0; r < reps; r++) {
        t = performance.now();
        anyLength.synthesize(kf, kc, n, { post: true }).free();
        anyBest = Math.min(anyBest, performance.now() - t);
      }
      // the default pipeline (residual network for whole-pose keys, keys exact):
      // its first call at this length, then the best of reps
      t = performance.now();
      withResidual.synthesize(kf, kc, n, { post: true }).free();
      const resFirst = performance.now() - t;
      let resBest = Infinity, resNet = null;
      for (let r = 0; r < reps; r++) {
        t = performance.now();
        const res = withResidual.synthesize(kf, kc, n, { post: true });
        const total = performance.now() - t;
        if (total < resBest) { resBest = total; resNet = res.times[0]; }
        res.free();
      }
      t = performance.now();
      model.interpolate(kf, kc, n).free();
      const slerp = performance.now() - t;
      out.push({ frames: n, total_ms: resBest, first_call_ms: resFirst,
                 default_method: residualDefault ? 'residual' : 'generator',
                 residual_network_ms: residualDefault ? resNet : null,
                 generator_pipeline: { generator_ms: best[0], rcfk_ms: best[1], path_ms: best[2], post_ms: best[3],
                                       total_ms: bestTotal, first_call_ms: first,
                                       any_length_first_call_ms: anyFirst, any_length_total_ms: anyBest },
                 slerp_lerp_ms_with_bvh_and_fk: slerp });
    }
    return out;
  }, { sizes, reps: smoke ? 1 : 3 });
  console.log(JSON.stringify({ bench: 'inbetween', target: 'wasm (headless Chromium, SwiftShader, 1 thread)', rows }, null, 1));
});
