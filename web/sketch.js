// The keyframe-sketching page. Synthesis runs in a Web Worker (client.js);
// the main thread keeps the keys, draws, and never loses them on errors.
// The view is the crate's wgpu renderer (WebGPU, or WebGL2 as the fallback;
// `?webgl2` forces WebGL2); a 2-D canvas projection remains as the last
// resort when neither is available (`?view=2d` forces it).
import init, { BvhClip, Viewer } from './pkg/deeprep.js';
import { DeeprepClient } from './client.js';

const MODEL_BASE = new URL('../models/onnx', import.meta.url).href;
const EXAMPLES = new URL('../models/examples', import.meta.url).href;
const $ = (id) => document.getElementById(id);

const state = {
  skeleton: null,      // { header, names, parents, channels }
  library: [],         // [{ name, channels }]
  keys: [],            // [{ frame, channels }] (a pose) or [{ frame, root }] (a root-only key), sorted by frame
  length: 300,
  frame: 0,
  playing: false,
  result: null,        // { positions, frames, bvh, method, times }
  selected: -1,        // joint index
  undo: [], redo: [],
  cam: { yaw: 0.6, pitch: 0.35, dist: 520, target: [0, 80, 0] },
  fkCache: new Map(),
  client: null,
  view: null,          // see createView()
  dragPose: null,      // joint positions while a joint is dragged
};

function setStatus(text, error = false) {
  $('status').textContent = text;
  $('status').classList.toggle('error', error);
}

// ---------------------------------------------------------------- skeleton
function parseSkeleton(bvhText) {
  const header = bvhText.slice(0, bvhText.indexOf('MOTION'));
  const clip = BvhClip.parse(`${header}MOTION\nFrames: 0\nFrame Time: 0.0166667\n`);
  const s = { header, names: clip.jointNames, parents: Array.from(clip.parents), channels: clip.channelCount };
  clip.free();
  return s;
}

function fk(channels) {
  const k = channels.join(' ');
  let p = state.fkCache.get(k);
  if (!p) {
    const clip = BvhClip.parse(`${state.skeleton.header}MOTION\nFrames: 1\nFrame Time: 0.0166667\n${k}\n`);
    p = clip.fkPositions(0, 1);
    clip.free();
    if (state.fkCache.size > 500) state.fkCache.clear();
    state.fkCache.set(k, p);
  }
  return p;
}

// ---------------------------------------------------------------- history
function snapshot() { return JSON.stringify({ keys: state.keys, length: state.length }); }
function pushHistory() { state.undo.push(snapshot()); state.redo.length = 0; if (state.undo.length > 200) state.undo.shift(); }
function restore(s) { const o = JSON.parse(s); state.keys = o.keys; state.length = o.length; $('length').value = o.length; refreshTimeline(); draw(); }
function undo() { if (!state.undo.length) return; state.redo.push(snapshot()); restore(state.undo.pop()); }
function redo() { if (!state.redo.length) return; state.undo.push(snapshot()); restore(state.redo.pop()); }

// ---------------------------------------------------------------- camera and drawing
function camera(canvas) {
  const { yaw, pitch, dist, target } = state.cam;
  const eye = [target[0] + dist * Math.cos(pitch) * Math.sin(yaw), target[1] + dist * Math.sin(pitch), target[2] + dist * Math.cos(pitch) * Math.cos(yaw)];
  const f = norm(sub(target, eye));
  const r = norm(cross(f, [0, 1, 0]));
  const u = cross(r, f);
  const focal = canvas.height * 1.3;
  return (p) => {
    const d = sub(p, eye);
    const z = dot(d, f);
    if (z < 1) return null;
    return [canvas.width / 2 + (focal * dot(d, r)) / z, canvas.height / 2 - (focal * dot(d, u)) / z, z];
  };
}
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => { const n = Math.hypot(...a) || 1; return [a[0] / n, a[1] / n, a[2] / n]; };

