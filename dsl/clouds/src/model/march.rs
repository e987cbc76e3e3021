//! The primary ray march through the cloud layers, with its lighting: secondary rays towards
//! the sun and the ground, multiple-scattering octaves, powder, sky light, ground bounce, beer
//! shadow map lookup, and energy-conserving integration over each step (Hillaire 2016).
//!
//! Geometry is camera-relative in a local tangent frame (y up): the CPU passes the camera's
//! altitude, and every altitude along a ray is computed from it and the ray's elevation
//! without forming planet-sized squares (see [`super::shell`]).

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::key::{CloudKey, PixelOutput};
use nimbus_dsl::prelude::*;

use super::air_shadow::{air_sunlit, near_air_sunlit};
use super::air_table::air_along;
use super::bindings::CLOUDS;
use super::blob2d::{blob2d_clouds, blob2d_overhead};
use super::choices::{
    APPROXIMATE_MIE, DIFFUSION, DUAL_LOBE, FLAT_HIGH_LAYER, GROUND_BOUNCE, GROUPS, HAZE,
    HENYEY_GREENSTEIN, ICE_CRYSTAL, LIGHT_SHAFTS, OCTAVES, ORTHOGRAPHIC, POWDER, SCENE_DEPTH,
    SHADOWS, SUN_SKY_LIGHT, gate, key_count, phase_is,
};
use super::density::{MediaParams, eroded_density, weather_density};
use super::diffusion::{diffuse_scattering, phase_asymmetry, sky_diffuse_scattering};
use super::flat_layer::flat_layer;
use super::impostor::{IMPOSTOR_MARCHES, impostor_clouds, impostor_view};
use super::layers::LayerGroup;
use super::mesh::{mesh_clouds, mesh_overhead};
use super::noise::interleaved_gradient_noise;
use super::orthographic::orthographic_fragment;
use super::phase::{
    approximate_mie, dual_lobe_hg, henyey_greenstein, ice_crystal_phase, isotropic_phase,
};
use super::ray_light::{RayLight, gathered_result, ground_samples, lit_sample};
use super::scene_depth::{composite_over_scene, scene_distance};
use super::scene_shadow::sun_through_clouds;
use super::shadow::{ShadowParams, shadow_read, shadow_texel};
use super::shell::{ground_hit, ray_shell};
use super::sky::{AtmosphereParams, ground_radiance, sky_distance, sun_disc};
use super::slices::slices_at;
use super::transmission::{DROPLET_ASYMMETRY, slab_diffuse_transmittance};

/// March settings for one quality preset (uniforms: changing them needs no new pipeline).
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct MarchParams {
    pub max_iterations: u32,
    pub sun_steps: u32,
    pub ground_steps: u32,
    pub min_step: f32,
    pub max_step: f32,
    pub max_ray_distance: f32,
    pub perspective_step_scale: f32,
    pub min_density: f32,
    pub min_extinction: f32,
    pub min_transmittance: f32,
    pub min_secondary_step: f32,
    pub secondary_step_scale: f32,
    /// 1: the secondary marches span the whole path out of the cloud slab, with a jittered
    /// sample in each interval (unbiased; the reference). 0: they span
    /// [`secondary_reach`] with a sample at each interval's midpoint, and the beer shadow map
    /// takes over beyond (real time).
    pub secondary_full_path: u32,
    /// Lowest layer bottom and highest layer top over all layers (m).
    pub min_height: f32,
    pub max_height: f32,
    /// Top of the shadow-casting layers (m).
    pub shadow_top_height: f32,
    /// Planet radius (m).
    pub radius: f32,
}

/// Light and medium.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct LightParams {
    /// Unit vector towards the sun, local frame (y up).
    pub sun_direction: Vec3,
    /// Sun irradiance reaching the clouds (W/m² per channel, any consistent unit).
    pub sun_irradiance: Vec3,
    /// Sky irradiance (same unit).
    pub sky_irradiance: Vec3,
    pub scattering_coefficient: f32,
    pub absorption_coefficient: f32,
    pub sky_light_scale: f32,
    pub ground_bounce_scale: f32,
    pub ground_albedo: f32,
    pub powder_scale: f32,
    pub powder_exponent: f32,
    pub g1: f32,
    pub g2: f32,
    pub lobe_weight: f32,
    /// Droplet diameter for the approximate Mie phase function (µm).
    pub droplet_diameter: f32,
}

/// Analytic exponential haze (after iquilezles' "fog" and @takram/three-clouds `approximateHaze`).
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct HazeParams {
    /// Extinction at the ground (1/m).
    pub density: f32,
    /// Inverse scale height (1/m).
    pub exponent: f32,
    pub scattering_coefficient: f32,
    pub absorption_coefficient: f32,
}

/// What the composite adds around the clouds, each a factor of 1 (on) or 0 (off): switched off
/// together with the lighting extras, a render is pure single scattering of the sun by the
/// clouds, comparable with an independent renderer's (verification mode).
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct CompositeParams {
    /// The sky's light behind the clouds (and in front of the ground).
    pub sky: f32,
    /// The sun's disc behind the clouds.
    pub sun_disc: f32,
    /// The lit ground behind the clouds.
    pub ground: f32,
    /// The air between the camera and the clouds: its in-scattering and its dimming.
    pub aerial_perspective: f32,
}

impl CompositeParams {
    /// Everything on: the image a user sees.
    pub const ALL: CompositeParams = CompositeParams {
        sky: 1.0,
        sun_disc: 1.0,
        ground: 1.0,
        aerial_perspective: 1.0,
    };
    /// Nothing but the clouds' own light (verification mode).
    pub const NONE: CompositeParams = CompositeParams {
        sky: 0.0,
        sun_disc: 0.0,
        ground: 0.0,
        aerial_perspective: 0.0,
    };
}

/// All uniforms of the cloud pass.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct CloudUniforms {
    /// Four layers per group; a variant reads the first `key.groups` of them.
    pub groups: [LayerGroup; 2],
    pub media: MediaParams,
    pub march: MarchParams,
    pub light: LightParams,
    pub haze: HazeParams,
    pub composite: CompositeParams,
    /// Camera altitude above the ground (m), computed in f64 on the CPU.
    pub camera_altitude: f32,
    /// Camera's horizontal position folded into the texture tiles (m), for noise lookups.
    pub camera_offset: Vec3,
    /// Clip space to local-frame direction (inverse view-projection without translation).
    pub inverse_view_projection: Mat4,
    /// Beer shadow map cascades and their march.
    pub shadow: ShadowParams,
    /// The atmosphere behind and in front of the clouds.
    pub sky: AtmosphereParams,
    /// Full output size in pixels.
    pub resolution: Vec2,
    /// Pixel of the full image a fragment shades: `floor(frag) · pixel_scale + pixel_offset`
    /// (scale 4 and a Bayer offset per frame when temporally upscaled; 1 and 0 otherwise).
    pub pixel_offset: Vec2,
    pub pixel_scale: f32,
    /// Where in its pixel the ray passes ((0.5, 0.5): the centre). Accumulated frames move it
    /// over the pixel ([`crate::frame_sequence::subpixel_offset`]), so their mean is the pixel's area average: the
    /// detail that a single sample per pixel aliased into a mosaic averages out.
    pub subpixel: Vec2,
    /// Frame index, which varies the per-pixel jitter of the first sample.
    pub frame: u32,
    /// Per-frame jitter phase in [0, 1), added to the per-pixel jitter.
    pub jitter: f32,
}

