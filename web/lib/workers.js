// Workers for the mesh and hair pages: a promise API over a module worker
// that replaces a worker whose wasm trapped, and "latest request wins"
// lanes for sliders.

/**
 * A module worker answering {id, ...} requests with {type: 'result'|'error'|'progress', id}.
 * An error reply with `trapped` (the worker's wasm hit a WebAssembly.RuntimeError) makes
 * the client replace the worker: calls queued on the old one reject with code
 * E_WASM_TRAP, and the last successful request of each type in `replay` (its loaded
 * state, e.g. 'init') is sent again to the new one, so later calls work.
 */
export function workerClient(url, { onProgress = () => {}, onError = () => {}, replay = ['init'] } = {}) {
  const pending = new Map();
  const kept = new Map();
  let worker;
  let nextId = 1;
  const fail = (code, message) => Object.assign(new Error(message), { code });
  const client = { restarts: 0 };
  const start = () => {
    worker = new Worker(url, { type: 'module' });
    worker.onmessage = (e) => {
      const m = e.data;
      if (m.type === 'progress') { onProgress(m); return; }
      const p = pending.get(m.id);
      if (m.type === 'error' && m.trapped) restart(m);
      if (!p) return;
      pending.delete(m.id);
      if (m.type === 'error') { p.reject(fail(m.trapped ? 'E_WASM_TRAP' : 'E_BAD_INPUT', m.message)); return; }
      if (replay.includes(p.msg.type)) kept.set(p.msg.type, p.msg);
      p.resolve(m);
    };
    worker.onerror = (e) => onError(new Error(`worker failed: ${e.message || e.type}`));
  };
  const restart = (m) => {
    worker.terminate();
    client.restarts++;
    for (const [id, p] of [...pending]) {
      if (id === m.id) continue;
      pending.delete(id);
      p.reject(fail('E_WASM_TRAP', `the worker trapped during another call: ${m.message}`));
    }
    start();
    for (const msg of kept.values()) worker.postMessage({ ...msg, id: 0 }); // its reply (id 0) is ignored
  };
  start();
  client.request = (msg, transfer = []) => {
    const id = nextId++;
    return new Promise((resolve, reject) => {
      pending.set(id, { resolve, reject, msg });
      worker.postMessage({ ...msg, id }, transfer);
    });
  };
  return client;
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
