// The packed package (pkg/, scripts/build-npm.sh) served as a CDN serves it:
// from a second origin with CORS. A page on the first origin imports
// DeeprepClient from there with a plain <script type="module"> and no
// build step, create()s it with no arguments and in-betweens a clip; and a
// worker URL that does not exist rejects with E_WORKER naming it.
// Usage: node tests/npm/cdn_smoke.mjs [PKG_DIR]
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { launch } from '../web/chromium.mjs';
import { serve } from '../../scripts/serve.mjs';

const pkg = path.resolve(process.argv[2] || 'pkg');
const cdn = await serve(pkg, 0, '127.0.0.1', { cors: true });
const base = `http://127.0.0.1:${cdn.address().port}/`;
const site = fs.mkdtempSync(path.join(os.tmpdir(), 'deeprep-cdn-'));
fs.writeFileSync(path.join(site, 'index.html'), `<!doctype html><meta charset="utf-8"><pre id="out"></pre>
<script type="module">
import { DeeprepClient } from '${base}client.js';
try {
  const client = await DeeprepClient.create();
  const head = client.skeletonBvh.replace(/MOTION[\\s\\S]*/, '');
  const n = client.skeletonBvh.split('CHANNELS').slice(1).reduce((a, s) => a + Number(s.trim().split(/\\s+/)[0]), 0);
  const rows = Array.from({ length: 61 }, (_, f) => Array.from({ length: n }, (_, i) => (i === 0 ? f : i === 1 ? 90 : 0)).join(' '));
  const r = await client.synthesizeFromBvh(head + 'MOTION\\nFrames: 61\\nFrame Time: 0.0166667\\n' + rows.join('\\n') + '\\n', { keys: [0, 60] });
  const missing = await DeeprepClient.create({ workerUrl: './no-such-worker.js' }).then(() => null, (e) => e);
  if (missing?.code !== 'E_WORKER' || !missing.message.includes('no-such-worker.js')) throw new Error('a missing worker: ' + missing?.code + ' ' + missing?.message);
  document.getElementById('out').textContent = 'from ' + '${base}' + ': ' + r.frames + ' frames by ' + r.ran + '; a missing worker: ' + missing.code;
  document.body.dataset.done = '1';
} catch (e) {
  document.body.dataset.error = (e.code || '') + ' ' + e.message;
}
</script>`);
const page0 = await serve(site, 0);
const url = `http://127.0.0.1:${page0.address().port}/index.html`;
const browser = await launch();
let failed = null;
try {
  const page = await browser.context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => document.body.dataset.done || document.body.dataset.error, null, { timeout: 120_000 });
  const error = await page.evaluate(() => document.body.dataset.error);
  if (error) failed = `the CDN page failed: ${error}`;
  else if (errors.length) failed = `page errors: ${errors.join(' | ')}`;
  else console.log(`cdn smoke: ${await page.textContent('#out')}`);
} finally {
  await browser.close();
  cdn.close();
  page0.close();
  fs.rmSync(site, { recursive: true, force: true });
}
if (failed) { console.error(failed); process.exit(1); }