/// Result of a march.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct MarchResult {
    /// In-scattered radiance.
    pub radiance: Vec3,
    /// Transmittance of the whole path, in [0, 1].
    pub transmittance: f32,
    /// Transmittance-weighted mean distance of the scattering (m); -1 if none.
    pub front_depth: f32,
    /// Full density evaluations the march made (primary and secondary rays).
    pub samples: f32,
}

/// Altitude above the ground at distance `t` along a ray leaving `camera_altitude` with
/// up-cosine `mu`, without forming planet-sized squares:
/// `h = (h_c(2R + h_c) + 2(R + h_c)μt + t²) / (r + R)`, `r = R + h`.
#[shader_fn]
pub fn altitude_along(camera_altitude: f32, mu: f32, t: f32, radius: f32) -> f32 {
    let num = camera_altitude * (2.0 * radius + camera_altitude)
        + 2.0 * (radius + camera_altitude) * mu * t
        + t * t;
    let r = (radius * radius + num).max(0.0).sqrt();
    num / (r + radius)
}

/// The haze's phase function: the clouds' (the look the scenes were built on), but never a
/// diffraction peak: for the droplets' approximate Mie and the ice crystals' phase, a
/// Henyey–Greenstein lobe of the same mean cosine. The Mie peak, hundreds of times the lobe's
/// a degree from the sun, lit the haze under a deck of 75 optical depths wherever the shadow
/// map let a trace of sunlight through, and showed the sun as a spot through it.
#[shader_fn]
pub fn haze_phase(cos_theta: f32, #[spec] key: CloudKey) -> f32 {
    if phase_is(key, APPROXIMATE_MIE) {
        return henyey_greenstein(cos_theta, phase_asymmetry(key));
    }
    if phase_is(key, ICE_CRYSTAL) {
        return henyey_greenstein(cos_theta, phase_asymmetry(key));
    }
    cloud_phase(cos_theta, 1.0, key)
}

/// Phase function with the anisotropy scaled by `g_scale` (the octave attenuation `cᵏ`).
#[shader_fn]
pub fn cloud_phase(cos_theta: f32, g_scale: f32, #[spec] key: CloudKey) -> f32 {
    let light = CLOUDS.get().light;
    if phase_is(key, HENYEY_GREENSTEIN) {
        return henyey_greenstein(cos_theta, light.g1 * g_scale);
    }
    if phase_is(key, DUAL_LOBE) {
        return dual_lobe_hg(
            cos_theta,
            light.g1 * g_scale,
            light.g2 * g_scale,
            light.lobe_weight,
        );
    }
    if phase_is(key, APPROXIMATE_MIE) {
        // The Mie fit has no single anisotropy to attenuate; later octaves blend it towards
        // isotropic by the same factor.
        return mix(
            isotropic_phase(cos_theta),
            approximate_mie(cos_theta, light.droplet_diameter),
            g_scale,
        );
    }
    if phase_is(key, ICE_CRYSTAL) {
        // As the Mie fit: later octaves blend the crystals' phase towards isotropic.
        return mix(
            isotropic_phase(cos_theta),
            ice_crystal_phase(cos_theta, light.g1, light.lobe_weight),
            g_scale,
        );
    }
    isotropic_phase(cos_theta)
}

/// The octaves' phase functions along one view ray, each times its weight `aᵏ` (octave `k` in
/// lane `k % 4` of `low`, `mid` or `high`): the angle to the sun is the same at every sample of
/// a ray, so the phases (two Henyey–Greenstein powers per octave for the dual lobe, sixteen a
/// sample at eight octaves) are worked out once per ray, not once per sample.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct OctavePhases {
    pub low: Vec4,
    pub mid: Vec4,
    pub high: Vec4,
}

/// Octave `k`'s phase at `cos_theta` times its weight: `aᵏ p(μ; cᵏg)`, a = c = 1/2.
#[shader_fn]
pub fn octave_phase(cos_theta: f32, k: u32, #[spec] key: CloudKey) -> f32 {
    let scale = (-(k as f32)).exp2();
    scale * cloud_phase(cos_theta, scale, key)
}

/// Four octaves' weighted phases from octave `first`.
#[shader_fn]
pub fn four_octave_phases(cos_theta: f32, first: u32, #[spec] key: CloudKey) -> Vec4 {
    vec4(
        octave_phase(cos_theta, first, key),
        octave_phase(cos_theta, first + 1u32, key),
        octave_phase(cos_theta, first + 2u32, key),
        octave_phase(cos_theta, first + 3u32, key),
    )
}

/// The weighted phases of the key's octaves for a view ray at `cos_theta` from the sun (lanes
/// beyond the key's octave count are left 0 and never read).
#[shader_fn]
pub fn octave_phases(cos_theta: f32, #[spec] key: CloudKey) -> OctavePhases {
    let n = key_count(key, OCTAVES);
    let mut mid = Vec4::ZERO;
    let mut high = Vec4::ZERO;
    if n > 4u32 {
        mid = four_octave_phases(cos_theta, 4u32, key);
    }
    if n > 8u32 {
        high = four_octave_phases(cos_theta, 8u32, key);
    }
    OctavePhases {
        low: four_octave_phases(cos_theta, 0u32, key),
        mid,
        high,
    }
}

/// Multiple scattering by octaves (Wrenninge et al. 2013, "Oz"): `Σ aᵏ e^(−τbᵏ) p(μ; cᵏg)` with
/// a = b = c = 1/2, from the ray's weighted phases ([`octave_phases`]). One exponential for all
/// octaves: the last octave's `e^(−τ/2ⁿ⁻¹)`, each earlier one the square of the next
/// (`e^(−τ/2ᵏ) = (e^(−τ/2ᵏ⁺¹))²`), seven squarings at eight octaves, 1e-5 relative at most.
#[shader_fn]
pub fn multiple_scattering(optical_depth: f32, phases: OctavePhases, #[spec] key: CloudKey) -> f32 {
    let n = key_count(key, OCTAVES);
    let last = n.max(1u32) - 1u32;
    let mut attenuation = (-optical_depth * (-(last as f32)).exp2()).exp();
    let mut sum = 0.0f32;
    // Unrolled in a specialised shader: each copy reads a fixed lane of a fixed vector.
    for octave in unroll_known(0u32..key_count(key, OCTAVES)) {
        let k = last - octave;
        let lanes = select(
            select(phases.high, phases.mid, k < 8u32),
            phases.low,
            k < 4u32,
        );
        sum += lanes[(k % 4u32) as usize] * attenuation;
        attenuation *= attenuation;
    }
    sum
}

