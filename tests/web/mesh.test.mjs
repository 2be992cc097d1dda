// The mesh page in headless Chromium: loads the CC0 robot from the shared
// data set (skips without it), encodes a held-out pose, colors the error,
// shows the latent vertices, and edits one latent vertex locally (Fig. 2.7).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { launch, startServer, watchErrors, ROOT } from './chromium.mjs';

const GLB = path.resolve(process.env.DEEPREP_DATA || path.join(ROOT, '..', 'shared', 'data'), 'gltf', 'RobotExpressive.glb');
const HAVE_GLB = fs.existsSync(GLB);
if (!HAVE_GLB) console.log(`SKIP mesh page tests: ${GLB} is absent (the shared data set is not on this machine)`);

let browser, server;
before(async () => { if (!HAVE_GLB) return; server = await startServer(); browser = await launch(); });
after(async () => { await browser?.close(); await server?.close(); });

// Pixels in the latent-vertex color (cyan), in the error ramp's warm end
// (yellow to red), and anything drawn at all.
async function stats(page) {
  return page.evaluate(async () => {
    const d = await window.deeprepMesh.pixels();
    let lit = 0, cyan = 0, warm = 0;
    for (let i = 0; i < d.length; i += 4) {
      const [r, g, b] = [d[i], d[i + 1], d[i + 2]];
      if (Math.max(r, g, b) > 60) lit++;
      if (b > 150 && g > 130 && r < 110) cyan++;
      if (r > 150 && b < 90 && r > b + 90) warm++;
    }
    return { lit, cyan, warm, total: d.length / 4 };
  });
}

test('mesh page: encode a held-out pose, show the error and the latent vertices, edit one locally', { skip: !HAVE_GLB && 'no ../shared/data' }, async () => {
  const page = await browser.context.newPage();
  const errors = watchErrors(page);
  await page.goto(`${server.url}/web/mesh.html?webgl2`);
  await page.waitForSelector('body[data-ready="1"]', { timeout: 120_000 }).catch(async (e) => {
    throw new Error(`mesh page never became ready: ${await page.textContent('#status')} ${errors.join(' | ')} (${e.message})`);
  });
  assert.deepEqual(errors, []);
  const info = await page.evaluate(() => {
    const s = window.deeprepMesh;
    return { vertices: s.info.vertexCount, latent: s.info.latentVertices.length, names: s.info.latentNames,
             clip: s.info.clipNames[Number(document.getElementById('clip-a').value)],
             meanError: s.a.meanError, maxError: s.a.maxError, timing: s.timings.at(-1), view: document.body.dataset.view };
  });
  console.log(`mesh page: ${JSON.stringify(info)}`);
  assert.equal(info.view, 'webgl2');
  assert.equal(info.vertices, 1820);
  assert.equal(info.latent, 8);
  assert.equal(info.clip, 'Wave'); // held out of training
  for (const n of ['Palm2.L', 'Palm2.R', 'Foot.L_end', 'Foot.R_end', 'Head_end']) assert.ok(info.names.includes(n), n);
  assert.ok(info.meanError > 0 && info.meanError < 0.3, `reconstruction error ${info.meanError}`);

  const s1 = await stats(page);
  assert.ok(s1.lit > 0.02 * s1.total, `the mesh is not drawn: ${JSON.stringify(s1)}`);
  assert.ok(s1.cyan > 30, `latent vertices not drawn: ${JSON.stringify(s1)}`);
  await page.uncheck('#show-latent');
  const s2 = await stats(page);
  assert.ok(s2.cyan < s1.cyan / 3, `latent markers still drawn: ${JSON.stringify([s1, s2])}`);

  // Fig. 2.7: the right hand's latent vertex alone moves from Wave to Punch.
  await page.check('input[name=show][value=edit]');
  const hand = info.names.indexOf('Palm2.R');
  await page.selectOption('#latent', String(hand));
  await page.$eval('#blend', (el) => { el.value = '1'; el.dispatchEvent(new Event('input')); });
  await page.waitForSelector(`body[data-edited="${hand}:1"]`, { timeout: 60_000 });
  const edit = await page.evaluate(() => ({ inside: window.deeprepMesh.edit.inside, outside: window.deeprepMesh.edit.outside }));
  console.log(`edit of the right hand's latent vertex: mean move ${edit.inside.toFixed(3)} in its region, ${edit.outside.toFixed(3)} elsewhere`);
  assert.ok(edit.inside > 3 * edit.outside, JSON.stringify(edit));
  const s3 = await stats(page);
  assert.ok(s3.warm > 50, `the moved region is not colored: ${JSON.stringify(s3)}`);
  fs.mkdirSync(path.join(ROOT, 'tests/out'), { recursive: true });
  await page.screenshot({ path: path.join(ROOT, 'tests/out/mesh.png') });

  // t = 0 gives back A's reconstruction: nothing moves.
  await page.$eval('#blend', (el) => { el.value = '0'; el.dispatchEvent(new Event('input')); });
  await page.waitForSelector(`body[data-edited="${hand}:0"]`, { timeout: 60_000 });
  const still = await page.evaluate(() => window.deeprepMesh.edit.inside + window.deeprepMesh.edit.outside);
  assert.ok(still < 1e-5, `t = 0 moved the mesh by ${still}`);

  // A file that is not the robot gives a clear error and keeps the robot.
  await page.setInputFiles('#glb', { name: 'broken.glb', mimeType: 'model/gltf-binary', buffer: Buffer.from('not a glTF') });
  await page.waitForSelector('body[data-load-error]', { timeout: 30_000 });
  assert.match(await page.textContent('#status'), /cannot use broken\.glb: .*glTF/i);
  assert.equal(await page.evaluate(() => window.deeprepMesh.info.vertexCount), 1820);
  assert.deepEqual(errors, []);
  await page.close();
});

