// deeprep synthesis worker: loads the wasm package and the in-betweening
// models off the main thread, and answers requests with progress events.
//   -> {type: 'init', modelBase, models}   (modelBase: an absolute URL of a folder with the
//      model files; models: their bytes {generator, path, manifest}; neither: the copies
//      shipped beside this file in the npm package, models/)
//      wasm: 'simd128' loads the plain SIMD build even where relaxed SIMD is there (default: the fastest the browser runs)
//   <- {type: 'result', id, skeletonBvh, hasModel, defaultVariation, modelError, wasm} (the protocol of web/lib/workers.js;
//      wasm: the build that runs, 'relaxed-simd' or 'simd128')
//   -> {type: 'synthesize', id, keyFrames, keyChannels, frames, post, dna, method, variation, footLock, bvh}
//      (bvh: false: the result's bvh is '', its text not written)
//      or {type: 'synthesize', id, keys, frames, ...}: keys of any kind (pose, root, xy; motion::keys)
//   <- {type: 'progress', id, stage, fraction}  ...  {type: 'result', id, method, ran, ...} | {type: 'error', id, message}
//      (ran: the method that made the motion, 'residual', 'generator' or 'slerp')
//   -> {type: 'rcAngles', id, channels, joint} / {type: 'setRcAngles', id, channels, joint, angles}
//   -> {type: 'ik', id, positions, frames}   (IK from joint positions; the IK model loads on first use)
//   -> {type: 'importBvh', id, bytes}        (parse a user's file here, never on the page; another
//      humanoid skeleton is retargeted onto the model's: the result's retargetedFrom says from what)
//   -> {type: 'synthesizeFromBvh', id, bytes, keys, method, post, variation, footLock}
//   -> {type: 'fillGaps', id, bytes, gaps ([start, end, ...]), method, before, after}
//   -> {type: 'retarget', id, bytes, target (bytes or null: the model's skeleton), map (JSON or undefined)}
//   <- {type: 'result', id, bvh}
//   <- {type: 'error', id, code, message, trapped}: trapped when the wasm instance
//      hit a RuntimeError (a deeprep bug); the client then replaces this worker.
// the package without the GPU code (web/pkg-core): a smaller download
import init, { Inbetweener, IkSolver, BvhClip, maxGap } from './pkg-core/deeprep.js';
import { hasRelaxedSimd, WARM_UP_ROUNDS } from './lib/wasm-features.js';

/** Starts the wasm: the relaxed-SIMD build (issue 23: tract's matrix kernel
 *  fuses its multiply-adds, about 15% off the in-betweening network) where the
 *  browser has relaxed SIMD and `wasm` does not ask for 'simd128', else the
 *  plain SIMD build, which is also the fallback when the relaxed file cannot
 *  be loaded. Returns the build that runs. */
async function startWasm(wasm) {
  if (wasm !== 'simd128' && hasRelaxedSimd()) {
    try {
      await init({ module_or_path: new URL('./pkg-core/deeprep_relaxed_bg.wasm', import.meta.url) });
      return 'relaxed-simd';
    } catch (e) {
      console.warn(`deeprep: the relaxed-SIMD build did not load (${e.message || e}); using plain SIMD`);
    }
  }
  await init();
  return 'simd128';
}
let wasmBuild = null;

let model = null;
let ik = null;
let skeletonNames = null;
let residualManifest = null;
let condManifest = null;
// the conditional network's manifest makes it the model for gaps over
// maxGap() / for root paths (motion::plan)
let condForLongGaps = false;
let condForRootKeys = false;
// whether it takes Motion DNA (its manifest's `dna`)
let condDna = false;
// the DNA network (tween_cond_dna: a conditional network trained with Motion
// DNA, for requests with DNA), loaded on the first request with DNA that it
// serves: method 'cond', or 'model' when its manifest says default_for_dna
let condDnaManifest = null;
let condDnaForModel = false;
// the gap-filling networks' manifests (issue 50) and the gap lengths the
// `model` fill gives each ([fill_from, fill_up_to]; motion::fill::method_for):
// 'fill-mlp' (tween_fill_mlp, the short-gap network over a gap's edges),
// 'fill' (tween_fill) and 'fill-long' (tween_fill_long, a residual network)
let fillMlpRange = null;
let fillManifest = null;
let fillRange = null;
let fillLongManifest = null;
let fillLongRange = null;