/// The sunlight a sample scatters towards the camera, per unit of irradiance and of σs: the
/// octaves (the first alone is single scattering), and with [`DIFFUSION`] the light that the
/// cloud around the sample scatters many times (`model::diffusion`): the sample lies `tau_sun`
/// from the sun, `tau_up` below the top and `tau_down` above the base. `view_up` is the view
/// ray's up-cosine.
#[shader_fn]
pub fn sun_scattering(
    tau_sun: f32,
    tau_up: f32,
    tau_down: f32,
    cos_theta: f32,
    phases: OctavePhases,
    view_up: f32,
    #[spec] key: CloudKey,
) -> f32 {
    let mut scattered = multiple_scattering(tau_sun, phases, key);
    if gate(key, DIFFUSION) {
        scattered += diffuse_scattering(tau_sun, tau_up, tau_down, cos_theta, view_up, key);
    }
    scattered
}

/// Optical depth from a sample straight along `vertical` (±y) out of the cloud slab, by as many
/// steps as the ground march takes: down, the ground's light comes through it and the
/// diffusion's slab ends there; up, it tells the diffusion whether the sunlight came in
/// through the top or through a side.
#[shader_fn]
pub fn vertical_optical_depth(
    p: Vec3,
    h: f32,
    vertical: f32,
    offset: f32,
    footprint: f32,
    #[spec] key: CloudKey,
) -> f32 {
    let m = CLOUDS.get().march;
    secondary_optical_depth(
        p,
        h,
        vec3(0.0, vertical, 0.0),
        m.ground_steps,
        offset,
        true,
        footprint,
        key,
    )
}

/// Density (summed over the layer groups of the key) at a camera-relative position, for a
/// sample that stands for `footprint` metres across (0: a point; see
/// [`super::density::detail_level`]).
///
/// Where the weather allows no cloud at all the erosion is not run: eroding nothing leaves
/// nothing (every erosion stage maps 0 to 0), so skipping its shape, detail and turbulence
/// reads changes no value, while the shadow map's sun rays and the secondary marches, which
/// have no coverage test of their own, spend most of a broken sky's steps in clear air.
#[shader_fn]
pub fn total_density(position: Vec3, altitude: f32, footprint: f32, #[spec] key: CloudKey) -> f32 {
    let p = position + CLOUDS.get().camera_offset;
    let mut sum = 0.0f32;
    for group in 0u32..key_count(key, GROUPS) {
        let coverage = weather_density(p, altitude, group, key);
        if coverage.dot(Vec4::ONE) > 0.0 {
            sum += eroded_density(p, altitude, group, coverage, footprint, key).dot(Vec4::ONE);
        }
    }
    sum
}

/// Distance from a sample at `altitude` along a ray with up-cosine `mu` to where the ray leaves
/// the cloud slab for good: the top shell going up, the bottom shell going down (or the top,
/// when a downward ray curves back out above the bottom), capped at the march's reach.
#[shader_fn]
pub fn slab_exit(altitude: f32, mu: f32) -> f32 {
    let m = CLOUDS.get().march;
    let top = ray_shell(altitude, mu, m.max_height, m.radius).y;
    let bottom = ray_shell(altitude, mu, m.min_height, m.radius).x;
    let exit = select(top, bottom, mu < 0.0 && bottom > 0.0);
    exit.max(0.0).min(m.max_ray_distance)
}

/// `1 + s + s² + … + sⁿ⁻¹`: the span of `n` steps that grow ×`s`, in units of the first.
#[shader_fn]
pub fn geometric_span(steps: u32, scale: f32) -> f32 {
    let n = steps.max(1u32) as f32;
    select(
        n,
        (scale.powf(n) - 1.0) / (scale - 1.0),
        (scale - 1.0).abs() > 1e-4,
    )
}

/// Optical depth along `direction` from a sample, by `steps` geometrically growing intervals
/// (each ×`secondary_step_scale` the last), with one sample per interval at `offset` of its
/// length (0.5: the midpoint; uniform in [0, 1): stratified, so the sum is unbiased over
/// offsets). With `full_path` the intervals span the whole way out of the cloud slab; otherwise
/// the first is `min_secondary_step / steps` and they span [`secondary_reach`], and the beer
/// shadow map takes over beyond (towards the sun only: the ground has no map, so its march
/// always spans the whole path). A
/// sample near the start of each interval would over-weight the dense start (the ray leaves a
/// point inside a cloud): +11.6 % on the reference before this scheme. With 0 steps it is 0.
/// Its samples stand for `footprint` metres across, as the primary sample it starts from does.
#[shader_fn]
#[expect(
    clippy::too_many_arguments,
    reason = "a shader function: its inputs are values, not a struct the GPU would copy"
)]
pub fn secondary_optical_depth(
    position: Vec3,
    altitude: f32,
    direction: Vec3,
    steps: u32,
    offset: f32,
    full_path: bool,
    footprint: f32,
    #[spec] key: CloudKey,
) -> f32 {
    let m = CLOUDS.get().march;
    let l = CLOUDS.get().light;
    let span = geometric_span(steps, m.secondary_step_scale);
    let first = select(
        m.min_secondary_step / (steps.max(1u32) as f32),
        slab_exit(altitude, direction.y) / span,
        full_path,
    );
    let mut tau = 0.0f32;
    let mut step = first;
    let mut start = 0.0f32;
    for _i in 0u32..steps {
        let t = start + offset * step;
        let h = altitude_along(altitude, direction.y, t, m.radius);
        let rho = total_density(position + direction * t, h, footprint, key);
        let sigma_t = rho * (l.scattering_coefficient + l.absorption_coefficient);
        tau += sigma_t * step;
        start += step;
        step *= m.secondary_step_scale;
    }
    tau
}

/// Optical depth from `p` (altitude `h`) towards the sun: the secondary march, and beyond its
/// reach the beer shadow map where the variant has one.
///
/// Above the top of every shadow-casting layer, where cirrus and the other layers that cast no
/// shadow lie, no map takes over beyond the short march, so its steps span the whole way out
/// of the slab instead. Cut at 150 m, the sun march of a cirrus deck 1.4 km deep under a 35°
/// sun had read 11-19 % bright against the reference in the accuracy study.
#[shader_fn]
pub fn sun_optical_depth(
    p: Vec3,
    h: f32,
    offset: f32,
    footprint: f32,
    #[spec] key: CloudKey,
) -> f32 {
    let m = CLOUDS.get().march;
    let l = CLOUDS.get().light;
    // Without a map the march is all there is: cut at its reach, it read a deck's sun depth
    // at 0.55 of the slab's and the diffusion took the deck for one lit from the side.
    let mut full_path = true;
    if gate(key, SHADOWS) {
        full_path = m.secondary_full_path > 0u32 || h > m.shadow_top_height;
    }
    // A preset may leave the way to the sun to the map alone (`low`: no sun steps), but where
    // no map takes over (above the shadow-casting layers, or without shadows) one step over
    // the whole path at least: with none a cirrus deck was lit as if nothing shaded it.
    let mut steps = select(m.sun_steps, m.sun_steps.max(1u32), full_path);
    // The march's share: 1, or towards the map's edge the fallback's (below).
    let mut weight = 1.0f32;
    let mut tau = 0.0f32;
    if gate(key, SHADOWS) {
        let map = shadow_read(p);
        let to_top = (m.shadow_top_height - h).max(0.0) / l.sun_direction.y.max(0.01);
        // A full-path march has covered the whole way: nothing left for the map.
        let reach = select(
            secondary_reach(m.sun_steps, m.min_secondary_step, m.secondary_step_scale),
            to_top,
            full_path,
        );
        tau = shadow_optical_depth(map.texel, to_top, reach);
        // Towards the map's edge and beyond it (the clouds 50 km away and more, all of them
        // seen from orbit) the map fades out and one short step fades in, as the reference
        // library's `low` takes everywhere. With nothing there the limb from 400 km read 13 %
        // bright at `low` (FLIP 0.058 against 0.026); with one step over the whole path, which
        // mostly lands in the clear air between layers, 11 %. It is where a preset takes no
        // steps, so it is the same march with one step: one call serves both (as two, the
        // setup of the second cost `low` 20 ms a frame on SwiftShader, which runs both sides
        // of a branch).
        let fallback = m.sun_steps == 0u32 && !full_path && map.held < 1.0;
        steps = select(steps, 1u32, fallback);
        weight = select(1.0, 1.0 - map.held, fallback);
    }
    tau += weight
        * secondary_optical_depth(
            p,
            h,
            l.sun_direction,
            steps,
            offset,
            full_path,
            footprint,
            key,
        );
    tau
}

