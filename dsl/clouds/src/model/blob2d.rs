//! The map of the `blob2d` path ([`crate::Path::Blob2d`]): the sky drawn from a 2D map. A
//! pass of its own bakes, per horizontal point around the camera and per altitude band (the
//! slab's lower and upper half, so a low deck and a high layer above it stay apart), what the
//! clouds' column holds there: its optical depth straight up, the mean and spread of its
//! density's altitude, and the optical depth towards the sun at four depths into it. The cloud
//! pass takes a few samples along each view ray's way through each band; each reads the map
//! (two texels) and stands the column's optical depth up as a bell of that mean and spread,
//! and is lit by the march's own source term ([`sample_source`]: phase, octaves, sky, ground,
//! powder) with the sun's optical depth at its depth into the column. No noise, no secondary
//! march.
//!
//! The seeds' 2D clouds overlay one blob, baked once into an atlas, into larger clouds: a
//! picture that cannot be the genus' weather. Here the "blobs" are the genus' own columns,
//! baked from its `#[shader_fn]` density wherever its weather puts them, so the picture agrees
//! with the volume where a 2D map can: seen from afar, where a pixel spans more than a
//! column's structure. What it drops: a band's column holds one bell of cloud (two decks in
//! one half of the slab merge), and the light inside it varies only with depth.
//!
//! The map uses the slice stack's horizontal grid ([`slice_coordinate`]: even near the camera,
//! coarser in proportion to distance), [`BLOB_TEXELS`] across, four tiles side by side, two
//! per band (lower first): the first holds (optical depth, mean altitude, altitude spread, 0),
//! the second the optical depths to the sun where the column's optical depth from its top
//! reaches 1/8, 3/8, 5/8 and 7/8 of its whole. The optical depth above and below a point sums
//! both bands.

use glam::{Vec2, Vec3, Vec4};

use nimbus_dsl::prelude::*;

use super::bindings::{BAKE, CLOUDS, LINEAR_REPEAT};
use super::choices::{DIFFUSION, GROUND_BOUNCE, GROUPS, gate, key_count};
use super::march::{
    MarchResult, altitude_along, octave_phases, sample_source, shell_range, sun_optical_depth,
    total_density,
};
use super::ray_light::{RayLight, add_step, gathered_result};
use super::shell::{ground_hit, ray_shell};
use super::slices::{curved_height, slice_coordinate, slice_offset};
use crate::key::CloudKey;

/// Texels across the map, in x and in z.
pub const BLOB_TEXELS: u32 = 512;
/// Altitude bands, each with its own column per texel.
pub const BLOB_BANDS: u32 = 2;
/// Density samples up a band's column.
pub const BLOB_COLUMN_STEPS: u32 = 16;
/// Samples along a view ray's way through each band (each reads the band's two tiles).
pub const BLOB_SAMPLES: u32 = 8;

/// The map's width and height in texels (two tiles per band side by side).
pub fn blob2d_size() -> (u32, u32) {
    (2 * BLOB_BANDS * BLOB_TEXELS, BLOB_TEXELS)
}

/// Fractions of a column's optical depth (from its top) where a band's second tile holds the
/// optical depth to the sun.
const QUARTILE_CENTRES: Vec4 = Vec4::new(0.125, 0.375, 0.625, 0.875);

/// Bottom and top altitude (m) of what the layers hold in band `band` (0: the slab's lower
/// half, 1: its upper half): the band's column and its samples span only that, so a low deck
/// and a high layer far above it each get the band's whole resolution. An empty band spans
/// nothing (bottom = top).
#[shader_fn]
pub fn band_bounds(band: f32, #[spec] key: CloudKey) -> Vec2 {
    let u = CLOUDS.get();
    let m = u.march;
    let split = 0.5 * (m.min_height + m.max_height);
    let lo = select(split, m.min_height, band < 0.5);
    let hi = select(m.max_height, split, band < 0.5);
    let mut bottom = hi;
    let mut top = lo;
    for g in 0u32..key_count(key, GROUPS) {
        let layers = u.groups[g as usize];
        let a = layers.min_height.max(Vec4::splat(lo));
        let b = layers.max_height.min(Vec4::splat(hi));
        // Lanes with some of their layer inside the band; the others stand at the far ends.
        let inside = step(Vec4::splat(1e-4), b - a);
        let outside = Vec4::ONE - inside;
        let low = a * inside + Vec4::splat(hi) * outside;
        let high = b * inside + Vec4::splat(lo) * outside;
        bottom = bottom.min(low.x.min(low.y).min(low.z.min(low.w)));
        top = top.max(high.x.max(high.y).max(high.z.max(high.w)));
    }
    vec2(bottom, top.max(bottom))
}

