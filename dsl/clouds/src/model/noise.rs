//! Tileable procedural noise for the cloud textures: an integer hash, gradient (Perlin) noise,
//! cellular (Worley) noise and their fractal sums. Every lattice coordinate is wrapped by the
//! period, so a texture built from them tiles seamlessly. The same functions run on the CPU
//! (tests) and in the compute shaders that fill the textures.

use glam::Vec3;

use nimbus_dsl::prelude::*;

/// pcg3d (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering"), reduced to one word.
#[shader_fn]
pub fn hash3(x: u32, y: u32, z: u32) -> u32 {
    let mut a = x.wrapping_mul(1_664_525u32).wrapping_add(1_013_904_223u32);
    let mut b = y.wrapping_mul(1_664_525u32).wrapping_add(1_013_904_223u32);
    let mut c = z.wrapping_mul(1_664_525u32).wrapping_add(1_013_904_223u32);
    a = a.wrapping_add(b.wrapping_mul(c));
    b = b.wrapping_add(c.wrapping_mul(a));
    c = c.wrapping_add(a.wrapping_mul(b));
    a ^= a >> 16u32;
    b ^= b >> 16u32;
    c ^= c >> 16u32;
    a = a.wrapping_add(b.wrapping_mul(c));
    b = b.wrapping_add(c.wrapping_mul(a));
    a ^ b
}

/// A pseudo-random vector in [-1, 1]³ for lattice point (x, y, z), wrapped by `period`, salted
/// by `seed`.
#[shader_fn]
pub fn lattice_vector(x: i32, y: i32, z: i32, period: i32, seed: u32) -> Vec3 {
    let h = hash3(
        x.rem_euclid(period) as u32,
        y.rem_euclid(period) as u32,
        z.rem_euclid(period) as u32 + seed.wrapping_mul(7919u32),
    );
    let gx = (h & 1023u32) as f32 / 511.5 - 1.0;
    let gy = ((h >> 10u32) & 1023u32) as f32 / 511.5 - 1.0;
    let gz = ((h >> 20u32) & 1023u32) as f32 / 511.5 - 1.0;
    vec3(gx, gy, gz)
}

/// Contribution of one lattice corner to gradient noise.
#[shader_fn]
pub fn corner(cell: Vec3, offset: Vec3, f: Vec3, period: i32, seed: u32) -> f32 {
    let c = cell + offset;
    let g = lattice_vector(c.x as i32, c.y as i32, c.z as i32, period, seed);
    g.dot(f - offset)
}

/// Tileable gradient (Perlin) noise, roughly in [-1, 1], with quintic interpolation; `p` is in
/// lattice units and the noise repeats every `period` units.
#[shader_fn]
pub fn perlin(p: Vec3, period: i32, seed: u32) -> f32 {
    let cell = p.floor();
    let f = p - cell;
    let u = f * f * f * (f * (f * 6.0 - Vec3::splat(15.0)) + Vec3::splat(10.0));
    let c000 = corner(cell, vec3(0.0, 0.0, 0.0), f, period, seed);
    let c100 = corner(cell, vec3(1.0, 0.0, 0.0), f, period, seed);
    let c010 = corner(cell, vec3(0.0, 1.0, 0.0), f, period, seed);
    let c110 = corner(cell, vec3(1.0, 1.0, 0.0), f, period, seed);
    let c001 = corner(cell, vec3(0.0, 0.0, 1.0), f, period, seed);
    let c101 = corner(cell, vec3(1.0, 0.0, 1.0), f, period, seed);
    let c011 = corner(cell, vec3(0.0, 1.0, 1.0), f, period, seed);
    let c111 = corner(cell, vec3(1.0, 1.0, 1.0), f, period, seed);
    let x00 = mix(c000, c100, u.x);
    let x10 = mix(c010, c110, u.x);
    let x01 = mix(c001, c101, u.x);
    let x11 = mix(c011, c111, u.x);
    mix(mix(x00, x10, u.y), mix(x01, x11, u.y), u.z)
}

