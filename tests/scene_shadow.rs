//! The clouds' shadow on the engine's objects (the `scene_shadow` pass): for each pixel of the
//! engine's depth buffer, the sun's light through the clouds at the surface there. The GPU pass
//! on a flat ground seen by a perspective camera is checked against the CPU twin of
//! `sun_through_clouds` evaluated at the ground points the test computes itself (from the
//! plane, not from the depth buffer), with the GPU's own shadow atlas; the controls: the same
//! reference for a sun 90° round fails it, pixels with no surface are unshadowed, and the
//! ground is partly shadowed and partly lit.

mod common;

use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};
use nimbus_clouds::model::bindings::CloudTextures;
use nimbus_clouds::model::scene_depth::SceneDepthParams;
use nimbus_clouds::model::scene_shadow::sun_through_clouds;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_dsl::cpu::{Texture2d, Texture3d};
use nimbus_runtime::render::{Frame, Image, Renderer, TextureSizes};
use nimbus_runtime::scene_depth::SceneDepth;

const W: u32 = 96;
const H: u32 = 54;
const NEAR: f32 = 1.0;
const FAR: f32 = 1e6;
/// Ground farther than this is left undrawn (the sky of the engine's scene).
const GROUND_REACH: f32 = 30_000.0;

fn frame() -> Frame {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let mut genus = lib.genus("cumulus").expect("cumulus").clone();
    genus.coverage = 0.35;
    let mut f = Frame::new(genus, Quality::Medium, W, H);
    f.camera_altitude = 300.0;
    f.camera_pitch_deg = -12.0;
    f.sun_elevation_deg = 35.0;
    f.sun_azimuth_deg = 200.0;
    f
}

/// The unit view ray through the centre of pixel `(x, y)` (top-down), as the passes make it.
fn ray(f: &Frame, x: u32, y: u32) -> Vec3 {
    let inverse = f.view_projection().inverse();
    let ndc = Vec2::new(
        (x as f32 + 0.5) / f.width as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / f.height as f32 * 2.0,
    );
    let clip = inverse * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
    (clip.truncate() / clip.w).normalize()
}

/// Where the ray of pixel `(x, y)` meets the flat ground, camera-relative, if it does within
/// reach.
fn ground_point(f: &Frame, x: u32, y: u32) -> Option<Vec3> {
    let d = ray(f, x, y);
    let t = -f.camera_altitude / d.y;
    (d.y < 0.0 && t < GROUND_REACH).then(|| d * t)
}

/// The flat ground's depth in an OpenGL-style perspective buffer of the frame's camera.
fn ground_depth(f: &Frame) -> SceneDepth {
    let aspect = f.width as f32 / f.height as f32;
    let projection = Mat4::perspective_rh_gl(f.fov_deg.to_radians(), aspect, NEAR, FAR);
    let (forward, _) = f.camera_basis();
    let params = SceneDepthParams::opengl(projection, Mat4::IDENTITY, forward, f.width, f.height);
    let mut texels = Vec::with_capacity((f.width * f.height) as usize);
    for y in 0..f.height {
        for x in 0..f.width {
            texels.push(match ground_point(f, x, y) {
                Some(p) => {
                    let clip = projection * Vec4::new(0.0, 0.0, -p.dot(forward), 1.0);
                    (clip.z / clip.w + 1.0) * 0.5
                }
                None => params.clear_depth,
            });
        }
    }
    SceneDepth {
        width: f.width,
        height: f.height,
        texels,
        params,
    }
}

/// The CPU twin's light through the clouds at every ground pixel (`None` where there is no
/// ground), with the GPU's atlas bound as the passes bind it.
fn reference(f: &Frame, atlas: &Image) -> Vec<Option<f32>> {
    let plane = |size: u32| {
        Arc::new(Texture2d {
            size: [size, size],
            texels: vec![Vec4::ZERO; (size * size) as usize],
        })
    };
    let cube = Arc::new(Texture3d {
        size: [1, 1, 1],
        texels: vec![Vec4::ZERO],
    });
    let textures = CloudTextures {
        weather: plane(1),
        shape: cube.clone(),
        detail: cube,
        turbulence: plane(1),
        shadow: Arc::new(Texture2d {
            size: [atlas.width, atlas.height],
            texels: atlas.pixels.iter().map(|p| Vec4::from_array(*p)).collect(),
        }),
    };
    let _bound = textures.bind(Renderer::uniforms(f));
    (0..f.height)
        .flat_map(|y| (0..f.width).map(move |x| (x, y)))
        .map(|(x, y)| ground_point(f, x, y).map(sun_through_clouds))
        .collect()
}

/// Mean and largest difference between the pass's red channel and `expected` over the ground.
fn difference(mask: &Image, expected: &[Option<f32>]) -> (f32, f32) {
    let (mut sum, mut worst, mut n) = (0.0f32, 0.0f32, 0);
    for (p, e) in mask.pixels.iter().zip(expected) {
        if let Some(e) = e {
            let d = (p[0] - e).abs();
            sum += d;
            worst = worst.max(d);
            n += 1;
        }
    }
    (sum / n.max(1) as f32, worst)
}

#[test]
fn the_scene_shadow_pass_is_the_suns_light_through_the_clouds_at_each_surface() {
    let Some(gpu) = common::gpu() else { return };
    let sizes = TextureSizes {
        weather: 128,
        shape: 32,
        detail: 16,
        turbulence: 32,
    };
    let mut r = Renderer::new(gpu, sizes);
    let mut f = frame();
    f.scene_depth = Some(ground_depth(&f));
    assert!(
        f.variant().key.shadow_key().is_some(),
        "the frame's key has a shadow atlas"
    );
    r.render(&f).expect("renders");
    let mask = r
        .scene_shadow()
        .expect("the scene shadow pass runs")
        .expect("a frame with a scene and an atlas has one");
    let atlas = r
        .shadow_atlas()
        .expect("reads the atlas")
        .expect("an atlas");
    println!("on {}", gpu.info());

    let expected = reference(&f, &atlas);
    let (mean, worst) = difference(&mask, &expected);
    let ground: Vec<f32> = expected.iter().flatten().copied().collect();
    let shadowed = ground.iter().filter(|t| **t < 0.5).count();
    let lit = ground.iter().filter(|t| **t > 0.9).count();
    println!(
        "{} ground pixels: {shadowed} in shadow (< 0.5), {lit} lit (> 0.9); GPU pass against the \
         CPU twin: mean {mean:.4}, worst {worst:.4}",
        ground.len()
    );
    assert!(
        shadowed > 20 && lit > 20,
        "the view holds both shadow and sunlit ground: {shadowed} / {lit}"
    );
    assert!(mean < 0.01 && worst < 0.08, "mean {mean}, worst {worst}");
    // Where the scene has no surface nothing is shadowed.
    for (p, e) in mask.pixels.iter().zip(&expected) {
        if e.is_none() {
            assert_eq!(p[0], 1.0, "a pixel with no surface: {p:?}");
        }
    }

    // The control: the shadow of a sun 90° round is not this one.
    let mut turned = f.clone();
    turned.sun_azimuth_deg += 90.0;
    let (mean, _) = difference(&mask, &reference(&turned, &atlas));
    println!("against a sun 90° round: mean {mean:.4}");
    assert!(mean > 0.05, "the mask does not follow the sun: {mean}");
}