/** A gap-filling manifest's band [fill_from, fill_up_to], or null. */
function bandOf(manifest) {
  try {
    const m = JSON.parse(manifest);
    return Number.isInteger(m?.fill_up_to) ? [m.fill_from ?? 1, m.fill_up_to] : null;
  } catch { return null; }
}

/** A gap-filling network at init: loaded now where msg.models gives its bytes
 * (`key`, and `${key}Manifest` its manifest's text), else its manifest (the
 * promise `fetched`) kept for the first request that runs it, where it gives a
 * band. Resolves to [manifest kept or null, band or null]. */
async function bandedAtInit(msg, key, set, fetched) {
  if (msg.models?.[key]) {
    set(new Uint8Array(msg.models[key]), msg.models[`${key}Manifest`]);
    return [null, bandOf(msg.models[`${key}Manifest`])];
  }
  const manifest = await fetched;
  const band = bandOf(manifest);
  return [band ? manifest : null, band];
}

/** The gap-filling network the `model` fill gives a gap of `len` frames
 * (motion::fill::method_for's order: 'fill-mlp', 'fill', 'fill-long', each
 * on its manifest's band), or null where none does. */
function fillNetworkFor(len) {
  const inside = (r) => r && len >= r[0] && len <= r[1];
  if (inside(fillMlpRange)) return 'fill-mlp';
  if (inside(fillRange)) return 'fill';
  if (inside(fillLongRange)) return 'fill-long';
  return null;
}

/** Whether a fillGaps request runs the gap-filling network `name` ('fill-mlp',
 * 'fill' or 'fill-long'), so that it is loaded first: that method, or
 * 'model' with a gap (its length: frames inside it) that fillNetworkFor
 * gives it. */
function needsFill(msg, name) {
  const method = msg.method || 'model';
  if (method === name) return true;
  if (method !== 'model' || !Array.isArray(msg.gaps)) return false;
  for (let i = 0; i + 1 < msg.gaps.length; i += 2) {
    if (fillNetworkFor(msg.gaps[i + 1] + 1 - msg.gaps[i]) === name) return true;
  }
  return false;
}

/** Whether a request gives Motion DNA (flat channels or pose rows). */
function hasDna(msg) {
  return msg.type === 'synthesize' && msg.dna != null && msg.dna.length > 0;
}

/** Whether the planner may run the DNA network for `msg`, so that it is loaded first. */
function needsCondDna(msg) {
  const method = msg.method ?? 'model';
  return hasDna(msg) && (method === 'cond' || (method === 'model' && condDnaForModel));
}

/** Whether the planner may run the conditional network for a `model`
 * request, so that it is loaded first: a gap over maxGap() frames when its
 * manifest says default_for_long_gaps, a root-only key when it says
 * default_for_root_keys (the core checks the rest: whole poses, no DNA). */
function needsCond(msg) {
  if ((msg.method ?? 'model') !== 'model') return false;
  const objects = msg.type === 'synthesize' && Array.isArray(msg.keys) ? msg.keys : null;
  if (condForRootKeys && objects?.some((k) => k && k.root && !k.xy && !k.channels)) return true;
  if (!condForLongGaps) return false;
  const frames = objects ? objects.map((k) => k?.frame)
    : msg.type === 'synthesize' ? Array.from(msg.keyFrames || [])
      : msg.type === 'synthesizeFromBvh' ? Array.from(msg.keys || []) : [];
  const sorted = frames.filter(Number.isFinite).sort((a, b) => a - b);
  return sorted.some((f, i) => i > 0 && f - sorted[i - 1] > maxGap());
}

/** An Error with a deeprep error code (see client.js). */
function coded(code, message) {
  const e = new Error(message);
  e.code = code;
  return e;
}

// The code of an uncoded failure, by the request that failed.
const DEFAULT_CODE = { init: 'E_MODEL_LOAD', synthesize: 'E_BAD_KEYS', synthesizeFromBvh: 'E_BAD_BVH', importBvh: 'E_BAD_BVH', retarget: 'E_BAD_BVH', fillGaps: 'E_BAD_INPUT' };

