//! Beer shadow map (Hillaire 2020) with cascades, packed in a grid in one atlas texture.
//!
//! Each texel marches the clouds once along the sun and stores front depth, mean extinction,
//! maximum optical depth and a tail for early termination; a shading point then gets its
//! optical depth to the sun in O(1) ([`super::march::shadow_optical_depth`]).
//!
//! Cascades are nested squares around the camera, each four times the side of the previous,
//! projected along the sun onto the plane at the top of the shadow-casting layers. One atlas
//! with a tile per cascade keeps the pass to one colour attachment and one draw, whatever the
//! device's colour-attachment limit (WebGL2 guarantees only four draw buffers). The tiles lie
//! in a grid as square as the count allows ([`atlas_columns`]): side by side, `ultra`'s three
//! cascades of 1,024 texels made an atlas 3,072 wide, past the 2,048 WebGL2 guarantees.

use glam::{Mat4, Vec2, Vec3, Vec4};

use nimbus_dsl::prelude::*;

use super::bindings::{CLOUDS, LINEAR_REPEAT, SHADOW_MAP};
use super::choices::{GROUPS, key_count};
use super::density::{eroded_density, weather_density};
use crate::key::CloudKey;

/// Cascades and the shadow march (uniforms: changing them needs no new pipeline).
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct ShadowParams {
    /// Where each tile of the atlas is read: camera-relative position to every tile's texture
    /// coordinates, each tile through the transform it was drawn with.
    pub lookup: CascadeLookup,
    /// Cascade-0 coordinates (x, y) to the point on the plane at the top of the
    /// shadow-casting layers (camera-relative metres), for the sun as it is now: what a tile
    /// drawn this frame is drawn from.
    pub inverse_matrix: Mat4,
    /// Side of each cascade relative to cascade 0 (1, 4, 16, 64).
    pub cascade_scales: Vec4,
    /// Cascades in the atlas (1..=4) and texels per tile side.
    pub cascade_count: u32,
    pub map_size: f32,
    pub max_iterations: u32,
    pub min_step: f32,
    pub max_step: f32,
    pub min_extinction: f32,
    pub min_transmittance: f32,
    /// Scale of the optical depth guessed for what lies beyond an early termination.
    pub tail_scale: f32,
}

/// Every cascade tile's transform at once: component `k` of `u * p.extend(1.0)` is the
/// horizontal texture coordinate of camera-relative `p` in tile `k` (its centre 0.5, the tile
/// [0, 1]²), projected along the sun onto the plane at the top of the shadow-casting layers;
/// `v` likewise the vertical one. A transform per tile, not one scaled per cascade, so that
/// tiles drawn on different frames (cascades in rotation, [`redrawn_tiles`]) are each read
/// through the sun and the place they were drawn from.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct CascadeLookup {
    pub u: Mat4,
    pub v: Mat4,
}

/// Altitude of a camera-relative point `p`, on a sphere of `radius` (stable for |p| ≪ R: no
/// planet-sized squares are formed).
#[shader_fn]
pub fn altitude_at(p: Vec3, camera_altitude: f32, radius: f32) -> f32 {
    let y = camera_altitude + p.y;
    let d2 = p.x * p.x + p.z * p.z;
    let r = radius + y;
    y + d2 / ((r * r + d2).sqrt() + r)
}

/// Columns of the atlas's grid of `count` cascade tiles (tile `k` in column `k % columns`, row
/// `k / columns`): 1 for one cascade, else 2, so four tiles make a square and three leave one
/// corner empty (its texels are never drawn on: [`shadow_fragment`] returns at once).
#[shader_fn]
pub fn atlas_columns(count: u32) -> u32 {
    select(1u32, 2u32, count > 1u32)
}

/// Rows of the atlas's grid of `count` cascade tiles (at most four, two to a row).
#[shader_fn]
pub fn atlas_rows(count: u32) -> u32 {
    select(1u32, 2u32, count > 2u32)
}

impl ShadowParams {
    /// The atlas's width and height in texels.
    pub fn atlas_size(&self) -> (u32, u32) {
        let side = self.map_size as u32;
        (
            side * atlas_columns(self.cascade_count),
            side * atlas_rows(self.cascade_count),
        )
    }
}

/// What the shadow atlas knows at a point: the texel ([`shadow_texel`]) and how much of it
/// the map holds (1 inside its cascades, fading to 0 over the outer fifth of the last, 0
/// beyond), so that a caller with nothing else towards the sun can take over where the map
/// fades.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct ShadowRead {
    pub texel: Vec4,
    pub held: f32,
}