function drawSkeleton(ctx, proj, pos, color, width, alpha, selected) {
  const J = state.skeleton.names.length;
  ctx.globalAlpha = alpha;
  ctx.strokeStyle = color;
  ctx.lineCap = 'round';
  for (let j = 1; j < J; j++) {
    const p = state.skeleton.parents[j];
    const a = proj([pos[3 * p], pos[3 * p + 1], pos[3 * p + 2]]);
    const b = proj([pos[3 * j], pos[3 * j + 1], pos[3 * j + 2]]);
    if (!a || !b) continue;
    ctx.lineWidth = Math.max(1.5, (width * 500) / ((a[2] + b[2]) / 2));
    ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
  }
  ctx.fillStyle = color;
  for (let j = 0; j < J; j++) {
    const a = proj([pos[3 * j], pos[3 * j + 1], pos[3 * j + 2]]);
    if (!a) continue;
    ctx.beginPath(); ctx.arc(a[0], a[1], j === selected ? 6 : 3, 0, 2 * Math.PI); ctx.fill();
  }
  ctx.globalAlpha = 1;
}

function currentPose() {
  if (state.dragPose) return state.dragPose;
  const J = state.skeleton.names.length;
  if (state.result && state.frame < state.result.frames) {
    return state.result.positions.subarray(state.frame * J * 3, (state.frame + 1) * J * 3);
  }
  const k = nearestKey(state.frame);
  return k ? fk(k.channels) : null;
}

function nearestKey(frame) {
  let best = null;
  for (const k of state.keys.filter((x) => x.channels)) if (!best || Math.abs(k.frame - frame) < Math.abs(best.frame - frame)) best = k;
  return best;
}

// Dots on the ground: the synthesized root path, and the root-only keys
// (a short cross of dots each, so they show before any synthesis).
function trajectory() {
  const out = [];
  for (const k of state.keys.filter((x) => x.root)) {
    for (let d = -6; d <= 6; d += 3) out.push(k.root[0] + d, 0, k.root[2], k.root[0], 0, k.root[2] + d);
  }
  if (state.result) {
    const J = state.skeleton.names.length;
    for (let f = 0; f < state.result.frames; f += 3) out.push(state.result.positions[f * J * 3], 0, state.result.positions[f * J * 3 + 2]);
  }
  return new Float32Array(out);
}

function draw() {
  if (!state.view) return;
  if (state.view.lost && state.view.lost()) { replaceLostView(); return; }
  $('frame-label').textContent = `${state.frame} / ${state.length}`;
  if (!state.skeleton) return;
  const poseKeys = state.keys.filter((k) => k.channels);
  const keys = poseKeys.map((k) => fk(k.channels));
  state.view.draw({ pose: currentPose(), keys, keyFrames: poseKeys.map((k) => k.frame), trajectory: trajectory(), selected: state.selected });
}

