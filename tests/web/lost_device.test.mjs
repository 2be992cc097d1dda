// Every page with a GPU view, loaded without ?webgl2: WebGPU first, and in
// headless Chromium (whose SwiftShader WebGPU loses its device after the
// first present) the page must switch to WebGL2 by itself and draw. Checks
// drawn pixels, not just the absence of errors (issue 24).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { launch, litInScreenshot, startServer, watchErrors, ROOT } from './chromium.mjs';

const GLB = path.resolve(process.env.DEEPREP_DATA || path.join(ROOT, '..', 'shared', 'data'), 'gltf', 'RobotExpressive.glb');
const HAVE_GLB = fs.existsSync(GLB);

let browser, server;
before(async () => { server = await startServer(); browser = await launch(); });
after(async () => { await browser?.close(); await server?.close(); });

// The share of pixels with anything drawn, read through the page's own
// `pixels()` (which draws first), once the page has settled: read every
// half second until something is drawn or 15 s have passed (the device is
// lost at the first present, and the switch to WebGL2 takes longer on a
// loaded machine: one CI run read 0% at 0.5 s with the view still 'webgpu').
async function drawn(page, global) {
  let lit = 0;
  for (let i = 0; i < 30 && lit <= 0.01; i++) {
    await new Promise((r) => setTimeout(r, 500));
    lit = await page.evaluate(async (g) => {
      const d = await window[g].pixels();
      let n = 0;
      for (let j = 0; j < d.length; j += 4) if (Math.max(d[j], d[j + 1], d[j + 2]) > 60) n++;
      return n / (d.length / 4);
    }, global);
  }
  return lit;
}

for (const [name, url, global, skip] of [
  ['mesh', '/web/mesh.html', 'deeprepMesh', !HAVE_GLB && `no ${GLB}`],
  ['hair', '/web/hair.html', 'deeprepHair', false],
]) {
  test(`${name} page without ?webgl2 recovers from a lost WebGPU device and draws`, { skip }, async () => {
    const page = await browser.context.newPage();
    const errors = watchErrors(page);
    await page.goto(`${server.url}${url}`);
    await page.waitForSelector('body[data-ready="1"]', { timeout: 180_000 }).catch(async (e) => {
      throw new Error(`${name} page never became ready: ${await page.textContent('#status')} ${errors.join(' | ')} (${e.message})`);
    });
    const lit = await drawn(page, global);
    const view = await page.evaluate(() => document.body.dataset.view);
    console.log(`${name} page without ?webgl2: view ${view}, ${(100 * lit).toFixed(1)}% of pixels drawn`);
    assert.ok(['webgpu', 'webgl2'].includes(view), `view: ${view}`);
    assert.ok(lit > 0.01, `${name} page draws nothing after the device change (${lit})`);
    assert.deepEqual(errors, []);
    await page.close();
  });
}

// What is on screen (issue 52): a screenshot of each page's visible canvases,
// decoded in the page and counted, at the default URL (WebGPU first, WebGL2
// after the lost device) and with ?webgl2. Nothing the test triggers draws.

for (const [name, url, canvases, skip] of [
  ['sketching', '/web/index.html', ['#view'], false],
  ['mesh', '/web/mesh.html', ['#view'], !HAVE_GLB && `no ${GLB}`],
  ['hair', '/web/hair.html', ['#view', '#input'], false],
]) {
  for (const query of ['', '?webgl2']) {
    test(`${name} page${query ? ` with ${query}` : ' at its default URL'}: a screenshot shows the scene`, { skip }, async () => {
      const page = await browser.context.newPage();
      const errors = watchErrors(page);
      await page.goto(`${server.url}${url}${query}`);
      await page.waitForSelector('body[data-ready="1"]', { timeout: 180_000 });
      await new Promise((r) => setTimeout(r, 1500));
      for (const sel of canvases) {
        const lit = await litInScreenshot(page, sel);
        console.log(`${name}${query} ${sel}: ${(100 * lit).toFixed(1)}% of the screenshot drawn`);
        assert.ok(lit > 0.01, `${name} page${query} shows an empty ${sel} (${(100 * lit).toFixed(2)}% drawn)`);
      }
      assert.deepEqual(errors, []);
      await page.close();
    });
  }
}
