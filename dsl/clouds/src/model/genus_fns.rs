//! The built-in genus functions ([`crate::functions`]) and the three calls through which the
//! density reaches whichever functions the key names.
//!
//! `genus_weather`, `genus_shape` and `genus_profile` are hand-written twin pairs (like the
//! key's choices in [`super::choices`]): the CPU twin calls the key's function, the shader twin
//! records the key's function, so a specialised shader holds exactly the genus' code.

use glam::{Vec2, Vec4};

use nimbus_dsl::prelude::*;
use nimbus_dsl::shader;

use super::bindings::{CLOUDS, LINEAR_REPEAT, WEATHER};
use super::density::shape_altering;
use super::layers::{LayerGroup, LayerGroupShader};
use super::noise::hash3;
use crate::functions::{HeightFn, WeatherFn};
use crate::key::CloudKey;
use crate::{height_fn, weather_fn};

/// The reference library's weather: each layer reads its channel of the weather texture (the
/// model raises it to the layer's weather exponent: [`weather_exponent`]).
#[shader_fn]
pub fn texture_weather(_xz: Vec2, uv: Vec2, layers: LayerGroup) -> Vec4 {
    let rgba = WEATHER.get().sample_level(&LINEAR_REPEAT.get(), uv, 0.0);
    (layers.channel_matrix * rgba).saturate()
}

/// Fibres: the weather texture stretched 12× along the wind (x) and squeezed 3× across it, so
/// a cell becomes a streak tens of kilometres long and a few wide, as cirrus uncinus and
/// fibratus are drawn out by the shear of the jet stream.
#[shader_fn]
pub fn streak_weather(_xz: Vec2, uv: Vec2, layers: LayerGroup) -> Vec4 {
    // `uv` holds the offset (the wind), so the field moves before it is stretched, as in every
    // weather function, and all genera drift alike.
    let rgba = WEATHER
        .get()
        .sample_level(&LINEAR_REPEAT.get(), uv * vec2(1.0 / 12.0, 3.0), 0.0);
    (layers.channel_matrix * rgba).saturate()
}

/// Few, large cells: the weather texture at a fifth of its frequency, so a 100 km tile holds a
/// handful of cells 10–20 km across, each the footprint of one storm (cumulonimbus stand apart,
/// not as a field of heaps).
#[shader_fn]
pub fn sparse_weather(_xz: Vec2, uv: Vec2, layers: LayerGroup) -> Vec4 {
    let rgba = WEATHER
        .get()
        .sample_level(&LINEAR_REPEAT.get(), uv * 0.2, 0.0);
    (layers.channel_matrix * rgba).saturate()
}

/// Cells within patches: the weather texture at its own scale decides where the deck is, the
/// same texture 9× finer breaks the deck into cells with clear gaps between them (the
/// cellular look of stratocumulus, altocumulus and cirrocumulus, whose cells are a few hundred
/// metres to a few kilometres across).
#[shader_fn]
pub fn cellular_weather(_xz: Vec2, uv: Vec2, layers: LayerGroup) -> Vec4 {
    let smp = LINEAR_REPEAT.get();
    let patches = WEATHER.get().sample_level(&smp, uv, 0.0);
    // The fine cells come from another part of the texture (offset), so they do not line up
    // with the patches they sit in.
    let cells = WEATHER
        .get()
        .sample_level(&smp, uv * 9.0 + vec2(0.37, 0.61), 0.0);
    let patch = (layers.channel_matrix * patches).saturate();
    let cell = (layers.channel_matrix * cells).saturate();
    // Inside a patch the cells decide; the product keeps gaps between cells even where the
    // patch is full.
    (patch.pow(Vec4::splat(0.5)) * cell).saturate()
}

/// Distance (in lattice units) from `p` to the nearest of the feature points, one per lattice
/// cell, each placed in the middle 70 % of its cell: 2-D cellular noise evaluated in place,
/// not read from a texture, so elements a hundred metres apart need no texture tile that would
/// repeat across the sky. Keeping the points off the cell borders makes the elements nearly
/// even in size and spacing, as the cells of cirrocumulus and altocumulus are.
#[shader_fn]
pub fn nearest_feature(p: Vec2, seed: u32) -> f32 {
    let cell = p.floor();
    let mut nearest = 4.0f32;
    for dy in -1i32..2i32 {
        for dx in -1i32..2i32 {
            let c = cell + vec2(dx as f32, dy as f32);
            // Negative lattice coordinates wrap to large words alike in Rust and the shaders.
            let h = hash3(c.x as i32 as u32, c.y as i32 as u32, seed);
            let jitter = vec2((h & 65535u32) as f32, (h >> 16u32) as f32) * (0.7 / 65535.0)
                + Vec2::splat(0.15);
            nearest = nearest.min((c + jitter - p).length());
        }
    }
    nearest
}