/// The atlas texel of the finest cascade that holds camera-relative `p`, its optical depth
/// faded out towards the edge of the last cascade; an empty texel (no optical depth) outside
/// every cascade.
#[shader_fn]
pub fn shadow_texel(p: Vec3) -> Vec4 {
    shadow_read(p).texel
}

/// [`shadow_texel`] with the share of it the map holds.
#[shader_fn]
pub fn shadow_read(p: Vec3) -> ShadowRead {
    let s = CLOUDS.get().shadow;
    let q = p.extend(1.0);
    // Every tile's coordinates at once, centred on the tile.
    let u = s.lookup.u * q - Vec4::splat(0.5);
    let v = s.lookup.v * q - Vec4::splat(0.5);
    let extent = u.abs().max(v.abs());
    // One texel of margin, so bilinear filtering never reads the neighbouring tile.
    let margin = 0.5 - 1.0 / s.map_size;
    let count = s.cascade_count as f32;
    let active = step(vec4(0.5, 1.5, 2.5, 3.5), Vec4::splat(count));
    let holding = step(extent, Vec4::splat(margin)) * active;
    // The finest tile that holds `p` (4: none). Tiles drawn around different places need not
    // nest, so the first that holds it, not a count of those that do.
    let order = vec4(0.0, 1.0, 2.0, 3.0) + (Vec4::ONE - holding) * 4.0;
    let k = order.x.min(order.y).min(order.z.min(order.w));
    if k > 3.5 {
        return ShadowRead {
            texel: Vec4::ZERO,
            held: 0.0,
        };
    }
    let local = vec2(lane_of(u, k), lane_of(v, k)) + Vec2::splat(0.5);
    let columns = atlas_columns(s.cascade_count) as f32;
    let rows = atlas_rows(s.cascade_count) as f32;
    let row = (k / columns).floor();
    let column = k - row * columns;
    let texel = SHADOW_MAP.get().sample_level(
        &LINEAR_REPEAT.get(),
        vec2((column + local.x) / columns, (row + local.y) / rows),
        0.0,
    );
    // Fade the optical depth out over the outer fifth of the last cascade: beyond it nothing
    // is known and nothing shadows, and a shadow cut off there was a straight-edged wedge on
    // the ground (and a jump in the light shafts) wherever the map's coverage ended.
    let last = lane_of(extent, count - 1.0) / margin;
    let fade = 1.0 - smoothstep(0.8, 1.0, last);
    ShadowRead {
        texel: vec4(texel.x, texel.y * fade, texel.z * fade, texel.w * fade),
        held: fade,
    }
}

/// Lane `k` of `v`, for a whole number `k` in 0..=3 held in a float, picked by a mask, not by
/// an index: a vector indexed by a value known only per pixel is spilled to memory and read
/// back by compilers that keep vectors in registers otherwise (SwiftShader: 3 % of `low`'s
/// frame in the browser benchmark, for the two such reads of [`shadow_read`]). A whole `k`
/// outside 0..=3 reads 0; every lane must be finite (an infinite lane not picked is ∞·0).
#[shader_fn]
pub fn lane_of(v: Vec4, k: f32) -> f32 {
    v.dot(step(
        (vec4(0.0, 1.0, 2.0, 3.0) - Vec4::splat(k)).abs(),
        Vec4::splat(0.5),
    ))
}

/// The largest front depth (m) the shadow atlas stores: half floats end at 65,504.
pub const SHADOW_DEPTH_LIMIT: f32 = 65_000.0;

/// Density at `position` (camera-relative; a sample `footprint` metres across) of the layers
/// that cast shadows: what the shadow map holds. A layer whose genus says it casts none (the
/// nimbostratus' scud under its deck) is left out here, as @takram/three-clouds leaves out the
/// layers its `shadowLayerMask` clears, and drawn as usual by the view march. As in
/// [`super::march::total_density`], the erosion is not run where no casting layer has weather.
#[shader_fn]
pub fn shadow_casting_density(
    position: Vec3,
    altitude: f32,
    footprint: f32,
    #[spec] key: CloudKey,
) -> f32 {
    let u = CLOUDS.get();
    let p = position + u.camera_offset;
    let mut sum = 0.0f32;
    for group in 0u32..key_count(key, GROUPS) {
        let casts = u.groups[group as usize].shadow_mask;
        // Eroded as the view march erodes them (the turbulence's push follows all the cloud
        // there), then only the casting lanes kept.
        let coverage = weather_density(p, altitude, group, key);
        if coverage.dot(casts) > 0.0 {
            sum += eroded_density(p, altitude, group, coverage, footprint, key).dot(casts);
        }
    }
    sum
}

