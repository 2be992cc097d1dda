// The hair page: a procedural test render goes through HairNet (in a
// worker), its strand features are upsampled to thousands of strands,
// smoothed and curled, and drawn around the collision body; two results
// interpolate in strand-feature space (Fig. B.2).
import init from './pkg/deeprep.js';
import { latestRunner, workerClient } from './lib/workers.js';
import { openView, wireOrbit } from './lib/view.js';

const MODEL_BASE = new URL('../models/onnx', import.meta.url).href;
const params = new URLSearchParams(location.search);
const HAIR_COLOR = [0.78, 0.55, 0.32, 1];
const TRUTH_COLOR = [0.45, 0.75, 0.95, 1];
const $ = (id) => document.getElementById(id);

const state = {
  info: null,       // classNames, body mesh
  image: null,      // the current input, 3 x 256 x 256
  truth: null,      // its procedural hair, 1024 x 100 x 3
  features: null,   // the network's strand features for it
  strands: null,    // { points, count, ms, collision }
  featuresMs: null,
  a: null, b: null, // kept strand features for interpolation
  view: null,
  error: null,      // mean distance to the truth (1,024-strand reconstructions)
};
window.deeprepHair = state; // for tests and the console

function setStatus(text, error = false) {
  const s = $('status');
  s.textContent = text;
  s.classList.toggle('error', error);
}

const client = workerClient(new URL('./hair-worker.js', import.meta.url), { onError: (e) => setStatus(e.message, true) });
const latest = latestRunner({ onError: (e) => { setStatus(`error: ${e.message}`, true); console.warn(e); } });

// ---------------------------------------------------------------- view
let attachCanvas = null;
async function onViewReplaced(view) {
  attachCanvas(view.canvas());
  document.body.dataset.view = view.name();
  $('view-badge').textContent = view.name();
  upload(true);
  // Chromium drops the 2-D canvases' contents with the lost GPU device: the input again
  if (state.image) showInput(state.image);
}

function shownPoints() {
  if ($('show').value === 'truth') return state.truth ? { points: state.truth, color: TRUTH_COLOR } : null;
  return state.strands ? { points: state.strands.points, color: HAIR_COLOR } : null;
}

// Sends the body and the shown strands to the viewer (the strands' GPU
// buffer is rebuilt only here, not every frame).
function upload(frame = false) {
  const v = state.view.viewer;
  if (!state.info) return;
  v.setGrid(0, 1, 0);
  v.setMesh(state.info.bodyPositions, state.info.bodyTriangles, new Float32Array(0), 1);
  const shown = shownPoints();
  v.setStrands(shown ? shown.points : new Float32Array(0), 100, Float32Array.from(shown ? shown.color : HAIR_COLOR));
  if (frame) v.frame();
  draw();
}

function draw() {
  if (!state.view || state.view.replacing) return;
  if (state.view.viewer.deviceLost) { state.view.ensure(); return; }
  const c = state.view.canvas();
  state.view.viewer.resize(c.width, c.height);
  state.view.viewer.render();
}
state.pixels = async () => state.view.pixels(draw);

function showInput(image) {
  const canvas = $('input');
  if (!canvas.dataset.restores) {
    // a 2-D canvas whose GPU context is lost and restored comes back blank
    canvas.addEventListener('contextrestored', () => { if (state.image) showInput(state.image); });
    canvas.dataset.restores = '1';
  }
  const ctx = canvas.getContext('2d');
  const img = ctx.createImageData(256, 256);
  const plane = 256 * 256;
  for (let i = 0; i < plane; i++) {
    img.data[4 * i] = 255 * image[i];
    img.data[4 * i + 1] = 255 * image[plane + i];
    img.data[4 * i + 2] = 255 * image[2 * plane + i];
    img.data[4 * i + 3] = 255;
  }
  ctx.putImageData(img, 0, 0);
}

// ---------------------------------------------------------------- pipeline
function options() {
  return { count: Number($('count').value), smooth: $('smooth').checked ? 1.5 : 0, curl: $('curls').checked ? 15 : Infinity };
}

async function decode(features) {
  const o = options();
  let r;
  try {
    r = await client.request({ type: 'strands', features, count: o.count, smooth: o.smooth, curl: o.curl, gpu: $('device').value === 'gpu' });
  } catch (e) {
    if ($('device').value !== 'gpu') throw e;
    // no WebGPU compute here: back to the CPU path, and say so
    $('device').value = 'cpu';
    setStatus(`WebGPU decoding unavailable (${e.message}); using the CPU`, true);
    r = await client.request({ type: 'strands', features, count: o.count, smooth: o.smooth, curl: o.curl, gpu: false });
  }
  state.strands = { points: r.points, count: o.count, ms: r.ms, collision: r.collision, device: r.device };
  // at 1,024 strands, strand i grows from the truth's root i: compare them
  state.error = null;
  if (o.count === 1024 && state.truth && features === state.features) {
    let s = 0;
    for (let i = 0; i < state.truth.length; i += 3) {
      s += Math.hypot(r.points[i] - state.truth[i], r.points[i + 1] - state.truth[i + 1], r.points[i + 2] - state.truth[i + 2]);
    }
    state.error = s / (state.truth.length / 3);
  }
  showNumbers();
  upload();
  document.body.dataset.strands = `${o.count}`;
  document.body.dataset.decoded = `${r.device}:${o.count}:${o.curl}`;
}

