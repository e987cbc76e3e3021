//! The derived (minimal) variant renders what the all-effects variant renders wherever the
//! effects it leaves out contribute nothing: the elimination is correct, not just faster.

mod common;

use std::path::Path;

use nimbus_clouds::{CloudLibrary, Features, ScenePreset};
use nimbus_runtime::render::{Frame, Image, Renderer, TextureSizes};

const SIZES: TextureSizes = TextureSizes {
    weather: 128,
    shape: 32,
    detail: 16,
    turbulence: 32,
};

fn library() -> CloudLibrary {
    CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data")
}

/// Largest difference between two renders, relative to the brightest value.
fn difference(a: &Image, b: &Image) -> f32 {
    let peak = a
        .pixels
        .iter()
        .flatten()
        .fold(0.0f32, |m, v| m.max(v.abs()))
        .max(1e-6);
    let worst = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| p.iter().zip(q).map(|(x, y)| (x - y).abs()))
        .fold(0.0f32, f32::max);
    worst / peak
}

/// Renders `scene` with its derived variant and with every effect on; returns the relative
/// difference after checking that the variants really differ.
fn derived_against_all(scene: &ScenePreset, expect_off: &[&str]) -> Option<f32> {
    let gpu = common::gpu()?;
    let lib = library();
    let genus = lib.genus(&scene.genus).expect("genus");
    let mut derived = Frame::from_scene(scene, genus, 64, 36);
    // What is eliminated here is exact; the approximation the analysis may choose (the flat
    // high layer) is not, and the accuracy study measures it instead.
    derived.features.flat_high_layer = false;
    let mut all = derived.clone();
    all.features = Features::default();
    for t in expect_off {
        let toggle = nimbus_clouds::Toggle::parse(t).expect("toggle");
        assert!(!toggle.get(&derived.features), "{t} should be derived off");
    }
    assert_ne!(derived.variant().key, all.variant().key);
    let mut r = Renderer::new(gpu, SIZES);
    let a = r.render(&derived).expect("derived");
    let b = r.render(&all).expect("all effects");
    let d = difference(&a, &b);
    println!(
        "{}: {} vs {}: largest difference {d:.2e} of the peak",
        scene.name,
        derived.variant().name(),
        all.variant().name()
    );
    Some(d)
}

#[test]
fn twilight_without_sun_haze_turbulence_or_detail_renders_the_same() {
    let lib = library();
    let scene = &lib.scenes["twilight-cirrus"].1;
    let Some(d) = derived_against_all(
        scene,
        &[
            "shadows",
            "light-shafts",
            "haze",
            "turbulence",
            "shape-detail",
        ],
    ) else {
        return;
    };
    assert!(d < 1e-3, "elimination changed the picture by {d}");
}

#[test]
fn a_veil_without_shadow_casters_detail_or_turbulence_renders_the_same() {
    let lib = library();
    let scene = &lib.scenes["still-cirrostratus"].1;
    let Some(d) = derived_against_all(
        scene,
        &["shadows", "light-shafts", "turbulence", "shape-detail"],
    ) else {
        return;
    };
    assert!(d < 1e-3, "elimination changed the picture by {d}");
}

#[test]
fn still_clean_air_over_cumulus_renders_the_same_without_haze_and_turbulence() {
    let lib = library();
    let mut scene = lib.scenes["partly-cloudy"].1.clone();
    scene.haze_density = 0.0;
    scene.turbulence_displacement = 0.0;
    scene.camera_pitch_deg = 20.0;
    let Some(d) = derived_against_all(&scene, &["haze", "light-shafts", "turbulence"]) else {
        return;
    };
    assert!(d < 1e-3, "elimination changed the picture by {d}");
}

#[test]
fn a_real_difference_is_caught() {
    // The same harness must see a difference where an effect does contribute: shadows on a
    // sunlit cumulus field.
    let Some(gpu) = common::gpu() else { return };
    let lib = library();
    let scene = &lib.scenes["partly-cloudy"].1;
    let genus = lib.genus(&scene.genus).expect("genus");
    let mut on = Frame::from_scene(scene, genus, 64, 36);
    on.camera_pitch_deg = -10.0;
    let mut off = on.clone();
    off.features.shadows = false;
    off.features.light_shafts = false;
    let mut r = Renderer::new(gpu, SIZES);
    let d = difference(&r.render(&on).expect("on"), &r.render(&off).expect("off"));
    println!("shadows on vs off: {d:.2e}");
    assert!(d > 1e-2, "shadows made no difference: {d}");
}