// Where each model file is: under msg.modelBase, or the package's own copies,
// written as literal `new URL(..., import.meta.url)` so bundlers ship them.
function modelUrls(base) {
  if (base) {
    const at = (f) => `${base.replace(/\/$/, '')}/${f}`;
    return { generator: at('tween_generator.onnx'), path: at('tween_path.onnx'), manifest: at('tween_generator.manifest.json'),
             residual: at('tween_residual.onnx'), residualManifest: at('tween_residual.manifest.json'),
             cond: at('tween_cond.onnx'), condManifest: at('tween_cond.manifest.json'),
             condDna: at('tween_cond_dna.onnx'), condDnaManifest: at('tween_cond_dna.manifest.json'),
             fill: at('tween_fill.onnx'), fillManifest: at('tween_fill.manifest.json'),
             fillLong: at('tween_fill_long.onnx'), fillLongManifest: at('tween_fill_long.manifest.json'),
             ik: at('ik.onnx'), ikManifest: at('ik.manifest.json') };
  }
  return {
    generator: new URL('./models/tween_generator.onnx', import.meta.url).href,
    path: new URL('./models/tween_path.onnx', import.meta.url).href,
    manifest: new URL('./models/tween_generator.manifest.json', import.meta.url).href,
    residual: new URL('./models/tween_residual.onnx', import.meta.url).href,
    residualManifest: new URL('./models/tween_residual.manifest.json', import.meta.url).href,
    cond: new URL('./models/tween_cond.onnx', import.meta.url).href,
    condManifest: new URL('./models/tween_cond.manifest.json', import.meta.url).href,
    condDna: new URL('./models/tween_cond_dna.onnx', import.meta.url).href,
    condDnaManifest: new URL('./models/tween_cond_dna.manifest.json', import.meta.url).href,
    fill: new URL('./models/tween_fill.onnx', import.meta.url).href,
    fillManifest: new URL('./models/tween_fill.manifest.json', import.meta.url).href,
    fillLong: new URL('./models/tween_fill_long.onnx', import.meta.url).href,
    fillLongManifest: new URL('./models/tween_fill_long.manifest.json', import.meta.url).href,
    ik: new URL('./models/ik.onnx', import.meta.url).href,
    ikManifest: new URL('./models/ik.manifest.json', import.meta.url).href,
  };
}
let urls = null;

/** Fetches a file, reporting download progress (by Content-Length when the server gives it). */
async function fetchBytes(url, onBytes = () => {}) {
  const r = await fetch(url);
  if (!r.ok) throw coded('E_MODEL_LOAD', `${url}: HTTP ${r.status}`);
  if (!r.body) return new Uint8Array(await r.arrayBuffer());
  const total = Number(r.headers.get('Content-Length')) || 0;
  const parts = [];
  let got = 0;
  for (const reader = r.body.getReader(); ;) {
    const { done, value } = await reader.read();
    if (done) break;
    parts.push(value);
    got += value.length;
    onBytes(got, total);
  }
  const out = new Uint8Array(got);
  let at = 0;
  for (const p of parts) { out.set(p, at); at += p.length; }
  return out;
}

async function fetchText(url) {
  return new TextDecoder().decode(await fetchBytes(url));
}

