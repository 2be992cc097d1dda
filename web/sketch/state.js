// The sketch page's state: the keys (the user's work, never lost on
// errors), the library, the result, the view and the undo history.

export const $ = (id) => document.getElementById(id);

export const state = {
  skeleton: null,      // see skeleton.js: { clip, names, parents, channels }
  library: [],         // [{ name, channels }]
  dnaClip: null,       // the last imported clip's motion, { name, motion } (seeded DNA is drawn from it)
  imported: null,      // the last imported clip as text, { name, bvh, frames } (what a gap fill repairs)
  // sorted by frame: [{ frame, channels }] (a pose), [{ frame, root }] (a root-only key)
  // or [{ frame, xy, root, positions }] (a 2-D key: joints' x and y, the root; positions are what is drawn)
  keys: [],
  length: 300,
  frame: 0,
  playing: false,
  result: null,        // { positions, frames, bvh (null until an export writes it), request, method, times }
  ghost: null,         // the same keys with the next seed: { positions, frames, seed, meanDistance }
  selected: -1,        // joint index
  undo: [], redo: [],
  client: null,
  view: null,          // see view.js
  dragPose: null,      // joint positions while a joint is dragged
  // whether the user moved the variation slider: until then requests name no
  // variation and the core's planner (motion::plan) runs each pipeline at its own
  // default (the residual network's for whole poses, the generator's for root paths)
  variationTouched: false,
};

export function setStatus(text, error = false) {
  $('status').textContent = text;
  $('status').classList.toggle('error', error);
}
