//! Meshes (thesis ch. 2): the fully convolutional mesh autoencoder's graph
//! machinery, kept free of any network code.
//!
//! - [`codec`]: the exported autoencoder run by tract, and local latent edits.
//! - [`files`]: the topology and pose-set files the training code reads.
//! - [`graph`]: vertex graphs of meshes of any topology (manifold or not),
//!   ring neighbourhoods and graph distances.
//! - [`obj`]: Wavefront OBJ meshes (any topology) read strictly.
//! - [`rig`]: a rigged glTF character posed on the CPU (rigid parts and
//!   linear blend skinning, animations sampled at any time).
//! - [`topology`]: a rig's welded, connected graph and its sampling levels.
//! - [`shapes`]: meshes the project makes for the thesis' other experiments
//!   (a tetrahedral block, crossing planes, subdivision) and random deformations.
//! - [`template`]: any OBJ or glTF as an autoencoder's template (welded mesh,
//!   sampling, its rig when it has one).
//! - [`sampling`]: graph down- and up-sampling that depends on topology
//!   alone (Sec. 2.2.1, Appendix A.1.2), emitted as the padded index/mask
//!   tables of Appendix A.1.1 for the training code.

#[cfg(feature = "onnx")]
pub mod codec;
pub mod files;
pub mod graph;
pub mod obj;
pub mod rig;
pub mod sampling;
pub mod shapes;
pub mod template;
pub mod topology;

#[cfg(feature = "onnx")]
pub use codec::MeshCodec;
pub use graph::Graph;
pub use rig::Rig;
pub use sampling::{sample, NeighborTable, Sampling};
pub use template::Template;
pub use topology::{Params, Topology, ROBOT_SEED_NODES};
