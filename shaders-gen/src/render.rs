//! `nimbus render`: a scene file (plus flag overrides) rendered through the wgpu runtime to a
//! PNG, on whatever adapter there is.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::error::CliError;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use nimbus_clouds::{
    CloudLibrary, Features, Genus, Quality, ScenePreset, analyse, load_genus, load_scene,
};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes, TextureSource};
use nimbus_runtime::textures::NoiseKind;

use crate::data;

/// What `nimbus render` takes.
#[derive(Args)]
pub(crate) struct RenderArgs {
    /// Scene file (TOML; see examples/scenes). Default: scenes/default.toml of the data folder.
    scene: Option<PathBuf>,
    /// Output PNG.
    #[arg(short, long, default_value = "clouds.png")]
    out: PathBuf,
    /// Genus: a name from genera/, or the path of a genus TOML file.
    #[arg(short, long)]
    genus: Option<String>,
    /// Quality preset (default: the scene's).
    #[arg(short, long, value_enum)]
    quality: Option<Quality>,
    #[command(flatten)]
    toggles: crate::ToggleArgs,
    /// Image size, WIDTHxHEIGHT.
    #[arg(short, long, default_value = "640x360")]
    resolution: String,
    /// Frames of temporal accumulation (default 4, averaging the march's jitter; 16 with
    /// --upscale, so that every pixel is shaded once).
    #[arg(short, long)]
    frames: Option<u32>,
    /// Temporal upscaling: shade one pixel in sixteen per frame.
    #[arg(long)]
    upscale: bool,
    /// Sun elevation above the horizon (degrees).
    #[arg(long, allow_hyphen_values = true)]
    sun_elevation: Option<f32>,
    /// Sun azimuth, clockwise from north (degrees).
    #[arg(long, allow_hyphen_values = true)]
    sun_azimuth: Option<f32>,
    /// Camera altitude above the ground (m).
    #[arg(long)]
    camera_altitude: Option<f32>,
    /// Camera pitch above the horizon (degrees).
    #[arg(long, allow_hyphen_values = true)]
    pitch: Option<f32>,
    /// Camera heading (degrees).
    #[arg(long, allow_hyphen_values = true)]
    yaw: Option<f32>,
    /// Vertical field of view (degrees).
    #[arg(long)]
    fov: Option<f32>,
    /// Sky coverage 0..1 (overrides the scene's and the genus').
    #[arg(long)]
    coverage: Option<f32>,
    /// Seed of the jitter sequence.
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Exposure applied before the ACES tone curve.
    #[arg(long, default_value_t = 8.0)]
    exposure: f32,
    /// Weather texture (PNG; R, G, B, A = coverage of the layer channels).
    #[arg(long)]
    weather_texture: Option<PathBuf>,
    /// Turbulence texture (PNG; curl vectors in R, G around 0.5).
    #[arg(long)]
    turbulence_texture: Option<PathBuf>,
    /// Shape texture (raw R8 or RGBA8 cube, N³ or 4·N³ bytes).
    #[arg(long)]
    shape_texture: Option<PathBuf>,
    /// Shape-detail texture (raw R8 or RGBA8 cube).
    #[arg(long)]
    detail_texture: Option<PathBuf>,
}

pub(crate) fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("resolution `{s}`: expected WIDTHxHEIGHT, e.g. 640x360");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    Ok((w, h))
}

/// The library a scene's genus names refer to: `--data`, else `$NIMBUS_DATA`, else the folder
/// above the scene's `scenes/` when it has `genera/`, else the repository's examples.
pub(crate) fn library_for(
    data: Option<&Path>,
    scene: Option<&Path>,
) -> Result<CloudLibrary, CliError> {
    if data.is_none() && std::env::var_os("NIMBUS_DATA").is_none() {
        let beside = scene
            .and_then(Path::parent)
            .and_then(Path::parent)
            .filter(|d| d.join("genera").is_dir());
        if let Some(dir) = beside {
            return Ok(CloudLibrary::load(dir)?);
        }
    }
    data::load(data)
}

pub(crate) fn genus_of(lib: &CloudLibrary, name: &str) -> Result<Genus, CliError> {
    if name.ends_with(".toml") || name.contains('/') {
        return Ok(load_genus(Path::new(name))?);
    }
    lib.genus(name).cloned().ok_or_else(|| CliError::Unknown {
        kind: "genus",
        given: name.to_string(),
        known: lib.genera.keys().cloned().collect::<Vec<_>>().join(", "),
    })
}

/// The scene's derived features (see `nimbus explain`), with what the flags changed in the
/// scene taken into account, then the flags' own toggles on top.
fn derive_features(
    scene: &ScenePreset,
    frame: &Frame,
    toggles: &crate::ToggleArgs,
) -> Result<Features, Box<dyn std::error::Error>> {
    let mut seen = scene.clone();
    seen.quality = frame.quality;
    seen.coverage = Some(frame.genus.coverage);
    seen.sun_elevation_deg = frame.sun_elevation_deg;
    seen.camera_altitude = frame.camera_altitude;
    let mut features = analyse(&seen, &frame.genus).features;
    for t in &toggles.enable {
        t.set(&mut features, true);
    }
    for t in &toggles.disable {
        t.set(&mut features, false);
    }
    if let Some(o) = toggles.octaves {
        if !(1..=12).contains(&o) {
            return Err(format!("--octaves must be in 1..=12, got {o}").into());
        }
        features.octaves = o;
    }
    Ok(features)
}

