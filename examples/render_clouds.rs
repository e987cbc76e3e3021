//! Renders a genus to PNG through the wgpu runtime (any adapter; lavapipe without a GPU).
//!
//! `cargo run --release --example render_clouds -- [genus] [quality] [out.png]`

use std::path::Path;

use nimbus_clouds::model::tonemap::tonemap;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let genus_name = args.next().unwrap_or_else(|| "cumulus".into());
    let quality = args
        .next()
        .and_then(|q| Quality::parse(&q))
        .unwrap_or(Quality::Low);
    let out = args
        .next()
        .unwrap_or_else(|| format!("docs/{genus_name}.png"));
    let lib = CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"))?;
    let genus = lib
        .genus(&genus_name)
        .ok_or_else(|| format!("unknown genus `{genus_name}`"))?
        .clone();
    let gpu = Gpu::new()?;
    println!("adapter: {}", gpu.info());
    let mut renderer = Renderer::new(
        &gpu,
        TextureSizes {
            weather: 256,
            shape: 64,
            detail: 32,
            turbulence: 64,
        },
    );
    let frame = Frame::new(genus, quality, 480, 270);
    let start = std::time::Instant::now();
    let image = renderer.render(&frame)?;
    println!(
        "rendered {}x{} in {:.2} s",
        image.width,
        image.height,
        start.elapsed().as_secs_f64()
    );
    let png = image::RgbaImage::from_fn(image.width, image.height, |x, y| {
        let p = image.pixels[(y * image.width + x) as usize];
        let c = tonemap(glam::vec3(p[0], p[1], p[2]), 4.0);
        let to8 = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        image::Rgba([to8(c.x), to8(c.y), to8(c.z), 255])
    });
    // All or nothing, and never over a file Nimbus did not write.
    nimbus_output::write_png(
        std::path::Path::new(&out),
        (png.width(), png.height()),
        png.as_raw(),
        nimbus_output::Overwrite::OwnOnly,
    )?;
    println!("wrote {out}");
    Ok(())
}
