//! Cloud density at a point, for four layers at once: height fraction, the shape-altering
//! (rounding) function, coverage remap against the weather signal, shape and detail erosion,
//! turbulent displacement and the vertical density profile. Formulas follow
//! @takram/three-clouds (`clouds.glsl`), with its divisions by zero guarded.

use glam::{Vec2, Vec3, Vec4};

use nimbus_dsl::prelude::*;

use super::bindings::{CLOUDS, DETAIL, LINEAR_REPEAT, SHAPE, TURBULENCE, WEATHER};
use super::choices::{SHAPE_DETAIL, TURBULENCE as TURBULENCE_ON, UNTILED_WEATHER, gate};
use super::genus_fns::{genus_profile, genus_shape, raised_weather};
use super::layers::LayerGroup;
use super::noise::{DETAIL_MOMENTS, DETAIL_SIZE};
use super::untiled_weather::untiled_weather;
use crate::key::CloudKey;

/// Sampling frequencies and offsets of the textures, and the coverage.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct MediaParams {
    /// Fraction of the sky covered, 0..1.
    pub coverage: f32,
    /// Turbulent displacement at cloud bases (m).
    pub turbulence_displacement: f32,
    /// Weather texture repeats per metre (x, z) and offset (tiles).
    pub weather_repeat: Vec2,
    pub weather_offset: Vec2,
    /// Turbulence texture repeats per weather tile.
    pub turbulence_repeat: Vec2,
    /// Shape (Perlin–Worley) texture repeats per metre and offset (tiles).
    pub shape_repeat: Vec3,
    pub shape_offset: Vec3,
    /// Detail (Worley) texture repeats per metre and offset (tiles).
    pub detail_repeat: Vec3,
    pub detail_offset: Vec3,
    /// How much the planet-scale weather ([`planet_coverage`]) moves the coverage beyond the
    /// viewer's surroundings: 0 (every tile alike) to 1.
    pub planet_weather: f32,
    /// Footprints (m) between which the detail noise gives way to its mean: all detail while a
    /// sample stands for less than `x`, none from `y` on ([`detail_level`]). Set with
    /// [`MediaParams::with_detail_lod`] from the texture's texel size.
    pub detail_fade: Vec2,
    /// Means of the detail noise `d` and of `d⁶` over the texture: the erosion's inputs where
    /// the detail is finer than a sample's footprint.
    pub detail_moments: Vec2,
    /// How far the wind has carried the clouds (m, x and z) at the ground, and how much more
    /// per metre of altitude (shear): see [`wind_drifted`] and `crate::wind`.
    pub wind_drift: Vec2,
    pub wind_shear_drift: Vec2,
}

impl Default for MediaParams {
    fn default() -> Self {
        Self {
            coverage: 0.3,
            turbulence_displacement: 350.0,
            weather_repeat: Vec2::splat(1.0 / 100_000.0),
            weather_offset: Vec2::ZERO,
            turbulence_repeat: Vec2::splat(20.0),
            shape_repeat: Vec3::splat(1.5e-4),
            shape_offset: Vec3::ZERO,
            detail_repeat: Vec3::splat(6e-3),
            detail_offset: Vec3::ZERO,
            planet_weather: 1.0,
            detail_fade: Vec2::ZERO,
            detail_moments: Vec2::ZERO,
            wind_drift: Vec2::ZERO,
            wind_shear_drift: Vec2::ZERO,
        }
        .with_detail_lod(DETAIL_SIZE, DETAIL_MOMENTS)
    }
}

/// Footprints, in detail texels, over which the detail noise fades to its mean: the finest
/// Worley octave has cells two texels across, so a sample half a texel across still resolves
/// it; by two texels it would alias, and what a pixel shows there is the noise's mean.
pub const DETAIL_FADE_TEXELS: Vec2 = Vec2::new(0.5, 2.0);

