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

/** An error from deeprep, with a machine-readable `code`. */
export class DeeprepError extends Error {
  constructor(code, message) {
    super(message);
    this.name = 'DeeprepError';
    this.code = code;
  }
}

export class DeeprepClient {
  static async create({ modelBase, models, workerUrl, onProgress = () => {} } = {}) {
    const c = new DeeprepClient();
    // Relative to the page, not to the worker's own URL.
    const page = globalThis.document?.baseURI ?? globalThis.location?.href;
    c.modelBase = modelBase ? new URL(String(modelBase), page).href : undefined;
    c.models = models;
    c.workerUrl = workerUrl;
    c.onProgress = onProgress;
    c.pending = new Map();
    c.nextId = 1;
    c.restarts = 0;
    const info = await c.start();
    if (!info.hasModel) {
      c.worker.terminate();
      throw new DeeprepError('E_MODEL_LOAD', `the in-betweening models could not be loaded: ${info.modelError}`);
    }
    c.skeletonBvh = info.skeletonBvh;
    c.skeleton = info.skeleton; // { names, parents (-1: root), offsets (joints x 3) }
    c.hasModel = info.hasModel;
    c.hasResidual = info.hasResidual; // method 'residual' (the supervised residual network) is available
    c.defaultVariation = info.defaultVariation;
    c.modelError = info.modelError;
    return c;
  }

  /** Starts a worker and loads the models in it; resolves with its 'ready' message. */
  start() {
    // Written inline, so bundlers (Vite, webpack 5, esbuild-based tools) see
    // the worker and bundle it with the wasm it imports. `workerUrl` overrides.
    const worker = this.workerUrl
      ? new Worker(this.workerUrl, { type: 'module' })
      : new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
    this.worker = worker;
    this.ready = new Promise((resolve, reject) => {
      worker.onerror = (e) => reject(new DeeprepError('E_WORKER', `worker failed to start: ${e.message || e.type}`));
      worker.onmessage = (e) => {
        const m = e.data;
        if (m.type === 'ready') { resolve(m); return; }
        if (m.type === 'progress') { this.onProgress(m); return; }
        const p = this.pending.get(m.id);
        if (m.type === 'error' && m.trapped) this.restart(m.id, 'E_WASM_TRAP', `the worker trapped during another call: ${m.message}`);
        if (!p) return;
        this.pending.delete(m.id);
        if (m.type === 'error') p.reject(new DeeprepError(m.code || 'E_BAD_INPUT', m.message)); else p.resolve(m);
      };
    });
    worker.postMessage({ type: 'init', modelBase: this.modelBase, models: this.models });
    return this.ready;
  }

  /** Replaces the worker (after a trap, or to abort a call: wasm cannot be
   * interrupted): calls queued on the old one, except `keep`, fail with
   * `code`, and a fresh worker serves the calls that follow. */
  restart(keep, code, message) {
    this.worker.terminate();
    this.restarts++;
    for (const [id, p] of [...this.pending]) {
      if (id === keep) continue;
      this.pending.delete(id);
      p.reject(new DeeprepError(code, message));
    }
    this.start().catch(() => {});
  }

  async request(msg, transfer = [], { signal } = {}) {
    if (signal?.aborted) throw new DeeprepError('E_ABORTED', 'aborted before it started');
    await this.ready;
    if (signal?.aborted) throw new DeeprepError('E_ABORTED', 'aborted before it started');
    const id = this.nextId++;
    return new Promise((resolve, reject) => {
      const onAbort = () => {
        if (!this.pending.has(id)) return;
        this.pending.delete(id);
        reject(new DeeprepError('E_ABORTED', 'aborted'));
        this.restart(id, 'E_ABORTED', 'aborted with another call (the worker was replaced)');
      };
      const done = (f) => (v) => { signal?.removeEventListener('abort', onAbort); f(v); };
      this.pending.set(id, { resolve: done(resolve), reject: done(reject) });
      signal?.addEventListener('abort', onAbort, { once: true });
      this.worker.postMessage({ ...msg, id }, transfer);
    });
  }

  /** In-betweening (or SLERP+LERP with method 'slerp'); `opts.signal` aborts it. */
  synthesize({ signal, ...opts }) { return this.request({ type: 'synthesize', ...opts }, [], { signal }); }
  /** One call from a user's clip to motion (the CLI's `--from-bvh --keys`): `bvh` is BVH
   * text or bytes on the model's skeleton at any frame rate; `keys` are frames of that clip.
   * Resolves with the whole clip (its frame rate and length), the span between the first
   * and last key synthesized. */
  synthesizeFromBvh(bvh, { keys, method = 'model', post = true, variation, footLock, signal } = {}) {
    const bytes = typeof bvh === 'string' ? new TextEncoder().encode(bvh) : new Uint8Array(bvh).slice();
    return this.request({ type: 'synthesizeFromBvh', bytes: bytes.buffer, keys: Array.from(keys || []), method, post, variation, footLock },
                        [bytes.buffer], { signal });
  }
  /** Parses BVH bytes in the worker and checks its skeleton against the model's:
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
  terminate() {
    this.worker.terminate();
    for (const p of this.pending.values()) p.reject(new DeeprepError('E_TERMINATED', 'the client was terminated'));
    this.pending.clear();
  }
}