/// Optical depth towards the sun from a beer shadow map texel (Hillaire 2020):
/// R = front depth, G = mean extinction, B = max optical depth, A = tail; `distance` is the
/// sample's distance below the top of the shadow-casting layers along the sun, `offset` the
/// part already covered by the secondary march.
#[shader_fn]
pub fn shadow_optical_depth(texel: Vec4, distance: f32, offset: f32) -> f32 {
    let inside = (distance - offset - texel.x).max(0.0);
    (texel.z + texel.w).min(texel.y * inside).max(0.0)
}

/// Near and far distances of the cloud slab along a ray from the camera; far < near when the
/// ray sees no clouds (it hits the ground first, or points away).
///
/// The far end is where the ray leaves the slab for good: the ground, or its last crossing of
/// the top shell. A ray that dips below the slab's bottom and comes back up (a downward ray
/// near the horizon, seen from inside or above the slab) re-enters it far away; the march skips
/// the gap ([`next_boundary`]) rather than stopping at the first exit, so the result does not
/// jump when the ray, or the camera, crosses a shell.
#[shader_fn]
pub fn cloud_range(mu: f32) -> Vec2 {
    let camera_altitude = CLOUDS.get().camera_altitude;
    let march = CLOUDS.get().march;
    let bottom = ray_shell(camera_altitude, mu, march.min_height, march.radius);
    let top = ray_shell(camera_altitude, mu, march.max_height, march.radius);
    let ground = ground_hit(camera_altitude, mu, march.radius);
    let hits_ground = ground >= 0.0;
    let exit = select(top.y, ground, hits_ground);
    shell_range(
        vec2(march.min_height, march.max_height),
        bottom,
        top,
        exit,
        hits_ground,
    )
}

/// Distances along a view ray to where it enters the shell between the altitudes `heights`
/// (bottom, top) and to `exit`, where it leaves (`far < near`: it never enters), capped at the
/// march's reach: from below it enters through the bottom (`bottom`: the ray's crossings of
/// the bottom shell) unless it `hits_ground` first; from inside it is in already; from above
/// it enters through the top (`top`) if it reaches it.
#[shader_fn]
pub fn shell_range(heights: Vec2, bottom: Vec2, top: Vec2, exit: f32, hits_ground: bool) -> Vec2 {
    let camera_altitude = CLOUDS.get().camera_altitude;
    let mut near = 0.0f32;
    let mut far = -1.0f32;
    if camera_altitude < heights.x {
        if !hits_ground {
            near = bottom.y;
            far = exit;
        }
    } else if camera_altitude <= heights.y {
        far = exit;
    } else if top.x > 0.0 {
        near = top.x;
        far = exit;
    }
    vec2(near, far.min(near + CLOUDS.get().march.max_ray_distance))
}

/// How far along its ray a real-time secondary march of `steps` steps reaches: the first step
/// is `min_step / steps` and each next one `scale` times longer. The beer shadow map takes over
/// from there, so the two neither overlap nor leave a gap.
#[shader_fn]
pub fn secondary_reach(steps: u32, min_step: f32, scale: f32) -> f32 {
    let n = steps.max(1u32) as f32;
    select(
        0.0,
        min_step / n * geometric_span(steps, scale),
        steps > 0u32,
    )
}

/// `(1 − e^(−x)) / x` for optical depth `x ≥ 0`. Below 0.1 the direct form loses digits to
/// cancellation (all of them as x → 0, where it is 0/0); the series `1 − x/2 + x²/6 − x³/24`
/// is good to x⁴/120 < 1e-6 there.
#[shader_fn]
pub fn one_minus_exp_over(x: f32) -> f32 {
    let series = 1.0 - x * (0.5 - x * (1.0 / 6.0 - x / 24.0));
    select((1.0 - (-x).exp()) / x.max(1e-30), series, x < 0.1)
}

/// Relative change of the sun's atmospheric transmittance between the camera's altitude and
/// `altitude` (Kasten–Young air mass, one exponential atmosphere of 8 km scale height and
/// zenith optical depth 0.1). The camera-level irradiance is what the CPU supplies; this
/// corrects it per sample. Bruneton's precomputed tables replace it in the runtime.
#[shader_fn]
pub fn sun_attenuation(altitude: f32, camera_altitude: f32, sun_cos: f32) -> f32 {
    let c = sun_cos.clamp(0.0, 1.0);
    let zenith_deg = c.acos() * 57.295_78;
    let air_mass = 1.0 / (c + 0.505_72 * (96.079_95 - zenith_deg).max(0.1).powf(-1.636_4));
    let density_difference = (-camera_altitude / 8000.0).exp() - (-altitude / 8000.0).exp();
    (0.1 * air_mass * density_difference).min(20.0).exp()
}

/// Light a haze particle scatters from everything but the direct sun, for an isotropic share
/// of its phase function: the sky dome above (`∫L dΩ ≈ 2·E_sky` for a sky of near-uniform
/// radiance) and the Lambertian ground below (`2·albedo·(E_sun·μ + E_sky)`), over 4π, the
/// sun on the ground taken as shaded where the coverage says there is cloud (the haze sees a
/// wide stretch of ground, not the one point a shadow-map lookup would give). It used to be
/// `E_sky/4π` alone, six times too little: the haze then darkened every horizon it thickened,
/// a dark band between a bright sky and a bright ground.
#[shader_fn]
pub fn haze_ambient(light: LightParams, sky: AtmosphereParams, sun_mu: f32, coverage: f32) -> Vec3 {
    let sunlit = light.sun_irradiance * (sun_mu.max(0.0) * (1.0 - coverage.saturate()));
    let ground = sky.ground_albedo * (sunlit + light.sky_irradiance);
    (light.sky_irradiance + ground) * (2.0 * INV_FOUR_PI)
}

