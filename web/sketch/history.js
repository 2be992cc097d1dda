// Undo and redo of the keys and the length (200 steps).
import { $, state } from './state.js';
import { refreshTimeline } from './timeline.js';
import { draw } from './view.js';

function snapshot() { return JSON.stringify({ keys: state.keys, length: state.length }); }

function restore(s) {
  const o = JSON.parse(s);
  state.keys = o.keys;
  state.length = o.length;
  $('length').value = o.length;
  refreshTimeline();
  draw();
}

/** Records the state before an edit. */
export function pushHistory() {
  state.undo.push(snapshot());
  state.redo.length = 0;
  if (state.undo.length > 200) state.undo.shift();
}

/** Forgets the last recorded state (an edit that failed). */
export function dropHistory() { state.undo.pop(); }

export function undo() { if (!state.undo.length) return; state.redo.push(snapshot()); restore(state.undo.pop()); }
export function redo() { if (!state.redo.length) return; state.undo.push(snapshot()); restore(state.redo.pop()); }
