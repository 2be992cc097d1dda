// The residual network's two plans in headless Chromium (issue 23): the plan
// for any length (what the worker's first request of a length runs on) and
// the length's own plan (what the worker builds when idle after it,
// Inbetweener.prepareLength), run alternately on the same input, best of 8,
// with the worker's wasm build; each plan's first call (the own plan's
// includes building it) and tract's profile of each (top four operators).
// Prints JSON, one line per length.
// Usage: node tests/web/bench_plans.mjs [FRAMES...]   (default 1024 2048 4096)
import { withBenchPage } from './chromium.mjs';

const lengths = process.argv.slice(2).map(Number);
await withBenchPage(async (page) => {
  const rows = await page.evaluate(async (lengths) => {
    const { hasRelaxedSimd } = await import('./lib/wasm-features.js');
    const wasm = hasRelaxedSimd() ? 'relaxed-simd' : 'simd128';
    const m = await import('./pkg-core/deeprep.js');
    await m.default(wasm === 'relaxed-simd' ? { module_or_path: './pkg-core/deeprep_relaxed_bg.wasm' } : undefined);
    const bytes = new Uint8Array(await (await fetch('../models/onnx/tween_residual.onnx')).arrayBuffer());
    const own = new m.OnnxModel(bytes), any = new m.OnnxModel(bytes);
    let t = performance.now();
    any.prepareAnyShape();
    const out = [{ wasm, prepare_any_shape_ms: performance.now() - t }];
    const top = (model, x, n) => JSON.parse(model.profileInputs(x, [1, 265, n], [3], 2)).slice(0, 4)
      .map((o) => ({ op: o.op, ms: +o.ms.toFixed(1) }));
    for (const n of lengths) {
      const x = new Float32Array(265 * n);
      for (let i = 0; i < x.length; i++) x[i] = Math.sin(i * 0.37) * 0.8;
      const row = { frames: n, own_ms: Infinity, any_ms: Infinity };
      t = performance.now(); const a = any.run(x, [1, 265, n]); row.any_first_ms = performance.now() - t;
      t = performance.now(); const b = own.run(x, [1, 265, n]); row.own_first_ms = performance.now() - t;
      row.max_difference = a.reduce((d, v, i) => Math.max(d, Math.abs(v - b[i])), 0);
      for (let r = 0; r < 8; r++) {
        t = performance.now(); own.run(x, [1, 265, n]); row.own_ms = Math.min(row.own_ms, performance.now() - t);
        t = performance.now(); any.run(x, [1, 265, n]); row.any_ms = Math.min(row.any_ms, performance.now() - t);
      }
      row.own_profile = top(own, x, n);
      row.any_profile = top(any, x, n);
      out.push(row);
    }
    return out;
  }, lengths.length ? lengths : [1024, 2048, 4096]);
  for (const r of rows) console.log(JSON.stringify(r));
});
