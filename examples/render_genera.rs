//! Renders every genus of the catalogue to PNG through the wgpu runtime (any adapter; lavapipe
//! or llvmpipe without a GPU).
//!
//! `cargo run --release --example render_genera -- [out-folder] [quality]`
//! (default: `genera-renders`, `medium`).

use std::path::{Path, PathBuf};

use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "genera-renders".into()));
    let quality = match args.next() {
        Some(q) => Quality::parse(&q).ok_or_else(|| format!("unknown quality preset `{q}`"))?,
        None => Quality::Medium,
    };
    let lib = CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"))?;
    std::fs::create_dir_all(&out)?;
    let gpu = Gpu::new()?;
    println!("adapter: {}", gpu.info());
    let mut renderer = Renderer::new(&gpu, TextureSizes::default());
    for (name, (_, genus)) in &lib.genera {
        let mut frame = Frame::new(genus.clone(), quality, 480, 270);
        frame.weather_offset = glam::Vec2::new(0.1, 0.1);
        frame.camera_pitch_deg = 15.0;
        let start = std::time::Instant::now();
        let image = renderer.render(&frame)?;
        let file = out.join(format!("{name}.png"));
        image.save_png(&file, 8.0, nimbus_output::Overwrite::OwnOnly)?;
        println!(
            "{name:>16}: {:.2} s -> {}",
            start.elapsed().as_secs_f64(),
            file.display()
        );
    }
    println!(
        "{} pipelines built for {} genera (genera sharing a variant key share pipelines)",
        renderer.pipeline_count(),
        lib.genera.len()
    );
    Ok(())
}
