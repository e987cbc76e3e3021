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
//! the whole sphere, a texel about 0.55°, a 2 × 2 grid of tiles 1,280 texels square within
//! WebGL2's guaranteed 2,048), and a new bake when what the clouds are made of or lit by
//! changes (the sun, the weather, the camera's place, and a redrawn shadow cascade, which its
//! marches read; with the view baked, the haze and the composite's switches too:
//! [`super::bake::bake_ignores`]). Its use: a background sky, a device that cannot march, a
//! view whose camera turns but does not travel.
//!
//! For such a view everything a pixel shows is a function of its direction alone: the clouds,
//! the sky and the ground behind them, the air in front and the haze. So the map holds the
//! whole picture ([`CloudKey::bakes_view`]): each texel is the volume's own pixel, marched and
//! composited ([`super::march::composite`]) along the texel's direction, and the cloud pass is
//! two reads and the sun's disc (a pixel per texel of it, so it is drawn per pixel, sharp).
//! The per-pixel composite was 88 % of a 640 × 360 frame in SwiftShader. The horizon stays
//! sharp as the air table keeps it: the map's two rows are two views, one of directions above
//! the horizon and one below, each continued a little past it, and a pixel reads the row of its
//! own side, so no texel of the sky is ever blended with one of the ground.
//!
//! The grid's columns are the marches, each with a jitter of its own (stratified between them),
//! which the cloud pass averages: a texel is magnified several times on screen, and one
//! march's jitter, frozen into it, would show as a pattern. Over the engine's depth (and for
//! the linear layers) the composite must be per pixel, and the map holds the march's result
//! instead: the top row (light, transmittance) per march, and in the bottom row's first tile
//! (opacity × front depth in km, the bake's samples, 0, 0), opacity-weighted so that bilinear
//! filtering across a cloud's edge blends depths in proportion to what each texel shows.

use glam::{Vec2, Vec3, Vec4};

use nimbus_dsl::prelude::*;

use super::air_table::horizon_elevation;
use super::bindings::{BAKE, CLOUDS, LINEAR_REPEAT};
use super::choices::{HAZE, gate};
use super::march::{MarchResult, composite, haze_opacity, march_clouds};
use super::noise::interleaved_gradient_noise;
use super::shell::ground_hit;
use super::sky::{sun_disc, transmittance_towards};
use crate::key::CloudKey;

/// Texels across each of the map's tiles (the whole sphere of directions).
pub const IMPOSTOR_TEXELS: u32 = 640;

/// Marches per direction, each in a column of tiles of its own with a jitter of its own
/// (stratified between them); the cloud pass averages them.
pub const IMPOSTOR_MARCHES: u32 = 2;

/// Rows of tiles: the views above and below the horizon, or the marches' light and their depth.
const ROWS: u32 = 2;

