//! Temporal upscaling and accumulation: 16 upscaled frames rebuild the full image, a game loop
//! of single-frame calls equals one multi-frame call, and reprojection follows a turning
//! camera.

mod common;

use std::path::Path;

use image_compare::rgb_hybrid_compare;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::render::{Frame, Image, Renderer, TextureSizes};

const SIZES: TextureSizes = TextureSizes {
    weather: 64,
    shape: 32,
    detail: 16,
    turbulence: 32,
};

fn frame() -> Frame {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let mut f = Frame::new(
        lib.genus("cumulus").expect("cumulus").clone(),
        Quality::Low,
        64,
        36,
    );
    f.genus.coverage = 0.6;
    f.camera_pitch_deg = 25.0;
    f
}

fn similarity(a: &Image, b: &Image) -> f64 {
    let a = image::DynamicImage::ImageRgba8(a.to_rgba8(8.0)).to_rgb8();
    let b = image::DynamicImage::ImageRgba8(b.to_rgba8(8.0)).to_rgb8();
    rgb_hybrid_compare(&a, &b).expect("same size").score
}

#[test]
fn sixteen_upscaled_frames_rebuild_the_full_image() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, SIZES);
    let mut full = frame();
    full.frames = 16;
    let reference = r.render(&full).expect("full resolution");
    let mut up = frame();
    up.upscale = true;
    up.frames = 1;
    let one = r.render(&up).expect("one upscaled frame");
    up.frames = 16;
    let sixteen = r.render(&up).expect("16 upscaled frames");
    let (s1, s16) = (
        similarity(&one, &reference),
        similarity(&sixteen, &reference),
    );
    println!("similarity to the full-resolution image: 1 frame {s1:.4}, 16 frames {s16:.4}");
    // Clipping against the coarse neighbourhood softens the finest detail a little; what is
    // asserted is that 16 frames recover the image that one frame only hints at.
    assert!(s16 > 0.85, "16 upscaled frames differ: {s16}");
    assert!(s16 > s1 + 0.3, "more frames must help: {s1} -> {s16}");
}

#[test]
fn a_game_loop_of_single_frames_equals_one_call_of_many() {
    let Some(gpu) = common::gpu() else { return };
    let mut batch = frame();
    batch.upscale = true;
    batch.frames = 6;
    let mut r = Renderer::new(gpu, SIZES);
    let whole = r.render(&batch).expect("batch");
    let mut step = frame();
    step.upscale = true;
    step.frames = 1;
    let mut r = Renderer::new(gpu, SIZES);
    let mut last = None;
    for i in 0..6 {
        step.continue_history = i > 0;
        last = Some(r.render(&step).expect("step"));
    }
    assert_eq!(last.expect("frames").pixels, whole.pixels);
}

#[test]
fn reprojection_follows_a_turning_camera() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, SIZES);
    let mut f = frame();
    f.upscale = true;
    f.frames = 16;
    let before = r.render(&f).expect("converged");
    // Turn by 6° (about 10 pixels) and render one more upscaled frame on the old history.
    f.camera_yaw_deg = 6.0;
    f.frames = 1;
    f.continue_history = true;
    let after = r.render(&f).expect("turned");
    let mut fresh = f.clone();
    fresh.upscale = false;
    fresh.frames = 16;
    fresh.continue_history = false;
    let truth = Renderer::new(gpu, SIZES).render(&fresh).expect("truth");
    let (stale, reprojected) = (similarity(&before, &truth), similarity(&after, &truth));
    println!("similarity to the turned view: stale {stale:.4}, reprojected {reprojected:.4}");
    assert!(
        reprojected > stale + 0.02,
        "reprojection did not follow the camera: stale {stale}, reprojected {reprojected}"
    );
}
