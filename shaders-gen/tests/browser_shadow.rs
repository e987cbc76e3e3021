//! The clouds' shadow on the user's own three.js objects, in a real browser: a flat white
//! ground under cumulus (`medium`, sun 30° at azimuth 200°, camera 300 m up looking 10° down),
//! lit by a directional light from the clouds' sun alone. The package (built with `--enable
//! scene-depth`) draws the scene's depth, then its `scene_shadow` pass, and the ground is drawn
//! with a `MeshStandardMaterial` given to `NimbusClouds.shadowMaterial`. Checked: the pass's
//! output against Nimbus's runtime drawing the same pass for the same ground (its depth computed
//! here, ray by ray), and the material's light against the unshadowed material's scaled by the
//! pass's output, pixel by pixel. The controls: the material left untouched, the pass's output
//! read upside down, and the runtime's pass for a sun 90° round each fail.
//!
//! Needs node, `browser/node_modules`, Chromium and a GPU adapter (lavapipe in CI).

mod common;

use std::path::Path;

use glam::{Mat4, Vec2, Vec4};
use nimbus_clouds::model::scene_depth::SceneDepthParams;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::Gpu;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};
use nimbus_runtime::scene_depth::SceneDepth;
use nimbus_testkit::skip::browser_tools_present;
use serde_json::Value;

use common::{emit_package, have_gpu, missing_browser, render_page};

const W: u32 = 160;
const H: u32 = 90;
const FOV: f32 = 60.0;
const PITCH: f32 = -10.0;
const ALTITUDE: f32 = 300.0;
const SUN: (f32, f32) = (30.0, 200.0);
/// The ground's side (m), centred under the camera, as the page's `ground=` takes it.
const GROUND: f32 = 60_000.0;
const NEAR: f32 = 1.0;
const FAR: f32 = 1e6;
/// Unshadowed light below this (linear) is too dim for its ratio to mean anything.
const LIT_ENOUGH: f32 = 0.05;

fn frame(sun_azimuth: f32) -> Frame {
    let lib = CloudLibrary::load(Path::new(&common::examples(""))).expect("library");
    let genus = lib.genus("cumulus").expect("cumulus").clone();
    let mut f = Frame::new(genus, Quality::Medium, W, H);
    f.sun_elevation_deg = SUN.0;
    f.sun_azimuth_deg = sun_azimuth;
    f.camera_altitude = ALTITUDE;
    f.camera_pitch_deg = PITCH;
    f.fov_deg = FOV;
    f
}

/// The ground's depth as three.js writes it for the page's camera (OpenGL perspective, first
/// row at the top), and which pixels show it.
fn ground_depth(f: &Frame) -> (SceneDepth, Vec<bool>) {
    let inverse = f.view_projection().inverse();
    let (forward, _) = f.camera_basis();
    let projection = Mat4::perspective_rh_gl(FOV.to_radians(), W as f32 / H as f32, NEAR, FAR);
    let params = SceneDepthParams::opengl(projection, Mat4::IDENTITY, forward, W, H);
    let mut texels = Vec::new();
    let mut ground = Vec::new();
    for y in 0..H {
        for x in 0..W {
            let ndc = Vec2::new(
                (x as f32 + 0.5) / W as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / H as f32 * 2.0,
            );
            let clip = inverse * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
            let d = (clip.truncate() / clip.w).normalize();
            let t = -ALTITUDE / d.y;
            let p = d * t;
            let on = d.y < 0.0 && p.x.abs() < GROUND / 2.0 && p.z.abs() < GROUND / 2.0;
            ground.push(on);
            texels.push(if on {
                let clip = projection * Vec4::new(0.0, 0.0, -p.dot(forward), 1.0);
                clip.z / clip.w * 0.5 + 0.5
            } else {
                params.clear_depth
            });
        }
    }
    let depth = SceneDepth {
        width: W,
        height: H,
        texels,
        params,
    };
    (depth, ground)
}

/// Nimbus's runtime drawing the `scene_shadow` pass for the ground (red, first row the top).
fn runtime_mask(gpu: &Gpu, sun_azimuth: f32) -> (Vec<f32>, Vec<bool>) {
    let mut f = frame(sun_azimuth);
    let (depth, ground) = ground_depth(&f);
    f.scene_depth = Some(depth);
    let mut r = Renderer::new(gpu, TextureSizes::default());
    r.render(&f).expect("renders");
    let mask = r
        .scene_shadow()
        .expect("draws the pass")
        .expect("the frame has a scene and an atlas");
    (mask.pixels.iter().map(|p| p[0]).collect(), ground)
}

/// The page's values: the pass's output (first row the top) and both renders (first row the
/// bottom), as published.
struct PageValues {
    mask: Vec<f32>,
    lit: Vec<f32>,
    unlit: Vec<f32>,
}