/// Opacity of the haze over `distance` along a ray with up-cosine `mu` from `camera_altitude`:
/// `1 − e^(−τ)`, `τ = ρ₀ e^(−k h_c) (1 − e^(−kμL)) / (kμ)`, with μ kept off 0 so horizontal rays
/// stay finite (the limit is `ρ₀ e^(−k h_c) L`).
#[shader_fn]
pub fn haze_opacity(mu: f32, distance: f32) -> f32 {
    let haze = CLOUDS.get().haze;
    let camera_altitude = CLOUDS.get().camera_altitude;
    let rho0 = haze.density * (-haze.exponent * camera_altitude).exp();
    let k_mu = haze.exponent * select(mu.max(1e-5), mu.min(-1e-5), mu < 0.0);
    let tau = rho0 * (1.0 - (-k_mu * distance).exp()) / k_mu;
    1.0 - (-tau.max(0.0)).exp()
}

/// Length of the view ray's path that lies in cloud shadow (m), by marching the beer shadow
/// map: each step adds its shadowed fraction `1 − e^(−τ_BSM)`.
#[shader_fn]
pub fn shadow_length(direction: Vec3, distance: f32, jitter: f32) -> f32 {
    let u = CLOUDS.get();
    let m = u.march;
    let mut length = 0.0f32;
    let mut step = m.min_step;
    let mut t = step * jitter;
    for _i in 0u32..m.max_iterations {
        if t > distance {
            break;
        }
        let p = direction * t;
        let h = altitude_along(u.camera_altitude, direction.y, t, m.radius);
        let texel = shadow_texel(p);
        let to_top = (m.shadow_top_height - h).max(0.0) / u.light.sun_direction.y.max(0.01);
        length += (1.0 - (-shadow_optical_depth(texel, to_top, 0.0)).exp()) * step;
        // Steps grow with distance (coarser where a pixel covers more), up to the maximum step.
        step = (step * m.perspective_step_scale).min(m.max_step);
        t += step;
    }
    length
}

const INV_PI: f32 = core::f32::consts::FRAC_1_PI;
const INV_FOUR_PI: f32 = 0.079_577_47;

/// How many of the layers of group `group` contain `altitude`, give or take 1 cm: a sample
/// placed on a boundary must not read as outside because its altitude rounded the wrong way
/// (the march would then jump past the layer). A zero-height layer contains nothing.
#[shader_fn]
pub fn layers_containing(altitude: f32, group: u32) -> f32 {
    let group = CLOUDS.get().groups[group as usize];
    let h = Vec4::splat(altitude);
    let tolerance = Vec4::splat(1e-2);
    let inside = step(group.min_height - tolerance, h)
        * step(h, group.max_height + tolerance)
        * step(Vec4::splat(1e-4), group.max_height - group.min_height);
    inside.dot(Vec4::ONE)
}

/// Length of the primary step at distance `t`: the minimum step, growing with distance (a
/// pixel covers more there) up to the maximum. A function of distance alone, so a march that
/// jumps a gap between layers resumes with the step it would have had, and a camera either
/// side of a shell samples the layer beyond alike.
#[shader_fn]
pub fn march_step(t: f32) -> f32 {
    let march = CLOUDS.get().march;
    (march.min_step + (march.perspective_step_scale - 1.0) * t.max(0.0)).min(march.max_step)
}

/// The first step into a layer entered at `t`: the ordinary step, but no longer than the ray's
/// path to the next layer boundary. A layer thinner than a step (a 1 m veil under 100 m steps)
/// then gets one sample that stands for its whole path, instead of being hit by one jittered
/// sample in a hundred and drawn as scattered dots (or, at 1 mm, not at all).
#[shader_fn]
pub fn layer_step(mu: f32, t: f32, #[spec] key: CloudKey) -> f32 {
    // Past the boundary just crossed: its root, recomputed, can land a few ulps beyond `t`.
    let past = t + t.abs() * 4e-7 + 1e-5;
    let mut exit = 1e30f32;
    for group in 0u32..key_count(key, GROUPS) {
        exit = next_boundary(mu, past, group, exit);
    }
    march_step(t).min((exit - t).max(1e-5))
}

/// The earlier of `best` and each root of `roots` that lies beyond `t`.
#[shader_fn]
pub fn earliest_after(t: f32, roots: Vec2, best: f32) -> f32 {
    let a = select(best, best.min(roots.x), roots.x > t);
    select(a, a.min(roots.y), roots.y > t)
}

/// Distance to the next crossing of any layer boundary of group `group` beyond `t` (or
/// `best`): the bottom and the top of each of its four layers.
#[shader_fn]
pub fn next_boundary(mu: f32, t: f32, group: u32, best: f32) -> f32 {
    let camera_altitude = CLOUDS.get().camera_altitude;
    let radius = CLOUDS.get().march.radius;
    let layers = CLOUDS.get().groups[group as usize];
    let mut b = best;
    // A loop, not `unroll`: unrolled, this body (two shell intersections) inlined into the march
    // made SwiftShader's compile of the cloud pass run past two minutes. Nor four shells at once
    // without the branch (the same roots to the bit): no gain measured in SwiftShader, and on an
    // H200 `high` and `ultra` took 13-15 % longer (more registers in the march, presumably).
    for lane in 0u32..4u32 {
        let bottom = layers.min_height[lane as usize];
        let top = layers.max_height[lane as usize];
        b = earliest_after(t, ray_shell(camera_altitude, mu, bottom, radius), b);
        b = earliest_after(t, ray_shell(camera_altitude, mu, top, radius), b);
    }
    b
}

/// Step over a sample whose weather allows no cloud. Near the camera it is the ordinary step:
/// a long stride there jumps over the clouds beside a gap and shows false holes (the
/// accuracy study found stratocumulus decks seen from above full of them). It lengthens to
/// the maximum step by 100 km, where a pixel covers that much anyway (as @takram/three-clouds'
/// weather-mip ramp `mix(step, maxStepSize, min(1, mip))`, with `mip = log2(1 + t·1e-5)`).
#[shader_fn]
pub fn empty_step(t: f32, step: f32) -> f32 {
    let march = CLOUDS.get().march;
    let far = (1.0 + t.max(0.0) * 1e-5).log2().min(1.0);
    mix(step, march.max_step.max(step), far)
}

/// Light bounced from the ground that reaches a sample through `tau_ground` of cloud below it:
/// the ground lit by the sky and by the sun where the coverage leaves it in the open, a
/// Lambertian reflector, scattered isotropically.
#[shader_fn]
pub fn ground_bounce_light(tau_ground: f32) -> Vec3 {
    let u = CLOUDS.get();
    let l = u.light;
    let ground_irradiance = l.sky_irradiance
        + l.sun_irradiance * ((1.0 - u.media.coverage) * l.sun_direction.y.max(0.0));
    let bounce =
        l.ground_albedo * INV_PI * (-tau_ground).exp() * INV_FOUR_PI * l.ground_bounce_scale;
    ground_irradiance * bounce
}

