// Helpers for checking deeprep/three.js' Character against three.js itself
// (tests/web/three_character.test.mjs, docs/experiments/robot_retarget_picture.mjs).
import { AnimationMixer, LoopOnce, Vector3 } from 'three';
import { BVHLoader } from 'three/examples/jsm/loaders/BVHLoader.js';

/** BVH text read by three's own BVHLoader, as a synthesis result's local tracks
 *  (End Sites included, file order): what Character.clipFrom takes. */
export function asResult(text) {
  const r = new BVHLoader().parse(text);
  const bones = r.skeleton.bones, J = bones.length, tracks = r.clip.tracks;
  const frames = tracks[0].times.length, frameTime = frames > 1 ? tracks[0].times[1] : 1 / 30;
  const translations = new Float32Array(frames * J * 3), quaternions = new Float32Array(frames * J * 4);
  bones.forEach((b, j) => {
    const end = b.name === 'ENDSITE';
    const pt = !end && tracks.find((t) => t.name === `${b.name}.position`);
    const qt = !end && tracks.find((t) => t.name === `${b.name}.quaternion`);
    for (let f = 0; f < frames; f++) {
      translations.set(pt ? pt.values.subarray(f * 3, f * 3 + 3) : b.position.toArray(), (f * J + j) * 3);
      quaternions.set(qt ? qt.values.subarray(f * 4, f * 4 + 4) : [0, 0, 0, 1], (f * J + j) * 4);
    }
  });
  return { frames, frameTime, translations, quaternions };
}

/** Every bone's world position at each time, the clip played once by AnimationMixer. */
export function play(character, clip, times) {
  const mixer = new AnimationMixer(character.root);
  const action = mixer.clipAction(clip);
  action.setLoop(LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
  const out = times.map((t) => {
    mixer.setTime(t);
    character.root.updateMatrixWorld(true);
    return character.bones.map((b) => b.getWorldPosition(new Vector3()));
  });
  action.stop();
  mixer.uncacheRoot(character.root);
  character.rest();
  return out;
}

