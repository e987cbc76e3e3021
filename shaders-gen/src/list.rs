//! `nimbus list`.

use std::path::Path;

use nimbus_clouds::catalog::{catalog, cloud_catalog};
use nimbus_clouds::{Quality, Toggle};
use nimbus_codegen::Target;

use crate::error::CliError;

use crate::data::load_dir;
use crate::data_folder::DataFolder;

pub(crate) fn run(data: Option<&Path>) -> Result<(), CliError> {
    let folder = DataFolder::find(data)?;
    let lib = load_dir(&folder.dir)?;
    say!(
        "genera ({}, from {}):",
        folder.dir.join("genera").display(),
        folder.source
    );
    for (name, (_, g)) in &lib.genera {
        say!(
            "  {name:<16} {} layer(s), coverage {:.2}: {}",
            g.layers.len(),
            g.coverage,
            g.description
        );
    }
    say!("scene presets:");
    for (name, (_, s)) in &lib.scenes {
        say!(
            "  {name:<16} {} at {} quality, sun {}°: {}",
            s.genus,
            s.quality.name(),
            s.sun_elevation_deg,
            s.description
        );
    }
    say!("quality presets:");
    for q in Quality::ALL {
        let st = q.settings();
        let off: Vec<&str> = Toggle::ALL
            .iter()
            .copied()
            .filter(|t| !t.get(&q.features()))
            .map(|t| t.name())
            .collect();
        say!(
            "  {:<16} {} steps ≥ {} m, sun {} / ground {} secondary steps, shadow map {}²; off: {}",
            q.name(),
            st.max_iteration_count,
            st.min_step_size,
            st.max_iteration_count_to_sun,
            st.max_iteration_count_to_ground,
            st.shadow_map_size,
            if off.is_empty() {
                "nothing".to_string()
            } else {
                off.join(", ")
            }
        );
    }
    say!("toggles (--enable / --disable; tag in shader keys):");
    for t in Toggle::ALL {
        say!("  {:<26} {:<8} {}", t.name(), t.tag(), t.doc());
    }
    say!("paths (--path, or `path` in a scene's [features]; tag in shader keys):");
    for p in nimbus_clouds::Path::ALL {
        say!(
            "  {:<26} {:<8} {}",
            p.name(),
            p.tag().unwrap_or("-"),
            p.doc(),
        );
    }
    let mut entries = catalog();
    let clouds = cloud_catalog(&lib);
    entries.extend(clouds);
    say!(
        "shaders, one per key ({} genera × {} presets = {} pairs):",
        lib.genera.len(),
        Quality::ALL.len(),
        lib.genera.len() * Quality::ALL.len()
    );
    crate::data::print_sharing(&entries);
    say!("targets:");
    for t in Target::ALL {
        let what = match t {
            Target::Wgsl => "WGSL (wgpu, Bevy, WebGPU); overrides kept",
            Target::GlslEs300 => "GLSL ES 3.00 (WebGL2, three.js); no compute entry points",
            Target::Glsl450 => "GLSL 4.50 core, explicit bindings",
            Target::Hlsl => "HLSL SM 6.0 (D3D12 binding model)",
            Target::Msl => "Metal Shading Language 2.1, explicit slots",
            Target::SpirV => "SPIR-V 1.0 (Vulkan)",
        };
        say!("  {:<24} {what}", t.name());
    }
    Ok(())
}
