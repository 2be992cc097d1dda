// The mesh page: pose the CC0 robot, encode it with the fully convolutional
// mesh autoencoder (thesis ch. 2), see the reconstruction error per vertex,
// and move one latent vertex's code from pose A towards pose B (Fig. 2.7).
// The autoencoder runs in a worker (mesh-worker.js); the view is the
// crate's wgpu renderer (WebGPU, or WebGL2 when WebGPU is missing or its
// device is lost; `?webgl2` forces WebGL2).
import init from './pkg/deeprep.js';
import { latestRunner, workerClient } from './lib/workers.js';
import { openView, wireOrbit } from './lib/view.js';

const MODEL_BASE = new URL('../models/onnx', import.meta.url).href;
const params = new URLSearchParams(location.search);
// scripts/serve.mjs serves the shared data set's glTF files in place here.
const DEFAULT_GLB = params.get('glb') || new URL('../shared-data/gltf/RobotExpressive.glb', import.meta.url).href;
const ERROR_MAX = 0.2; // units (the robot is 4.46 tall): red in the error colors
const MOVE_MAX = 0.5; // units: red in the displacement colors
const $ = (id) => document.getElementById(id);

const state = {
  info: null,     // what the worker reports about the loaded robot
  a: null,        // { positions, codes, recon, error: Float32Array }
  b: null,        // { positions, codes }
  edit: null,     // { positions, moved: Float32Array, inside, outside }
  latent: 0,
  timings: [],    // [{ encodeMs, decodeMs }] of every encode in this page
  view: null,
};
window.deeprepMesh = state; // for tests and the console

function setStatus(text, error = false) {
  const s = $('status');
  s.textContent = text;
  s.classList.toggle('error', error);
}

// ---------------------------------------------------------------- worker
const client = workerClient(new URL('./mesh-worker.js', import.meta.url), {
  onProgress: (m) => setStatus(`${m.stage}…`),
  onError: (e) => setStatus(e.message, true),
});
const request = (msg) => client.request(msg);
const latestRaw = latestRunner({
  onError: (e) => { setStatus(`error: ${e.message}`, true); console.warn(e); },
  onIdle: () => { document.body.dataset.busy = '0'; },
});
const latest = (kind, fn) => latestRaw(kind, fn);

// ---------------------------------------------------------------- view
let attachCanvas = null;
async function onViewReplaced(view) {
  attachCanvas(view.canvas());
  document.body.dataset.view = view.name();
  $('view-badge').textContent = view.name();
  setupView(true);
  draw();
}

function setupView(frame) {
  const v = state.view.viewer;
  if (!state.info) return;
  v.setGrid(6, 0.5, state.info.ground);
  const shown = shownPositions();
  if (shown) v.setMesh(shown.positions, state.info.triangles, new Float32Array(0), 1);
  if (frame) v.frame();
}

function highestY(p) {
  let y = -Infinity;
  for (let i = 1; i < p.length; i += 3) y = Math.max(y, p[i]);
  return Number.isFinite(y) ? y : 0;
}

function lowestY(p) {
  let y = Infinity;
  for (let i = 1; i < p.length; i += 3) y = Math.min(y, p[i]);
  return Number.isFinite(y) ? y : 0;
}

function mode() { return document.querySelector('input[name=show]:checked').value; }

// What the view shows: positions and per-vertex values (with their scale).
function shownPositions() {
  const m = mode();
  if (m === 'input' && state.a) return { positions: state.a.positions, values: new Float32Array(0), max: 1 };
  if (m === 'recon' && state.a) return { positions: state.a.recon, values: state.a.error, max: ERROR_MAX };
  if (m === 'edit' && state.edit) return { positions: state.edit.positions, values: state.edit.moved, max: MOVE_MAX };
  return state.a ? { positions: state.a.positions, values: new Float32Array(0), max: 1 } : null;
}

function draw() {
  if (!state.view || state.view.replacing) return;
  if (state.view.viewer.deviceLost) { state.view.ensure(); return; }
  const v = state.view.viewer;
  const shown = shownPositions();
  if (shown) {
    v.setMesh(shown.positions, state.info.triangles, shown.values, shown.max);
    const marks = $('show-latent').checked ? latentPoints(shown.positions) : new Float32Array(0);
    v.setMarkers(marks.length ? marks : new Float32Array(0), 0.09, marks.length ? state.latent : -1);
    $('legend-max').textContent = shown.values.length ? `${shown.max} units${mode() === 'recon' ? ' of error' : ' moved'} and more` : 'no colors';
  }
  const c = state.view.canvas();
  v.resize(c.width, c.height);
  v.render();
}

// RGBA pixels of the view, read right after drawing (for tests).
state.pixels = async () => state.view.pixels(draw);

function latentPoints(p) {
  const out = new Float32Array(state.info.latentVertices.length * 3);
  state.info.latentVertices.forEach((v, i) => out.set(p.subarray(3 * v, 3 * v + 3), 3 * i));
  return out;
}

