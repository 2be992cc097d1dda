//! Skeletons, BVH files and forward kinematics.
//!
//! - [`bvh`]: a reader and writer for any BVH skeleton (per-joint channel
//!   orders, End Sites, any frame time), with line-numbered errors.
//! - [`fk`]: forward kinematics from BVH channels to global positions.

pub mod bvh;
pub mod fk;

pub use bvh::{Bvh, Channel, Joint};
