//! Golden images: small renders of a few genera and presets against reviewed references in
//! tests/golden/, compared in display space (8-bit sRGB, as `nimbus render` writes them).
//!
//! Renders are deterministic for a fixed seed and frame index: on lavapipe, the adapter CI
//! runs and the references were made on, a render is its reference bit for bit. The tolerance
//! is therefore tight: a mean difference of 0.005 levels and no value more than 4 levels off.
//! The perceptual score used before (MSSIM ≥ 0.97) let whole effects go missing: switching off
//! turbulence scored 0.9985, ground bounce 0.998, the accurate sun and sky light 0.999. The
//! mutation control ([`each_effect_the_scene_shows_fails_the_golden_when_switched`]) renders
//! every case with each effect the scene analysis says is visible switched, and requires every
//! one to fail.
//!
//! Updating, after a deliberate change: `NIMBUS_BLESS=1 cargo test --test golden` rewrites
//! the references; review them with `git diff` (an image diff tool shows the PNGs) before
//! committing. A failing run writes the actual image and a difference image to
//! target/golden/ for review.

mod common;

use std::path::{Path, PathBuf};

use nimbus_clouds::analysis::{SceneContent, rule};
use nimbus_clouds::{CloudLibrary, Quality, Toggle};
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

/// Largest mean difference from the reference (display levels, 0..255, over every channel).
const MAX_MEAN: f64 = 0.005;
/// Largest difference of any one channel of any pixel (display levels).
const MAX_LEVELS: u8 = 4;
const EXPOSURE: f32 = 8.0;

struct Case {
    name: &'static str,
    genus: &'static str,
    quality: Quality,
    coverage: f32,
    pitch: f32,
    sun_elevation: f32,
    upscale: bool,
}

const CASES: [Case; 4] = [
    Case {
        name: "cumulus-low",
        genus: "cumulus",
        quality: Quality::Low,
        coverage: 0.4,
        pitch: 15.0,
        sun_elevation: 30.0,
        upscale: false,
    },
    Case {
        name: "default-high",
        genus: "takram-default",
        quality: Quality::High,
        coverage: 0.4,
        pitch: 10.0,
        sun_elevation: 25.0,
        upscale: false,
    },
    Case {
        name: "stratocumulus-medium-sunset",
        genus: "stratocumulus",
        quality: Quality::Medium,
        coverage: 0.35,
        pitch: 8.0,
        sun_elevation: 4.0,
        upscale: false,
    },
    Case {
        name: "cirrus-high-upscaled",
        genus: "cirrus",
        quality: Quality::High,
        coverage: 0.45,
        pitch: 30.0,
        sun_elevation: 50.0,
        upscale: true,
    },
];

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// The frame of `case`.
fn frame(case: &Case) -> Frame {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let mut f = Frame::new(
        lib.genus(case.genus).expect("genus").clone(),
        case.quality,
        160,
        90,
    );
    f.genus.coverage = case.coverage;
    f.camera_pitch_deg = case.pitch;
    f.sun_elevation_deg = case.sun_elevation;
    f.weather_offset = glam::Vec2::new(0.1, 0.1);
    f.upscale = case.upscale;
    f.frames = if case.upscale { 16 } else { 1 };
    f
}

/// `f` rendered and tone-mapped as `nimbus render` writes it.
fn render_frame(renderer: &mut Renderer<'_>, f: &Frame) -> image::RgbImage {
    let image = renderer.render(f).expect("render");
    image.check().expect("a usable frame");
    image::DynamicImage::ImageRgba8(image.to_rgba8(EXPOSURE)).to_rgb8()
}

fn render(case: &Case) -> Option<image::RgbImage> {
    let gpu = common::gpu()?;
    let mut r = Renderer::new(gpu, TextureSizes::default());
    Some(render_frame(&mut r, &frame(case)))
}

fn reference(case: &Case) -> image::RgbImage {
    let file = golden_dir().join(format!("{}.png", case.name));
    image::open(&file)
        .unwrap_or_else(|e| {
            panic!(
                "missing reference {} ({e}); create it with NIMBUS_BLESS=1",
                file.display()
            )
        })
        .to_rgb8()
}

/// How far `a` is from `b`: the mean and largest difference of a channel, in display levels.
#[derive(Clone, Copy, Debug)]
struct Difference {
    mean: f64,
    max: u8,
}

