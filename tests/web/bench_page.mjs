// In-betweening benchmark in headless Chromium (wasm, one thread), 512-4096
// frames, whole-pose keys every 240 frames (4 s), post-processing on. Each
// row's `total_ms` and `first_call_ms` are the default pipeline as the npm
// package runs it (the worker loads the residual network, which serves
// whole-pose keys without Motion DNA: `default_method`); `generator_pipeline`
// holds the generator + path predictor pipeline per stage (the default for
// partial keys, DNA and gaps over 600 frames), with its first call and its
// best again with the models prepared for any length
// (Inbetweener.prepareAnyLength, as the npm worker); and the SLERP+LERP
// baseline on the same keys (its BVH text read, as before results wrote it
// eagerly). The wasm is the worker's: web/pkg-core, the relaxed-SIMD build
// where this Chromium validates relaxed SIMD (`wasm`); `simd128_total_ms` is
// the default pipeline with the plain SIMD build, run alternately with it in
// the same page. `bvh_ms` is the first read of the default result's BVH text
// (written on demand since issue 23; the sketch page asks for it only to
// export). Before the first length, the default pipeline's Inbetweener warms
// up as the worker's does after loading and then when idle (Inbetweener.warmUp,
// WARM_UP_ROUNDS, `warm_up_ms`), so `first_call_ms` is a worker's first
// request at that length (one that comes after the idle rounds). After the
// first call at a length, the residual network's own plan for it is built
// and run once (`prepare_length_ms`), as the worker does when idle; the
// warm runs (`total_ms`) use it, the first call ran on the any-length plan.
// With `--candidate FILE` (a residual-network ONNX, path from the repository
// root, run with the bundled manifest), the default pipeline runs with it too,
// alternately with the bundled network in the same reps (`candidate_total_ms`,
// `candidate_ran`): a network's speed is judged against the bundled one in one
// run (train/README.md's bundle rules).
// `fill_60_frames_in_512`: Inbetweener.fillGaps on a 60-frame gap of a 512-frame clip
// (the default method and the Hermite curve), best of reps after a first call;
// `fill_30_frames_in_512` the same on a 30-frame gap (the short-gap or gap-filling network's band).
// `partial_keys`: root-only keys at the same frames (each pose key's root
// position), by the conditional network (`cond`, issue 47: at most 150 ms at
// 2,048 frames) and by the generator pipeline (`generator`, what `model` runs
// for them while the conditional network is not the default), side by side in
// the same reps through synthesizeRequest, as the npm worker sends them; with
// the DNA network in models/onnx, the same keys with Motion DNA too (`cond-dna`).
// Prints JSON. Usage: node tests/web/bench_page.mjs [--smoke] [--candidate FILE]
import { withBenchPage } from './chromium.mjs';