// ---------------------------------------------------------------- views
// Both views offer: name, draw(scene), pick(x, y) -> joint | -1, orbit, pan,
// zoom, groundDelta(x0, y0, x1, y1) -> [dx, dz], frame().
function gpuView(viewer, canvas) {
  let parentsSet = false;
  return {
    name: viewer.backend,
    draw({ pose, keys, trajectory, selected }) {
      if (!parentsSet) { viewer.setParents(Int32Array.from(state.skeleton.parents.map((p) => (p == null ? -1 : p)))); parentsSet = true; }
      const flatKeys = new Float32Array(keys.length * (keys[0] ? keys[0].length : 0));
      keys.forEach((k, i) => flatKeys.set(k, i * k.length));
      viewer.setSelected(selected);
      viewer.setPoses(pose ? Float32Array.from(pose) : new Float32Array(0), flatKeys);
      viewer.setTrajectory(trajectory);
      viewer.resize(canvas.width, canvas.height);
      viewer.render();
    },
    pick: (x, y) => viewer.pickJoint(x, y),
    orbit: (dx, dy) => viewer.orbit(dx, dy),
    pan: (dx, dy) => viewer.pan(dx, dy),
    zoom: (f) => viewer.zoom(f),
    // Where pixel (x, y) looks at the ground, or null.
    groundPoint(x, y) { const p = viewer.groundPoint(x, y); return p.length ? p : null; },
    groundDelta(x0, y0, x1, y1) {
      const a = viewer.groundPoint(x0, y0), b = viewer.groundPoint(x1, y1);
      return a.length && b.length ? [b[0] - a[0], b[2] - a[2]] : [0, 0];
    },
    // World motion of a point at p dragged from pixel (x0, y0) to (x1, y1) in the view plane.
    dragDelta(p, x0, y0, x1, y1) {
      const a = viewer.planePoint(x0, y0, p[0], p[1], p[2]), b = viewer.planePoint(x1, y1, p[0], p[1], p[2]);
      return a.length && b.length ? [b[0] - a[0], b[1] - a[1], b[2] - a[2]] : [0, 0, 0];
    },
    frame() { viewer.frame(); },
    project: (p) => viewer.projectPoint(p[0], p[1], p[2]),
    lost: () => viewer.deviceLost,
    // RGBA pixels of the view, read right after drawing.
    async pixels() { draw(); return readCanvas(canvas); },
  };
}

// A lost GPU device (a GPU reset; or headless Chromium, whose SwiftShader
// WebGPU cannot present a canvas) falls back to WebGL2 on a fresh canvas.
let replacing = null;
function replaceLostView() {
  if (replacing) return;
  replacing = (async () => {
    console.warn(`the ${state.view.name} device was lost; switching to WebGL2`);
    const old = $('view');
    const fresh = old.cloneNode(true);
    old.replaceWith(fresh);
    try {
      state.view = gpuView(await Viewer.create(fresh, true), fresh);
    } catch (e) {
      console.warn(`WebGL2 unavailable too, using the 2-D canvas: ${e.message}`);
      state.view = canvasView(fresh);
    }
    state.view.lost = state.view.lost || (() => false);
    wireCanvas(fresh);
    document.body.dataset.view = state.view.name;
    $('view-badge').textContent = viewLabel(state.view.name);
    state.view.frame();
    replacing = null;
    draw();
  })();
}

function viewLabel(name) {
  return { webgpu: 'WebGPU', webgl2: 'WebGL2', '2d': '2-D canvas (no WebGPU or WebGL2)' }[name] || name;
}

function readCanvas(canvas) {
  const o = document.createElement('canvas');
  o.width = canvas.width; o.height = canvas.height;
  const x = o.getContext('2d');
  x.drawImage(canvas, 0, 0);
  return x.getImageData(0, 0, o.width, o.height).data;
}

