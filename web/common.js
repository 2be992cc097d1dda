// Helpers shared by the mesh and hair pages: a promise API over a module
// worker, "latest request wins" lanes for sliders, and the wgpu viewer with
// its WebGL2 fallback on a lost device.
import { Viewer } from './pkg/deeprep.js';

/** The bytes at `url`; an Error naming the URL and HTTP status otherwise. */
export async function fetchBytes(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${url}: HTTP ${r.status}`);
  return new Uint8Array(await r.arrayBuffer());
}

/** The text at `url`; an Error "<what>: HTTP <status>" otherwise. */
export async function fetchText(url, what) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${what}: HTTP ${r.status}`);
  return r.text();
}

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

/**
 * The wgpu viewer on the canvas with id `canvasId` (WebGPU first unless
 * `forceWebgl2`). `view.ensure()` replaces a viewer whose GPU device was
 * lost (a GPU reset, or headless Chromium, whose WebGPU cannot present a
 * canvas) with WebGL2 on a fresh canvas, calling `onReplace(view)` so the
 * page can re-upload its scene and re-wire its listeners.
 */
export async function openView(canvasId, forceWebgl2, onReplace) {
  const view = { viewer: await Viewer.create(document.getElementById(canvasId), forceWebgl2), replacing: null };
  view.canvas = () => document.getElementById(canvasId);
  view.name = () => view.viewer.backend;
  view.ensure = () => {
    if (!view.viewer.deviceLost || view.replacing) return view.replacing;
    view.replacing = (async () => {
      console.warn(`the ${view.viewer.backend} device was lost; switching to WebGL2`);
      const old = view.canvas();
      const fresh = old.cloneNode(true);
      old.replaceWith(fresh);
      view.viewer = await Viewer.create(fresh, true);
      await onReplace(view);
      view.replacing = null;
    })();
    return view.replacing;
  };
  /** RGBA pixels right after `draw()` (for tests). */
  view.pixels = (draw) => {
    draw();
    const c = view.canvas();
    const o = document.createElement('canvas');
    o.width = c.width; o.height = c.height;
    const x = o.getContext('2d');
    x.drawImage(c, 0, 0);
    return x.getImageData(0, 0, o.width, o.height).data;
  };
  return view;
}

/** Canvas pixel coordinates of a mouse event on `canvas`. */
export function toCanvas(canvas, e) {
  const r = canvas.getBoundingClientRect();
  return [((e.clientX - r.left) * canvas.width) / r.width, ((e.clientY - r.top) * canvas.height) / r.height];
}

/**
 * Orbit (drag), pan (shift-drag) and zoom (wheel) on the viewer's canvas;
 * `onDown(x, y)` sees every press. Returns `attach(canvas)` for a
 * replacement canvas (the window listeners are registered once).
 */
export function wireOrbit(view, draw, onDown = () => {}) {
  let drag = null;
  const attach = (canvas) => {
    canvas.addEventListener('mousedown', (e) => {
      const [x, y] = toCanvas(canvas, e);
      onDown(x, y);
      drag = { x, y, pan: e.shiftKey };
    });
    canvas.addEventListener('wheel', (e) => { e.preventDefault(); view.viewer.zoom(Math.exp(e.deltaY * 0.001)); draw(); }, { passive: false });
  };
  attach(view.canvas());
  window.addEventListener('mouseup', () => { drag = null; });
  window.addEventListener('mousemove', (e) => {
    if (!drag) return;
    const [x, y] = toCanvas(view.canvas(), e);
    if (drag.pan) view.viewer.pan(x - drag.x, y - drag.y); else view.viewer.orbit(x - drag.x, y - drag.y);
    drag.x = x; drag.y = y;
    draw();
  });
  return attach;
}
