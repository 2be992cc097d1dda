// scripts/serve.mjs (the demo and test server) answers malformed requests
// with 400 and keeps serving (issue 22: one bad percent-escape used to stop it).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import http from 'node:http';
import { serve } from '../../scripts/serve.mjs';
import { ROOT } from './chromium.mjs';

function get(port, path) {
  return new Promise((resolve, reject) => {
    http.get({ host: '127.0.0.1', port, path }, (r) => { r.resume(); r.on('end', () => resolve(r.statusCode)); }).on('error', reject);
  });
}

test('serve.mjs: malformed URLs get 400, the server keeps serving', async () => {
  const server = await serve(ROOT, 0);
  const port = server.address().port;
  try {
    assert.equal(await get(port, '/%E0%A4%A'), 400);
    assert.equal(await get(port, '/%'), 400);
    assert.equal(await get(port, '/web/%00.html'), 400);
    assert.equal(await get(port, '/web/../../etc/passwd'), 404);
    assert.equal(await get(port, '/web/index.html'), 200);
  } finally {
    server.close();
  }
});
