//! Clouds in the engine's own scene (the `scene-depth` key): the engine's depth buffer stops the
//! march, whatever the buffer's encoding, and the output is premultiplied over the engine's
//! picture — the full sky where the engine drew nothing, only the clouds (and the air and haze
//! in front of the engine's surfaces) otherwise.

mod common;

use std::path::Path;

use glam::{Mat4, Vec3, Vec4};
use nimbus_clouds::model::march::CompositeParams;
use nimbus_clouds::model::scene_depth::SceneDepthParams;
use nimbus_clouds::{CloudLibrary, PixelOutput, Quality};
use nimbus_runtime::render::{Frame, Image, Renderer, TextureSizes};
use nimbus_runtime::scene_depth::SceneDepth;

const W: u32 = 64;
const H: u32 = 36;
const NEAR: f32 = 1.0;
const FAR: f32 = 1e6;

fn frame() -> Frame {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let mut genus = lib.genus("cumulus").expect("cumulus").clone();
    genus.coverage = 0.6;
    let mut f = Frame::new(genus, Quality::Low, W, H);
    f.camera_pitch_deg = 14.0;
    f
}

fn small_textures() -> TextureSizes {
    TextureSizes {
        weather: 128,
        shape: 32,
        detail: 16,
        turbulence: 32,
    }
}

/// How a depth buffer was written.
#[derive(Clone, Copy, Debug)]
enum Encoding {
    /// OpenGL: depth 0 near, 1 far, NDC z in [−1, 1].
    Perspective,
    /// Reversed-Z with an infinite far plane (WebGPU, D3D style): depth 1 near, 0 far.
    ReversedInfinite,
    /// three.js's logarithmic depth: log2(1 + w) / log2(far + 1).
    Logarithmic,
}