/// Tileable cellular (Worley) noise: 1 − distance to the nearest feature point (one per cell),
/// clamped to [0, 1].
#[shader_fn]
pub fn worley(p: Vec3, period: i32, seed: u32) -> f32 {
    let cell = p.floor();
    let mut nearest = 10.0f32;
    for dz in -1i32..2i32 {
        for dy in -1i32..2i32 {
            for dx in -1i32..2i32 {
                let c = cell + vec3(dx as f32, dy as f32, dz as f32);
                let jitter = lattice_vector(c.x as i32, c.y as i32, c.z as i32, period, seed) * 0.5
                    + Vec3::splat(0.5);
                nearest = nearest.min((c + jitter - p).length());
            }
        }
    }
    (1.0 - nearest).clamp(0.0, 1.0)
}

/// Fractal sum of `octaves` Perlin octaves (frequency ×2, amplitude ×0.5), mapped to [0, 1].
#[shader_fn]
pub fn perlin_fbm(p: Vec3, period: i32, seed: u32, octaves: u32) -> f32 {
    let mut sum = 0.0f32;
    let mut amplitude = 0.5f32;
    let mut frequency = 1.0f32;
    let mut total = 0.0f32;
    for _o in 0u32..octaves {
        sum += amplitude * perlin(p * frequency, (period as f32 * frequency) as i32, seed);
        total += amplitude;
        amplitude *= 0.5;
        frequency *= 2.0;
    }
    (sum / total * 0.5 + 0.5).clamp(0.0, 1.0)
}

/// Three Worley octaves weighted 0.625, 0.25, 0.125 (the Nubis recipe), in [0, 1].
#[shader_fn]
pub fn worley_fbm(p: Vec3, period: i32, seed: u32) -> f32 {
    let w1 = worley(p, period, seed);
    let w2 = worley(p * 2.0, period * 2i32, seed);
    let w3 = worley(p * 4.0, period * 4i32, seed);
    w1 * 0.625 + w2 * 0.25 + w3 * 0.125
}

/// The shape texture's value at `uvw` ∈ [0, 1)³: Perlin–Worley (Perlin remapped onto the Worley
/// floor, Schneider 2015), tiling with `cells` lattice cells per side.
#[shader_fn]
pub fn shape_noise(uvw: Vec3, cells: i32) -> f32 {
    let p = uvw * (cells as f32);
    let perlin01 = perlin_fbm(p, cells, 1u32, 4u32);
    let w = worley_fbm(p, cells, 2u32);
    // remap(perlin, 0, 1, worley, 1)
    let s = (w + perlin01 * (1.0 - w)).clamp(0.0, 1.0) * w.max(0.35);
    (SHAPE_MATCH.x + SHAPE_MATCH.y * s).saturate()
}

/// `offset, gain` that give the shape noise the distribution of @takram/three-clouds'
/// `shape.bin` (quantiles 10/25/50/75/90 %: 0.694, 0.749, 0.804, 0.855, 0.890; ours were 0.235,
/// 0.282, 0.361, 0.439, 0.518). The erosion cuts `amount·(1 − s)`, so with the raw noise
/// (mean 0.37 against 0.80) a coverage of 0.4 left mostly clear sky where the reference library
/// shows mostly cloud: matched, a coverage means what it means there.
const SHAPE_MATCH: Vec2 = Vec2::new(0.545, 0.69);

/// The same for the detail noise against `shape_detail.bin` (0.588, 0.647, 0.718, 0.784,
/// 0.839; ours were 0.329, 0.396, 0.478, 0.561, 0.631).
const DETAIL_MATCH: Vec2 = Vec2::new(0.315, 0.831);

/// Per-channel `gain, offset` that give the weather channels the distribution of
/// `local_weather.png` (R: a quarter of it 0, median 0.224, 90 % 0.678; G: median 0.035,
/// 90 % 0.522; B: median 0.498; A: median 0.384), so that each layer's channel covers as much of
/// the sky at a given coverage as the reference library's does.
const WEATHER_GAIN: Vec4 = Vec4::new(2.16, 2.30, 1.261, 1.33);
const WEATHER_OFFSET: Vec4 = Vec4::new(-0.847, -1.111, -0.116, -0.27);