/// One texel of the map: a band's column (optical depth, mean altitude, spread), or the
/// optical depths to the sun at four depths into it.
#[shader_fn]
pub fn blob2d_fragment(frag_coord: Vec4, #[spec] key: CloudKey) -> Vec4 {
    let l = CLOUDS.get().light;
    let texel = vec2(frag_coord.x, frag_coord.y).floor();
    let n = BLOB_TEXELS as f32;
    let tile = (texel.x / n).floor();
    let band = (tile * 0.5).floor();
    let cell = texel - vec2(tile * n, 0.0);
    let c = (cell + Vec2::splat(0.5)) / n * 2.0 - Vec2::ONE;
    let x = slice_offset(c.x);
    let z = slice_offset(c.y);
    let d = vec2(x, z).length();
    let half = 1.0 / n;
    let footprint = (slice_offset(c.x.abs() + half) - slice_offset(c.x.abs() - half))
        .max(slice_offset(c.y.abs() + half) - slice_offset(c.y.abs() - half));
    let sigma_ratio = l.scattering_coefficient + l.absorption_coefficient;
    let bounds = band_bounds(band, key);
    let dz = (bounds.y - bounds.x).max(1e-3) / BLOB_COLUMN_STEPS as f32;
    // Down the column from the band's top: its optical depth, and the first two moments of
    // its altitude (relative to the band's middle, which keeps the variance's digits).
    let middle = 0.5 * (bounds.x + bounds.y);
    let mut tau = 0.0f32;
    let mut first = 0.0f32;
    let mut second = 0.0f32;
    for i in 0u32..BLOB_COLUMN_STEPS {
        let h = bounds.y - (i as f32 + 0.5) * dz;
        let p = vec3(x, curved_height(h, d), z);
        let step_tau = total_density(p, h, footprint, key) * sigma_ratio * dz;
        tau += step_tau;
        first += step_tau * (h - middle);
        second += step_tau * (h - middle) * (h - middle);
    }
    let mean = first / tau.max(1e-20);
    // A step's own thickness is the least spread a sampled column can resolve.
    let spread = (second / tau.max(1e-20) - mean * mean)
        .max(0.0)
        .sqrt()
        .max(0.5 * dz);
    if tile - 2.0 * band < 0.5 {
        return vec4(tau, middle + select(0.0, mean, tau > 1e-6), spread, 0.0);
    }
    // The sun tile: where the optical depth from the band's top reaches each quartile's centre
    // (the depth below the top is the sum over steps of the part of each step above that
    // point), and the optical depth to the sun from there.
    let targets = QUARTILE_CENTRES * tau;
    let mut depth = Vec4::ZERO;
    let mut above = 0.0f32;
    for i in 0u32..BLOB_COLUMN_STEPS {
        let h = bounds.y - (i as f32 + 0.5) * dz;
        let p = vec3(x, curved_height(h, d), z);
        let step_tau = total_density(p, h, footprint, key) * sigma_ratio * dz;
        depth += ((targets - Vec4::splat(above)) / step_tau.max(1e-12)).saturate() * dz;
        above += step_tau;
    }
    let heights = Vec4::splat(bounds.y) - depth;
    vec4(
        sun_depth_from(x, z, d, heights.x, footprint, key),
        sun_depth_from(x, z, d, heights.y, footprint, key),
        sun_depth_from(x, z, d, heights.z, footprint, key),
        sun_depth_from(x, z, d, heights.w, footprint, key),
    )
}

