// The timeline: key marks, the current frame, playback, adding and
// deleting pose keys.
import { $, setStatus, state } from './state.js';
import { pushHistory } from './history.js';
import { refreshJointEditor } from './joints.js';
import { draw } from './view.js';

/** Sorts the keys and redraws their marks and list. */
export function refreshTimeline() {
  state.keys.sort((a, b) => a.frame - b.frame);
  $('scrub').max = String(state.length - 1);
  const marks = $('keymarks');
  marks.innerHTML = '';
  for (const k of state.keys) {
    const s = document.createElement('span');
    s.style.left = `${(100 * k.frame) / Math.max(1, state.length - 1)}%`;
    s.title = k.xy ? `2-D key at frame ${k.frame}` : k.root ? `root key at frame ${k.frame}` : `key at frame ${k.frame}`;
    if (k.xy) s.classList.add('xy'); else if (k.root) s.classList.add('root');
    s.onclick = () => setFrame(k.frame);
    marks.appendChild(s);
  }
  $('keys-list').textContent = state.keys.length ? `keys at frames ${state.keys.map((k) => k.frame).join(', ')}` : 'no keys yet';
}

export function setFrame(f) {
  state.frame = Math.max(0, Math.min(state.length - 1, f | 0));
  $('scrub').value = String(state.frame);
  refreshJointEditor();
  draw();
}

/** The key at `frame`, if any. */
export function keyAt(frame) { return state.keys.find((k) => k.frame === frame); }

/** The library pose selected in #pose becomes the key at the current frame. */
export function addKey() {
  const pose = state.library[$('pose').selectedIndex];
  if (!pose) return;
  pushHistory();
  const existing = keyAt(state.frame);
  if (existing) { existing.channels = pose.channels.slice(); delete existing.root; delete existing.xy; delete existing.positions; }
  else state.keys.push({ frame: state.frame, channels: pose.channels.slice() });
  refreshTimeline();
  draw();
}

export function deleteKey() {
  const k = keyAt(state.frame);
  if (!k) { setStatus(`no key at frame ${state.frame} to delete`, true); return; }
  pushHistory();
  state.keys = state.keys.filter((x) => x !== k);
  refreshTimeline();
  draw();
}

/** Sets the output length (1..4096 frames); false with a message otherwise. */
export function setLength(n) {
  if (!Number.isInteger(n) || n < 1 || n > 4096) { setStatus('length must be 1..4096 frames', true); return false; }
  if (n !== state.length) { pushHistory(); state.length = n; refreshTimeline(); setFrame(state.frame); }
  return true;
}

let last = 0;
function tick(t = performance.now()) {
  if (!state.playing) return;
  if (t - last >= 1000 / 60 - 1) { last = t; setFrame((state.frame + 1) % state.length); }
  requestAnimationFrame(tick);
}

/** Starts or pauses playback at 60 fps. */
export function togglePlay() {
  state.playing = !state.playing;
  $('play').textContent = state.playing ? '❚❚ Pause' : '▶ Play';
  if (state.playing) tick();
}
