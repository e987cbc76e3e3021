//! Translation of a validated module to the non-WGSL targets, one entry point at a time.
//!
//! Each entry point is lowered on its own from the IR with its overrides baked as constants
//! (only the functions and globals it reaches, so no stale `override` or unused item remains)
//! and validated once; each backend is then called with every option set explicitly so that
//! debug and release builds emit the same bytes.

mod glsl;
mod msl;
mod spirv;

use crate::wgsl_spelling::wgsl_type;
use naga::back::PipelineConstants;
use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};
use nimbus_dsl::ir::{GlobalKind, Module as DslModule, SamplerDesc, Stage};

use crate::lower::{LowerError, Lowering, lower};
use crate::manifest::{
    BindingManifest, BufferSize, BufferSizes, CombinedSampler, ManifestBinding, ManifestField,
    ManifestOverride, ManifestSampler, ManifestStruct,
};
use crate::target::Target;

/// The contents of one emitted file.
#[derive(Clone, Debug, PartialEq)]
pub enum Contents {
    Text(String),
    SpirV(Vec<u32>),
}

impl Contents {
    /// Bytes as written to disk (SPIR-V little-endian words).
    pub fn to_bytes(&self) -> Vec<u8> {
        match self {
            Contents::Text(s) => s.as_bytes().to_vec(),
            Contents::SpirV(words) => words.iter().flat_map(|w| w.to_le_bytes()).collect(),
        }
    }

    pub fn len_bytes(&self) -> usize {
        match self {
            Contents::Text(s) => s.len(),
            Contents::SpirV(words) => words.len() * 4,
        }
    }
}

pub(crate) fn naga_stage(stage: Stage) -> naga::ShaderStage {
    match stage {
        Stage::Vertex => naga::ShaderStage::Vertex,
        Stage::Fragment => naga::ShaderStage::Fragment,
        Stage::Compute => naga::ShaderStage::Compute,
    }
}

/// The override values of a module (its defaults; a host may bake others).
pub fn default_constants(dsl: &DslModule) -> PipelineConstants {
    let mut pc = PipelineConstants::default();
    for g in &dsl.globals {
        if let GlobalKind::Override { default } = g.kind {
            let v = match default {
                nimbus_dsl::ir::Literal::F32(b) => f64::from(f32::from_bits(b)),
                nimbus_dsl::ir::Literal::I32(v) => f64::from(v),
                nimbus_dsl::ir::Literal::U32(v) => f64::from(v),
                nimbus_dsl::ir::Literal::Bool(v) => f64::from(u8::from(v)),
            };
            pc.insert(g.name.clone(), v);
        }
    }
    pc
}

/// A module specialised for one entry point with overrides baked.
pub(crate) struct Baked {
    pub module: naga::Module,
    pub info: ModuleInfo,
}

pub(crate) fn bake(dsl: &DslModule, entry: &str) -> Result<Baked, String> {
    let lowered = lower(dsl, Lowering::Baked { entry }).map_err(|e| match e {
        LowerError::Codegen(e) => e.to_string(),
        LowerError::Unsupported(what) => format!("cannot lower {what}"),
    })?;
    let module = lowered.module;
    let info = Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .map_err(|e| {
            format!(
                "validation of the baked entry point failed: {}",
                e.as_inner()
            )
        })?;
    Ok(Baked { module, info })
}

/// Translates one entry point to `target`; returns the file contents and, for targets that
/// need one, the binding manifest.
pub(crate) fn translate(
    baked: &Baked,
    constants: &PipelineConstants,
    dsl: &DslModule,
    variant: &str,
    target: Target,
    stage: Stage,
    entry: &str,
) -> Result<(Contents, Option<BindingManifest>), String> {
    let mut combined = Vec::new();
    let mut sizes_slot = None;
    let (contents, names) = match target {
        Target::Wgsl => return Err("WGSL is printed, not translated".into()),
        Target::GlslEs300 | Target::Glsl450 => {
            let (contents, names, pairs) = glsl::write(baked, target, stage, entry)?;
            combined = pairs;
            (contents, names)
        }
        Target::Hlsl => return Err("HLSL is printed, not translated".into()),
        Target::Msl => {
            let (contents, names, sizes) = msl::write(baked, dsl, stage, entry)?;
            sizes_slot = sizes;
            (contents, names)
        }
        Target::SpirV => (spirv::write(baked, stage, entry)?, Vec::new()),
    };
    if !target.has_binding_manifest() {
        return Ok((contents, None));
    }
    let mut manifest = manifest_for(baked, dsl, variant, target, stage, entry, constants, &names);
    manifest.buffer_sizes = sizes_slot.map(|target_name| buffer_sizes(baked, target_name));
    manifest.combined_samplers = combined
        .into_iter()
        .map(|(name, texture, sampler)| {
            // A texture loaded by texel reads no sampler state: nearest, clamped, says the same.
            let desc = match &sampler {
                Some(sampler) => dsl
                    .globals
                    .iter()
                    .find(|g| &g.name == sampler)
                    .and_then(|g| g.sampler)
                    .unwrap_or(SamplerDesc::LINEAR_REPEAT),
                None => SamplerDesc::NEAREST_CLAMP,
            };
            CombinedSampler {
                name,
                texture,
                sampler,
                address_mode: desc.address.name(),
                filter: desc.filter.name(),
            }
        })
        .collect();
    Ok((contents, Some(manifest)))
}