/// Optical depth to the sun from the column at (`x`, `z`) (`d` from the camera's vertical) at
/// altitude `h`, as the volume's march takes it at this key ([`sun_optical_depth`]: its sun
/// steps, then the shadow map), so the map's light is the volume's.
#[shader_fn]
pub fn sun_depth_from(
    x: f32,
    z: f32,
    d: f32,
    h: f32,
    footprint: f32,
    #[spec] key: CloudKey,
) -> f32 {
    let p = vec3(x, curved_height(h, d), z);
    sun_optical_depth(p, h, 0.5, footprint, key)
}

/// The map's texel of `tile` at the camera-relative horizontal point (`x`, `z`), bilinear
/// within the tile; nothing outside the map.
#[shader_fn]
pub fn blob2d_at(x: f32, z: f32, tile: f32) -> Vec4 {
    let c = vec2(slice_coordinate(x), slice_coordinate(z));
    let n = BLOB_TEXELS as f32;
    let cell = ((c + Vec2::ONE) * 0.5 * n).clamp(Vec2::splat(0.5), Vec2::splat(n - 0.5));
    let uv = (cell + vec2(tile * n, 0.0)) / vec2((2u32 * BLOB_BANDS) as f32 * n, n);
    let value = BAKE.get().sample_level(&LINEAR_REPEAT.get(), uv, 0.0);
    let outside = c.x.abs() > 1.0 || c.y.abs() > 1.0;
    select(value, Vec4::ZERO, outside)
}

/// The optical depth to the sun at fraction `f` of a column's optical depth from its top, from
/// the four values `q` of its sun tile (linear between their depths, extended linearly beyond
/// them, never below zero).
#[shader_fn]
pub fn sun_depth_at(q: Vec4, f: f32) -> f32 {
    let s = f * 4.0 - 0.5;
    let inside = s.clamp(0.0, 3.0);
    let centres = vec4(0.0, 1.0, 2.0, 3.0);
    let distance = (Vec4::splat(inside) - centres).max(centres - Vec4::splat(inside));
    let hat = (Vec4::ONE - distance).max(Vec4::ZERO);
    let slope = select(q.w - q.z, q.y - q.x, s < 1.5);
    (q.dot(hat) + (s - inside) * slope).max(0.0)
}

/// Fraction of a column's optical depth above `altitude`, its density a bell of `mean` and
/// `spread` (a logistic in place of the normal distribution's integral: within 1 % of it).
#[shader_fn]
pub fn fraction_above(altitude: f32, mean: f32, spread: f32) -> f32 {
    1.0 / (1.0 + (1.702 * (altitude - mean) / spread).exp())
}

/// Distances along a view ray of up-cosine `mu` to where it enters the band between altitudes
/// `bounds` and where it first leaves it (`far < near`: it never enters): the first stretch
/// of the ray inside the band, capped at the march's reach.
#[shader_fn]
pub fn band_range(mu: f32, bounds: Vec2) -> Vec2 {
    let u = CLOUDS.get();
    let m = u.march;
    let below = ray_shell(u.camera_altitude, mu, bounds.x, m.radius);
    let above = ray_shell(u.camera_altitude, mu, bounds.y, m.radius);
    let hits_ground = ground_hit(u.camera_altitude, mu, m.radius) >= 0.0;
    // Leaving through the bottom where the ray reaches it, else through the top.
    let exit = select(above.y, below.x, below.x > 0.0);
    shell_range(bounds, below, above, exit, hits_ground)
}

