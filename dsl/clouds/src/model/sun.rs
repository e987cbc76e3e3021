//! What the sun's position decides, derived from the rest of the uniform block: the sun's and
//! the sky's irradiance at the camera, and the shadow cascades' transforms. It is the part of
//! the block a host must recompute when the sun (or the camera's height) moves, so it is one
//! `#[shader_fn]`: Nimbus's runtime fills the block with its CPU twin (through
//! [`CloudUniforms::for_genus`]), and an engine package's JavaScript host calls its JavaScript
//! twin ([`nimbus_codegen::print_js`], `nimbus-sun.js` in a three.js package), so the formulas
//! exist once. Hosts without JavaScript (wgpu, Vulkan, Unity, Metal) run it on the GPU
//! instead: [`sun_light_module`] is a one-invocation kernel that completes the block the host
//! filled, so moving the sun needs no host code beyond writing its direction.

use glam::{Mat4, Vec3};

use nimbus_dsl::prelude::*;
use nimbus_dsl::{DslError, ModuleBuilder, loc};

use super::bindings::{CLOUDS, SunLightBinding};
use super::march::CloudUniforms;
use super::shadow::{
    CascadeLookup, anchored_tiles, atlas_columns, atlas_rows, redrawn_tiles, shadow_anchor,
    shadow_matrices,
};
use super::sky::{sky_irradiance_at, sun_irradiance_at};
use super::tile_bands::{band_redraw, tiles_out_of_date};

/// The members of the cloud block that follow the sun.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct SunLight {
    /// `light.sun_direction`: unit vector towards the sun, y up.
    pub sun_direction: Vec3,
    /// `light.sun_irradiance` and `light.sky_irradiance` at the camera.
    pub sun_irradiance: Vec3,
    pub sky_irradiance: Vec3,
    /// `shadow.lookup` (every tile drawn for this sun, around the camera) and
    /// `shadow.inverse_matrix`.
    pub shadow_lookup: CascadeLookup,
    pub shadow_inverse_matrix: Mat4,
}

/// The unit vector towards a sun `elevation_deg` above the horizon and `azimuth_deg` clockwise
/// from north (−z), in the local frame (y up): how scenes give the sun.
#[shader_fn]
pub fn sun_direction(elevation_deg: f32, azimuth_deg: f32) -> Vec3 {
    let el = elevation_deg.to_radians();
    let az = azimuth_deg.to_radians();
    Vec3::new(el.cos() * az.sin(), el.sin(), -el.cos() * az.cos())
}

/// The sun-dependent members of `u` for a sun in `sun_direction` (a unit vector, y up), from
/// its atmosphere, layers, camera height and shadow settings.
#[shader_fn]
pub fn sun_light(u: CloudUniforms, sun_direction: Vec3) -> SunLight {
    let m = u.march;
    // Cascade 0 is the finest: each coarser one is four times its side, the coarsest the
    // preset's maximum ray distance.
    let mut coarsest = 1.0f32;
    for _cascade in 1u32..u.shadow.cascade_count {
        coarsest *= 4.0;
    }
    let mid = 0.5 * (m.min_height.min(m.max_height) + m.max_height);
    let cascades = shadow_matrices(
        sun_direction,
        u.camera_altitude,
        m.shadow_top_height,
        mid,
        m.max_ray_distance / coarsest,
        u.shadow.cascade_scales,
    );
    SunLight {
        sun_direction,
        sun_irradiance: sun_irradiance_at(u.camera_altitude, sun_direction, u.sky, m.radius),
        sky_irradiance: sky_irradiance_at(u.camera_altitude, sun_direction, u.sky, m.radius),
        shadow_lookup: cascades.lookup,
        shadow_inverse_matrix: cascades.inverse_matrix,
    }
}

