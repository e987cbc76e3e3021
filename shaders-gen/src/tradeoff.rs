//! `nimbus tradeoff`: what accuracy costs in time. Renders the canonical views (the scene files
//! of `views/`) with each quality preset and with the high preset missing one effect at a
//! time, measures each against the converged reference of the same model, and writes a
//! Markdown report and an SVG plot of error against time with the Pareto front.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use nimbus_clouds::Quality;
use nimbus_clouds::limits::{self, Origin};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};
use nimbus_testkit::metrics::ImageError;
use nimbus_testkit::tradeoff::{
    Clock, Measurement, RowSpec, StudyOptions, dominators, measure, pareto_front, reference, rows,
};

use crate::plot::{Point, svg_plot};
use nimbus_output::{Overwrite, Signature, TEXT_MARKER, check_file, write_file};

use crate::scene_input::SceneInput;

/// What `nimbus tradeoff` takes.
#[derive(Args)]
pub(crate) struct TradeoffArgs {
    /// Folder of view files (scene TOML). Default: views/ of the data folder.
    #[arg(long)]
    views: Option<PathBuf>,
    /// Output folder: tradeoff.md, tradeoff.svg and one reference PNG per view.
    #[arg(short, long, default_value = "tradeoff")]
    out: PathBuf,
    /// Image size, WIDTHxHEIGHT.
    #[arg(short, long, default_value = "256x144")]
    resolution: String,
    /// Frames accumulated per measured image.
    #[arg(short, long, default_value_t = 4)]
    frames: u32,
    /// Frames accumulated for each reference.
    #[arg(long, default_value_t = 16)]
    reference_frames: u32,
    /// Exposure of the display values the error is measured on (as `render`'s).
    #[arg(long, default_value_t = 8.0, allow_hyphen_values = true)]
    exposure: f32,
    /// Timed renders per row, each under its own jitter seed: the median time is reported, and
    /// their spread is the row's noise (at least 2 for the bias/noise split).
    #[arg(short = 'n', long, default_value_t = 3)]
    repeats: u32,
    /// Only these rows (comma-separated labels: `low`, `high - shadows`...); default all.
    #[arg(long, value_delimiter = ',')]
    rows: Vec<String>,
    /// Replace tradeoff.md, tradeoff.svg and reference PNGs even when Nimbus did not write
    /// them.
    #[arg(long)]
    force: bool,
}

/// Mean over the views of one row.
struct Summary {
    label: String,
    preset: bool,
    ms: f64,
    samples: f64,
    rmse: f64,
    psnr: f64,
    ssim: f64,
    flip: f64,
    linear: f64,
    bias: f64,
    noise: f64,
    luminance_ratio: f64,
}

/// Where the reference image of view `name` goes.
fn reference_png(out: &Path, name: &str) -> PathBuf {
    out.join(format!("reference-{name}.png"))
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    sum / n.max(1) as f64
}

fn view_files(dir: &Path) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("views folder {}: {e}", dir.display()))?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(format!("no view files (*.toml) in {}", dir.display()).into());
    }
    Ok(files)
}

