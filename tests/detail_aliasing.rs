//! Sunset clouds are not a mosaic. Each pixel marched one point of the 5 m detail noise, at
//! the centre of the pixel every frame: a cloud a few kilometres away showed a mosaic of
//! unrelated noise values that accumulating frames did not remove (every frame picked the same
//! point), and isolated bright pixels on its edges. Now a sample that stands for more than half
//! a detail texel erodes with the noise's means (`detail_level`), and accumulated frames move
//! the ray over the pixel (`subpixel_offset`), so their mean is the pixel's area average.
//!
//! The measure: pixel-scale contrast (mean |Laplacian| of display luminance over the sky half)
//! of an 8-frame accumulation against that of the same view rendered at 4× the resolution and
//! averaged down to the same pixels, the picture a pixel should show. Measured on lavapipe at
//! 320 × 180 before this change: 1.37 × the reference's, and 7 isolated bright pixels (73 in a
//! single frame), and 1.68 temporally upscaled (32 frames: two visits per pixel); after: 0.93
//! and 1 (18), and 1.08.

mod common;

use std::path::Path;

use nimbus_clouds::CloudLibrary;
use nimbus_runtime::render::{Frame, Image, Renderer, TextureSizes};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 180;
/// The rows measured: the sky and the clouds above the horizon (the ground is flat colour).
const ROWS: usize = 108; // 60 % of HEIGHT

/// Display luminance (0..1) of every pixel, as `nimbus render` writes it (exposure 8).
fn luminance(im: &Image) -> Vec<f64> {
    im.to_rgba8(8.0)
        .pixels()
        .map(|p| (0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64) / 255.0)
        .collect()
}

/// `l` (`w` wide) averaged over `k`×`k` blocks.
fn box_down(l: &[f64], w: usize, k: usize) -> Vec<f64> {
    let (ow, oh) = (w / k, l.len() / w / k);
    let mut out = vec![0.0; ow * oh];
    for y in 0..oh * k {
        for x in 0..ow * k {
            out[(y / k) * ow + x / k] += l[y * w + x] / (k * k) as f64;
        }
    }
    out
}

/// Mean |4·c − the four neighbours| over the top 60 % of the rows (interior pixels).
fn pixel_contrast(l: &[f64], w: usize) -> f64 {
    let rows = l.len() / w * ROWS / HEIGHT as usize;
    let mut sum = 0.0;
    let mut n = 0usize;
    for y in 1..rows - 1 {
        for x in 1..w - 1 {
            let c = l[y * w + x];
            let lap = 4.0 * c
                - l[y * w + x - 1]
                - l[y * w + x + 1]
                - l[(y - 1) * w + x]
                - l[(y + 1) * w + x];
            sum += lap.abs();
            n += 1;
        }
    }
    sum / n as f64
}

/// Pixels brighter than all eight neighbours by more than 12/255 in the first `ROWS` rows.
fn sparkles(l: &[f64], w: usize) -> usize {
    let mut count = 0;
    for y in 1..ROWS - 1 {
        for x in 1..w - 1 {
            let c = l[y * w + x];
            let brightest = (0..9)
                .filter(|&i| i != 4)
                .map(|i| l[(y + i / 3 - 1) * w + x + i % 3 - 1])
                .fold(f64::MIN, f64::max);
            if c - brightest > 12.0 / 255.0 {
                count += 1;
            }
        }
    }
    count
}

#[test]
fn sunset_clouds_are_not_a_mosaic_and_do_not_sparkle() {
    let Some(gpu) = common::gpu() else { return };
    println!("adapter: {}", gpu.info());
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let (_, scene) = &lib.scenes["sunset"];
    let genus = lib.genus(&scene.genus).expect("genus");
    let mut renderer = Renderer::new(gpu, TextureSizes::default());
    let mut render = |scale: u32, frames: u32, detail: bool, upscale: bool| {
        let mut f = Frame::from_scene(scene, genus, WIDTH * scale, HEIGHT * scale);
        f.frames = frames;
        f.features.shape_detail = detail;
        f.upscale = upscale;
        luminance(&renderer.render(&f).expect("render"))
    };
    let w = WIDTH as usize;
    let fine = render(4, 1, true, false);
    let reference = box_down(&fine, w * 4, 4);
    let single = render(1, 1, true, false);
    let accumulated = render(1, 8, true, false);
    // Temporally upscaled, each pixel shaded once per 16 frames: 32 frames are two visits.
    let upscaled = render(1, 32, true, true);
    let reference_contrast = pixel_contrast(&reference, w);
    let ratio = |l: &[f64]| pixel_contrast(l, w) / reference_contrast;
    let (single_ratio, accumulated_ratio) = (ratio(&single), ratio(&accumulated));
    let upscaled_ratio = ratio(&upscaled);
    let counts = [&reference, &single, &accumulated].map(|l| sparkles(l, w));
    println!(
        "pixel-scale contrast against the 4×-supersampled picture: 1 frame {single_ratio:.2}, \
         8 frames {accumulated_ratio:.2}, 32 upscaled {upscaled_ratio:.2}; isolated bright pixels: supersampled {}, 1 frame {}, \
         8 frames {}",
        counts[0], counts[1], counts[2]
    );
    // The control: one frame still has its ray-start jitter noise, which the measure sees.
    assert!(
        single_ratio > 1.25,
        "the measure does not see one frame's noise: {single_ratio:.2}"
    );
    assert!(
        accumulated_ratio < 1.15,
        "8 accumulated frames keep a pixel-scale mosaic: {accumulated_ratio:.2} × the \
         supersampled picture's contrast (1.37 before the detail's level of detail)"
    );
    assert!(
        upscaled_ratio < 1.3,
        "temporal upscaling breaks the clouds into dots: {upscaled_ratio:.2} × the \
         supersampled picture's contrast after 32 frames (1.68 before)"
    );
    assert!(
        counts[2] <= 3,
        "{} isolated bright pixels after 8 frames (7 before)",
        counts[2]
    );
    // Not by blurring: the accumulated picture is the supersampled one, pixel for pixel.
    let mean_difference = accumulated
        .iter()
        .zip(&reference)
        .take(ROWS * w)
        .map(|(a, b)| (a - b).abs())
        .sum::<f64>()
        / (ROWS * w) as f64;
    println!(
        "mean difference from the supersampled picture: {:.2}/255",
        mean_difference * 255.0
    );
    assert!(
        mean_difference < 2.0 / 255.0,
        "the accumulated picture is not the supersampled one: {:.2}/255",
        mean_difference * 255.0
    );
    // And the detail is still there where pixels resolve it: at 4× the resolution the same
    // clouds without the detail stage have markedly less pixel-scale contrast.
    let plain = render(4, 1, false, false);
    let contrast = |l: &[f64]| pixel_contrast(l, w * 4) * 255.0;
    let (detailed, smooth) = (contrast(&fine), contrast(&plain));
    println!(
        "at {}×{}: pixel-scale contrast {detailed:.2}/255 with the detail, {smooth:.2}/255 without",
        WIDTH * 4,
        HEIGHT * 4
    );
    assert!(
        detailed > smooth * 1.2,
        "the level of detail took the detail from clouds whose pixels resolve it: {detailed:.2} \
         against {smooth:.2} without"
    );
}
