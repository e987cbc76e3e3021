//! Temporal resolve: turns the cloud pass's output into the full image, frame after frame.
//!
//! Upscaled, the cloud pass shades one pixel of every 4×4 block per frame (a Bayer order of
//! offsets, so 16 frames visit every pixel); the other fifteen come from the history,
//! reprojected and clipped to the box of the current neighbourhood (mean ± γσ, Salvi 2016) so
//! stale colours cannot linger, unless the block's one shaded pixel finds the history it lands
//! on still good: a box of samples a block apart misses what is thinner than a block. At full
//! resolution every pixel is current and the history is an accumulation of jittered frames.
//!
//! Reprojection finds where what a pixel sees was a frame ago. The camera's turn moves every
//! direction; the wind moves the clouds: a pixel's ray meets the clouds at their
//! slab's face towards the camera (the bases seen from below: [`facing_altitude`]), and the cloud
//! there was `cloud_shift` upwind a frame ago, so the history is read where that point was seen. Rays that miss the slab (the ground, the sky beyond) are reprojected as
//! distant directions. The parallax of a moving camera, and the depth of the clouds about their
//! middle, are left to the clipping.

use glam::{Mat4, Vec2, Vec3, Vec4, ivec2};

use nimbus_dsl::prelude::*;

use super::bindings::{CURRENT, HISTORY, LINEAR_CLAMP, NEAREST_CLAMP, RESOLVE};
use super::shell::ray_shell;

/// Uniforms of the resolve pass.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct ResolveParams {
    /// This frame's clip space to a local-frame direction, and the previous frame's
    /// view-projection (both without translation).
    pub inverse_view_projection: Mat4,
    pub previous_view_projection: Mat4,
    /// How far the wind carried the clouds since the previous frame (m, local frame, at
    /// `cloud_altitude`); zero for still clouds.
    pub cloud_shift: Vec3,
    /// Altitude where a pixel's ray meets the clouds ([`facing_altitude`]), the camera's, and
    /// the planet's radius.
    pub cloud_altitude: f32,
    pub camera_altitude: f32,
    pub planet_radius: f32,
    /// Full output size, and the size of the cloud pass's target.
    pub resolution: Vec2,
    pub low_resolution: Vec2,
    /// Pixel of each block shaded this frame, and the block side (4 upscaled, 1 otherwise).
    pub pixel_offset: Vec2,
    pub pixel_scale: f32,
    /// Weight of the current sample where there is one (1 replaces the history).
    pub current_weight: f32,
    /// Width of the clipping box in standard deviations; 0 turns clipping off (a still camera
    /// at full resolution, whose history is the exact running mean of the same pixels, which
    /// clipping to one frame's neighbourhood could only bias).
    pub variance_gamma: f32,
    /// 0 on the first frame: there is no history to read.
    pub history_valid: f32,
}

