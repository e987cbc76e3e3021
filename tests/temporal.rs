//! Temporal upscaling and accumulation: 16 upscaled frames rebuild the full image, a game loop
//! of single-frame calls equals one multi-frame call, and reprojection follows a turning
//! camera and clouds drifting in the wind (the ghosting measured).

mod common;

use std::path::Path;

use image_compare::rgb_hybrid_compare;
use nimbus_clouds::wind::Drift;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::Gpu;
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

/// `f` at full resolution, converged over 16 frames on a history of its own: the picture an
/// upscaled history must settle to.
fn converged(gpu: &'static Gpu, f: &Frame) -> Image {
    let mut truth = f.clone();
    truth.upscale = false;
    truth.frames = 16;
    truth.continue_history = false;
    Renderer::new(gpu, SIZES).render(&truth).expect("truth")
}

/// The test frame upscaled, its history settled over 16 frames in `r`: the frame, to change
/// and draw once more on that history, and its picture.
fn settled_upscaled(r: &mut Renderer<'_>) -> (Frame, Image) {
    let mut f = frame();
    f.upscale = true;
    f.frames = 16;
    let image = r.render(&f).expect("converged");
    (f, image)
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
    let mut single = frame();
    single.frames = 1;
    let full_one = r.render(&single).expect("one full-resolution frame");
    let (s1, s16, s_full) = (
        similarity(&one, &reference),
        similarity(&sixteen, &reference),
        similarity(&full_one, &reference),
    );
    println!(
        "similarity to the converged full-resolution image: 1 upscaled frame {s1:.4}, 16 \
         upscaled frames {s16:.4}, 1 full-resolution frame {s_full:.4}"
    );
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
    let (mut f, before) = settled_upscaled(&mut r);
    // Turn by 6° (about 10 pixels) and render one more upscaled frame on the old history.
    f.camera_yaw_deg = 6.0;
    f.frames = 1;
    f.continue_history = true;
    let after = r.render(&f).expect("turned");
    let truth = converged(gpu, &f);
    let (stale, reprojected) = (similarity(&before, &truth), similarity(&after, &truth));
    println!("similarity to the turned view: stale {stale:.4}, reprojected {reprojected:.4}");
    assert!(
        reprojected > stale + 0.02,
        "reprojection did not follow the camera: stale {stale}, reprojected {reprojected}"
    );
}

/// With the camera and the wind still, the history stays where it is, and only the block's
/// shaded pixel can tell that the clouds changed (a genus' coverage, a weather change, a moving
/// sun): the history kept where that pixel agrees with it must not outlive a change.
#[test]
fn a_still_view_follows_the_clouds_changing() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, SIZES);
    let (mut f, before) = settled_upscaled(&mut r);
    f.genus.coverage = 0.45;
    f.frames = 2;
    f.continue_history = true;
    let after = r.render(&f).expect("changed");
    let truth = converged(gpu, &f);
    let (stale, followed) = (similarity(&before, &truth), similarity(&after, &truth));
    println!(
        "similarity to the clouds at coverage 0.45, two upscaled frames after 0.6: stale \
         {stale:.4}, followed {followed:.4}"
    );
    assert!(
        followed > stale + 0.1,
        "the history outlived the change: stale {stale}, after two frames {followed}"
    );
}

/// Ghosting of `image` against `truth` (display values): the mean absolute difference per
/// channel (of 255), and the share of pixels off by more than 24/255 in some channel.
fn ghosting(image: &Image, truth: &Image) -> (f64, f64) {
    let a = image.to_rgba8(8.0);
    let b = truth.to_rgba8(8.0);
    let (mut sum, mut ghosts) = (0.0f64, 0usize);
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d: Vec<i32> = (0..3)
            .map(|c| (i32::from(p[c]) - i32::from(q[c])).abs())
            .collect();
        sum += d.iter().map(|v| f64::from(*v)).sum::<f64>() / 3.0;
        ghosts += usize::from(d.iter().any(|v| *v > 24));
    }
    let n = (a.width() * a.height()) as f64;
    (sum / n, ghosts as f64 / n)
}

