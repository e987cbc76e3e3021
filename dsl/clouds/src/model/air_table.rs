//! The air table: the sky-view and aerial-perspective tables of Hillaire ("A Scalable and
//! Production Ready Sky and Atmosphere Rendering Technique", 2020) in one texture, filled by a
//! pass of its own when the sun or the camera's altitude changes, and read by the composite in
//! place of the two twelve-sample integrals ([`super::sky::air_integrals`]) each pixel made:
//! one along the whole ray for the sky behind the clouds, one to the clouds' front for the air
//! in front of them. Those integrals were a third of `low`'s frame in the browser benchmark.
//!
//! A texel holds the phase-free integrals ([`AirIntegrals`]) for one direction and one
//! distance along it: the phases are applied per pixel, exactly, so the table holds only what
//! varies slowly with direction (the Mie aureole round the sun, a few degrees wide, is not in
//! it). The air's light depends on a direction only through its elevation and its angle to
//! the sun's vertical plane (0 to π, symmetric either side), so a table is valid for every
//! camera heading: turning the camera redraws nothing.
//!
//! Layout: [`AIR_DISTANCES`] slices side by side, each [`AIR_AZIMUTHS`] wide; three bands one
//! above the other, each [`AIR_ELEVATIONS`] high, for the Rayleigh integral, the Mie integral
//! and the optical depth. Elevations crowd towards the horizon (`α ∝ f²` from it, as Hillaire's
//! sky-view table) and split there: the lower half holds rays that meet the ground, the upper
//! half rays that reach the top of the atmosphere, and a lookup never blends across, so the
//! horizon stays sharp. Distances run over `(k / (n − 1))²` of the ray's path through the air (to
//! the ground, or the top of the atmosphere), the last slice the sky behind everything.

use std::sync::{Arc, Mutex};

use glam::{Vec3, Vec4};

use nimbus_dsl::CpuBindings;
use nimbus_dsl::cpu::Texture2d;
use nimbus_dsl::prelude::*;

use super::bindings::{AIR_TABLE, CLOUDS, LINEAR_REPEAT};
use super::choices::{ACCURATE_AIR_LIGHT, ORTHOGRAPHIC, gate};
use super::march::CloudUniforms;
use super::shell::{ground_hit, ray_shell};
use super::sky::{
    AirIntegrals, AirLight, air_integrals, air_light, phased_air_light, sky_distance,
};
use crate::key::CloudKey;

/// Directions across the angle to the sun's vertical plane, 0 to π.
pub const AIR_AZIMUTHS: u32 = 16;
/// Directions in elevation, half below the horizon and half above.
pub const AIR_ELEVATIONS: u32 = 128;
/// Distances along each direction, from the camera to the end of the ray.
pub const AIR_DISTANCES: u32 = 16;
/// Bands: the Rayleigh integral, the Mie integral, the optical depth.
pub const AIR_BANDS: u32 = 3;

/// The table's width and height in texels.
pub fn air_table_size() -> (u32, u32) {
    (AIR_AZIMUTHS * AIR_DISTANCES, AIR_ELEVATIONS * AIR_BANDS)
}

const PI: f32 = core::f32::consts::PI;
const HALF_PI: f32 = core::f32::consts::FRAC_PI_2;

/// Elevation (rad) of the geometric horizon seen from `camera_altitude`: `−atan(√(h(2R + h)) / R)`,
/// written without `acos(R / (R + h))`, which loses every digit for a camera near the ground.
#[shader_fn]
pub fn horizon_elevation(camera_altitude: f32, radius: f32) -> f32 {
    let h = camera_altitude.max(0.0);
    -((h * (2.0 * radius + h)).sqrt() / radius).atan()
}

/// The highest elevation (rad) whose ray meets the air: the zenith, or from above the top of
/// the atmosphere (a camera in orbit) the ray that grazes that top. Above it the table's upper
/// half would spend its rows on rays through vacuum; with them spent below it, the limb, a few
/// degrees wide seen from orbit, gets every row.
#[shader_fn]
pub fn air_zenith(camera_altitude: f32, top_height: f32, radius: f32) -> f32 {
    let outer = radius + camera_altitude.max(0.0);
    let top = radius + top_height;
    let grazing = -((outer * outer - top * top).max(0.0).sqrt() / top).atan();
    select(HALF_PI, grazing, camera_altitude > top_height)
}

