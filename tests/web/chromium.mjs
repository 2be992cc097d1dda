// Shared helpers for the browser tests: Debian's Chromium driven by
// playwright-core (never a downloaded browser), and a static server for the
// repository root.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from '../../scripts/serve.mjs';

export const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
export const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';

export const BASE_FLAGS = [
  '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--disable-dev-shm-usage',
  // Software WebGPU and WebGL2 (SwiftShader) for the renderer tests.
  '--enable-unsafe-webgpu', '--use-webgpu-adapter=swiftshader',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
];

export async function launch() {
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'deeprep-chromium-'));
  const context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: CHROMIUM,
    headless: true,
    args: BASE_FLAGS,
    viewport: { width: 1400, height: 1000 },
  });
  return { context, close: async () => { await context.close(); fs.rmSync(userDataDir, { recursive: true, force: true }); } };
}

export async function startServer() {
  const server = await serve(ROOT, 0);
  return { url: `http://127.0.0.1:${server.address().port}`, close: () => new Promise((r) => server.close(r)) };
}

/**
 * The benchmarks' page: serves the repository, opens web/rotations.html in
 * a fresh headless Chromium (its ./pkg/deeprep.js is the wasm package),
 * waits for it, runs `run(page)` and closes everything; returns what `run`
 * returns.
 */
export async function withBenchPage(run) {
  const server = await startServer();
  const browser = await launch();
  try {
    const page = await browser.context.newPage();
    await page.goto(`${server.url}/web/rotations.html`);
    await page.waitForSelector('body[data-ready="1"]', { timeout: 120_000 });
    return await run(page);
  } finally {
    await browser.close();
    await server.close();
  }
}

/** Collects console errors and page errors. */
export function watchErrors(page) {
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  return errors;
}

/** The share of drawn pixels in a screenshot of the element `selector`
 *  (what is on screen; decoded in the page): pixels brighter than the pages'
 *  dark background by more than its shading. */
export async function litInScreenshot(page, selector) {
  const png = await page.locator(selector).screenshot();
  return page.evaluate(async (b64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const c = new OffscreenCanvas(img.width, img.height);
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, img.width, img.height).data;
    // a pixel differs from the page's dark background by more than its shading
    let lit = 0;
    for (let i = 0; i < d.length; i += 4) if (Math.max(d[i], d[i + 1], d[i + 2]) > 60) lit++;
    return lit / (d.length / 4);
  }, png.toString('base64'));
}