/// Builds the frame the arguments describe (no GPU needed: bad input fails here first).
pub(crate) fn frame(
    data: Option<&Path>,
    a: &RenderArgs,
) -> Result<Frame, Box<dyn std::error::Error>> {
    let (width, height) = parse_resolution(&a.resolution)?;
    let lib = library_for(data, a.scene.as_deref())?;
    let scene_file = match &a.scene {
        Some(p) => p.clone(),
        None => data::data_dir(data).join("scenes/default.toml"),
    };
    let scene = load_scene(&scene_file)?;
    let mut genus = genus_of(&lib, a.genus.as_deref().unwrap_or(&scene.genus))?;
    if let Some(c) = a.coverage.or(scene.coverage) {
        if !(c.is_finite() && (0.0..=1.0).contains(&c)) {
            return Err(format!("--coverage must be in [0, 1], got {c}").into());
        }
        genus.coverage = c;
    }
    let quality = a.quality.unwrap_or(scene.quality);
    let mut seen = scene.clone();
    seen.quality = quality;
    seen.coverage = None; // already in the genus, with --coverage applied
    let mut frame = Frame::from_scene(&seen, &genus, width, height);
    frame.sun_elevation_deg = a.sun_elevation.unwrap_or(scene.sun_elevation_deg);
    frame.sun_azimuth_deg = a.sun_azimuth.unwrap_or(scene.sun_azimuth_deg);
    frame.camera_altitude = a.camera_altitude.unwrap_or(scene.camera_altitude);
    frame.camera_pitch_deg = a.pitch.unwrap_or(scene.camera_pitch_deg);
    frame.camera_yaw_deg = a.yaw.unwrap_or(scene.camera_yaw_deg);
    frame.fov_deg = a.fov.unwrap_or(scene.fov_deg);
    frame.upscale = a.upscale;
    frame.frames = a.frames.unwrap_or(if a.upscale { 16 } else { 4 });
    frame.seed = a.seed;
    let checks = [
        ("--sun-elevation", frame.sun_elevation_deg, -90.0, 90.0),
        ("--camera-altitude", frame.camera_altitude, 0.0, 1e6),
        ("--pitch", frame.camera_pitch_deg, -90.0, 90.0),
        ("--fov", frame.fov_deg, 1.0, 179.0),
    ];
    for (flag, v, lo, hi) in checks {
        if !(v.is_finite() && (lo..=hi).contains(&v)) {
            return Err(format!("{flag} must be in [{lo}, {hi}], got {v}").into());
        }
    }
    if frame.frames == 0 || frame.frames > 4096 {
        return Err(format!("--frames must be in 1..=4096, got {}", frame.frames).into());
    }
    frame.features = derive_features(&scene, &frame, &a.toggles)?;
    Ok(frame)
}

pub(crate) fn run(data: Option<&Path>, a: &RenderArgs) -> Result<(), Box<dyn std::error::Error>> {
    let frame = frame(data, a)?;
    let gpu = Gpu::new()?;
    println!("adapter: {}", gpu.info());
    let mut renderer = Renderer::new(&gpu, TextureSizes::default());
    let user = [
        (NoiseKind::Weather, &a.weather_texture, false),
        (NoiseKind::Turbulence, &a.turbulence_texture, false),
        (NoiseKind::Shape, &a.shape_texture, true),
        (NoiseKind::Detail, &a.detail_texture, true),
    ];
    for (kind, path, volume) in user {
        if let Some(p) = path {
            let t = if volume {
                gpu.load_raw_volume(p)?
            } else {
                gpu.load_png_texture(p)?
            };
            renderer.set_texture(kind, TextureSource::User(t));
        }
    }
    let variant = frame.variant();
    println!(
        "variant: {} ({}x{}, {} frame{}{})",
        variant.name(),
        frame.width,
        frame.height,
        frame.frames,
        if frame.frames == 1 { "" } else { "s" },
        if frame.upscale { ", upscaled 1/16" } else { "" }
    );
    println!(
        "shader: {}",
        nimbus_dsl::ShaderVariant::id(&nimbus_clouds::catalog::ShaderKey::Clouds(variant.key))
    );
    let bar = ProgressBar::new(u64::from(frame.frames));
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames  {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let image = renderer.render_with_progress(&frame, &mut |done, _| {
        bar.set_position(u64::from(done));
    });
    bar.finish_and_clear();
    let image = image?;
    image.save_png(&a.out, a.exposure)?;
    let stats = renderer.stats();
    let mut passes: Vec<(&str, usize)> = Vec::new();
    for p in &stats.passes {
        match passes.iter_mut().find(|(n, _)| n == p) {
            Some((_, c)) => *c += 1,
            None => passes.push((p, 1)),
        }
    }
    let passes: Vec<String> = passes.iter().map(|(n, c)| format!("{n} ×{c}")).collect();
    println!(
        "rendered in {:.2} s (passes: {}); wrote {}",
        start.elapsed().as_secs_f64(),
        passes.join(", "),
        a.out.display()
    );
    Ok(())
}
