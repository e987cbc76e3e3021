//! Every binding of a generated module, described as data: slot, kind, type, sampler state and
//! the stages that read it. A host builds its bind-group layouts and bind groups from this
//! description (the wgpu runtime does), never from the WGSL text or a global's name.

use crate::wgsl_spelling::wgsl_type;
use nimbus_dsl::ir::{GlobalKind, Module, SamplerDesc, Stage, Type};
use serde::Serialize;

use crate::validate::Validated;

/// The dimension of a texture binding (2D or 3D, sampled as filterable float).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum TextureDimension {
    D2,
    D3,
}

/// What is bound at a slot.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum BindingKind {
    /// A uniform buffer holding one struct of `size` bytes (naga's layout).
    Uniform { struct_name: String, size: u32 },
    /// A storage buffer of scalars.
    Storage { read_write: bool },
    /// A float texture; `filterable` when some entry point samples it, else it is only loaded
    /// by texel (`textureLoad`) and binds unfilterable textures too (an engine's depth).
    Texture {
        dimension: TextureDimension,
        filterable: bool,
    },
    /// A filtering sampler with its declared state.
    Sampler(SamplerDesc),
}

impl BindingKind {
    /// `uniform`, `storage`, `texture` or `sampler`, as the manifests spell it.
    pub fn word(&self) -> &'static str {
        match self {
            BindingKind::Uniform { .. } => "uniform",
            BindingKind::Storage { .. } => "storage",
            BindingKind::Texture { .. } => "texture",
            BindingKind::Sampler(_) => "sampler",
        }
    }
}

/// One binding of a generated module.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct BindingInfo {
    pub group: u32,
    pub binding: u32,
    /// The WGSL name (for people and manifests; hosts bind by slot).
    pub name: String,
    pub kind: BindingKind,
    /// The WGSL type.
    pub wgsl_type: String,
    /// The stages whose entry points read it, in stage order.
    pub visibility: Vec<Stage>,
}

impl BindingInfo {
    /// Whether any entry point of `stage` reads it.
    pub fn visible_in(&self, stage: Stage) -> bool {
        self.visibility.contains(&stage)
    }
}

/// Whether any function of `naga` samples the texture `global` (rather than only loading it).
fn sampled(naga: &naga::Module, global: naga::Handle<naga::GlobalVariable>) -> bool {
    let functions = naga
        .functions
        .iter()
        .map(|(_, f)| f)
        .chain(naga.entry_points.iter().map(|e| &e.function));
    for f in functions {
        for (_, e) in f.expressions.iter() {
            if let naga::Expression::ImageSample { image, .. } = e
                && matches!(f.expressions[*image], naga::Expression::GlobalVariable(g) if g == global)
            {
                return true;
            }
        }
    }
    false
}

/// The bindings of a specialised, validated module, in (group, binding) order. Only bindings
/// some entry point reaches remain after specialisation.
pub(crate) fn describe(dsl: &Module, validated: &Validated) -> Vec<BindingInfo> {
    let naga = &validated.module;
    let mut out = Vec::new();
    for (i, g) in dsl.globals.iter().enumerate() {
        let Some((group, binding)) = g.binding() else {
            continue;
        };
        let handle = validated.globals.get(i).copied().flatten();
        let kind = match (&g.kind, g.ty) {
            (GlobalKind::Uniform { .. }, Type::Struct(def)) => BindingKind::Uniform {
                struct_name: def.name.to_string(),
                size: handle.map_or(0, |h| {
                    naga.types[naga.global_variables[h].ty]
                        .inner
                        .size(naga.to_ctx())
                }),
            },
            (GlobalKind::Uniform { .. }, _) => BindingKind::Uniform {
                struct_name: wgsl_type(g.ty),
                size: handle.map_or(0, |h| {
                    naga.types[naga.global_variables[h].ty]
                        .inner
                        .size(naga.to_ctx())
                }),
            },
            (GlobalKind::Storage { read_write, .. }, _) => BindingKind::Storage {
                read_write: *read_write,
            },
            (GlobalKind::Handle { .. }, Type::Sampler) => {
                BindingKind::Sampler(g.sampler.unwrap_or(SamplerDesc::LINEAR_REPEAT))
            }
            (GlobalKind::Handle { .. }, Type::Texture3d) => BindingKind::Texture {
                dimension: TextureDimension::D3,
                filterable: handle.is_none_or(|h| sampled(naga, h)),
            },
            (GlobalKind::Handle { .. }, _) => BindingKind::Texture {
                dimension: TextureDimension::D2,
                filterable: handle.is_none_or(|h| sampled(naga, h)),
            },
            (GlobalKind::Override { .. } | GlobalKind::Const { .. } | GlobalKind::Private, _) => {
                continue;
            }
        };
        let mut visibility = Vec::new();
        if let Some(h) = handle {
            for (i, ep) in naga.entry_points.iter().enumerate() {
                let stage = match ep.stage {
                    naga::ShaderStage::Vertex => Stage::Vertex,
                    naga::ShaderStage::Fragment => Stage::Fragment,
                    _ => Stage::Compute,
                };
                if !validated.info.get_entry_point(i)[h].is_empty() && !visibility.contains(&stage)
                {
                    visibility.push(stage);
                }
            }
        }
        visibility.sort();
        out.push(BindingInfo {
            group,
            binding,
            name: g.name.clone(),
            kind,
            wgsl_type: wgsl_type(g.ty),
            visibility,
        });
    }
    out.sort_by_key(|b| (b.group, b.binding));
    out
}
