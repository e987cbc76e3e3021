//! The slice stack of the `slices` path ([`crate::Path::Slices`]): the clouds around the camera
//! baked into [`SLICE_LEVELS`] horizontal slices, one per altitude between the lowest layer
//! bottom and the highest layer top, by a pass of their own, and read by the view march in
//! place of the procedural density and its secondary marches.
//!
//! A texel holds what the march's lighting needs at its point: the density (the sum over the
//! layer groups, [`total_density`]), the optical depth towards the sun as the volume's march
//! takes it at the same key ([`sun_optical_depth`]: its sun steps, then the shadow map), and,
//! where the key lights by them, the optical depths straight down to the base and up to the
//! top. The phase, the octaves, the sky light and the powder stay per
//! sample in the march ([`super::march::march_clouds`]), so the sun's angle to the view is
//! exact and the stack is the same for every view direction: turning the camera redraws
//! nothing; moving the sun, the camera or the weather does.
//!
//! Horizontally each slice spans the march's reach either side of the camera, on a grid that
//! is fine near the camera and coarse far away (`x = L·((1 + W/L)^|c| − 1)` for grid
//! coordinate `c` in [−1, 1]), so a texel subtends about the same angle wherever it is seen
//! from the camera: [`SLICE_TEXELS`] across give about 2° for clouds beside the camera's
//! vertical and finer overhead. Each texel's density is the mean over its footprint (the detail
//! erosion fades to its mean as the march's does for a wide pixel), so the stack is the volume
//! seen at the scale of its texels: the path is for skies seen from afar, backgrounds and
//! devices that cannot march.
//!
//! Layout: levels side by side, [`SLICE_TILES_ACROSS`] to a row, each a square of
//! [`SLICE_TEXELS`]; x east along a tile's columns, z south along its rows. Reads never blend
//! across a tile's edge; between levels the march blends the two nearest.

use glam::{Vec2, Vec3, Vec4};

use nimbus_dsl::prelude::*;

use super::bindings::{BAKE, CLOUDS, LINEAR_REPEAT};
use super::choices::{DIFFUSION, GROUND_BOUNCE, gate};
use super::march::{secondary_optical_depth, sun_optical_depth, total_density};
use crate::key::CloudKey;

/// Texels across a slice, in x and in z.
pub const SLICE_TEXELS: u32 = 256;
/// Slices (altitudes) in the stack.
pub const SLICE_LEVELS: u32 = 32;
/// Slices side by side in one row of the stack's texture.
pub const SLICE_TILES_ACROSS: u32 = 8;
/// Distance from the camera (m) within which the grid is about even; beyond it the texels grow
/// in proportion to their distance.
pub const SLICE_NEAR: f32 = 1000.0;
/// Steps of the bake's marches straight down and up (ground bounce, diffusion).
pub const SLICE_VERTICAL_STEPS: u32 = 4;

/// Rows of slices in the stack's texture.
pub const SLICE_TILE_ROWS: u32 = SLICE_LEVELS.div_ceil(SLICE_TILES_ACROSS);

/// The stack texture's width and height in texels.
pub fn slices_size() -> (u32, u32) {
    (
        SLICE_TEXELS * SLICE_TILES_ACROSS,
        SLICE_TEXELS * SLICE_TILE_ROWS,
    )
}

/// Horizontal half-width of the stack (m): the march's reach.
#[shader_fn]
pub fn slice_extent() -> f32 {
    CLOUDS.get().march.max_ray_distance.max(2.0 * SLICE_NEAR)
}

/// Grid coordinate in [−1, 1] of a camera-relative horizontal offset `x` (m); beyond ±1 the
/// point lies outside the stack.
#[shader_fn]
pub fn slice_coordinate(x: f32) -> f32 {
    let span = (1.0 + slice_extent() / SLICE_NEAR).ln();
    select(-1.0, 1.0, x >= 0.0) * (1.0 + x.abs() / SLICE_NEAR).ln() / span
}

/// Camera-relative horizontal offset (m) of grid coordinate `c`: the inverse of
/// [`slice_coordinate`].
#[shader_fn]
pub fn slice_offset(c: f32) -> f32 {
    let span = (1.0 + slice_extent() / SLICE_NEAR).ln();
    select(-1.0, 1.0, c >= 0.0) * SLICE_NEAR * ((c.abs() * span).exp() - 1.0)
}

/// Altitude (m) of slice `level` (its index; fractions between).
#[shader_fn]
pub fn slice_altitude(level: f32) -> f32 {
    let m = CLOUDS.get().march;
    m.min_height + (level + 0.5) / SLICE_LEVELS as f32 * (m.max_height - m.min_height).max(1.0)
}

/// Camera-relative height (m) of the point at `altitude` a horizontal distance `d` (m) from the
/// camera's vertical: the planet's surface curves away below the local frame's plane. Written
/// as a difference of squares over a sum, which keeps its digits at planet scale.
#[shader_fn]
pub fn curved_height(altitude: f32, d: f32) -> f32 {
    let u = CLOUDS.get();
    let outer = u.march.radius + altitude;
    let drop = d * d / ((outer * outer - d * d).max(0.0).sqrt() + outer);
    altitude - u.camera_altitude - drop
}

