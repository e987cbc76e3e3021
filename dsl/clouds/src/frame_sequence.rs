//! The frame sequence: what a host writes into the cloud and resolve blocks for each frame of
//! a temporal sequence (upscaled or accumulated), written once.
//!
//! These are host functions: Nimbus's wgpu runtime calls their CPU twins, and engine packages
//! with a JavaScript host get their JavaScript twins (`nimbus-frame.js`, printed from
//! [`host_module`] by `nimbus_codegen::print_js`), so the two hosts cannot drift apart. Each
//! result struct names its fields after the block members they fill (`CloudUniforms::jitter`,
//! `ResolveParams::variance_gamma`, ...): a host copies a result into its block field by field,
//! with no member path spelled by hand.
//!
//! The sequences are fixed-point (u32 arithmetic that wraps, then the top 24 bits as a
//! fraction), so that every host computes the same bits: an f32 golden-ratio sequence differs
//! between an f32 and an f64 host after a few frames and loses all precision after 2²⁴.

use glam::{Vec2, Vec3, Vec4};
use nimbus_dsl::prelude::*;
use nimbus_dsl::{DslError, ModuleBuilder, host_fn, loc};

/// What the host writes into the cloud block for one frame (members of the same names in
/// [`crate::model::march::CloudUniforms`]).
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct CloudFrame {
    /// Seeds the per-pixel jitter noise.
    pub frame: u32,
    /// Per-frame jitter phase in [0, 1), added to the per-pixel jitter.
    pub jitter: f32,
    /// The pixel of each block the cloud pass shades (a Bayer order upscaled, 0 otherwise).
    pub pixel_offset: Vec2,
    /// The block side: 4 upscaled, 1 at full resolution.
    pub pixel_scale: f32,
    /// Where in its pixel the ray passes ((0.5, 0.5) first).
    pub subpixel: Vec2,
}

/// What the host writes into the resolve block for one frame (members of the same names in
/// [`crate::model::resolve::ResolveParams`]).
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct ResolveFrame {
    /// The cloud pass's target size: the output's divided by the block side, rounded up.
    pub low_resolution: Vec2,
    pub pixel_offset: Vec2,
    pub pixel_scale: f32,
    /// Weight of this frame's sample in the pixels it shades: 1 / (visits + 1).
    pub current_weight: f32,
    /// Width of the history's clipping box in standard deviations: 2 upscaled, 0 for a still
    /// camera over still clouds at full resolution (the history is then the exact running mean
    /// of the same pixels), 4 when either moved.
    pub variance_gamma: f32,
    /// 0 on the first frame: there is no history to read.
    pub history_valid: f32,
    /// How far the wind moved the clouds at the reprojection's altitude since the last frame
    /// (m, local frame).
    pub cloud_shift: Vec3,
}

/// Fixed-point golden ratio, 2³² · 0.6180340: the frame jitter's step.
pub const GOLDEN_STEP: u32 = 2_654_435_769;
/// 2³² · 0.7548777 (1 / the plastic number): the seed's step, and the R2 sequence's x.
pub const PLASTIC_STEP: u32 = 3_242_174_889;
/// 2³² · 0.5698403: the R2 sequence's y.
pub const PLASTIC_SQUARED_STEP: u32 = 2_447_445_414;
/// 2³² · 0.5: the R2 sequence starts at the pixel's centre.
pub const HALF_TURN: u32 = 2_147_483_648;
/// Frames per pass over a 4×4 block when upscaling.
pub const BLOCK_FRAMES: u32 = 16;

/// The top 24 bits of `bits` as a fraction in [0, 1): exact in f32, the same on every host.
#[shader_fn]
pub fn unit_fraction(bits: u32) -> f32 {
    (bits >> 8u32) as f32 * (1.0 / 16_777_216.0)
}

/// The pixel of a 4×4 block that frame `index` shades when upscaling: the Bayer order (0,0),
/// (2,2), (2,0), (0,2), (1,1), ..., so consecutive frames spread over the block and 16 visit
/// every pixel once. Bits 0–1 of the index choose the 2×2 quadrant, bits 2–3 the pixel in it.
#[shader_fn]
pub fn bayer_offset(index: u32) -> Vec2 {
    let coarse = index & 3u32;
    let fine = (index >> 2u32) & 3u32;
    let x = ((coarse ^ (coarse >> 1u32)) & 1u32) * 2u32 + ((fine ^ (fine >> 1u32)) & 1u32);
    let y = (coarse & 1u32) * 2u32 + (fine & 1u32);
    vec2(x as f32, y as f32)
}

