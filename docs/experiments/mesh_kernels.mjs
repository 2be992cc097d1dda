// Session 28: which matrix kernel each product of the mesh models and the
// strand decoder runs, with deeprep's kernel allowed ("own") and with
// tract's ("tract"), the relaxed build alone in one page: best of 20 and
// the profile per operator. Usage: node docs/experiments/mesh_kernels.mjs
import { withBenchPage } from '../../tests/web/chromium.mjs';
await withBenchPage(async (page) => {
  const res = await page.evaluate(async () => {
    const r = await import('./pkg-core/deeprep.js');
    await r.default({ module_or_path: './pkg-core/deeprep_relaxed_bg.wasm' });
    const out = {};
    for (const [file, shape] of [['mesh_encoder', [1, 1820, 3]], ['mesh_decoder', [1, 8, 16]], ['hair_strands', [1, 64, 1024, 1]]]) {
      const bytes = new Uint8Array(await (await fetch(`../models/onnx/${file}.onnx`)).arrayBuffer());
      const n = shape.reduce((a, b) => a * b, 1);
      const x = new Float32Array(n).map((_, i) => Math.sin(i * 0.37));
      for (const k of ['own', 'tract']) {
        r.OnnxModel.setMatmulKernel(k);
        const m = file.startsWith('mesh') ? r.OnnxModel.withFoldedFactors(bytes) : new r.OnnxModel(bytes);
        m.runInputs(x, new Uint32Array(shape), new Uint32Array([shape.length]));
        let best = Infinity;
        for (let i = 0; i < 20; i++) { const t = performance.now(); m.runInputs(x, new Uint32Array(shape), new Uint32Array([shape.length])); best = Math.min(best, performance.now() - t); }
        out[`${file} ${k}`] = { best, prof: JSON.parse(m.profileInputs(x, new Uint32Array(shape), new Uint32Array([shape.length]), 10)).slice(0, 8) };
        m.free();
      }
      r.OnnxModel.setMatmulKernel('auto');
    }
    return out;
  });
  for (const [k, v] of Object.entries(res)) {
    console.log(k, v.best.toFixed(2));
    for (const o of v.prof) console.log('   ', o.op, o.kernel || '', o.ms.toFixed(2), o.nodes);
  }
});
