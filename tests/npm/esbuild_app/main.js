// The app tests/npm/esbuild_smoke.sh bundles with plain esbuild (which does
// not follow `new URL('./worker.js', import.meta.url)`): without options the
// client either works or rejects with E_WORKER naming the worker URL it
// tried; with the README's recipe (the package's worker.js, core/, lib/ and
// models/ copied to deeprep/ beside the bundle, `workerUrl` given) it
// in-betweens a clip. Sets body[data-done] or body[data-error].
import { DeeprepClient } from 'deeprep/client.js';
try {
  const plain = await DeeprepClient.create().then((c) => { c.terminate(); return 'works'; }, (e) => e);
  if (plain !== 'works' && !(plain.code === 'E_WORKER' && /worker\.js/.test(plain.message))) {
    throw new Error(`plain esbuild: ${plain.code} ${plain.message}`);
  }
  const client = await DeeprepClient.create({ workerUrl: './deeprep/worker.js' });
  const head = client.skeletonBvh.replace(/MOTION[\s\S]*/, '');
  const n = client.skeletonBvh.split('CHANNELS').slice(1).reduce((a, s) => a + Number(s.trim().split(/\s+/)[0]), 0);
  const rows = Array.from({ length: 61 }, (_, f) => Array.from({ length: n }, (_, i) => (i === 0 ? f : i === 1 ? 90 : 0)).join(' '));
  const r = await client.synthesizeFromBvh(`${head}MOTION\nFrames: 61\nFrame Time: 0.0166667\n${rows.join('\n')}\n`, { keys: [0, 60] });
  if (r.frames !== 61) throw new Error(`${r.frames} frames`);
  document.body.dataset.firstResultMs = String(performance.now());
  document.body.dataset.firstSynthesisMs = '0';
  document.body.dataset.warmSynthesisMs = '0';
  document.body.dataset.stages = '{}';
  document.getElementById('out').textContent = `plain esbuild: ${plain === 'works' ? 'works' : `${plain.code} naming the worker URL`}; the recipe: ${r.frames} frames by ${r.ran}`;
  document.body.dataset.done = '1';
} catch (e) {
  document.body.dataset.error = `${e.code || ''} ${e.message}`;
}
