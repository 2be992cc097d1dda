// A Promise API over the synthesis worker, with progress callbacks.
//   const c = await DeeprepClient.create();   // the models shipped in the package
//   const c = await DeeprepClient.create({ modelBase: '../models/onnx', onProgress });
//   (modelBase is resolved against the page; or models: { generator, path, manifest } as bytes/text)
//   const r = await c.synthesize({ keyFrames, keyChannels, frames, post: true, dna: [], method: 'model', variation: 1 });
//   (variation, optional, in [0, 2]: share of the networks' departure from SLERP+LERP kept, pose and
//   root path; 1 = the networks as trained, 0 = SLERP+LERP; absent = c.defaultVariation,
//   the model's own default)
//   const clip = await c.importBvh(bytes);   // parsed and checked in the worker, never on the page
//
// Every rejection is a DeeprepError with a `code`:
//   E_MODEL_LOAD  the models could not be fetched or read
//   E_BAD_BVH     a BVH file is malformed or not on the model's skeleton
//   E_BAD_KEYS    keys or options of a synthesis request are invalid
//   E_BAD_INPUT   other invalid input (IK positions, joint angles)
//   E_WASM_TRAP   the wasm instance trapped (a bug in deeprep); the client has
//                 already started a fresh worker, so later calls work
//   E_WORKER      the worker could not start
//   E_ABORTED     the call's AbortSignal fired (the worker is replaced, since
//                 wasm cannot be interrupted mid-call)
//   E_TERMINATED  the client was terminated while the call was pending
//
// Every call takes an optional { signal } (an AbortSignal) as its last argument.

import { WorkerChannel } from './lib/workers.js';

/** An error from deeprep, with a machine-readable `code`. */
export class DeeprepError extends Error {
  constructor(code, message) {
    super(message);
    this.name = 'DeeprepError';
    this.code = code;
  }
}

/** A worker_threads Worker behind the Web Worker interface WorkerChannel uses. */
function nodeWorker(NodeWorker, url) {
  const w = new NodeWorker(url);
  return {
    postMessage: (message, transfer) => w.postMessage(message, transfer),
    terminate: () => { w.terminate(); },
    set onmessage(f) { w.removeAllListeners('message'); w.on('message', (data) => f({ data })); },
    set onerror(f) { w.removeAllListeners('error'); w.on('error', (e) => f({ message: e?.message || String(e), type: 'error' })); },
  };
}

