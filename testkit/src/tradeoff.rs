//! Accuracy against time: each quality preset, and the high preset with one effect switched
//! off, rendered over a set of views and measured against a converged reference of the same
//! model (`Quality::Reference`). Per row and view: time per frame (GPU timestamps where the
//! adapter has them, else wall time around a synchronised render), density samples per pixel
//! (from the instrumented variant), the error of the image (see [`crate::metrics`]), and its
//! split into bias and noise over renders under different jitter seeds.

use std::time::Instant;

use nimbus_clouds::{Features, Path, Quality, Toggle};

use crate::metrics::{BiasNoise, ImageError, bias_noise, image_error, linear_rms};
use nimbus_runtime::RuntimeError;
use nimbus_runtime::render::{Frame, Image, Renderer};

/// What a row renders.
#[derive(Clone, Debug, PartialEq)]
pub struct RowSpec {
    /// `low`, `high - shadows`, `reference`...
    pub label: String,
    pub quality: Quality,
    pub features: Features,
    /// A quality preset as shipped (the points the report judges against the Pareto front).
    pub preset: bool,
}

/// The rows of the study: the four presets, then high with each of its effects off in turn
/// (multiple scattering "off" is one octave and no diffusion; "high - diffusion" is high with
/// the octaves in its place).
pub fn rows() -> Vec<RowSpec> {
    let mut rows: Vec<RowSpec> = Quality::ALL
        .into_iter()
        .map(|q| RowSpec {
            label: q.name().into(),
            quality: q,
            features: q.features(),
            preset: true,
        })
        .collect();
    let high = Quality::High.features();
    for &t in Toggle::ALL.iter().filter(|t| t.get(&high)) {
        let mut f = high;
        t.set(&mut f, false);
        rows.push(RowSpec {
            label: format!("high - {}", t.name()),
            quality: Quality::High,
            features: f,
            preset: false,
        });
    }
    rows.push(RowSpec {
        label: "high - multiple-scattering".into(),
        quality: Quality::High,
        features: Features {
            octaves: 1,
            diffusion: false,
            ..high
        },
        preset: false,
    });
    // Each path drawn from the same model, at the cheapest and the default preset: its
    // stack baked once per view (the sun and the camera stand still), as a game draws it.
    for path in Path::ALL.into_iter().filter(|p| *p != Path::Volume) {
        for q in [Quality::Low, Quality::High] {
            rows.push(RowSpec {
                label: format!("{path} ({})", q.name()),
                quality: q,
                features: Features {
                    path,
                    ..q.features()
                },
                preset: false,
            });
        }
    }
    rows
}

/// How times were taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clock {
    /// Timestamp queries around the passes.
    GpuTimestamps,
    /// Wall time around a render call that waits for the GPU (readback included).
    Wall,
}

/// One row measured on one view.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    pub view: String,
    pub row: String,
    pub ms_per_frame: f64,
    pub samples_per_pixel: f64,
    /// The first seed's image against the reference.
    pub error: ImageError,
    /// Bias and noise over the timed renders' seeds.
    pub split: BiasNoise,
}

/// Study settings.
#[derive(Clone, Copy, Debug)]
pub struct StudyOptions {
    /// Frames accumulated per row image (jitter averaged as `nimbus render` does).
    pub frames: u32,
    /// Frames accumulated for the reference.
    pub reference_frames: u32,
    /// Exposure of the display values the error is computed on.
    pub exposure: f32,
    /// Timed renders per row (the median is kept), each under its own jitter seed, so their
    /// spread is the row's noise; the reference is timed once.
    pub repeats: u32,
}

/// Renders `frame` `repeats` times, the k-th under jitter seed `frame.seed + k`, and returns
/// the images and the median time per frame on `clock`. A first, untimed call builds the
/// variant's pipelines and shadow map.
fn timed(
    renderer: &mut Renderer<'_>,
    frame: &Frame,
    repeats: u32,
) -> Result<(Vec<Image>, f64, Clock), RuntimeError> {
    let mut warm = frame.clone();
    warm.frames = 1;
    renderer.render(&warm)?;
    let frames = f64::from(frame.frames.max(1));
    let mut times = Vec::new();
    let mut clock = Clock::GpuTimestamps;
    let mut images = Vec::new();
    for k in 0..repeats.max(1) {
        let mut seeded = frame.clone();
        seeded.seed = frame.seed.wrapping_add(k);
        let start = Instant::now();
        let out = renderer.render(&seeded)?;
        let wall = start.elapsed().as_secs_f64() * 1e3;
        match renderer.last_gpu_time_ms() {
            Some(gpu) if gpu > 0.0 => times.push(gpu / frames),
            _ => {
                clock = Clock::Wall;
                times.push(wall / frames);
            }
        }
        images.push(out);
    }
    times.sort_by(f64::total_cmp);
    Ok((images, times[times.len() / 2], clock))
}

/// Mean density samples per pixel of `frame`'s variant, from one instrumented frame.
pub fn samples_per_pixel(renderer: &mut Renderer<'_>, frame: &Frame) -> Result<f64, RuntimeError> {
    let mut f = frame.clone();
    f.output = nimbus_clouds::PixelOutput::Samples;
    f.frames = 1;
    f.upscale = false;
    f.continue_history = false;
    let image = renderer.render(&f)?;
    let sum: f64 = image.pixels.iter().map(|p| f64::from(p[3])).sum();
    Ok(sum / image.pixels.len().max(1) as f64)
}

