//! The engine's own scene: its opaque surfaces, read from the engine's depth buffer.
//!
//! With the `scene-depth` toggle the march stops where the engine drew something opaque, and
//! the pass's output becomes premultiplied over the engine's picture: colour is what Nimbus adds
//! in front of the engine's pixel (clouds, the air's light, haze), alpha how much of the
//! engine's pixel it hides. Where the engine drew nothing Nimbus draws its sky and ground as
//! before (alpha 1), or nothing at all when the composite's sky is switched off (clouds only,
//! over the engine's own background).
//!
//! The depth buffer is decoded with the engine camera's own projection, so standard,
//! reversed-Z and logarithmic buffers (three.js's `logarithmicDepthBuffer`) need no
//! conversion pass: [`SceneDepthParams`] holds the projection's z row and the encoding.

use glam::{Mat4, Vec2, Vec3, Vec4, ivec2};

use nimbus_dsl::prelude::*;

use super::air_shadow::{air_sunlit, near_air_sunlit};
use super::air_table::air_along;
use super::bindings::{CLOUDS, SCENE, SCENE_DEPTH};
use super::choices::{HAZE, ORTHOGRAPHIC, gate};
use super::march::{MarchResult, clouds_through_air, composite, haze_light, haze_opacity};
use super::orthographic::ray_origin;
use crate::key::CloudKey;

/// Distance (m) standing for "no surface": the engine drew nothing in the pixel.
pub const NO_SURFACE: f32 = 1e30;

/// How the engine's depth buffer encodes distance, and the camera it was drawn with.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct SceneDepthParams {
    /// The engine camera's view-projection without its translation: projects a view
    /// direction onto the depth texel under it.
    pub view_projection: Mat4,
    /// The camera's forward direction (local frame): depth is measured along it.
    pub forward: Vec3,
    /// 0: a projection's depth (perspective, reversed-Z); 1: logarithmic, `log2(1 + w) /
    /// log2(far + 1)` (three.js's `logarithmicDepthBuffer`).
    pub encoding: u32,
    /// The projection's z and w rows in view z: clip.z = x·z + y, clip.w = z·z + w (a
    /// perspective camera: (P22, P32, −1, 0); columns 2 and 3 of the projection's third and
    /// fourth rows).
    pub projection_zw: Vec4,
    /// Normalised device z from a depth texel: ndc = depth · scale + offset (OpenGL and WebGL:
    /// 2, −1; WebGPU, Vulkan, D3D and Metal: 1, 0).
    pub depth_scale: f32,
    pub depth_offset: f32,
    /// `log2(far + 1)`, the logarithmic encoding's range.
    pub log_range: f32,
    /// What the depth buffer holds where nothing was drawn (1, or 0 reversed).
    pub clear_depth: f32,
    /// The depth texture's size in pixels.
    pub resolution: Vec2,
    /// 1 when the depth texture's first row is the bottom one (OpenGL, WebGL).
    pub flip_y: f32,
}

impl SceneDepthParams {
    /// A camera's depth in an OpenGL-style buffer (depth 0 at the near plane, 1 at the far one;
    /// NDC z in [−1, 1]) of `width` × `height` texels, first row at the top, drawn with
    /// `projection` (perspective or orthographic) and the view `view_projection` (without
    /// translation), looking along `forward`.
    pub fn opengl(
        projection: Mat4,
        view_projection: Mat4,
        forward: Vec3,
        width: u32,
        height: u32,
    ) -> Self {
        SceneDepthParams {
            view_projection,
            forward,
            encoding: 0,
            projection_zw: projection_zw(projection),
            depth_scale: 2.0,
            depth_offset: -1.0,
            log_range: 0.0,
            clear_depth: 1.0,
            resolution: Vec2::new(width as f32, height as f32),
            flip_y: 0.0,
        }
    }
}

/// (P22, P32, P23, P33) in glam's column-major naming: how clip z and w follow view z.
pub fn projection_zw(projection: Mat4) -> Vec4 {
    Vec4::new(
        projection.z_axis.z,
        projection.w_axis.z,
        projection.z_axis.w,
        projection.w_axis.w,
    )
}

/// Distance along the forward axis (m) of a depth texel `depth`, or [`NO_SURFACE`] where the
/// engine drew nothing.
#[shader_fn]
pub fn forward_distance(depth: f32) -> f32 {
    let s = SCENE.get();
    // A projection's depth: ndc = (x·z + y) / (z·z + w), solved for the view z (negative in
    // front of a right-handed camera).
    let ndc = depth * s.depth_scale + s.depth_offset;
    let p = s.projection_zw;
    let view_z = (p.y - ndc * p.w) / (ndc * p.z - p.x);
    let projected = -view_z;
    // Logarithmic: depth = log2(1 + w) / log2(far + 1), w the forward distance.
    let logarithmic = (depth * s.log_range).exp2() - 1.0;
    let distance = select(projected, logarithmic, s.encoding == 1u32);
    select(distance, NO_SURFACE, depth == s.clear_depth)
}

