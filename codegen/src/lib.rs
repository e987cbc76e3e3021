//! nimbus-codegen: from a recorded DSL module to validated shaders for every target.
//!
//! The chain is `specialise` → `share` (repeated sub-expressions bound once) → `wgsl` (readable printer + span table) → `validate` (naga, the
//! single gate) → `backend` (GLSL ES 3.00, GLSL 4.50, HLSL, MSL, SPIR-V via naga) → `emit`.
//! Codegen knows nothing of wgpu.

mod backend;
pub mod bindings;
mod dts;
mod emit;
mod error;
pub mod external;
mod generate;
pub mod js;
pub mod manifest;
mod names;
mod share;
pub mod specialise;
mod target;
mod uniform_copy;
mod validate;
pub mod wgsl;

pub use backend::{Contents, default_constants};
pub use bindings::{BindingInfo, BindingKind, TextureDimension};
pub use dts::print_dts;
pub use emit::{EmitExtras, EmitReport, MARKER_FILE, emit};
pub use error::{CodegenError, Origin};
pub use generate::{
    Generated, OutputFile, VariantStats, file_name, generate, print_and_validate, shader_id,
};
pub use js::print_js;
pub use target::Target;
pub use uniform_copy::{copy_uniforms_per_invocation, flatten_uniform_blocks};
pub use validate::{Validated, validate};

use nimbus_dsl::ShaderVariant;

/// Records and generates one shader variant for `targets`.
pub fn generate_variant(
    source: &impl ShaderVariant,
    targets: &[Target],
) -> Result<Generated, CodegenError> {
    let module = source.record()?;
    generate(module, &source.variant(), targets)
}