// ---------------------------------------------------------------- model
function distances(p, q) {
  const d = new Float32Array(p.length / 3);
  for (let i = 0; i < d.length; i++) {
    d[i] = Math.hypot(p[3 * i] - q[3 * i], p[3 * i + 1] - q[3 * i + 1], p[3 * i + 2] - q[3 * i + 2]);
  }
  return d;
}
const mean = (a) => a.reduce((s, x) => s + x, 0) / Math.max(a.length, 1);

async function poseOf(which) {
  // a template without clips: random smooth deformations (seed per pose slot)
  if (!state.info.clipNames.length) return (await request({ type: 'random', seed: which === 'a' ? 1 : 2, degrees: 30 })).positions;
  const clip = Number($(`clip-${which}`).value);
  const time = Number($(`time-${which}`).value) * state.info.clipDurations[clip];
  return (await request({ type: 'pose', clip, time })).positions;
}

async function encodePose(which, positions) {
  const r = await request({ type: 'encode', positions });
  state.timings.push({ encodeMs: r.encodeMs, decodeMs: r.decodeMs });
  const entry = { positions, codes: r.codes, recon: r.recon, error: distances(positions, r.recon) };
  state[which] = entry;
  if (which === 'a') {
    const err = entry.error;
    entry.meanError = mean(err);
    entry.maxError = err.reduce((m, x) => Math.max(m, x), 0);
  }
}

async function updatePose(which, positions) {
  await encodePose(which, positions ?? await poseOf(which));
  await updateEdit();
}

async function updateEdit() {
  if (!state.a || !state.b) return;
  const t = Number($('blend').value);
  const r = await request({ type: 'blend', a: state.a.codes, b: state.b.codes, vertex: state.latent, t });
  const moved = distances(state.a.recon, r.positions);
  const regions = state.info.latentRegions;
  const inside = [], outside = [];
  moved.forEach((d, i) => (regions[i] === state.latent ? inside : outside).push(d));
  state.edit = { positions: r.positions, moved, inside: mean(inside), outside: mean(outside), decodeMs: r.decodeMs, vertex: state.latent, t };
  document.body.dataset.edited = `${state.latent}:${t}`;
  showNumbers();
  draw();
}

function showNumbers() {
  const rows = [];
  const fmt = (x, d = 3) => (x == null ? '–' : x.toFixed(d));
  if (state.a) {
    rows.push(['A: mean error (units)', fmt(state.a.meanError)]);
    rows.push(['A: max error (units)', fmt(state.a.maxError)]);
    rows.push([`A: mean error / ${state.info.source}'s height`, `${fmt((100 * state.a.meanError) / state.info.height, 2)} %`]);
  }
  const t = state.timings.at(-1);
  if (t) rows.push(['encode / decode (ms, in the worker)', `${fmt(t.encodeMs, 0)} / ${fmt(t.decodeMs, 0)}`]);
  if (state.edit) {
    rows.push(['edit: mean move in the vertex\'s region', fmt(state.edit.inside)]);
    rows.push(['edit: mean move elsewhere', fmt(state.edit.outside)]);
  }
  const table = $('numbers');
  table.replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement('tr');
    for (const x of [k, v]) { const td = document.createElement('td'); td.textContent = x; tr.append(td); }
    return tr;
  }));
}

// ---------------------------------------------------------------- loading
// A mesh (glb bytes or obj text) with the bundled model or the user's
// ({encoder, decoder, manifest}); the worker refuses, with the reason, a
// model trained on another mesh, and keeps what it had.
async function loadTemplate({ glb, obj, models }, source) {
  setStatus(`reading ${source}…`);
  const info = await request({ type: 'init', glb, obj, models, modelBase: MODEL_BASE });
  info.ground = 0;
  info.source = source;
  state.info = info;
  state.a = state.b = state.edit = null;
  for (const w of ['a', 'b']) {
    const sel = $(`clip-${w}`);
    sel.replaceChildren(...info.clipNames.map((n, i) => new Option(n, String(i))));
  }
  // Defaults: two clips held out of training (Wave, Punch).
  const pick = (name, fallback) => {
    const i = info.clipNames.indexOf(name);
    return String(i >= 0 ? i : Math.min(fallback, info.clipNames.length - 1));
  };
  $('clip-a').value = pick('Wave', 0);
  $('clip-b').value = pick('Punch', 1);
  $('latent').replaceChildren(...info.latentVertices.map((v, i) =>
    new Option(`${i}: ${info.latentNames[i] || 'sampled'} (vertex ${v})`, String(i))));
  const hand = info.latentNames.indexOf('Palm2.R');
  state.latent = hand >= 0 ? hand : 0;
  $('latent').value = String(state.latent);
  for (const w of ['a', 'b']) for (const id of [`clip-${w}`, `time-${w}`]) $(id).disabled = !info.clipNames.length;
  await encodePose('b', await poseOf('b'));
  await updatePose('a');
  info.ground = lowestY(state.a.positions);
  info.height = Math.max(1e-6, highestY(state.a.positions) - info.ground);
  setupView(true);
  showNumbers();
  draw();
  $('glb-note').textContent = `${source}: ${info.vertexCount} welded vertices, ${info.triangles.length / 3} triangles, `
    + (info.clipNames.length ? `${info.clipNames.length} clips` : 'no clips (poses are random smooth deformations)');
  document.body.dataset.template = source;
  setStatus('ready');
}

