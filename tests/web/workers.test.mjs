// The one worker protocol (web/lib/workers.js) in headless Chromium, on a
// tiny worker made here: a result per request, a trap that replaces the
// worker and replays 'init' before the next call, an abort, termination.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, startServer } from './chromium.mjs';

let browser, server;
before(async () => { server = await startServer(); browser = await launch(); });
after(async () => { await browser?.close(); await server?.close(); });

test('WorkerChannel: results, a trap replayed from init, aborts, termination', async () => {
  const page = await browser.context.newPage();
  await page.goto(`${server.url}/web/rotations.html`);
  const r = await page.evaluate(async () => {
    const { WorkerChannel } = await import('/web/lib/workers.js');
    const src = `let state = null;
      onmessage = async (e) => {
        const m = e.data;
        if (m.type === 'init') { state = m.value; postMessage({ type: 'progress', id: m.id, stage: 'init' }); postMessage({ type: 'result', id: m.id }); }
        else if (m.type === 'echo') postMessage({ type: 'result', id: m.id, value: state });
        else if (m.type === 'trap') postMessage({ type: 'error', id: m.id, trapped: true, message: 'unreachable' });
        else if (m.type === 'bad') postMessage({ type: 'error', id: m.id, code: 'E_BAD_KEYS', message: 'no keys' });
        else if (m.type === 'slow') { await new Promise((r) => setTimeout(r, 2000)); postMessage({ type: 'result', id: m.id }); }
      };`;
    const url = URL.createObjectURL(new Blob([src], { type: 'text/javascript' }));
    const progress = [];
    const ch = new WorkerChannel(() => new Worker(url, { type: 'module' }), { onProgress: (m) => progress.push(m.stage) });
    const code = (p) => p.then(() => 'resolved', (e) => e.code);
    await ch.request({ type: 'init', value: 42 });
    const out = { echo: (await ch.request({ type: 'echo' })).value, progress: [...progress] };
    out.bad = await code(ch.request({ type: 'bad' }));
    out.trap = await code(ch.request({ type: 'trap' }));
    out.restarts = ch.restarts;
    out.afterTrap = (await ch.request({ type: 'echo' })).value; // init was replayed first
    const ac = new AbortController();
    const slow = code(ch.request({ type: 'slow' }, [], { signal: ac.signal }));
    setTimeout(() => ac.abort(), 50);
    out.aborted = await slow;
    out.afterAbort = (await ch.request({ type: 'echo' })).value;
    out.early = await code(ch.request({ type: 'echo' }, [], { signal: AbortSignal.abort() }));
    const pending = code(ch.request({ type: 'slow' }));
    ch.terminate();
    out.terminated = await pending;
    out.restartsEnd = ch.restarts;
    return out;
  });
  assert.deepEqual(r, { echo: 42, progress: ['init'], bad: 'E_BAD_KEYS', trap: 'E_WASM_TRAP', restarts: 1, afterTrap: 42,
                        aborted: 'E_ABORTED', afterAbort: 42, early: 'E_ABORTED', terminated: 'E_TERMINATED', restartsEnd: 2 });
  await page.close();
});