fn page(package: &Path, out: &Path, name: &str, extra: &[&str]) -> PageValues {
    let png = out.join(format!("{name}.png"));
    let mut args = vec![
        "page=shadow".to_string(),
        format!("width={W}"),
        format!("height={H}"),
        format!("fov={FOV}"),
        format!("pitch={PITCH}"),
        format!("altitude={ALTITUDE}"),
        format!("ground={GROUND}"),
        format!("sun={},{}", SUN.0, SUN.1),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    let log = render_page(package, &png, &args);
    let log: Value = serde_json::from_str(&log).expect("the page's log is JSON");
    let values = &log["values"];
    let floats = |key: &str| -> Vec<f32> {
        values[key]
            .as_array()
            .unwrap_or_else(|| panic!("{name}: no `{key}` values"))
            .iter()
            .map(|v| v.as_f64().unwrap_or(f64::NAN) as f32)
            .collect()
    };
    let v = PageValues {
        mask: floats("mask"),
        lit: floats("lit"),
        unlit: floats("unlit"),
    };
    for (key, list) in [("mask", &v.mask), ("lit", &v.lit), ("unlit", &v.unlit)] {
        assert_eq!(list.len(), (W * H) as usize, "{name}: {key}");
    }
    v
}

/// Top-down index of the pixel a WebGL read's index `i` (first row the bottom) holds.
fn top_down(i: usize) -> usize {
    let (x, row) = (i % W as usize, i / W as usize);
    (H as usize - 1 - row) * W as usize + x
}

/// Mean |lit / unlit − mask| over the sunlit ground, with the mask read top-down (as the
/// material must) or, for the control, as WebGL rows.
fn ratio_error(v: &PageValues, upside_down: bool) -> (f32, usize) {
    let (mut sum, mut n) = (0.0f32, 0usize);
    for i in 0..v.lit.len() {
        if v.unlit[i] < LIT_ENOUGH {
            continue;
        }
        let m = if upside_down {
            v.mask[i]
        } else {
            v.mask[top_down(i)]
        };
        sum += (v.lit[i] / v.unlit[i] - m).abs();
        n += 1;
    }
    (sum / n.max(1) as f32, n)
}

/// Mean |a − b| over the ground.
fn mask_difference(a: &[f32], b: &[f32], ground: &[bool]) -> f32 {
    let (sum, n) = a
        .iter()
        .zip(b)
        .zip(ground)
        .filter(|(_, g)| **g)
        .fold((0.0f32, 0usize), |(s, n), ((x, y), _)| {
            (s + (x - y).abs(), n + 1)
        });
    sum / n.max(1) as f32
}

#[test]
fn the_clouds_shadow_falls_on_a_three_js_scene_as_nimbus_draws_it() {
    if !browser_tools_present("the browser shadow test", missing_browser()) || !have_gpu() {
        return;
    }
    let gpu = Gpu::new().expect("adapter");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("browser-shadow");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("output folder");
    let package = out.join("package");
    emit_package("three", "cumulus", "medium", &["scene-depth"], &package);

    let shadowed = page(&package, &out, "shadowed", &[]);
    let (reference, ground) = runtime_mask(&gpu, SUN.1);
    println!("runtime on {}", gpu.info());

    // The ground is partly in the clouds' shadow and partly sunlit.
    let on_ground: Vec<f32> = reference
        .iter()
        .zip(&ground)
        .filter(|(_, g)| **g)
        .map(|(m, _)| *m)
        .collect();
    let dark = on_ground.iter().filter(|m| **m < 0.5).count();
    let bright = on_ground.iter().filter(|m| **m > 0.9).count();
    println!(
        "{} ground pixels: {dark} in shadow (< 0.5), {bright} sunlit (> 0.9)",
        on_ground.len()
    );
    assert!(dark > 100 && bright > 100, "{dark} / {bright}");

    // The pass in Chromium against the runtime's, and against a sun 90° round (control).
    let browser_mask = shadowed.mask.clone();
    let against_runtime = mask_difference(&browser_mask, &reference, &ground);
    let (turned, _) = runtime_mask(&gpu, SUN.1 + 90.0);
    let against_turned = mask_difference(&browser_mask, &turned, &ground);
    println!(
        "scene_shadow in Chromium against the runtime: mean {against_runtime:.4}; against a sun \
         90° round {against_turned:.4}"
    );
    assert!(against_runtime < 0.01, "{against_runtime}");
    assert!(against_turned > 0.05, "the control: {against_turned}");
    // Where the scene has no surface, no shadow.
    for (i, g) in ground.iter().enumerate() {
        if !g && (i / W as usize) < (H as usize / 3) {
            assert_eq!(browser_mask[i], 1.0, "sky pixel {i}");
        }
    }

    // The material's direct light is the unshadowed material's scaled by the pass's output.
    let (error, n) = ratio_error(&shadowed, false);
    let (upside_down, _) = ratio_error(&shadowed, true);
    let untouched = page(&package, &out, "untouched", &["shadow=0"]);
    let (without, _) = ratio_error(&untouched, false);
    println!(
        "lit / unlit against the pass over {n} sunlit pixels: mean {error:.2e}; read upside \
         down {upside_down:.3}; material untouched {without:.3}"
    );
    assert!(n > 1000, "{n} pixels compared");
    assert!(error < 0.01, "{error}");
    assert!(
        upside_down > 0.05,
        "the control (rows flipped): {upside_down}"
    );
    assert!(without > 0.05, "the control (no shadow): {without}");
}
