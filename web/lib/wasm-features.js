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
