// Editing a key's pose: a joint's RC angles within Table D.1's ranges
// (sliders), and dragged joints solved into a pose by the IK network.
import { $, setStatus, state } from './state.js';
import { dropHistory, pushHistory } from './history.js';
import { keyAt } from './timeline.js';
import { draw } from './view.js';

/** Shows the RC-angle sliders of the selected joint of the key at the current frame. */
export async function refreshJointEditor() {
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

/** A slider moved: the key's channels with the joint's new RC angles. */
export async function onAngleInput() {
  const k = keyAt(state.frame);
  if (!k?.channels || state.selected <= 0) return;
  const angles = ['ax', 'ay', 'az'].map((id) => Number($(id).value));
  try {
    k.channels = await state.client.setRcAngles(k.channels, state.selected, angles);
    draw();
  } catch (e) { setStatus(`edit failed: ${e.message}`, true); }
}

/**
 * A joint dragged in the 2-D key mode (Sec. 5.4.2): the key at this frame
 * becomes a 2-D key giving every joint's x and y (and the root), its depth
 * left to the networks; post-processing makes the output meet x and y.
 */
export function makeXyKey(key, positions) {
  pushHistory();
  const p = Array.from(positions);
  const J = p.length / 3;
  key.xy = Array.from({ length: J }, (_, j) => [p[3 * j], p[3 * j + 1]]);
  key.root = [p[0], p[1], p[2]];
  key.positions = p;
  delete key.channels;
  state.dragPose = null;
  setStatus(`2-D key at frame ${key.frame}: every joint's x and y as sketched; synthesize to lift it to 3-D`);
  refreshJointEditor();
  draw();
}

/** A dragged joint becomes a new key pose: joint positions -> IK network -> channels. */
export async function solveDraggedPose(key, positions) {
  try {
    pushHistory();
    setStatus('solving the dragged pose with the IK network…');
    const r = await state.client.ik(positions, 1);
    const ch = Array.from(r.channels);
    ch[0] = key.channels[0]; ch[1] = key.channels[1]; ch[2] = key.channels[2]; // the root stays where it was
    key.channels = ch;
    setStatus(`pose solved by IK (mean joint error ${r.meanError.toFixed(2)} units); synthesize to update the motion`);
  } catch (e) {
    dropHistory();
    setStatus(`IK failed, the key is unchanged: ${e.message}`, true);
  }
  state.dragPose = null;
  refreshJointEditor();
  draw();
}
