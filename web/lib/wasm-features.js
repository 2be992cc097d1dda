// What this browser's WebAssembly runs, for picking a build of deeprep's wasm
// (the worker, web/worker.js, and the benchmarks in tests/web/).

// A module that validates only where the browser has relaxed SIMD: three
// f32x4 splats into f32x4.relaxed_madd (opcode 0xfd 0x105).
const RELAXED_SIMD_PROBE = new Uint8Array([
  0, 97, 115, 109, 1, 0, 0, 0, 1, 5, 1, 96, 0, 1, 123, 3, 2, 1, 0, 10, 28, 1, 26, 0,
  67, 0, 0, 0, 0, 253, 19, 67, 0, 0, 0, 0, 253, 19, 67, 0, 0, 0, 0, 253, 19, 253, 133, 2, 11]);

/** Whether this browser runs relaxed SIMD (Chrome 114+): where it does, the
 *  relaxed build's matrix kernel fuses its multiply-adds (issue 23). */
export function hasRelaxedSimd() {
  try { return WebAssembly.validate(RELAXED_SIMD_PROBE); } catch { return false; }
}

/** Rounds of Inbetweener.warmUp (512-frame syntheses of made-up keys) the
 *  worker runs before it reports ready and then, one at a time, while no
 *  request has come: V8 runs a wasm function's first calls on baseline code,
 *  so after the 64-frame synthesis that was the warm-up before them a page's
 *  first 512-frame synthesis took 1.5-1.8x a warm one (issue
 *  23; README, Speed). The benchmarks warm up the same way. */
export const WARM_UP_ROUNDS = { beforeReady: 1, whenIdle: 4 };