/// A wall facing the camera `distance` metres ahead (along its forward axis) over the right
/// half of the image; nothing drawn on the left.
fn wall(f: &Frame, distance: f32, encoding: Encoding) -> SceneDepth {
    let aspect = f.width as f32 / f.height as f32;
    let fov = f.fov_deg.to_radians();
    let (projection, params) = match encoding {
        Encoding::Perspective | Encoding::Logarithmic => {
            let p = Mat4::perspective_rh_gl(fov, aspect, NEAR, FAR);
            (
                p,
                SceneDepthParams::opengl(p, Mat4::IDENTITY, Vec3::Z, f.width, f.height),
            )
        }
        Encoding::ReversedInfinite => {
            let p = Mat4::perspective_infinite_reverse_rh(fov, aspect, NEAR);
            let mut params =
                SceneDepthParams::opengl(p, Mat4::IDENTITY, Vec3::Z, f.width, f.height);
            params.depth_scale = 1.0;
            params.depth_offset = 0.0;
            params.clear_depth = 0.0;
            (p, params)
        }
    };
    let mut params = params;
    if let Encoding::Logarithmic = encoding {
        params.encoding = 1;
        params.log_range = (FAR + 1.0).log2();
    }
    let depth_of = |z: f32| -> f32 {
        match encoding {
            Encoding::Logarithmic => (1.0 + z).log2() / (FAR + 1.0).log2(),
            _ => {
                let clip = projection * Vec4::new(0.0, 0.0, -z, 1.0);
                let ndc = clip.z / clip.w;
                (ndc - params.depth_offset) / params.depth_scale
            }
        }
    };
    let mut texels = Vec::with_capacity((f.width * f.height) as usize);
    for _y in 0..f.height {
        for x in 0..f.width {
            texels.push(if x >= f.width / 2 {
                depth_of(distance)
            } else {
                params.clear_depth
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

fn render(r: &mut Renderer, f: &Frame) -> Image {
    r.render(f).expect("renders")
}

fn right_half(img: &Image) -> impl Iterator<Item = &[f32; 4]> {
    img.pixels
        .iter()
        .enumerate()
        .filter(|(i, _)| (*i as u32 % W) >= W / 2)
        .map(|(_, p)| p)
}

fn mean_alpha_right(img: &Image) -> f32 {
    let (sum, n) = right_half(img).fold((0.0, 0), |(s, n), p| (s + p[3], n + 1));
    sum / n as f32
}

#[test]
fn a_near_wall_hides_the_sky_and_the_rest_is_the_full_composite() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, small_textures());
    let plain = frame();
    let without = render(&mut r, &plain);
    let mut f = frame();
    f.scene_depth = Some(wall(&f, 2.0, Encoding::Perspective));
    let with = render(&mut r, &f);
    println!("on {}", gpu.info());
    // In front of a wall 2 m away Nimbus adds nothing and hides nothing of it.
    let worst = right_half(&with).fold(0.0f32, |m, p| m.max(p[0]).max(p[1]).max(p[2]).max(p[3]));
    assert!(
        worst < 2e-3,
        "in front of a 2 m wall: largest value {worst}"
    );
    // The control: without the scene those pixels are Nimbus's sky.
    let sky = right_half(&without).fold(0.0f32, |m, p| m.max(p[2]));
    assert!(sky > 0.01, "the sky without a scene: {sky}");
    // Where the engine drew nothing, the full composite, opaque.
    let mut largest = 0.0f32;
    for (i, (a, b)) in without.pixels.iter().zip(&with.pixels).enumerate() {
        if (i as u32 % W) < W / 2 {
            for c in 0..3 {
                largest = largest.max((a[c] - b[c]).abs());
            }
            assert_eq!(b[3], 1.0, "pixel {i}: Nimbus's sky is opaque");
        }
    }
    assert!(largest < 1e-5, "left half differs by {largest}");
}

#[test]
fn clouds_stop_at_the_scene_in_every_depth_encoding() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, small_textures());
    // A wall among the clouds: part of them in front of it, the rest hidden.
    let mut opacity = Vec::new();
    for distance in [300.0, 4_000.0, 12_000.0, 60_000.0] {
        let mut f = frame();
        f.scene_depth = Some(wall(&f, distance, Encoding::Perspective));
        opacity.push(mean_alpha_right(&render(&mut r, &f)));
    }
    println!("opacity in front of walls at 0.3, 4, 12, 60 km: {opacity:?}");
    // 300 m of air and haze, no cloud: under the clouds' base for every ray.
    assert!(
        opacity[0] < 0.05,
        "nothing but air stands in front of a wall 300 m away: {opacity:?}"
    );
    assert!(
        opacity.windows(2).all(|w| w[1] > w[0] + 0.01),
        "further walls have more cloud in front of them: {opacity:?}"
    );
    // The same wall in three encodings of the depth buffer.
    let mut images = Vec::new();
    for encoding in [
        Encoding::Perspective,
        Encoding::ReversedInfinite,
        Encoding::Logarithmic,
    ] {
        let mut f = frame();
        f.scene_depth = Some(wall(&f, 12_000.0, encoding));
        images.push((encoding, render(&mut r, &f)));
    }
    let (_, reference) = &images[0];
    for (encoding, img) in &images[1..] {
        let mean: f32 = img
            .pixels
            .iter()
            .zip(&reference.pixels)
            .map(|(a, b)| (0..4).map(|c| (a[c] - b[c]).abs()).sum::<f32>())
            .sum::<f32>()
            / (img.pixels.len() * 4) as f32;
        println!("{encoding:?} against perspective: mean difference {mean:.2e}");
        assert!(mean < 2e-4, "{encoding:?}: mean difference {mean}");
    }
}

#[test]
fn clouds_only_output_is_the_clouds_radiance_and_transmittance() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, small_textures());
    // The clouds alone as the march gives them.
    let mut raw = frame();
    raw.features.haze = false;
    raw.output = PixelOutput::Clouds;
    let clouds = render(&mut r, &raw);
    // Clouds-only over the engine's background: no sky, ground, sun or air of Nimbus's, and
    // a scene whose surfaces are all beyond the clouds.
    let mut f = frame();
    f.features.haze = false;
    f.composite = CompositeParams::NONE;
    f.scene_depth = Some(wall(&f, 400_000.0, Encoding::Perspective));
    let over = render(&mut r, &f);
    let mut worst = 0.0f32;
    for (a, b) in clouds.pixels.iter().zip(&over.pixels) {
        for c in 0..3 {
            worst = worst.max((a[c] - b[c]).abs());
        }
        worst = worst.max((1.0 - a[3] - b[3]).abs());
    }
    let cloudy = clouds.pixels.iter().filter(|p| p[3] < 0.9).count();
    println!("{cloudy} cloudy pixels; largest difference {worst:.2e}");
    assert!(cloudy > 50, "{cloudy} cloudy pixels");
    // Half-float targets: alpha holds 1 − T here and T there, 4.9e-4 apart near 1.
    assert!(
        worst < 1e-3,
        "clouds-only differs from the clouds by {worst}"
    );
}

