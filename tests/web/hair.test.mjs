// The hair page in headless Chromium: HairNet reconstructs a procedural
// test render into thousands of strands drawn around the body, compares the
// 1,024-strand result with the truth, interpolates two results, and turns a
// synthetic photo and mask into an orientation input (Gabor filters).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { launch, startServer, watchErrors, ROOT } from './chromium.mjs';

let browser, server;
before(async () => { server = await startServer(); browser = await launch(); });
after(async () => { await browser?.close(); await server?.close(); });

async function hairPixels(page) {
  return page.evaluate(async () => {
    const d = await window.deeprepHair.pixels();
    let hair = 0, lit = 0;
    for (let i = 0; i < d.length; i += 4) {
      const [r, g, b] = [d[i], d[i + 1], d[i + 2]];
      if (Math.max(r, g, b) > 60) lit++;
      if (r > 110 && r > g + 25 && g > b + 15) hair++;
    }
    return { hair, lit, total: d.length / 4 };
  });
}

test('hair page: reconstruct, compare with the truth, interpolate, photo path', async () => {
  const page = await browser.context.newPage();
  const errors = watchErrors(page);
  await page.goto(`${server.url}/web/hair.html?webgl2`);
  await page.waitForSelector('body[data-ready="1"]', { timeout: 180_000 }).catch(async (e) => {
    throw new Error(`hair page never became ready: ${await page.textContent('#status')} ${errors.join(' | ')} (${e.message})`);
  });
  assert.deepEqual(errors, []);
  assert.equal(await page.evaluate(() => document.body.dataset.strands), '9000');
  assert.equal(await page.evaluate(() => window.deeprepHair.strands.points.length), 9000 * 100 * 3);
  const px = await hairPixels(page);
  assert.ok(px.hair > 2000, `strands not drawn: ${JSON.stringify(px)}`);

  // 1,024 strands grow from the truth's own roots: the page reports the distance.
  await page.selectOption('#count', '1024');
  await page.waitForSelector('body[data-strands="1024"]', { timeout: 60_000 });
  const r = await page.evaluate(() => ({ error: window.deeprepHair.error, collision: window.deeprepHair.strands.collision,
                                          featuresMs: window.deeprepHair.featuresMs, strandsMs: window.deeprepHair.strands.ms }));
  console.log(`hair page (L-wavy #7): mean distance to the truth ${(100 * r.error).toFixed(2)} cm, collision ${r.collision.toExponential(2)}, ` +
              `features ${r.featuresMs.toFixed(0)} ms, 1,024 strands ${r.strandsMs.toFixed(0)} ms`);
  assert.ok(r.error > 0 && r.error < 0.08, `mean distance ${r.error} m`);
  assert.ok(Number.isFinite(r.collision) && r.collision >= 0);
  await page.selectOption('#show', 'truth');
  const truthPx = await hairPixels(page);
  assert.ok(truthPx.hair < px.hair / 4, 'the truth is drawn in its own color');
  await page.selectOption('#show', 'recon');

  // The WGSL compute decoder (WebGPU, SwiftShader here) agrees with the CPU
  // path; curls off, so that no threshold decision can differ.
  await page.selectOption('#count', '9000');
  await page.uncheck('#curls');
  await page.waitForSelector('body[data-decoded="cpu:9000:Infinity"]', { timeout: 60_000 });
  await page.evaluate(() => { window.cpuPoints = window.deeprepHair.strands.points; });
  await page.selectOption('#device', 'gpu');
  await page.waitForSelector('body[data-decoded="webgpu:9000:Infinity"]', { timeout: 120_000 });
  const gpu = await page.evaluate(() => {
    const a = window.cpuPoints, b = window.deeprepHair.strands.points;
    let d = 0;
    for (let i = 0; i < a.length; i++) d = Math.max(d, Math.abs(a[i] - b[i]));
    return { d, n: b.length, ms: window.deeprepHair.strands.ms };
  });
  console.log(`9,000 strands on WebGPU compute: ${gpu.ms.toFixed(0)} ms, largest difference from the CPU ${gpu.d.toExponential(2)} m`);
  assert.equal(gpu.n, 9000 * 300);
  assert.ok(gpu.d < 1e-4, `GPU and CPU strands differ by ${gpu.d} m`);
  await page.selectOption('#device', 'cpu');
  await page.check('#curls');

  // Interpolation: A = L-wavy #7, B = XS-curly #3, halfway.
  await page.click('#keep-a');
  // the click took effect: the button names what it kept (a failure here and not at the blend below
  // says the click itself was lost)
  await page.waitForSelector('#keep-a:text("A: L-wavy #7")', { timeout: 10_000 });
  await page.selectOption('#cls', 'XS-curly');
  await page.fill('#seed', '3');
  await page.dispatchEvent('#seed', 'change');
  await page.waitForSelector('body[data-input="XS-curly:3:20"]', { timeout: 60_000 });
  await page.click('#keep-b');
  await page.waitForSelector('#keep-b:text("B: XS-curly #3")', { timeout: 10_000 });
  // keeping A and B enables the blend (waited for: one full CI run under load saw it still disabled here)
  await page.waitForSelector('#blend:not([disabled])', { timeout: 10_000 });
  await page.$eval('#blend', (el) => { el.value = '0.5'; el.dispatchEvent(new Event('input')); });
  await page.waitForSelector('body[data-blend="0.5"]', { timeout: 60_000 });
  const mid = await page.evaluate(() => Array.from(window.deeprepHair.strands.points.slice(0, 300)));
  assert.ok(mid.every(Number.isFinite));

  // Photo path: vertical stripes inside a round mask -> orientation 90° there.
  await page.evaluate(async () => {
    const make = async (draw, name) => {
      const c = new OffscreenCanvas(200, 200);
      draw(c.getContext('2d'));
      const blob = await c.convertToBlob({ type: 'image/png' });
      return new File([blob], name, { type: 'image/png' });
    };
    const photo = await make((x) => { x.fillStyle = '#000'; x.fillRect(0, 0, 200, 200); x.fillStyle = '#fff'; for (let i = 0; i < 200; i += 4) x.fillRect(i, 0, 2, 200); }, 'stripes.png');
    const mask = await make((x) => { x.fillStyle = '#000'; x.fillRect(0, 0, 200, 200); x.fillStyle = '#fff'; x.beginPath(); x.arc(100, 80, 60, 0, 7); x.fill(); }, 'mask.png');
    for (const [id, f] of [['photo', photo], ['mask', mask]]) {
      const dt = new DataTransfer();
      dt.items.add(f);
      const el = document.getElementById(id);
      el.files = dt.files;
      el.dispatchEvent(new Event('change'));
    }
  });
  await page.click('#from-photo');
  await page.waitForSelector('body[data-input="photo:stripes.png"]', { timeout: 120_000 });
  const orient = await page.evaluate(() => {
    const img = window.deeprepHair.image, plane = 256 * 256;
    let n = 0, vertical = 0;
    for (let i = 0; i < plane; i++) {
      if (img[2 * plane + i] === 1) { n++; if (img[i] < 0.1) vertical++; }   // (cos 2θ + 1)/2 ≈ 0 at θ = 90°
    }
    return { n, vertical };
  });
  assert.ok(orient.n > 5000 && orient.vertical > 0.8 * orient.n, JSON.stringify(orient));
  assert.deepEqual(errors, []);
  fs.mkdirSync(path.join(ROOT, 'tests/out'), { recursive: true });
  await page.selectOption('#cls', 'L-wavy');
  await page.fill('#seed', '7');
  await page.dispatchEvent('#seed', 'change');
  await page.waitForSelector('body[data-input="L-wavy:7:20"]', { timeout: 60_000 });
  await page.selectOption('#count', '30000');
  await page.waitForSelector('body[data-strands="30000"]', { timeout: 120_000 });
  await page.screenshot({ path: path.join(ROOT, 'tests/out/hair.png') });
  await page.close();
});