/// Distance (m) along the unit view ray `direction` (local frame) to the engine's opaque
/// surface in its pixel, or [`NO_SURFACE`]; the distance is the forward distance's along the
/// ray from the camera's plane, which an orthographic ray leaves from.
#[shader_fn]
pub fn scene_distance(direction: Vec3, #[spec] key: CloudKey) -> f32 {
    // A point of the ray projects onto its pixel: one metre along it, from the camera or, with
    // an orthographic camera, from the ray's own origin.
    let point = if gate(key, ORTHOGRAPHIC) {
        ray_origin() + direction
    } else {
        direction
    };
    surface_distance(point, direction)
}

/// Distance (m) along the unit ray `direction` through the camera-relative `point` to the
/// engine's opaque surface in the pixel `point` projects onto, or [`NO_SURFACE`]: measured as
/// the forward distance's along the ray from the camera's plane.
#[shader_fn]
pub fn surface_distance(point: Vec3, direction: Vec3) -> f32 {
    let s = SCENE.get();
    let clip = s.view_projection * point.extend(1.0);
    let ndc = vec2(clip.x, clip.y) / clip.w;
    let top_down = vec2(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    // The texel under the point, loaded as it is: an engine's depth texture is unfilterable
    // (a WebGPU `depth32float` binds as `unfilterable-float`), and depths must not be blended.
    let cell = (top_down * s.resolution)
        .floor()
        .clamp(Vec2::ZERO, s.resolution - Vec2::ONE);
    let row = cell.y + (s.resolution.y - 1.0 - 2.0 * cell.y) * s.flip_y;
    let depth = SCENE_DEPTH
        .get()
        .load(ivec2(cell.x as i32, row as i32), 0)
        .x;
    // The marker is kept as it is: divided by a cosine a hair over 1 it would read as a surface.
    let forward = forward_distance(depth);
    let along = select(
        forward / direction.dot(s.forward).max(1e-6),
        NO_SURFACE,
        forward >= NO_SURFACE,
    );
    // Behind the camera, or outside the depth texture: nothing of the engine's there.
    let outside = clip.w <= 0.0
        || top_down.x < 0.0
        || top_down.x > 1.0
        || top_down.y < 0.0
        || top_down.y > 1.0;
    select(along, NO_SURFACE, outside)
}

/// What Nimbus puts in front of the engine's pixel along `direction`, premultiplied: colour is
/// the light it adds (clouds, the air's glow in front of the engine's surface, haze), alpha
/// how much of the engine's pixel it hides. Where the engine drew nothing and the composite's
/// sky is on, Nimbus's own sky and ground are the background: the full composite, opaque.
#[shader_fn]
pub fn composite_over_scene(
    direction: Vec3,
    jitter: f32,
    clouds: MarchResult,
    #[spec] key: CloudKey,
) -> Vec4 {
    let u = CLOUDS.get();
    let switches = u.composite;
    let surface = scene_distance(direction, key);
    let has_surface = surface < NO_SURFACE;
    if !has_surface && switches.sky > 0.0 {
        return composite(direction, jitter, clouds, key)
            .truncate()
            .extend(1.0);
    }
    let air_weight = switches.aerial_perspective;
    // The air in front ends at the clouds' front, else at the engine's surface, else at the
    // march's reach; so does the haze. The sun's share of it is read once for both
    // (`composite`).
    let open = select(u.march.max_ray_distance, surface, has_surface);
    let near = select(open, clouds.front_depth, clouds.front_depth > 0.0);
    let sunlit = near_air_sunlit(
        direction,
        near,
        clouds.front_depth > 0.0 || has_surface,
        jitter,
        key,
    );
    // The engine's pixel shows through the clouds and, in front of its surface, the air.
    let mut color = Vec3::ZERO;
    let mut through = clouds.transmittance;
    if has_surface {
        let air = air_along(direction, surface, key);
        let mut surface_sunlit = sunlit;
        if clouds.front_depth > 0.0 {
            surface_sunlit = air_sunlit(direction, surface, jitter, key);
        }
        color = air.inscatter * (clouds.transmittance * air_weight * surface_sunlit);
        through *= 1.0 + (air.transmittance.dot(Vec3::splat(1.0 / 3.0)) - 1.0) * air_weight;
    }
    if clouds.front_depth > 0.0 {
        // Aerial perspective on the clouds, as over Nimbus's own sky.
        color += clouds_through_air(direction, clouds, air_weight, sunlit, key);
    }
    if gate(key, HAZE) {
        let opacity = haze_opacity(direction.y, near);
        color = color + (haze_light(direction, near, jitter, sunlit, key) - color) * opacity;
        through *= 1.0 - opacity;
    }
    color.extend(1.0 - through)
}