function canvasView(canvas) {
  const ctx = canvas.getContext('2d');
  const cam = state.cam;
  const scale = () => cam.dist / (canvas.height * 1.3);
  return {
    name: '2d',
    draw({ pose, keys, keyFrames, trajectory: traj, selected }) {
      ctx.fillStyle = '#0b0e11';
      ctx.fillRect(0, 0, canvas.width, canvas.height);
      const proj = camera(canvas);
      ctx.strokeStyle = '#1f2a36';
      ctx.lineWidth = 1;
      for (let i = -10; i <= 10; i++) {
        for (const [a, b] of [[[i * 50, 0, -500], [i * 50, 0, 500]], [[-500, 0, i * 50], [500, 0, i * 50]]]) {
          const pa = proj(a), pb = proj(b);
          if (pa && pb) { ctx.beginPath(); ctx.moveTo(pa[0], pa[1]); ctx.lineTo(pb[0], pb[1]); ctx.stroke(); }
        }
      }
      for (let i = 0; i < traj.length; i += 3) {
        const p = proj([traj[i], 0, traj[i + 2]]);
        if (!p) continue;
        ctx.fillStyle = `hsl(${200 + (120 * i) / traj.length}, 70%, 60%)`;
        ctx.fillRect(p[0] - 1.5, p[1] - 1.5, 3, 3);
      }
      keys.forEach((k, i) => drawSkeleton(ctx, proj, k, '#f273a6', 3, keyFrames[i] === state.frame ? 0.9 : 0.35, -1));
      if (pose) drawSkeleton(ctx, proj, pose, '#8fd0ff', 4, 1, selected);
    },
    pick(x, y) {
      const pose = currentPose();
      if (!pose) return -1;
      const proj = camera(canvas);
      let best = 14, hit = -1;
      for (let j = 0; j < state.skeleton.names.length; j++) {
        const p = proj([pose[3 * j], pose[3 * j + 1], pose[3 * j + 2]]);
        if (p && Math.hypot(p[0] - x, p[1] - y) < best) { best = Math.hypot(p[0] - x, p[1] - y); hit = j; }
      }
      return hit;
    },
    orbit(dx, dy) { cam.yaw -= dx * 0.008; cam.pitch = Math.max(-0.2, Math.min(1.4, cam.pitch + dy * 0.008)); },
    pan(dx, dy) { const s = scale(); cam.target[0] -= s * dx * Math.cos(cam.yaw); cam.target[2] += s * dx * Math.sin(cam.yaw); cam.target[1] += s * dy; },
    zoom(f) { cam.dist = Math.max(80, Math.min(3000, cam.dist * f)); },
    groundPoint: () => null, // the 2-D fallback has no ray casting: no root paths
    groundDelta(x0, y0, x1, y1) {
      const s = scale(), dx = x1 - x0, dy = y1 - y0, { yaw } = cam;
      return [s * (dx * Math.cos(yaw) + dy * Math.sin(yaw)), s * (-dx * Math.sin(yaw) + dy * Math.cos(yaw))];
    },
    dragDelta(p, x0, y0, x1, y1) {
      const s = scale(), dx = x1 - x0, dy = y1 - y0, { yaw } = cam;
      return [s * dx * Math.cos(yaw), -s * dy, -s * dx * Math.sin(yaw)];
    },
    frame() {},
    project(p) { const q = camera(canvas)(p); return q ? [q[0], q[1]] : []; },
    async pixels() { return ctx.getImageData(0, 0, canvas.width, canvas.height).data; },
  };
}

async function createView() {
  const params = new URLSearchParams(location.search);
  let canvas = $('view');
  if (params.get('view') !== '2d') {
    try {
      return gpuView(await Viewer.create(canvas, params.has('webgl2')), canvas);
    } catch (e) {
      console.warn(`wgpu viewer unavailable, using the 2-D canvas: ${e.message}`);
      const fresh = canvas.cloneNode(true); // a canvas that holds a GPU context cannot give a 2-D one
      canvas.replaceWith(fresh);
      canvas = fresh;
    }
  }
  return canvasView(canvas);
}

// ---------------------------------------------------------------- timeline and keys
function refreshTimeline() {
  state.keys.sort((a, b) => a.frame - b.frame);
  $('scrub').max = String(state.length - 1);
  const marks = $('keymarks');
  marks.innerHTML = '';
  for (const k of state.keys) {
    const s = document.createElement('span');
    s.style.left = `${(100 * k.frame) / Math.max(1, state.length - 1)}%`;
    s.title = k.root ? `root key at frame ${k.frame}` : `key at frame ${k.frame}`;
    if (k.root) s.classList.add('root');
    s.onclick = () => setFrame(k.frame);
    marks.appendChild(s);
  }
  $('keys-list').textContent = state.keys.length ? `keys at frames ${state.keys.map((k) => k.frame).join(', ')}` : 'no keys yet';
}

function setFrame(f) {
  state.frame = Math.max(0, Math.min(state.length - 1, f | 0));
  $('scrub').value = String(state.frame);
  refreshJointEditor();
  draw();
}

function keyAt(frame) { return state.keys.find((k) => k.frame === frame); }

