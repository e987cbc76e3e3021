//! The catalogue of emittable module variants: what `nimbus list` shows and `nimbus check`
//! generates. A variant is a module recorded with its generation-time choices fixed.

use crate::ir::Module;
use crate::model::preview::{PhaseModel, preview_module};
use crate::{DslError, SpecValue};

/// One emittable variant.
#[derive(Clone, Debug)]
pub struct VariantSource {
    pub module: &'static str,
    pub variant: String,
    pub description: &'static str,
    build: BuildFn,
}

#[derive(Clone, Copy, Debug)]
enum BuildFn {
    Preview(PhaseModel),
}

impl VariantSource {
    /// `module/variant`, the name used on the command line and in manifests.
    pub fn key(&self) -> String {
        format!("{}/{}", self.module, self.variant)
    }

    /// Records the module.
    pub fn build(&self) -> Result<Module, DslError> {
        match self.build {
            BuildFn::Preview(model) => preview_module(model),
        }
    }
}

/// Every variant, in a stable order.
pub fn catalog() -> Vec<VariantSource> {
    PhaseModel::ALL
        .iter()
        .map(|m| VariantSource {
            module: "preview",
            variant: m.suffix(),
            description: "false-colour density profile and phase function preview",
            build: BuildFn::Preview(*m),
        })
        .collect()
}

/// Finds variants by `module/variant`, or every variant of a module by `module`.
pub fn select(name: &str) -> Vec<VariantSource> {
    catalog()
        .into_iter()
        .filter(|v| v.key() == name || v.module == name)
        .collect()
}