/// One texel of the stack (its pass draws every texel once per sun, camera or weather change):
/// density, optical depth to the sun, and down and up through the slab where the key needs
/// them.
#[shader_fn]
#[expect(
    clippy::if_same_then_else,
    reason = "the march down runs once for either of two key gates: one `if` per gate is how a \
              shader function branches on the key"
)]
pub fn slices_fragment(frag_coord: Vec4, #[spec] key: CloudKey) -> Vec4 {
    let texel = vec2(frag_coord.x, frag_coord.y).floor();
    let n = SLICE_TEXELS as f32;
    let tile = (texel / n).floor();
    let level = tile.y * SLICE_TILES_ACROSS as f32 + tile.x;
    let cell = texel - tile * n;
    let c = (cell + Vec2::splat(0.5)) / n * 2.0 - Vec2::ONE;
    let x = slice_offset(c.x);
    let z = slice_offset(c.y);
    let h = slice_altitude(level);
    let p = vec3(x, curved_height(h, vec2(x, z).length()), z);
    // The texel stands for its whole footprint: the wider of its two sides.
    let half = 1.0 / n;
    let footprint = (slice_offset(c.x.abs() + half) - slice_offset(c.x.abs() - half))
        .max(slice_offset(c.y.abs() + half) - slice_offset(c.y.abs() - half));
    let rho = total_density(p, h, footprint, key);
    // The volume's own light at this key. The stack had its own march, 8 steps the whole way
    // out of the slab: where the volume lit from the map (`low`, and every preset past its sun
    // steps) the path drew other light, 3.6/255 from the volume's picture for stratocumulus at
    // `low` and 8.6/255 for stratus at `medium` (0.6 and 0.3 with the volume's light).
    let tau_sun = sun_optical_depth(p, h, 0.5, footprint, key);
    let mut tau_down = 0.0f32;
    if gate(key, GROUND_BOUNCE) {
        tau_down = vertical_depth(p, h, -1.0, footprint, key);
    } else if gate(key, DIFFUSION) {
        tau_down = vertical_depth(p, h, -1.0, footprint, key);
    }
    let mut tau_up = 0.0f32;
    if gate(key, DIFFUSION) {
        tau_up = vertical_depth(p, h, 1.0, footprint, key);
    }
    vec4(rho, tau_sun, tau_down, tau_up)
}

/// Optical depth from `p` straight along `vertical` (±1) out of the slab, the whole way.
#[shader_fn]
pub fn vertical_depth(
    p: Vec3,
    h: f32,
    vertical: f32,
    footprint: f32,
    #[spec] key: CloudKey,
) -> f32 {
    secondary_optical_depth(
        p,
        h,
        vec3(0.0, vertical, 0.0),
        SLICE_VERTICAL_STEPS,
        0.5,
        true,
        footprint,
        key,
    )
}

/// The stack's texel at grid cell `cell` (texel-centre coordinates, clamped inside a tile) of
/// slice `level`.
#[shader_fn]
pub fn slice_texel(cell: Vec2, level: f32) -> Vec4 {
    let width = (SLICE_TEXELS * SLICE_TILES_ACROSS) as f32;
    let height = (SLICE_TEXELS * SLICE_TILE_ROWS) as f32;
    let row = (level / SLICE_TILES_ACROSS as f32).floor();
    let column = level - row * SLICE_TILES_ACROSS as f32;
    let corner = vec2(column, row) * SLICE_TEXELS as f32;
    let uv = (corner + cell) / vec2(width, height);
    BAKE.get().sample_level(&LINEAR_REPEAT.get(), uv, 0.0)
}

/// What the stack holds at the camera-relative point `p` at `altitude` (density, optical depth
/// to the sun, down and up), blended between the two nearest slices; nothing outside it.
#[shader_fn]
pub fn slices_at(p: Vec3, altitude: f32) -> Vec4 {
    let m = CLOUDS.get().march;
    let c = vec2(slice_coordinate(p.x), slice_coordinate(p.z));
    let n = SLICE_TEXELS as f32;
    // Within a tile the bilinear footprint stays inside its own texels.
    let cell = ((c + Vec2::ONE) * 0.5 * n).clamp(Vec2::splat(0.5), Vec2::splat(n - 0.5));
    let level = ((altitude - m.min_height) / (m.max_height - m.min_height).max(1.0)
        * SLICE_LEVELS as f32
        - 0.5)
        .clamp(0.0, (SLICE_LEVELS - 1u32) as f32);
    let below = level.floor();
    let above = (below + 1.0).min((SLICE_LEVELS - 1u32) as f32);
    let value = mix(
        slice_texel(cell, below),
        slice_texel(cell, above),
        level - below,
    );
    let outside = c.x.abs() > 1.0 || c.y.abs() > 1.0;
    select(value, Vec4::ZERO, outside)
}
