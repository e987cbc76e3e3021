//! The `nimbus` facade: the crates an engine integration needs, under one name.
//!
//! - [`dsl`]: the shader language (`#[shader_fn]`, IR, values); knows nothing of clouds;
//! - [`clouds`]: the cloud model, genus and scene data, effect table, analysis, catalogue;
//! - [`codegen`]: specialisation, the WGSL printer, naga validation, every target;
//! - [`runtime`]: the thin wgpu layer that renders cloud keys.

pub use nimbus_clouds as clouds;
pub use nimbus_codegen as codegen;
pub use nimbus_dsl as dsl;
pub use nimbus_runtime as runtime;
