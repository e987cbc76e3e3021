//! The impostor of the `impostor` path ([`crate::Path::Impostor`]): the clouds around the
//! camera baked, from every direction, into one octahedral map, and drawn from it at three
//! texture reads a pixel. A pass of its own marches, for each texel's direction, the
//! volume's own view ray ([`march_clouds`], the same function the volume path runs per pixel,
//! every effect of the key's march included) and keeps what the composite needs: the clouds'
//! light, their transmittance and the depth of their front. The cloud pass reads the texel of
//! its ray's direction (bilinear) and composites it over the sky, the ground, the air and the
//! haze exactly as the volume's march result is composited, so the air in front of the clouds,
//! the ground's shadows and the haze stay per pixel.
//!
//! This is the billboard impostor taken to its limit for a sky: a billboard per cloud, baked
//! from a specimen, cannot be the genus' weather (its clouds are wherever the weather puts
//! them, each its own shape); one billboard per direction around the camera, baked from the
//! clouds that are there, is. What it costs: the map's resolution ([`IMPOSTOR_TEXELS`] across
//! the whole sphere, a texel about 0.55°, three tiles 1,920 texels wide within WebGL2's
//! guaranteed 2,048), and a new bake when what the clouds
//! are made of or lit by changes (the sun, the weather, the camera's place, and a redrawn
//! shadow cascade, which its marches read: [`super::bake::bake_ignores`]). Its use: a
//! background sky, a
//! device that cannot march, a view whose camera turns but does not travel.
//!
//! The map is three tiles side by side, each the octahedral projection of the sphere of
//! directions (`y` up): two light tiles holding (light, transmittance), each from a march of
//! its own jitter (the cloud pass averages them), and a depth tile holding (opacity × front
//! depth in km, the bake's samples, 0, 0), opacity-weighted so that bilinear filtering across
//! a cloud's edge blends depths in proportion to what each texel shows.

use glam::{Vec2, Vec3, Vec4};

use nimbus_dsl::prelude::*;

use super::bindings::{BAKE, LINEAR_REPEAT};
use super::march::{MarchResult, march_clouds};
use super::noise::interleaved_gradient_noise;
use crate::key::CloudKey;

/// Texels across each of the map's tiles (the whole sphere of directions).
pub const IMPOSTOR_TEXELS: u32 = 640;

/// Light tiles, each its own march per direction with a jitter of its own (stratified between
/// them); the cloud pass averages them.
pub const IMPOSTOR_MARCHES: u32 = 2;

/// The map's tiles: [`IMPOSTOR_MARCHES`] light tiles, then the depth tile.
const TILES: u32 = IMPOSTOR_MARCHES + 1;

/// The map's width and height in texels (its tiles side by side).
pub fn impostor_size() -> (u32, u32) {
    (TILES * IMPOSTOR_TEXELS, IMPOSTOR_TEXELS)
}

/// The unit direction (`y` up) at the point `c` of the octahedral square `[-1, 1]²`: the upper
/// hemisphere inside the diamond `|x| + |y| ≤ 1`, the lower one folded out into its corners.
#[shader_fn]
pub fn octahedral_direction(c: Vec2) -> Vec3 {
    let up = 1.0 - c.x.abs() - c.y.abs();
    // Below the horizon the corner folds back over the diamond's edge.
    let folded = (Vec2::ONE - vec2(c.y.abs(), c.x.abs())) * vec2(sign_of(c.x), sign_of(c.y));
    let xz = select(c, folded, up < 0.0);
    vec3(xz.x, up, xz.y).normalize()
}

/// The point of the octahedral square `[-1, 1]²` of the unit direction `d` (the inverse of
/// [`octahedral_direction`]).
#[shader_fn]
pub fn octahedral_coordinate(d: Vec3) -> Vec2 {
    let p = vec2(d.x, d.z) / (d.x.abs() + d.y.abs() + d.z.abs()).max(1e-20);
    let folded = (Vec2::ONE - vec2(p.y.abs(), p.x.abs())) * vec2(sign_of(p.x), sign_of(p.y));
    select(p, folded, d.y < 0.0)
}

