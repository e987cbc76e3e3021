//! Cloud shadows on the engine's own objects.
//!
//! The clouds' shadow on a surface is the sun's light through them to that point: the shadow
//! atlas's optical depth towards the sun, turned into the light a slab of cloud lets through
//! ([`sun_through_clouds`], the same function that shadows Nimbus's own ground). An engine's
//! materials need it per pixel before they are lit, so the `scene_shadow` pass writes it for
//! every pixel of the engine's depth buffer (a perspective camera's): the engine renders its
//! depth, this pass, then its scene with materials that scale their direct sunlight by the
//! pass's output, then the clouds over it. The sky's light is the engine's own and is left as
//! it is.

use glam::{Vec2, Vec3, Vec4};

use nimbus_dsl::ir::Module;
use nimbus_dsl::prelude::*;
use nimbus_dsl::{DslError, ModuleBuilder, loc};

use super::bindings::{CLOUDS, SCENE};
use super::march::{shadow_optical_depth, view_direction};
use super::preview::fullscreen_position;
use super::scene_depth::{NO_SURFACE, surface_distance};
use super::shadow::{altitude_at, shadow_texel};
use super::transmission::{DROPLET_ASYMMETRY, slab_transmittance};

/// How much of the sun's direct light reaches the camera-relative point `p` through the clouds
/// (0..1): the shadow atlas's optical depth from `p` up to the top of the shadow-casting
/// layers, through a slab of droplets (forward scattering lets more through than Beer's law).
#[shader_fn]
pub fn sun_through_clouds(p: Vec3) -> f32 {
    let mu = CLOUDS.get().light.sun_direction.y.max(0.01);
    slab_transmittance(cloud_depth_to_sun(p) * mu, mu, DROPLET_ASYMMETRY)
}

/// Optical depth of the clouds on the sun's path from the camera-relative point `p`, from the
/// shadow atlas (0 above the top of the shadow-casting layers).
#[shader_fn]
pub fn cloud_depth_to_sun(p: Vec3) -> f32 {
    let u = CLOUDS.get();
    let mu = u.light.sun_direction.y.max(0.01);
    let h = altitude_at(p, u.camera_altitude, u.march.radius);
    let below_top = (u.march.shadow_top_height - h).max(0.0) / mu;
    shadow_optical_depth(shadow_texel(p), below_top, 0.0)
}

/// One pixel of the `scene_shadow` pass, one per texel of the engine's depth buffer: red, green
/// and blue the sun's light through the clouds at the engine's surface in the pixel (1 where
/// the engine drew nothing), alpha 1.
#[shader_fn]
pub fn scene_shadow_fragment(frag_coord: Vec4) -> Vec4 {
    let resolution = SCENE.get().resolution;
    // The cloud block's camera is the engine's, at the depth buffer's size: the pixel's centre.
    let scale = CLOUDS.get().resolution / resolution;
    let pixel = (vec2(frag_coord.x, frag_coord.y).floor() + Vec2::splat(0.5)) * scale;
    let direction = view_direction(pixel);
    let distance = surface_distance(direction, direction);
    let through = if distance < NO_SURFACE {
        sun_through_clouds(direction * distance)
    } else {
        1.0
    };
    Vec3::splat(through).extend(1.0)
}

/// Records the `scene_shadow` module (the same for every key that reads the engine's depth).
pub fn scene_shadow_module() -> Result<Module, DslError> {
    ModuleBuilder::build(
        "scene_shadow",
        "The clouds' shadow on the engine's objects: the sun's light through the clouds at the \
         surface in each pixel of the engine's depth buffer.",
        loc!(),
        |m| {
            m.vertex("vs_main", "Full-screen triangle.", loc!(), |vertex_index| {
                fullscreen_position::shader(vertex_index)
            });
            m.fragment(
                "fs_scene_shadow",
                "The sun's light through the clouds at one pixel's surface.",
                loc!(),
                scene_shadow_fragment::shader,
            );
        },
    )
}