impl MediaParams {
    /// The detail level of detail for a detail texture of `size` texels per side (at this
    /// `detail_repeat`) whose red channel has the means `moments` (`d`, `d⁶`).
    pub fn with_detail_lod(mut self, size: u32, moments: Vec2) -> Self {
        let texel = 1.0 / (self.detail_repeat.max_element().max(1e-9) * size.max(1) as f32);
        self.detail_fade = DETAIL_FADE_TEXELS * texel;
        self.detail_moments = moments;
        self
    }
}

/// Largest density (extinction per metre at unit coefficients): a millimetre of it is optical
/// depth 1,000, opaque to any step; far from f32's overflow however it is multiplied.
pub const MAX_DENSITY: f32 = 1e6;

/// Height fraction η ∈ [0, 1] of `altitude` in each layer. A zero-height (absent) layer gives
/// 0 or 1, never 0/0.
#[shader_fn]
pub fn height_fraction(altitude: f32, layers: LayerGroup) -> Vec4 {
    let thickness = (layers.max_height - layers.min_height).max(Vec4::splat(1e-4));
    ((Vec4::splat(altitude) - layers.min_height) / thickness).saturate()
}

/// Rounds clouds towards their tops: `1 − x²` with `x = clamp(2η^bias − 1, −1, 1)`; 0 at both
/// ends of the layer, peak at η = 0.5^(1/bias).
#[shader_fn]
pub fn shape_altering(eta: Vec4, bias: Vec4) -> Vec4 {
    let x = (eta.pow(bias) * 2.0 - Vec4::ONE).clamp(Vec4::splat(-1.0), Vec4::ONE);
    Vec4::ONE - x * x
}

/// Coverage remap (after Skybolt): the weather signal must exceed `1 − coverage·S`, with a soft
/// edge of width `filter_width` (validated > 0).
#[shader_fn]
pub fn coverage_remap(weather: Vec4, coverage: f32, shape: Vec4, filter_width: Vec4) -> Vec4 {
    let threshold = Vec4::ONE - shape * coverage;
    let softened = weather + (Vec4::ONE - weather) * filter_width;
    ((softened - threshold) / filter_width).saturate()
}

/// Erodes density by the shape noise `s` (0..1) with strength `amount`.
#[shader_fn]
pub fn shape_erosion(density: Vec4, s: f32, amount: Vec4) -> Vec4 {
    let cut = amount * (1.0 - s);
    // (ρ − cut) / (1 − cut), with the denominator kept off 0 when the noise is 0 at full amount.
    ((density - cut) / (Vec4::ONE - cut).max(Vec4::splat(1e-5))).saturate()
}

/// Erodes density by the detail noise, given as its two erosion signals `wispy` (`d⁶`, at the
/// bottom) and `billowy` (`1 − d`, towards the top) so that a far sample can pass their means
/// ([`detail_level`]).
///
/// The reference computes `(2ρ − m/2) / (1 − m/2)`, whose gain of 2 applies even at amount 0,
/// so "detail on, amount 0" would be twice as dense as "detail off". Here the gain is
/// `1 + amount`: amount 1 is the reference, amount 0 leaves the density exactly as it is, so a
/// variant without the stage is exact for layers that do not use it.
#[shader_fn]
pub fn detail_erosion(density: Vec4, wispy: f32, billowy: f32, eta: Vec4, amount: Vec4) -> Vec4 {
    let t = ((eta - Vec4::splat(0.2)) / 0.2).saturate();
    let m = (Vec4::splat(wispy) + (Vec4::splat(billowy) - Vec4::splat(wispy)) * t) * amount;
    ((density * (Vec4::ONE + amount) - m * 0.5) / (Vec4::ONE - m * 0.5)).saturate()
}

