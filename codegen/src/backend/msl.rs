//! Metal Shading Language 2.1 with explicit slots: buffers, textures and samplers are numbered
//! per kind in (group, binding) order.

use naga::back::msl::{
    BindSamplerTarget, BindTarget, EntryPointResources, Options, PipelineOptions,
};
use nimbus_dsl::ir::{Module as DslModule, Stage};

use super::glsl::strip_trailing_ws;
use super::{Baked, Contents, TargetNames, naga_stage};

pub(super) fn write(
    baked: &Baked,
    _dsl: &DslModule,
    stage: Stage,
    entry: &str,
) -> Result<(Contents, TargetNames, Option<String>), String> {
    let mut globals: Vec<_> = baked
        .module
        .global_variables
        .iter()
        .filter_map(|(_, g)| g.binding.map(|rb| (rb, g)))
        .collect();
    globals.sort_by_key(|(rb, _)| (rb.group, rb.binding));
    let mut resources = EntryPointResources::default();
    let mut names = TargetNames::new();
    let (mut buffers, mut textures, mut samplers) = (0u8, 0u8, 0u8);
    for (rb, g) in globals {
        let mut target = BindTarget::default();
        let slot = match &baked.module.types[g.ty].inner {
            naga::TypeInner::Sampler { .. } => {
                target.sampler = Some(BindSamplerTarget::Resource(samplers));
                samplers += 1;
                format!("[[sampler({})]]", samplers - 1)
            }
            naga::TypeInner::Image { .. } => {
                target.texture = Some(textures);
                textures += 1;
                format!("[[texture({})]]", textures - 1)
            }
            _ => {
                target.buffer = Some(buffers);
                target.mutable = matches!(g.space, naga::AddressSpace::Storage { access } if access.contains(naga::StorageAccess::STORE));
                buffers += 1;
                format!("[[buffer({})]]", buffers - 1)
            }
        };
        if let Some(n) = &g.name {
            names.push((n.clone(), slot));
        }
        resources.resources.insert(rb, target);
    }
    // Runtime-sized arrays need a buffer of sizes; give it the next free buffer slot.
    resources.sizes_buffer = Some(buffers);
    let mut options = Options {
        lang_version: (2, 1),
        fake_missing_bindings: false,
        ..Default::default()
    };
    options
        .per_entry_point_map
        .insert(entry.to_string(), resources);
    let pipeline = PipelineOptions {
        entry_point: Some((naga_stage(stage), entry.to_string())),
        ..Default::default()
    };
    let (text, info) =
        naga::back::msl::write_string(&baked.module, &baked.info, &options, &pipeline)
            .map_err(|e| e.to_string())?;
    for r in &info.entry_point_names {
        if let Err(e) = r {
            return Err(e.to_string());
        }
    }
    names.sort();
    // naga declares the sizes buffer only when a runtime-sized array needs it.
    let sizes = text
        .contains("_mslBufferSizes")
        .then(|| format!("[[buffer({buffers})]]"));
    Ok((Contents::Text(strip_trailing_ws(&text)), names, sizes))
}