/// MSL's buffer of runtime-sized arrays' byte sizes: naga names one `uint size<N>` member per
/// such global, `N` being the global's index in the module.
fn buffer_sizes(baked: &Baked, target_name: String) -> BufferSizes {
    let members = baked
        .module
        .global_variables
        .iter()
        .filter(|(_, g)| {
            let inner = &baked.module.types[g.ty].inner;
            inner.is_dynamically_sized(&baked.module.types)
        })
        .map(|(h, g)| BufferSize {
            member: format!("size{}", h.index()),
            binding: g.name.clone().unwrap_or_default(),
        })
        .collect();
    BufferSizes {
        target_name,
        members,
    }
}

/// naga's namer appends `_` to identifiers that end in a digit, in every backend.
fn target_member_name(name: &str) -> String {
    if name.ends_with(|c: char| c.is_ascii_digit()) {
        format!("{name}_")
    } else {
        name.to_string()
    }
}

/// Target-specific names, keyed by the WGSL global name.
pub(crate) type TargetNames = Vec<(String, String)>;

#[allow(
    clippy::too_many_arguments,
    reason = "plain data gathered for one manifest"
)]
fn manifest_for(
    baked: &Baked,
    dsl: &DslModule,
    variant: &str,
    target: Target,
    stage: Stage,
    entry: &str,
    constants: &PipelineConstants,
    names: &TargetNames,
) -> BindingManifest {
    let mut bindings = Vec::new();
    for (_, g) in baked.module.global_variables.iter() {
        let (Some(name), Some(rb)) = (&g.name, &g.binding) else {
            continue;
        };
        let Some(src) = dsl.globals.iter().find(|d| &d.name == name) else {
            continue;
        };
        let kind = match (&src.kind, src.ty) {
            (GlobalKind::Uniform { .. }, _) => "uniform",
            (GlobalKind::Storage { .. }, _) => "storage",
            (GlobalKind::Handle { .. }, nimbus_dsl::ir::Type::Sampler) => "sampler",
            (GlobalKind::Handle { .. }, _) => "texture",
            (GlobalKind::Override { .. } | GlobalKind::Const { .. } | GlobalKind::Private, _) => {
                continue;
            }
        };
        let target_name = names
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, t)| t.clone())
            .unwrap_or_default();
        bindings.push(ManifestBinding {
            name: name.clone(),
            kind,
            group: rb.group,
            binding: rb.binding,
            wgsl_type: wgsl_type(src.ty),
            target_name,
            sampler: src.sampler.map(|d| ManifestSampler {
                address_mode: d.address.name(),
                filter: d.filter.name(),
            }),
        });
    }
    bindings.sort_by_key(|a| (a.group, a.binding));
    let mut structs = Vec::new();
    for (_, ty) in baked.module.types.iter() {
        if let naga::TypeInner::Struct { members, span } = &ty.inner {
            let Some(name) = &ty.name else { continue };
            let Some(def) = dsl.structs.iter().find(|s| s.name == name) else {
                continue;
            };
            structs.push(ManifestStruct {
                name: name.clone(),
                size: *span,
                fields: members
                    .iter()
                    .zip(def.fields)
                    .map(|(m, f)| ManifestField {
                        name: f.name.to_string(),
                        target_name: target_member_name(&m.name.clone().unwrap_or_default()),
                        wgsl_type: wgsl_type(f.ty),
                        offset: m.offset,
                    })
                    .collect(),
            });
        }
    }
    let mut overrides: Vec<ManifestOverride> = constants
        .iter()
        .map(|(k, v)| ManifestOverride {
            name: k.clone(),
            value: *v,
        })
        .collect();
    overrides.sort_by(|a, b| a.name.cmp(&b.name));
    BindingManifest {
        module: dsl.name.clone(),
        variant: variant.to_string(),
        target: target.name().to_string(),
        entry_points: [(stage.name().to_string(), entry.to_string())].into(),
        bindings,
        combined_samplers: Vec::new(),
        buffer_sizes: None,
        structs,
        overrides,
    }
}
