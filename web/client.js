// A Promise API over the synthesis worker, with progress callbacks.
//   const c = await DeeprepClient.create({ modelBase: '../models/onnx', onProgress });
//   const r = await c.synthesize({ keyFrames, keyChannels, frames, post: true, dna: [], method: 'model', variation: 1 });
//   (variation, optional, in [0, 2]: share of the networks' departure from SLERP+LERP kept, pose and
//   root path; 1 = the networks as trained, 0 = SLERP+LERP; absent = c.defaultVariation,
//   the model's own default)
export class DeeprepClient {
  static async create({ modelBase, workerUrl = new URL('./worker.js', import.meta.url), onProgress = () => {} } = {}) {
    const c = new DeeprepClient();
    c.worker = new Worker(workerUrl, { type: 'module' });
    c.pending = new Map();
    c.nextId = 1;
    c.onProgress = onProgress;
    const ready = new Promise((resolve, reject) => {
      c.worker.onerror = (e) => reject(new Error(`worker failed to start: ${e.message || e.type}`));
      c.worker.onmessage = (e) => {
        const m = e.data;
        if (m.type === 'ready') { resolve(m); return; }
        if (m.type === 'progress') { c.onProgress(m); return; }
        const p = c.pending.get(m.id);
        if (!p) return;
        c.pending.delete(m.id);
        if (m.type === 'error') p.reject(new Error(m.message)); else p.resolve(m);
      };
    });
    c.worker.postMessage({ type: 'init', modelBase });
    const info = await ready;
    c.skeletonBvh = info.skeletonBvh;
    c.hasModel = info.hasModel;
    c.defaultVariation = info.defaultVariation;
    c.modelError = info.modelError;
    return c;
  }

  request(msg) {
    const id = this.nextId++;
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject });
      this.worker.postMessage({ ...msg, id });
    });
  }

  synthesize(opts) { return this.request({ type: 'synthesize', ...opts }); }
  /** IK from joint positions: `positions` is frames x joints x 3 (global, the skeleton's joint order). */
  ik(positions, frames) { return this.request({ type: 'ik', positions: Array.from(positions), frames }); }
  rcAngles(channels, joint) { return this.request({ type: 'rcAngles', channels, joint }).then((m) => m.angles); }
  setRcAngles(channels, joint, angles) { return this.request({ type: 'setRcAngles', channels, joint, angles }).then((m) => m.channels); }
  terminate() { this.worker.terminate(); }
}
