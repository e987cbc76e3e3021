//! nimbus-codegen: from a recorded DSL module to validated shaders for every target.
//!
//! The chain is `specialise` → `share` (repeated sub-expressions bound once) → `lower` (the IR
//! built straight into a `naga::Module`) → `validate` (naga, the single gate, once per key) →
//! `backend` (GLSL ES 3.00, GLSL 4.50, MSL, SPIR-V via naga) → `emit`. The `wgsl` printer
//! writes the same IR as readable WGSL with a span table, for people, snapshots and WebGPU
//! hosts, and the `hlsl` printer as HLSL in Direct3D 11's binding model; when naga refuses a lowered module, that text is parsed to say which Rust line is at
//! fault. A key asked for more than WGSL runs its per-function passes, prints, baking and
//! translations on every core (rayon; `generate`). Codegen knows nothing of wgpu.

mod backend;
pub mod bindings;
pub mod csharp;
mod dts;
mod emit;
mod error;
pub mod external;
mod generate;
pub mod hlsl;
mod host_functions;
pub mod js;
mod lower;
pub mod manifest;
mod names;
mod share;
pub mod specialise;
mod target;
mod uniform_copy;
mod validate;
pub mod wgsl;
mod wgsl_spelling;

pub use backend::{Contents, default_constants};
pub use bindings::{BindingInfo, BindingKind, TextureDimension};
pub use csharp::print_csharp;
pub use dts::print_dts;
pub use emit::{EmitExtras, EmitReport, MARKER_FILE, emit};
pub use error::{CodegenError, Origin};
pub use generate::{
    Generated, OutputFile, VariantStats, file_name, generate, print_and_validate, shader_id,
};
pub use js::print_js;
pub use target::Target;
pub use uniform_copy::{copy_uniforms_per_invocation, flatten_uniform_blocks};
pub use validate::{Validated, lower_and_validate, validate};
pub use wgsl_spelling::{wgsl_builtin, wgsl_operator, wgsl_scalar, wgsl_type};

use nimbus_dsl::ShaderVariant;

/// Records and generates one shader variant for `targets`.
pub fn generate_variant(
    source: &impl ShaderVariant,
    targets: &[Target],
) -> Result<Generated, CodegenError> {
    let module = source.record()?;
    generate(module, &source.variant(), targets)
}