/// Coverage-stage density of each layer of group `group` at a point (in noise space): what the
/// weather allows before erosion. The weather signal and the shape over height are the genus'
/// functions ([`crate::functions`]).
#[shader_fn]
pub fn weather_density(position: Vec3, altitude: f32, group: u32, #[spec] key: CloudKey) -> Vec4 {
    let layers = CLOUDS.get().groups[group as usize];
    let media = CLOUDS.get().media;
    let drifted = wind_drifted(position, altitude);
    let xz = vec2(drifted.x, drifted.z);
    let uv = xz * media.weather_repeat + media.weather_offset;
    let weather = if gate(key, UNTILED_WEATHER) {
        untiled_weather(xz, uv, layers, key)
    } else {
        raised_weather(xz, uv, layers, key)
    };
    let eta = height_fraction(altitude, layers);
    let shape = genus_shape(key, eta, layers);
    let coverage = planet_coverage(position, drifted, media.coverage);
    coverage_remap(weather, coverage, shape, layers.coverage_filter_width)
}

/// Where the air at `position` (noise space) and `altitude` was when the wind started: the
/// point whose noise it now carries. Weather, shape, detail and turbulence all read there, so
/// a cloud drifts whole, and a tall one leans downwind with the shear.
#[shader_fn]
pub fn wind_drifted(position: Vec3, altitude: f32) -> Vec3 {
    let media = CLOUDS.get().media;
    let d = media.wind_drift + media.wind_shear_drift * altitude;
    position - vec3(d.x, 0.0, d.y)
}

/// The coverage at `position` (noise space) under planet-scale weather. The weather texture
/// repeats every 100 km, so a long horizon or a view from orbit showed the same tile again
/// and again, each cell below a pixel: white noise. Beyond the viewer's surroundings the
/// coverage now follows a field of fronts and clear regions hundreds of kilometres across:
/// two octaves of the weather texture's smooth channels (b, a), 37× and 9× coarser and turned
/// against the tile grid, as a factor of mean ~1 (0.2 to 1.8). Within 30 km of the camera the coverage is the
/// one asked for, so a scene still gets the sky it names; the field fades in by 150 km.
///
/// `position` says how far from the camera the point is; `drifted` (the same point carried
/// back by the wind) where in the field it lies, so that fronts move with the wind.
#[shader_fn]
pub fn planet_coverage(position: Vec3, drifted: Vec3, coverage: f32) -> f32 {
    let u = CLOUDS.get();
    let media = u.media;
    let offset = position - u.camera_offset;
    let far = smoothstep(30_000.0, 150_000.0, offset.length()) * media.planet_weather;
    if far <= 0.0 {
        // Near the camera: no texture reads.
        return coverage;
    }
    // With the weather offset, so that fronts drift with the wind as the local weather does.
    let uv = vec2(drifted.x, drifted.z) * media.weather_repeat + media.weather_offset;
    // Turned by ~29° so that no grid line of the field runs along one of the tiles'.
    let turned = vec2(uv.x * 0.875 - uv.y * 0.485, uv.x * 0.485 + uv.y * 0.875);
    let smp = LINEAR_REPEAT.get();
    let fronts = WEATHER
        .get()
        .sample_level(&smp, turned * (1.0 / 37.0) + vec2(0.31, 0.77), 0.0)
        .z;
    let systems = WEATHER
        .get()
        .sample_level(&smp, turned * (1.0 / 9.0) + vec2(0.53, 0.11), 0.0)
        .w;
    let field = (fronts * 0.65 + systems * 0.35).saturate();
    // Centred on the field's own mean (0.47), so the factor averages 1.
    let factor = 0.2 + 1.6 * smoothstep(0.12, 0.82, field);
    (coverage * (1.0 + (factor - 1.0) * far)).saturate()
}

/// How far the detail noise has given way to its mean for a sample that stands for
/// `footprint` metres (0: all detail, 1: only the mean).
///
/// The detail noise has 5 m features (a 32³ tile per 167 m). A pixel 5 km away at 640 × 360
/// covers 16 m: one noise value picked per pixel was a mosaic of unrelated values that did not
/// average out over accumulated frames, and single bright pixels on cloud edges; in the shadow
/// map each 40 m texel picked one, a blocky pattern when magnified at a low sun. What such a
/// sample should see is the noise's mean over its footprint, as a mip-mapped texture would give.
/// The erosion's numerator is linear in its two signals; its divisor and clamp are not, so the
/// means stand in for the mean erosion (as a mip level would), not exactly.
#[shader_fn]
pub fn detail_level(footprint: f32) -> f32 {
    let fade = CLOUDS.get().media.detail_fade;
    smoothstep(fade.x, fade.y, footprint)
}

