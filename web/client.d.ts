/** Progress of a synthesis request, posted by the worker. */
export interface Progress { id: number; stage: string; fraction: number }
/** A synthesized motion. */
export interface SynthesisResult {
  /** The method the request asked for. */
  method: 'model' | 'residual' | 'cond' | 'slerp';
  /** The pipeline that made the motion, as the core's planner (motion::plan) chose it, the same
   *  for the CLI: 'model' runs the residual network where its manifest makes it the default and
   *  the keys are whole poses without DNA, else the conditional network where its manifest makes
   *  it the default for partial keys and it reads them, else the generator. */
  ran: 'residual' | 'cond' | 'cond-dna' | 'fill-mlp' | 'fill' | 'fill-long' | 'generator' | 'slerp' | 'zerovel' | 'hermite';
  /** The variation it ran at: the request's, else the chosen pipeline's own default (0 for SLERP+LERP). */
  variation: number;
  /** BVH text, 60 fps, the model's skeleton; empty when the request said `bvh: false`. */
  bvh: string;
  frames: number;
  /** Global joint positions, frames x joints x 3. */
  positions: Float32Array;
  /** Seconds per frame (1/60, or the clip's for synthesizeFromBvh). */
  frameTime: number;
  /** Local translations (offset plus position channels), frames x joints x 3. */
  translations: Float32Array;
  /** Local rotations as quaternions [x, y, z, w], frames x joints x 4 (deeprep/three.js turns these into an AnimationClip). */
  quaternions: Float32Array;
  /** Milliseconds: generator, RC-FK, path, post-processing (also by name in `stages`). */
  times: number[];
  stages: { generatorMs: number; rcfkMs: number; pathMs: number; postMs: number };
  /** Mean key errors: root and joints before post-processing, then after (also by name in `keyErrors`). */
  keyError: number[];
  keyErrors: { before: { root: number; joints: number }; after: { root: number; joints: number } };
  /** Empty when the networks ran directly; with a gap over 600 frames (up to 3,000) the
   *  synthesis is hierarchical and these are the frames of the critical keys made first. */
  criticalFrames: number[];
}
/** A whole pose: one BVH channel row of the model's skeleton. */
export interface PoseKey { frame: number; channels: number[] }
/** The root's global position only (thesis Sec. 5.4.1: a path on the ground). */
export interface RootKey { frame: number; root: [number, number, number] }
/** Global x and y of joints (front view, Sec. 5.4.2), null where not given, in the
 *  skeleton's joint order (client.skeleton.names); the root's position, or null. */
export interface XyKey { frame: number; xy: ([number, number] | null)[]; root: [number, number, number] | null }
export type Key = PoseKey | RootKey | XyKey;
export interface SynthesisRequest {
  /** Keys of any kind, sorted by frame, unique, each < frames, at most 3,000 apart (over 600: hierarchical)
   *  (instead of keyFrames + keyChannels). Root-only and 2-D keys need method 'model' or 'cond'. */
  keys?: Key[];
  /** Sorted, unique key frames, each < frames, at most 3,000 apart (whole poses; over 600: hierarchical). */
  keyFrames?: number[];
  /** BVH channel rows of the model's skeleton, keys x channels. */
  keyChannels?: number[] | Float32Array;
  frames: number;
  /** Make the keys exact (post-processing; default true). */
  post?: boolean;
  /** After post-processing, pin feet in contact by two-bone IK (default false). */
  footLock?: boolean;
  /** Motion DNA poses as channel rows (may be empty); with `keys`, a list of rows. The generator places them
   *  anywhere; a conditional network that takes DNA (`condDna`) spreads them over the output in the order
   *  given, each steering the frames around its place. */
  dna?: number[] | Float32Array | number[][];
  /** 'residual': the supervised residual network (variation scales its correction; no DNA, post or foot locking).
   *  'cond': the conditional network (whole poses, root positions and 2-D keys of every joint); with DNA, the
   *  DNA network when it is bundled (`condDna`; the result's `ran` is 'cond-dna'). 'model' (the default) sends
   *  DNA to the DNA network too when its manifest says `default_for_dna`, else to the generator. */
  method?: 'model' | 'residual' | 'cond' | 'slerp';
  /** Share of the networks' departure from SLERP+LERP kept, in the pose and the
   *  root path, in [0, 2] (1: the networks as trained; 0: SLERP+LERP).
   *  Default: the pipeline's own (the result's `variation` says which ran; for whole-pose keys
   *  `DeeprepClient.defaultVariation`). */
  variation?: number;
  /** Method 'cond' with `keys`: the seed of its noise input (a non-negative integer; absent: zero
   *  noise). Another seed, another motion through the same keys. */
  seed?: number;
  /** false: the result's `bvh` is empty, its text not written (tens of ms at 2,048 frames;
   *  the tracks and positions are there either way). Default true. */
  bvh?: boolean;
}
/** IK from joint positions (thesis Sec. 4.4.3). */
export interface IkSolution {
  /** The poses as BVH text on the model's skeleton. */
  bvh: string;
  /** BVH channel values, frames x channels. */
  channels: Float32Array;
  /** Forward kinematics of the solution, frames x joints x 3. */
  positions: Float32Array;
  /** Mean and largest distance between input and reconstructed joints (BVH units). */
  meanError: number;
  maxError: number;
}
/** Error codes of DeeprepError. */
export type DeeprepErrorCode = 'E_MODEL_LOAD' | 'E_BAD_BVH' | 'E_BAD_KEYS' | 'E_BAD_INPUT' | 'E_ABORTED'
  | 'E_TERMINATED' | 'E_WORKER' | 'E_WASM_TRAP';