/// +1 for zero and above, −1 below (the fold needs a side for the axes themselves).
#[shader_fn]
pub fn sign_of(x: f32) -> f32 {
    select(-1.0, 1.0, x >= 0.0)
}

/// One texel of the map: the volume's march along the texel's direction, as (light,
/// transmittance) in a light tile and (opacity × front depth in km, samples, 0, 0) in the
/// depth tile. One march a texel, and no loop around it: a march inside a loop took a
/// browser's shader compiler minutes.
#[shader_fn]
pub fn impostor_fragment(frag_coord: Vec4, #[spec] key: CloudKey) -> Vec4 {
    let texel = vec2(frag_coord.x, frag_coord.y).floor();
    let n = IMPOSTOR_TEXELS as f32;
    let tile = (texel.x / n).floor();
    let cell = texel - vec2(tile * n, 0.0);
    let c = (cell + Vec2::splat(0.5)) / n * 2.0 - Vec2::ONE;
    let direction = octahedral_direction(c);
    // The angle the texel subtends (its wider side, measured towards the square's centre so
    // the neighbour never crosses the square's folded edge).
    let across = 2.0 / n;
    let beside_x = octahedral_direction(c - vec2(across * sign_of(c.x), 0.0));
    let beside_y = octahedral_direction(c - vec2(0.0, across * sign_of(c.y)));
    let angle = (beside_x - direction)
        .length()
        .max((beside_y - direction).length());
    // A fixed sequence (frame 0): the bake is drawn once and must not depend on the frame it
    // was drawn in. The light tiles' jitters are stratified between them: a texel is
    // magnified several times on screen, and one march's jitter, frozen into it, would show
    // as a pattern. The depth tile marches as the first light tile does.
    let jitter = interleaved_gradient_noise(cell + Vec2::splat(0.5), 0u32);
    let depth_tile = tile > IMPOSTOR_MARCHES as f32 - 0.5;
    let stratum = select(tile, 0.0, depth_tile) / IMPOSTOR_MARCHES as f32;
    let clouds = march_clouds(
        direction,
        (jitter + stratum).fract_gl(),
        angle,
        key.impostor_march(),
    );
    let opacity = 1.0 - clouds.transmittance;
    let km = select(0.0, clouds.front_depth * 1e-3, clouds.front_depth > 0.0);
    select(
        clouds.radiance.extend(clouds.transmittance),
        vec4(opacity * km, clouds.samples, 0.0, 0.0),
        depth_tile,
    )
}

/// The map's texel of `tile` in the direction `d`, bilinear within the tile.
#[shader_fn]
pub fn impostor_at(d: Vec3, tile: f32) -> Vec4 {
    let n = IMPOSTOR_TEXELS as f32;
    let c = octahedral_coordinate(d);
    let cell = ((c + Vec2::ONE) * 0.5 * n).clamp(Vec2::splat(0.5), Vec2::splat(n - 0.5));
    let uv = (cell + vec2(tile * n, 0.0)) / vec2(TILES as f32 * n, n);
    BAKE.get().sample_level(&LINEAR_REPEAT.get(), uv, 0.0)
}

/// The clouds along `direction` read from the map (the march's result, for
/// [`super::march::composite`]): the mean of the light tiles' (light, transmittance) in the
/// direction's texel, and the depth of their front where it shows cloud.
#[shader_fn]
pub fn impostor_clouds(direction: Vec3) -> MarchResult {
    let mut light = Vec4::ZERO;
    for i in 0u32..IMPOSTOR_MARCHES {
        light += impostor_at(direction, i as f32);
    }
    light *= 1.0 / IMPOSTOR_MARCHES as f32;
    let depth = impostor_at(direction, IMPOSTOR_MARCHES as f32);
    let opacity = 1.0 - light.w;
    MarchResult {
        radiance: light.xyz(),
        transmittance: light.w,
        front_depth: select(-1.0, depth.x / opacity.max(1e-6) * 1e3, opacity > 1e-4),
        // The reads stand for the bake's marches (its samples are the map's, per texel).
        samples: TILES as f32,
    }
}
