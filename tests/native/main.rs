//! The native integration tests, in one binary: each test binary links the
//! library and tract, so nine of them cost nine links and nine copies of the
//! same generic code (issue 48). Run one file's tests with its module name:
//! `cargo test --test native bvh::`. The hostile-input tests are their own
//! binary (tests/native/hostile.rs): they count the process's heap bytes.

mod common;

mod bvh;
mod hair;
mod ik;
mod mesh;
mod motion;
mod onnx_runtime;
mod rcfk;
mod rotation;
mod viewer;
