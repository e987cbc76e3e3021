//! A thin high layer (cirrus, cirrostratus) drawn as a textured 2D layer: a few density reads
//! along the view ray's path through the layer give its optical depth, and the layer is lit as
//! a homogeneous slab of that depth, by the sun through it
//! (the model's multiple-scattering octaves and phase function, averaged over its depth), the sky and the ground,
//! darkened by the march's powder term as its samples would be. No march:
//! [`FLAT_SAMPLES`] density reads per pixel instead of tens of samples with a sun march each.
//!
//! Where it holds: seen from far below, a layer a few hundred metres thick at 7–10 km is a sheet
//! whose thickness no pixel resolves; the slab's path length along the ray (from the cloud
//! range, so the horizon's long grazing paths stay bounded) carries its brightening towards the
//! horizon. What it drops: the layer's vertical structure (self-shadowing inside it, the sides of
//! towers), which a thin high layer barely has. The scene analysis chooses it only there
//! ([`crate::analysis::flat_high_layer`]); the accuracy study measures its error and cost.

use nimbus_dsl::prelude::*;

use super::bindings::CLOUDS;
use super::choices::{GROUND_BOUNCE, POWDER, gate};
use super::march::{
    MarchResult, altitude_along, cloud_range, ground_bounce_light, octave_phases, sun_scattering,
    total_density,
};
use super::shell::ray_shell;
use crate::key::CloudKey;

/// Density reads per pixel, stratified along the ray's path through the layer.
pub const FLAT_SAMPLES: u32 = 4;

/// Optical depth of the clouds along `direction` between distances `near` and `far` (the ray's
/// path through the slab), by [`FLAT_SAMPLES`] stratified reads, each standing for `footprint`
/// metres across (x); and the same depth weighted by the march's powder term at each read (y),
/// so that the powder darkens the layer as the march's would, per sample and not at the mean
/// (it is convex in the extinction: at the mean it darkened streaky cirrus by a tenth). Along
/// the ray, not straight up: a grazing ray crosses many streaks.
#[shader_fn]
pub fn flat_path_depth(
    direction: Vec3,
    near: f32,
    far: f32,
    jitter: f32,
    pixel_angle: f32,
    #[spec] key: CloudKey,
) -> Vec2 {
    let u = CLOUDS.get();
    let m = u.march;
    let l = u.light;
    let sigma_ratio = l.scattering_coefficient + l.absorption_coefficient;
    let dt = (far - near).max(0.0) / FLAT_SAMPLES as f32;
    let mut tau = 0.0f32;
    let mut powdered = 0.0f32;
    for i in 0u32..FLAT_SAMPLES {
        let t = near + (i as f32 + jitter) * dt;
        let h = altitude_along(u.camera_altitude, direction.y, t, m.radius);
        let sigma_t = total_density(direction * t, h, t * pixel_angle, key) * sigma_ratio;
        let mut weight = 1.0f32;
        if gate(key, POWDER) {
            weight = 1.0 - l.powder_scale * (-sigma_t * l.powder_exponent).exp();
        }
        tau += sigma_t * dt;
        powdered += sigma_t * weight * dt;
    }
    vec2(tau, powdered)
}

/// The clouds along `direction` as a flat layer (the march's result, for [`super::march::composite`]).
#[shader_fn]
pub fn flat_layer(
    direction: Vec3,
    jitter: f32,
    pixel_angle: f32,
    #[spec] key: CloudKey,
) -> MarchResult {
    let u = CLOUDS.get();
    let m = u.march;
    let l = u.light;
    let mu = direction.y;
    let range = cloud_range(mu);
    // The ray's path through the slab (none where it sees no clouds: far < near).
    let path = (range.y - range.x).max(0.0);
    let depths = flat_path_depth(direction, range.x, range.x + path, jitter, pixel_angle, key);
    let tau_view = depths.x;
    let transmittance = (-tau_view).exp();
    // The same extinction, spread evenly over the layer's thickness, straight up.
    let thickness = (m.max_height - m.min_height).max(1.0);
    let tau_vertical = tau_view / path.max(1e-3) * thickness;
    // Where the ray crosses the layer's middle: the depth the result reports.
    let middle = 0.5 * (m.min_height + m.max_height);
    let roots = ray_shell(u.camera_altitude, mu, middle, m.radius);
    let t = select(roots.y, roots.x, roots.x > 0.0).max(range.x);
    // The sun's light averaged over the layer's depth, along its own slant: two-point
    // Gauss–Legendre in depth (the octaves' exponentials are convex in it, so the middle alone
    // reads darker than the mean).
    let sun_mu = l.sun_direction.y.max(0.02);
    let tau_sun = tau_vertical / sun_mu;
    let cos_theta = direction.dot(l.sun_direction);
    let phases = octave_phases(cos_theta, key);
    let sun_up = select(0.0, 1.0, l.sun_direction.y > 0.0);
    let scattered = 0.5
        * (sun_scattering(
            tau_sun * GAUSS_NEAR,
            tau_vertical * GAUSS_NEAR,
            tau_vertical * GAUSS_FAR,
            cos_theta,
            phases,
            mu,
            key,
        ) + sun_scattering(
            tau_sun * GAUSS_FAR,
            tau_vertical * GAUSS_FAR,
            tau_vertical * GAUSS_NEAR,
            cos_theta,
            phases,
            mu,
            key,
        ));
    let mut light = l.sun_irradiance * (scattered * sun_up);
    if gate(key, GROUND_BOUNCE) {
        // The ground's light, through the lower half of the layer, as the march adds it.
        light += ground_bounce_light(0.5 * tau_vertical);
    }
    // The sky's light, as the march gives it at a layer's middle.
    light += l.sky_irradiance * (INV_FOUR_PI * 0.75 * l.sky_light_scale);
    // The powder term, weighted by extinction as the march's samples weight it (1 without it).
    light *= select(1.0, depths.y / tau_view.max(1e-20), tau_view > 1e-20);
    let albedo =
        l.scattering_coefficient / (l.scattering_coefficient + l.absorption_coefficient).max(1e-6);
    // A homogeneous slab with a uniform source: S·(σs/σt)·(1 − e^(−τ)).
    MarchResult {
        radiance: light * (albedo * (1.0 - transmittance)),
        transmittance,
        front_depth: select(-1.0, t, tau_view > 1e-6),
        samples: FLAT_SAMPLES as f32,
    }
}

const INV_FOUR_PI: f32 = 0.079_577_47;
/// Depth fractions of the two-point Gauss–Legendre rule on [0, 1]: (1 ∓ 1/√3) / 2.
const GAUSS_NEAR: f32 = 0.211_324_87;
const GAUSS_FAR: f32 = 0.788_675_1;
