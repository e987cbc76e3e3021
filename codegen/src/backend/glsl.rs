//! GLSL ES 3.00 (WebGL2, three.js) and GLSL 4.50.

use std::collections::BTreeMap;

use naga::back::glsl::{Options, PipelineOptions, Version, Writer, WriterFlags};
use nimbus_dsl::ir::Stage;

use super::{Baked, Contents, TargetNames, naga_stage};
use crate::target::Target;

/// One combined sampler naga wrote: (GLSL name, WGSL texture name, WGSL sampler name).
pub(super) type Combined = (String, String, Option<String>);

pub(super) fn write(
    baked: &Baked,
    target: Target,
    stage: Stage,
    entry: &str,
) -> Result<(Contents, TargetNames, Vec<Combined>), String> {
    let version = match target {
        Target::GlslEs300 => Version::Embedded {
            version: 300,
            is_webgl: true,
        },
        _ => Version::Desktop(450),
    };
    // Desktop GLSL gets explicit `binding =` qualifiers (units numbered in (group, binding)
    // order); WebGL2 has none, so hosts bind by the names in the manifest.
    let mut binding_map = BTreeMap::new();
    if matches!(version, Version::Desktop(_)) {
        let mut rbs: Vec<_> = baked
            .module
            .global_variables
            .iter()
            .filter_map(|(_, g)| g.binding)
            .collect();
        rbs.sort_by_key(|rb| (rb.group, rb.binding));
        for (unit, rb) in rbs.into_iter().enumerate() {
            binding_map.insert(rb, unit as u8);
        }
    }
    let options = Options {
        version,
        // Clip space as GL expects it (y up, z in [-1, 1]), as wgpu's GL backend does.
        writer_flags: WriterFlags::ADJUST_COORDINATE_SPACE,
        binding_map: binding_map.clone(),
        zero_initialize_workgroup_memory: true,
    };
    let pipeline = PipelineOptions {
        shader_stage: naga_stage(stage),
        entry_point: entry.to_string(),
        multiview: None,
    };
    let mut text = String::new();
    let reflection = Writer::new(
        &mut text,
        &baked.module,
        &baked.info,
        &options,
        &pipeline,
        naga::proc::BoundsCheckPolicies::default(),
    )
    .map_err(|e| e.to_string())?
    .write()
    .map_err(|e| e.to_string())?;

    let mut names = TargetNames::new();
    for (handle, block) in &reflection.uniforms {
        if let Some(n) = &baked.module.global_variables[*handle].name {
            names.push((n.clone(), block.clone()));
        }
    }
    // GLSL has no separate textures and samplers: naga writes one combined sampler per
    // (texture, sampler) pair the entry point uses, and a sampler may appear in several.
    let mut combined = Vec::new();
    for (name, mapping) in &reflection.texture_mapping {
        let texture = baked.module.global_variables[mapping.texture].name.clone();
        let sampler = mapping
            .sampler
            .and_then(|s| baked.module.global_variables[s].name.clone());
        // A texture only loaded by texel (`texelFetch`) is a combined sampler with no sampler.
        if let Some(t) = texture {
            combined.push((name.clone(), t, sampler));
        }
    }
    combined.sort();
    // A texture's target name is its combined sampler(s); a sampler has none of its own.
    for (name, texture, _) in &combined {
        match names.iter_mut().find(|(n, _)| n == texture) {
            Some(entry) => entry.1 = format!("{}, {name}", entry.1),
            None => names.push((texture.clone(), name.clone())),
        }
    }
    if !binding_map.is_empty() {
        for (handle, g) in baked.module.global_variables.iter() {
            let _ = handle;
            if let (Some(n), Some(rb)) = (&g.name, g.binding)
                && let Some(unit) = binding_map.get(&rb)
            {
                for entry in names.iter_mut().filter(|(name, _)| name == n) {
                    entry.1 = format!("{} (binding = {unit})", entry.1);
                }
            }
        }
    }
    names.sort();
    Ok((Contents::Text(strip_trailing_ws(&text)), names, combined))
}

pub(super) fn strip_trailing_ws(s: &str) -> String {
    let mut out: String = s
        .lines()
        .map(|l| l.trim_end())
        .collect::<Vec<_>>()
        .join("\n");
    out.push('\n');
    out
}