function addKey() {
  const pose = state.library[$('pose').selectedIndex];
  if (!pose) return;
  pushHistory();
  const existing = keyAt(state.frame);
  if (existing) { existing.channels = pose.channels.slice(); delete existing.root; }
  else state.keys.push({ frame: state.frame, channels: pose.channels.slice() });
  refreshTimeline();
  draw();
}

function deleteKey() {
  const k = keyAt(state.frame);
  if (!k) { setStatus(`no key at frame ${state.frame} to delete`, true); return; }
  pushHistory();
  state.keys = state.keys.filter((x) => x !== k);
  refreshTimeline();
  draw();
}

// ---------------------------------------------------------------- joint editing within RC ranges
async function refreshJointEditor() {
  const k = keyAt(state.frame);
  const box = $('joint-edit');
  if (!k?.channels || state.selected <= 0 || !state.client?.hasModel) { box.hidden = true; return; }
  try {
    const a = await state.client.rcAngles(k.channels, state.selected);
    $('joint-name').textContent = state.skeleton.names[state.selected];
    ['ax', 'ay', 'az'].forEach((id, i) => {
      const el = $(id);
      el.min = String(a[3 + 2 * i]); el.max = String(a[4 + 2 * i]); el.value = String(a[i]);
      el.disabled = a[3 + 2 * i] === a[4 + 2 * i];
    });
    box.hidden = false;
  } catch (e) {
    box.hidden = true; // the root and End Sites have no RC angles
  }
}

async function onAngleInput() {
  const k = keyAt(state.frame);
  if (!k?.channels || state.selected <= 0) return;
  const angles = ['ax', 'ay', 'az'].map((id) => Number($(id).value));
  try {
    k.channels = await state.client.setRcAngles(k.channels, state.selected, angles);
    draw();
  } catch (e) { setStatus(`edit failed: ${e.message}`, true); }
}

// ---------------------------------------------------------------- synthesis
function mulberry32(a) { return () => { a |= 0; a = (a + 0x6d2b79f5) | 0; let t = Math.imul(a ^ (a >>> 15), 1 | a); t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t; return ((t ^ (t >>> 14)) >>> 0) / 4294967296; }; }

const chunk = (flat, n) => Array.from({ length: flat.length / n }, (_, i) => flat.slice(i * n, (i + 1) * n));

function dnaChannels() {
  const picked = [...$('dna').selectedOptions].map((o) => state.library[Number(o.value)]);
  if (!picked.length && state.library.length) {
    const rnd = mulberry32(Number($('seed').value) || 0);
    const k = Math.max(1, Math.floor(state.length / 180));
    for (let i = 0; i < k; i++) picked.push(state.library[Math.floor(rnd() * state.library.length)]);
  }
  return picked.flatMap((p) => p.channels);
}