/// Cumuliform elements about `spacing` metres apart, lined up in rows `rows` spacings apart
/// across the wind (x), within the patches of the layer's weather channel: the cells "in groups
/// and rows" of altocumulus and the grains and ripples of cirrocumulus, whose names differ by
/// the elements' size (WMO: under 1° wide seen more than 30° above the horizon for
/// cirrocumulus, 1° to 5° for altocumulus). The rows bend with a slow field, as billows do.
///
/// Elements smaller than a pixel would be noise: beyond `fade` metres from the camera they give
/// way to a sheet at `level`, the signal whose density after the coverage remap is the
/// elements' mean at the genus' coverage (the remap is not linear, so the signal's own mean,
/// 0.19, is not that level in general). The distance is taken in the plane before the wind's
/// drift, which an animation moves by far less than the fade's width.
#[shader_fn]
pub fn elements_in_rows(
    xz: Vec2,
    uv: Vec2,
    layers: LayerGroup,
    spacing: f32,
    rows: f32,
    fade: f32,
    level: f32,
) -> Vec4 {
    let u = CLOUDS.get();
    let smp = LINEAR_REPEAT.get();
    let patch = (layers.channel_matrix * WEATHER.get().sample_level(&smp, uv, 0.0)).saturate();
    let bend = WEATHER
        .get()
        .sample_level(&smp, uv * 23.0 + vec2(0.71, 0.29), 0.0)
        .z;
    let p = xz / spacing;
    // 1 at a feature point, 0 from 0.75 spacings away: round elements, close-packed, with
    // narrow gaps where the coverage cuts them.
    let element = (1.0 - nearest_feature(p, 11u32) / 0.75).clamp(0.0, 1.0);
    let phase = (p.x + bend * rows * 3.0) * (TAU / rows);
    let row = 0.4 + 0.6 * phase.cos();
    let camera = vec2(u.camera_offset.x, u.camera_offset.z);
    let far = smoothstep(0.5 * fade, fade, (xz - camera).length());
    let detail = mix(element * row, level, far);
    (patch.pow(Vec4::splat(0.5)) * detail).saturate()
}

/// The reference library's weather exponent: each layer's signal, whatever the genus' weather
/// function made it, raised to the layer's `weather_exponent`. The model applies it after the
/// weather function ([`genus_exponent`]), so no weather function repeats it.
#[shader_fn]
pub fn weather_exponent(signal: Vec4, layers: LayerGroup) -> Vec4 {
    signal.pow(layers.weather_exponent)
}

/// [`weather_exponent`] where every layer's exponent is 1: the signal as it is, without a
/// power per lane and sample (4 of a density sample's transcendentals). A key gets it wherever
/// that is exact ([`crate::GenusFunctions::for_layers`]).
#[shader_fn]
pub fn unit_exponent(signal: Vec4, _layers: LayerGroup) -> Vec4 {
    signal
}

/// The key's genus weather at `xz` (tile coordinates `uv`) raised to the layers' weather
/// exponents: the signal the coverage remap reads. The untiled weather blends several of these,
/// each raised before the blend, as the tiled weather is.
#[shader_fn]
pub fn raised_weather(xz: Vec2, uv: Vec2, layers: LayerGroup, #[spec] key: CloudKey) -> Vec4 {
    genus_exponent(key, genus_weather(key, xz, uv, layers), layers)
}

/// A whole turn, for the rows' phase.
const TAU: f32 = core::f32::consts::TAU;

/// Cirrocumulus: grains 120 m apart (0.7° seen 45° up at 7 km), in ripples 2.5 grains apart;
/// beyond 25 km a grain is under 0.3° and gives way to the sheet (level for coverage 0.65).
#[shader_fn]
pub fn grain_weather(xz: Vec2, uv: Vec2, layers: LayerGroup) -> Vec4 {
    elements_in_rows(xz, uv, layers, 120.0, 2.5, 25_000.0, 0.23)
}

