//! nimbus-testkit: the instruments Nimbus is checked and measured with, kept out of the
//! libraries an engine integration links (`nimbus-dsl`, `nimbus-clouds`, `nimbus-codegen`,
//! `nimbus-runtime`). Only tests, benches and the `nimbus` CLI depend on it.
//!
//! - [`stability`]: the named hard cases and their invariants, run on the CPU twins and,
//!   through the generated shaders, on the GPU;
//! - [`parity`]: runs `#[shader_fn]`s as compute kernels over many inputs, for CPU/GPU parity;
//! - [`fuzz`]: the bodies of the fuzz targets, shared with the default run's smoke test;
//! - [`metrics`]: RMSE, PSNR and SSIM between two images;
//! - [`tradeoff`]: the accuracy study (presets and effects against a converged reference).

pub mod fuzz;
pub mod metrics;
pub mod mutation;
pub mod parity;
pub mod skip;
pub mod stability;
pub mod tradeoff;