/// The light a cloud sample of density `rho` at `altitude` scatters towards a view ray of
/// up-cosine `view_up` per metre (its source term): the sun's through `tau_sun` (its phase
/// and octaves for the view's angle `cos_theta` to the sun), the ground's through
/// `tau_ground` below it, the sky's (by diffusion through `tau_up` above and `tau_ground`, or
/// a crude gradient over the layer), darkened by the powder term where the key has it.
#[shader_fn]
#[expect(
    clippy::too_many_arguments,
    reason = "a shader function takes what a sample knows as plain arguments"
)]
pub fn sample_source(
    rho: f32,
    altitude: f32,
    tau_sun: f32,
    tau_up: f32,
    tau_ground: f32,
    cos_theta: f32,
    phases: OctavePhases,
    view_up: f32,
    #[spec] key: CloudKey,
) -> Vec3 {
    let u = CLOUDS.get();
    let m = u.march;
    let l = u.light;
    let mut sun = l.sun_irradiance;
    if gate(key, SUN_SKY_LIGHT) {
        sun *= sun_attenuation(altitude, u.camera_altitude, l.sun_direction.y);
    }
    let mut light =
        sun * sun_scattering(tau_sun, tau_up, tau_ground, cos_theta, phases, view_up, key);
    if gate(key, GROUND_BOUNCE) {
        light += ground_bounce_light(tau_ground);
    }
    if gate(key, DIFFUSION) {
        light += l.sky_irradiance
            * (sky_diffuse_scattering(tau_up, tau_ground, view_up, key) * l.sky_light_scale);
    } else {
        // Crude sky gradient: half the sky light at a layer's base, all of it at the top.
        let height_fraction =
            ((altitude - m.min_height) / (m.max_height - m.min_height).max(1.0)).saturate();
        light +=
            l.sky_irradiance * (INV_FOUR_PI * (0.5 + 0.5 * height_fraction) * l.sky_light_scale);
    }
    let sigma_t = rho * (l.scattering_coefficient + l.absorption_coefficient);
    let mut source = light * (rho * l.scattering_coefficient);
    if gate(key, POWDER) {
        source *= 1.0 - l.powder_scale * (-sigma_t * l.powder_exponent).exp();
    }
    source
}

/// Marches one view ray (unit `direction`, local frame) through the clouds; `pixel_angle` is
/// the angle (rad) its pixel subtends, so a sample at distance `t` stands for `t·pixel_angle`
/// metres across (0: every sample a point).
#[shader_fn]
#[expect(
    clippy::collapsible_if,
    reason = "the outer `if` is a generation-time choice (the path), the inner one a gate or a \
              shader value: `&&` cannot join a Rust `bool` to a shader `Bool`"
)]
#[expect(
    clippy::mut_range_bound,
    reason = "the inner loop starts where the last one stopped (`taken`), which it records as \
              it goes: the range is read once, on entry"
)]
pub fn march_clouds(
    direction: Vec3,
    jitter: f32,
    pixel_angle: f32,
    #[spec] key: CloudKey,
) -> MarchResult {
    let u = CLOUDS.get();
    let m = u.march;
    let l = u.light;
    let mu = direction.y;
    // The engine's opaque scene ends the ray where it stands.
    let range = if gate(key, SCENE_DEPTH) {
        let open = cloud_range(mu);
        vec2(open.x, open.y.min(scene_distance(direction, key)))
    } else {
        cloud_range(mu)
    };
    let cos_theta = direction.dot(l.sun_direction);
    let phases = octave_phases(cos_theta, key);
    let sigma_ratio = l.scattering_coefficient + l.absorption_coefficient;
    let mut gathered: RayLight = RayLight {
        radiance: Vec3::ZERO,
        transmittance: 1.0,
        depth_sum: 0.0,
        weight_sum: 0.0,
    };
    let mut samples = 0.0f32;
    let start = range.x.max(0.0);
    let mut step = layer_step(mu, start, key);
    let mut t = start + step * jitter;
    // Steps taken, of `max_iterations`.
    let mut taken = 0u32;
    // Two loops: the inner one walks the cheap steps (between the layers, no coverage, eroded
    // to nothing) up to the next sample with extinction, the outer one lights it. A SIMD group
    // runs a loop's body while any of its lanes needs it, and SwiftShader runs both sides of a
    // branch: in one loop every step paid for the light (the map, the sun march, the octaves,
    // the ground and sky steps), wanted at a third of them. Split, a group lights its lanes'
    // samples together. The steps, their order and the sums are the same. SwiftShader, `low`
    // at the bench's view: 385 → 352 ms a frame; llvmpipe, the default scene at 640 × 360:
    // `medium` 387 → 211 ms, `high` 709 → 420. The slices path reads its light with its
    // density (one texture read), so there is nothing to gather: it lights each sample where
    // its inner loop finds it, which is then the single loop it was, and its outer loop runs
    // once (llvmpipe: split, its `low` took 64 → 90 ms), a bound the compiler sees (with the
    // iteration count as its bound, `low` upscaled read 27.5 ms, not 16).
    let passes = if key.reads_slices() {
        1u32
    } else {
        m.max_iterations
    };
    for _lit in 0u32..passes {
        let mut lit = false;
        let mut ended = false;
        let mut h = 0.0f32;
        let mut p = Vec3::ZERO;
        let mut first = Vec4::ZERO;
        let mut rho = 0.0f32;
        let mut footprint = 0.0f32;
        for i in taken..m.max_iterations {
            taken = i + 1u32;
            if t > range.y {
                ended = true;
                break;
            }
            h = altitude_along(u.camera_altitude, mu, t, m.radius);
            // Between layers: jump to the next layer boundary instead of stepping through the
            // gap.
            let mut inside = 0.0f32;
            for group in 0u32..key_count(key, GROUPS) {
                inside += layers_containing(h, group);
            }
            if inside < 0.5 {
                let mut next = 1e30f32;
                for group in 0u32..key_count(key, GROUPS) {
                    next = next_boundary(mu, t, group, next);
                }
                if next > 1e29 {
                    ended = true;
                    break;
                }
                // Resume inside the next layer as a march starting there would: same step,
                // same jitter.
                step = layer_step(mu, next, key);
                t = next + step * jitter;
                continue;
            }
            p = direction * t;
            // Cheap coverage test before the full density: no weather here, take a long step.
            // The coverage-stage densities it reads are the erosion's input too (a key has at
            // most two layer groups). The slices path reads the density and the optical depths
            // its light needs from the baked stack instead (into `first`: density, to the sun,
            // down, up): one sample in place of the noise and the secondary marches.
            let q = p + u.camera_offset;
            first = if key.reads_slices() {
                slices_at(p, h)
            } else {
                weather_density(q, h, 0u32, key)
            };
            let mut coverage = if key.reads_slices() {
                first.x
            } else {
                first.dot(Vec4::ONE)
            };
            let mut second = Vec4::ZERO;
            if !key.reads_slices() {
                if key_count(key, GROUPS) > 1u32 {
                    second = weather_density(q, h, 1u32, key);
                    coverage += second.dot(Vec4::ONE);
                }
            }
            if coverage <= m.min_density {
                t += empty_step(t, step);
                step = march_step(t);
                continue;
            }
            // The secondary rays' samples stand for as much as this one: the light at a pixel
            // is the mean over what the pixel covers.
            footprint = t * pixel_angle;
            rho = if key.reads_slices() {
                first.x
            } else {
                eroded_density(q, h, 0u32, first, footprint, key).dot(Vec4::ONE)
            };
            if !key.reads_slices() {
                if key_count(key, GROUPS) > 1u32 {
                    rho += eroded_density(q, h, 1u32, second, footprint, key).dot(Vec4::ONE);
                }
            }
            samples += 1.0;
            if rho * sigma_ratio > m.min_extinction {
                if key.reads_slices() {
                    gathered = lit_sample(
                        gathered,
                        rho,
                        p,
                        h,
                        first,
                        t,
                        step,
                        0.5,
                        footprint,
                        cos_theta,
                        phases,
                        direction.y,
                        key,
                    );
                    if gathered.transmittance <= 0.0 {
                        ended = true;
                        break;
                    }
                } else {
                    lit = true;
                    break;
                }
            }
            t += step;
            step = march_step(t);
        }
        if ended {
            break;
        }
        if !lit {
            // Every iteration spent (the slices path always ends here, its samples lit).
            break;
        }
        if !key.reads_slices() {
            samples += m.sun_steps as f32;
            // Midpoints in real time; in the reference a stratified offset per sample,
            // decorrelated from the primary jitter and from the previous sample's.
            let offset = select(
                0.5,
                (jitter * 257.0 + 0.618_034 * samples).fract_gl(),
                m.secondary_full_path > 0u32,
            );
            gathered = lit_sample(
                gathered,
                rho,
                p,
                h,
                first,
                t,
                step,
                offset,
                footprint,
                cos_theta,
                phases,
                direction.y,
                key,
            );
            samples += ground_samples(key);
            if gathered.transmittance <= 0.0 {
                break;
            }
            t += step;
            step = march_step(t);
        }
    }
    gathered_result(gathered, samples)
}

