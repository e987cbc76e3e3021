//! A simple physically based sky: single Rayleigh and Mie scattering in an exponential
//! atmosphere over a spherical planet, the sun's transmittance from the Chapman function
//! (Schüler, "An Approximation to the Chapman Grazing-Incidence Function", GPU Pro 3), and the
//! ground lit by the sun and the sky.
//!
//! The same functions give the sun and sky irradiance the cloud march is lit with
//! ([`sun_irradiance_at`], [`sky_irradiance_at`]), so clouds and sky agree: on the CPU for
//! Nimbus's runtime, in JavaScript for an engine package's host.

use glam::Vec3;

use nimbus_dsl::prelude::*;

use super::march::altitude_along;
use super::phase::henyey_greenstein;
use super::shell::{ground_hit, ray_shell};

/// Scattering media of the atmosphere (Bruneton 2017's Earth defaults, without ozone).
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct AtmosphereParams {
    /// Rayleigh scattering at sea level (1/m) and its scale height (m).
    pub rayleigh_scattering: Vec3,
    pub rayleigh_height: f32,
    /// Mie scattering at sea level (1/m, grey), its extinction, scale height and anisotropy.
    pub mie_scattering: f32,
    pub mie_extinction: f32,
    pub mie_height: f32,
    pub mie_g: f32,
    /// Sun irradiance at the top of the atmosphere, and the sun's angular radius (rad).
    pub solar_irradiance: Vec3,
    pub sun_angular_radius: f32,
    /// Ground reflectance (Lambertian): 0.2, grass and soil in the visible; the clouds' ground
    /// bounce uses its mean.
    pub ground_albedo: Vec3,
    /// Altitude of the top of the atmosphere (m).
    pub top_height: f32,
}

impl Default for AtmosphereParams {
    fn default() -> Self {
        Self {
            rayleigh_scattering: Vec3::new(5.802e-6, 13.558e-6, 33.1e-6),
            rayleigh_height: 8000.0,
            mie_scattering: 3.996e-6,
            mie_extinction: 4.44e-6,
            mie_height: 1200.0,
            mie_g: 0.8,
            solar_irradiance: Vec3::splat(1.2),
            sun_angular_radius: 0.004_675,
            ground_albedo: Vec3::new(0.2, 0.2, 0.16),
            top_height: 100_000.0,
        }
    }
}

/// Light leaving a stretch of view ray: what the air scatters in, and what it lets through.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct AirLight {
    pub inscatter: Vec3,
    pub transmittance: Vec3,
}

/// Chapman function times `e^(−h/H)`: relative air mass towards direction cosine `mu` from
/// altitude `altitude` in an exponential layer of scale height `scale_height`. For rays below
/// the horizon the caller has already checked that the ray does not meet the ground, so the
/// exponent `X − x₀` is ≤ 0 and cannot overflow.
#[shader_fn]
pub fn chapman(altitude: f32, mu: f32, scale_height: f32, radius: f32) -> f32 {
    let x = radius / scale_height;
    let h = altitude / scale_height;
    let c = (x + h).sqrt();
    let above = c / (c * mu + 1.0) * (-h).exp();
    if mu >= 0.0 {
        return above;
    }
    let s = ((1.0 - mu) * (1.0 + mu)).max(0.0).sqrt();
    let x0 = s * (x + h);
    let c0 = x0.sqrt();
    2.0 * c0 * (x - x0).min(0.0).exp() - c / (1.0 - c * mu) * (-h).exp()
}

/// Transmittance of the atmosphere from `altitude` towards a direction of up-cosine `mu`; 0 when
/// the planet is in the way (the sun has set for this point).
#[shader_fn]
pub fn transmittance_towards(
    altitude: f32,
    mu: f32,
    atmosphere: AtmosphereParams,
    radius: f32,
) -> Vec3 {
    let h = altitude.max(0.0);
    if ground_hit(h, mu, radius) >= 0.0 {
        return Vec3::ZERO;
    }
    let rayleigh = atmosphere.rayleigh_height
        * chapman(h, mu, atmosphere.rayleigh_height, radius)
        * atmosphere.rayleigh_scattering;
    let mie = Vec3::splat(
        atmosphere.mie_height
            * chapman(h, mu, atmosphere.mie_height, radius)
            * atmosphere.mie_extinction,
    );
    (-(rayleigh + mie)).exp()
}

