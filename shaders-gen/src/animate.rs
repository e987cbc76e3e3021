//! `nimbus animate`: a scene's timeline as a sequence of pictures — the sun following its
//! clock, the clouds drifting with its wind, its weather states taking over one from another —
//! written as numbered PNG frames, an animated GIF, and an MP4 where `ffmpeg` is installed.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use nimbus_clouds::limits::{self, Origin};
use nimbus_output::{Overwrite, replace_folder};
use nimbus_runtime::Gpu;
use nimbus_runtime::formation::FormationSim;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};
use serde_json::json;

use crate::error::CliError;
use crate::scene_input::SceneInput;

/// The index of the output folder.
const INDEX: &str = "animation.json";
const GIF: &str = "animation.gif";
const MP4: &str = "animation.mp4";
/// The most pictures one command renders.
const MAX_PICTURES: u64 = 20_000;

/// What `nimbus animate` takes.
#[derive(Args)]
pub(crate) struct AnimateArgs {
    /// Scene file (TOML) with a timeline: `[clock]`, `[wind]`, `[[weather]]` states.
    scene: PathBuf,
    /// Output folder (replaced whole; only a folder Nimbus wrote, unless --force).
    #[arg(short, long, default_value = "animation")]
    out: PathBuf,
    /// Timeline second of the first picture.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    from: f64,
    /// Timeline second of the last picture.
    #[arg(long, allow_hyphen_values = true)]
    to: f64,
    /// Pictures per second of the animation.
    #[arg(long, default_value_t = 12.0, allow_hyphen_values = true)]
    fps: f64,
    /// Timeline seconds per second of the animation (a time-lapse factor: 600 shows ten
    /// minutes of the sky in each second).
    #[arg(long, default_value_t = 1.0)]
    speed: f64,
    /// Picture size, WIDTHxHEIGHT.
    #[arg(short, long, default_value = "320x180")]
    resolution: String,
    /// Frames of temporal accumulation per picture.
    #[arg(short, long, default_value_t = 4)]
    frames: u32,
    /// Exposure before the ACES curve.
    #[arg(long, default_value_t = 8.0)]
    exposure: f32,
    /// Replace the output folder even when Nimbus did not write it.
    #[arg(long)]
    force: bool,
}

fn positive(flag: &'static str, v: f64) -> Result<(), CliError> {
    if v.is_finite() && v > 0.0 {
        return Ok(());
    }
    Err(CliError::Unknown {
        kind: flag,
        given: v.to_string(),
        known: "a number above 0".into(),
    })
}