async function loadRobot(bytes, source) { return loadTemplate({ glb: bytes }, source); }

// The "Your mesh and model" section: an OBJ or glTF, and optionally the
// three model files (told apart by name: *encoder*.onnx, *decoder*.onnx, *.json).
async function loadUserFiles() {
  const mesh = $('user-mesh').files[0];
  if (!mesh) { setStatus('choose a mesh file first', true); return; }
  const files = [...$('user-model').files];
  const find = (test) => files.find((f) => test(f.name.toLowerCase()));
  let models;
  if (files.length) {
    const [enc, dec, man] = [find((n) => n.includes('encoder') && n.endsWith('.onnx')), find((n) => n.includes('decoder') && n.endsWith('.onnx')), find((n) => n.endsWith('.json'))];
    if (!enc || !dec || !man) { setStatus('the model needs three files: an encoder .onnx, a decoder .onnx and its manifest .json', true); return; }
    models = { encoder: await enc.arrayBuffer(), decoder: await dec.arrayBuffer(), manifest: await man.text() };
  }
  const isObj = mesh.name.toLowerCase().endsWith('.obj');
  try {
    await loadTemplate(isObj ? { obj: await mesh.text(), models } : { glb: await mesh.arrayBuffer(), models }, mesh.name);
    delete document.body.dataset.loadError;
    delete document.body.dataset.needsGlb;
    document.body.dataset.ready = '1';
  } catch (err) {
    setStatus(`cannot use ${mesh.name}${models ? ' with that model' : ' with the bundled robot model'}: ${err.message}`, true);
    document.body.dataset.loadError = err.message;
  }
}

async function loadDefault() {
  let r;
  try {
    r = await fetch(DEFAULT_GLB);
  } catch (e) {
    r = null;
  }
  if (!r || !r.ok) {
    $('glb-note').textContent = 'The robot model (RobotExpressive.glb) is not on this site: choose a rigged .glb with the file picker above to see it here. (Site owners: scripts/build-site.sh copies it in when ../shared/data is present; the demo server serves it from there.)';
    setStatus('waiting for the robot glTF');
    document.body.dataset.needsGlb = '1';
    return;
  }
  await loadRobot(await r.arrayBuffer(), 'RobotExpressive.glb');
}

// ---------------------------------------------------------------- input
function pickLatent(x, y) {
  const hit = state.view ? state.view.viewer.pickJoint(x, y) : -1;
  if (hit >= 0 && state.info && hit < state.info.latentVertices.length) {
    state.latent = hit;
    $('latent').value = String(hit);
    latest('edit', updateEdit);
  }
}

function wireInput() {
  attachCanvas = wireOrbit(state.view, draw, pickLatent);
  for (const w of ['a', 'b']) {
    const refresh = () => latest(`pose-${w}`, async () => { if (w === 'a') await updatePose('a'); else { await encodePose('b', await poseOf('b')); await updateEdit(); } draw(); });
    $(`clip-${w}`).addEventListener('change', refresh);
    $(`time-${w}`).addEventListener('input', refresh);
    $(`random-${w}`).addEventListener('click', () => latest(`pose-${w}`, async () => {
      const seed = Math.floor(Math.random() * 2 ** 31);
      const { positions } = await request({ type: 'random', seed, degrees: 30 });
      if (w === 'a') await updatePose('a', positions); else { await encodePose('b', positions); await updateEdit(); }
      draw();
    }));
  }
  $('latent').addEventListener('change', () => { state.latent = Number($('latent').value); latest('edit', updateEdit); });
  $('blend').addEventListener('input', () => latest('edit', updateEdit));
  for (const r of document.querySelectorAll('input[name=show]')) r.addEventListener('change', draw);
  $('show-latent').addEventListener('change', draw);
  $('user-load').addEventListener('click', loadUserFiles);
  $('glb').addEventListener('change', async (e) => {
    const f = e.target.files[0];
    if (!f) return;
    try {
      await loadRobot(await f.arrayBuffer(), f.name);
      delete document.body.dataset.needsGlb;
      document.body.dataset.ready = '1';
    } catch (err) {
      // The robot already loaded (if any) stays usable.
      setStatus(`cannot use ${f.name}: ${err.message}`, true);
      document.body.dataset.loadError = err.message;
    }
  });
}

async function main() {
  await init();
  try {
    state.view = await openView('view', params.has('webgl2'), onViewReplaced);
  } catch (e) {
    throw new Error(`this page needs WebGPU or WebGL2 (${e.message})`);
  }
  wireInput();
  document.body.dataset.view = state.view.name();
  $('view-badge').textContent = state.view.name();
  await loadDefault();
  // A GPU device lost right after its first frames (headless Chromium's
  // WebGPU cannot present a canvas) is replaced before the page says ready.
  draw();
  await new Promise((r) => setTimeout(r, 200));
  draw();
  if (state.view.replacing) await state.view.replacing;
  if (state.info) document.body.dataset.ready = '1';
}

main().catch((e) => { setStatus(`error: ${e.message}`, true); console.error(e); });
