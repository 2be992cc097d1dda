// The page's view: the crate's wgpu renderer through web/lib/view.js
// (WebGPU, or WebGL2 when asked with `?webgl2` or when the device is lost),
// or the 2-D canvas (view2d.js) when neither is available. Both offer:
// name, canvas(), draw(scene), pick(x, y) -> joint | -1, orbit, pan, zoom,
// groundPoint(x, y), groundDelta(x0, y0, x1, y1) -> [dx, dz],
// dragDelta(p, x0, y0, x1, y1), frame(), setView(yaw, pitch) ((0, 0): the
// front view), project(p), lost(), ensure(), pixels().
import { openView } from '../lib/view.js';
import { $, state } from './state.js';
import { fk } from './skeleton.js';
import { canvasView } from './view2d.js';

let onNewCanvas = () => {};
let replacing = null;

function gpuView(lv) {
  let parentsSet = false;
  const v = () => lv.viewer; // replaced on a lost device
  return {
    name: v().backend,
    canvas: () => lv.canvas(),
    draw({ pose, keys, trajectory, selected }) {
      if (!parentsSet) { v().setParents(Int32Array.from(state.skeleton.parents.map((p) => (p == null ? -1 : p)))); parentsSet = true; }
      const flatKeys = new Float32Array(keys.length * (keys[0] ? keys[0].length : 0));
      keys.forEach((k, i) => flatKeys.set(k, i * k.length));
      const canvas = lv.canvas();
      v().setSelected(selected);
      v().setPoses(pose ? Float32Array.from(pose) : new Float32Array(0), flatKeys);
      v().setTrajectory(trajectory);
      v().resize(canvas.width, canvas.height);
      v().render();
    },
    pick: (x, y) => v().pickJoint(x, y),
    orbit: (dx, dy) => v().orbit(dx, dy),
    pan: (dx, dy) => v().pan(dx, dy),
    zoom: (f) => v().zoom(f),
    // Where pixel (x, y) looks at the ground, or null.
    groundPoint(x, y) { const p = v().groundPoint(x, y); return p.length ? p : null; },
    groundDelta(x0, y0, x1, y1) {
      const a = v().groundPoint(x0, y0), b = v().groundPoint(x1, y1);
      return a.length && b.length ? [b[0] - a[0], b[2] - a[2]] : [0, 0];
    },
    // World motion of a point at p dragged from pixel (x0, y0) to (x1, y1) in the view plane.
    dragDelta(p, x0, y0, x1, y1) {
      const a = v().planePoint(x0, y0, p[0], p[1], p[2]), b = v().planePoint(x1, y1, p[0], p[1], p[2]);
      return a.length && b.length ? [b[0] - a[0], b[1] - a[1], b[2] - a[2]] : [0, 0, 0];
    },
    frame() { v().frame(); },
    setView: (yaw, pitch) => v().setView(yaw, pitch),
    project: (p) => v().projectPoint(p[0], p[1], p[2]),
    lost: () => v().deviceLost,
    ensure: () => lv.ensure(),
    // RGBA pixels of the view, read right after drawing.
    async pixels() { return lv.pixels(draw); },
  };
}

function viewLabel(name) {
  return { webgpu: 'WebGPU', webgl2: 'WebGL2', '2d': '2-D canvas (no WebGPU or WebGL2)' }[name] || name;
}

function adopt(view) {
  state.view = view;
  onNewCanvas(view.canvas());
  document.body.dataset.view = view.name;
  $('view-badge').textContent = viewLabel(view.name);
}

/**
 * Opens the view on the canvas #view; `wire(canvas)` attaches the page's
 * listeners to it and again to any replacement canvas.
 */
export async function createView(wire) {
  onNewCanvas = wire;
  const params = new URLSearchParams(location.search);
  let view = null;
  if (params.get('view') !== '2d') {
    const replaced = (lv) => { adopt(gpuView(lv)); state.view.frame(); draw(); };
    const failed = (fresh, e) => {
      console.warn(`WebGL2 unavailable too, using the 2-D canvas: ${e.message}`);
      adopt(canvasView(fresh));
      draw();
    };
    try {
      view = gpuView(await openView('view', params.has('webgl2'), replaced, failed));
    } catch (e) {
      console.warn(`wgpu viewer unavailable, using the 2-D canvas: ${e.message}`);
      const old = $('view');
      const fresh = old.cloneNode(true); // a canvas that holds a GPU context cannot give a 2-D one
      old.replaceWith(fresh);
    }
  }
  adopt(view || canvasView($('view')));
}

/** A promise while a lost view is being replaced, else null. */
export const viewReplacing = () => replacing;

/** The pose shown at the current frame: a dragged pose, the result, or the nearest pose key. */
export function currentPose() {
  if (state.dragPose) return state.dragPose;
  const J = state.skeleton.names.length;
  if (state.result && state.frame < state.result.frames) {
    return state.result.positions.subarray(state.frame * J * 3, (state.frame + 1) * J * 3);
  }
  const k = nearestKey(state.frame);
  return k ? keyPositions(k) : null;
}

/** The joint positions a key shows: its pose's FK, or a 2-D key's sketched positions. */
export function keyPositions(k) {
  return k.channels ? fk(k.channels) : k.positions;
}

/** The key nearest to `frame` that shows a pose (a whole pose or a 2-D key), or null. */
export function nearestKey(frame) {
  let best = null;
  for (const k of state.keys.filter((x) => x.channels || x.positions)) if (!best || Math.abs(k.frame - frame) < Math.abs(best.frame - frame)) best = k;
  return best;
}

// Dots on the ground: the synthesized root path, and the root-only keys
// (a short cross of dots each, so they show before any synthesis).
function trajectory() {
  const out = [];
  for (const k of state.keys.filter((x) => x.root && !x.xy)) {
    for (let d = -6; d <= 6; d += 3) out.push(k.root[0] + d, 0, k.root[2], k.root[0], 0, k.root[2] + d);
  }
  if (state.result) {
    const J = state.skeleton.names.length;
    for (let f = 0; f < state.result.frames; f += 3) out.push(state.result.positions[f * J * 3], 0, state.result.positions[f * J * 3 + 2]);
  }
  return new Float32Array(out);
}

/** Draws the current frame (replacing the view first if its device was lost). */
export function draw() {
  if (!state.view) return;
  if (state.view.lost()) {
    if (!replacing) replacing = Promise.resolve(state.view.ensure()).finally(() => { replacing = null; });
    return;
  }
  $('frame-label').textContent = `${state.frame} / ${state.length}`;
  if (!state.skeleton) return;
  const poseKeys = state.keys.filter((k) => k.channels || k.positions);
  const J = state.skeleton.names.length, g = state.ghost;
  const ghost = g && state.frame < g.frames ? [g.positions.subarray(state.frame * J * 3, (state.frame + 1) * J * 3)] : [];
  state.view.draw({
    pose: currentPose(),
    keys: [...poseKeys.map(keyPositions), ...ghost],
    keyFrames: poseKeys.map((k) => k.frame),
    trajectory: trajectory(),
    selected: state.selected,
  });
}