/// Density of each layer of group `group` at `position` (noise space: camera-relative metres in
/// the local tangent frame, y up, plus the camera's offset) and `altitude` (m above the ground),
/// with the erosion stages of `key`, for a sample that stands for `footprint` metres across
/// (0: a point).
#[shader_fn]
pub fn layer_density(
    position: Vec3,
    altitude: f32,
    group: u32,
    footprint: f32,
    #[spec] key: CloudKey,
) -> Vec4 {
    let coverage = weather_density(position, altitude, group, key);
    eroded_density(position, altitude, group, coverage, footprint, key)
}

/// [`layer_density`] from the coverage-stage density `coverage` ([`weather_density`]) already
/// read at the same point: the primary march tests coverage before it pays for erosion, and
/// reads the weather once for both.
#[shader_fn]
pub fn eroded_density(
    position: Vec3,
    altitude: f32,
    group: u32,
    coverage: Vec4,
    footprint: f32,
    #[spec] key: CloudKey,
) -> Vec4 {
    let layers = CLOUDS.get().groups[group as usize];
    let media = CLOUDS.get().media;
    let smp = LINEAR_REPEAT.get();
    let eta = height_fraction(altitude, layers);
    // The 3D noise is read at the altitude, not at the height above the camera: with the
    // camera's height the clouds' shapes moved up and down through the noise, and they changed
    // as a camera climbed (seen first by the orthographic camera, whose picture straight down
    // must not depend on its height); the planet's curvature no longer bends it either.
    let drifted = wind_drifted(position, altitude);
    let mut p = vec3(drifted.x, altitude, drifted.z);
    if gate(key, TURBULENCE_ON) {
        let uv = vec2(p.x, p.z) * media.weather_repeat * media.turbulence_repeat;
        let curl = TURBULENCE.get().sample_level(&smp, uv, 0.0).xyz() * 2.0 - Vec3::ONE;
        // Strongest at the base, gone by η = 0.3, weighted by how much cloud is there.
        let fade = ((Vec4::splat(0.3) - eta) / 0.3).saturate();
        p += curl * (media.turbulence_displacement * coverage.dot(fade));
    }
    let s = SHAPE
        .get()
        .sample_level(&smp, p * media.shape_repeat + media.shape_offset, 0.0)
        .x;
    let mut density = shape_erosion(coverage, s, layers.shape_amount);
    if gate(key, SHAPE_DETAIL) {
        let level = detail_level(footprint);
        let mut d = media.detail_moments.x;
        let mut d6 = media.detail_moments.y;
        // Beyond the fade no texture read at all: far samples are cheaper, not only smoother.
        if level < 1.0 {
            let n = DETAIL
                .get()
                .sample_level(&smp, p * media.detail_repeat + media.detail_offset, 0.0)
                .x;
            d = mix(n, d, level);
            d6 = mix(n * n * n * n * n * n, d6, level);
        }
        density = detail_erosion(density, d6, 1.0 - d, eta, layers.shape_detail_amount);
    }
    // Not clamped to 1: `density_scale` is extinction per metre at full density, so a 1 mm
    // layer of scale 1000 has optical depth 1 (the reference library's saturate made it 1e-3).
    // Bounded by MAX_DENSITY: an unbounded scale times a profile near its 1e36 limit would be
    // infinite, and ∞·0 (an empty step, an empty shadow texel) a NaN.
    (density * layers.density_scale * genus_profile(key, eta, layers))
        .clamp(Vec4::ZERO, Vec4::splat(MAX_DENSITY))
}
