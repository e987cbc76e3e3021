//! nimbus-runtime: a thin wgpu layer over codegen's output. It never writes shader text: every
//! pipeline is created from WGSL that codegen printed and naga validated.
//!
//! For now it holds the device setup (any adapter, including lavapipe/llvmpipe on machines
//! without a GPU) and the compute path used by CPU/GPU parity tests.

mod error;
mod gpu;
pub mod parity;
pub mod render;
pub mod textures;

pub use error::RuntimeError;
pub use gpu::{Gpu, GpuInfo, GpuResource};
