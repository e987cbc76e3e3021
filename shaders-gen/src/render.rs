//! `nimbus render`: a scene file (plus flag overrides) rendered through the wgpu runtime to a
//! PNG, on whatever adapter there is.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::error::CliError;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use nimbus_clouds::limits::{self, Limit, Origin};
use nimbus_clouds::{Features, Genus, Quality, ScenePreset, Toggle, analyse, load_scene};
use nimbus_output::{Overwrite, Signature, check_file};
use nimbus_runtime::Gpu;
use nimbus_runtime::formation::FormationSim;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes, TextureSource};
use nimbus_runtime::textures::NoiseKind;
use nimbus_runtime::user_textures::DecodedTexture;

use crate::data;
use crate::scene_input::SceneInput;

/// What `nimbus render` takes.
#[derive(Args)]
pub(crate) struct RenderArgs {
    /// Scene file (TOML; see examples/scenes). Default: scenes/default.toml of the data folder.
    scene: Option<PathBuf>,
    /// Output file: a tonemapped PNG, or with `--format exr` (or a `.exr` name) a linear
    /// OpenEXR with the composited image and the clouds' radiance, transmittance and depth.
    #[arg(short, long, default_value = "clouds.png")]
    out: PathBuf,
    /// Output format (default: from the output's extension, PNG unless it is `.exr`).
    #[arg(long, value_enum)]
    format: Option<ImageFormat>,
    /// Verification mode: pure single scattering of a sun of irradiance 1 (one octave unless
    /// --octaves says more, no diffusion unless --enable diffusion asks; no powder, ground bounce, sky light, sun filtering, haze, aerial
    /// perspective or background), as an independent path tracer renders the same density.
    #[arg(long)]
    verification: bool,
    /// Replace the output file even when Nimbus did not write it.
    #[arg(long)]
    force: bool,
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
    /// Seconds into the scene's timeline: the sun follows its clock, the clouds its wind, the
    /// weather its states (see `nimbus animate`).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) time: Option<f64>,
    /// Sun elevation above the horizon (degrees).
    #[arg(long, allow_hyphen_values = true)]
    sun_elevation: Option<f32>,
    /// Sun azimuth, clockwise from north (degrees).
    #[arg(long, allow_hyphen_values = true)]
    sun_azimuth: Option<f32>,
    /// Camera altitude above the ground (m).
    #[arg(long, allow_hyphen_values = true)]
    camera_altitude: Option<f32>,
    /// Camera pitch above the horizon (degrees).
    #[arg(long, allow_hyphen_values = true)]
    pitch: Option<f32>,
    /// Camera heading (degrees).
    #[arg(long, allow_hyphen_values = true)]
    yaw: Option<f32>,
    /// Vertical field of view (degrees).
    #[arg(long, allow_hyphen_values = true)]
    fov: Option<f32>,
    /// Sky coverage 0..1 (overrides the scene's and the genus').
    #[arg(long, allow_hyphen_values = true)]
    coverage: Option<f32>,
    /// Seed of the jitter sequence.
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Exposure applied before the ACES tone curve.
    #[arg(long, default_value_t = 8.0, allow_hyphen_values = true)]
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

/// What `render` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum ImageFormat {
    /// Display-referred 8-bit sRGB through exposure and the ACES curve.
    Png,
    /// Linear 32-bit float layers: R G B A, clouds.R G B, clouds.transmittance, depth.Z.
    Exr,
}

impl ImageFormat {
    /// The extension a file of this format carries.
    fn extension(self) -> &'static str {
        match self {
            ImageFormat::Png => "png",
            ImageFormat::Exr => "exr",
        }
    }

    /// The format `--format` names, else the one `out`'s extension implies (PNG for a name
    /// without one). A name with another format's extension is refused: the bytes would not
    /// be what the name says (PNG bytes in `out.jpg`, an EXR in `out.png`).
    fn of(flag: Option<ImageFormat>, out: &Path) -> Result<ImageFormat, CliError> {
        let ext = out
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        let implied = match ext.as_deref() {
            None => None,
            Some("png") => Some(ImageFormat::Png),
            Some("exr") => Some(ImageFormat::Exr),
            Some(other) => {
                return Err(CliError::Refused {
                    what: "--out",
                    given: format!("{} names a .{other} file", out.display()),
                    accepted: format!(
                        "Nimbus writes PNG (.png) or OpenEXR (.exr): name it {}",
                        out.with_extension(flag.unwrap_or(ImageFormat::Png).extension())
                            .display()
                    ),
                });
            }
        };
        match (flag, implied) {
            (Some(f), Some(i)) if f != i => Err(CliError::Refused {
                what: "--format",
                given: format!(
                    "{} writes {}, but -o {} names a .{} file",
                    f.extension(),
                    f.extension().to_uppercase(),
                    out.display(),
                    i.extension()
                ),
                accepted: format!(
                    "name it {}, or drop --format",
                    out.with_extension(f.extension()).display()
                ),
            }),
            (Some(f), _) => Ok(f),
            (None, i) => Ok(i.unwrap_or(ImageFormat::Png)),
        }
    }
}