async function handleInit(msg) {
  postMessage({ type: 'progress', id: msg.id, stage: 'compiling wasm', fraction: 0 });
  wasmBuild = await startWasm(msg.wasm);
  urls = modelUrls(msg.modelBase);
  // the optional networks' manifests (small files; null where the folder
  // lacks one, or where msg.models gives the network): all requested now,
  // beside the generator's download, each awaited where it is read
  const manifestOf = (given, url) => (given ? null : fetchText(url).catch(() => null));
  const manifests = {
    residual: manifestOf(msg.models?.residual, urls.residualManifest),
    cond: manifestOf(msg.models?.cond, urls.condManifest),
    condDna: manifestOf(msg.models?.condDna, urls.condDnaManifest),
    fill: manifestOf(msg.models?.fill, urls.fillManifest),
    fillLong: manifestOf(msg.models?.fillLong, urls.fillLongManifest),
  };
  try {
    let g, p, m;
    if (msg.models) {
      ({ generator: g, path: p, manifest: m } = msg.models);
      g = new Uint8Array(g); p = new Uint8Array(p);
    } else {
      const got = { g: [0, 0], p: [0, 0] };
      const report = (k) => (n, total) => {
        got[k] = [n, total];
        const all = got.g[1] + got.p[1];
        postMessage({ type: 'progress', id: msg.id, stage: 'downloading models', fraction: all ? (got.g[0] + got.p[0]) / all : 0 });
      };
      [g, p, m] = await Promise.all([fetchBytes(urls.generator, report('g')), fetchBytes(urls.path, report('p')), fetchText(urls.manifest)]);
    }
    postMessage({ type: 'progress', id: msg.id, stage: 'loading models', fraction: 1 });
    model = new Inbetweener(g, p, m);
    // The supervised residual network (issue 19) is optional and loads on
    // first use; its small manifest says here whether it is there.
    if (msg.models?.residual) {
      model.setResidual(new Uint8Array(msg.models.residual), msg.models.residualManifest);
    } else {
      residualManifest = await manifests.residual;
      // the residual network is the model for whole-pose keys when its
      // manifest says so: then it loads now, not on first use
      let isDefault = false;
      try { isDefault = JSON.parse(residualManifest)?.default_for_whole_pose_keys === true; } catch { /* no manifest */ }
      if (isDefault) {
        postMessage({ type: 'progress', id: msg.id, stage: 'downloading models', fraction: 1 });
        model.setResidual(await fetchBytes(urls.residual), residualManifest);
      }
    }
    // The conditional network (issue 47: whole-pose, root-only and 2-D keys)
    // likewise: now when its manifest makes it the model for partial keys;
    // when it makes it the model for long whole-pose gaps or root paths, on
    // the first request with a gap over maxGap() frames or a root-only key
    // (needsCond: most users never make one, and it is a 2 MB download);
    // else on the first request that names method 'cond'.
    if (msg.models?.cond) {
      model.setCond(new Uint8Array(msg.models.cond), msg.models.condManifest);
      try { condDna = JSON.parse(msg.models.condManifest)?.dna === true; } catch { /* setCond checked it */ }
    } else {
      condManifest = await manifests.cond;
      let isDefault = false;
      try {
        const m = JSON.parse(condManifest);
        isDefault = m?.default_for_partial_keys === true;
        condForLongGaps = m?.default_for_long_gaps === true;
        condForRootKeys = m?.default_for_root_keys === true;
        condDna = m?.dna === true;
      } catch { /* no manifest */ }
      if (isDefault) model.setCond(await fetchBytes(urls.cond), condManifest);
    }
    // The DNA network: its manifest now (a small file), its weights on the
    // first request with DNA that it serves (needsCondDna)
    if (msg.models?.condDna) {
      model.setCondDna(new Uint8Array(msg.models.condDna), msg.models.condDnaManifest);
      try { condDnaForModel = JSON.parse(msg.models.condDnaManifest)?.default_for_dna === true; } catch { /* setCondDna checked it */ }
    } else {
      condDnaManifest = await manifests.condDna;
      try { condDnaForModel = JSON.parse(condDnaManifest)?.default_for_dna === true; } catch { condDnaManifest = null; }
    }
    // The gap-filling networks (issue 50) on the first fillGaps that runs each (needsFill).
    [fillManifest, fillRange] = await bandedAtInit(msg, 'fill', (b, m) => model.setFill(b, m), manifests.fill);
    [fillLongManifest, fillLongRange] = await bandedAtInit(msg, 'fillLong', (b, m) => model.setFillLong(b, m), manifests.fillLong);
    // the short-gap fill network: none is bundled yet (docs/fill.md), so there
    // is no file to fetch; msg.models.fillMlp (bytes and manifest) loads one now
    [, fillMlpRange] = await bandedAtInit(msg, 'fillMlp', (b, m) => model.setFillMlp(b, m), Promise.resolve(null));
    // One plan for any length now, so the first synthesis of each length
    // does not wait for tract to optimize one (runtime::Model::prepare_any_shape),
    // then the code a request runs, so that the user's first is not the one
    // that brings the wasm code up to speed (Inbetweener.warmUp; more rounds
    // once ready, while no request comes: warmWhenIdle).
    postMessage({ type: 'progress', id: msg.id, stage: 'preparing models', fraction: 1 });
    model.prepareAnyLength();
    postMessage({ type: 'progress', id: msg.id, stage: 'warming up', fraction: 1 });
    model.warmUp(WARM_UP_ROUNDS.beforeReady, true);
    const skel = BvhClip.parse(model.skeletonBvh);
    skeletonNames = skel.jointNames;
    const skeleton = { names: skeletonNames, parents: Array.from(skel.parents), offsets: Array.from(skel.offsets) };
    skel.free();
    postMessage({ type: 'result', id: msg.id, skeletonBvh: model.skeletonBvh, skeleton, hasModel: true,
                  hasResidual: model.hasResidual || residualManifest !== null,
                  hasCond: model.hasCond || condManifest !== null,
                  condDna: condDna || model.hasCondDna || condDnaManifest !== null,
                  hasFill: model.hasFill || fillManifest !== null,
                  hasFillLong: model.hasFillLong || fillLongManifest !== null,
                  hasFillMlp: model.hasFillMlp,
                  fillBands: { 'fill-mlp': fillMlpRange, fill: fillRange, 'fill-long': fillLongRange },
                  defaultVariation: model.defaultVariation, wasm: wasmBuild });
    warmWhenIdle(WARM_UP_ROUNDS.whenIdle);
  } catch (e) {
    postMessage({ type: 'result', id: msg.id, skeletonBvh: null, hasModel: false, modelError: String(e.message || e), wasm: wasmBuild });
  }
}