impl CloudUniforms {
    /// This block with what a sun in `sun_direction` (unit, y up) decides filled in, by the CPU
    /// twin of [`sun_light`]: how Nimbus's runtime fills it, as the `sun_light` pass and
    /// `nimbus-sun.js` do in engine packages.
    pub fn with_sun(mut self, sun_direction: Vec3) -> Self {
        let light = sun_light(self, sun_direction);
        self.light.sun_direction = light.sun_direction;
        self.light.sun_irradiance = light.sun_irradiance;
        self.light.sky_irradiance = light.sky_irradiance;
        self.shadow.lookup = light.shadow_lookup;
        self.shadow.inverse_matrix = light.shadow_inverse_matrix;
        self
    }
}

/// A module holding [`sun_light`], [`sun_direction`] and what they call, for printing their host
/// twins (`nimbus-sun.js`).
pub fn host_module() -> Result<nimbus_dsl::ir::Module, DslError> {
    ModuleBuilder::build(
        "host",
        "Host functions: what the sun's position decides.",
        loc!(),
        |m| {
            m.host(nimbus_dsl::host_fn!(sun_direction), loc!());
            m.host(nimbus_dsl::host_fn!(sun_light), loc!());
            // Cascades in rotation: where each tile lies in the atlas, what a host keeps per
            // tile, and the lookup it writes.
            m.host(nimbus_dsl::host_fn!(atlas_columns), loc!());
            m.host(nimbus_dsl::host_fn!(atlas_rows), loc!());
            m.host(nimbus_dsl::host_fn!(shadow_anchor), loc!());
            m.host(nimbus_dsl::host_fn!(redrawn_tiles), loc!());
            m.host(nimbus_dsl::host_fn!(anchored_tiles), loc!());
            // Each tile in bands: which rows a frame draws, and when a tile is done.
            m.host(nimbus_dsl::host_fn!(tiles_out_of_date), loc!());
            m.host(nimbus_dsl::host_fn!(band_redraw), loc!());
        },
    )
}

/// The `sun_light` kernel: reads the cloud block as the host filled it (any non-zero
/// `light.sun_direction`; the rest as in the pair's uniform file) and writes the whole block,
/// with the direction normalised and what the sun decides filled in, into a storage buffer the
/// host then binds as the shadow and cloud passes' block. One invocation; run it when the sun
/// or the camera's altitude moves.
pub fn sun_light_module() -> Result<nimbus_dsl::ir::Module, DslError> {
    ModuleBuilder::build(
        "sun",
        "What the sun's position decides, derived on the GPU: sun and sky irradiance at the \
         camera and the shadow cascades' transforms, written into the cloud block.",
        loc!(),
        |m| {
            let (group, binding) = SunLightBinding::Block.slot();
            let block = m.storage::<nimbus_dsl::value::U32>(
                "block",
                group,
                binding,
                true,
                "The completed cloud block: bind this buffer as `clouds` in the shadow and \
                 cloud passes.",
            );
            m.compute(
                "cs_sun_light",
                "Completes the cloud block (one invocation).",
                loc!(),
                [1, 1, 1],
                |_| {
                    let u = CLOUDS.read();
                    let out = block.array();
                    // One evaluation, read by every store below.
                    let light = nimbus_dsl::control::bind(
                        "light",
                        loc!(),
                        sun_light::shader(u, u.light.sun_direction.normalize()),
                    );
                    out.write_uniform(0, u);
                    out.write_uniform_member(0, u, u.light.sun_direction, light.sun_direction);
                    out.write_uniform_member(0, u, u.light.sun_irradiance, light.sun_irradiance);
                    out.write_uniform_member(0, u, u.light.sky_irradiance, light.sky_irradiance);
                    out.write_uniform_member(0, u, u.shadow.lookup, light.shadow_lookup);
                    out.write_uniform_member(
                        0,
                        u,
                        u.shadow.inverse_matrix,
                        light.shadow_inverse_matrix,
                    );
                },
            );
        },
    )
}