/// One pixel of the resolved image.
#[shader_fn]
pub fn resolve_fragment(frag_coord: Vec4) -> Vec4 {
    let r = RESOLVE.get();
    let current_tex = CURRENT.get();
    let nearest = NEAREST_CLAMP.get();
    let pixel = vec2(frag_coord.x, frag_coord.y).floor();
    let block = (pixel / r.pixel_scale).floor();
    let texel = Vec2::ONE / r.low_resolution;
    let current = current_tex.sample_level(&nearest, (block + Vec2::splat(0.5)) * texel, 0.0);
    // Mean and spread of the current samples around this block: nine texels read as they are
    // (`load`; the sampler would clamp to the edge, so the indices are clamped), the loop
    // unrolled (SwiftShader ran it as a loop 8 ms slower in a 640 × 360 frame).
    let last = r.low_resolution - Vec2::ONE;
    let mut sum = Vec4::ZERO;
    let mut sum_sq = Vec4::ZERO;
    for dy in unroll(-1i32..2i32) {
        for dx in unroll(-1i32..2i32) {
            let at = (block + vec2(dx as f32, dy as f32)).clamp(Vec2::ZERO, last);
            let c = current_tex.load(ivec2(at.x as i32, at.y as i32), 0);
            sum += c;
            sum_sq += c * c;
        }
    }
    let mean = sum / 9.0;
    let sigma = (sum_sq / 9.0 - mean * mean).max(Vec4::ZERO).powf(0.5);
    let within = pixel - block * r.pixel_scale - r.pixel_offset;
    let is_current = within.x.abs() + within.y.abs() < 0.5;
    if r.history_valid < 0.5 {
        return current;
    }
    let reprojected = history_uv(pixel);
    if reprojected.z < 0.5 {
        return current;
    }
    let history = HISTORY
        .get()
        .sample_level(&LINEAR_CLAMP.get(), reprojected.xy(), 0.0);
    let mut clipped = history;
    if r.variance_gamma > 0.0 {
        let half = sigma * r.variance_gamma;
        clipped = history.clamp(mean - half, mean + half);
        if !is_current {
            // Nine samples a block apart miss what is thinner than a block (the horizon's
            // line, far clouds' edges): the box clipped it every frame, and 16 upscaled frames
            // of a still view came 0.82 similar to the converged picture where one
            // full-resolution frame comes 0.94. So the block's own shaded pixel says whether the
            // history here still holds: where this frame's sample lies within the box's
            // half-width of the history it lands on (the tolerance the clip itself allows), the
            // history is kept as it is; from twice that, clipped; between, blended.
            let shaded = block * r.pixel_scale + r.pixel_offset;
            let there = history_uv(shaded);
            let before = HISTORY
                .get()
                .sample_level(&LINEAR_CLAMP.get(), there.xy(), 0.0);
            let change = (current - before).abs() / half.max(Vec4::splat(1e-6));
            let worst = change.x.max(change.y).max(change.z.max(change.w));
            let kept = select(0.0, 1.0 - (worst - 1.0).saturate(), there.z > 0.5);
            clipped += (history - clipped) * kept;
        }
    }
    if is_current {
        return clipped + (current - clipped) * r.current_weight;
    }
    clipped
}

/// Where the history holds what the full-resolution `pixel` (its corner) shows this frame:
/// its texture coordinates in x and y, and in z 1 when that lies on the screen (0 otherwise).
#[shader_fn]
pub fn history_uv(pixel: Vec2) -> Vec3 {
    let r = RESOLVE.get();
    let ndc = vec2(
        (pixel.x + 0.5) / r.resolution.x * 2.0 - 1.0,
        1.0 - (pixel.y + 0.5) / r.resolution.y * 2.0,
    );
    let far = r.inverse_view_projection * vec4(ndc.x, ndc.y, 1.0, 1.0);
    let direction = (far.xyz() / far.w).normalize();
    let point = previous_point(
        direction,
        r.cloud_shift,
        r.cloud_altitude,
        r.camera_altitude,
        r.planet_radius,
    );
    let previous = r.previous_view_projection * point.extend(1.0);
    let previous_ndc = vec2(previous.x, previous.y) / previous.w;
    let uv = vec2(previous_ndc.x * 0.5 + 0.5, 0.5 - previous_ndc.y * 0.5);
    let on_screen = previous.w > 0.0 && uv.x >= 0.0 && uv.x <= 1.0 && uv.y >= 0.0 && uv.y <= 1.0;
    uv.extend(select(0.0, 1.0, on_screen))
}

/// The altitude where a view ray first meets a cloud slab from `bottom` to `top` (m): its base
/// for a camera below (what the bases show), its top for one above, its middle from inside. The
/// reprojection moves what is seen there with the wind; measured against the middle, the base
/// left a seventh of the ghost pixels under a cumulus field (`tests/temporal.rs`).
#[shader_fn]
pub fn facing_altitude(camera_altitude: f32, bottom: f32, top: f32) -> f32 {
    select(
        select(0.5 * (bottom + top), top, camera_altitude >= top),
        bottom,
        camera_altitude <= bottom,
    )
}

/// Where the clouds a pixel's ray (`direction`) meets at `cloud_altitude` were before the wind
/// moved them by `shift`, camera-relative (m); the direction itself where the ray misses that
/// altitude or nothing moved (a point at any distance along it projects the same).
#[shader_fn]
pub fn previous_point(
    direction: Vec3,
    shift: Vec3,
    cloud_altitude: f32,
    camera_altitude: f32,
    radius: f32,
) -> Vec3 {
    let roots = ray_shell(camera_altitude, direction.y, cloud_altitude, radius);
    let distance = select(roots.y, roots.x, roots.x > 0.0);
    let moved = shift.dot(shift) > 0.0 && distance > 0.0;
    select(direction, direction * distance - shift, moved)
}