impl Difference {
    fn of(a: &image::RgbImage, b: &image::RgbImage) -> Difference {
        assert_eq!(a.dimensions(), b.dimensions(), "image sizes differ");
        let d: Vec<u8> = a
            .as_raw()
            .iter()
            .zip(b.as_raw())
            .map(|(x, y)| x.abs_diff(*y))
            .collect();
        Difference {
            mean: d.iter().map(|&x| f64::from(x)).sum::<f64>() / d.len() as f64,
            max: d.iter().copied().max().unwrap_or(0),
        }
    }

    fn passes(self) -> bool {
        self.mean <= MAX_MEAN && self.max <= MAX_LEVELS
    }
}

impl std::fmt::Display for Difference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "mean {:.4} levels, largest {}", self.mean, self.max)
    }
}

#[test]
fn renders_match_the_reviewed_references() {
    let bless = std::env::var("NIMBUS_BLESS").is_ok_and(|v| v == "1");
    let mut failures = Vec::new();
    let mut rendered = Vec::new();
    for case in &CASES {
        let Some(actual) = render(case) else { return };
        let file = golden_dir().join(format!("{}.png", case.name));
        if bless {
            actual.save(&file).expect("write reference");
            println!("blessed {}", file.display());
            rendered.push(actual);
            continue;
        }
        let expected = reference(case);
        let d = Difference::of(&actual, &expected);
        println!("{}: {d}", case.name);
        if !d.passes() {
            let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("golden");
            std::fs::create_dir_all(&out).expect("output folder");
            actual
                .save(out.join(format!("{}.actual.png", case.name)))
                .expect("write actual");
            let diff = image::RgbImage::from_fn(actual.width(), actual.height(), |x, y| {
                let (a, e) = (actual.get_pixel(x, y), expected.get_pixel(x, y));
                image::Rgb(std::array::from_fn(|c| {
                    a[c].abs_diff(e[c]).saturating_mul(4)
                }))
            });
            diff.save(out.join(format!("{}.diff.png", case.name)))
                .expect("write diff");
            failures.push(format!(
                "{}: {d} (allowed: mean {MAX_MEAN}, largest {MAX_LEVELS}; actual and diff in {})",
                case.name,
                out.display()
            ));
        }
        rendered.push(actual);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The mutation control: every case rendered with one effect switched (off where the case has
/// it, on where it has not), for each effect the scene analysis says this scene can show, must
/// fail its golden. A tolerance loose enough to let a missing effect through would pin nothing.
#[test]
fn each_effect_the_scene_shows_fails_the_golden_when_switched() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, TextureSizes::default());
    let mut caught = 0;
    let mut missed = Vec::new();
    for case in &CASES {
        let base = frame(case);
        let expected = reference(case);
        let content = SceneContent {
            genus: &base.genus,
            coverage: base.genus.coverage,
            sun_elevation_deg: base.sun_elevation_deg,
            camera_altitude: base.camera_altitude,
            haze_density: base.haze_density,
            turbulence_displacement: base.turbulence_displacement,
        };
        for &t in Toggle::ALL {
            let mut f = base.clone();
            let on = t.get(&base.features);
            t.set(&mut f.features, !on);
            let switched = if on { "off" } else { "on" };
            if f.variant().key == base.variant().key {
                continue;
            }
            if t == Toggle::AccurateAirLight {
                // How the air is computed, not what is drawn: the picture must stay within a
                // level or two of the golden, a few tenths on average (the table's half floats
                // round a wide sky by one level here and there; `air_table.rs` holds the table
                // to the integral direction by direction).
                let d = Difference::of(&render_frame(&mut r, &f), &expected);
                println!(
                    "{}: {} {switched}: {d} (must stay close)",
                    case.name,
                    t.name()
                );
                assert!(
                    d.mean <= 0.3 && d.max <= 2,
                    "{}: the air table departs from the integral: {d}",
                    case.name
                );
                continue;
            }
            if let Some(verdict) = rule(t).map(|rule| rule(&content))
                && !verdict.visible
            {
                println!(
                    "{}: {} {switched}: not checked ({})",
                    case.name,
                    t.name(),
                    verdict.reason
                );
                continue;
            }
            let d = Difference::of(&render_frame(&mut r, &f), &expected);
            println!("{}: {} {switched}: {d}", case.name, t.name());
            if d.passes() {
                missed.push(format!("{}: {} {switched} ({d})", case.name, t.name()));
            } else {
                caught += 1;
            }
        }
    }
    println!("{caught} switched effects fail their golden");
    assert!(
        missed.is_empty(),
        "the goldens let these switched effects through:\n{}",
        missed.join("\n")
    );
    assert!(caught >= 20, "only {caught} switched effects were checked");
}