async function handleIk(msg) {
  const { id } = msg;
  if (!ik) {
    postMessage({ type: 'progress', id, stage: 'loading the IK model', fraction: 0.1 });
    const [bytes, manifest] = await Promise.all([fetchBytes(urls.ik), fetchText(urls.ikManifest)]);
    ik = new IkSolver(bytes, manifest);
  }
  postMessage({ type: 'progress', id, stage: 'solving IK', fraction: 0.5 });
  const r = ik.solve(new Float32Array(msg.positions), msg.frames);
  const positions = r.positions;
  const channels = r.channels;
  postMessage({ type: 'result', id, bvh: r.bvh, channels, positions, meanError: r.meanError, maxError: r.maxError },
              [positions.buffer, channels.buffer]);
  r.free();
}

function importBvh(msg) {
  let clip = BvhClip.fromBytes(new Uint8Array(msg.bytes));
  let retargetedFrom = null;
  try {
    const names = clip.jointNames;
    if (skeletonNames && (names.length !== skeletonNames.length || names.some((n, i) => n !== skeletonNames[i]))) {
      // another humanoid: retargeted onto the model's skeleton (skeleton::retarget)
      let text;
      try {
        if (!model) throw new Error('the models are not loaded');
        text = model.retarget(new Uint8Array(msg.bytes));
      } catch (e) {
        throw coded('E_BAD_BVH', `its skeleton (${names.length} joints) is not the model's (${skeletonNames.length} joints), and it cannot be retargeted onto it: ${e.message || e}`);
      }
      retargetedFrom = { joints: names.length, root: names[0] };
      clip.free();
      clip = BvhClip.parse(text);
    }
    const motion = clip.motion;
    const positions = clip.fkPositions(0, clip.frameCount);
    postMessage({ type: 'result', id: msg.id, jointNames: clip.jointNames, channelCount: clip.channelCount, frameTime: clip.frameTime,
                  frameCount: clip.frameCount, motion, positions, bvh: clip.toBvh(), retargetedFrom }, [motion.buffer, positions.buffer]);
  } finally {
    clip.free();
  }
}

/** Posts a synthesis result (and frees it): BVH text ('' when the request
 * says `bvh: false`: writing it is a fifth of a long synthesis), global
 * positions, and the local tracks (translations, quaternions) that three.js
 * and glTF take. */