/// The table row (in texels from the band's first, texel centres at `i + 0.5`) of a direction
/// at `elevation` (rad): rows `[0, n/2)` below the horizon for rays that meet the ground, rows
/// `[n/2, n)` above it up to `zenith` ([`air_zenith`]), `α ∝ f²` from the horizon within each
/// half, so rows crowd where the light changes fastest.
#[shader_fn]
pub fn air_row(elevation: f32, horizon: f32, zenith: f32, meets_ground: bool) -> f32 {
    let half = (AIR_ELEVATIONS / 2u32) as f32;
    let above = ((elevation - horizon).max(0.0) / (zenith - horizon).max(1e-6))
        .min(1.0)
        .sqrt();
    let below = ((horizon - elevation).max(0.0) / (HALF_PI + horizon))
        .min(1.0)
        .sqrt();
    select(
        half + 0.5 + above * (half - 1.0),
        half - 0.5 - below * (half - 1.0),
        meets_ground,
    )
}

/// The elevation (rad) of table row `row` (its index, 0 at the bottom): the inverse of
/// [`air_row`] at texel centres.
#[shader_fn]
pub fn row_elevation(row: f32, horizon: f32, zenith: f32) -> f32 {
    let half = (AIR_ELEVATIONS / 2u32) as f32;
    let above = (row - half) / (half - 1.0);
    let below = (half - 1.0 - row) / (half - 1.0);
    select(
        horizon + above * above * (zenith - horizon),
        horizon - below * below * (HALF_PI + horizon),
        row < half,
    )
}

/// Where a ray from the camera at `elevation` ends: the ground for the table's lower half (at
/// its grazing row, where the ground recedes to the tangent point, that point), the top of the
/// atmosphere for the upper half.
#[shader_fn]
pub fn air_ray_length(mu: f32, lower_half: bool) -> f32 {
    let u = CLOUDS.get();
    let h = u.camera_altitude.max(0.0);
    let radius = u.march.radius;
    let tangent = (h * (2.0 * radius + h)).sqrt();
    let ground = ground_hit(h, mu, radius);
    let sky = sky_distance(h, mu, u.sky.top_height, radius).abs();
    select(sky, select(tangent, ground, ground >= 0.0), lower_half)
}

/// Where a ray from the camera enters the air: 0 inside the atmosphere; from above it (a
/// camera in orbit) where the ray meets its top (the slices are spent on the air, not on the
/// vacuum before it).
#[shader_fn]
pub fn air_ray_entry(mu: f32) -> f32 {
    let u = CLOUDS.get();
    let top = ray_shell(u.camera_altitude, mu, u.sky.top_height, u.march.radius);
    select(0.0, top.x.max(0.0), u.camera_altitude > u.sky.top_height)
}

/// One texel of the air table (its pass draws every texel once per sun or altitude change).
#[shader_fn]
pub fn air_table_fragment(frag_coord: Vec4) -> Vec4 {
    let u = CLOUDS.get();
    let texel = vec2(frag_coord.x, frag_coord.y).floor();
    let slice = (texel.x / AIR_AZIMUTHS as f32).floor();
    let azimuth = (texel.x - slice * AIR_AZIMUTHS as f32) / (AIR_AZIMUTHS - 1u32) as f32 * PI;
    let band = (texel.y / AIR_ELEVATIONS as f32).floor();
    let row = texel.y - band * AIR_ELEVATIONS as f32;
    let horizon = horizon_elevation(u.camera_altitude, u.march.radius);
    let zenith = air_zenith(u.camera_altitude, u.sky.top_height, u.march.radius);
    let elevation = row_elevation(row, horizon, zenith);
    // The sun in the vertical plane x-y; the direction `azimuth` round from it.
    let sun = u.light.sun_direction;
    let sun_across = (1.0 - sun.y * sun.y).max(0.0).sqrt();
    let across = elevation.cos();
    let direction = vec3(
        across * azimuth.cos(),
        elevation.sin(),
        across * azimuth.sin(),
    );
    let lower_half = row < (AIR_ELEVATIONS / 2u32) as f32;
    let length = air_ray_length(direction.y, lower_half);
    let entry = air_ray_entry(direction.y).min(length);
    let fraction = slice / (AIR_DISTANCES - 1u32) as f32;
    let air = air_integrals(
        u.camera_altitude,
        direction,
        vec3(sun_across, sun.y, 0.0),
        entry + (length - entry) * fraction * fraction,
        u.sky,
        u.march.radius,
        // The optical-depth band (the top third) needs no sunlight.
        band < 1.5,
    );
    let value = select(
        air.optical_depth,
        select(air.mie, air.rayleigh, band < 0.5),
        band < 1.5,
    );
    value.extend(1.0)
}