async function synthesize() {
  const length = Number($('length').value);
  if (!Number.isInteger(length) || length < 1 || length > 4096) { setStatus('length must be 1..4096 frames', true); return; }
  if (length !== state.length) { pushHistory(); state.length = length; refreshTimeline(); }
  const keys = state.keys.filter((k) => k.frame < length);
  if (!keys.length) { setStatus('add at least one keyframe first', true); return; }
  const rootKeys = keys.some((k) => k.root);
  if (rootKeys && (!state.client.hasModel || $('method').value !== 'model')) {
    setStatus('root-path keys need the Generative Tweening model (interpolation needs whole poses)', true);
    return;
  }
  const method = state.client.hasModel ? $('method').value : 'slerp';
  $('synth').disabled = true;
  $('progress').value = 0;
  try {
    const t0 = performance.now();
    const common = { frames: length, post: $('post').checked, footLock: $('footlock').checked, method, variation: Number($('variation').value) };
    const r = rootKeys
      // keys of both kinds in the request form (motion::keys), DNA as rows
      ? await state.client.synthesize({ ...common, keys: keys.map((k) => (k.root ? { frame: k.frame, root: k.root } : { frame: k.frame, channels: k.channels })),
                                       dna: chunk(dnaChannels(), state.skeleton.channels) })
      : await state.client.synthesize({ ...common, keyFrames: keys.map((k) => k.frame), keyChannels: keys.flatMap((k) => k.channels), dna: dnaChannels() });
    state.result = { positions: r.positions, frames: r.frames, bvh: r.bvh, method, times: r.times };
    $('method-badge').textContent = { slerp: 'SLERP+LERP interpolation baseline', residual: 'supervised residual network' }[method] || 'Generative Tweening model';
    $('method-badge').classList.toggle('baseline', method === 'slerp');
    const ms = performance.now() - t0;
    $('timing').textContent = `${r.frames} frames in ${ms.toFixed(0)} ms` + (method === 'model' ? ` (generator ${r.times[0].toFixed(0)} ms, RC-FK ${r.times[1].toFixed(0)}, path ${r.times[2].toFixed(0)}, post ${r.times[3].toFixed(0)})` : '')
      + (r.criticalFrames?.length ? `; hierarchical (a gap over 600 frames): critical keys made first at frames ${r.criticalFrames.join(', ')}` : '');
    $('progress').value = 1;
    $('progress-label').textContent = 'done';
    document.body.dataset.synthesized = String(r.frames);
    setStatus('ready');
    draw();
  } catch (e) {
    setStatus(`synthesis failed: ${e.message} (your keys are unchanged)`, true);
    $('progress-label').textContent = '';
  } finally {
    $('synth').disabled = false;
  }
}

// ---------------------------------------------------------------- BVH import / export
function exportBvh() {
  if (!state.result) { setStatus('synthesize first: nothing to export yet', true); return; }
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([state.result.bvh], { type: 'text/plain' }));
  a.download = `deeprep-${state.result.frames}f.bvh`;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

async function importBvh(file) {
  try {
    // Parsed and checked in the synthesis worker: a hostile file can at worst
    // cost that worker (which the client replaces), never this page.
    const clip = await state.client.importBvh(new Uint8Array(await file.arrayBuffer()))
      .catch((e) => { throw new Error(`${file.name}: ${e.message}`); });
    const c = clip.channelCount, m = clip.motion, step = Math.max(1, Math.round(0.5 / clip.frameTime));
    let added = 0;
    for (let f = 0; f < clip.frameCount; f += step) {
      state.library.push({ name: `${file.name} @${f}`, channels: Array.from(m.subarray(f * c, (f + 1) * c)) });
      added++;
    }
    state.result = { positions: clip.positions, frames: clip.frameCount, bvh: clip.bvh, method: 'imported' };
    $('method-badge').textContent = `imported ${file.name}`;
    fillLibrary();
    setStatus(`imported ${file.name}: ${added} poses added to the library`);
    draw();
    state.view.frame();
    draw();
  } catch (e) {
    setStatus(`import failed: ${e.message}`, true);
  }
}

function fillLibrary() {
  for (const id of ['pose', 'dna']) {
    const sel = $(id);
    const keep = [...sel.selectedOptions].map((o) => o.value);
    sel.innerHTML = '';
    state.library.forEach((p, i) => { const o = new Option(p.name, String(i)); o.selected = keep.includes(String(i)); sel.add(o); });
  }
}

// ---------------------------------------------------------------- input
let drag = null;
const toCanvas = (e) => { const c = $('view'); const r = c.getBoundingClientRect(); return [((e.clientX - r.left) * c.width) / r.width, ((e.clientY - r.top) * c.height) / r.height]; };

