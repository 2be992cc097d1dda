// The demo page in headless Chromium: it loads with no console errors, draws
// Figure C.1 (not blank, many hues), and runs the ONNX model in tract.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { launch, startServer, watchErrors, ROOT } from './chromium.mjs';

let browser, server;
before(async () => { server = await startServer(); browser = await launch(); });
after(async () => { await browser?.close(); await server?.close(); });

test('the page draws Figure C.1 and runs the ONNX model, with no console errors', async () => {
  const page = await browser.context.newPage();
  const errors = watchErrors(page);
  await page.goto(`${server.url}/web/rotations.html`);
  await page.waitForSelector('body[data-ready="1"]', { timeout: 60_000 }).catch(async (e) => {
    throw new Error(`page never became ready: ${await page.textContent('#status')} ${errors.join(' | ')} (${e.message})`);
  });
  assert.deepEqual(errors, []);

  // Pixel statistics of the figure canvas: drawn, not blank, colored by angle.
  const stats = await page.evaluate(() => {
    const c = document.getElementById('figure');
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let lit = 0; const hues = new Set();
    for (let i = 0; i < d.length; i += 4) {
      const [r, g, b] = [d[i], d[i + 1], d[i + 2]];
      const max = Math.max(r, g, b), min = Math.min(r, g, b);
      if (max - min > 60) {
        lit++;
        let h;
        if (max === r) h = ((g - b) / (max - min) + 6) % 6; else if (max === g) h = (b - r) / (max - min) + 2; else h = (r - g) / (max - min) + 4;
        hues.add(Math.floor(h * 6)); // 36 hue bins
      }
    }
    return { lit, total: d.length / 4, hues: hues.size };
  });
  assert.ok(stats.lit > 0.005 * stats.total, `figure looks blank: ${JSON.stringify(stats)}`);
  assert.ok(stats.hues >= 30, `figure lacks the angle hues: ${JSON.stringify(stats)}`);

  // Jumps table: continuous rows stay small, discontinuous rows jump.
  const jumps = await page.$$eval('#jumps tbody tr', (rows) => rows.map((r) => [...r.children].map((c) => c.textContent)));
  const row = (name) => jumps.find((r) => r[0].startsWith(name)).slice(1).map(Number);
  for (const name of ['SO(3)', '6D', '5D']) assert.ok(Math.max(...row(name)) < 0.2, `${name} jumps: ${row(name)}`);
  for (const name of ['Unit quaternion', 'Axis-angle', 'Euler']) assert.ok(Math.max(...row(name)) > 1.0, `${name} should jump: ${row(name)}`);

  // The tiny network, run by tract in the page, reconstructs rotations.
  const meanDeg = Number(await page.getAttribute('#onnx', 'data-mean-deg'));
  assert.ok(meanDeg < 3, `ONNX reconstruction error ${meanDeg}°`);

  fs.mkdirSync(path.join(ROOT, 'tests/out'), { recursive: true });
  await page.screenshot({ path: path.join(ROOT, 'tests/out/page.png'), fullPage: true });
});

test('bad input to the JS API raises an Error with a message', async () => {
  const page = await browser.context.newPage();
  await page.goto(`${server.url}/web/rotations.html`);
  await page.waitForSelector('body[data-ready="1"]', { timeout: 60_000 });
  const msgs = await page.evaluate(async () => {
    const m = await import('./pkg/deeprep.js');
    const out = [];
    for (const f of [
      () => m.convertRotations('6d', 'quat', new Float32Array(7)),
      () => m.convertRotations('6d', 'quat', new Float32Array(6)),
      () => m.convertRotations('quaternion', 'quat', new Float32Array(4)),
      () => new m.OnnxModel(new Uint8Array([1, 2, 3])),
      () => m.BvhClip.parse('HIERARCHY\nROOT a\n{\n OFFSET 0 x 0\n'),
    ]) {
      try { f(); out.push('no error'); } catch (e) { out.push(e instanceof Error ? e.message : `non-Error: ${e}`); }
    }
    return out;
  });
  assert.match(msgs[0], /multiple of 6/);
  assert.match(msgs[1], /degenerate/);
  assert.match(msgs[2], /unknown rotation representation/);
  assert.match(msgs[3], /model/);
  assert.match(msgs[4], /^line 4: expected a number for OFFSET y, found 'x'/);
});

test('BVH from JS: parse, FK positions, write, parse again', async () => {
  const page = await browser.context.newPage();
  await page.goto(`${server.url}/web/rotations.html`);
  await page.waitForSelector('body[data-ready="1"]', { timeout: 60_000 });
  const r = await page.evaluate(async () => {
    const m = await import('./pkg/deeprep.js');
    const text = 'HIERARCHY\nROOT r\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n'
      + ' JOINT c\n {\n  OFFSET 1 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 2 0\n  }\n }\n}\n'
      + 'MOTION\nFrames: 2\nFrame Time: 0.1\n1 2 3 90 0 0 0 0 0\n0 0 0 0 0 0 0 90 0\n';
    const clip = m.BvhClip.fromBytes(new TextEncoder().encode(text));
    const again = m.BvhClip.parse(clip.toBvh());
    return {
      names: clip.jointNames, parents: Array.from(clip.parents), frames: clip.frameCount,
      fk: Array.from(clip.fkPositions(0, 2)), fkAgain: Array.from(again.fkPositions(0, 2)),
      isF32: clip.fkPositions(0, 1) instanceof Float32Array,
      rangeError: (() => { try { clip.fkPositions(1, 3); return ''; } catch (e) { return e.message; } })(),
    };
  });
  assert.deepEqual(r.names, ['r', 'c', 'c_Nub']);
  assert.deepEqual(r.parents, [-1, 0, 1]);
  assert.equal(r.frames, 2);
  assert.ok(r.isF32);
  const expect = [1, 2, 3, 1, 3, 3, -1, 3, 3, 0, 0, 0, 1, 0, 0, 1, 0, 2];
  r.fk.forEach((v, i) => assert.ok(Math.abs(v - expect[i]) < 1e-5, `fk[${i}] = ${v}, expected ${expect[i]}`));
  assert.deepEqual(r.fkAgain, r.fk);
  assert.match(r.rangeError, /outside the clip's 2 frames/);
});
