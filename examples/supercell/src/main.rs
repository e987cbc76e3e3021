//! Emits the supercell's shaders for every target (validated by naga on the way) and renders
//! it, from this crate's own genus functions.
//!
//! `cargo run --release -p supercell -- [out-folder]` (default `supercell-out`): writes
//! `out-folder/shaders/` (WGSL, GLSL ES 3.00, GLSL 4.50, HLSL, MSL, SPIR-V and their binding
//! manifests, for the cloud pass and its shadow pass) and `out-folder/supercell.png`.

use std::path::PathBuf;

use nimbus_clouds::Quality;
use nimbus_clouds::catalog::ShaderKey;
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_codegen::{EmitExtras, Target, emit, generate_variant};
use nimbus_dsl::ShaderVariant;
use nimbus_output::Overwrite;
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "supercell-out".into()),
    );
    let genus = supercell::genus()?;
    let quality = Quality::High;
    let variant = CloudVariant::new(&genus, quality, quality.features());
    println!("{}: {}", genus.name, genus.description);
    for (slot, name, path, about) in genus.functions.slots() {
        println!("  {slot:<8} {name} ({path}): {about}");
    }
    let mut shaders = vec![ShaderKey::Clouds(variant.key)];
    shaders.extend(variant.key.shadow_key().map(ShaderKey::Shadow));
    let mut generated = Vec::new();
    for key in &shaders {
        // Every target, each validated by naga; an invalid shader stops here.
        let g = generate_variant(key, &Target::ALL)?;
        println!(
            "  {} → {} files, valid on every target",
            key.id(),
            g.files.len()
        );
        generated.push(g);
    }
    std::fs::create_dir_all(&out)?;
    let report = emit(
        &generated,
        &EmitExtras::default(),
        &out.join("shaders"),
        Overwrite::OwnOnly,
    )?;
    println!(
        "wrote {} files to {}",
        report.files.len(),
        report.dir.display()
    );

    let gpu = Gpu::new()?;
    println!("adapter: {}", gpu.info());
    let mut frame = Frame::new(genus, quality, 640, 360);
    frame.camera_altitude = 300.0;
    frame.camera_pitch_deg = 14.0;
    frame.fov_deg = 70.0;
    frame.sun_elevation_deg = 28.0;
    frame.frames = 4;
    let image = Renderer::new(&gpu, TextureSizes::default()).render(&frame)?;
    let png = out.join("supercell.png");
    image.save_png(&png, 8.0, Overwrite::OwnOnly)?;
    println!("wrote {}", png.display());
    Ok(())
}
