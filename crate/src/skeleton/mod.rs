//! Skeletons, BVH files and forward kinematics.
//!
//! - [`bvh`]: a reader and writer for any BVH skeleton (per-joint channel
//!   orders, End Sites, any frame time), with line-numbered errors.
//! - [`fk`]: forward kinematics from BVH channels to global positions.
//! - [`resample`]: frame-rate conversion (slerped rotations).

pub mod bvh;
pub mod fk;
pub mod resample;

pub use bvh::{Bvh, Channel, Joint};
