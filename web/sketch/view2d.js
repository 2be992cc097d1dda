// The last-resort view when neither WebGPU nor WebGL2 is available (or
// `?view=2d`): the same scene projected onto a 2-D canvas, with the same
// interface as the GPU view (see view.js).
import { state } from './state.js';

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => { const n = Math.hypot(...a) || 1; return [a[0] / n, a[1] / n, a[2] / n]; };

/** A perspective projection for the orbit camera `cam`: world point -> [x, y, depth] or null. */
function camera(cam, canvas) {
  const { yaw, pitch, dist, target } = cam;
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

/** The 2-D view on `canvas` (a canvas that never held a GPU context). */
export function canvasView(canvas) {
  const ctx = canvas.getContext('2d');
  const cam = { yaw: 0.6, pitch: 0.35, dist: 520, target: [0, 80, 0] };
  const scale = () => cam.dist / (canvas.height * 1.3);
  let last = null; // the scene drawn last (what pick() sees)
  return {
    name: '2d',
    canvas: () => canvas,
    draw(scene) {
      last = scene;
      const { pose, keys, keyFrames, trajectory: traj, selected } = scene;
      ctx.fillStyle = '#0b0e11';
      ctx.fillRect(0, 0, canvas.width, canvas.height);
      const proj = camera(cam, canvas);
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
      const pose = last?.pose;
      if (!pose) return -1;
      const proj = camera(cam, canvas);
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
    setView(yaw, pitch) { cam.yaw = yaw; cam.pitch = Math.max(-0.2, Math.min(1.4, pitch)); },
    project(p) { const q = camera(cam, canvas)(p); return q ? [q[0], q[1]] : []; },
    lost: () => false,
    ensure: () => null,
    async pixels() { return ctx.getImageData(0, 0, canvas.width, canvas.height).data; },
  };
}
