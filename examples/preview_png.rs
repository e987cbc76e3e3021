//! Renders the sample preview module to PNG with its CPU twin: the same `#[shader_fn]` code the
//! emitted shaders run, evaluated per pixel on the CPU.
//!
//! `cargo run --example preview_png -- [out.png] [hg|dual_lobe]`

use nimbus_clouds::model::preview::{PhaseModel, PreviewParams, preview_fragment};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = args.next().unwrap_or_else(|| "docs/preview.png".into());
    let model = match args.next().as_deref() {
        None | Some("dual_lobe") => PhaseModel::DualLobe,
        Some("hg") => PhaseModel::HenyeyGreenstein,
        Some(other) => return Err(format!("unknown phase model `{other}` (hg, dual_lobe)").into()),
    };
    let (w, h) = (480u32, 270u32);
    let params = PreviewParams {
        resolution: glam::vec2(w as f32, h as f32),
        ..PreviewParams::default()
    };
    let img = image::RgbaImage::from_fn(w, h, |x, y| {
        // Pixel centres, as the rasteriser passes them in @builtin(position).
        let frag = glam::vec4(x as f32 + 0.5, y as f32 + 0.5, 0.0, 1.0);
        let c = preview_fragment(frag, params, 1.0, model);
        let to8 = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        image::Rgba([to8(c.x), to8(c.y), to8(c.z), to8(c.w)])
    });
    if let Some(dir) = std::path::Path::new(&out).parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir)?;
    }
    // All or nothing, and never over a file Nimbus did not write.
    nimbus_output::write_png(
        std::path::Path::new(&out),
        (img.width(), img.height()),
        img.as_raw(),
        nimbus_output::Overwrite::OwnOnly,
    )?;
    println!("wrote {out} ({w}x{h}, {model:?}, CPU twin of preview_fragment)");
    Ok(())
}