// Listeners on the view canvas (again on a replacement canvas).
function wireCanvas(canvas) {
  canvas.addEventListener('mousedown', (e) => {
    const [x, y] = toCanvas(e);
    if ($('path-mode').checked && !e.shiftKey) { dropRootKey(x, y); return; }
    const hit = currentPose() ? state.view.pick(x, y) : -1;
    if (hit >= 0) { state.selected = hit; refreshJointEditor(); draw(); }
    const k = keyAt(state.frame);
    drag = { x, y, moveRoot: hit === 0 && !!k?.channels, pushed: false, pan: e.shiftKey,
             joint: hit > 0 && !!k?.channels && !e.shiftKey ? { index: hit, key: k, positions: Float32Array.from(fk(k.channels)), moved: false } : null };
  });
  canvas.addEventListener('wheel', (e) => { e.preventDefault(); state.view.zoom(Math.exp(e.deltaY * 0.001)); draw(); }, { passive: false });
}

// Path mode (Sec. 5.4.1): the clicked ground point becomes a root-only key
// at the current frame, at the height of the pose keys' root (or the
// library's first pose), and the frame moves on by the path step.
function dropRootKey(x, y) {
  const p = state.view.groundPoint(x, y);
  if (!p) { setStatus(state.view.name === '2d' ? 'root paths need the WebGPU or WebGL2 view' : 'click on the ground to place the root', true); return; }
  const pose = nearestKey(state.frame)?.channels || state.library[0]?.channels;
  const height = pose ? pose[1] : 56;
  pushHistory();
  const frame = state.frame, k = keyAt(frame);
  if (k && k.channels) { k.channels[0] = p[0]; k.channels[2] = p[2]; } // a pose key moves there instead
  else if (k) k.root = [p[0], height, p[2]];
  else state.keys.push({ frame, root: [p[0], height, p[2]] });
  refreshTimeline();
  setFrame(Math.min(state.length - 1, frame + (Number($('path-step').value) || 60)));
  setStatus(`root at (${p[0].toFixed(0)}, ${p[2].toFixed(0)}) on the ground at frame ${frame}`);
}

function subtree(j) {
  const out = [j];
  for (let i = 0; i < out.length; i++) state.skeleton.parents.forEach((p, c) => { if (p === out[i]) out.push(c); });
  return out;
}

// A dragged joint becomes a new key pose: joint positions -> IK network -> channels.
async function solveDraggedPose(key, positions) {
  try {
    pushHistory();
    setStatus('solving the dragged pose with the IK network…');
    const r = await state.client.ik(positions, 1);
    const ch = Array.from(r.channels);
    ch[0] = key.channels[0]; ch[1] = key.channels[1]; ch[2] = key.channels[2]; // the root stays where it was
    key.channels = ch;
    setStatus(`pose solved by IK (mean joint error ${r.meanError.toFixed(2)} units); synthesize to update the motion`);
  } catch (e) {
    state.undo.pop();
    setStatus(`IK failed, the key is unchanged: ${e.message}`, true);
  }
  state.dragPose = null;
  refreshJointEditor();
  draw();
}