/// `WIDTHxHEIGHT`, each side checked against [`limits::IMAGE_SIDE`]; errors name `flag`.
pub(crate) fn parse_resolution_flag(
    flag: &'static str,
    s: &str,
) -> Result<(u32, u32), Box<dyn std::error::Error>> {
    let bad = || format!("{flag}: `{s}` is not WIDTHxHEIGHT (e.g. 640x360)");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    for side in [w, h] {
        limits::IMAGE_SIDE.check(f64::from(side), Origin::Flag(flag))?;
    }
    Ok((w, h))
}

/// `--resolution WIDTHxHEIGHT`.
pub(crate) fn parse_resolution(s: &str) -> Result<(u32, u32), Box<dyn std::error::Error>> {
    parse_resolution_flag("--resolution", s)
}

/// The textures given by flags, read and checked on the CPU; an error names the flag.
fn user_textures(
    a: &RenderArgs,
) -> Result<Vec<(NoiseKind, &'static str, DecodedTexture)>, CliError> {
    let given = [
        (
            NoiseKind::Weather,
            "--weather-texture",
            &a.weather_texture,
            false,
        ),
        (
            NoiseKind::Turbulence,
            "--turbulence-texture",
            &a.turbulence_texture,
            false,
        ),
        (NoiseKind::Shape, "--shape-texture", &a.shape_texture, true),
        (
            NoiseKind::Detail,
            "--detail-texture",
            &a.detail_texture,
            true,
        ),
    ];
    let mut out = Vec::new();
    for (kind, flag, path, volume) in given {
        if let Some(p) = path {
            let t = if volume {
                DecodedTexture::raw_volume(p)
            } else {
                DecodedTexture::png(p)
            };
            out.push((
                kind,
                flag,
                t.map_err(|source| CliError::Texture {
                    flag,
                    source: Box::new(source),
                })?,
            ));
        }
    }
    Ok(out)
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
        limits::OCTAVES.check(f64::from(o), Origin::Flag(limits::OCTAVES.flag))?;
        features.octaves = o;
    }
    // A scene file's path was checked when it was loaded.
    if let Some(p) = toggles.path {
        features.path = p;
    }
    Ok(features)
}

/// Builds the frame the arguments describe. Every value is checked here, before any GPU work,
/// through the one path every command shares ([`nimbus_clouds::limits`]): the scene file's own
/// values when it is loaded, then the flags' overrides, each error naming the flag or the
/// file and field the value came from.
pub(crate) fn frame(
    data: Option<&Path>,
    a: &RenderArgs,
) -> Result<Frame, Box<dyn std::error::Error>> {
    let mut frames = frames(data, a)?;
    if frames.len() > 1 {
        return Err(CliError::Unknown {
            kind: "--time for this command",
            given: "a moment while one genus gives way to another".into(),
            known: "a time at which one weather state holds (or changes within its genus)".into(),
        }
        .into());
    }
    Ok(frames.remove(0).0)
}

/// The frames the arguments describe, each with its weight in the picture: one, or with
/// `--time` during a change of genus two, blended ([`nimbus_clouds::timeline`]). At `--time`
/// the sun follows the scene's clock (unless a flag sets it), the clouds its wind, and the
/// genus and coverage its weather states.
pub(crate) fn frames(
    data: Option<&Path>,
    a: &RenderArgs,
) -> Result<Vec<(Frame, f32)>, Box<dyn std::error::Error>> {
    let input = SceneInput::load(data, &scene_file(data, a)?, a.genus.as_deref())?;
    // A scene without a timeline is the same at every time; one with a clock, wind or weather
    // states starts at second 0.
    let seconds = a.time.unwrap_or(0.0);
    limits::TIME.check(seconds, Origin::Flag(limits::TIME.flag))?;
    let mut out = Vec::new();
    for state in input.at(seconds)? {
        let mut f = frame_of(a, &input.file, state.scene, state.genus)?;
        f.wind = state.drift;
        out.push((f, state.weight));
    }
    Ok(out)
}