const VIEW_SAMPLES: u32 = 12;
const PI: f32 = core::f32::consts::PI;
const INV_PI: f32 = core::f32::consts::FRAC_1_PI;

/// The air's single scattering along a view ray without its phase functions, which are
/// constant along a ray and so factor out: `inscatter = (rayleigh·p_R(θ) + mie·p_M(θ))·E_sun`.
/// What the air table stores (`model::air_table`): smooth in direction where the phased light
/// (the Mie aureole round the sun) is not.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct AirIntegrals {
    /// `∫ β_R(h) T_sun T_view dt` (1/sr before the phase).
    pub rayleigh: Vec3,
    /// `∫ β_M(h) T_sun T_view dt`.
    pub mie: Vec3,
    /// The view ray's optical depth (its transmittance is `e^(−τ)`).
    pub optical_depth: Vec3,
}

/// The air's light from its phase-free integrals, for a view ray at cosine `cos_theta` from the
/// sun.
#[shader_fn]
pub fn phased_air_light(
    integrals: AirIntegrals,
    cos_theta: f32,
    atmosphere: AtmosphereParams,
) -> AirLight {
    let rayleigh_phase = 0.059_683_1 * (1.0 + cos_theta * cos_theta);
    let mie_phase = henyey_greenstein(cos_theta, atmosphere.mie_g);
    AirLight {
        inscatter: (integrals.rayleigh * rayleigh_phase + integrals.mie * mie_phase)
            * atmosphere.solar_irradiance,
        transmittance: (-integrals.optical_depth).exp(),
    }
}

/// Single scattering along the view ray from `camera_altitude` in unit `direction` (y up), over
/// `distance` metres, without the phase functions ([`AirIntegrals`]). Samples are spaced
/// quadratically (denser near the camera, where the air is thick), each lit by the sun
/// through [`transmittance_towards`]. From above the atmosphere (a camera in orbit) they start
/// where the ray enters it, not in the vacuum before. With `lit` false only the optical depth
/// is integrated (the scattered light reads 0): the air table's optical-depth band, whose
/// texels need no sun, skips the two Chapman functions per sample that the light costs.
#[shader_fn]
pub fn air_integrals(
    camera_altitude: f32,
    direction: Vec3,
    sun_direction: Vec3,
    distance: f32,
    atmosphere: AtmosphereParams,
    radius: f32,
    lit: bool,
) -> AirIntegrals {
    let mu = direction.y;
    let mut optical_depth = Vec3::ZERO;
    let mut rayleigh = Vec3::ZERO;
    let mut mie = Vec3::ZERO;
    let top = ray_shell(camera_altitude, mu, atmosphere.top_height, radius);
    let entry = select(
        0.0,
        top.x.max(0.0).min(distance),
        camera_altitude > atmosphere.top_height,
    );
    let length = distance - entry;
    let mut previous = entry;
    let n = VIEW_SAMPLES as f32;
    for i in 0u32..VIEW_SAMPLES {
        let f = (i as f32 + 1.0) / n;
        let t_end = entry + length * f * f;
        let dt = t_end - previous;
        let t = previous + dt * 0.5;
        previous = t_end;
        let h = altitude_along(camera_altitude, mu, t, radius).max(0.0);
        let rho_r = (-h / atmosphere.rayleigh_height).exp();
        let rho_m = (-h / atmosphere.mie_height).exp();
        let extinction =
            atmosphere.rayleigh_scattering * rho_r + Vec3::splat(atmosphere.mie_extinction * rho_m);
        if lit {
            // Cosine of the sun's elevation at the sample (the local up turns along the ray).
            let r = radius + h;
            let up = (direction * t + vec3(0.0, radius + camera_altitude, 0.0)) / r;
            let sun_mu = up.dot(sun_direction);
            let to_sun = transmittance_towards(h, sun_mu, atmosphere, radius);
            let light = to_sun * (-(optical_depth + extinction * (dt * 0.5))).exp() * dt;
            rayleigh += atmosphere.rayleigh_scattering * light * rho_r;
            mie += light * (atmosphere.mie_scattering * rho_m);
        }
        optical_depth += extinction * dt;
    }
    AirIntegrals {
        rayleigh,
        mie,
        optical_depth,
    }
}

