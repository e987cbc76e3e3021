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