function postResult(id, method, r, withBvh = true) {
  const positions = r.positions, translations = r.translations, quaternions = r.quaternions;
  const times = Array.from(r.times), keyError = Array.from(r.keyError);
  const ran = r.method, frames = r.frames, variation = r.variation;
  postMessage({ type: 'result', id, method, ran, variation, bvh: withBvh ? r.bvh : '', frames, frameTime: r.frameTime, times, keyError,
                // the same numbers by name
                stages: { generatorMs: times[0], rcfkMs: times[1], pathMs: times[2], postMs: times[3] },
                keyErrors: { before: { root: keyError[0], joints: keyError[1] }, after: { root: keyError[2], joints: keyError[3] } },
                criticalFrames: Array.from(r.criticalFrames), positions, translations, quaternions },
              [positions.buffer, translations.buffer, quaternions.buffer]);
  r.free();
  if (ran === 'residual') prepareWhenIdle(frames);
}

/** After a residual synthesis of `frames` frames, once the worker is idle:
 *  the residual network's own plan for that length, built and run once
 *  (Inbetweener.prepareLength;
 *  11-18% faster than the any-length plan the first request ran on at
 *  2,048-4,096 frames, little at 1,024; 100-360 ms to build), so the next
 *  requests of that length (an animator adjusting keys) run faster. A request
 *  already queued may run before it; one that comes while it builds waits. */
function prepareWhenIdle(frames) {
  setTimeout(() => {
    try {
      model?.prepareLength(frames);
    } catch (e) {
      console.warn(`deeprep: the plan for ${frames} frames was not built (${e.message || e})`);
    }
  }, 0);
}

/** Requests received since loading; an idle warm-up round stops once one comes. */
let requestCount = 0;

/** After loading, `rounds` more warm-up rounds (Inbetweener.warmUp, ~30 ms
 *  each once warm), one task each, while no request has come: a request that
 *  comes meanwhile waits for one round at most, and ends them (it runs the
 *  code itself). */
function warmWhenIdle(rounds) {
  if (rounds <= 0) return;
  const seen = requestCount;
  setTimeout(() => {
    if (requestCount !== seen || !model) return;
    try {
      model.warmUp(1, false);
    } catch (e) {
      console.warn(`deeprep: warm-up stopped (${e.message || e})`);
      return;
    }
    warmWhenIdle(rounds - 1);
  }, 0);
}

function handle(msg) {
  const { id } = msg;
  if (msg.type === 'importBvh') { importBvh(msg); return; }
  if (!model) throw coded('E_MODEL_LOAD', 'the in-betweening models are not loaded');
  if (msg.type === 'synthesize') {
    postMessage({ type: 'progress', id, stage: msg.method === 'slerp' ? 'interpolating' : 'generator, RC-FK, path, post-processing', fraction: 0.1 });
    if (msg.keys) {
      // keys of any kind (whole pose, root only, 2-D joints): the core reads the request
      const { type, id: _, signal, bvh, ...request } = msg;
      postResult(id, msg.method, model.synthesizeRequest(JSON.stringify(request)), bvh !== false);
      return;
    }
    const kf = new Uint32Array(msg.keyFrames);
    const kc = new Float32Array(msg.keyChannels);
    const r = msg.method === 'slerp' ? model.interpolate(kf, kc, msg.frames)
      : msg.method === 'residual' ? model.residual(kf, kc, msg.frames, msg.variation)
        : model.synthesize(kf, kc, msg.frames, {
          post: msg.post ?? true, dna: new Float32Array(msg.dna || []), variation: msg.variation ?? undefined, footLock: msg.footLock ?? false,
        });
    if (msg.bvh !== false) postMessage({ type: 'progress', id, stage: 'writing BVH', fraction: 0.9 });
    postResult(id, msg.method, r, msg.bvh !== false);
  } else if (msg.type === 'synthesizeFromBvh') {
    postMessage({ type: 'progress', id, stage: 'reading the clip and synthesizing', fraction: 0.1 });
    const r = model.synthesizeFromBvh(new Uint8Array(msg.bytes), new Uint32Array(msg.keys), msg.method || 'model',
                                      msg.post ?? true, msg.variation, msg.footLock);
    postResult(id, msg.method || 'model', r);
  } else if (msg.type === 'fillGaps') {
    postMessage({ type: 'progress', id, stage: 'filling gaps', fraction: 0.1 });
    const gaps = msg.gaps.map((v) => {
      if (!Number.isInteger(v) || v < 0 || v > 0xffffffff) throw coded('E_BAD_INPUT', `a gap's frame must be a non-negative integer, found ${v}`);
      return v;
    });
    const r = model.fillGaps(new Uint8Array(msg.bytes), new Uint32Array(gaps), msg.method || 'model', msg.before, msg.after);
    postResult(id, msg.method || 'model', r);
  } else if (msg.type === 'retarget') {
    const bvh = model.retarget(new Uint8Array(msg.bytes), msg.target ? new Uint8Array(msg.target) : undefined, msg.map);
    postMessage({ type: 'result', id, bvh });
  } else if (msg.type === 'rcAngles') {
    postMessage({ type: 'result', id, angles: Array.from(model.rcAngles(new Float32Array(msg.channels), msg.joint)) });
  } else if (msg.type === 'setRcAngles') {
    postMessage({ type: 'result', id, channels: Array.from(model.setRcAngles(new Float32Array(msg.channels), msg.joint, new Float64Array(msg.angles))) });
  } else {
    throw coded('E_BAD_INPUT', `unknown request '${msg.type}'`);
  }
}

