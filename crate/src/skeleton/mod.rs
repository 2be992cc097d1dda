//! Skeletons, BVH files and forward kinematics.
//!
//! - [`bvh`]: a reader and writer for any BVH skeleton (per-joint channel
//!   orders, End Sites, any frame time), with line-numbered errors.
//! - [`pose`]: one frame in local form ([`Pose`]), the one reader and
//!   writer of a BVH channel row.
//! - [`fk`]: forward kinematics from BVH channels to global positions.
//! - [`resample`]: frame-rate conversion (slerped rotations).
//! - [`retarget`]: humanoid roles found by name, motion carried between
//!   skeletons (rest alignment per bone, world-space rotation changes).
//! - [`two_bone`]: two-bone IK (feet locked, feet placed).

pub mod bvh;
pub mod fk;
pub mod pose;
pub mod resample;
pub mod retarget;
pub mod two_bone;

pub use bvh::{Bvh, Channel, Joint};
pub use pose::Pose;
