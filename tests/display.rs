//! The display pass an engine package ends its frame with: on the GPU it equals its CPU twin,
//! its 8-bit output is exactly what `nimbus render` writes to a PNG from the same HDR image, and
//! `flip_y` turns the image upright for bottom-up framebuffers.

mod common;

use std::sync::Arc;

use glam::{Vec2, Vec4};
use nimbus_clouds::model::bindings::{DISPLAY, DISPLAY_SAMPLER, DISPLAY_SOURCE};
use nimbus_clouds::model::display::{DisplayParams, DisplayParamsShader, display_fragment};
use nimbus_dsl::cpu::{AddressMode, Filter, Sampler, Texture2d};
use nimbus_dsl::ir::{ExprId, Scalar, Type};
use nimbus_dsl::layout::Flatten;
use nimbus_dsl::shader;
use nimbus_dsl::{CpuBindings, Value};
use nimbus_runtime::GpuResource;
use nimbus_runtime::render::Image;
use nimbus_testkit::parity::{KernelFn, run_on_gpu};

const W: u32 = 24;
const H: u32 = 16;

/// An HDR image with values f16 holds exactly (the GPU copy is half floats), from dark to
/// brighter than the tone curve's knee.
fn source() -> Texture2d {
    let texels = (0..W * H)
        .map(|i| {
            let v = |k: u32| ((i * 37 + k * 11) % 97) as f32 / 64.0;
            Vec4::new(v(0), v(1), v(2), ((i % 5) as f32) / 4.0)
        })
        .collect();
    Texture2d {
        size: [W, H],
        texels,
    }
}

fn nearest() -> Sampler {
    Sampler {
        address: AddressMode::ClampToEdge,
        filter: Filter::Nearest,
    }
}

fn params(flip_y: f32) -> DisplayParams {
    DisplayParams {
        resolution: Vec2::new(W as f32, H as f32),
        exposure: 8.0,
        keep_alpha: 0.0,
        flip_y,
    }
}

/// The CPU twin at every pixel centre, row-major from the top.
fn cpu(tex: &Texture2d, p: DisplayParams) -> Vec<Vec4> {
    let _bound = CpuBindings::new()
        .set(&DISPLAY, p)
        .set(&DISPLAY_SOURCE, Arc::new(tex.clone()))
        .set(&DISPLAY_SAMPLER, nearest())
        .bind();
    (0..H)
        .flat_map(|y| (0..W).map(move |x| (x, y)))
        .map(|(x, y)| display_fragment(Vec4::new(x as f32 + 0.5, y as f32 + 0.5, 0.0, 1.0)))
        .collect()
}

#[test]
fn the_display_pass_matches_its_cpu_twin_on_the_gpu() {
    let Some(gpu) = common::gpu() else { return };
    println!("adapter: {}", gpu.info());
    let tex = source();
    let resources = [
        (DISPLAY_SOURCE.slot().1, GpuResource::Texture2d(tex.clone())),
        (DISPLAY_SAMPLER.slot().1, GpuResource::Sampler(nearest())),
    ];
    let call = |a: &[ExprId]| {
        DISPLAY.feed(DisplayParamsShader::from_id(a[1]));
        display_fragment::shader(shader::Vec4::from_id(a[0])).id()
    };
    let f = KernelFn {
        name: "display_fragment",
        params: vec![
            Type::Vector(4, Scalar::F32),
            <DisplayParamsShader as Value>::TYPE,
        ],
        result: Type::Vector(4, Scalar::F32),
        call: &call,
        resources: &resources,
    };
    for flip in [0.0, 1.0] {
        let mut words = Vec::new();
        for y in 0..H {
            for x in 0..W {
                let frag = [x as f32 + 0.5, y as f32 + 0.5, 0.0, 1.0];
                words.extend(frag.map(f32::to_bits));
                params(flip).flatten(&mut words);
            }
        }
        let out = run_on_gpu(gpu, &f, &words).expect("GPU run");
        let want = cpu(&tex, params(flip));
        let mut worst = 0.0f32;
        for (w, c) in out.chunks_exact(4).zip(&want) {
            let g = Vec4::from_array([0, 1, 2, 3].map(|i| f32::from_bits(w[i])));
            worst = worst.max((g - *c).abs().max_element());
        }
        println!(
            "flip_y {flip}: {} pixels, largest difference {worst:e}",
            want.len()
        );
        assert!(worst < 1e-5, "flip_y {flip}: GPU and CPU differ by {worst}");
    }
}

#[test]
fn the_display_pass_writes_what_render_writes_to_a_png() {
    let tex = source();
    let image = Image {
        width: W,
        height: H,
        pixels: tex.texels.iter().map(|t| t.to_array()).collect(),
    };
    let png = image.to_rgba8(8.0);
    let to8 = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    for (flip, mirrored) in [(0.0, false), (1.0, true)] {
        let shown = cpu(&tex, params(flip));
        let mut differing = 0;
        for y in 0..H {
            for x in 0..W {
                let c = shown[(y * W + x) as usize];
                let src_row = if mirrored { H - 1 - y } else { y };
                let want = png.get_pixel(x, src_row).0;
                if [to8(c.x), to8(c.y), to8(c.z), to8(c.w)] != want {
                    differing += 1;
                }
            }
        }
        println!(
            "flip_y {flip}: {differing} of {} pixels differ from the PNG",
            W * H
        );
        assert_eq!(differing, 0, "flip_y {flip}");
    }
}