/// Altocumulus: rounded cells 300 m apart (3.3° seen 35° up at 3 km), in rows 2 cells apart;
/// beyond 60 km a cell is under 0.3° and gives way to the sheet (level for coverage 0.6).
#[shader_fn]
pub fn cell_rows_weather(xz: Vec2, uv: Vec2, layers: LayerGroup) -> Vec4 {
    elements_in_rows(xz, uv, layers, 300.0, 2.0, 60_000.0, 0.2)
}

/// The reference library's shape: `1 − x²` with `x = 2η^bias − 1`, zero at both ends of the
/// layer, widest at `η = 0.5^(1/bias)`: clouds rounded at the top and the bottom.
#[shader_fn]
pub fn rounded_shape(eta: Vec4, layers: LayerGroup) -> Vec4 {
    shape_altering(eta, layers.shape_altering_bias)
}

/// A cumulonimbus: a flat base reached within the lowest 3 % of the layer, a tower that narrows
/// slowly with height, and from 72 % of the height an anvil that spreads out to 1.5× the
/// tower's width, levelled off under a flat top (the tropopause). The spread makes the
/// coverage threshold low near the top, so the anvil covers far more ground than the tower
/// below it. `shape_altering_bias` moves the anvil: 1 puts its widest point at 88 % of the
/// height, smaller values lower it.
#[shader_fn]
pub fn anvil_shape(eta: Vec4, layers: LayerGroup) -> Vec4 {
    let h = eta.pow(layers.shape_altering_bias);
    let base = (eta / 0.03).saturate();
    let tower = Vec4::ONE - h * 0.3;
    let spread = smoothstep(Vec4::splat(0.72), Vec4::splat(0.88), h);
    let top = Vec4::ONE - smoothstep(Vec4::splat(0.94), Vec4::ONE, eta);
    base * (tower + spread * 0.4) * top
}

/// The reference library's profile `a·e^(b·η) + c·η + d` with each layer's coefficients
/// (|b| ≤ 80 is validated, so the exponential is finite and `0·e^(bη)` is 0).
#[shader_fn]
pub fn exponential_profile(eta: Vec4, layers: LayerGroup) -> Vec4 {
    layers.profile_a * (layers.profile_b * eta).exp() + layers.profile_c * eta + layers.profile_d
}

/// [`exponential_profile`] where every layer's exponential term is a constant (`a = 0` or
/// `b = 0`, as in every example genus): `a + c·η + d`, the same numbers without an exponential
/// per lane and sample. A key gets it in place of the exponential form wherever that is exact
/// ([`crate::GenusFunctions::for_layers`]).
#[shader_fn]
pub fn linear_profile(eta: Vec4, layers: LayerGroup) -> Vec4 {
    layers.profile_a + layers.profile_c * eta + layers.profile_d
}

pub const TEXTURE_WEATHER: WeatherFn = weather_fn!(
    texture_weather,
    "each layer's channel of the weather texture, raised to its weather exponent"
);
pub const STREAK_WEATHER: WeatherFn = weather_fn!(
    streak_weather,
    "the weather texture stretched 12x along x and squeezed 3x across: fibres and streaks"
);
pub const SPARSE_WEATHER: WeatherFn = weather_fn!(
    sparse_weather,
    "the weather texture at a fifth of its frequency: a few cells 10-20 km across, one storm each"
);
pub const CELLULAR_WEATHER: WeatherFn = weather_fn!(
    cellular_weather,
    "patches of the weather texture broken into cells 9x finer, with gaps between them"
);
pub const GRAIN_WEATHER: WeatherFn = weather_fn!(
    grain_weather,
    "grains 120 m apart in ripples across the wind, within patches: cirrocumulus"
);
pub const CELL_ROWS_WEATHER: WeatherFn = weather_fn!(
    cell_rows_weather,
    "rounded cells 300 m apart in rows across the wind, within patches: altocumulus"
);
pub const ROUNDED_SHAPE: HeightFn = height_fn!(
    rounded_shape,
    "1 - (2 eta^bias - 1)^2: rounded at top and bottom (the reference library's)"
);
pub const ANVIL_SHAPE: HeightFn = height_fn!(
    anvil_shape,
    "flat base, narrowing tower, anvil spreading to 1.5x from 75% of the height, flat top"
);
pub const EXPONENTIAL_PROFILE: HeightFn = height_fn!(
    exponential_profile,
    "a e^(b eta) + c eta + d with the layer's coefficients (the reference library's)"
);
pub const WEATHER_EXPONENT: HeightFn = height_fn!(
    weather_exponent,
    "signal^exponent with each layer's weather exponent (the reference library's)"
);
pub const UNIT_EXPONENT: HeightFn = height_fn!(
    unit_exponent,
    "the weather signal as it is: the weather exponent where every layer's is 1 (chosen for you)"
);
pub const LINEAR_PROFILE: HeightFn = height_fn!(
    linear_profile,
    "a + c eta + d: the reference library's profile where each layer's a or b is 0 (chosen for you)"
);