/// One texel of the shadow atlas: march along the sun's rays, down from the top of the
/// shadow-casting layers, and store front depth (transmittance-weighted mean distance, m),
/// mean extinction, maximum optical depth and the tail beyond an early termination.
#[shader_fn]
pub fn shadow_fragment(frag_coord: Vec4, #[spec] key: CloudKey) -> Vec4 {
    let u = CLOUDS.get();
    let s = u.shadow;
    let m = u.march;
    let sun = u.light.sun_direction;
    let column = (frag_coord.x / s.map_size).floor();
    let row = (frag_coord.y / s.map_size).floor();
    let k = column + row * atlas_columns(s.cascade_count) as f32;
    if k >= s.cascade_count as f32 {
        // The grid's empty corner: no cascade, never sampled.
        return Vec4::ZERO;
    }
    let local = vec2(
        frag_coord.x - column * s.map_size,
        frag_coord.y - row * s.map_size,
    ) / s.map_size
        - Vec2::splat(0.5);
    let base = local * lane_of(s.cascade_scales, k) + Vec2::splat(0.5);
    let top = (s.inverse_matrix * vec4(base.x, base.y, 0.0, 1.0)).xyz();
    let sigma_ratio = u.light.scattering_coefficient + u.light.absorption_coefficient;
    // Through the whole slab of shadow-casting layers, however low the sun.
    let length = ((m.shadow_top_height - m.min_height) / sun.y.max(0.01)).min(m.max_ray_distance);
    let step_size = (length / (s.max_iterations.max(1u32) as f32)).clamp(s.min_step, s.max_step);
    // What one texel stands for across (m): the detail finer than that is its mean here, or
    // each texel picks one noise value and the map is a blocky mosaic when magnified.
    let footprint = (s.inverse_matrix * vec4(1.0, 0.0, 0.0, 0.0)).xyz().length()
        * lane_of(s.cascade_scales, k)
        / s.map_size;
    let mut t = step_size * 0.5;
    let mut transmittance = 1.0f32;
    let mut optical_depth = 0.0f32;
    let mut extinction_sum = 0.0f32;
    let mut samples = 0.0f32;
    let mut depth_sum = 0.0f32;
    let mut weight_sum = 0.0f32;
    let mut end = length;
    for _i in 0u32..s.max_iterations {
        if t > length {
            break;
        }
        let p = top - sun * t;
        let h = altitude_at(p, u.camera_altitude, m.radius);
        let sigma_t = shadow_casting_density(p, h, footprint, key) * sigma_ratio;
        if sigma_t > s.min_extinction {
            extinction_sum += sigma_t;
            samples += 1.0;
            depth_sum += t * transmittance;
            weight_sum += transmittance;
            optical_depth += sigma_t * step_size;
            transmittance = (-optical_depth).exp();
            if transmittance <= s.min_transmittance {
                end = t;
                break;
            }
        }
        t += step_size;
    }
    // Depths stay within what the half-float atlas holds: the march's reach (100–200 km) was
    // +∞ there, and filtering between such a texel and a cloudy one is undefined (SwiftShader
    // and lavapipe disagreed by a whole shadow along a texel's edge near the camera).
    let far = length.min(SHADOW_DEPTH_LIMIT);
    if samples < 0.5 {
        // No medium on this sun ray: nothing shadows, whatever the depth; the end of the ray
        // through the slab, so that filtering towards a cloudy texel fades its shadow out.
        return vec4(far, 0.0, 0.0, 0.0);
    }
    let mean_extinction = extinction_sum / samples;
    let tail = mean_extinction * (length - end).max(0.0) * s.tail_scale;
    vec4(
        (depth_sum / weight_sum.max(1e-20)).min(far),
        mean_extinction,
        optical_depth,
        tail,
    )
}

/// The cascades' transforms for the sun as it is: every tile's lookup, and back from cascade 0
/// on the top plane (what the shadow pass draws from).
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct ShadowMatrices {
    pub lookup: CascadeLookup,
    pub inverse_matrix: Mat4,
}

