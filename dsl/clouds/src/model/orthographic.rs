//! Orthographic cameras: parallel rays, each leaving its own point of the image plane.
//!
//! The march, the composite and everything under them see the world from "the camera": the
//! cloud block's `camera_altitude` and `camera_offset`, with positions relative to it. An
//! orthographic pixel's ray is the same ray a camera standing at that pixel's origin would
//! cast, so the `orthographic` key shades each pixel with [`CLOUDS`] fed a copy of the block
//! whose camera stands there ([`ray_block`]: its altitude, its offset over the noise, and the
//! shadow cascades' transform moved with it), and the rest of the model is unchanged. A key
//! without the toggle carries none of this.

use glam::{Vec2, Vec3, Vec4};

use nimbus_dsl::prelude::*;

use super::bindings::{CLOUDS, CLOUDS_INPUT};
use super::march::{CloudUniforms, shade_ray};
use super::shadow::{ShadowParams, shifted_lookup};
use crate::key::CloudKey;

/// One orthographic pixel's ray: the pixel (its block's corner when upscaled), where the ray
/// leaves the camera's plane (camera-relative, local frame) and its direction.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct OrthographicRay {
    pub cell: Vec2,
    pub origin: Vec3,
    pub direction: Vec3,
}

/// The ray of the pixel under `frag_coord`: two points of it unprojected by the block's
/// inverse view-projection (NDC depth 0 and 1, in front of the camera in OpenGL's and WebGPU's
/// ranges), and its origin where it crosses the plane through the camera across it.
#[shader_fn]
pub fn orthographic_ray(frag_coord: Vec4) -> OrthographicRay {
    let u = CLOUDS_INPUT.get();
    let cell = vec2(frag_coord.x, frag_coord.y).floor() * u.pixel_scale + u.pixel_offset;
    let pixel = cell + u.subpixel;
    let ndc = vec2(
        pixel.x / u.resolution.x * 2.0 - 1.0,
        1.0 - pixel.y / u.resolution.y * 2.0,
    );
    let a = u.inverse_view_projection * vec4(ndc.x, ndc.y, 0.0, 1.0);
    let b = u.inverse_view_projection * vec4(ndc.x, ndc.y, 1.0, 1.0);
    let near = a.xyz() / a.w;
    let far = b.xyz() / b.w;
    let direction = (far - near).normalize();
    OrthographicRay {
        cell,
        origin: near - direction * near.dot(direction),
        direction,
    }
}

/// The block `u` with its camera moved to `origin` (camera-relative, local frame): the
/// altitude (flat: orthographic views are local; held at the ground), the offset over the
/// noise, and the shadow cascades' transform, which takes positions relative to the camera.
#[shader_fn]
pub fn ray_block(u: CloudUniforms, origin: Vec3) -> CloudUniforms {
    let s = u.shadow;
    CloudUniforms {
        groups: u.groups,
        media: u.media,
        march: u.march,
        light: u.light,
        haze: u.haze,
        composite: u.composite,
        camera_altitude: (u.camera_altitude + origin.y).max(0.0),
        camera_offset: u.camera_offset + vec3(origin.x, 0.0, origin.z),
        inverse_view_projection: u.inverse_view_projection,
        shadow: ShadowParams {
            lookup: shifted_lookup(s.lookup, origin),
            inverse_matrix: s.inverse_matrix,
            cascade_scales: s.cascade_scales,
            cascade_count: s.cascade_count,
            map_size: s.map_size,
            max_iterations: s.max_iterations,
            min_step: s.min_step,
            max_step: s.max_step,
            min_extinction: s.min_extinction,
            min_transmittance: s.min_transmittance,
            tail_scale: s.tail_scale,
        },
        sky: u.sky,
        resolution: u.resolution,
        pixel_offset: u.pixel_offset,
        pixel_scale: u.pixel_scale,
        subpixel: u.subpixel,
        frame: u.frame,
        jitter: u.jitter,
    }
}

/// Where the ray being shaded left the camera's plane (camera-relative): the difference
/// between the block as bound and as [`ray_block`] fed it (what the engine's depth buffer is
/// looked up with).
#[shader_fn]
pub fn ray_origin() -> Vec3 {
    let bound = CLOUDS_INPUT.get();
    let shaded = CLOUDS.get();
    vec3(
        shaded.camera_offset.x - bound.camera_offset.x,
        shaded.camera_altitude - bound.camera_altitude,
        shaded.camera_offset.z - bound.camera_offset.z,
    )
}

/// Colour of one orthographic pixel: [`shade_ray`] along its parallel ray, the block's camera
/// standing at the ray's origin. A sample stands for a pixel's width wherever it is, not for an
/// angle: the detail's level of detail is left at its finest.
///
/// A twin pair written by hand, as `gate` is: the shader twin feeds [`CLOUDS`] (a private copy
/// from here on) and the CPU twin binds it for the call, which no `#[shader_fn]` body can say.
pub fn orthographic_fragment(frag_coord: Vec4, key: CloudKey) -> Vec4 {
    let ray = orthographic_ray(frag_coord);
    let block = ray_block(*CLOUDS_INPUT.get(), ray.origin);
    let _shaded = nimbus_dsl::CpuBindings::new().set(&CLOUDS, block).bind();
    shade_ray(ray.cell, ray.direction, 0.0, key)
}

#[doc(hidden)]
pub use orthographic_fragment::shader as __shader_twin_orthographic_fragment;

/// Shader twin of [`orthographic_fragment()`](fn@orthographic_fragment).
pub mod orthographic_fragment {
    use super::*;
    use nimbus_dsl::shader::Vec4 as Vec4Shader;

    pub fn shader(frag_coord: impl Into<Vec4Shader>, key: CloudKey) -> Vec4Shader {
        let ray = orthographic_ray::shader(frag_coord);
        CLOUDS.feed(ray_block::shader(CLOUDS_INPUT.read(), ray.origin));
        shade_ray::shader(ray.cell, ray.direction, 0.0f32, key)
    }
}