/// The table's value in band `band` at direction column `column` and row `row` (texel-centre
/// coordinates within a slice), slice `slice`: bilinear within the slice, never across.
#[shader_fn]
pub fn air_table_texel(band: f32, slice: f32, column: f32, row: f32) -> Vec3 {
    let width = (AIR_AZIMUTHS * AIR_DISTANCES) as f32;
    let height = (AIR_ELEVATIONS * AIR_BANDS) as f32;
    let uv = vec2(
        (slice * AIR_AZIMUTHS as f32 + column) / width,
        (band * AIR_ELEVATIONS as f32 + row) / height,
    );
    AIR_TABLE
        .get()
        .sample_level(&LINEAR_REPEAT.get(), uv, 0.0)
        .xyz()
}

/// The air's light along unit `direction` over its first `distance` metres, read from the air
/// table: the same as [`super::sky::air_light`] at the table's directions and distances,
/// interpolated between them. `meets_ground` says which half of the table holds the ray (the
/// caller's own ground test, so the sky and the ground never blend at the horizon).
#[shader_fn]
pub fn air_from_table(direction: Vec3, distance: f32, meets_ground: bool) -> AirLight {
    let u = CLOUDS.get();
    let sun = u.light.sun_direction;
    let horizon = horizon_elevation(u.camera_altitude, u.march.radius);
    let zenith = air_zenith(u.camera_altitude, u.sky.top_height, u.march.radius);
    let elevation = direction.y.clamp(-1.0, 1.0).asin();
    let row = air_row(elevation, horizon, zenith, meets_ground);
    // The angle between the ray's and the sun's vertical planes (0 when either is vertical,
    // where every angle reads the same).
    let flat = vec2(direction.x, direction.z);
    let sun_flat = vec2(sun.x, sun.z);
    let norms = (flat.dot(flat) * sun_flat.dot(sun_flat)).sqrt();
    let cos_azimuth = select(1.0, flat.dot(sun_flat) / norms.max(1e-30), norms > 1e-12);
    let azimuth = cos_azimuth.clamp(-1.0, 1.0).acos();
    let column = 0.5 + azimuth / PI * (AIR_AZIMUTHS - 1u32) as f32;
    let length = air_ray_length(direction.y, meets_ground);
    let entry = air_ray_entry(direction.y).min(length);
    let span = (length - entry).max(1e-3);
    let last = (AIR_DISTANCES - 1u32) as f32;
    let w = (((distance - entry) / span).saturate().sqrt() * last).min(last);
    let near = w.floor().min(last - 1.0);
    // Linear in distance between the two slices, not in the slices' square-root spacing: the
    // air's light grows in proportion to a short distance, and 2 m of air read from slices 0
    // and 5 km (a horizontal ray's first) as √ of the way held a thousand times its light.
    let d_near = entry + span * (near / last) * (near / last);
    let d_far = entry + span * ((near + 1.0) / last) * ((near + 1.0) / last);
    let f = ((distance - d_near) / (d_far - d_near).max(1e-6)).saturate();
    // Between two slices the optical depth is linear in distance (exact where the air along
    // the stretch is of one density), and each integral is its slice's share of the light the
    // air scatters, `I / (1 − e^(−τ))` (constant in air of one density, a slowly moving mean in
    // real air), times `1 − e^(−τ)` at the distance: linear in the integrals themselves, they
    // read up to 10 % low 2 km towards the sun, where the haze thins fast with height, and 7 %
    // low 11 km along the horizon, where the light saturates between slices 5 and 20 km out.
    // Six reads: each band at the two slices.
    let rayleigh_near = air_table_texel(0.0, near, column, row);
    let rayleigh_far = air_table_texel(0.0, near + 1.0, column, row);
    let mie_near = air_table_texel(1.0, near, column, row);
    let mie_far = air_table_texel(1.0, near + 1.0, column, row);
    let tau_near = air_table_texel(2.0, near, column, row);
    let tau_far = air_table_texel(2.0, near + 1.0, column, row);
    let tau = tau_near + (tau_far - tau_near) * f;
    let scattered_near = (Vec3::ONE - (-tau_near).exp()).max(Vec3::splat(1e-12));
    let scattered_far = (Vec3::ONE - (-tau_far).exp()).max(Vec3::splat(1e-12));
    // The first slice is the camera (nothing scattered yet): its share is the next one's.
    let at_camera = near < 0.5;
    let rayleigh_share_far = rayleigh_far / scattered_far;
    let mie_share_far = mie_far / scattered_far;
    let rayleigh_share_near = select(
        rayleigh_near / scattered_near,
        rayleigh_share_far,
        at_camera,
    );
    let mie_share_near = select(mie_near / scattered_near, mie_share_far, at_camera);
    let scattered = Vec3::ONE - (-tau).exp();
    let integrals = AirIntegrals {
        rayleigh: (rayleigh_share_near + (rayleigh_share_far - rayleigh_share_near) * f)
            * scattered,
        mie: (mie_share_near + (mie_share_far - mie_share_near) * f) * scattered,
        optical_depth: tau,
    };
    phased_air_light(integrals, direction.dot(sun), u.sky)
}