/// Sub-pixel position of the `visit`-th sample a pixel gets (0: its centre): the R2 sequence
/// (Roberts 2018), whose successive points cover the square evenly for any count.
#[shader_fn]
pub fn subpixel_offset(visit: u32) -> Vec2 {
    vec2(
        unit_fraction(visit.wrapping_mul(PLASTIC_STEP).wrapping_add(HALF_TURN)),
        unit_fraction(
            visit
                .wrapping_mul(PLASTIC_SQUARED_STEP)
                .wrapping_add(HALF_TURN),
        ),
    )
}

/// How many samples a pixel had before frame `index`: every frame shades every pixel at full
/// resolution; upscaled, one frame in [`BLOCK_FRAMES`] does.
#[shader_fn]
pub fn pixel_visits(index: u32, upscale: u32) -> u32 {
    select(index, index / BLOCK_FRAMES, upscale > 0u32)
}

/// The cloud block's per-frame members for frame `index` (from 0, counted since the history
/// started; always 0 for a frame nothing resolves) of a sequence seeded by `seed`; `upscale`
/// is 1 when the cloud pass shades one pixel in sixteen.
#[shader_fn]
pub fn cloud_frame(index: u32, seed: u32, upscale: u32) -> CloudFrame {
    let upscaled = upscale > 0u32;
    CloudFrame {
        frame: seed.wrapping_mul(7919u32).wrapping_add(index),
        jitter: unit_fraction(
            index
                .wrapping_mul(GOLDEN_STEP)
                .wrapping_add(seed.wrapping_mul(PLASTIC_STEP)),
        ),
        pixel_offset: select(Vec2::ZERO, bayer_offset(index % BLOCK_FRAMES), upscaled),
        pixel_scale: select(1.0, 4.0, upscaled),
        subpixel: subpixel_offset(pixel_visits(index, upscale)),
    }
}

/// Where the clouds at `altitude` are after a drift `drift` (ground drift in x, y; its growth
/// per metre of altitude in z, w: `media.wind_drift` and `media.wind_shear_drift`), in the
/// local frame's x and z.
#[shader_fn]
pub fn drift_at(drift: Vec4, altitude: f32) -> Vec3 {
    vec3(
        drift.x + drift.z * altitude,
        0.0,
        drift.y + drift.w * altitude,
    )
}

/// The resolve block's per-frame members for frame `index` of an output of `resolution`
/// pixels: `camera_moved` is 1 when the view-projection differs from the last frame's; the
/// clouds' drift now and at the last frame ([`drift_at`]'s packing) and the altitude the
/// reprojection follows ([`crate::model::resolve::facing_altitude`]) give the wind's shift.
#[shader_fn]
pub fn resolve_frame(
    index: u32,
    upscale: u32,
    camera_moved: u32,
    drift: Vec4,
    previous_drift: Vec4,
    cloud_altitude: f32,
    resolution: Vec2,
) -> ResolveFrame {
    let upscaled = upscale > 0u32;
    let scale = select(1.0, 4.0, upscaled);
    let change = (drift - previous_drift).abs();
    let clouds_moved = change.x.max(change.y).max(change.z.max(change.w)) > 0.0;
    let moved = (camera_moved > 0u32) | clouds_moved;
    ResolveFrame {
        low_resolution: vec2((resolution.x / scale).ceil(), (resolution.y / scale).ceil()),
        pixel_offset: select(Vec2::ZERO, bayer_offset(index % BLOCK_FRAMES), upscaled),
        pixel_scale: scale,
        current_weight: 1.0 / (pixel_visits(index, upscale) as f32 + 1.0),
        variance_gamma: select(select(0.0, 4.0, moved), 2.0, upscaled),
        history_valid: select(1.0, 0.0, index == 0u32),
        cloud_shift: drift_at(drift, cloud_altitude) - drift_at(previous_drift, cloud_altitude),
    }
}

/// A module holding the frame sequence's host functions, for printing their twins
/// (`nimbus-frame.js` in engine packages with a JavaScript host).
pub fn host_module() -> Result<nimbus_dsl::ir::Module, DslError> {
    ModuleBuilder::build(
        "frame",
        "Host functions: the frame sequence of temporal upscaling and accumulation.",
        loc!(),
        |m| {
            m.host(host_fn!(cloud_frame), loc!());
            m.host(host_fn!(resolve_frame), loc!());
            m.host(host_fn!(drift_at), loc!());
        },
    )
}
