//! HLSL, shader model 6.0, in wgpu's D3D12 binding model (registers from group/binding, samplers
//! through naga's sampler heap).

use naga::back::hlsl::{Options, PipelineOptions, ShaderModel, Writer};
use nimbus_dsl::ir::Stage;

use super::glsl::strip_trailing_ws;
use super::{Baked, Contents, TargetNames, naga_stage};

pub(super) fn write(
    baked: &Baked,
    stage: Stage,
    entry: &str,
) -> Result<(Contents, TargetNames), String> {
    let options = Options {
        shader_model: ShaderModel::V6_0,
        fake_missing_bindings: true,
        ..Default::default()
    };
    let pipeline = PipelineOptions {
        entry_point: Some((naga_stage(stage), entry.to_string())),
    };
    let mut text = String::new();
    Writer::new(&mut text, &options, &pipeline)
        .write(&baked.module, &baked.info, None)
        .map_err(|e| e.to_string())?;
    let mut names = TargetNames::new();
    for (_, g) in baked.module.global_variables.iter() {
        let (Some(n), Some(rb)) = (&g.name, g.binding) else {
            continue;
        };
        let reg = match (&g.space, &baked.module.types[g.ty].inner) {
            (naga::AddressSpace::Uniform, _) => {
                format!("register(b{}, space{})", rb.binding, rb.group)
            }
            (naga::AddressSpace::Storage { access }, _)
                if access.contains(naga::StorageAccess::STORE) =>
            {
                format!("register(u{}, space{})", rb.binding, rb.group)
            }
            (_, naga::TypeInner::Sampler { .. }) => format!(
                "nagaSamplerHeap[nagaGroup{}SamplerIndexArray[{}]]",
                rb.group, rb.binding
            ),
            _ => format!("register(t{}, space{})", rb.binding, rb.group),
        };
        names.push((n.clone(), reg));
    }
    names.sort();
    Ok((Contents::Text(strip_trailing_ws(&text)), names))
}
