//! `nimbus list`.

use nimbus_codegen::{Target, catalog};

pub(crate) fn run() {
    println!("variants (module/variant):");
    for v in catalog() {
        println!("  {:<24} {}", v.key(), v.description);
    }
    println!("targets:");
    for t in Target::ALL {
        let what = match t {
            Target::Wgsl => "WGSL (wgpu, Bevy, WebGPU); overrides kept",
            Target::GlslEs300 => "GLSL ES 3.00 (WebGL2, three.js); no compute entry points",
            Target::Glsl450 => "GLSL 4.50 core, explicit bindings",
            Target::Hlsl => "HLSL SM 6.0 (D3D12 binding model)",
            Target::Msl => "Metal Shading Language 2.1, explicit slots",
            Target::SpirV => "SPIR-V 1.0 (Vulkan)",
        };
        println!("  {:<24} {what}", t.name());
    }
}