/** The networks that load on first use: each one's manifest was fetched at
 * init (null where the models folder lacks it), its weights are fetched
 * before the first request that runs it (`runs`), with a progress stage. */
function lazyNetworks() {
  return [
    { name: 'the residual network', has: () => model.hasResidual, manifest: residualManifest, url: urls.residual,
      set: (b, m) => model.setResidual(b, m), runs: (msg) => msg.type === 'synthesize' && msg.method === 'residual' },
    { name: 'the conditional network', has: () => model.hasCond, manifest: condManifest, url: urls.cond,
      set: (b, m) => model.setCond(b, m),
      runs: (msg) => ['synthesize', 'synthesizeFromBvh', 'fillGaps'].includes(msg.type) && (msg.method === 'cond' || needsCond(msg)) },
    { name: 'the Motion DNA network', has: () => model.hasCondDna, manifest: condDnaManifest, url: urls.condDna,
      set: (b, m) => model.setCondDna(b, m), runs: needsCondDna },
    { name: 'the gap-filling network', has: () => model.hasFill, manifest: fillManifest, url: urls.fill,
      set: (b, m) => model.setFill(b, m), runs: (msg) => msg.type === 'fillGaps' && needsFill(msg, 'fill') },
    { name: 'the long-gap filling network', has: () => model.hasFillLong, manifest: fillLongManifest, url: urls.fillLong,
      set: (b, m) => model.setFillLong(b, m), runs: (msg) => msg.type === 'fillGaps' && needsFill(msg, 'fill-long') },
  ];
}

/** Fetches and loads every lazy network `msg` runs that is not loaded yet. */
async function loadWhatRuns(msg) {
  for (const n of lazyNetworks()) {
    if (n.manifest && !n.has() && n.runs(msg)) {
      postMessage({ type: 'progress', id: msg.id, stage: `loading ${n.name}`, fraction: 0.05 });
      n.set(await fetchBytes(n.url), n.manifest);
    }
  }
}

onmessage = async (e) => {
  const msg = e.data;
  if (msg.type !== 'init') requestCount++;
  try {
    if (model) await loadWhatRuns(msg);
    if (msg.type === 'init') await handleInit(msg);
    else if (msg.type === 'ik') await handleIk(msg);
    else handle(msg);
  } catch (err) {
    const trapped = err instanceof WebAssembly.RuntimeError;
    const code = trapped ? 'E_WASM_TRAP' : (err && err.code) || DEFAULT_CODE[msg.type] || 'E_BAD_INPUT';
    postMessage({ type: 'error', id: msg.id, code, trapped, message: String(err && err.message ? err.message : err) });
  }
};