const smoke = process.argv.includes('--smoke');
const ci = process.argv.indexOf('--candidate');
const candidate = ci > 0 ? process.argv[ci + 1] : null;
if (ci > 0 && !candidate) throw new Error('--candidate needs an ONNX file (a path from the repository root)');
const sizes = smoke ? [512] : [512, 1024, 2048, 4096];
await withBenchPage(async (page) => {
  const result = await page.evaluate(async ({ sizes, reps, candidate }) => {
    // the worker's wasm (web/worker.js startWasm): relaxed SIMD where it validates
    const { hasRelaxedSimd, WARM_UP_ROUNDS } = await import('./lib/wasm-features.js');
    const wasm = hasRelaxedSimd() ? 'relaxed-simd' : 'simd128';
    const m = await import('./pkg-core/deeprep.js');
    await m.default(wasm === 'relaxed-simd' ? { module_or_path: './pkg-core/deeprep_relaxed_bg.wasm' } : undefined);
    // a second instance of the glue (the query makes it another module) with the plain build
    const plain = await import('./pkg-core/deeprep.js?simd128');
    await plain.default();
    const fetchOk = async (u) => {
      const r = await fetch(u);
      if (!r.ok) throw new Error(`${u}: HTTP ${r.status}`);
      return r;
    };
    const get = async (u) => new Uint8Array(await (await fetchOk(u)).arrayBuffer());
    const text = async (u) => (await fetchOk(u)).text();
    // every file once; each Inbetweener copies what it is given
    const [gen, path, genManifest, residual, residualManifest, cond, condManifest] = await Promise.all([
      get('../models/onnx/tween_generator.onnx'), get('../models/onnx/tween_path.onnx'),
      text('../models/onnx/tween_generator.manifest.json'), get('../models/onnx/tween_residual.onnx'),
      text('../models/onnx/tween_residual.manifest.json'), get('../models/onnx/tween_cond.onnx'),
      text('../models/onnx/tween_cond.manifest.json')]);
    // an Inbetweener of the glue `mod`, with the residual network `res` when given
    const inbetweener = (mod, res) => {
      const ib = new mod.Inbetweener(gen, path, genManifest);
      if (res) ib.setResidual(res, residualManifest);
      return ib;
    };
    const model = inbetweener(m);
    // the same models prepared for any length, as the npm worker runs them
    const anyLength = inbetweener(m);
    anyLength.prepareAnyLength();
    // the default for whole-pose keys: the residual network (as the npm worker loads it)
    const withResidual = inbetweener(m, residual);
    const residualDefault = withResidual.residualIsDefault;
    withResidual.setCond(cond, condManifest);
    // the DNA network, where the models folder has it (requests with Motion DNA)
    const dnaFiles = await Promise.all(['onnx', 'manifest.json'].map((x) => fetch(`../models/onnx/tween_cond_dna.${x}`)));
    if (dnaFiles.every((r) => r.ok)) {
      withResidual.setCondDna(new Uint8Array(await dnaFiles[0].arrayBuffer()), await dnaFiles[1].text());
    }
    // the long-gap filling network, where the models folder has it (the default fill of a 60-frame gap)
    const longFiles = await Promise.all(['onnx', 'manifest.json'].map((x) => fetch(`../models/onnx/tween_fill_long.${x}`)));
    if (longFiles.every((r) => r.ok)) {
      withResidual.setFillLong(new Uint8Array(await longFiles[0].arrayBuffer()), await longFiles[1].text());
    }
    // the gap-filling and short-gap fill networks likewise (the default fill of a 30-frame gap)
    for (const [name, set] of [['tween_fill', 'setFill'], ['tween_fill_mlp', 'setFillMlp']]) {
      const files = await Promise.all(['onnx', 'manifest.json'].map((x) => fetch(`../models/onnx/${name}.${x}`)));
      if (files.every((r) => r.ok)) withResidual[set](new Uint8Array(await files[0].arrayBuffer()), await files[1].text());
    }
    const plainResidual = inbetweener(plain, residual);
    const cand = candidate ? inbetweener(m, await get(`../${candidate}`).catch((e) => {
      throw new Error(`--candidate ${e.message}`);
    })) : null;
    const poses = (await fetch('../models/examples/poses.json').then((r) => r.json())).poses;
    const t0 = performance.now();
    // the worker's warm-up: before it reports ready, then when idle
    withResidual.warmUp(WARM_UP_ROUNDS.beforeReady, true);
    withResidual.warmUp(WARM_UP_ROUNDS.whenIdle, false);
    const warmUpMs = performance.now() - t0;
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
      const firstResult = withResidual.synthesize(kf, kc, n, { post: true });
      const resFirst = performance.now() - t;
      const ran = firstResult.method;
      firstResult.free();
      plainResidual.synthesize(kf, kc, n, { post: true }).free();
      // then, as the worker does when idle after a residual synthesis, the network's
      // own plan for this length, which the warm runs below use
      t = performance.now();
      const prepared = withResidual.prepareLength(n);
      const prepareMs = performance.now() - t;
      plainResidual.prepareLength(n);
      let candRan = null, candBest = null;
      if (cand) {
        const c = cand.synthesize(kf, kc, n, { post: true });
        candRan = c.method;
        c.free();
        cand.prepareLength(n);
        candBest = Infinity;
      }
      let resBest = Infinity, resNet = null, plainBest = Infinity, bvhMs = Infinity;
      for (let r = 0; r < reps; r++) {
        t = performance.now();
        const res = withResidual.synthesize(kf, kc, n, { post: true });
        const total = performance.now() - t;
        if (total < resBest) { resBest = total; resNet = res.times[0]; }
        t = performance.now();
        if (!res.bvh.startsWith('HIERARCHY')) throw new Error('no BVH text');
        bvhMs = Math.min(bvhMs, performance.now() - t);
        res.free();
        t = performance.now();
        plainResidual.synthesize(kf, kc, n, { post: true }).free();
        plainBest = Math.min(plainBest, performance.now() - t);
        if (cand) {
          t = performance.now();
          cand.synthesize(kf, kc, n, { post: true }).free();
          candBest = Math.min(candBest, performance.now() - t);
        }
      }
      // root-only keys: the conditional network and the generator pipeline, alternately
      const rootKeys = frames.map((f, i) => ({ frame: f, root: Array.from(kc.subarray(i * (kc.length / frames.length), i * (kc.length / frames.length) + 3)) }));
      const partial = {};
      // with the DNA network: the same keys with Motion DNA (one pose per 180 frames), method 'cond'
      const dna = Array.from({ length: Math.max(1, Math.floor(n / 180)) }, (_, i) => poses[(i + 1) % poses.length].channels);
      const partialMethods = withResidual.hasCondDna ? ['cond', 'generator', 'cond-dna'] : ['cond', 'generator'];
      const partialRequest = (method) => JSON.stringify(method === 'cond-dna'
        ? { frames: n, keys: rootKeys, method: 'cond', dna } : { frames: n, keys: rootKeys, method });
      for (const method of partialMethods) {
        const req = partialRequest(method);
        t = performance.now();
        const r = withResidual.synthesizeRequest(req);
        partial[method] = { first_call_ms: performance.now() - t, ran: r.method, total_ms: Infinity };
        r.free();
      }
      for (let r = 0; r < reps; r++) {
        for (const method of partialMethods) {
          const req = partialRequest(method);
          t = performance.now();
          withResidual.synthesizeRequest(req).free();
          partial[method].total_ms = Math.min(partial[method].total_ms, performance.now() - t);
        }
      }
      t = performance.now();
      const slerpResult = model.interpolate(kf, kc, n);
      if (!slerpResult.bvh.startsWith('HIERARCHY')) throw new Error('no BVH text');
      slerpResult.free();
      const slerp = performance.now() - t;
      out.push({ frames: n, total_ms: resBest, first_call_ms: resFirst, wasm, simd128_total_ms: plainBest, bvh_ms: bvhMs,
                 prepare_length_ms: prepared ? prepareMs : null,
                 default_method: residualDefault ? 'residual' : 'generator', ran,
                 residual_network_ms: residualDefault ? resNet : null,
                 generator_pipeline: { generator_ms: best[0], rcfk_ms: best[1], path_ms: best[2], post_ms: best[3],
                                       total_ms: bestTotal, first_call_ms: first,
                                       any_length_first_call_ms: anyFirst, any_length_total_ms: anyBest },
                 slerp_lerp_ms_with_bvh_and_fk: slerp, partial_keys: partial,
                 ...(cand ? { candidate_total_ms: candBest, candidate_ran: candRan } : {}) });
    }
    // a 60-frame gap filled in a 512-frame clip (issue 50: under 20 ms), with the default
    // (the network for gaps over 45 frames) and the Hermite curve; the BVH text written
    const fk = new Uint32Array([0, 240, 480]);
    const fc = new Float32Array([0, 1, 2].flatMap((i) => { const c = poses[i % poses.length].channels.slice(); c[0] = 30 * i; return c; }));
    const base = withResidual.synthesize(fk, fc, 512, { post: true });
    const clipBytes = new TextEncoder().encode(base.bvh);
    base.free();
    const fill = {}, fill30 = {};
    for (const [out, gap] of [[fill, [200, 259]], [fill30, [200, 229]]]) {
      for (const method of ['model', 'hermite']) {
        let best = Infinity, ran = null;
        for (let r = 0; r <= reps; r++) {
          const t = performance.now();
          const f = withResidual.fillGaps(clipBytes, new Uint32Array(gap), method);
          const ms = performance.now() - t;
          if (r > 0) best = Math.min(best, ms); // the first call builds the plan for its length
          ran = f.method;
          f.free();
        }
        out[method] = { ms: best, ran };
      }
    }
    // which matrix kernel the worker's build ran products with (runtime::matmul_kernel)
    return { rows: out, warmUpMs, fill, fill30, matmulKernel: JSON.parse(m.OnnxModel.matmulKernel()) };
  }, { sizes, reps: smoke ? 1 : 3, candidate });
  console.log(JSON.stringify({ bench: 'inbetween', target: 'wasm (headless Chromium, SwiftShader, 1 thread)',
    ...(candidate ? { candidate } : {}), warm_up_ms: result.warmUpMs, matmul_kernel: result.matmulKernel,
    fill_60_frames_in_512: result.fill, fill_30_frames_in_512: result.fill30, rows: result.rows }, null, 1));
});
