//! The faint margins of clouds on the GPU against the model's own density marched on the CPU.
//!
//! A cloud's edge is where the coverage threshold cuts the filtered noise, and the threshold
//! clamps at zero: any rounding of the filtered texture values, zero on average, keeps only its
//! positive half there and draws cloud where the model has none. With the textures in RGBA8,
//! lavapipe filtered them in 8-bit arithmetic: a one-pixel halo of faint opacity around every
//! cloud, and pixels under 1 % opacity 1.7 times as opaque as the model's (the agreement
//! suite's thin edges read 3.5 % bright against Mitsuba). The textures are half floats now
//! (`textures::texel_value`).
//!
//! The view is the agreement suite's cumulus from above; the CPU side marches the same density
//! (the CPU twins of the same texels) in 2 m steps along 2×2 rays per pixel. The control gives
//! the GPU a weather texture one 8-bit level high, the size of the rounding that caused the
//! halo: the margins must see it.

mod common;

use std::path::Path;

use glam::Vec2;
use nimbus_clouds::model::march::{altitude_along, cloud_range, total_density, view_direction};
use nimbus_clouds::{CloudLibrary, PixelOutput, load_scene};
use nimbus_runtime::density_export::generate_cpu_textures;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes, TextureSource};
use nimbus_runtime::textures::NoiseKind;
use nimbus_runtime::user_textures::DecodedTexture;

const SIZE: (u32, u32) = (48, 27);

fn frame() -> Frame {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let lib = CloudLibrary::load(&root).expect("data");
    let scene = load_scene(&root.join("verification/cumulus-nadir.toml")).expect("scene");
    let mut f = Frame::from_scene(
        &scene,
        lib.genus(&scene.genus).expect("genus"),
        SIZE.0,
        SIZE.1,
    );
    f.output = PixelOutput::Clouds;
    f.frames = 8;
    f
}

/// Opacity (1 − transmittance) per pixel of the model's density, marched in 2 m steps along
/// 2×2 rays per pixel.
fn cpu_opacity(frame: &Frame) -> Vec<f64> {
    let u = Renderer::uniforms(frame);
    let key = frame.variant().key;
    let sigma = u.light.scattering_coefficient + u.light.absorption_coefficient;
    let textures = generate_cpu_textures(TextureSizes::default());
    let _bound = textures.bind(u);
    let mut out = Vec::with_capacity((SIZE.0 * SIZE.1) as usize);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let mut transmittance = 0.0f64;
            for s in 0..4 {
                let sub = Vec2::new(0.25 + 0.5 * (s % 2) as f32, 0.25 + 0.5 * (s / 2) as f32);
                let d = view_direction(Vec2::new(x as f32, y as f32) + sub);
                let range = cloud_range(d.y);
                let start = range.x.max(0.0);
                let mut tau = 0.0f64;
                if range.y > start {
                    let n = ((range.y - start) / 2.0).ceil().clamp(1.0, 50_000.0) as u32;
                    let dt = (range.y - start) / n as f32;
                    for i in 0..n {
                        let t = start + (i as f32 + 0.5) * dt;
                        let h = altitude_along(u.camera_altitude, d.y, t, u.march.radius);
                        tau += f64::from(total_density(d * t, h, 0.0, key) * sigma * dt);
                    }
                }
                transmittance += 0.25 * (-tau).exp();
            }
            out.push(1.0 - transmittance);
        }
    }
    out
}

/// The margins of `gpu` against `cpu` (opacities per pixel): pixels the GPU draws cloud in
/// (opacity over 1e-3) where the model has next to none (under 1e-4), and the GPU's mean
/// opacity over the model's where the model's is 0.1–1 %.
fn margins(gpu: &[f64], cpu: &[f64]) -> (usize, f64) {
    let halo = gpu
        .iter()
        .zip(cpu)
        .filter(|(g, c)| **g > 1e-3 && **c < 1e-4)
        .count();
    let faint: Vec<(f64, f64)> = gpu
        .iter()
        .zip(cpu)
        .filter(|(_, c)| (1e-3..1e-2).contains(*c))
        .map(|(g, c)| (*g, *c))
        .collect();
    assert!(faint.len() > 20, "only {} faint pixels", faint.len());
    let (g, c) = faint
        .iter()
        .fold((0.0, 0.0), |(g, c), (gi, ci)| (g + gi, c + ci));
    (halo, g / c)
}

fn gpu_opacity(renderer: &mut Renderer<'_>, frame: &Frame) -> Vec<f64> {
    let image = renderer.render(frame).expect("render");
    image.pixels.iter().map(|p| 1.0 - f64::from(p[3])).collect()
}

#[test]
fn cloud_margins_on_the_gpu_are_the_models() {
    let Some(gpu) = common::gpu() else { return };
    let frame = frame();
    let cpu = cpu_opacity(&frame);
    let mut renderer = Renderer::new(gpu, TextureSizes::default());
    let (halo, faint) = margins(&gpu_opacity(&mut renderer, &frame), &cpu);
    // Control: the weather texture one 8-bit level high.
    let size = TextureSizes::default().weather;
    let rgba: Vec<u8> = (0..size * size)
        .flat_map(|i| {
            let word = NoiseKind::Weather.cpu_texel(size, i % size, i / size, 0);
            word.to_le_bytes().map(|b| b.saturating_add(1))
        })
        .collect();
    let texture = DecodedTexture {
        file: "one level high".into(),
        size: [size, size, 1],
        volume: false,
        rgba,
    };
    let high = gpu.upload_texture(&texture).expect("upload");
    renderer.set_texture(NoiseKind::Weather, TextureSource::User(high));
    let (control_halo, control_faint) = margins(&gpu_opacity(&mut renderer, &frame), &cpu);
    println!(
        "margins: {halo} halo pixels, faint pixels {faint:.3} times the model's opacity; \
         control (weather one level high): {control_halo}, {control_faint:.3}"
    );
    assert!(halo <= 2, "{halo} pixels of cloud where the model has none");
    assert!(
        (0.8..1.25).contains(&faint),
        "faint margins {faint:.3} times the model's opacity"
    );
    assert!(
        control_halo > 2 || !(0.8..1.25).contains(&control_faint),
        "the control passes: {control_halo} halo pixels, {control_faint:.3}"
    );
    // The model's margins are there to compare: most of the image is not empty.
    let cloudy = cpu.iter().filter(|c| **c > 1e-3).count();
    assert!(cloudy * 4 > cpu.len(), "only {cloudy} cloudy pixels");
}
