//! nimbus-codegen: from a recorded DSL module to validated shaders for every target.
//!
//! The chain is `specialise` → `wgsl` (readable printer + span table) → `validate` (naga, the
//! single gate) → `backend` (GLSL ES 3.00, GLSL 4.50, HLSL, MSL, SPIR-V via naga) → `emit`.
//! Codegen knows nothing of wgpu.

mod backend;
mod emit;
mod error;
pub mod external;
mod generate;
pub mod manifest;
pub mod specialise;
mod target;
mod validate;
pub mod wgsl;

pub use backend::{Contents, default_constants};
pub use emit::{EmitReport, MARKER_FILE, emit};
pub use error::{CodegenError, Origin};
pub use generate::{Generated, OutputFile, VariantStats, file_name, generate, print_and_validate};
pub use nimbus_dsl::catalog::{VariantSource, catalog, cloud_catalog, cloud_variant};
pub use target::Target;
pub use validate::{Validated, validate};

/// Generates one catalogue variant for `targets`.
pub fn generate_variant(
    source: &VariantSource,
    targets: &[Target],
) -> Result<Generated, CodegenError> {
    let module = source.build()?;
    generate(module, &source.variant, targets)
}

/// Finds catalogue variants by `module/variant` or `module`, as a typed error when none match.
pub fn select_variants(
    name: &str,
    lib: Option<&nimbus_dsl::cloud::CloudLibrary>,
) -> Result<Vec<VariantSource>, CodegenError> {
    let found = nimbus_dsl::catalog::select(name, lib);
    if found.is_empty() {
        let mut known: Vec<String> = catalog().iter().map(VariantSource::key).collect();
        if lib.is_some() {
            known.push("clouds/<genus>.<quality> (see `nimbus list`)".into());
        }
        return Err(CodegenError::UnknownVariant {
            given: name.to_string(),
            known: known.join(", "),
        });
    }
    Ok(found)
}
