//! The catalogue of emittable module variants: what `nimbus list` shows and `nimbus check`
//! generates. A variant is a module recorded with its generation-time choices fixed.

use crate::cloud::{CloudLibrary, Features, Quality};
use crate::ir::Module;
use crate::model::clouds::{CloudVariant, cloud_module, resolve_module, shadow_module};
use crate::model::preview::{PhaseModel, preview_module};
use crate::{DslError, SpecValue};

/// One emittable variant.
#[derive(Clone, Debug)]
pub struct VariantSource {
    pub module: &'static str,
    pub variant: String,
    pub description: String,
    build: BuildFn,
}

#[derive(Clone, Debug)]
enum BuildFn {
    Preview(PhaseModel),
    Clouds(Box<CloudVariant>),
    Shadow(Box<CloudVariant>),
    Resolve,
}

impl VariantSource {
    /// `module/variant`, the name used on the command line and in manifests.
    pub fn key(&self) -> String {
        format!("{}/{}", self.module, self.variant)
    }

    /// Records the module.
    pub fn build(&self) -> Result<Module, DslError> {
        match &self.build {
            BuildFn::Preview(model) => preview_module(*model),
            BuildFn::Clouds(v) => cloud_module(v),
            BuildFn::Shadow(v) => shadow_module(v),
            BuildFn::Resolve => resolve_module(),
        }
    }

    /// The cloud variant, for cloud modules.
    pub fn cloud_variant(&self) -> Option<&CloudVariant> {
        match &self.build {
            BuildFn::Clouds(v) | BuildFn::Shadow(v) => Some(v),
            BuildFn::Preview(_) | BuildFn::Resolve => None,
        }
    }

    /// A cloud variant as a catalogue entry.
    pub fn clouds(variant: CloudVariant, description: &str) -> VariantSource {
        VariantSource {
            module: "clouds",
            variant: variant.name(),
            description: description.to_string(),
            build: BuildFn::Clouds(Box::new(variant)),
        }
    }

    /// The beer-shadow-map pass of a cloud variant, or `None` when the variant samples no
    /// shadow map (no shadows, and no light shafts in haze): then there is no such pass at all.
    pub fn shadow(variant: &CloudVariant) -> Option<VariantSource> {
        variant.key.uses_shadow_map().then(|| VariantSource {
            module: "cloud_shadow",
            variant: variant.name(),
            description: "beer shadow map atlas for the cloud variant of the same name".into(),
            build: BuildFn::Shadow(Box::new(variant.clone())),
        })
    }

    /// The temporal resolve pass.
    pub fn resolve() -> VariantSource {
        VariantSource {
            module: "resolve",
            variant: "temporal".into(),
            description: "temporal upscaling and accumulation, reprojection, history clipping"
                .into(),
            build: BuildFn::Resolve,
        }
    }
}

/// The sample preview variants (no data needed).
pub fn catalog() -> Vec<VariantSource> {
    PhaseModel::ALL
        .iter()
        .map(|m| VariantSource {
            module: "preview",
            variant: m.suffix(),
            description: "false-colour density profile and phase function preview".into(),
            build: BuildFn::Preview(*m),
        })
        .chain([VariantSource::resolve()])
        .collect()
}

/// Every genus at every quality preset, with the preset's features.
pub fn cloud_catalog(lib: &CloudLibrary) -> Vec<VariantSource> {
    let mut out = Vec::new();
    for (_, genus) in lib.genera.values() {
        for q in Quality::ALL {
            let v = CloudVariant::new(genus, q, q.features());
            out.extend(VariantSource::shadow(&v));
            out.push(VariantSource::clouds(v, &genus.description));
        }
    }
    out
}

/// The cloud variant of `genus` at `quality` with features adjusted by `adjust`.
pub fn cloud_variant(
    lib: &CloudLibrary,
    genus: &str,
    quality: Quality,
    adjust: impl FnOnce(&mut Features),
) -> Option<VariantSource> {
    let g = lib.genus(genus)?;
    let mut features = quality.features();
    adjust(&mut features);
    Some(VariantSource::clouds(
        CloudVariant::new(g, quality, features),
        &g.description,
    ))
}

/// Finds variants by `module/variant`, or every variant of a module by `module`.
pub fn select(name: &str, lib: Option<&CloudLibrary>) -> Vec<VariantSource> {
    let mut all = catalog();
    if let Some(lib) = lib {
        all.extend(cloud_catalog(lib));
    }
    all.into_iter()
        .filter(|v| v.key() == name || v.module == name)
        .collect()
}
