//! A genus defined in TOML outside the catalogue (examples/custom/anvil-tower.toml), validated
//! like any other and rendered to PNG.
//!
//! `cargo run --release --example custom_genus -- [genus.toml] [out.png]`

use std::path::{Path, PathBuf};

use nimbus_clouds::{Quality, load_genus};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let file = args.next().map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/custom/anvil-tower.toml"),
        PathBuf::from,
    );
    let out = PathBuf::from(args.next().unwrap_or_else(|| "anvil-tower.png".into()));
    // A bad file stops here with its path, the field and the reason.
    let genus = load_genus(&file)?;
    println!(
        "{}: {} layer(s), {}",
        genus.name,
        genus.layers.len(),
        genus.description
    );
    let gpu = Gpu::new()?;
    println!("adapter: {}", gpu.info());
    let mut frame = Frame::new(genus, Quality::High, 640, 360);
    frame.camera_pitch_deg = 18.0;
    frame.sun_elevation_deg = 20.0;
    frame.weather_offset = glam::Vec2::new(0.1, 0.1);
    let image = Renderer::new(&gpu, TextureSizes::default()).render(&frame)?;
    image.save_png(&out, 8.0, nimbus_output::Overwrite::OwnOnly)?;
    println!("wrote {}", out.display());
    Ok(())
}
