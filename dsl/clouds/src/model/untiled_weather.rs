//! The genus' weather without the weather tile's repetition.
//!
//! One tile of weather is 100 km. A view from high above crosses ten tiles and more, and the
//! same clusters of clouds came back at the same spacing along both axes of the tile: rows and
//! columns of look-alike cloud fields that the eye picks out at once (the "speckle" of the
//! orbit views lined up on this lattice). After Mikkelsen's hex tiling ("Practical Real-Time
//! Hex-Tiling", JCGT 2022), the plane is laid under a triangle lattice a little under a tile
//! apart; around each vertex the genus' weather is evaluated at an offset of the vertex's own
//! (a hash of it, up to a tile), and only in narrow bands between the vertices' regions are two
//! or three evaluations blended. No two neighbouring regions show the same part of the tile,
//! so nothing repeats on any period.
//!
//! It works on the genus' weather function as a whole, so every function (the built-in ones,
//! those computed in place, a genus' own) loses its repetition alike. Only translations: the
//! genera drawn out along the wind (cirrus streaks, rows across the wind) keep their direction.
//! The vertex at the origin has no offset, so a painted weather map lies as painted around the
//! point it was painted for. A toggle (`untiled-weather`), because its lattice arithmetic costs
//! about a fifth of the frame on a CPU rasteriser that runs both sides of every branch; the
//! scene analysis chooses it for views from high above (`analysis::untiled_weather`).

use glam::{Vec2, Vec3, Vec4};

use nimbus_dsl::prelude::*;

use super::genus_fns::raised_weather;
use super::layers::LayerGroup;
use crate::key::CloudKey;

/// Lattice vertices this many tiles apart: each vertex's region (where it alone is evaluated)
/// is under a tile across, so no region holds a repeat of itself.
const SPACING: f32 = 0.75;

/// Width of the blend between two vertices' regions, in barycentric weight: 0.05 is a band
/// about 2.5 km wide on either side of a border at the 100 km tile, 9 % of the plane. The
/// blend is linear, so in the bands the weather has less spread than elsewhere (two unrelated
/// fields averaged): about a fifth less, on a tenth of the plane, where a wider band would
/// draw a hexagonal net of paler lanes.
const BAND: f32 = 0.05;

/// The three lattice vertices around a point and their weights.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct HexCorners {
    /// The vertices, in the skewed lattice's integer coordinates.
    pub v1: Vec2,
    pub v2: Vec2,
    pub v3: Vec2,
    /// Their weights (summing to 1): a single 1 away from the borders between their regions.
    pub weights: Vec3,
}

/// The lattice vertices around `uv` (tiles) and their weights.
#[shader_fn]
pub fn hex_corners(uv: Vec2) -> HexCorners {
    let st = uv * (1.0 / SPACING);
    // Skewed so that the triangle lattice's vertices fall on integer coordinates.
    let skewed = vec2(st.x - st.y * 0.577_350_3, st.y * 1.154_700_5);
    let base = skewed.floor();
    let f = skewed - base;
    let z = 1.0 - f.x - f.y;
    // The triangle holding `uv`: its vertices and their barycentric weights.
    let mut v1 = base;
    let mut v2 = base + vec2(0.0, 1.0);
    let mut v3 = base + vec2(1.0, 0.0);
    let mut b = vec3(z, f.y, f.x);
    if z < 0.0 {
        v1 = base + vec2(1.0, 1.0);
        v2 = base + vec2(1.0, 0.0);
        v3 = base + vec2(0.0, 1.0);
        b = vec3(-z, 1.0 - f.y, 1.0 - f.x);
    }
    // A vertex weighs what its barycentric weight comes within `BAND` of the largest: one
    // evaluation wherever one vertex leads by more than that.
    let lead = b.x.max(b.y).max(b.z) - BAND;
    let c = (b - Vec3::splat(lead)).max(Vec3::ZERO);
    HexCorners {
        v1,
        v2,
        v3,
        weights: c / (c.x + c.y + c.z),
    }
}

/// The key's genus weather at `xz` (noise-space metres), whose tile coordinates are `uv`,
/// without the tile's repetition: the weather read at `uv` shifted by the offsets of the
/// lattice vertices around it, blended only near the borders of their regions. The lattice
/// lies in the tile coordinates (with the wind's offset), so it drifts with the weather.
#[shader_fn]
pub fn untiled_weather(xz: Vec2, uv: Vec2, layers: LayerGroup, #[spec] key: CloudKey) -> Vec4 {
    let h = hex_corners(uv);
    let w = h.weights;
    let mut weather = Vec4::ZERO;
    if w.x > 0.0 {
        weather += raised_weather(xz, uv + vertex_offset(h.v1), layers, key) * w.x;
    }
    if w.y > 0.0 {
        weather += raised_weather(xz, uv + vertex_offset(h.v2), layers, key) * w.y;
    }
    if w.z > 0.0 {
        weather += raised_weather(xz, uv + vertex_offset(h.v3), layers, key) * w.z;
    }
    weather
}

/// The offset (tiles, in [0, 1)²) at which lattice vertex `vertex` reads the weather: a hash of
/// the vertex, none at the origin.
#[shader_fn]
pub fn vertex_offset(vertex: Vec2) -> Vec2 {
    // Negative lattice coordinates wrap to large words alike in Rust and the shaders.
    let mut h = (vertex.x as i32 as u32).wrapping_mul(0x27d4_eb2du32)
        ^ (vertex.y as i32 as u32).wrapping_mul(0x1656_67b1u32);
    h = (h ^ (h >> 15u32)).wrapping_mul(0x85eb_ca6bu32);
    let mut offset = vec2((h & 65535u32) as f32, (h >> 16u32) as f32) * (1.0 / 65536.0);
    if vertex.x == 0.0 && vertex.y == 0.0 {
        offset = Vec2::ZERO;
    }
    offset
}
