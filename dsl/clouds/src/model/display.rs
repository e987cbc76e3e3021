//! The display transform as a pass: the HDR image the cloud or resolve pass wrote, tonemapped
//! to display sRGB by the same [`tonemap`] that `nimbus render` applies on the CPU when it
//! writes a PNG. An engine that draws Nimbus's passes ends its frame with this one (or with its
//! own tone mapping, reading the HDR target directly).

use glam::{Vec2, Vec4};

use nimbus_dsl::prelude::*;

use super::bindings::{DISPLAY, DISPLAY_SAMPLER, DISPLAY_SOURCE};
use super::tonemap::tonemap;

/// Uniforms of the display pass.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct DisplayParams {
    /// Size of the source image in pixels (the output has the same size).
    pub resolution: Vec2,
    /// Linear radiance is multiplied by this before the tone curve.
    pub exposure: f32,
    /// 1 to keep the source's alpha (cloud opacity), 0 for an opaque image.
    pub keep_alpha: f32,
    /// 1 where the framebuffer's first row is the bottom one (OpenGL, WebGL, three.js): every
    /// pass works top-down, as WGSL's `position` does, and this last one turns the image
    /// upright. 0 for WebGPU, Vulkan, D3D and Metal.
    pub flip_y: f32,
}

impl Default for DisplayParams {
    fn default() -> Self {
        DisplayParams {
            resolution: Vec2::new(640.0, 360.0),
            exposure: 8.0,
            keep_alpha: 0.0,
            flip_y: 0.0,
        }
    }
}

/// One displayed pixel: the source texel under it, tonemapped.
#[shader_fn]
pub fn display_fragment(frag_coord: Vec4) -> Vec4 {
    let params = DISPLAY.get();
    let pixel = vec2(frag_coord.x, frag_coord.y).floor();
    let row = pixel.y + (params.resolution.y - 1.0 - 2.0 * pixel.y) * params.flip_y;
    let uv = (vec2(pixel.x, row) + Vec2::splat(0.5)) / params.resolution;
    let hdr = DISPLAY_SOURCE
        .get()
        .sample_level(&DISPLAY_SAMPLER.get(), uv, 0.0);
    let alpha = 1.0 + (hdr.w - 1.0) * params.keep_alpha;
    tonemap(hdr.truncate(), params.exposure).extend(alpha)
}
