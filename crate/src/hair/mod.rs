//! Hair (thesis ch. 3, HairNet): strands as 100 points in their root's
//! frame on a 32 × 32 scalp grid, the procedural hair data this project
//! trains on, and the reconstruction steps that run after the network.
//!
//! - [`body`]: the four collision ellipsoids of Fig. 3.2 and the collision
//!   error of eq. 3.3–3.5.
//! - [`scalp`]: the 32 × 32 scalp parameterization (Sec. 3.2.3) and roots.
//! - [`strand`]: per-sample curvature, Gaussian smoothing and curl
//!   restoration (Sec. 3.2.4).
//! - [`dataset`]: the procedural training set's files, written and read back.
//! - [`generator`]: procedural hairstyles across Table 3.1's classes
//!   (gravity, stiffness, partings, curls, clumps, collisions, blending).
//! - [`orientation`]: the photo path: a Gabor filter bank turns an image
//!   and a hair mask into the network's orientation input.
//! - [`ppm`]: binary PPM images, the CLI's preview and image input.
//! - [`render`]: the 3 × 256 × 256 network input (undirected orientation and
//!   segmentation) from a view, with per-sample visibility for eq. 3.2.
//! - [`gpu`]: the strand MLPs as a WGSL compute shader, checked against the CPU.
//! - [`model`]: the exported network run by tract, and the reconstruction.
//! - [`job`]: one reconstruction as the CLI, wasm and the page describe it
//!   (a seeded test hair or an image, and the settings).
//! - [`upsample`]: bilinear interpolation of strand features on the scalp
//!   grid to any number of strands (Sec. 3.2.4, Fig. 3.4).
//!
//! The procedural data stand in for USC-HairSalon, which cannot be used
//! here; results on them are not comparable with the thesis' numbers.

pub mod body;
pub mod dataset;
pub mod generator;
#[cfg(all(feature = "gpu", feature = "onnx"))]
pub mod gpu;
pub mod job;
#[cfg(feature = "onnx")]
pub mod model;
pub mod orientation;
pub mod ppm;
pub mod render;
pub mod scalp;
pub mod strand;
pub mod upsample;

pub use body::{Body, Ellipsoid};
pub use generator::{Curl, Hair, HairClass, Length, Style};
pub use job::{HairInput, TestHair};
#[cfg(feature = "onnx")]
pub use job::{HairJob, HairResult};
#[cfg(feature = "onnx")]
pub use model::{blend_features, HairModel, Reconstruct, StrandDecoding, Strands};
pub use render::{render, Render, View, MAX_IMAGE_SIZE};
pub use scalp::Scalp;

/// Points per strand (M in the thesis).
pub const POINTS: usize = 100;
/// Scalp grid side: 32 × 32 = 1024 guide strands (N).
pub const GRID: usize = 32;
