// The deeprep demo page. Loads the wasm package and draws Figure C.1 live.
import init, * as deeprep from './pkg/deeprep.js';

const ROWS = [
  ['SO(3) matrix', 'matrix'],
  ['6D', '6d'],
  ['5D', '5d'],
  ['Unit quaternion (eq. C.8)', 'quat_gu'],
  ['Axis-angle', 'axis_angle'],
  ['Euler angles (XYZ)', 'euler:XYZ'],
];
const AXES = ['x', 'y', 'z'];
const STEPS = 720;

const status = document.getElementById('status');
function setStatus(text, isError = false) {
  status.textContent = text;
  status.classList.toggle('error', isError);
}

function drawCell(ctx, x0, y0, w, h, pts, label) {
  ctx.strokeStyle = '#263040';
  ctx.strokeRect(x0 + 0.5, y0 + 0.5, w - 1, h - 1);
  let minX = Infinity, maxX = -Infinity, minY = Infinity, maxY = -Infinity;
  for (let i = 0; i < pts.length; i += 2) {
    minX = Math.min(minX, pts[i]); maxX = Math.max(maxX, pts[i]);
    minY = Math.min(minY, pts[i + 1]); maxY = Math.max(maxY, pts[i + 1]);
  }
  const span = Math.max(maxX - minX, maxY - minY, 1e-6);
  const s = (Math.min(w, h) - 40) / span;
  const cx = x0 + w / 2, cy = y0 + h / 2 + 8;
  const mx = (minX + maxX) / 2, my = (minY + maxY) / 2;
  const n = pts.length / 2;
  for (let i = 0; i < n; i++) {
    ctx.fillStyle = `hsl(${(360 * i) / n}, 85%, 60%)`;
    ctx.beginPath();
    ctx.arc(cx + (pts[2 * i] - mx) * s, cy - (pts[2 * i + 1] - my) * s, 2.2, 0, 2 * Math.PI);
    ctx.fill();
  }
  if (label) {
    ctx.fillStyle = '#8a96a3';
    ctx.font = '20px system-ui';
    ctx.fillText(label, x0 + 8, y0 + 24);
  }
}

function maxJump(v, dim) {
  let m = 0;
  for (let i = dim; i < v.length; i += dim) {
    let d = 0;
    for (let k = 0; k < dim; k++) d += (v[i + k] - v[i - dim + k]) ** 2;
    m = Math.max(m, Math.sqrt(d));
  }
  return m;
}

async function drawFigure() {
  const canvas = document.getElementById('figure');
  const ctx = canvas.getContext('2d');
  ctx.fillStyle = '#0b0e11';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  const w = canvas.width / 3, h = canvas.height / ROWS.length;
  const tbody = document.querySelector('#jumps tbody');
  tbody.innerHTML = '';
  ROWS.forEach(([title, repr], r) => {
    const dim = deeprep.rotationDim(repr);
    const tr = document.createElement('tr');
    tr.innerHTML = `<td>${title}</td>`;
    AXES.forEach((axis, c) => {
      const v = deeprep.rotationCircle(repr, axis, STEPS);
      const pts = deeprep.pca2d(v, dim);
      drawCell(ctx, c * w, r * h, w, h, pts, `${title} · ${axis.toUpperCase()}`);
      const td = document.createElement('td');
      const j = maxJump(v, dim);
      td.textContent = j.toFixed(3);
      if (j > 0.2) td.style.color = '#ff9b6b';
      tr.appendChild(td);
    });
    tbody.appendChild(tr);
  });
}

async function runOnnx() {
  const el = document.getElementById('onnx');
  const res = await fetch('../models/onnx/rot6d_autoencoder.onnx');
  if (!res.ok) throw new Error(`could not fetch the model (${res.status})`);
  const model = new deeprep.OnnxModel(new Uint8Array(await res.arrayBuffer()));
  // 64 rotations about a tilted axis, through the network and back.
  const n = 64;
  const aa = new Float32Array(n * 4);
  for (let i = 0; i < n; i++) aa.set([0.3, 0.8, 0.52, (Math.PI * i) / n], 4 * i);
  const mats = deeprep.convertRotations('axis_angle', 'matrix', aa);
  const t0 = performance.now();
  const out = model.run(mats, new Uint32Array([n, 9]));
  const ms = performance.now() - t0;
  const err = deeprep.geodesicDistances('matrix', mats, out);
  let mean = 0, max = 0;
  for (const e of err) { mean += e / n; max = Math.max(max, e); }
  const deg = (x) => ((x * 180) / Math.PI).toFixed(2);
  el.innerHTML = `tract ran the 6D autoencoder on ${n} rotations in ${ms.toFixed(1)} ms: `
    + `mean error <code>${deg(mean)}°</code>, max <code>${deg(max)}°</code>.`;
  el.dataset.meanDeg = deg(mean);
}

async function main() {
  const t0 = performance.now();
  await init();
  setStatus(`deeprep ${deeprep.version()} loaded in ${(performance.now() - t0).toFixed(0)} ms`);
  await drawFigure();
  try {
    await runOnnx();
  } catch (e) {
    document.getElementById('onnx').textContent = `ONNX demo unavailable: ${e.message}`;
    throw e;
  }
  document.body.dataset.ready = '1';
}

main().catch((e) => {
  setStatus(`error: ${e.message}`, true);
  console.error(e);
});
