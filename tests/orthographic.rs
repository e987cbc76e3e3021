//! Orthographic cameras (the `orthographic` key): parallel rays, each from its own point of the
//! camera's plane. The property that tells them from a perspective camera: looking straight
//! down, an orthographic camera sees the same clouds, pixel for pixel, from any height above
//! them; a perspective camera's view widens with its height.

mod common;

use std::path::Path;

use nimbus_clouds::{CloudLibrary, PixelOutput, Quality};
use nimbus_runtime::render::{Frame, Image, Renderer, TextureSizes};

const W: u32 = 96;
const H: u32 = 54;
/// The view's height (m).
const EXTENT: f32 = 6000.0;

/// Straight down from `altitude` over cumulus (1.5–3 km), the clouds' own transmittance
/// (no air, no sky: what the march alone sees).
fn frame(altitude: f32, orthographic: bool) -> Frame {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let mut genus = lib.genus("cumulus").expect("cumulus").clone();
    genus.coverage = 0.35;
    let mut f = Frame::new(genus, Quality::Low, W, H);
    f.camera_altitude = altitude;
    f.camera_pitch_deg = -90.0;
    f.output = PixelOutput::Clouds;
    f.features.haze = false;
    if orthographic {
        f.orthographic = Some(EXTENT);
    }
    f
}

/// Mean absolute difference of the transmittance (alpha), and the share of pixels with cloud.
fn transmittance_difference(a: &Image, b: &Image) -> (f32, f32) {
    let n = a.pixels.len() as f32;
    let diff = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (p[3] - q[3]).abs())
        .sum::<f32>()
        / n;
    let cloudy = a.pixels.iter().filter(|p| p[3] < 0.9).count() as f32 / n;
    (diff, cloudy)
}

#[test]
fn looking_down_an_orthographic_camera_sees_the_same_clouds_from_any_height() {
    let Some(gpu) = common::gpu() else { return };
    let small = TextureSizes {
        weather: 128,
        shape: 32,
        detail: 16,
        turbulence: 32,
    };
    let mut r = Renderer::new(gpu, small);
    let low = r.render(&frame(5000.0, true)).expect("renders");
    let high = r.render(&frame(9000.0, true)).expect("renders");
    assert!(
        low.pixels.iter().flatten().all(|v| v.is_finite()),
        "non-finite pixel"
    );
    let (ortho, cloudy) = transmittance_difference(&low, &high);
    // The control: a perspective camera from the same two heights.
    let p_low = r.render(&frame(5000.0, false)).expect("renders");
    let p_high = r.render(&frame(9000.0, false)).expect("renders");
    let (perspective, _) = transmittance_difference(&p_low, &p_high);
    if let Ok(dir) = std::env::var("NIMBUS_DUMP") {
        for (n, img) in [("ol", &low), ("oh", &high), ("pl", &p_low), ("ph", &p_high)] {
            let g = image::GrayImage::from_fn(W, H, |x, y| {
                image::Luma([(img.pixels[(y * W + x) as usize][3] * 255.0) as u8])
            });
            g.save(format!("{dir}/{n}.png")).expect("saves");
        }
    }
    println!(
        "on {}: {:.0} % of pixels cloudy; transmittance from 5 and 9 km apart by {ortho:.4} \
         (orthographic), {perspective:.4} (perspective)",
        gpu.info(),
        cloudy * 100.0
    );
    assert!((0.1..0.95).contains(&cloudy), "cloudy share {cloudy}");
    assert!(
        ortho < 0.02,
        "an orthographic camera's clouds changed with its height: {ortho}"
    );
    assert!(
        perspective > 5.0 * ortho,
        "the perspective camera's did not: {perspective} against {ortho}"
    );
}

/// The temporal resolve reprojects rays from one point: an orthographic view asked to
/// accumulate or upscale is refused with the field named, not drawn with every pixel reading
/// the centre's history.
#[test]
fn an_orthographic_view_is_not_resolved_over_frames() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, TextureSizes::default());
    for (frames, upscale) in [(4, false), (1, true)] {
        let mut f = frame(5000.0, true);
        f.frames = frames;
        f.upscale = upscale;
        let e = r.render(&f).expect_err("refused").to_string();
        assert!(e.contains("Frame::orthographic"), "{e}");
    }
    // One frame at a time is drawn.
    assert!(r.render(&frame(5000.0, true)).is_ok());
}