pub(crate) fn run(data: Option<&Path>, a: &TradeoffArgs) -> Result<(), Box<dyn std::error::Error>> {
    let (width, height) = crate::render::parse_resolution(&a.resolution)?;
    // Every flag is checked before any work, through the limits render uses.
    for (flag, v) in [
        ("--frames", a.frames),
        ("--reference-frames", a.reference_frames),
    ] {
        limits::FRAMES.check(f64::from(v), Origin::Flag(flag))?;
    }
    limits::REPEATS.check(f64::from(a.repeats), Origin::Flag(limits::REPEATS.flag))?;
    limits::EXPOSURE.check(f64::from(a.exposure), Origin::Flag(limits::EXPOSURE.flag))?;
    let mut specs = rows();
    if !a.rows.is_empty() {
        let wanted: Vec<&str> = a.rows.iter().map(|r| r.trim()).collect();
        if let Some(unknown) = wanted
            .iter()
            .find(|w| !specs.iter().any(|s| s.label == **w))
        {
            return Err(format!(
                "unknown row `{unknown}`; rows are: {}",
                specs
                    .iter()
                    .map(|s| s.label.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
            .into());
        }
        specs.retain(|s| wanted.contains(&s.label.as_str()));
    }
    let dir = match &a.views {
        Some(d) => d.clone(),
        None => crate::data::data_dir(data)?.join("views"),
    };
    // Every view file is read and checked before any GPU work, as `render` reads a scene.
    let mut views: Vec<(String, Frame)> = Vec::new();
    // Views where the analysis chooses the flat high layer at `high`: its error and cost are
    // measured there, against the marched volume of the same preset.
    let mut flat_views: Vec<String> = Vec::new();
    for file in view_files(&dir)? {
        let state = SceneInput::load(data, &file, None)?.single_at(0.0, "a view file")?;
        let (scene, genus) = (&state.scene, &state.genus);
        let at_high = nimbus_clouds::ScenePreset {
            quality: Quality::High,
            ..scene.clone()
        };
        if nimbus_clouds::analyse(&at_high, genus)
            .features
            .flat_high_layer
        {
            flat_views.push(scene.name.clone());
        }
        views.push((scene.name.clone(), state.frame(width, height)));
    }
    // Every output is checked before any GPU work: a folder, writable, and holding no file of
    // these names that Nimbus did not write (unless --force).
    if a.out.exists() && !a.out.is_dir() {
        return Err(nimbus_output::OutputError::IsFile {
            path: a.out.clone(),
        }
        .into());
    }
    std::fs::create_dir_all(&a.out)
        .map_err(|e| format!("output folder {}: {e}", a.out.display()))?;
    let overwrite = Overwrite::forced(a.force);
    let md = a.out.join("tradeoff.md");
    let svg = a.out.join("tradeoff.svg");
    let text = Signature::FirstLine(TEXT_MARKER);
    check_file(&md, text, overwrite)?;
    check_file(&svg, text, overwrite)?;
    for (name, _) in &views {
        check_file(&reference_png(&a.out, name), Signature::Png, overwrite)?;
    }
    let options = StudyOptions {
        frames: a.frames,
        reference_frames: a.reference_frames,
        exposure: a.exposure,
        repeats: a.repeats,
    };
    let gpu = Gpu::new()?;
    say!("adapter: {}", gpu.info());
    gpu.check_picture("each view", width, height)?;
    let mut renderer = Renderer::new(&gpu, TextureSizes::default());
    let flat_spec = RowSpec {
        label: "high, flat high layer".into(),
        quality: Quality::High,
        features: nimbus_clouds::Features {
            flat_high_layer: true,
            ..Quality::High.features()
        },
        preset: false,
    };
    let mut approximations: Vec<Measurement> = Vec::new();
    let bar = ProgressBar::new((views.len() * (specs.len() + 1) + flat_views.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut measurements: Vec<Measurement> = Vec::new();
    let mut references = Vec::new();
    let mut clock = Clock::Wall;
    for (name, view) in &views {
        bar.set_message(format!("{name}: reference"));
        let r = reference(&mut renderer, view, &options)?;
        r.image
            .save_png(&reference_png(&a.out, name), a.exposure, overwrite)?;
        bar.inc(1);
        for spec in &specs {
            bar.set_message(format!("{name}: {}", spec.label));
            let (m, c) = measure(&mut renderer, name, view, spec, &r, &options)?;
            clock = c;
            measurements.push(m);
            bar.inc(1);
        }
        if flat_views.contains(name) {
            bar.set_message(format!("{name}: {}", flat_spec.label));
            let (m, _) = measure(&mut renderer, name, view, &flat_spec, &r, &options)?;
            approximations.push(m);
            bar.inc(1);
        }
        references.push((
            name.clone(),
            r.ms_per_frame,
            r.samples_per_pixel,
            r.noise,
            r.noise_linear,
        ));
    }
    bar.finish_and_clear();

    let summaries: Vec<Summary> = specs
        .iter()
        .map(|s| {
            let of = |f: &dyn Fn(&Measurement) -> f64| {
                mean(measurements.iter().filter(|m| m.row == s.label).map(f))
            };
            Summary {
                label: s.label.clone(),
                preset: s.preset,
                ms: of(&|m| m.ms_per_frame),
                samples: of(&|m| m.samples_per_pixel),
                rmse: of(&|m| m.error.rmse),
                psnr: of(&|m| m.error.psnr_db),
                ssim: of(&|m| m.error.ssim),
                flip: of(&|m| m.error.flip),
                linear: of(&|m| m.error.linear),
                bias: of(&|m| m.split.bias),
                noise: of(&|m| m.split.noise),
                luminance_ratio: of(&|m| m.error.luminance_ratio),
            }
        })
        .collect();
    // The front is judged on FLIP, the perceptual difference.
    let points: Vec<(f64, f64)> = summaries.iter().map(|s| (s.ms, s.flip)).collect();
    let front = pareto_front(&points);
    let mut report = report(
        &gpu.info().to_string(),
        clock,
        (width, height),
        &options,
        &views,
        &summaries,
        &front,
        &measurements,
        &references,
    );
    report.push_str(&approximations_section(&approximations, &measurements));
    write_file(&md, text, overwrite, report.as_bytes())?;
    let points: Vec<Point<'_>> = summaries
        .iter()
        .map(|s| Point {
            label: &s.label,
            ms: s.ms,
            error: s.flip,
            preset: s.preset,
        })
        .collect();
    let plot = svg_plot(
        &format!(
            "Error against time, mean of {} views ({width}x{height}, {})",
            views.len(),
            gpu.info().name
        ),
        "mean FLIP against the reference (display values)",
        &points,
        &front,
    )?;
    write_file(&svg, text, overwrite, plot.as_bytes())?;
    say_part!("{report}");
    say!("wrote {} and {}", md.display(), svg.display());
    Ok(())
}

/// The approximations the scene analysis chooses, each beside the `high` preset's march on the
/// same view: what it saves in time and what it costs in error.
fn approximations_section(approximations: &[Measurement], measurements: &[Measurement]) -> String {
    let mut out = String::from(
        "\n## Approximations the analysis chooses\n\n\
         The flat high layer (`flat-high-layer`): where `nimbus explain` finds that a thin high \
         layer seen from far below is all the sky holds, the real-time presets draw it as a 2D \
         layer. Measured on the views where the analysis chooses it, against the same reference, \
         beside `high`'s march:\n\n",
    );
    if approximations.is_empty() {
        out.push_str("(no view of this study has such a sky)\n");
        return out;
    }
    out.push_str(
        "| view | row | ms/frame | samples/px | FLIP | RMSE | luminance ratio |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for a in approximations {
        let high = measurements
            .iter()
            .find(|m| m.view == a.view && m.row == Quality::High.name());
        for m in high.into_iter().chain([a]) {
            let _ = writeln!(
                out,
                "| {} | {} | {:.2} | {:.1} | {:.4} | {:.4} | {:.3} |",
                m.view,
                m.row,
                m.ms_per_frame,
                m.samples_per_pixel,
                m.error.flip,
                m.error.rmse,
                m.error.luminance_ratio
            );
        }
        if let Some(h) = high {
            let _ = writeln!(
                out,
                "\n{}: {:.1}× faster than the march, FLIP {:+.4} against it.\n",
                a.view,
                h.ms_per_frame / a.ms_per_frame.max(1e-9),
                a.error.flip - h.error.flip
            );
        }
    }
    out
}

#[expect(
    clippy::too_many_arguments,
    reason = "one report from every part of the study"
)]
fn report(
    adapter: &str,
    clock: Clock,
    (width, height): (u32, u32),
    options: &StudyOptions,
    views: &[(String, Frame)],
    summaries: &[Summary],
    front: &[usize],
    measurements: &[Measurement],
    references: &[(String, f64, f64, ImageError, f64)],
) -> String {
    let mut s = String::new();
    let clock = match clock {
        Clock::GpuTimestamps => "GPU timestamp queries around the passes",
        Clock::Wall => "wall time around a render call that waits for the GPU",
    };
    let high = summaries
        .iter()
        .find(|r| r.label == Quality::High.name())
        .map_or(f64::NAN, |r| r.ms);
    let _ = writeln!(s, "<!-- {TEXT_MARKER}: nimbus tradeoff -->");
    let _ = writeln!(s, "# Accuracy against time\n");
    let _ = writeln!(
        s,
        "Adapter: {adapter}. Times: {clock}, per frame of {} accumulated frames at {width}x{height} (median of {} renders, each under its own jitter seed), shadow map cached as in a game loop. \
         Error: each image against the reference of its view ({} frames of the `reference` preset: 20 m steps up to 100 m, no early termination or cut-offs, \
         unbiased sun and ground marches over the whole path out of the layers, multiple scattering by diffusion, every effect). \
         Display space (exposure {}, ACES, sRGB): RMSE, PSNR, SSIM and mean FLIP. Linear space: mean |ΔY| over the reference's mean luminance; \
         the error split into bias (of the mean over the seeds, less the noise it still carries) and noise (spread across seeds), both RMS over the reference's mean luminance; \
         and the mean-luminance ratio to the reference. Rows are means over the {} views: {}.\n",
        options.frames,
        options.repeats,
        options.reference_frames,
        options.exposure,
        views.len(),
        views
            .iter()
            .map(|(n, _)| format!("`{n}`"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        s,
        "| row | ms/frame | ×high | density samples/px | RMSE | PSNR (dB) | SSIM | FLIP | linear | bias | noise | luminance | Pareto front (FLIP) |"
    );
    let _ = writeln!(
        s,
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|:---:|"
    );
    for (i, r) in summaries.iter().enumerate() {
        let name = if r.preset {
            format!("**{}**", r.label)
        } else {
            r.label.clone()
        };
        let _ = writeln!(
            s,
            "| {name} | {:.1} | {:.2} | {:.0} | {:.4} | {:.1} | {:.3} | {:.4} | {:.1} % | {:.1} % | {:.1} % | {:.3} | {} |",
            r.ms,
            r.ms / high,
            r.samples,
            r.rmse,
            r.psnr,
            r.ssim,
            r.flip,
            100.0 * r.linear,
            100.0 * r.bias,
            100.0 * r.noise,
            r.luminance_ratio,
            if front.contains(&i) { "yes" } else { "" }
        );
    }
    let refs = mean(references.iter().map(|r| r.1));
    let ref_samples = mean(references.iter().map(|r| r.2));
    let floor = mean(references.iter().map(|r| r.3.flip));
    let _ = writeln!(
        s,
        "| reference | {refs:.1} | {:.2} | {ref_samples:.0} | 0 | ∞ | 1 | 0 | 0 | | | 1 | |",
        refs / high
    );
    let _ = writeln!(
        s,
        "| reference, another seed | | | | {:.4} | {:.1} | {:.3} | {floor:.4} | {:.1} % | | {:.1} % | {:.3} | |\n",
        mean(references.iter().map(|r| r.3.rmse)),
        mean(references.iter().map(|r| r.3.psnr_db)),
        mean(references.iter().map(|r| r.3.ssim)),
        100.0 * mean(references.iter().map(|r| r.3.linear)),
        100.0 * mean(references.iter().map(|r| r.4)),
        mean(references.iter().map(|r| r.3.luminance_ratio)),
    );
    let _ = writeln!(
        s,
        "The last line is the reference against itself rendered with another jitter seed: FLIP differences smaller than {floor:.4} are the reference's own noise. \
         A luminance ratio within ±2 % of 1 means the preset neither darkens nor brightens the image as a whole.\n"
    );
    let points: Vec<(f64, f64)> = summaries.iter().map(|r| (r.ms, r.flip)).collect();
    let _ = writeln!(s, "## Presets and the Pareto front\n");
    for (i, r) in summaries.iter().enumerate().filter(|(_, r)| r.preset) {
        if front.contains(&i) {
            let _ = writeln!(
                s,
                "- **{}** is on the front: nothing measured is both faster and more accurate (FLIP {:.4}, luminance {:.3}).",
                r.label, r.flip, r.luminance_ratio
            );
        } else {
            // How far above the front it sits: its FLIP less the best the front reaches in
            // the same time or less.
            let best = front
                .iter()
                .filter(|&&j| summaries[j].ms <= r.ms)
                .map(|&j| summaries[j].flip)
                .fold(f64::INFINITY, f64::min);
            let gap = r.flip - best;
            let near = if gap <= floor {
                format!(
                    " It is {gap:.4} above the front, within the reference's own noise ({floor:.4}): near it."
                )
            } else {
                format!(
                    " It is {gap:.4} above the front (the reference's own noise is {floor:.4})."
                )
            };
            let by: Vec<String> = dominators(&points, i)
                .into_iter()
                .map(|j| {
                    format!(
                        "`{}` ({:.1} ms, FLIP {:.4})",
                        summaries[j].label, summaries[j].ms, summaries[j].flip
                    )
                })
                .collect();
            let _ = writeln!(
                s,
                "- **{}** is off the front ({:.1} ms, FLIP {:.4}): beaten by {}.{near}",
                r.label,
                r.ms,
                r.flip,
                by.join(", ")
            );
        }
    }
    let _ = writeln!(s, "\n## Per view\n");
    let _ = writeln!(
        s,
        "| view | row | ms/frame | density samples/px | RMSE | PSNR (dB) | SSIM | FLIP | linear | bias | noise | luminance |"
    );
    let _ = writeln!(
        s,
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for (view, ms, samples, noise, noise_linear) in references {
        let _ = writeln!(
            s,
            "| {view} | reference | {ms:.1} | {samples:.0} | 0 | ∞ | 1 | 0 | 0 | | | 1 |"
        );
        let _ = writeln!(
            s,
            "| {view} | reference, another seed | | | {:.4} | {:.1} | {:.3} | {:.4} | {:.1} % | | {:.1} % | {:.3} |",
            noise.rmse,
            noise.psnr_db,
            noise.ssim,
            noise.flip,
            100.0 * noise.linear,
            100.0 * noise_linear,
            noise.luminance_ratio
        );
        for m in measurements.iter().filter(|m| &m.view == view) {
            let _ = writeln!(
                s,
                "| {view} | {} | {:.1} | {:.0} | {:.4} | {:.1} | {:.3} | {:.4} | {:.1} % | {:.1} % | {:.1} % | {:.3} |",
                m.row,
                m.ms_per_frame,
                m.samples_per_pixel,
                m.error.rmse,
                m.error.psnr_db,
                m.error.ssim,
                m.error.flip,
                100.0 * m.error.linear,
                100.0 * m.split.bias,
                100.0 * m.split.noise,
                m.error.luminance_ratio
            );
        }
    }
    s
}
