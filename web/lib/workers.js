// The one worker protocol of every page and of the npm client (client.js):
//   page -> worker  {type, id, ...}
//   worker -> page  {type: 'progress', id, ...} | {type: 'result', id, ...}
//                   | {type: 'error', id, message, code?, trapped?}
// `trapped` (the worker's wasm hit a WebAssembly.RuntimeError) makes the
// channel replace the worker: calls queued on the old one reject with code
// E_WASM_TRAP, and the last successful request of each type in `replay`
// (its loaded state, e.g. 'init') is sent again to the new one before any
// later call. An AbortSignal replaces the worker too (wasm cannot be
// interrupted mid-call). Also: "latest request wins" lanes for sliders.

/** A promise API over a module worker, as described above. */
export class WorkerChannel {
  /**
   * `makeWorker()` creates the worker (written by the caller as
   * `new Worker(new URL('./x.js', import.meta.url), { type: 'module' })`
   * so bundlers see it); `error(code, message)` makes the rejections.
   */
  constructor(makeWorker, { onProgress = () => {}, onError = () => {}, replay = ['init'], error, describeError } = {}) {
    // the message of a worker's `error` event (which names neither URL nor cause)
    this.describeError = describeError || ((e) => `worker failed: ${e.message || e.type}`);
    this.makeWorker = makeWorker;
    this.onProgress = onProgress;
    this.onError = onError;
    this.replayTypes = replay;
    this.error = error || ((code, message) => Object.assign(new Error(message), { code }));
    this.pending = new Map();
    this.kept = new Map();
    this.nextId = 1;
    this.restarts = 0;
    this.ready = Promise.resolve();
    this.start();
  }

  start() {
    const worker = this.makeWorker();
    this.worker = worker;
    worker.onmessage = (e) => {
      if (worker !== this.worker) return; // a replaced worker's late reply
      const m = e.data;
      if (m.type === 'progress') { this.onProgress(m); return; }
      const p = this.pending.get(m.id);
      if (m.type === 'error' && m.trapped) this.restart(m.id, 'E_WASM_TRAP', `the worker trapped during another call: ${m.message}`);
      if (!p) return;
      this.pending.delete(m.id);
      if (m.type === 'error') { p.reject(this.error(m.code || (m.trapped ? 'E_WASM_TRAP' : 'E_BAD_INPUT'), m.message)); return; }
      if (this.replayTypes.includes(p.msg.type)) this.kept.set(p.msg.type, p.msg);
      p.resolve(m);
    };
    worker.onerror = (e) => {
      const err = this.error('E_WORKER', this.describeError(e));
      for (const p of this.pending.values()) p.reject(err);
      this.pending.clear();
      this.onError(err);
    };
  }

  post(msg, transfer = []) {
    const id = this.nextId++;
    if (this.closed) return Promise.reject(this.error('E_TERMINATED', 'the client was terminated'));
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject, msg });
      this.worker.postMessage({ ...msg, id }, transfer);
    });
  }

  /** Sends `msg`; resolves with the worker's result, rejects with `error(code, message)`. */
  async request(msg, transfer = [], { signal } = {}) {
    if (signal?.aborted) throw this.error('E_ABORTED', 'aborted before it started');
    await this.ready;
    if (signal?.aborted) throw this.error('E_ABORTED', 'aborted before it started');
    const id = this.nextId;
    const done = this.post(msg, transfer);
    if (!signal) return done;
    const onAbort = () => {
      const p = this.pending.get(id);
      if (!p) return;
      this.pending.delete(id);
      p.reject(this.error('E_ABORTED', 'aborted'));
      this.restart(id, 'E_ABORTED', 'aborted with another call (the worker was replaced)');
    };
    signal.addEventListener('abort', onAbort, { once: true });
    return done.finally(() => signal.removeEventListener('abort', onAbort));
  }

  /** Replaces the worker: pending calls but `keep` fail with `code`; the kept state is replayed first. */
  restart(keep, code, message) {
    this.worker.terminate();
    this.restarts++;
    for (const [id, p] of [...this.pending]) {
      if (id === keep) continue;
      this.pending.delete(id);
      p.reject(this.error(code, message));
    }
    this.start();
    const replays = [...this.kept.values()].map((m) => this.post(m).catch(() => {}));
    this.ready = Promise.all(replays).then(() => {});
  }

  /** Stops the worker; pending calls reject with E_TERMINATED. */
  terminate() {
    this.closed = true; // calls still waiting for a replay reject too
    this.worker.terminate();
    for (const p of this.pending.values()) p.reject(this.error('E_TERMINATED', 'the client was terminated'));
    this.pending.clear();
  }
}

/** The mesh and hair pages' client: `request(msg, transfer)` and `restarts`. */
export function workerClient(url, options = {}) {
  const channel = new WorkerChannel(() => new Worker(url, { type: 'module' }), options);
  return {
    request: (msg, transfer = []) => channel.request(msg, transfer),
    get restarts() { return channel.restarts; },
  };
}

/**
 * Runs async jobs per kind so that while one runs, only the newest waiting
 * job of that kind is kept (slider drags stay responsive). `onError` gets
 * failures; `onIdle` is called when a kind's queue empties.
 */
export function latestRunner({ onError = console.warn, onIdle = () => {} } = {}) {
  const lanes = new Map();
  return function latest(kind, fn) {
    let lane = lanes.get(kind);
    if (!lane) { lane = { running: null, next: null }; lanes.set(kind, lane); }
    lane.next = fn;
    if (!lane.running) {
      lane.running = (async () => {
        while (lane.next) {
          const f = lane.next;
          lane.next = null;
          try { await f(); } catch (e) { onError(e); }
        }
        lane.running = null;
        onIdle(kind);
      })();
    }
    return lane.running;
  };
}
