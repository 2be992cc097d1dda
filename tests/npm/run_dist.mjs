// Serves a built app's dist/ folder and runs it in headless Chromium: the
// page must set body[data-done] (its own checks passed) with no console
// errors. Usage: node tests/npm/run_dist.mjs DIST_DIR
import { launch, watchErrors } from '../web/chromium.mjs';
import { serve } from '../../scripts/serve.mjs';

const dist = process.argv[2];
const server = await serve(dist, 0);
const url = `http://127.0.0.1:${server.address().port}/index.html`;
const browser = await launch();
let failed = null;
try {
  const page = await browser.context.newPage();
  const errors = watchErrors(page);
  page.on('response', (r) => { if (r.status() >= 400) errors.push(`HTTP ${r.status()} ${r.url()}`); });
  const t0 = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => document.body.dataset.done || document.body.dataset.error, null, { timeout: 180_000 });
  const error = await page.evaluate(() => document.body.dataset.error);
  const out = await page.textContent('#out');
  if (error) failed = `the app failed: ${error}`;
  else if (errors.length) failed = `console errors: ${errors.join(' | ')}`;
  else console.log(`production build ran in Chromium in ${Date.now() - t0} ms: ${out}`);
} finally {
  await browser.close();
  server.close();
}
if (failed) { console.error(failed); process.exit(1); }