/// Texels per side of the procedural detail texture (@takram/three-clouds' 32³).
pub const DETAIL_SIZE: u32 = 32;

/// Means of the procedural detail noise `d` and of `d⁶` over its texture (pinned by
/// `texture_statistics::detail_moments_are_the_texture_s`): what the erosion sees where the
/// detail is finer than a sample's footprint.
pub const DETAIL_MOMENTS: Vec2 = Vec2::new(0.714, 0.171);

/// The detail texture's value: Worley octaves only (wispy erosion).
#[shader_fn]
pub fn detail_noise(uvw: Vec3, cells: i32) -> f32 {
    let d = worley_fbm(uvw * (cells as f32), cells, 3u32);
    (DETAIL_MATCH.x + DETAIL_MATCH.y * d).saturate()
}

/// Contrast of the weather signals about their mean.
const WEATHER_CONTRAST: f32 = 3.0;

/// Lattice cells per side of the weather texture's tile (its base frequency).
pub const WEATHER_CELLS: i32 = 8;

/// Local weather at `uv` ∈ [0, 1)²: coverage signals for low (r), mid (g), high (b) and extra
/// (a) clouds, each a tileable Perlin fbm at its own scale.
#[shader_fn]
pub fn weather_noise(uv: Vec2, cells: i32) -> Vec4 {
    let p = vec3(uv.x, uv.y, 0.0) * (cells as f32);
    let r = perlin_fbm(p, cells, 4u32, 5u32);
    let g = perlin_fbm(p * 2.0, cells * 2i32, 5u32, 4u32);
    // Half the frequency needs half the period, or the channel does not tile: its seam was a
    // hard straight edge across every high layer (cirrus, cirrocumulus, cirrostratus read b).
    let b = perlin_fbm(p * 0.5 + vec3(0.0, 0.0, 0.5), cells / 2i32, 6u32, 4u32);
    let a = perlin_fbm(p + vec3(0.0, 0.0, 1.5), cells, 7u32, 3u32);
    // fbm clusters around 0.5; stretching it gives clear sky between cloud fields, as a
    // painted weather map has.
    let w =
        ((vec4(r, g, b, a) - Vec4::splat(0.5)) * WEATHER_CONTRAST + Vec4::splat(0.5)).saturate();
    (w * WEATHER_GAIN + WEATHER_OFFSET).saturate()
}

/// Curl of a tileable 2D potential at `uv`, encoded in [0, 1] (0.5 = no flow), for turbulence.
#[shader_fn]
pub fn curl_noise(uv: Vec2, cells: i32) -> Vec4 {
    let p = vec3(uv.x, uv.y, 0.0) * (cells as f32);
    let e = 0.01f32;
    let dx =
        perlin(p + vec3(e, 0.0, 0.0), cells, 8u32) - perlin(p - vec3(e, 0.0, 0.0), cells, 8u32);
    let dy =
        perlin(p + vec3(0.0, e, 0.0), cells, 8u32) - perlin(p - vec3(0.0, e, 0.0), cells, 8u32);
    let flow = vec2(dy, -dx) / (2.0 * e) * 0.25;
    vec4(flow.x * 0.5 + 0.5, flow.y * 0.5 + 0.5, 0.5, 1.0).saturate()
}

/// Interleaved gradient noise (Jimenez 2014) in [0, 1): a cheap per-pixel jitter with
/// blue-noise-like spectrum, varied per frame.
#[shader_fn]
pub fn interleaved_gradient_noise(pixel: Vec2, frame: u32) -> f32 {
    let p = pixel + Vec2::splat(5.588_238 * ((frame % 64u32) as f32));
    (52.982_918 * (0.067_110_56 * p.x + 0.005_837_15 * p.y).fract_gl()).fract_gl()
}
