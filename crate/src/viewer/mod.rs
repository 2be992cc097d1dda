//! The viewer: a wgpu renderer for skeletons, the ground grid, root
//! trajectories and keyframe poses (and, for the hair and mesh systems, line
//! strips and triangle meshes).
//!
//! - [`camera`]: the orbit/pan/zoom camera (pure math).
//! - [`scene`]: what is drawn, as plain data, and joint picking (pure math).
//! - [`renderer`]: GPU pipelines that draw a scene into any color target:
//!   a WebGPU or WebGL2 canvas in the browser, an offscreen texture natively.
//! - [`gpu`]: device setup and readback, once for every GPU user.
//! - [`headless`] (native): a scene into an RGBA image, for tests and the CLI.
//!
//! App state (keys, timeline, selection) stays with the caller, which
//! rebuilds the [`scene::Scene`] each frame.

pub mod camera;
#[cfg(feature = "gpu")]
pub mod gpu;
#[cfg(all(feature = "gpu", not(target_arch = "wasm32")))]
pub mod headless;
#[cfg(feature = "gpu")]
pub mod renderer;
pub mod scene;

pub use camera::OrbitCamera;
#[cfg(feature = "gpu")]
pub use renderer::Renderer;
pub use scene::{pick_joint, Grid, LineStrips, Scene, SkeletonPose, TriMesh};