async function reconstruct() {
  const cls = $('cls').value, seed = Number($('seed').value), yaw = Number($('yaw').value);
  setStatus('rendering the input…');
  const t = await client.request({ type: 'test', cls, seed, yaw });
  state.image = t.image;
  state.truth = t.truth;
  showInput(t.image);
  setStatus('HairNet…');
  const f = await client.request({ type: 'features', image: t.image });
  state.features = f.features;
  state.featuresMs = f.ms;
  await decode(f.features);
  $('blend').value = '0';
  setStatus('ready');
  document.body.dataset.input = `${cls}:${seed}:${yaw}`;
}

// Grey values and a mask from image files, at most 512 px on a side.
async function pixelsOf(file) {
  const bmp = await createImageBitmap(file);
  const k = Math.min(1, 512 / Math.max(bmp.width, bmp.height));
  const [w, h] = [Math.max(1, Math.round(bmp.width * k)), Math.max(1, Math.round(bmp.height * k))];
  const c = new OffscreenCanvas(w, h);
  const ctx = c.getContext('2d');
  ctx.drawImage(bmp, 0, 0, w, h);
  const d = ctx.getImageData(0, 0, w, h).data;
  const grey = new Float32Array(w * h);
  for (let i = 0; i < w * h; i++) grey[i] = (0.299 * d[4 * i] + 0.587 * d[4 * i + 1] + 0.114 * d[4 * i + 2]) / 255;
  return { grey, w, h };
}

async function fromPhoto() {
  const [photo, mask] = [$('photo').files[0], $('mask').files[0]];
  if (!photo || !mask) throw new Error('choose a photo and its hair mask');
  setStatus('orientation filter…');
  const [p, m] = await Promise.all([pixelsOf(photo), pixelsOf(mask)]);
  if (p.w !== m.w || p.h !== m.h) throw new Error(`the mask (${m.w}×${m.h}) must have the photo's size (${p.w}×${p.h})`);
  const r = await client.request({ type: 'photo', grey: p.grey, hair: m.grey, w: p.w, h: p.h });
  state.image = r.image;
  state.truth = null;
  showInput(r.image);
  setStatus('HairNet…');
  const f = await client.request({ type: 'features', image: r.image });
  state.features = f.features;
  state.featuresMs = f.ms;
  await decode(f.features);
  setStatus(`ready (orientation filter ${r.ms.toFixed(0)} ms)`);
  document.body.dataset.input = `photo:${photo.name}`;
}

async function blend() {
  if (!state.a || !state.b) return;
  const t = Number($('blend').value);
  const f = new Float32Array(state.a.length);
  for (let i = 0; i < f.length; i++) f[i] = state.a[i] + t * (state.b[i] - state.a[i]);
  await decode(f);
  document.body.dataset.blend = String(t);
}

function showNumbers() {
  const fmt = (x, d = 1) => (x == null || !Number.isFinite(x) ? '–' : x.toFixed(d));
  const rows = [
    ['HairNet: image → features (ms)', fmt(state.featuresMs)],
    [`strands: upsample + MLPs + smoothing/curls (ms, ${state.strands ? `${state.strands.count}, ${state.strands.device}` : '–'})`, fmt(state.strands?.ms)],
    ['collision error (eq. 3.3)', state.strands ? state.strands.collision.toExponential(2) : '–'],
    ['mean distance to the truth (cm, 1,024 strands)', state.error == null ? 'pick 1,024' : fmt(100 * state.error, 2)],
  ];
  $('numbers').replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement('tr');
    for (const x of [k, v]) { const td = document.createElement('td'); td.textContent = x; tr.append(td); }
    return tr;
  }));
}

function wireInput() {
  attachCanvas = wireOrbit(state.view, draw);
  for (const id of ['cls', 'seed', 'yaw']) $(id).addEventListener('change', () => latest('recon', reconstruct));
  for (const id of ['count', 'smooth', 'curls', 'device']) $(id).addEventListener('change', () => latest('decode', () => decode(state.features)));
  $('show').addEventListener('change', () => upload());
  const keep = (k) => {
    if (!state.features) return;
    state[k] = Float32Array.from(state.features);
    $(`keep-${k}`).textContent = `${k.toUpperCase()}: ${$('cls').value} #${$('seed').value}`;
    $('blend').disabled = !(state.a && state.b);
  };
  $('keep-a').addEventListener('click', () => keep('a'));
  $('keep-b').addEventListener('click', () => keep('b'));
  $('blend').addEventListener('input', () => latest('decode', blend));
  const photoReady = () => { $('from-photo').disabled = !($('photo').files[0] && $('mask').files[0]); };
  $('photo').addEventListener('change', photoReady);
  $('mask').addEventListener('change', photoReady);
  $('from-photo').addEventListener('click', () => latest('recon', fromPhoto));
}

async function main() {
  await init();
  try {
    state.view = await openView('view', params.has('webgl2'), onViewReplaced);
  } catch (e) {
    throw new Error(`this page needs WebGPU or WebGL2 (${e.message})`);
  }
  document.body.dataset.view = state.view.name();
  $('view-badge').textContent = state.view.name();
  wireInput();
  setStatus('loading HairNet in a worker…');
  state.info = await client.request({ type: 'init', modelBase: MODEL_BASE });
  $('cls').replaceChildren(...state.info.classNames.map((n) => new Option(n, n)));
  $('cls').value = params.get('class') || 'L-wavy';
  await reconstruct();
  upload(true);
  await new Promise((r) => setTimeout(r, 200));
  draw();
  if (state.view.replacing) await state.view.replacing;
  document.body.dataset.ready = '1';
}

main().catch((e) => { setStatus(`error: ${e.message}`, true); console.error(e); });