export class DeeprepClient {
  static async create({ modelBase, models, workerUrl, wasm, onProgress = () => {} } = {}) {
    const c = new DeeprepClient();
    // Relative to the page, not to the worker's own URL (in Node: to the working directory).
    const page = globalThis.document?.baseURI ?? globalThis.location?.href
      ?? (globalThis.process?.cwd ? `file://${globalThis.process.cwd().replace(/\\/g, '/')}/` : undefined);
    c.modelBase = modelBase ? new URL(String(modelBase), page).href : undefined;
    c.models = models;
    c.onProgress = onProgress;
    // The worker is written inline, so bundlers (Vite, webpack 5) see it and
    // bundle it with the wasm it imports; `workerUrl` overrides. Loaded from
    // another origin (a CDN), the browser refuses that worker: a same-origin
    // Blob module that imports it takes its place. The protocol, trap
    // recovery and aborts are web/lib/workers.js's, shared with the pages.
    // Node 20+: the same worker on worker_threads (node-worker.js gives it
    // the Web Worker globals and reads the package's files)
    let NodeWorker = null;
    if (typeof Worker === 'undefined') {
      if (!globalThis.process?.versions?.node) {
        throw new DeeprepError('E_WORKER', 'this environment has neither Web Workers nor Node\'s worker_threads: DeeprepClient cannot start its worker here');
      }
      const threads = 'node:worker_threads'; // not a literal: bundlers leave it alone
      try {
        ({ Worker: NodeWorker } = await import(/* webpackIgnore: true */ /* @vite-ignore */ threads));
      } catch (e) {
        throw new DeeprepError('E_WORKER', `Node's worker_threads could not be loaded: ${e?.message || e}`);
      }
    }
    const nodeWorkerUrl = () => new URL(['.', 'node-worker.js'].join('/'), import.meta.url);
    const tried = workerUrl ? new URL(String(workerUrl), page).href : (NodeWorker ? nodeWorkerUrl() : new URL('./worker.js', import.meta.url)).href;
    const make = () => {
      if (NodeWorker) return nodeWorker(NodeWorker, new URL(tried));
      try {
        return workerUrl ? new Worker(tried, { type: 'module' }) : new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
      } catch (e) {
        if (e?.name !== 'SecurityError') throw e;
        const blob = new Blob([`import ${JSON.stringify(tried)};`], { type: 'text/javascript' });
        return new Worker(URL.createObjectURL(blob), { type: 'module' });
      }
    };
    try {
      c.channel = new WorkerChannel(make, {
        onProgress: (m) => c.onProgress(m),
        error: (code, message) => new DeeprepError(code, message),
        describeError: (e) => `the worker ${tried} could not start (${e.message || e.type}): serve the package's `
          + 'worker.js, core/, lib/ and models/ together, or pass DeeprepClient.create({ workerUrl, modelBase }) '
          + 'where your bundler put them (README: bundlers and CDNs)',
      });
    } catch (e) {
      throw new DeeprepError('E_WORKER', `the worker ${tried} could not be created: ${e?.message || e}`);
    }
    let info;
    try {
      info = await c.channel.request({ type: 'init', modelBase: c.modelBase, models, wasm });
    } catch (e) {
      c.channel.terminate();
      throw e; // E_WORKER when the worker could not start
    }
    if (!info.hasModel) {
      c.channel.terminate();
      throw new DeeprepError('E_MODEL_LOAD', `the in-betweening models could not be loaded: ${info.modelError}`);
    }
    c.skeletonBvh = info.skeletonBvh;
    c.skeleton = info.skeleton; // { names, parents (-1: root), offsets (joints x 3) }
    c.hasModel = info.hasModel;
    c.hasResidual = info.hasResidual; // method 'residual' (the supervised residual network) is available
    c.hasCond = info.hasCond; // method 'cond' (the conditional network: whole-pose, root-only, 2-D keys) is available
    c.condDna = info.condDna === true; // ... and it takes Motion DNA (`dna` with method 'cond': the DNA network, tween_cond_dna)
    c.hasFill = info.hasFill === true; // the gap-filling network (fillGaps' method 'fill', and 'model' on the gaps its manifest gives it)
    c.hasFillLong = info.hasFillLong === true; // the long-gap filling network (method 'fill-long', and 'model' on its band)
    c.hasFillMlp = info.hasFillMlp === true; // a short-gap fill network given in create's models (method 'fill-mlp', and 'model' on its band, first)
    // each gap-filling network's band of the 'model' fill's gap lengths ([from, to] or null), tried in this order
    c.fillBands = info.fillBands || { 'fill-mlp': null, fill: null, 'fill-long': null };
    c.defaultVariation = info.defaultVariation;
    c.modelError = info.modelError;
    c.wasm = info.wasm; // the wasm build the worker runs: 'relaxed-simd' or 'simd128'
    return c;
  }

  /** How many times the worker was replaced (after a trap or an abort). */
  get restarts() { return this.channel.restarts; }

  request(msg, transfer = [], { signal } = {}) { return this.channel.request(msg, transfer, { signal }); }