function wireInput() {
  wireCanvas($('view'));
  window.addEventListener('mouseup', () => {
    if (drag && drag.joint && drag.joint.moved) solveDraggedPose(drag.joint.key, drag.joint.positions);
    drag = null;
  });
  window.addEventListener('mousemove', (e) => {
    if (!drag) return;
    const [x, y] = toCanvas(e);
    const dx = x - drag.x, dy = y - drag.y;
    if (drag.joint) {
      // Move the joint and everything below it in the view plane; the pose
      // is solved by the IK network when the button is released.
      const { index, positions } = drag.joint;
      const p = [positions[3 * index], positions[3 * index + 1], positions[3 * index + 2]];
      const d = state.view.dragDelta(p, drag.x, drag.y, x, y);
      for (const j of subtree(index)) for (let a = 0; a < 3; a++) positions[3 * j + a] += d[a];
      drag.joint.moved = true;
      state.dragPose = positions;
    } else if (drag.moveRoot) {
      const k = keyAt(state.frame);
      if (!drag.pushed) { pushHistory(); drag.pushed = true; }
      const [gx, gz] = state.view.groundDelta(drag.x, drag.y, x, y);
      k.channels[0] += gx;
      k.channels[2] += gz;
    } else if (drag.pan) {
      state.view.pan(dx, dy);
    } else {
      state.view.orbit(dx, dy);
    }
    drag.x = x; drag.y = y;
    draw();
  });
  $('scrub').addEventListener('input', () => setFrame(Number($('scrub').value)));
  $('play').addEventListener('click', () => { state.playing = !state.playing; $('play').textContent = state.playing ? '❚❚ Pause' : '▶ Play'; if (state.playing) tick(); });
  $('add-key').addEventListener('click', addKey);
  $('del-key').addEventListener('click', deleteKey);
  $('undo').addEventListener('click', undo);
  $('redo').addEventListener('click', redo);
  $('synth').addEventListener('click', synthesize);
  $('variation').addEventListener('input', () => { $('variation-value').textContent = Number($('variation').value).toFixed(2); });
  $('length').addEventListener('change', () => {
    const n = Number($('length').value);
    if (!Number.isInteger(n) || n < 1 || n > 4096) { setStatus('length must be 1..4096 frames', true); return; }
    if (n !== state.length) { pushHistory(); state.length = n; refreshTimeline(); setFrame(state.frame); }
  });
  $('export').addEventListener('click', exportBvh);
  $('import').addEventListener('change', (e) => { if (e.target.files[0]) importBvh(e.target.files[0]); });
  for (const id of ['ax', 'ay', 'az']) {
    $(id).addEventListener('pointerdown', () => pushHistory());
    $(id).addEventListener('input', onAngleInput);
  }
  window.addEventListener('keydown', (e) => {
    if ((e.ctrlKey || e.metaKey) && e.key === 'z') { e.preventDefault(); undo(); }
    if ((e.ctrlKey || e.metaKey) && (e.key === 'y' || (e.shiftKey && e.key === 'Z'))) { e.preventDefault(); redo(); }
  });
}

let last = 0;
function tick(t = performance.now()) {
  if (!state.playing) return;
  if (t - last >= 1000 / 60 - 1) { last = t; setFrame((state.frame + 1) % state.length); }
  requestAnimationFrame(tick);
}

// ---------------------------------------------------------------- start
async function main() {
  await init();
  state.view = await createView();
  document.body.dataset.view = state.view.name;
  $('view-badge').textContent = viewLabel(state.view.name);
  wireInput();
  setStatus('loading models in a worker…');
  state.client = await DeeprepClient.create({
    modelBase: MODEL_BASE,
    onProgress: (m) => { $('progress').value = m.fraction; $('progress-label').textContent = m.stage; },
  });
  if (!state.client.hasModel) throw new Error(`models unavailable (${state.client.modelError})`);
  if (!state.client.hasResidual) $('method').querySelector('option[value="residual"]')?.remove();
  state.skeleton = parseSkeleton(state.client.skeletonBvh);
  $('variation').value = String(state.client.defaultVariation);
  $('variation-value').textContent = state.client.defaultVariation.toFixed(2);
  const [poses, keys] = await Promise.all([
    fetch(`${EXAMPLES}/poses.json`).then((r) => r.json()),
    fetch(`${EXAMPLES}/keys.json`).then((r) => r.json()),
  ]);
  state.library = poses.poses.map((p) => ({ name: p.name, channels: p.channels }));
  state.keys = keys.keys.map((k) => ({ frame: k.frame, channels: k.channels }));
  state.length = keys.frames;
  $('length').value = String(keys.frames);
  fillLibrary();
  refreshTimeline();
  setFrame(0);
  state.view.frame();
  draw();
  await synthesize();
  // A GPU device that is lost right after its first frames (see
  // replaceLostView) is replaced before the page reports ready.
  await new Promise((r) => setTimeout(r, 200));
  draw();
  if (replacing) await replacing;
  document.body.dataset.ready = '1';
}

main().catch((e) => { setStatus(`error: ${e.message}`, true); console.error(e); });
window.deeprepState = state; // for tests and the console
