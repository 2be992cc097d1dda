// Serves a built app's dist/ folder and runs it in headless Chromium: the
// page must set body[data-done] (its own checks passed) with no console
// errors. With --runs N it loads the page N times (a fresh browser profile
// each, so nothing is cached) and prints the time from navigation to the
// first synthesis result as JSON, with the first synthesis against a warm one.
// Usage: node tests/npm/run_dist.mjs DIST_DIR [--runs N]
import { launch } from '../web/chromium.mjs';
import { serve } from '../../scripts/serve.mjs';

const dist = process.argv[2];
const runsAt = process.argv.indexOf('--runs');
const runs = runsAt > 0 ? Number(process.argv[runsAt + 1]) : 1;
const server = await serve(dist, 0);
const url = `http://127.0.0.1:${server.address().port}/index.html`;
let failed = null;
const firsts = [], firstSynth = [], warmSynth = [], stages = [];
for (let i = 0; i < runs && !failed; i++) {
  const browser = await launch();
  try {
    const page = await browser.context.newPage();
    // ./no-models/ is the app's own test of a failed model load: its 404s are expected
    // (and DEEPREP_EXPECT_404's path: a test's deliberate miss)
    const miss = process.env.DEEPREP_EXPECT_404;
    const expected = (u) => (u || '').includes('/no-models/') || Boolean(miss && (u || '').endsWith(miss) && !(u || '').includes('/deeprep/'));
    const errors = [];
    // a failed load's console line names no URL; the response check below names it
    const loadFailure = (m) => Boolean(miss) && /^Failed to load resource/.test(m.text());
    page.on('console', (m) => { if (m.type() === 'error' && !expected(m.location()?.url) && !loadFailure(m)) errors.push(m.text()); });
    page.on('pageerror', (e) => errors.push(String(e)));
    page.on('response', (r) => { if (r.status() >= 400 && !expected(r.url())) errors.push(`HTTP ${r.status()} ${r.url()}`); });
    const t0 = Date.now();
    await page.goto(url);
    await page.waitForFunction(() => document.body.dataset.done || document.body.dataset.error, null, { timeout: 180_000 });
    const error = await page.evaluate(() => document.body.dataset.error);
    const out = await page.textContent('#out');
    if (error) failed = `the app failed: ${error}`;
    else if (errors.length) failed = `console errors: ${errors.join(' | ')}`;
    else {
      const d = await page.evaluate(() => ({ ...document.body.dataset }));
      firsts.push(Number(d.firstResultMs));
      firstSynth.push(Number(d.firstSynthesisMs));
      warmSynth.push(Number(d.warmSynthesisMs));
      stages.push(JSON.parse(d.stages));
      if (i === 0) console.log(`production build ran in Chromium in ${Date.now() - t0} ms: ${out}`);
    }
  } finally {
    await browser.close();
  }
}
server.close();
if (failed) { console.error(failed); process.exit(1); }
if (runs > 1) {
  const median = (v) => Math.round([...v].sort((a, b) => a - b)[Math.floor(v.length / 2)]);
  console.log(JSON.stringify({ bench: 'npm_first_result', dist, runs, first_result_ms: firsts.map((x) => Math.round(x)),
                               median_ms: median(firsts),
                               // the first synthesis after create() and the same request again
                               first_synthesis_ms: firstSynth.map((x) => Math.round(x)), median_first_synthesis_ms: median(firstSynth),
                               warm_synthesis_ms: warmSynth.map((x) => Math.round(x)), median_warm_synthesis_ms: median(warmSynth),
                               // ms from navigation to the start of each start-up stage, per run
                               stages_ms: stages }));
}