/// The map's width and height in texels (its tiles in a grid, a column per march).
pub fn impostor_size() -> (u32, u32) {
    (IMPOSTOR_MARCHES * IMPOSTOR_TEXELS, ROWS * IMPOSTOR_TEXELS)
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

/// One texel of the map: the volume's march along the texel's direction, composited where
/// the key bakes the view ([`view_texel`]); otherwise (light, transmittance) in the top row
/// and (opacity × front depth in km, samples, 0, 0) in the bottom row's first tile. One march
/// a texel, and no loop around it: a march inside a loop took a browser's shader compiler
/// minutes.
#[shader_fn]
pub fn impostor_fragment(frag_coord: Vec4, #[spec] key: CloudKey) -> Vec4 {
    let texel = vec2(frag_coord.x, frag_coord.y).floor();
    let n = IMPOSTOR_TEXELS as f32;
    let tile = (texel / n).floor();
    let cell = texel - tile * n;
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
    // was drawn in. The columns' jitters are stratified between them; the depth tile marches
    // as the first column does.
    let jitter = (interleaved_gradient_noise(cell + Vec2::splat(0.5), 0u32)
        + tile.x / IMPOSTOR_MARCHES as f32)
        .fract_gl();
    let lower = tile.y > 0.5;
    if key.bakes_view() {
        view_texel(direction, lower, jitter, angle, key)
    } else {
        // The bottom row's other tiles hold nothing.
        if lower && tile.x > 0.5 {
            return Vec4::ZERO;
        }
        let clouds = march_clouds(direction, jitter, angle, key.impostor_march());
        let opacity = 1.0 - clouds.transmittance;
        let km = select(0.0, clouds.front_depth * 1e-3, clouds.front_depth > 0.0);
        select(
            clouds.radiance.extend(clouds.transmittance),
            vec4(opacity * km, clouds.samples, 0.0, 0.0),
            lower,
        )
    }
}

/// One texel of a view tile: what the volume's pixel along `direction` (a texel `angle` rad
/// wide) shows, less the sun's disc, as the view above the horizon (`below` false) or below
/// it. A tile holds its own side and two texels past the horizon, there as the direction at
/// the horizon itself shows it (the reads of a pixel on its own side reach no further); the
/// rest of it is never read and is not marched.
#[shader_fn]
pub fn view_texel(
    direction: Vec3,
    below: bool,
    jitter: f32,
    angle: f32,
    #[spec] key: CloudKey,
) -> Vec4 {
    let u = CLOUDS.get();
    let horizon = horizon_elevation(u.camera_altitude, u.march.radius);
    let elevation = direction.y.clamp(-1.0, 1.0).asin();
    let reach = 2.0 * angle;
    let far = select(
        elevation < horizon - reach,
        elevation > horizon + reach,
        below,
    );
    if far {
        return Vec4::ZERO;
    }
    // A tenth of a texel inside the side: the ground test's roots are sure of their sign
    // there, and the picture cannot tell.
    let margin = 0.1 * angle;
    let side = select(
        elevation.max(horizon + margin),
        elevation.min(horizon - margin),
        below,
    );
    let flat = vec2(direction.x, direction.z);
    let heading = flat / flat.length().max(1e-20) * side.cos();
    let on_side = select(
        direction,
        vec3(heading.x, side.sin(), heading.y),
        side != elevation,
    );
    // The key's own march: without the engine's depth (which a view key never reads) it is
    // [`CloudKey::impostor_march`]'s, and the composite after it is specialised by the same key.
    let clouds = march_clouds(on_side, jitter, angle, key);
    composite(on_side, jitter, clouds, key)
}

/// The map's texel of the tile in `column` and `row` in the direction `d`, bilinear within
/// the tile.
#[shader_fn]
pub fn impostor_at(d: Vec3, column: f32, row: f32) -> Vec4 {
    let n = IMPOSTOR_TEXELS as f32;
    let c = octahedral_coordinate(d);
    let cell = ((c + Vec2::ONE) * 0.5 * n).clamp(Vec2::splat(0.5), Vec2::splat(n - 0.5));
    let uv = (cell + vec2(column, row) * n) / vec2(IMPOSTOR_MARCHES as f32 * n, ROWS as f32 * n);
    BAKE.get().sample_level(&LINEAR_REPEAT.get(), uv, 0.0)
}

/// The clouds along `direction` read from the map (the march's result, for
/// [`super::march::composite`]): the mean of the marches' (light, transmittance) in the
/// direction's texel, and the depth of their front where it shows cloud.
#[shader_fn]
pub fn impostor_clouds(direction: Vec3) -> MarchResult {
    let mut light = Vec4::ZERO;
    for i in unroll(0u32..IMPOSTOR_MARCHES) {
        light += impostor_at(direction, i as f32, 0.0);
    }
    light *= 1.0 / IMPOSTOR_MARCHES as f32;
    let depth = impostor_at(direction, 0.0, 1.0);
    let opacity = 1.0 - light.w;
    MarchResult {
        radiance: light.xyz(),
        transmittance: light.w,
        front_depth: select(-1.0, depth.x / opacity.max(1e-6) * 1e3, opacity > 1e-4),
        // The reads stand for the bake's marches (its samples are the map's, per texel).
        samples: (IMPOSTOR_MARCHES + 1) as f32,
    }
}

/// The picture along `direction` read from a map that holds it ([`CloudKey::bakes_view`]):
/// the mean of the marches' views on the direction's side of the horizon, and the sun's disc
/// through what they leave of it.
#[shader_fn]
pub fn impostor_view(direction: Vec3, #[spec] key: CloudKey) -> Vec4 {
    let u = CLOUDS.get();
    let below = ground_hit(u.camera_altitude, direction.y, u.march.radius) >= 0.0;
    let row = select(0.0, 1.0, below);
    let mut view = Vec4::ZERO;
    for i in unroll(0u32..IMPOSTOR_MARCHES) {
        view += impostor_at(direction, i as f32, row);
    }
    view *= 1.0 / IMPOSTOR_MARCHES as f32;
    (view.xyz() + disc_through(direction, 1.0 - view.w, key)).extend(view.w)
}

/// The sun's disc along `direction` as the composite draws it (through the air, the clouds'
/// transmittance `clouds_transmittance` and the haze to the march's reach); zero off the disc,
/// where nothing of it is computed.
#[shader_fn]
pub fn disc_through(direction: Vec3, clouds_transmittance: f32, #[spec] key: CloudKey) -> Vec3 {
    let u = CLOUDS.get();
    let cos_theta = direction.dot(u.light.sun_direction);
    let mut disc = Vec3::ZERO;
    if cos_theta >= u.sky.sun_angular_radius.cos() {
        let air = transmittance_towards(u.camera_altitude, direction.y, u.sky, u.march.radius);
        disc = sun_disc(cos_theta, air, u.sky) * (clouds_transmittance * u.composite.sun_disc);
        if gate(key, HAZE) {
            disc *= 1.0 - haze_opacity(direction.y, u.march.max_ray_distance);
        }
    }
    disc
}