/// The air's light along unit `direction` over its first `distance` metres, integrated along
/// the ray from the camera ([`air_light`]).
#[shader_fn]
pub fn integrated_air(direction: Vec3, distance: f32) -> AirLight {
    let u = CLOUDS.get();
    air_light(
        u.camera_altitude,
        direction,
        u.light.sun_direction,
        distance,
        u.sky,
        u.march.radius,
    )
}

/// The air's light along unit `direction` over its first `distance` metres as the key computes
/// it: integrated along the ray with `accurate-air-light` (and for an orthographic camera,
/// whose rays start at altitudes of their own), otherwise read from the air table.
#[shader_fn]
pub fn air_along(direction: Vec3, distance: f32, #[spec] key: CloudKey) -> AirLight {
    let u = CLOUDS.get();
    if gate(key, ACCURATE_AIR_LIGHT) {
        return integrated_air(direction, distance);
    }
    if gate(key, ORTHOGRAPHIC) {
        return integrated_air(direction, distance);
    }
    let meets_ground = ground_hit(u.camera_altitude, direction.y, u.march.radius) >= 0.0;
    air_from_table(direction, distance, meets_ground)
}

/// What the air table depends on: the sun, the camera's altitude, the atmosphere and the
/// planet. Two blocks that agree on these have the same table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AirTableInputs {
    pub sun_direction: Vec3,
    pub camera_altitude: f32,
    pub sky: super::sky::AtmosphereParams,
    pub radius: f32,
}

impl AirTableInputs {
    /// The inputs of the block `u`.
    pub fn of(u: &CloudUniforms) -> Self {
        AirTableInputs {
            sun_direction: u.light.sun_direction,
            camera_altitude: u.camera_altitude,
            sky: u.sky,
            radius: u.march.radius,
        }
    }
}

/// Tables computed on the CPU lately, newest last: a test or a reference render binds the same
/// sun and altitude again and again.
static CPU_TABLES: Mutex<Vec<(AirTableInputs, Arc<Texture2d>)>> = Mutex::new(Vec::new());
const CPU_TABLES_KEPT: usize = 8;

/// The air table of the block `u`, drawn on the CPU by the pass's own fragment (its CPU twin),
/// texel for texel what the GPU pass draws (in f32 where the GPU's target holds half floats).
/// Rows are shared between the machine's cores.
pub fn air_table_texture(u: &CloudUniforms) -> Arc<Texture2d> {
    let inputs = AirTableInputs::of(u);
    let cached = CPU_TABLES
        .lock()
        .ok()
        .and_then(|t| t.iter().find(|(k, _)| *k == inputs).map(|(_, v)| v.clone()));
    if let Some(table) = cached {
        return table;
    }
    let (width, height) = air_table_size();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let rows_per = (height as usize).div_ceil(threads);
    let mut texels = vec![Vec4::ZERO; (width * height) as usize];
    std::thread::scope(|scope| {
        for (chunk, rows) in texels.chunks_mut(rows_per * width as usize).enumerate() {
            let block = *u;
            scope.spawn(move || {
                let _bound = CpuBindings::new().set(&CLOUDS, block).bind();
                for (i, texel) in rows.iter_mut().enumerate() {
                    let x = (i % width as usize) as f32 + 0.5;
                    let y = (chunk * rows_per + i / width as usize) as f32 + 0.5;
                    *texel = air_table_fragment(Vec4::new(x, y, 0.0, 1.0));
                }
            });
        }
    });
    let table = Arc::new(Texture2d {
        size: [width, height],
        texels,
    });
    if let Ok(mut kept) = CPU_TABLES.lock() {
        if kept.len() >= CPU_TABLES_KEPT {
            kept.remove(0);
        }
        kept.push((inputs, table.clone()));
    }
    table
}