/// Unit direction (local frame) of the view ray through `pixel` (output pixels, y down; the
/// centre of pixel (0, 0) is (0.5, 0.5)).
#[shader_fn]
pub fn view_direction(pixel: Vec2) -> Vec3 {
    let u = CLOUDS.get();
    let ndc = vec2(
        pixel.x / u.resolution.x * 2.0 - 1.0,
        1.0 - pixel.y / u.resolution.y * 2.0,
    );
    let clip = u.inverse_view_projection * vec4(ndc.x, ndc.y, 1.0, 1.0);
    (clip.xyz() / clip.w).normalize()
}

/// Colour of one pixel: its view ray through the camera ([`shade_ray`]), or, for an
/// orthographic camera, its own parallel ray ([`orthographic_fragment`]).
#[shader_fn]
pub fn cloud_fragment(frag_coord: Vec4, #[spec] key: CloudKey) -> Vec4 {
    if gate(key, ORTHOGRAPHIC) {
        // Parallel rays, each from its own point of the image plane.
        return orthographic_fragment(frag_coord, key);
    }
    let u = CLOUDS.get();
    let cell = vec2(frag_coord.x, frag_coord.y).floor() * u.pixel_scale + u.pixel_offset;
    let pixel = cell + u.subpixel;
    let direction = view_direction(pixel);
    // The angle one output pixel subtends here (chord ≈ arc at these sizes).
    let pixel_angle = (view_direction(pixel + vec2(1.0, 0.0)) - direction).length();
    shade_ray(cell, direction, pixel_angle, key)
}

/// Colour of the pixel `cell` (its block's corner when upscaled) along the view ray
/// `direction`, whose pixel subtends `pixel_angle` (rad): its clouds marched (or read from a
/// path's map), then composited ([`composite`]), or one of the linear or instrumented layers of
/// [`PixelOutput`]; an impostor that holds the whole picture is read as it is.
#[shader_fn]
pub fn shade_ray(cell: Vec2, direction: Vec3, pixel_angle: f32, #[spec] key: CloudKey) -> Vec4 {
    if key.bakes_view() {
        // The impostor holds the whole picture; each read stands for a march of the bake.
        let view = impostor_view(direction, key);
        if key.writes(PixelOutput::Samples) {
            return view.xyz().extend(IMPOSTOR_MARCHES as f32);
        }
        return view;
    }
    let u = CLOUDS.get();
    // Seeded by the pixel, not the sample point within it: a pixel's jitter sequence is the
    // same whatever the sub-pixel offset.
    let jitter =
        (interleaved_gradient_noise(cell + Vec2::splat(0.5), u.frame) + u.jitter).fract_gl();
    let clouds = if key.reads_blob2d() || key.reads_impostor() || key.reads_mesh() {
        map_clouds(direction, jitter, key)
    } else if gate(key, FLAT_HIGH_LAYER) {
        flat_layer(direction, jitter, pixel_angle, key)
    } else {
        march_clouds(direction, jitter, pixel_angle, key)
    };
    if key.writes(PixelOutput::Clouds) {
        return clouds.radiance.extend(clouds.transmittance);
    }
    if key.writes(PixelOutput::Depth) {
        // Kilometres: the targets are half floats, whose largest value is 65,504.
        let km = select(-1.0, clouds.front_depth * 1e-3, clouds.front_depth > 0.0);
        return vec4(km, clouds.transmittance, clouds.samples, 1.0);
    }
    let color = if gate(key, SCENE_DEPTH) {
        composite_over_scene(direction, jitter, clouds, key)
    } else {
        composite(direction, jitter, clouds, key)
    };
    if key.writes(PixelOutput::Samples) {
        return color.xyz().extend(clouds.samples);
    }
    color
}

/// The clouds along `direction` read from the key's map (the 2D map, the impostor or the mesh's
/// cluster table). A map holds the whole ray's clouds, where the march stops at the engine's
/// surface: over the engine's scene, clouds whose front lies behind its surface are hidden (a
/// surface within a cloud keeps it whole: a map holds one front per direction, not where along
/// the ray its light was scattered).
#[shader_fn]
pub fn map_clouds(direction: Vec3, jitter: f32, #[spec] key: CloudKey) -> MarchResult {
    let clouds = if key.reads_blob2d() {
        blob2d_clouds(direction, jitter, key)
    } else if key.reads_impostor() {
        impostor_clouds(direction)
    } else {
        mesh_clouds(direction, key)
    };
    if gate(key, SCENE_DEPTH) {
        let hidden = clouds.front_depth > scene_distance(direction, key);
        return MarchResult {
            radiance: select(clouds.radiance, Vec3::ZERO, hidden),
            transmittance: select(clouds.transmittance, 1.0, hidden),
            front_depth: select(clouds.front_depth, -1.0, hidden),
            samples: clouds.samples,
        };
    }
    clouds
}

/// Samples of [`overhead_optical_depth`].
pub const OVERHEAD_STEPS: u32 = 4;

