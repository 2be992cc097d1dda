// The keyframe-sketching page in headless Chromium: loads with no console
// errors, synthesizes a 512-frame motion between 3 keys in its worker,
// draws it, exports a BVH with the requested frame count, and undoes edits.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { BVHLoader } from 'three/examples/jsm/loaders/BVHLoader.js';
import { launch, startServer, watchErrors, ROOT } from './chromium.mjs';

let browser, server;
before(async () => { server = await startServer(); browser = await launch(); });
after(async () => { await browser?.close(); await server?.close(); });

async function canvasStats(page) {
  return page.evaluate(() => {
    const c = document.getElementById('view');
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let lit = 0;
    for (let i = 0; i < d.length; i += 4) if (Math.max(d[i], d[i + 1], d[i + 2]) > 90) lit++;
    return { lit, total: d.length / 4 };
  });
}

test('sketch page: 3 keys, 512 frames, drawn, exported, undoable', async () => {
  const page = await browser.context.newPage();
  const errors = watchErrors(page);
  await page.goto(`${server.url}/web/index.html`);
  await page.waitForSelector('body[data-ready="1"]', { timeout: 120_000 }).catch(async (e) => {
    throw new Error(`page never became ready: ${await page.textContent('#status')} ${errors.join(' | ')} (${e.message})`);
  });
  assert.deepEqual(errors, []);
  assert.match(await page.textContent('#method-badge'), /Generative Tweening model/);

  // Keys at 0, 250 and 511 of a 512-frame motion.
  await page.fill('#length', '512');
  await page.dispatchEvent('#length', 'change');
  const setFrame = (f) => page.$eval('#scrub', (el, f) => { el.max = '511'; el.value = String(f); el.dispatchEvent(new Event('input')); }, f);
  for (const f of [150, 299]) { await setFrame(f); await page.click('#del-key'); }
  await setFrame(250); await page.selectOption('#pose', '4'); await page.click('#add-key');
  await setFrame(511); await page.selectOption('#pose', '2'); await page.click('#add-key');
  const frames = await page.evaluate(() => window.deeprepState.keys.map((k) => k.frame));
  assert.deepEqual(frames, [0, 250, 511]);

  await page.click('#synth');
  await page.waitForSelector('body[data-synthesized="512"]', { timeout: 120_000 });
  assert.deepEqual(errors, []);
  const stats = await canvasStats(page);
  assert.ok(stats.lit > 0.003 * stats.total, `canvas looks blank: ${JSON.stringify(stats)}`);
  await setFrame(380);
  fs.mkdirSync(path.join(ROOT, 'tests/out'), { recursive: true });
  await page.screenshot({ path: path.join(ROOT, 'tests/out/sketch.png') });

  // Export: a BVH with the requested frame count, parsed by three.js.
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export')]);
  const text = fs.readFileSync(await download.path(), 'utf8');
  assert.match(text, /Frames: 512/);
  const parsed = new BVHLoader().parse(text);
  assert.equal(parsed.clip.tracks[0].times.length, 512);

  // Undo restores the deleted key; redo removes it again.
  const keyFrames = () => page.evaluate(() => window.deeprepState.keys.map((k) => k.frame).sort((a, b) => a - b));
  await page.click('#undo'); await page.click('#undo');
  assert.deepEqual(await keyFrames(), [0]);
  await page.click('#undo'); await page.click('#undo');
  assert.deepEqual(await keyFrames(), [0, 150, 299]);
  await page.click('#redo');
  assert.deepEqual(await keyFrames(), [0, 299]);

  // A failed synthesis keeps the keys: a gap of more than 600 frames.
  await page.evaluate(() => { window.deeprepState.keys = [window.deeprepState.keys[0], { ...window.deeprepState.keys[1], frame: 700 }]; });
  await page.fill('#length', '800');
  await page.click('#synth');
  await page.waitForFunction(() => document.getElementById('status').classList.contains('error'));
  assert.match(await page.textContent('#status'), /600 frames.*keys are unchanged/);
  assert.equal(await page.evaluate(() => window.deeprepState.keys.length), 2);

});
