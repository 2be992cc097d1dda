// The in-betweening worker in Node (worker_threads), for DeeprepClient.create()
// in Node 20+: the Web Worker globals that worker.js uses (postMessage,
// onmessage) and a fetch that reads the package's own files (file: URLs,
// where Node's fetch has none), then worker.js itself: the same code, the
// same wasm and models, the same results as in a browser.
import { parentPort } from 'node:worker_threads';
import { readFile } from 'node:fs/promises';

const TYPES = { '.wasm': 'application/wasm', '.json': 'application/json' };
const webFetch = globalThis.fetch;
globalThis.fetch = async (input, init) => {
  const href = typeof input === 'string' ? input : input instanceof URL ? input.href : input?.url;
  if (!href || !href.startsWith('file:')) return webFetch(input, init);
  const url = new URL(href);
  try {
    const bytes = await readFile(url);
    const ext = url.pathname.slice(url.pathname.lastIndexOf('.'));
    return new Response(bytes, { status: 200, headers: { 'Content-Type': TYPES[ext] || 'application/octet-stream', 'Content-Length': String(bytes.length) } });
  } catch (e) {
    return new Response(null, { status: 404, statusText: String(e.code || e.message) });
  }
};
globalThis.postMessage = (message, transfer) => parentPort.postMessage(message, transfer);
// worker.js assigns onmessage, which in a module must already exist as a global
globalThis.onmessage = null;
// messages that arrive while worker.js loads wait for its handler
const early = [];
parentPort.on('message', (data) => (globalThis.onmessage ? globalThis.onmessage({ data }) : early.push(data)));
await import('./worker.js');
for (const data of early.splice(0)) globalThis.onmessage({ data });
