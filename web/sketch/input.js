// Mouse and keyboard: orbit/pan/zoom, picking and dragging joints, moving a
// key's root on the ground, dropping root-path keys (Sec. 5.4.1), and the
// controls' listeners.
import { toCanvas } from '../lib/view.js';
import { $, setStatus, state } from './state.js';
import { pushHistory, redo, undo } from './history.js';
import { exportBvh, fillGap, importBvh } from './io.js';
import { makeXyKey, onAngleInput, refreshJointEditor, solveDraggedPose } from './joints.js';
import { subtree } from './skeleton.js';
import { compareSeeds, synthesize } from './synth.js';
import { addKey, deleteKey, keyAt, refreshTimeline, setFrame, setLength, togglePlay } from './timeline.js';
import { currentPose, draw, keyPositions, nearestKey } from './view.js';

let drag = null;
const at = (e) => toCanvas(state.view.canvas(), e);

/** Listeners on a view canvas (again on a replacement canvas). */
export function wireCanvas(canvas) {
  canvas.addEventListener('mousedown', (e) => {
    const [x, y] = at(e);
    if ($('path-mode').checked && !e.shiftKey) { dropRootKey(x, y); return; }
    const hit = currentPose() ? state.view.pick(x, y) : -1;
    if (hit >= 0) { state.selected = hit; refreshJointEditor(); draw(); }
    const k = keyAt(state.frame);
    const shown = k && (k.channels || k.positions);
    drag = { x, y, moveRoot: hit === 0 && !!k?.channels, pushed: false, pan: e.shiftKey,
             joint: hit > 0 && shown && !e.shiftKey ? { index: hit, key: k, positions: Float32Array.from(keyPositions(k)), moved: false } : null };
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
  else if (k && k.xy) { setStatus('this frame has a 2-D key: its root is where it was sketched', true); return; }
  else if (k) k.root = [p[0], height, p[2]];
  else state.keys.push({ frame, root: [p[0], height, p[2]] });
  refreshTimeline();
  setFrame(Math.min(state.length - 1, frame + (Number($('path-step').value) || 60)));
  setStatus(`root at (${p[0].toFixed(0)}, ${p[2].toFixed(0)}) on the ground at frame ${frame}`);
}

function onMove(e) {
  if (!drag) return;
  const [x, y] = at(e);
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
}

/** The window's and the controls' listeners (once). */
export function wireInput() {
  window.addEventListener('mouseup', () => {
    if (drag && drag.joint && drag.joint.moved) {
      if ($('xy-mode').checked) makeXyKey(drag.joint.key, drag.joint.positions);
      else solveDraggedPose(drag.joint.key, drag.joint.positions);
    }
    drag = null;
  });
  window.addEventListener('mousemove', onMove);
  $('xy-mode').addEventListener('change', () => { if ($('xy-mode').checked) { state.view.setView(0, 0); draw(); } });
  $('scrub').addEventListener('input', () => setFrame(Number($('scrub').value)));
  $('play').addEventListener('click', togglePlay);
  $('add-key').addEventListener('click', addKey);
  $('del-key').addEventListener('click', deleteKey);
  $('undo').addEventListener('click', undo);
  $('redo').addEventListener('click', redo);
  $('synth').addEventListener('click', synthesize);
  $('compare-seeds').addEventListener('click', compareSeeds);
  $('variation').addEventListener('input', () => {
    state.variationTouched = true;
    $('variation-value').textContent = Number($('variation').value).toFixed(2);
  });
  $('length').addEventListener('change', () => setLength(Number($('length').value)));
  $('export').addEventListener('click', exportBvh);
  $('fill').addEventListener('click', fillGap);
  $('fill-from').addEventListener('click', () => { $('fill-start').value = String(state.frame); });
  $('fill-to').addEventListener('click', () => { $('fill-end').value = String(state.frame); });
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