/** Every rejection of the client is one of these. */
export class DeeprepError extends Error {
  readonly code: DeeprepErrorCode;
}
/** A BVH file parsed in the worker (DeeprepClient.importBvh). */
export interface ImportedBvh {
  jointNames: string[];
  channelCount: number;
  frameTime: number;
  frameCount: number;
  /** Channel values, frames x channels. */
  motion: Float32Array;
  /** Global joint positions, frames x joints x 3. */
  positions: Float32Array;
  /** The clip written back as BVH text (on the model's skeleton). */
  bvh: string;
  /** Set when the file was on another humanoid skeleton and was retargeted onto the model's. */
  retargetedFrom: { joints: number; root: string } | null;
}
export interface CreateOptions {
  /** Folder with the model files, resolved against the page. Default: the package's models/. */
  modelBase?: string | URL;
  /** The in-betweening models as bytes and text, instead of fetching them; `fillMlp` and
   *  `fillMlpManifest` add a short-gap fill network (`tween_fill_mlp.onnx` and its manifest's text,
   *  from `fill_mlp export`), which the package does not ship yet. */
  models?: { generator: Uint8Array | ArrayBuffer; path: Uint8Array | ArrayBuffer; manifest: string;
    fillMlp?: Uint8Array | ArrayBuffer; fillMlpManifest?: string };
  workerUrl?: URL | string;
  /** Download, compile and synthesis stages (id 0: start-up). */
  onProgress?: (p: Progress) => void;
  /** 'simd128' loads the plain SIMD wasm even where the browser has relaxed SIMD
   *  (default: the relaxed-SIMD build there, whose fused multiply-adds round differently). */
  wasm?: 'simd128';
}
/** A Promise API over a Web Worker that runs the wasm in-betweening. */
export class DeeprepClient {
  /** Rejects with E_MODEL_LOAD when the models cannot be loaded. */
  static create(opts?: CreateOptions): Promise<DeeprepClient>;
  /** How many times the worker was replaced (after a trap or an abort). */
  readonly restarts: number;
  readonly skeletonBvh: string | null;
  /** The model's skeleton: joint names, parent indices (-1 for the root) and rest offsets (joints x 3). */
  readonly skeleton: { names: string[]; parents: number[]; offsets: number[] };
  readonly hasModel: boolean;
  /** Whether method 'residual' (the supervised residual network on SLERP+LERP) is available. */
  readonly hasResidual: boolean;
  /** Whether method `'cond'` (the conditional network for whole-pose, root-only and 2-D keys) is available. */
  readonly hasCond: boolean;
  /** Whether method `'cond'` takes Motion DNA: the DNA network (`models/tween_cond_dna.onnx`, downloaded on
   *  the first request with DNA it serves) is there, or the conditional network's manifest says `dna`.
   *  When false, DNA with method `'cond'` is an error and method `'generator'` takes it. */
  readonly condDna: boolean;
  /** Whether the gap-filling network is bundled (`fillGaps` with method `'fill'`, and `'model'` on the gap
   *  lengths its manifest gives it; loaded on the first such call). */
  readonly hasFill: boolean;
  /** Whether the long-gap filling network is bundled (`fillGaps` with method `'fill-long'`, and `'model'` on
   *  the gap lengths its manifest gives it; loaded on the first such call). */
  readonly hasFillLong: boolean;
  /** Whether a short-gap fill network is loaded (`fillGaps` with method `'fill-mlp'`, and `'model'` on the
   *  gap lengths its manifest gives it, before the other networks' bands). The package ships none yet:
   *  `create({ models: { ..., fillMlp, fillMlpManifest } })` loads one. */
  readonly hasFillMlp: boolean;
  /** Each gap-filling network's band of the `'model'` fill's gap lengths (frames inside the gap,
   *  `[from, to]` inclusive; null where the network is not bundled or claims none), tried in this order;
   *  other gaps up to 45 frames get the Hermite curve, longer ones the residual network. */
  readonly fillBands: { 'fill-mlp': [number, number] | null; fill: [number, number] | null; 'fill-long': [number, number] | null };
  /** The variation a request without one gets: the model manifest's (chosen on training takes). */
  readonly defaultVariation?: number;
  readonly modelError?: string;
  /** The wasm build the worker runs: 'relaxed-simd' (Chrome 114+) or 'simd128'. */
  readonly wasm: 'relaxed-simd' | 'simd128';
  synthesize(req: SynthesisRequest & { signal?: AbortSignal }): Promise<SynthesisResult>;
  /** One call from a user's clip (BVH text or bytes, any frame rate) to motion: keys are frames of
   *  the clip; resolves with the whole clip at its own frame rate and on its own skeleton, the span
   *  between the first and last key synthesized at 60 fps (resampled there and back). A clip on
   *  another humanoid skeleton is retargeted onto the model's and the result back (docs/retarget.md). */
  synthesizeFromBvh(bvh: string | Uint8Array | ArrayBuffer, opts: { keys: number[]; method?: 'model' | 'slerp';
    post?: boolean; variation?: number; footLock?: boolean; signal?: AbortSignal }): Promise<SynthesisResult>;
  /** Fills gaps in captured motion: each { start, end } (inclusive frames of the clip) is synthesized
   *  from `context.before` frames before it and `context.after` after it (defaults 20 and 1); every
   *  other frame comes back exactly as it was. Bad ranges (reversed, outside the clip, overlapping,
   *  touching the clip's ends) reject with E_BAD_INPUT. 'model' (the default) gives each gap-filling
   *  network the gap lengths its manifest claims, in this order: the short-gap fill network
   *  (`hasFillMlp`), the gap-filling network (`hasFill`), the long-gap filling network (`hasFillLong`);
   *  other gaps up to 45 frames get the context-tangent Hermite curve, longer ones the residual network.
   *  'fill-mlp', 'fill' and 'fill-long' run that network on every gap. */
  fillGaps(bvh: string | Uint8Array | ArrayBuffer, gaps: { start: number; end: number }[],
    opts?: { method?: 'model' | 'fill-mlp' | 'fill' | 'fill-long' | 'residual' | 'cond' | 'slerp' | 'zerovel' | 'hermite';
      context?: { before?: number; after?: number };
      signal?: AbortSignal }): Promise<SynthesisResult>;
  /** A humanoid clip (BVH text or bytes) on another skeleton: `to` is BVH text or bytes whose
   *  skeleton receives the motion (its own motion is ignored), or 'model' (the default). `map`
   *  replaces roles found by name, e.g. { leftShin: 'Knee_L', leftToe: null }. Resolves with BVH
   *  text at the clip's frame rate; a skeleton whose hips, legs or arms cannot be found rejects
   *  with E_BAD_BVH naming them. */
  retarget(bvh: string | Uint8Array | ArrayBuffer, opts?: { to?: 'model' | string | Uint8Array | ArrayBuffer;
    map?: Record<string, string | null>; signal?: AbortSignal }): Promise<string>;
  /** Parses BVH bytes in the worker: a clip on the model's skeleton as it is, another humanoid's
   *  retargeted onto it (`retargetedFrom` says so); anything else rejects with E_BAD_BVH. */
  importBvh(bytes: Uint8Array | ArrayBuffer, opts?: { signal?: AbortSignal }): Promise<ImportedBvh>;
  /** IK from global joint positions (frames x joints x 3, the skeleton's joint order). */
  ik(positions: number[] | Float32Array, frames: number): Promise<IkSolution>;
  rcAngles(channels: number[], joint: number): Promise<number[]>;
  setRcAngles(channels: number[], joint: number, angles: number[]): Promise<number[]>;
  terminate(): void;
}