/// The impostor over the engine's scene keeps the march's result in its map and composites it
/// per pixel (the scene's depth is per pixel); without the scene its map holds the whole
/// picture. Where the engine drew nothing the two must show the same sky; in front of a 2 m
/// wall, nothing. The control: the per-pixel composite of a map baked for a sun 6° lower.
#[test]
fn the_impostor_over_the_scene_is_the_impostor_where_the_scene_is_empty() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, small_textures());
    let impostor = |f: &mut Frame| f.features.path = nimbus_clouds::Path::Impostor;
    let mut plain = frame();
    impostor(&mut plain);
    let baked_view = render(&mut r, &plain);
    let mut f = frame();
    impostor(&mut f);
    f.scene_depth = Some(wall(&f, 2.0, Encoding::Perspective));
    let over_scene = render(&mut r, &f);
    let mut lower = f.clone();
    lower.sun_elevation_deg -= 6.0;
    let control = render(&mut r, &lower);
    println!("on {}", gpu.info());
    let worst =
        right_half(&over_scene).fold(0.0f32, |m, p| m.max(p[0]).max(p[1]).max(p[2]).max(p[3]));
    assert!(
        worst < 2e-3,
        "in front of a 2 m wall: largest value {worst}"
    );
    // Mean relative difference over the left half, where the engine drew nothing.
    let left = |a: &Image, b: &Image| {
        let (mut diff, mut sum) = (0.0f32, 0.0f32);
        for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
            if (i as u32 % W) < W / 2 {
                for c in 0..3 {
                    diff += (p[c] - q[c]).abs();
                    sum += p[c].abs();
                }
            }
        }
        diff / sum.max(1e-20)
    };
    let d = left(&baked_view, &over_scene);
    let c = left(&baked_view, &control);
    println!("left half: over the scene {d:.4} from the baked view; control (sun 6° lower) {c:.4}");
    assert!(
        d < 0.02,
        "the impostor over the scene departs from its baked view by {d}"
    );
    assert!(c > 2.0 * 0.02, "the control passes: {c}");
}

/// Every baked path stops at the engine's surface: the slices' march ends there as the
/// volume's does, and the clouds of a map (the impostor's, the mesh's, the 2D map's, each the
/// whole ray's) are hidden where their front lies behind it. In front of a 2 m wall Nimbus adds
/// nothing; the control is the same path without the scene, its sky in those pixels.
#[test]
fn every_baked_path_stops_at_the_scene() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, small_textures());
    println!("on {}", gpu.info());
    for path in [
        nimbus_clouds::Path::Slices,
        nimbus_clouds::Path::Impostor,
        nimbus_clouds::Path::Mesh,
        nimbus_clouds::Path::Blob2d,
    ] {
        let mut plain = frame();
        plain.features.path = path;
        let sky = right_half(&render(&mut r, &plain)).fold(0.0f32, |m, p| m.max(p[2]));
        let mut f = plain.clone();
        f.scene_depth = Some(wall(&f, 2.0, Encoding::Perspective));
        let with = render(&mut r, &f);
        let worst =
            right_half(&with).fold(0.0f32, |m, p| m.max(p[0]).max(p[1]).max(p[2]).max(p[3]));
        println!("{path}: in front of a 2 m wall {worst:.2e}; without the scene {sky:.3}");
        assert!(sky > 0.01, "{path}: the sky without a scene: {sky}");
        assert!(
            worst < 2e-3,
            "{path} in front of a 2 m wall: largest value {worst}"
        );
    }
}
