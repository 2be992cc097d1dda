//! # deeprep
//!
//! The four systems of "Deep representations for shapes, structures and
//! motion" (Yi Zhou, USC, 2020) for the browser and native code.
//!
//! Modules, one per concept:
//! - [`rotation`]: rotation representations (chapter 4, appendix C).
//! - [`skeleton`]: BVH reading/writing and forward kinematics.
//! - [`rcfk`]: range-constrained forward kinematics (Sec. 5.2.3, Table D.1).
//! - [`motion`]: keyframe in-betweening (chapter 5).
//! - [`ik`]: inverse kinematics from joint positions (Sec. 4.4.3).
//! - [`hair`]: HairNet strands, procedural hair data and reconstruction (ch. 3).
//! - [`mesh`]: mesh graphs and topology-only graph sampling (ch. 2).
//! - [`viewer`]: the wgpu renderer (WebGPU, WebGL2, headless natively).
//! - [`runtime`]: ONNX models run by tract.
//! - [`rng`]: a deterministic seeded random generator.
//! - `wasm` (wasm32 only): the thin wasm-bindgen layer.
//!
//! The core is pure Rust with no web types, so it is tested natively.

// `!(x > eps)` is deliberate throughout: unlike `x <= eps`, it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Index loops mirror the equations they implement (rows, columns, axes).
#![allow(clippy::needless_range_loop)]

pub mod error;
pub mod hair;
#[cfg(feature = "onnx")]
pub mod ik;
pub mod mesh;
pub mod motion;
pub mod rcfk;
pub mod rng;
pub mod rotation;
#[cfg(feature = "onnx")]
pub mod runtime;
pub mod skeleton;
pub mod viewer;

#[cfg(all(target_arch = "wasm32", feature = "onnx"))]
pub mod wasm;

pub use error::{Error, Result};