/// Vertical optical depth of the shadow-casting layers above the ground point `ground`
/// (camera-relative), by [`OVERHEAD_STEPS`] stratified samples offset by `jitter`. Each sample
/// stands for its whole interval, so the detail is its mean ([`super::density::detail_level`])
/// and no detail texture is read.
#[shader_fn]
pub fn overhead_optical_depth(ground: Vec3, jitter: f32, #[spec] key: CloudKey) -> f32 {
    if key.reads_blob2d() {
        // The 2D path's map holds the column: one read, no noise.
        return blob2d_overhead(ground.x, ground.z);
    }
    if key.reads_mesh() {
        // The cluster table's puffs: their columns, in closed form.
        return mesh_overhead(ground.x, ground.z);
    }
    let u = CLOUDS.get();
    let m = u.march;
    let sigma_ratio = u.light.scattering_coefficient + u.light.absorption_coefficient;
    let bottom = m.min_height;
    let dh = (m.shadow_top_height - bottom).max(0.0) / OVERHEAD_STEPS as f32;
    let mut tau = 0.0f32;
    for i in 0u32..OVERHEAD_STEPS {
        let h = bottom + (i as f32 + jitter) * dh;
        // Straight up from the ground point: its horizontal position is the noise's, `h` its
        // altitude.
        let p = vec3(ground.x, h - u.camera_altitude, ground.z);
        // The slices path reads its stack here too: its cloud pass reads no noise at all.
        tau += (if key.reads_slices() {
            slices_at(p, h).x
        } else {
            total_density(p, h, dh, key)
        }) * sigma_ratio
            * dh;
    }
    tau
}

/// What a view ray shows around the clouds' march result: the clouds over a physically based
/// sky, or over the ground lit by the sun through the clouds' shadows; the air between the
/// camera and the clouds in front; then haze, lit by the sun only where the light-shaft march
/// finds no cloud shadow. Alpha is the clouds' opacity.
#[shader_fn]
pub fn composite(direction: Vec3, jitter: f32, clouds: MarchResult, #[spec] key: CloudKey) -> Vec4 {
    let u = CLOUDS.get();
    // Behind the clouds: the ground (negative distance) or the top of the atmosphere.
    let behind = sky_distance(
        u.camera_altitude,
        direction.y,
        u.sky.top_height,
        u.march.radius,
    );
    let switches = u.composite;
    // The air in front ends at the clouds' front, else at the ground, else at the march's
    // reach; so does the haze.
    let open = select(u.march.max_ray_distance, -behind, behind < 0.0);
    let near = select(open, clouds.front_depth, clouds.front_depth > 0.0);
    // The sun's share of that air, read once for the air's light and the haze's.
    let sunlit = near_air_sunlit(
        direction,
        near,
        clouds.front_depth > 0.0 || behind < 0.0,
        jitter,
        key,
    );
    // What lies behind the clouds shows only through them: an opaque ray (transmittance
    // exactly 0: `march_clouds`' early termination, a map's opaque texel, underflow) skips the
    // sky, the ground, the air in front of them and its shadows, which it would multiply by 0.
    let mut background = Vec3::ZERO;
    if clouds.transmittance > 0.0 {
        // The ground behind a cloud has air of its own in front of it.
        let mut ground_sunlit = sunlit;
        if clouds.front_depth > 0.0 && behind < 0.0 {
            ground_sunlit = air_sunlit(direction, -behind, jitter, key);
        }
        background = sky_or_ground(direction, behind, ground_sunlit, jitter, key);
    }
    let mut color = background * clouds.transmittance;
    if clouds.front_depth > 0.0 {
        color += clouds_through_air(direction, clouds, switches.aerial_perspective, sunlit, key);
    }
    if gate(key, HAZE) {
        let opacity = haze_opacity(direction.y, near);
        color = color + (haze_light(direction, near, jitter, sunlit, key) - color) * opacity;
    }
    color.extend(1.0 - clouds.transmittance)
}

/// What a view ray `direction` would show with no clouds: the sky and the sun's disc above the
/// horizon, else the ground `-behind` metres away lit by the sun and the sky through the
/// clouds' shadows ([`sky_distance`]'s sign), each seen through the air in front of it; the
/// sun reaches `sunlit` of the air in front of the ground ([`air_sunlit`]).
#[shader_fn]
pub fn sky_or_ground(
    direction: Vec3,
    behind: f32,
    sunlit: f32,
    jitter: f32,
    #[spec] key: CloudKey,
) -> Vec3 {
    let u = CLOUDS.get();
    let sun = u.light.sun_direction;
    let switches = u.composite;
    let air = air_along(direction, behind.abs(), key);
    let mut background = air.inscatter * switches.sky;
    if behind < 0.0 {
        // The air over the ground lies in the clouds' shadow as the ground does.
        background *= sunlit;
        // Under a cloud the ground gets the light the cloud scatters down as well as the
        // direct beam, and the sky's light through it (see `transmission`).
        let mut sun_through = 1.0f32;
        let mut sky_through = 1.0f32;
        if gate(key, SHADOWS) {
            let ground = direction * -behind;
            sun_through = sun_through_clouds(ground);
            // The sky's light comes from the whole dome: what dims it is the cloud overhead,
            // not the cloud on the way to the sun. With the sun's path for both, the ground in
            // the shadow of a storm tower 20 km away went black.
            let overhead = overhead_optical_depth(ground, jitter, key);
            sky_through = slab_diffuse_transmittance(overhead, DROPLET_ASYMMETRY);
        }
        background += air.transmittance
            * ground_radiance(
                u.light.sun_irradiance * sun_through,
                sun.y,
                u.light.sky_irradiance * sky_through,
                u.sky.ground_albedo,
            )
            * switches.ground;
    } else {
        // A map of the view draws the disc per pixel (`impostor_view`): its texels are wider.
        if !key.bakes_view() {
            background +=
                sun_disc(direction.dot(sun), air.transmittance, u.sky) * switches.sun_disc;
        }
    }
    background
}

/// The clouds' light as it reaches the camera along `direction` (aerial perspective): the air
/// in front of them dims them and adds its own light where the sun reaches it (`sunlit` of it:
/// [`air_sunlit`] over the clouds' front depth), weighted by `air` (1: all of it, 0: the
/// clouds' own light alone).
#[shader_fn]
pub fn clouds_through_air(
    direction: Vec3,
    clouds: MarchResult,
    air: f32,
    sunlit: f32,
    #[spec] key: CloudKey,
) -> Vec3 {
    let near = air_along(direction, clouds.front_depth, key);
    near.inscatter * ((1.0 - clouds.transmittance) * air * sunlit)
        + clouds.radiance * (Vec3::ONE + (near.transmittance - Vec3::ONE) * air)
}

/// The light the haze scatters towards the camera along `direction` over its first
/// `distance` metres: the sun's, where the light-shaft march finds no cloud shadow (without
/// light shafts, on `air_share` of the way: the air's, [`air_sunlit`]), and the sky's.
#[shader_fn]
pub fn haze_light(
    direction: Vec3,
    distance: f32,
    jitter: f32,
    air_share: f32,
    #[spec] key: CloudKey,
) -> Vec3 {
    let u = CLOUDS.get();
    let sun = u.light.sun_direction;
    let mut sunlit = air_share;
    if gate(key, LIGHT_SHAFTS) {
        sunlit = 1.0 - (shadow_length(direction, distance, jitter) / distance.max(1.0)).saturate();
    }
    let albedo = u.haze.scattering_coefficient
        / (u.haze.scattering_coefficient + u.haze.absorption_coefficient).max(1e-6);
    (u.light.sun_irradiance * (haze_phase(direction.dot(sun), key) * sunlit)
        + haze_ambient(u.light, u.sky, sun.y, u.media.coverage))
        * albedo
}