/// The clouds along `direction` drawn from the map (the march's result, for
/// [`super::march::composite`]): [`BLOB_SAMPLES`] samples, stratified by `jitter`, along the
/// ray's way through each band, the nearer band first; each reads its column and takes the
/// density of the column's bell at its altitude, lit by the march's source term with the
/// sun's optical depth at its depth into the column (and the other band's column above or
/// below it), and integrated as the march integrates a step.
#[shader_fn]
#[expect(
    clippy::if_same_then_else,
    reason = "the other band's column is read for either of two key gates: one `if` per gate is \
              how a shader function branches on the key"
)]
pub fn blob2d_clouds(direction: Vec3, jitter: f32, #[spec] key: CloudKey) -> MarchResult {
    let u = CLOUDS.get();
    let m = u.march;
    let l = u.light;
    let mu = direction.y;
    let sigma_ratio = l.scattering_coefficient + l.absorption_coefficient;
    let cos_theta = direction.dot(l.sun_direction);
    let phases = octave_phases(cos_theta, key);
    // Nearer band first (a ray going up meets the lower one first; a grazing ray going down
    // from inside the lower band may still leave through the upper one, far away).
    let lower = band_range(mu, band_bounds(0.0, key));
    let upper = band_range(mu, band_bounds(1.0, key));
    let lower_near = select(1e30, lower.x, lower.y > lower.x);
    let upper_near = select(1e30, upper.x, upper.y > upper.x);
    let first_band = select(1.0, 0.0, lower_near <= upper_near);
    let mut gathered: RayLight = RayLight {
        radiance: Vec3::ZERO,
        transmittance: 1.0,
        depth_sum: 0.0,
        weight_sum: 0.0,
    };
    // Samples taken (each a column read standing for a density sample, as the march counts).
    let mut samples = 0.0f32;
    for b in 0u32..BLOB_BANDS {
        let band = (first_band - b as f32).abs();
        let other = 1.0 - band;
        let range = select(upper, lower, band < 0.5);
        let step = (range.y - range.x).max(0.0) / BLOB_SAMPLES as f32;
        samples += select(0.0, BLOB_SAMPLES as f32, step > 0.0);
        for i in 0u32..BLOB_SAMPLES {
            let t = range.x + (i as f32 + jitter) * step;
            let h = altitude_along(u.camera_altitude, mu, t, m.radius);
            let x = direction.x * t;
            let z = direction.z * t;
            let column = blob2d_at(x, z, 2.0 * band);
            let spread = column.z.max(1.0);
            let s = (h - column.y) / spread;
            // The column's optical depth as a normal bell in altitude.
            let sigma_t = column.x * INV_SQRT_TWO_PI / spread * (-0.5 * s * s).exp();
            if sigma_t > m.min_extinction && gathered.transmittance > 0.0 {
                let above = fraction_above(h, column.y, spread);
                // The other band's column lies wholly above (band 0) or below (band 1); only
                // the ground's and the sky's light through the slab need it.
                let mut beyond = 0.0f32;
                if gate(key, GROUND_BOUNCE) {
                    beyond = blob2d_at(x, z, 2.0 * other).x;
                } else if gate(key, DIFFUSION) {
                    beyond = blob2d_at(x, z, 2.0 * other).x;
                }
                let tau_up = above * column.x + select(0.0, beyond, band < 0.5);
                let tau_ground = (1.0 - above) * column.x + select(beyond, 0.0, band < 0.5);
                let sun_depths = blob2d_at(x, z, 2.0 * band + 1.0);
                let source = sample_source(
                    sigma_t / sigma_ratio,
                    h,
                    sun_depth_at(sun_depths, above),
                    tau_up,
                    tau_ground,
                    cos_theta,
                    phases,
                    mu,
                    key,
                );
                // Integrated as the march integrates a step, and ended as it ends a ray.
                gathered = add_step(gathered, source, sigma_t, step, t);
            }
        }
    }
    gathered_result(gathered, samples)
}

/// The optical depth of the clouds above the ground point (`x`, `z`) (camera-relative): both
/// bands' columns there.
#[shader_fn]
pub fn blob2d_overhead(x: f32, z: f32) -> f32 {
    blob2d_at(x, z, 0.0).x + blob2d_at(x, z, 2.0).x
}

/// 1/√(2π): the normal bell's height per unit spread.
const INV_SQRT_TWO_PI: f32 = 0.398_942_3;
