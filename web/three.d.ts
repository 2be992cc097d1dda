import type { AnimationClip, Bone, Object3D, Skeleton } from 'three';
/** A synthesis result as a three.js Skeleton and AnimationClip (position and quaternion
 *  tracks per joint, as BVHLoader makes them). `skeleton` is DeeprepClient.skeleton. */
export function toThree(
  result: { frames: number; frameTime?: number; translations: Float32Array; quaternions: Float32Array },
  skeleton: { names: string[]; parents: number[]; offsets: number[] },
  opts?: { name?: string },
): { skeleton: Skeleton; clip: AnimationClip; root: Bone; bones: Bone[] };

/** A rigged three.js character (a glTF scene from GLTFLoader, or any Object3D with Bones under it)
 *  as a BVH skeleton on which deeprep can retarget and in-between its clips (docs/retarget.md).
 *  Make it while the character is at rest: the bones' pose then is taken as the rest pose.
 *  Bones an IK rig hangs from the root but that sit where a chain ends (RobotExpressive's
 *  feet) join that chain. Bad input throws a DeeprepError with code E_BAD_INPUT. */
export class Character {
  constructor(root: Object3D);
  readonly root: Object3D;
  /** The bones, in the order `names` and `parent` follow. */
  readonly bones: Bone[];
  /** The BVH joint names: the glTF nodes' own names (`Foot.L`), made unique. */
  readonly names: string[];
  /** Each bone's parent in the BVH (-1 for the root); joined bones have their chain's end. */
  readonly parent: number[];
  /** Bones that joined another chain. */
  readonly joined: number[];
  /** `clip` sampled at `fps` (default 30) as BVH text on this skeleton; the bones are left at rest. */
  toBvh(clip: AnimationClip, opts?: { fps?: number }): string;
  /** A result on this skeleton (client.synthesizeFromBvh(character.toBvh(clip), ...)) as an
   *  AnimationClip for the character: quaternion tracks, and position tracks where bones move. */
  clipFrom(result: { frames: number; frameTime?: number; translations: Float32Array; quaternions: Float32Array },
    opts?: { name?: string }): AnimationClip;
  /** Puts every bone back in its rest pose. */
  rest(): void;
}
