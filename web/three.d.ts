import type { AnimationClip, Bone, Skeleton } from 'three';
/** A synthesis result as a three.js Skeleton and AnimationClip (position and quaternion
 *  tracks per joint, as BVHLoader makes them). `skeleton` is DeeprepClient.skeleton. */
export function toThree(
  result: { frames: number; frameTime?: number; translations: Float32Array; quaternions: Float32Array },
  skeleton: { names: string[]; parents: number[]; offsets: number[] },
  opts?: { name?: string },
): { skeleton: Skeleton; clip: AnimationClip; root: Bone; bones: Bone[] };