#[test]
fn reprojection_follows_clouds_drifting_in_the_wind() {
    let Some(gpu) = common::gpu() else { return };
    // A game loop at 1/16 resolution while a 40 m/s wind carries the clouds 40 m a frame
    // (about a pixel here): each pixel is shaded once in 16 frames, the rest is history.
    let mut f = frame();
    f.width = 160;
    f.height = 90;
    f.upscale = true;
    f.frames = 1;
    let frames = 48u32;
    let drift = |i: u32| Drift {
        ground: glam::Vec2::new(40.0 * i as f32, 0.0),
        per_metre: glam::Vec2::ZERO,
    };
    let run = |follow: bool, upscale: bool| {
        let mut r = Renderer::new(gpu, SIZES);
        let mut last = None;
        for i in 0..frames {
            let mut step = f.clone();
            step.upscale = upscale;
            // At full resolution a call needs two frames for the resolve to run (one is drawn
            // as it is); the history then carries over between calls.
            step.frames = if upscale { 1 } else { 2 };
            step.continue_history = i > 0;
            step.wind = drift(i);
            step.reproject_wind = follow;
            last = Some(r.render(&step).expect("frame"));
        }
        last.expect("frames")
    };
    let (followed, camera_only) = (run(true, true), run(false, true));
    let mut truth = f.clone();
    truth.upscale = false;
    truth.frames = 16;
    truth.wind = drift(frames - 1);
    let truth = Renderer::new(gpu, SIZES).render(&truth).expect("truth");
    // Still clouds, the same loop: the ghosting the upscaling has anyway.
    let mut still = Renderer::new(gpu, SIZES);
    let mut settled = None;
    for i in 0..frames {
        let mut step = f.clone();
        step.continue_history = i > 0;
        step.wind = drift(frames - 1);
        settled = Some(still.render(&step).expect("still"));
    }
    let settled = settled.expect("frames");
    let (g_follow, g_camera, g_still) = (
        ghosting(&followed, &truth),
        ghosting(&camera_only, &truth),
        ghosting(&settled, &truth),
    );
    println!(
        "ghosting after {frames} upscaled frames of 40 m/frame wind, against the converged \
         picture: followed by the wind {:.2}/255 mean, {:.1} % ghost pixels; camera-only \
         reprojection {:.2}/255, {:.1} %; still clouds {:.2}/255, {:.1} %",
        g_follow.0,
        g_follow.1 * 100.0,
        g_camera.0,
        g_camera.1 * 100.0,
        g_still.0,
        g_still.1 * 100.0
    );
    // Following the wind removes most of the smear: what is left is the resampling of a
    // history that moves every frame (still clouds give the floor).
    assert!(
        g_follow.1 < 0.2 * g_camera.1 && g_follow.0 < 0.6 * g_camera.0,
        "the wind's reprojection did not reduce the ghosting: {g_follow:?} vs {g_camera:?}"
    );
    assert!(
        g_still.0 < g_follow.0,
        "the floor is not below: {g_still:?}"
    );
    // At full resolution every pixel is shaded each frame and the history is a running mean
    // carried between calls: following the wind helps there too.
    let (full, full_camera) = (
        ghosting(&run(true, false), &truth),
        ghosting(&run(false, false), &truth),
    );
    println!(
        "full resolution, the same loop: followed {:.2}/255, {:.1} %; camera-only {:.2}/255, \
         {:.1} %",
        full.0,
        full.1 * 100.0,
        full_camera.0,
        full_camera.1 * 100.0
    );
    assert!(
        full.0 < full_camera.0 && full.1 < 0.02,
        "full-resolution accumulation smears: {full:?} vs {full_camera:?}"
    );
}