test('mesh page without the robot asks for the file, then loads it from the picker', { skip: !HAVE_GLB && 'no ../shared/data' }, async () => {
  const page = await browser.context.newPage();
  const errors = watchErrors(page);
  await page.goto(`${server.url}/web/mesh.html?glb=${encodeURIComponent('../nowhere/none.glb')}`);
  await page.waitForSelector('body[data-needs-glb="1"]', { timeout: 60_000 });
  assert.match(await page.textContent('#glb-note'), /file picker/);
  await page.setInputFiles('#glb', GLB);
  await page.waitForSelector('body[data-ready="1"]', { timeout: 120_000 });
  assert.ok(await page.evaluate(() => window.deeprepMesh.a.meanError < 0.3));
  // The only console error allowed is the 404 of the missing default file.
  assert.ok(errors.every((e) => /404/.test(e)), errors.join(' | '));
  await page.close();
});

test('mesh page: a non-robot mesh with its own model loads; with the robot model it is refused, saying why', async () => {
  // no shared data needed: the page starts without the robot
  if (!server) { server = await startServer(); browser = await launch(); }
  const page = await browser.context.newPage();
  const errors = watchErrors(page);
  await page.goto(`${server.url}/web/mesh.html?glb=${encodeURIComponent('../nowhere/none.glb')}`);
  await page.waitForSelector('body[data-needs-glb="1"]', { timeout: 60_000 });
  const dir = path.join(ROOT, 'tests/fixtures/mesh_tet');
  // the tet block with the bundled robot model: a clear refusal
  await page.setInputFiles('#user-mesh', path.join(dir, 'tet.obj'));
  await page.click('#user-load');
  await page.waitForSelector('body[data-load-error]', { timeout: 60_000 });
  const refusal = await page.textContent('#status');
  assert.match(refusal, /cannot use tet\.obj with the bundled robot model: this mesh welds to 112 vertices .* trained on RobotExpressive\.glb/);
  // with its own model (tests/fixtures/mesh_tet, trained 2 minutes): loaded, encoded, drawn
  await page.setInputFiles('#user-model', ['mesh_encoder.onnx', 'mesh_decoder.onnx', 'mesh_autoencoder.manifest.json'].map((f) => path.join(dir, f)));
  await page.click('#user-load');
  await page.waitForSelector('body[data-template="tet.obj"][data-ready="1"]', { timeout: 60_000 });
  assert.match(await page.textContent('#glb-note'), /112 welded vertices.*no clips/);
  const a = await page.evaluate(() => ({ err: window.deeprepMesh.a.meanError, n: window.deeprepMesh.a.positions.length / 3 }));
  assert.equal(a.n, 112);
  assert.ok(a.err < 0.1, `mean reconstruction error ${a.err} on a 1-unit block`);
  const s = await stats(page);
  assert.ok(s.lit > 0.005 * s.total, `drawn: ${JSON.stringify(s)}`);
  // a model with a missing file is refused before loading
  await page.setInputFiles('#user-model', [path.join(dir, 'mesh_encoder.onnx')]);
  await page.click('#user-load');
  await page.waitForFunction(() => /three files/.test(document.getElementById('status').textContent));
  assert.ok(errors.every((e) => /404/.test(e)), errors.join(' | '));
  await page.close();
});