/// The reference image of a view, and its time per frame.
pub struct Reference {
    pub image: Image,
    pub ms_per_frame: f64,
    pub samples_per_pixel: f64,
    /// The reference against a second one with another jitter seed: the error floor below
    /// which differences between rows are the reference's own noise.
    pub noise: ImageError,
    /// The same in linear luminance: RMS difference over the mean luminance.
    pub noise_linear: f64,
}

/// The study's view of a frame: the sun's disc left out, so that a few pixels thousands of
/// times brighter than the clouds do not decide the linear errors (every row draws the disc
/// alike; the clouds, sky and air are what the presets differ in).
fn without_sun_disc(view: &Frame) -> Frame {
    let mut f = view.clone();
    f.composite.sun_disc = 0.0;
    f
}

/// Renders the reference of `view`: every effect, converged march settings, many frames.
pub fn reference(
    renderer: &mut Renderer<'_>,
    view: &Frame,
    options: &StudyOptions,
) -> Result<Reference, RuntimeError> {
    let mut f = without_sun_disc(view);
    f.quality = Quality::Reference;
    f.features = Quality::Reference.features();
    f.frames = options.reference_frames.max(1);
    f.upscale = false;
    f.continue_history = false;
    let (mut images, ms_per_frame, _) = timed(renderer, &f, 1)?;
    let image = images.remove(0);
    image.check()?;
    let mut other = f.clone();
    // Far from the seeds the rows use (seed + k), so no row shares the reference's jitter.
    other.seed = f.seed.wrapping_add(1000);
    let second = renderer.render(&other)?;
    let noise = image_error(&second, &image, options.exposure)?;
    let noise_linear = linear_rms(&second, &image)?;
    Ok(Reference {
        image,
        ms_per_frame,
        samples_per_pixel: samples_per_pixel(renderer, &f)?,
        noise,
        noise_linear,
    })
}

/// Measures one row on one view against its reference.
pub fn measure(
    renderer: &mut Renderer<'_>,
    view_name: &str,
    view: &Frame,
    row: &RowSpec,
    reference: &Reference,
    options: &StudyOptions,
) -> Result<(Measurement, Clock), RuntimeError> {
    let mut f = without_sun_disc(view);
    f.quality = row.quality;
    f.features = row.features;
    f.frames = options.frames.max(1);
    f.upscale = false;
    f.continue_history = false;
    // The rows' seeds start past the reference's, so no row shares its jitter.
    f.seed = view.seed.wrapping_add(1);
    let (images, ms_per_frame, clock) = timed(renderer, &f, options.repeats)?;
    for image in &images {
        image.check()?;
    }
    let error = image_error(&images[0], &reference.image, options.exposure)?;
    let split = bias_noise(&images, &reference.image, reference.noise_linear)?;
    Ok((
        Measurement {
            view: view_name.into(),
            row: row.label.clone(),
            ms_per_frame,
            samples_per_pixel: samples_per_pixel(renderer, &f)?,
            error,
            split,
        },
        clock,
    ))
}

/// Indices of the points no other point beats on both axes (lower time and lower error, one
/// of them strictly), in order of time: the Pareto front.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let dominated = |i: usize| {
        let (ti, ei) = points[i];
        points
            .iter()
            .any(|&(t, e)| t <= ti && e <= ei && (t < ti || e < ei))
    };
    let mut front: Vec<usize> = (0..points.len()).filter(|&i| !dominated(i)).collect();
    front.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0));
    front
}

/// For a point off the front, the front points that beat it (for the report's "why").
pub fn dominators(points: &[(f64, f64)], i: usize) -> Vec<usize> {
    let (ti, ei) = points[i];
    (0..points.len())
        .filter(|&j| {
            let (t, e) = points[j];
            j != i && t <= ti && e <= ei && (t < ti || e < ei)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_keeps_exactly_the_points_nothing_beats() {
        // (time, error): c is beaten by b on both; e ties d's time with more error.
        let points = [
            (10.0, 0.5),  // a: fastest
            (20.0, 0.2),  // b
            (30.0, 0.3),  // c: slower and worse than b
            (40.0, 0.1),  // d
            (40.0, 0.15), // e: as slow as d, worse
        ];
        assert_eq!(pareto_front(&points), vec![0, 1, 3]);
        assert_eq!(dominators(&points, 2), vec![1]);
        assert_eq!(dominators(&points, 4), vec![3]);
        assert!(dominators(&points, 1).is_empty());
    }

    #[test]
    fn rows_are_the_presets_then_high_minus_each_effect_then_the_paths() {
        let r = rows();
        let labels: Vec<&str> = r.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(&labels[..4], ["low", "medium", "high", "ultra"]);
        assert!(r[..4].iter().all(|s| s.preset) && r[4..].iter().all(|s| !s.preset));
        let high = Quality::High.features();
        let (volume, paths): (Vec<_>, Vec<_>) =
            r[4..].iter().partition(|s| s.features.path == Path::Volume);
        for s in volume {
            assert_eq!(s.quality, Quality::High);
            assert_ne!(s.features, high, "{} must differ from high", s.label);
        }
        // Each path beside the volume, at `low` and `high`, with the preset's effects.
        for s in &paths {
            assert_ne!(s.features.path, Path::Volume);
            let preset = Features {
                path: s.features.path,
                ..s.quality.features()
            };
            assert_eq!(s.features, preset, "{}", s.label);
        }
        assert!(labels.contains(&"slices (low)") && paths.len() >= 2);
        assert!(
            labels.contains(&"high - shadows") && labels.contains(&"high - multiple-scattering")
        );
    }
}
