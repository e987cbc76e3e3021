//! A toggle that is off creates nothing for its effect: no pipeline, no texture, no pass. Each
//! case renders the same frame with the effect on and off and compares what the renderer
//! created, so a check cannot pass because the effect was missing in both.

mod common;

use std::path::Path;

use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::render::{Frame, RenderStats, Renderer, TextureSizes, TextureSource};
use nimbus_runtime::textures::NoiseKind;

const SIZES: TextureSizes = common::SMALL_TEXTURES;

fn frame() -> Frame {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let mut f = Frame::new(
        lib.genus("cumulus").expect("cumulus").clone(),
        Quality::High,
        32,
        18,
    );
    f.camera_pitch_deg = 20.0;
    f
}

/// What a fresh renderer creates for `frame`.
fn stats(frame: &Frame) -> Option<RenderStats> {
    let gpu = common::gpu()?;
    let mut r = Renderer::new(gpu, SIZES);
    r.render(frame).expect("render");
    Some(r.stats())
}

fn has(list: &[String], what: &str) -> bool {
    list.iter().any(|s| s.starts_with(what))
}

#[test]
fn shadows_off_means_no_shadow_pipeline_atlas_or_pass() {
    let on = frame();
    let mut off = frame();
    off.features.shadows = false;
    off.features.light_shafts = false;
    let (Some(a), Some(b)) = (stats(&on), stats(&off)) else {
        return;
    };
    println!("on: {a:?}\noff: {b:?}");
    assert!(has(&a.pipelines, "shadow") && has(&a.textures, "shadow_map"));
    assert!(a.passes.contains(&"shadow"));
    assert!(!has(&b.pipelines, "shadow"), "{:?}", b.pipelines);
    assert!(!has(&b.textures, "shadow_map"), "{:?}", b.textures);
    assert!(!b.passes.contains(&"shadow"), "{:?}", b.passes);
}

#[test]
fn light_shafts_alone_still_need_the_atlas_and_shadows_alone_too() {
    // The atlas serves two effects: it goes only when neither needs it.
    let mut shafts = frame();
    shafts.features.shadows = false;
    let mut shadows = frame();
    shadows.features.light_shafts = false;
    for f in [shafts, shadows] {
        let Some(s) = stats(&f) else { return };
        assert!(s.passes.contains(&"shadow"), "{:?}", f.features);
    }
}

#[test]
fn shape_detail_off_means_no_detail_texture() {
    let on = frame();
    let mut off = frame();
    off.features.shape_detail = false;
    let (Some(a), Some(b)) = (stats(&on), stats(&off)) else {
        return;
    };
    assert!(has(&a.textures, "detail_texture"), "{:?}", a.textures);
    assert!(!has(&b.textures, "detail_texture"), "{:?}", b.textures);
}

#[test]
fn turbulence_off_means_no_turbulence_texture() {
    let on = frame();
    let mut off = frame();
    off.features.turbulence = false;
    let (Some(a), Some(b)) = (stats(&on), stats(&off)) else {
        return;
    };
    assert!(has(&a.textures, "turbulence_texture"), "{:?}", a.textures);
    assert!(!has(&b.textures, "turbulence_texture"), "{:?}", b.textures);
}

#[test]
fn one_full_resolution_frame_has_no_resolve_pass_or_history() {
    let single = frame();
    let mut upscaled = frame();
    upscaled.upscale = true;
    upscaled.frames = 2;
    let (Some(a), Some(b)) = (stats(&single), stats(&upscaled)) else {
        return;
    };
    assert!(!has(&a.pipelines, "resolve") && !has(&a.textures, "history"));
    assert!(!a.passes.contains(&"resolve"));
    assert!(has(&b.pipelines, "resolve") && has(&b.textures, "history"));
    assert_eq!(
        b.passes,
        ["shadow", "air", "clouds", "resolve", "clouds", "resolve"],
        "the shadow atlas and the air table are made once per render, clouds and resolve once \
         per frame"
    );
}

#[test]
fn a_variant_switched_off_drops_the_atlas_it_no_longer_needs() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, SIZES);
    r.render(&frame()).expect("with shadows");
    assert!(has(&r.stats().textures, "shadow_map"));
    let mut off = frame();
    off.features.shadows = false;
    off.features.light_shafts = false;
    r.render(&off).expect("without");
    assert!(!has(&r.stats().textures, "shadow_map"));
    assert!(r.shadow_atlas().expect("readback").is_none());
}

#[test]
fn the_atlas_is_redrawn_only_when_its_inputs_change() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, SIZES);
    let mut f = frame();
    r.render(&f).expect("first");
    assert_eq!(r.stats().passes, ["shadow", "air", "clouds"]);
    // Turning the camera does not move a shadow, nor change the air's light (the air table is
    // indexed by the angle to the sun's vertical plane, not the camera's heading).
    f.camera_yaw_deg = 30.0;
    r.render(&f).expect("turned");
    assert_eq!(r.stats().passes, ["clouds"]);
    // Moving the sun does both.
    f.sun_elevation_deg += 5.0;
    r.render(&f).expect("sun moved");
    assert_eq!(r.stats().passes, ["shadow", "air", "clouds"]);
    // Climbing relights the air (and moves the cascades, which follow the camera).
    f.camera_altitude += 100.0;
    r.render(&f).expect("camera climbed");
    assert_eq!(r.stats().passes, ["shadow", "air", "clouds"]);
    // So does the wind, the shadows only.
    f.weather_offset.x += 0.01;
    r.render(&f).expect("weather moved");
    assert_eq!(r.stats().passes, ["shadow", "clouds"]);
    r.render(&f).expect("unchanged");
    assert_eq!(r.stats().passes, ["clouds"]);
    // And a new weather map: the atlas was marched through the old one.
    r.set_texture(
        NoiseKind::Weather,
        TextureSource::User(gpu.constant_texture([1.0, 1.0, 1.0, 1.0])),
    );
    r.render(&f).expect("new weather map");
    assert_eq!(r.stats().passes, ["shadow", "clouds"]);
}
