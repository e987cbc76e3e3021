//! A short animation: the weather drifts with the wind while the camera turns slowly; each
//! frame is one temporally upscaled frame on the history of the previous ones (as a game loop
//! renders), written as numbered PNGs.
//!
//! `cargo run --release --example animation -- [out-folder] [frames]`
//! (default: `animation`, 48 frames; e.g. `ffmpeg -i animation/frame_%04d.png clouds.mp4`).

use std::path::{Path, PathBuf};

use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

/// Wind in weather tiles (100 km) per frame: 30 m per frame, a time-lapse of a 15 m/s wind
/// filmed at one frame every two seconds.
const DRIFT_PER_FRAME: f32 = 3e-4;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "animation".into()));
    let frames: u32 = args.next().map_or(Ok(48), |n| n.parse())?;
    let lib = CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"))?;
    let genus = lib.genus("cumulus").ok_or("cumulus missing")?.clone();
    std::fs::create_dir_all(&out)?;
    let gpu = Gpu::new()?;
    println!("adapter: {}", gpu.info());
    let mut renderer = Renderer::new(&gpu, TextureSizes::default());
    let mut frame = Frame::new(genus, Quality::Medium, 480, 270);
    frame.genus.coverage = 0.55;
    frame.upscale = true;
    // Fill the history once, then one upscaled frame per picture.
    frame.frames = 16;
    for i in 0..frames {
        let t = i as f32;
        frame.weather_offset = glam::Vec2::new(0.1 + DRIFT_PER_FRAME * t, 0.1);
        frame.camera_yaw_deg = 0.1 * t;
        let image = renderer.render(&frame)?;
        let file = out.join(format!("frame_{i:04}.png"));
        image.save_png(&file, 8.0, nimbus_output::Overwrite::OwnOnly)?;
        println!("{}", file.display());
        frame.frames = 1;
        frame.continue_history = true;
    }
    Ok(())
}
