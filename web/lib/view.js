// The wgpu viewer for every page: WebGPU first, WebGL2 when asked or when
// the GPU device is lost; canvas coordinates and orbit controls.
import { Viewer } from '../pkg/deeprep.js';

/**
 * The wgpu viewer on the canvas with id `canvasId` (WebGPU first unless
 * `forceWebgl2`). `view.ensure()` replaces a viewer whose GPU device was
 * lost (a GPU reset, or headless Chromium, whose WebGPU cannot present a
 * canvas) with WebGL2 on a fresh canvas, calling `onReplace(view)` so the
 * page can re-upload its scene and re-wire its listeners. When WebGL2 is
 * unavailable too, `onFail(freshCanvas, error)` is called if given (the
 * sketch page draws on a 2-D canvas then); otherwise `ensure()` rejects.
 */
export async function openView(canvasId, forceWebgl2, onReplace, onFail) {
  const view = { viewer: await Viewer.create(document.getElementById(canvasId), forceWebgl2), replacing: null };
  view.canvas = () => document.getElementById(canvasId);
  view.name = () => view.viewer.backend;
  view.ensure = () => {
    if (!view.viewer.deviceLost || view.replacing) return view.replacing;
    view.replacing = (async () => {
      console.warn(`the ${view.viewer.backend} device was lost; switching to WebGL2`);
      const old = view.canvas();
      const fresh = old.cloneNode(true);
      old.replaceWith(fresh);
      try {
        view.viewer = await Viewer.create(fresh, true);
      } catch (e) {
        view.replacing = null;
        if (!onFail) throw e;
        await onFail(fresh, e); // no WebGL2 either: the page's own fallback on the fresh canvas
        return;
      }
      // the new viewer is in place: the page's redraw in onReplace must not be
      // skipped as "still replacing" (it was, and the hair and mesh pages then
      // showed an empty view after a lost WebGPU device)
      view.replacing = null;
      await onReplace(view);
    })();
    return view.replacing;
  };
  /** RGBA pixels right after `draw()` (for tests). */
  view.pixels = (draw) => {
    draw();
    const c = view.canvas();
    const o = document.createElement('canvas');
    o.width = c.width; o.height = c.height;
    const x = o.getContext('2d');
    x.drawImage(c, 0, 0);
    return x.getImageData(0, 0, o.width, o.height).data;
  };
  return view;
}

/** Canvas pixel coordinates of a mouse event on `canvas`. */
export function toCanvas(canvas, e) {
  const r = canvas.getBoundingClientRect();
  return [((e.clientX - r.left) * canvas.width) / r.width, ((e.clientY - r.top) * canvas.height) / r.height];
}

/**
 * Orbit (drag), pan (shift-drag) and zoom (wheel) on the viewer's canvas;
 * `onDown(x, y)` sees every press. Returns `attach(canvas)` for a
 * replacement canvas (the window listeners are registered once).
 */
export function wireOrbit(view, draw, onDown = () => {}) {
  let drag = null;
  const attach = (canvas) => {
    canvas.addEventListener('mousedown', (e) => {
      const [x, y] = toCanvas(canvas, e);
      onDown(x, y);
      drag = { x, y, pan: e.shiftKey };
    });
    canvas.addEventListener('wheel', (e) => { e.preventDefault(); view.viewer.zoom(Math.exp(e.deltaY * 0.001)); draw(); }, { passive: false });
  };
  attach(view.canvas());
  window.addEventListener('mouseup', () => { drag = null; });
  window.addEventListener('mousemove', (e) => {
    if (!drag) return;
    const [x, y] = toCanvas(view.canvas(), e);
    if (drag.pan) view.viewer.pan(x - drag.x, y - drag.y); else view.viewer.orbit(x - drag.x, y - drag.y);
    drag.x = x; drag.y = y;
    draw();
  });
  return attach;
}
