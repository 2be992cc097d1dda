// BVH export of the result, BVH import (parsed in the worker) into the pose
// library and as the seeded DNA source, and the library's lists.
import { $, setStatus, state } from './state.js';
import { draw } from './view.js';

/**
 * Downloads the result as BVH. A synthesis comes without its text (writing it
 * is a fifth of a long synthesis, and most results are only watched): the
 * first export runs the same request again with it (the synthesis is
 * deterministic) and keeps the text for the next.
 */
export async function exportBvh() {
  const result = state.result;
  if (!result) { setStatus('synthesize first: nothing to export yet', true); return; }
  if (result.bvh === null) {
    setStatus('writing the BVH…');
    try {
      result.bvh = (await state.client.synthesize({ ...result.request, bvh: true })).bvh;
    } catch (e) {
      setStatus(`the export failed: ${e.message} (your keys and the result are unchanged)`, true);
      return;
    }
    setStatus('ready');
  }
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([result.bvh], { type: 'text/plain' }));
  a.download = `deeprep-${result.frames}f.bvh`;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

/** A rigged glTF character's clip as BVH text on its own skeleton (deeprep/three.js'
 *  Character; three.js is loaded on first use). Every clip of the file is offered in
 *  #gltf-clip; `clipName` picks one (default the first). */
async function gltfClipAsBvh(file, clipName) {
  const [{ GLTFLoader }, { Character }] = await Promise.all([import('three/addons/loaders/GLTFLoader.js'), import('../three.js')]);
  const gltf = await new GLTFLoader().parseAsync(await file.arrayBuffer(), '')
    .catch((e) => { throw new Error(`${file.name} is not a glTF file three.js reads: ${e.message || e}`); });
  if (!gltf.animations.length) throw new Error(`${file.name} has no animation clips`);
  const clip = gltf.animations.find((a) => a.name === clipName) || gltf.animations[0];
  const sel = $('gltf-clip');
  sel.innerHTML = '';
  for (const a of gltf.animations) sel.add(new Option(`${a.name} (${a.duration.toFixed(1)} s)`, a.name, false, a === clip));
  sel.onchange = () => importBvh(file, sel.value);
  $('gltf-clip-box').hidden = false;
  return { bvh: new Character(gltf.scene).toBvh(clip, { fps: 30 }), clip: clip.name, clips: gltf.animations.length };
}

/** Imports a BVH clip, or a clip of a rigged glTF character (.glb): parsed in the worker and,
 *  on another humanoid skeleton, retargeted onto the model's. */
export async function importBvh(file, clipName) {
  try {
    let bytes, what = '';
    if (/\.glb$/i.test(file.name)) {
      setStatus(`reading the glTF character ${file.name}…`);
      const g = await gltfClipAsBvh(file, clipName);
      bytes = new TextEncoder().encode(g.bvh);
      what = `, clip ${g.clip} of ${g.clips}`;
    } else {
      $('gltf-clip-box').hidden = true;
      bytes = new Uint8Array(await file.arrayBuffer());
    }
    // Parsed and checked in the synthesis worker: a hostile file can at worst
    // cost that worker (which the client replaces), never this page.
    const clip = await state.client.importBvh(bytes)
      .catch((e) => { throw new Error(`${file.name}: ${e.message}`); });
    const c = clip.channelCount, m = clip.motion, step = Math.max(1, Math.round(0.5 / clip.frameTime));
    let added = 0;
    for (let f = 0; f < clip.frameCount; f += step) {
      state.library.push({ name: `${file.name} @${f}`, channels: Array.from(m.subarray(f * c, (f + 1) * c)) });
      added++;
    }
    if (c === state.skeleton.channels) state.dnaClip = { name: file.name, motion: Float32Array.from(m) };
    // the clip a gap fill repairs (fillGap), as text
    state.imported = { name: file.name, bvh: clip.bvh, frames: clip.frameCount };
    state.result = { positions: clip.positions, frames: clip.frameCount, bvh: clip.bvh, method: 'imported' };
    $('method-badge').textContent = `imported ${file.name}`;
    fillLibrary();
    const from = clip.retargetedFrom ? ` (retargeted from its ${clip.retargetedFrom.joints}-joint skeleton onto the model's)` : '';
    setStatus(`imported ${file.name}${what}${from}: ${added} poses added to the library` + (state.dnaClip?.name === file.name ? '; seeded DNA is drawn from it' : ''));
    draw();
    state.view.frame();
    draw();
  } catch (e) {
    setStatus(`import failed: ${e.message}`, true);
  }
}

/** Refills the pose and DNA lists from the library, keeping the selection. */
export function fillLibrary() {
  for (const id of ['pose', 'dna']) {
    const sel = $(id);
    const keep = [...sel.selectedOptions].map((o) => o.value);
    sel.innerHTML = '';
    state.library.forEach((p, i) => { const o = new Option(p.name, String(i)); o.selected = keep.includes(String(i)); sel.add(o); });
  }
}

/**
 * Fills frames #fill-start..#fill-end of the imported clip from the frames
 * around them (client.fillGaps); the repaired clip is shown, exported by
 * Export BVH, and is what the next fill repairs.
 */
export async function fillGap() {
  const im = state.imported;
  if (!im) { setStatus('import a BVH first: a fill repairs frames of an imported clip', true); return; }
  const start = Number($('fill-start').value), end = Number($('fill-end').value);
  setStatus(`filling frames ${start}-${end} of ${im.name}…`);
  try {
    const r = await state.client.fillGaps(im.bvh, [{ start, end }]);
    im.bvh = r.bvh;
    state.result = { positions: r.positions, frames: r.frames, bvh: r.bvh, method: 'filled' };
    $('method-badge').textContent = `${im.name}: frames ${start}-${end} filled (${r.ran})`;
    document.body.dataset.filled = `${start}-${end}@${r.ran}`;
    setStatus(`filled frames ${start}-${end} of ${im.name} by ${r.ran}; Export BVH writes the repaired clip`);
    $('progress').value = 1;
    $('progress-label').textContent = '';
    draw();
  } catch (e) {
    setStatus(`fill failed: ${e.message} (the clip is unchanged)`, true);
  }
}