  /** In-betweening (or SLERP+LERP with method 'slerp'); `opts.signal` aborts it. */
  synthesize({ signal, ...opts }) { return this.request({ type: 'synthesize', ...opts }, [], { signal }); }
  /** One call from a user's clip to motion (the CLI's `--from-bvh --keys`): `bvh` is BVH
   * text or bytes at any frame rate, on the model's skeleton or another humanoid's (retargeted
   * onto the model's and back); `keys` are frames of that clip. Resolves with the whole clip
   * (its frame rate, length and skeleton), the span between the first and last key synthesized. */
  synthesizeFromBvh(bvh, { keys, method = 'model', post = true, variation, footLock, signal } = {}) {
    const bytes = typeof bvh === 'string' ? new TextEncoder().encode(bvh) : new Uint8Array(bvh).slice();
    return this.request({ type: 'synthesizeFromBvh', bytes: bytes.buffer, keys: Array.from(keys || []), method, post, variation, footLock },
                        [bytes.buffer], { signal });
  }
  /** Fills gaps in captured motion: `bvh` is BVH text or bytes (the model's skeleton or another
   * humanoid's, any frame rate), `gaps` a list of { start, end } (inclusive frames of the clip).
   * Each gap is synthesized from `context.before` frames before it and `context.after` after it
   * (defaults 20 and 1) by `method` ('model', 'fill-mlp', 'fill', 'fill-long', 'residual', 'cond', 'slerp', 'zerovel'
   * or 'hermite');
   * every other frame comes back exactly as it was. Bad ranges (reversed, outside the clip,
   * overlapping, touching the clip's ends) reject with E_BAD_INPUT. */
  fillGaps(bvh, gaps, { method = 'model', context = {}, signal } = {}) {
    const bytes = typeof bvh === 'string' ? new TextEncoder().encode(bvh) : new Uint8Array(bvh).slice();
    const pairs = (gaps || []).flatMap((g) => [g.start, g.end]);
    return this.request({ type: 'fillGaps', bytes: bytes.buffer, gaps: pairs, method, before: context.before, after: context.after },
                        [bytes.buffer], { signal });
  }
  /** A humanoid clip (BVH text or bytes) retargeted onto the model's skeleton (`to: 'model'`, the
   * default) or onto the skeleton of `to` (BVH text or bytes); `map` replaces roles found by name
   * ({ leftShin: 'Knee_L' }). Resolves with BVH text at the clip's frame rate. */
  retarget(bvh, { to = 'model', map, signal } = {}) {
    const asBytes = (b) => (typeof b === 'string' ? new TextEncoder().encode(b) : new Uint8Array(b).slice());
    const bytes = asBytes(bvh);
    const target = to === 'model' ? null : asBytes(to);
    const transfer = target ? [bytes.buffer, target.buffer] : [bytes.buffer];
    return this.request({ type: 'retarget', bytes: bytes.buffer, target: target && target.buffer, map: map ? JSON.stringify(map) : undefined },
                        transfer, { signal }).then((m) => m.bvh);
  }
  /** Parses BVH bytes in the worker; a clip on another humanoid skeleton is retargeted onto the
   * model's (`retargetedFrom` says from what), anything else rejects with E_BAD_BVH:
   * resolves with { jointNames, channelCount, frameTime, frameCount, motion, positions, bvh }. */
  importBvh(bytes, { signal } = {}) {
    const copy = new Uint8Array(bytes).slice();
    return this.request({ type: 'importBvh', bytes: copy.buffer }, [copy.buffer], { signal });
  }
  /** IK from joint positions: `positions` is frames x joints x 3 (global, the skeleton's joint order). */
  ik(positions, frames) { return this.request({ type: 'ik', positions: Array.from(positions), frames }); }
  rcAngles(channels, joint) { return this.request({ type: 'rcAngles', channels, joint }).then((m) => m.angles); }
  setRcAngles(channels, joint, angles) { return this.request({ type: 'setRcAngles', channels, joint, angles }).then((m) => m.channels); }
  /** Stops the worker; pending calls reject with E_TERMINATED. */
  terminate() { this.channel.terminate(); }
}