/// The built-in height functions (for shapes and profiles).
pub fn builtin_height_fns() -> Vec<HeightFn> {
    vec![
        ROUNDED_SHAPE,
        ANVIL_SHAPE,
        EXPONENTIAL_PROFILE,
        LINEAR_PROFILE,
    ]
}

/// The built-in weather functions.
pub fn builtin_weather_fns() -> Vec<WeatherFn> {
    vec![
        TEXTURE_WEATHER,
        STREAK_WEATHER,
        CELLULAR_WEATHER,
        SPARSE_WEATHER,
        GRAIN_WEATHER,
        CELL_ROWS_WEATHER,
    ]
}

/// One call through the key's genus height function of `slot`: the CPU twin calls the
/// function's CPU twin, the shader twin (`$name::shader`, found by the `#[shader_fn]` call
/// convention of `nimbus_dsl::twin`) records its shader twin. Written once for the two height
/// slots ([`genus_weather`] takes the tile coordinates besides).
macro_rules! genus_slot {
    ($(#[$doc:meta])* $name:ident, $twin:ident, $slot:ident, $arg:ident: $cpu:ty => $dsl:ty) => {
        $(#[$doc])*
        pub fn $name(key: CloudKey, $arg: $cpu, layers: LayerGroup) -> Vec4 {
            (key.functions.$slot.cpu)($arg, layers)
        }

        #[doc(hidden)]
        pub use $name::shader as $twin;

        #[doc = concat!("Shader twin of [`", stringify!($name), "()`](fn@", stringify!($name), ").")]
        pub mod $name {
            use super::*;

            pub fn shader(
                key: CloudKey,
                $arg: impl Into<$dsl>,
                layers: impl Into<LayerGroupShader>,
            ) -> shader::Vec4 {
                (key.functions.$slot.shader)($arg.into(), layers.into())
            }
        }
    };
}

/// The weather signal of the key's genus at `xz`, read from the weather tile at `uv` (CPU
/// twin; see [`WeatherFn`]).
pub fn genus_weather(key: CloudKey, xz: Vec2, uv: Vec2, layers: LayerGroup) -> Vec4 {
    (key.functions.weather.cpu)(xz, uv, layers)
}

#[doc(hidden)]
pub use genus_weather::shader as __shader_twin_genus_weather;

/// Shader twin of [`genus_weather()`](fn@genus_weather).
pub mod genus_weather {
    use super::*;

    pub fn shader(
        key: CloudKey,
        xz: impl Into<shader::Vec2>,
        uv: impl Into<shader::Vec2>,
        layers: impl Into<LayerGroupShader>,
    ) -> shader::Vec4 {
        (key.functions.weather.shader)(xz.into(), uv.into(), layers.into())
    }
}

genus_slot!(
    /// The coverage shape of the key's genus at height fractions `eta` (CPU twin).
    genus_shape, __shader_twin_genus_shape, shape, eta: Vec4 => shader::Vec4
);
genus_slot!(
    /// The key's weather exponent applied to the weather `signal` of each layer (CPU twin):
    /// [`weather_exponent`], or [`unit_exponent`] where every exponent is 1.
    genus_exponent, __shader_twin_genus_exponent, exponent, signal: Vec4 => shader::Vec4
);
genus_slot!(
    /// The density profile of the key's genus at height fractions `eta` (CPU twin).
    genus_profile, __shader_twin_genus_profile, profile, eta: Vec4 => shader::Vec4
);
