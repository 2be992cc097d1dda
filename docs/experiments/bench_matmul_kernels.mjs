// Issue 23 experiment (session 23, not part of the package): does another
// register tiling of the wasm matrix kernel speed up our networks? With
// docs/experiments/wasm_matmul_kernels.patch applied (`git apply`; it adds a
// dispatch tier and two kernels through tract-linalg's public mmm_tiers and
// mmm_routines registries, and a knob, OnnxModel.setMatmulTile) and
// `bash scripts/build-wasm.sh`, this runs one model with each choice in one
// page, alternately, best of 16: t0 tract's own (wasm_f32_8x8), t1 tract's
// wasm_f32_4x16, t2 a 6x8 and t3 a 4x12 kernel (12 accumulators, A
// broadcast by v128.load32_splat); diffN is the largest difference to t0.
// Usage: node docs/experiments/bench_matmul_kernels.mjs [model=NAME ch=C] FRAMES...
import { withBenchPage } from '../../tests/web/chromium.mjs';
const args = process.argv.slice(2);
const lengths = args.filter((a) => /^\d+$/.test(a)).map(Number);
const model = (args.find((a) => a.startsWith('model=')) || 'model=tween_residual').slice(6);
const chans = Number((args.find((a) => a.startsWith('ch=')) || 'ch=265').slice(3));
await withBenchPage(async (page) => {
  const rows = await page.evaluate(async ({ lengths, model, chans }) => {
    const { hasRelaxedSimd } = await import('./lib/wasm-features.js');
    const wasm = hasRelaxedSimd() ? 'relaxed-simd' : 'simd128';
    const m = await import('./pkg-core/deeprep.js');
    await m.default(wasm === 'relaxed-simd' ? { module_or_path: './pkg-core/deeprep_relaxed_bg.wasm' } : undefined);
    const bytes = new Uint8Array(await (await fetch(`../models/onnx/${model}.onnx`)).arrayBuffer());
    const tiles = [0, 1, 2, 3];
    const models = tiles.map(() => new m.OnnxModel(bytes));
    const out = [{ wasm }];
    for (const n of lengths) {
      const x = new Float32Array(chans * n);
      for (let i = 0; i < x.length; i++) x[i] = Math.sin(i * 0.37) * 0.8;
      const row = { frames: n };
      const res = [];
      for (let i = 0; i < tiles.length; i++) {
        m.OnnxModel.setMatmulTile(tiles[i]);
        res.push(models[i].run(x, [1, chans, n]));
        row[`t${tiles[i]}_ms`] = Infinity;
      }
      row.kernel_tile_stores = m.OnnxModel.setMatmulTile(0);
      for (let i = 1; i < tiles.length; i++) row[`diff${tiles[i]}`] = res[0].reduce((d, v, j) => Math.max(d, Math.abs(v - res[i][j])), 0);
      for (let r = 0; r < 16; r++) for (let i = 0; i < tiles.length; i++) {
        const t = performance.now(); models[i].run(x, [1, chans, n]);
        row[`t${tiles[i]}_ms`] = Math.min(row[`t${tiles[i]}_ms`], performance.now() - t);
      }
      out.push(row);
    }
    return out;
  }, { lengths: lengths.length ? lengths : [1024, 2048, 4096], model, chans });
  for (const r of rows) console.log(JSON.stringify(r));
});
