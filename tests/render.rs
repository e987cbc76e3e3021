//! The wgpu runtime renders a cloud variant: finite pixels, clouds present, deterministic for a
//! fixed frame, and pipelines reused from the cache when a preset comes back.

mod common;

use std::path::Path;

use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::ShaderInput;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

fn frame(quality: Quality) -> Frame {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    Frame::new(
        lib.genus("cumulus").expect("cumulus").clone(),
        quality,
        96,
        54,
    )
}

/// Small procedural textures: enough detail for clouds, quick to build on llvmpipe.
fn small_textures() -> TextureSizes {
    TextureSizes {
        weather: 128,
        shape: 32,
        detail: 16,
        turbulence: 32,
    }
}

#[test]
fn renders_clouds_deterministically_and_caches_pipelines() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, small_textures());
    let a = r.render(&frame(Quality::Low)).expect("render");
    assert_eq!(a.pixels.len(), 96 * 54);
    assert!(
        a.pixels.iter().flatten().all(|v| v.is_finite()),
        "non-finite pixel"
    );
    assert!(
        a.pixels.iter().all(|p| (0.0..=1.0).contains(&p[3])),
        "alpha outside [0, 1]"
    );
    let cloudy = a.pixels.iter().filter(|p| p[3] > 0.05).count();
    println!(
        "{cloudy} of {} pixels show cloud, on {}",
        a.pixels.len(),
        gpu.info()
    );
    assert!(cloudy > 20, "no clouds in the frame");
    let b = r.render(&frame(Quality::Low)).expect("render again");
    assert_eq!(a.pixels, b.pixels, "same frame, same pixels");
    // Low: the shadow atlas, the air table and the clouds.
    assert_eq!(r.pipeline_count(), 3, "{:?}", r.stats().pipelines);
    // Medium: its own clouds and shadow pass; the air table is every key's.
    r.render(&frame(Quality::Medium)).expect("medium");
    assert_eq!(r.pipeline_count(), 5, "{:?}", r.stats().pipelines);
    r.render(&frame(Quality::Low)).expect("low again");
    assert_eq!(
        r.pipeline_count(),
        5,
        "switching back reuses the cached pipelines"
    );
}

#[test]
fn a_bad_resolution_is_an_error_not_a_panic() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(
        gpu,
        TextureSizes {
            weather: 16,
            shape: 8,
            detail: 8,
            turbulence: 8,
        },
    );
    for (w, h) in [(0, 90), (100_000, 90)] {
        let mut f = frame(Quality::Low);
        f.width = w;
        f.height = h;
        let err = r.render(&f).expect_err("refused").to_string();
        assert!(
            err.contains("Frame::width") && err.contains(&w.to_string()),
            "{err}"
        );
    }
}

/// Largest difference between two images, relative to 1 + the first's value.
fn worst(a: &nimbus_runtime::render::Image, b: &nimbus_runtime::render::Image) -> f32 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| {
            p.iter()
                .zip(q)
                .map(|(x, y)| (x - y).abs() / (1.0 + x.abs()))
        })
        .fold(0.0f32, f32::max)
}

/// Uniform blocks bound as `vec4` word arrays and unpacked by the shader (the three.js
/// package's layout) draw exactly what the struct-bound shaders draw, from the same bytes; the
/// control is that a 1° turn of the sun, through the same path, changes the image.
#[test]
fn flattened_uniform_blocks_render_what_struct_blocks_render() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, small_textures());
    for q in [Quality::Low, Quality::High] {
        let mut f = frame(q);
        f.frames = 2;
        r.set_flat_uniforms(false);
        let structs = r.render(&f).expect("struct blocks");
        r.set_flat_uniforms(true);
        let flat = r.render(&f).expect("flattened blocks");
        let d = worst(&structs, &flat);
        println!(
            "{}: struct vs flattened blocks {d:.2e} on {}",
            q.name(),
            gpu.info()
        );
        assert!(d == 0.0, "{}: flattened blocks differ by {d}", q.name());
        let mut g = f.clone();
        g.sun_azimuth_deg += 1.0;
        let turned = r.render(&g).expect("sun turned");
        let control = worst(&flat, &turned);
        println!("{}: sun turned 1°: {control:.2e}", q.name());
        assert!(control > 1e-4, "the flattened uniforms are not read");
    }
}

/// Pipelines created from the naga module lowered from the DSL's IR (what the runtime uses)
/// draw what pipelines created from the printed WGSL (what WebGPU hosts load) draw: the two
/// forms of one shader agree. The control is a 1° turn of the sun through the lowered path.
#[test]
fn the_lowered_module_renders_what_the_printed_wgsl_renders() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, small_textures());
    for q in [Quality::Low, Quality::High, Quality::Ultra] {
        let mut f = frame(q);
        f.frames = 2;
        r.set_shader_input(ShaderInput::PrintedWgsl);
        let printed = r.render(&f).expect("printed WGSL");
        r.set_shader_input(ShaderInput::Lowered);
        let lowered = r.render(&f).expect("lowered module");
        let d = worst(&printed, &lowered);
        println!(
            "{}: printed WGSL vs lowered module {d:.2e} on {}",
            q.name(),
            gpu.info()
        );
        assert!(d <= 1e-6, "{}: the two forms differ by {d}", q.name());
        let mut g = f.clone();
        g.sun_azimuth_deg += 1.0;
        let turned = r.render(&g).expect("sun turned");
        let control = worst(&lowered, &turned);
        println!("{}: sun turned 1°: {control:.2e}", q.name());
        assert!(control > 1e-4, "the comparison cannot see a change");
    }
}

/// The uber-shader (every generation-time choice a uniform and a run-time branch) draws what
/// each preset's specialised shader draws; a key uniform that says "powder off" where the
/// specialised shader has it on is the control that the uniforms are read at all.
#[test]
fn the_uber_shader_renders_what_the_specialised_shaders_render() {
    let Some(gpu) = common::gpu() else { return };
    let mut r = Renderer::new(gpu, small_textures());
    for q in [Quality::Low, Quality::High] {
        let f = frame(q);
        r.set_uber_shader(false);
        let specialised = r.render(&f).expect("specialised");
        r.set_uber_shader(true);
        let uber = r.render(&f).expect("uber");
        let d = worst(&specialised, &uber);
        println!(
            "{}: largest relative difference specialised vs uber {d:.2e} on {}",
            q.name(),
            gpu.info()
        );
        assert!(d < 1e-3, "{}: uber differs by {d}", q.name());
        assert!(r.stats().pipelines.iter().any(|p| p.contains("uber")));
        // Control: the same uber pipeline told that powder is off draws another image.
        let mut g = f.clone();
        g.features.powder = !g.features.powder;
        let toggled = r.render(&g).expect("uber, powder toggled");
        let control = worst(&uber, &toggled);
        println!(
            "{}: powder toggled through the key uniforms: {control:.2e}",
            q.name()
        );
        assert!(control > 1e-3, "the key uniforms are not read");
    }
}
