// The static site (web/dist, written by scripts/build-site.sh) works from a
// plain static server rooted at web/dist, with nothing else reachable.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { launch, watchErrors, ROOT } from './chromium.mjs';
import { serve } from '../../scripts/serve.mjs';

const DIST = path.join(ROOT, 'web/dist');

test('web/dist serves the sketching page on its own', { skip: !fs.existsSync(DIST) && 'SKIP: run scripts/build-site.sh first' }, async () => {
  const server = await serve(DIST, 0);
  const browser = await launch();
  try {
    const page = await browser.context.newPage();
    const errors = watchErrors(page);
    await page.goto(`http://127.0.0.1:${server.address().port}/`);
    await page.waitForSelector('body[data-ready="1"]', { timeout: 120_000 });
    assert.deepEqual(errors, []);
    assert.ok(Number(await page.getAttribute('body', 'data-synthesized')) > 0);
  } finally {
    await browser.close();
    await new Promise((r) => server.close(r));
  }
});
