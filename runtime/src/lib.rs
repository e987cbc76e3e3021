//! nimbus-runtime: a thin wgpu layer over codegen's output. It never writes shader text: every
//! pipeline is created from the naga module codegen lowered from the DSL and validated (or, to
//! check the two agree, from the WGSL codegen printed: [`ShaderInput`]).
//!
//! It opens any adapter (a GPU, or lavapipe/llvmpipe on machines without one), generates the
//! procedural textures with compute kernels, renders cloud variants through the passes they
//! need (shadow atlas, clouds, temporal resolve) with pipelines cached by shader key, and runs
//! compute kernels (the noise textures; the parity harness of `nimbus-testkit`).

pub mod density_export;
mod device_limits;
mod error;
pub mod formation;
mod gpu;
pub mod linear_image;
pub mod mitsuba_scene;
pub mod pipelines;
mod png;
pub mod render;
pub mod scene_depth;
pub mod scene_time;
mod shader_input;
pub mod textures;
pub mod user_textures;

pub use error::RuntimeError;
pub use gpu::{Gpu, GpuInfo, GpuResource, ResourceCounts};
pub use shader_input::ShaderInput;