/// The scene file `--scene` names, or the data folder's default scene.
fn scene_file(data: Option<&Path>, a: &RenderArgs) -> Result<PathBuf, Box<dyn std::error::Error>> {
    Ok(match &a.scene {
        Some(p) => p.clone(),
        None => data::data_dir(data)?.join("scenes/default.toml"),
    })
}

/// The frame of `scene` (already at the asked time) with the flags' overrides.
fn frame_of(
    a: &RenderArgs,
    scene_file: &Path,
    scene: ScenePreset,
    mut genus: Genus,
) -> Result<Frame, Box<dyn std::error::Error>> {
    let (width, height) = parse_resolution(&a.resolution)?;
    limits::EXPOSURE.check(f64::from(a.exposure), Origin::Flag(limits::EXPOSURE.flag))?;

    // The flags override the scene; what they set is checked as theirs.
    let mut seen = scene.clone();
    let mut flagged: Vec<&'static str> = Vec::new();
    let mut set = |limit: &Limit, flag: Option<f32>, field: &mut f32| {
        if let Some(v) = flag {
            *field = v;
            flagged.push(limit.field);
        }
    };
    set(
        &limits::SUN_ELEVATION,
        a.sun_elevation,
        &mut seen.sun_elevation_deg,
    );
    set(
        &limits::SUN_AZIMUTH,
        a.sun_azimuth,
        &mut seen.sun_azimuth_deg,
    );
    set(
        &limits::CAMERA_ALTITUDE,
        a.camera_altitude,
        &mut seen.camera_altitude,
    );
    set(&limits::CAMERA_PITCH, a.pitch, &mut seen.camera_pitch_deg);
    set(&limits::CAMERA_YAW, a.yaw, &mut seen.camera_yaw_deg);
    set(&limits::FOV, a.fov, &mut seen.fov_deg);
    if let Some(c) = a.coverage {
        seen.coverage = Some(c);
        flagged.push(limits::COVERAGE.field);
    }
    if let Some(q) = a.quality {
        seen.quality = q;
    }
    seen.validate_from(&|l: &Limit| {
        if flagged.contains(&l.field) {
            Origin::Flag(l.flag)
        } else {
            Origin::File {
                file: scene_file.to_path_buf(),
                field: l.field.to_string(),
            }
        }
    })?;
    if let Some(c) = seen.coverage {
        genus.coverage = c;
    }
    seen.coverage = None; // now in the genus
    let frames = a.frames.unwrap_or(if a.upscale { 16 } else { 4 });
    limits::FRAMES.check(f64::from(frames), Origin::Flag(limits::FRAMES.flag))?;
    let mut frame = Frame::from_scene(&seen, &genus, width, height);
    frame.upscale = a.upscale;
    frame.frames = frames;
    frame.seed = a.seed;
    frame.verification = a.verification;
    frame.features = derive_features(&scene, &frame, &a.toggles)?;
    if a.verification {
        // Verification renders the sun's scattering alone: an effect asked for beside it would
        // be dropped without a word.
        for t in &a.toggles.enable {
            if !t.get(&frame.features.sun_scattering_only()) {
                return Err(CliError::Refused {
                    what: "--enable with --verification",
                    given: format!("`{}` is an effect verification mode leaves out", t.name()),
                    accepted: "verification renders the sun's scattering alone (no powder, ground \
                         bounce, haze, light shafts or per-sample sun/sky light): drop the \
                         toggle, or drop --verification"
                        .into(),
                }
                .into());
            }
        }
    }
    if a.verification && a.toggles.octaves.is_none() {
        frame.features.octaves = 1;
    }
    // Multiple scattering, by octaves or by diffusion, only when asked for.
    if a.verification && !a.toggles.enable.contains(&Toggle::Diffusion) {
        frame.features.diffusion = false;
    }
    frame.validate()?;
    Ok(frame)
}