/// Whether `ffmpeg` runs here.
fn ffmpeg_available() -> bool {
    std::process::Command::new("ffmpeg")
        .arg("-version")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// What `animate` will render, built and checked before any GPU work or write.
pub(crate) struct Plan {
    pub width: u32,
    pub height: u32,
    pub input: SceneInput,
    /// Each picture's timeline second and its weighted frames.
    pub pictures: Vec<(f64, Vec<(Frame, f32)>)>,
}

/// Checks every argument and builds every picture's frames: the part of `animate` that needs
/// neither a GPU nor the output folder (what the fuzz target runs).
pub(crate) fn plan(
    data: Option<&Path>,
    a: &AnimateArgs,
) -> Result<Plan, Box<dyn std::error::Error>> {
    let (width, height) = crate::render::parse_resolution(&a.resolution)?;
    limits::FRAMES.check(f64::from(a.frames), Origin::Flag("--frames"))?;
    limits::EXPOSURE.check(f64::from(a.exposure), Origin::Flag(limits::EXPOSURE.flag))?;
    limits::TIME.check(a.from, Origin::Flag("--from"))?;
    limits::TIME.check(a.to, Origin::Flag("--to"))?;
    positive("--fps", a.fps)?;
    positive("--speed", a.speed)?;
    if a.to < a.from {
        return Err(CliError::Refused {
            what: "--to",
            given: format!("{} s is before --from", a.to),
            accepted: format!("a time at or after --from ({} s)", a.from),
        }
        .into());
    }
    let step = a.speed / a.fps;
    let intervals = ((a.to - a.from) / step + 1e-9).floor();
    if !intervals.is_finite() || intervals >= MAX_PICTURES as f64 {
        return Err(CliError::Refused {
            what: "picture count",
            given: format!(
                "{} (from {} s to {} s every {step} s)",
                intervals + 1.0,
                a.from,
                a.to
            ),
            accepted: format!("at most {MAX_PICTURES}: raise --speed or lower --fps"),
        }
        .into());
    }
    let count = intervals as u64 + 1;
    let input = SceneInput::load(data, &a.scene, None)?;
    let mut pictures = Vec::with_capacity(count as usize);
    for k in 0..count {
        let t = a.from + k as f64 * step;
        let mut frames = Vec::new();
        for state in input.at(t)? {
            let mut f = state.frame(width, height);
            f.frames = a.frames;
            f.validate()?;
            frames.push((f, state.weight));
        }
        pictures.push((t, frames));
    }
    Ok(Plan {
        width,
        height,
        input,
        pictures,
    })
}

pub(crate) fn run(data: Option<&Path>, a: &AnimateArgs) -> Result<(), Box<dyn std::error::Error>> {
    // The destination first: a folder that is not Nimbus's fails now, not after the work.
    nimbus_output::check_folder(&a.out, Overwrite::forced(a.force))?;
    let Plan {
        width,
        height,
        input,
        pictures,
    } = plan(data, a)?;
    let count = pictures.len();
    let renders: usize = pictures.iter().map(|(_, f)| f.len()).sum();
    say!(
        "{count} pictures of {width}x{height} ({renders} renders of {} frame(s) each, two where \
         one genus gives way to another)",
        a.frames
    );
    let gpu = Gpu::new()?;
    say!("adapter: {}", gpu.info());
    gpu.check_picture("each picture", width, height)?;
    let mut renderer = Renderer::new(&gpu, TextureSizes::default());
    // Clouds forming and dissolving: the automaton advances with the pictures.
    let mut formation = match input.scene.formation {
        Some(f) => Some(FormationSim::new(&gpu, f, TextureSizes::default().weather)?),
        None => None,
    };
    let start = Instant::now();
    let video = ffmpeg_available();
    let overwrite = Overwrite::forced(a.force);
    replace_folder(&a.out, overwrite, |tmp| {
        let gif_file = std::fs::File::create(tmp.join(GIF)).map_err(|e| CliError::Unknown {
            kind: "animation file",
            given: format!("{} ({e})", tmp.join(GIF).display()),
            known: "a writable output folder".into(),
        })?;
        let mut gif = image::codecs::gif::GifEncoder::new_with_speed(gif_file, 10);
        gif.set_repeat(image::codecs::gif::Repeat::Infinite)?;
        let delay = image::Delay::from_saturating_duration(
            std::time::Duration::try_from_secs_f64(1.0 / a.fps).unwrap_or(std::time::Duration::MAX),
        );
        let mut index = Vec::new();
        for (k, (t, frames)) in pictures.iter().enumerate() {
            if let Some(sim) = &mut formation {
                sim.apply(&mut renderer, *t)?;
            }
            let image = renderer.render_blend(frames)?;
            let file = format!("frame-{k:05}.png");
            image.save_png(&tmp.join(&file), a.exposure, Overwrite::Force)?;
            gif.encode_frame(image::Frame::from_parts(
                image.to_rgba8(a.exposure),
                0,
                0,
                delay,
            ))?;
            let first = &frames[0].0;
            say!(
                "{file}: t {t:>8.1} s, sun {:>5.1}° at {:>5.1}°, {}",
                first.sun_elevation_deg,
                first.sun_azimuth_deg,
                frames
                    .iter()
                    .map(|(f, w)| format!("{} {:.2} ×{w:.2}", f.genus.name, f.genus.coverage))
                    .collect::<Vec<_>>()
                    .join(" + ")
            );
            index.push(json!({
                "file": file,
                "time_s": t,
                "sun_elevation_deg": first.sun_elevation_deg,
                "sun_azimuth_deg": first.sun_azimuth_deg,
                "wind_drift_m": first.wind.ground.to_array(),
                "weather": frames.iter().map(|(f, w)| json!({
                    "genus": f.genus.name,
                    "coverage": f.genus.coverage,
                    "weight": w,
                })).collect::<Vec<_>>(),
            }));
        }
        drop(gif);
        let mut outputs = vec![GIF];
        if video {
            let status = std::process::Command::new("ffmpeg")
                .current_dir(tmp)
                .args(["-loglevel", "error", "-y", "-framerate"])
                .arg(a.fps.to_string())
                .args(["-i", "frame-%05d.png", "-pix_fmt", "yuv420p", MP4])
                .status();
            if status.is_ok_and(|s| s.success()) {
                outputs.push(MP4);
            } else {
                say!("ffmpeg failed: wrote the frames and the GIF only");
            }
        } else {
            say!("ffmpeg is not installed: wrote the frames and the GIF (no MP4)");
        }
        let description = json!({
            "scene": a.scene.display().to_string(),
            "from_s": a.from,
            "to_s": a.to,
            "fps": a.fps,
            "speed": a.speed,
            "size": [width, height],
            "adapter": gpu.info().to_string(),
            "outputs": outputs,
            "frames": index,
        });
        let text = serde_json::to_string_pretty(&description)?;
        std::fs::write(tmp.join(INDEX), text).map_err(|e| CliError::Unknown {
            kind: "animation index",
            given: format!("{} ({e})", tmp.join(INDEX).display()),
            known: "a writable output folder".into(),
        })?;
        Ok::<_, Box<dyn std::error::Error>>(())
    })?;
    say!(
        "{count} pictures in {:.1} s; wrote {}/{INDEX}",
        start.elapsed().as_secs_f64(),
        a.out.display()
    );
    Ok(())
}