/// Single scattering along the view ray from `camera_altitude` in unit `direction` (y up), over
/// `distance` metres ([`air_integrals`] with the phases of the ray's angle to the sun).
#[shader_fn]
pub fn air_light(
    camera_altitude: f32,
    direction: Vec3,
    sun_direction: Vec3,
    distance: f32,
    atmosphere: AtmosphereParams,
    radius: f32,
) -> AirLight {
    let integrals = air_integrals(
        camera_altitude,
        direction,
        sun_direction,
        distance,
        atmosphere,
        radius,
        true,
    );
    phased_air_light(integrals, direction.dot(sun_direction), atmosphere)
}

/// Distance along a view ray to what ends it in the sky: the ground, or the top of the
/// atmosphere. Negative when the ray hits the ground (at least 1 mm away, so that a camera
/// on the ground still reads as "ground": −0 would not).
#[shader_fn]
pub fn sky_distance(camera_altitude: f32, mu: f32, top_height: f32, radius: f32) -> f32 {
    let ground = ground_hit(camera_altitude, mu, radius);
    if ground >= 0.0 {
        return -ground.max(1e-3);
    }
    ray_shell(camera_altitude, mu, top_height, radius)
        .y
        .max(0.0)
}

/// Radiance of the sun's disc seen through `transmittance` (uniform disc, limb darkening left
/// out): irradiance over the disc's solid angle.
#[shader_fn]
pub fn sun_disc(cos_theta: f32, transmittance: Vec3, atmosphere: AtmosphereParams) -> Vec3 {
    let r = atmosphere.sun_angular_radius;
    let inside = step(r.cos(), cos_theta);
    atmosphere.solar_irradiance * transmittance * (inside / (PI * r * r))
}

/// Radiance leaving a Lambertian ground lit by `sun` (irradiance on a plane facing the sun,
/// already attenuated by clouds and air) and `sky` irradiance.
#[shader_fn]
pub fn ground_radiance(sun: Vec3, sun_mu: f32, sky: Vec3, albedo: Vec3) -> Vec3 {
    albedo * (sun * sun_mu.max(0.0) + sky) * INV_PI
}

/// Sun irradiance on a plane facing the sun at `altitude` (what the cloud march is lit with;
/// computed once per frame, on the host: see [`super::sun::sun_light`]).
#[shader_fn]
pub fn sun_irradiance_at(
    altitude: f32,
    sun_direction: Vec3,
    atmosphere: AtmosphereParams,
    radius: f32,
) -> Vec3 {
    atmosphere.solar_irradiance
        * transmittance_towards(altitude, sun_direction.y, atmosphere, radius)
}

/// Elevation bands and azimuths of [`sky_irradiance_at`]'s quadrature.
const SKY_ELEVATIONS: u32 = 8;
const SKY_AZIMUTHS: u32 = 16;

/// Sky irradiance on a horizontal plane at `altitude`: the sky's radiance integrated over the
/// upper hemisphere, cosine-weighted, from the same [`air_light`] the shader draws.
#[shader_fn]
pub fn sky_irradiance_at(
    altitude: f32,
    sun_direction: Vec3,
    atmosphere: AtmosphereParams,
    radius: f32,
) -> Vec3 {
    let mut sum = Vec3::ZERO;
    for i in 0u32..SKY_ELEVATIONS {
        // Uniform in sin²(elevation), so each band carries equal cosine weight: E = π·mean(L).
        let mu = (((i as f32) + 0.5) / SKY_ELEVATIONS as f32).sqrt();
        let s = (1.0 - mu * mu).sqrt();
        for j in 0u32..SKY_AZIMUTHS {
            let phi = (j as f32 + 0.5) / SKY_AZIMUTHS as f32 * core::f32::consts::TAU;
            let d = Vec3::new(s * phi.cos(), mu, s * phi.sin());
            let distance = sky_distance(altitude, mu, atmosphere.top_height, radius).abs();
            sum += air_light(altitude, d, sun_direction, distance, atmosphere, radius).inscatter;
        }
    }
    sum * (core::f32::consts::PI / (SKY_ELEVATIONS * SKY_AZIMUTHS) as f32)
}