/// The cascade transforms for a sun direction: cascade 0 is `extent` metres on a side, centred
/// on where the sun's ray through the middle of the layers below the camera meets the plane at
/// `top_altitude`; cascade `k` is `scales[k]` times its side about the same centre.
#[shader_fn]
pub fn shadow_matrices(
    sun_direction: Vec3,
    camera_altitude: f32,
    top_altitude: f32,
    mid_altitude: f32,
    extent: f32,
    scales: Vec4,
) -> ShadowMatrices {
    // A sun at the horizon would stretch the projection without bound; shadows fade long
    // before, so a floor on its height keeps the transform finite.
    let sun = Vec3::new(sun_direction.x, sun_direction.y.max(0.05), sun_direction.z);
    let sx = sun.x / sun.y;
    let sz = sun.z / sun.y;
    let y_top = top_altitude - camera_altitude;
    let y_mid = mid_altitude - camera_altitude;
    let cx = sx * (y_top - y_mid);
    let cz = sz * (y_top - y_mid);
    // Tile k: x_top = p.x + sx·(y_top − p.y); u = (x_top − cx) / (extent · scale_k) + 0.5
    // (likewise z → v): one column per coordinate of p, one component per tile.
    let inv = Vec4::ONE / (scales * extent);
    let lookup = CascadeLookup {
        u: Mat4::from_cols(
            inv,
            -sx * inv,
            Vec4::ZERO,
            (sx * y_top - cx) * inv + Vec4::splat(0.5),
        ),
        v: Mat4::from_cols(
            Vec4::ZERO,
            -sz * inv,
            inv,
            (sz * y_top - cz) * inv + Vec4::splat(0.5),
        ),
    };
    let inverse_matrix = Mat4::from_cols(
        Vec4::new(extent, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 0.0, extent, 0.0),
        Vec4::ZERO,
        Vec4::new(cx - 0.5 * extent, y_top, cz - 0.5 * extent, 1.0),
    );
    ShadowMatrices {
        lookup,
        inverse_matrix,
    }
}

/// `lookup` read from positions `shift` metres away: what a point `p` reads is what `p + shift`
/// read before.
#[shader_fn]
pub fn shifted_lookup(lookup: CascadeLookup, shift: Vec3) -> CascadeLookup {
    let moved = Mat4::from_cols(
        vec4(1.0, 0.0, 0.0, 0.0),
        vec4(0.0, 1.0, 0.0, 0.0),
        vec4(0.0, 0.0, 1.0, 0.0),
        shift.extend(1.0),
    );
    CascadeLookup {
        u: lookup.u * moved,
        v: lookup.v * moved,
    }
}

/// Where the clouds stand relative to the camera's frame: the camera's place in the noise
/// (its horizontal offset less the wind's drift at the ground) and its altitude. Cascades in
/// rotation keep each tile's transform relative to this ([`redrawn_tiles`]), so that a tile
/// drawn frames ago is read where its clouds are now, however the camera or the wind moved
/// since (the wind's shear aside, which the tile's next redraw catches up with).
#[shader_fn]
pub fn shadow_anchor(camera_offset: Vec3, camera_altitude: f32, wind_drift: Vec2) -> Vec3 {
    vec3(
        camera_offset.x - wind_drift.x,
        camera_altitude,
        camera_offset.z - wind_drift.y,
    )
}

/// Cascades in rotation: the tiles a host keeps, relative to the clouds' anchor. The tiles
/// redrawn this frame (`redraw`, 1 per tile, 0 otherwise) take `current` (the sun's lookup
/// as [`super::sun::sun_light`] gives it, around the camera) made relative to `anchor`; the
/// others keep what they were drawn with. Read them with [`anchored_tiles`].
#[shader_fn]
pub fn redrawn_tiles(
    kept: CascadeLookup,
    current: CascadeLookup,
    anchor: Vec3,
    redraw: Vec4,
) -> CascadeLookup {
    let fresh = shifted_lookup(current, -anchor);
    CascadeLookup {
        u: tiles_mixed(kept.u, fresh.u, redraw),
        v: tiles_mixed(kept.v, fresh.v, redraw),
    }
}

/// The lookup of tiles kept relative to the clouds' anchor ([`redrawn_tiles`]), for a frame
/// whose anchor is `anchor`: the block's `shadow.lookup`.
#[shader_fn]
pub fn anchored_tiles(kept: CascadeLookup, anchor: Vec3) -> CascadeLookup {
    shifted_lookup(kept, anchor)
}

/// Each tile's row of `fresh` where `redraw` is 1, of `kept` where it is 0 (exactly: a
/// product by 0 or 1 and a sum with 0 round nothing).
#[shader_fn]
pub fn tiles_mixed(kept: Mat4, fresh: Mat4, redraw: Vec4) -> Mat4 {
    let keep = Vec4::ONE - redraw;
    Mat4::from_cols(
        kept.col(0) * keep + fresh.col(0) * redraw,
        kept.col(1) * keep + fresh.col(1) * redraw,
        kept.col(2) * keep + fresh.col(2) * redraw,
        kept.col(3) * keep + fresh.col(3) * redraw,
    )
}
