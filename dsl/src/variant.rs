//! What a project emits: a module recorded with its generation-time choices fixed, named after
//! them. Codegen generates any `ShaderVariant` without knowing what the project is about.

use crate::ir::Module;
use crate::module::DslError;

/// One shader a project can emit.
pub trait ShaderVariant {
    /// The module's name (`water`, say), which the generated code's header names.
    fn module(&self) -> &str;

    /// The name of this variant within the module, derived from its generation-time key.
    fn variant(&self) -> String;

    /// Records the module.
    fn record(&self) -> Result<Module, DslError>;

    /// `module-variant`: the shader's identity in file names, snapshots and manifests.
    fn id(&self) -> String {
        format!("{}-{}", self.module(), self.variant())
    }
}
