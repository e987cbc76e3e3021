//! Golden images: small renders of a few genera and presets against reviewed references in
//! tests/golden/, compared in display space with a perceptual metric (image-compare's hybrid
//! score: MSSIM on luma, RMS on chroma; 1 = identical).
//!
//! Renders are deterministic for a fixed seed and frame index, so on one adapter the score is
//! ~1; the tolerance allows other adapters' filtering and transcendental precision.
//!
//! Updating, after a deliberate change: `NIMBUS_BLESS=1 cargo test --test golden` rewrites
//! the references; review them with `git diff` (an image diff tool shows the PNGs) before
//! committing. A failing run writes the actual image and a difference image to
//! target/golden/ for review.

mod common;

use std::path::{Path, PathBuf};

use image_compare::rgb_hybrid_compare;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

/// Below this score a render has changed visibly.
const MIN_SCORE: f64 = 0.97;
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

fn render(case: &Case) -> Option<image::RgbImage> {
    let gpu = common::gpu()?;
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
    let mut r = Renderer::new(gpu, TextureSizes::default());
    let image = r.render(&f).expect("render");
    image.check().expect("a usable frame");
    Some(image::DynamicImage::ImageRgba8(image.to_rgba8(EXPOSURE)).to_rgb8())
}

fn score(a: &image::RgbImage, b: &image::RgbImage) -> f64 {
    rgb_hybrid_compare(a, b).expect("same size").score
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
        let expected = image::open(&file)
            .unwrap_or_else(|e| {
                panic!(
                    "missing reference {} ({e}); create it with NIMBUS_BLESS=1",
                    file.display()
                )
            })
            .to_rgb8();
        let s = score(&actual, &expected);
        println!("{}: score {s:.5}", case.name);
        if s < MIN_SCORE {
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
                "{}: score {s:.4} < {MIN_SCORE} (actual and diff in {})",
                case.name,
                out.display()
            ));
        }
        rendered.push(actual);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The metric must be able to tell different scenes apart, or the check above means nothing.
    let cross = score(&rendered[0], &rendered[3]);
    println!("cumulus-low vs cirrus-high: score {cross:.4}");
    assert!(
        cross < MIN_SCORE,
        "different scenes score {cross}: the metric cannot fail"
    );
}