pub(crate) fn run(data: Option<&Path>, a: &RenderArgs) -> Result<(), Box<dyn std::error::Error>> {
    let frames = frames(data, a)?;
    let frame = frames[0].0.clone();
    // The destination and the user's textures are checked before any GPU work: a bad -o or
    // texture fails now, not after the render.
    let overwrite = Overwrite::forced(a.force);
    let format = ImageFormat::of(a.format, &a.out)?;
    let signature = match format {
        ImageFormat::Png => Signature::Png,
        ImageFormat::Exr => Signature::Exr,
    };
    check_file(&a.out, signature, overwrite)?;
    let user = user_textures(a)?;
    // Clouds forming and dissolving: the scene's automaton, run to `--time`, gates the weather.
    // Checked before any GPU work, as the textures are.
    let formation = load_scene(&scene_file(data, a)?)?.formation;
    if formation.is_some() && a.weather_texture.is_some() {
        return Err(CliError::Unknown {
            kind: "--weather-texture with this scene",
            given: "a scene with [formation], whose automaton gates the procedural weather".into(),
            known: "one of them: drop --weather-texture, or the scene's [formation] table".into(),
        }
        .into());
    }
    let gpu = Gpu::new()?;
    say!("adapter: {}", gpu.info());
    gpu.check_picture("the image", frame.width, frame.height)?;
    let mut renderer = Renderer::new(&gpu, TextureSizes::default());
    for (kind, flag, t) in &user {
        let t = gpu.upload_texture(t).map_err(|source| CliError::Texture {
            flag,
            source: Box::new(source),
        })?;
        renderer.set_texture(*kind, TextureSource::User(t));
    }
    if let Some(f) = formation {
        let mut sim = FormationSim::new(&gpu, f, TextureSizes::default().weather)?;
        let seconds = a.time.unwrap_or(0.0);
        crate::formation_progress::advance(&gpu, &mut sim, &f, seconds)?;
        sim.apply(&mut renderer, seconds)?;
        say!(
            "formation: step {} of the automaton ({} s per step)",
            sim.step().saturating_sub(1),
            f.step_seconds
        );
    }
    let variant = frame.variant();
    say!(
        "variant: {}{} ({}x{}, {} frame{}{})",
        variant.name(),
        if frame.verification {
            " [verification: the sun's scattering alone, irradiance 1]"
        } else {
            ""
        },
        frame.width,
        frame.height,
        frame.frames,
        if frame.frames == 1 { "" } else { "s" },
        if frame.upscale { ", upscaled 1/16" } else { "" }
    );
    say!(
        "shader: {}",
        nimbus_dsl::ShaderVariant::id(&nimbus_clouds::catalog::ShaderKey::Clouds(variant.key))
    );
    let layers = if format == ImageFormat::Exr { 3 } else { 1 };
    let bar = ProgressBar::new(u64::from(layers * frame.frames));
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames  {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let mut progress = |done: u32, _| bar.set_position(u64::from(done));
    if frames.len() > 1 {
        for (f, w) in &frames {
            say!(
                "  blending {} (coverage {:.3}) with weight {w:.3}",
                f.genus.name,
                f.genus.coverage
            );
        }
    }
    match format {
        ImageFormat::Png if frames.len() > 1 => {
            let image = renderer.render_blend(&frames);
            bar.finish_and_clear();
            image?.save_png(&a.out, a.exposure, overwrite)?;
        }
        ImageFormat::Exr if frames.len() > 1 => {
            return Err(CliError::Unknown {
                kind: "--time with EXR output",
                given: "a moment while one genus gives way to another".into(),
                known: "PNG output (the two genera's pictures are blended), or a time at \
                        which one weather state holds"
                    .into(),
            }
            .into());
        }
        ImageFormat::Png => {
            let image = renderer.render_with_progress(&frame, &mut progress);
            bar.finish_and_clear();
            image?.save_png(&a.out, a.exposure, overwrite)?;
        }
        ImageFormat::Exr => {
            let image = renderer.render_layers(&frame, &mut progress);
            bar.finish_and_clear();
            image?.save_exr(&a.out, overwrite)?;
        }
    }
    let stats = renderer.stats();
    let mut passes: Vec<(&str, usize)> = Vec::new();
    for p in &stats.passes {
        match passes.iter_mut().find(|(n, _)| n == p) {
            Some((_, c)) => *c += 1,
            None => passes.push((p, 1)),
        }
    }
    let passes: Vec<String> = passes.iter().map(|(n, c)| format!("{n} ×{c}")).collect();
    say!(
        "rendered in {:.2} s (passes: {}); wrote {}",
        start.elapsed().as_secs_f64(),
        passes.join(", "),
        a.out.display()
    );
    Ok(())
}
