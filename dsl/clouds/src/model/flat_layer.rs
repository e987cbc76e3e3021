//! A thin high layer (cirrus, cirrostratus) drawn as a textured 2D layer: where the view ray
//! crosses the layer's middle, a few density reads straight up through it give its optical
//! depth, and the layer is lit as a homogeneous slab of that depth, by the sun through half of
//! it (with the model's multiple-scattering octaves and phase function), the sky and the ground,
//! darkened by the march's powder term at the layer's mean extinction. No march:
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
use super::march::{MarchResult, cloud_range, multiple_scattering, total_density};
use super::shell::ray_shell;
use crate::key::CloudKey;

/// Density reads per pixel, stratified through the layer's thickness.
pub const FLAT_SAMPLES: u32 = 4;

/// Vertical optical depth of the clouds over the horizontal position of `position`
/// (camera-relative, on the layer), by [`FLAT_SAMPLES`] stratified reads from the slab's bottom
/// to its top, each standing for `footprint` metres across.
#[shader_fn]
pub fn flat_vertical_depth(
    position: Vec3,
    jitter: f32,
    footprint: f32,
    #[spec] key: CloudKey,
) -> f32 {
    let u = CLOUDS.get();
    let m = u.march;
    let sigma_ratio = u.light.scattering_coefficient + u.light.absorption_coefficient;
    let dh = (m.max_height - m.min_height).max(0.0) / FLAT_SAMPLES as f32;
    let mut tau = 0.0f32;
    for i in 0u32..FLAT_SAMPLES {
        let h = m.min_height + (i as f32 + jitter) * dh;
        let p = vec3(position.x, h - u.camera_altitude, position.z);
        tau += total_density(p, h, footprint.max(dh), key) * sigma_ratio * dh;
    }
    tau
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
    // Where the ray crosses the layer's middle (the first crossing beyond the camera).
    let middle = 0.5 * (m.min_height + m.max_height);
    let roots = ray_shell(u.camera_altitude, mu, middle, m.radius);
    let t = select(roots.y, roots.x, roots.x > 0.0).max(range.x);
    let thickness = (m.max_height - m.min_height).max(1.0);
    let tau_vertical = flat_vertical_depth(direction * t, jitter, t * pixel_angle, key);
    // The slab's extinction, spread evenly over its thickness, along the ray's path in it (none
    // where the ray sees no clouds: far < near).
    let path = (range.y - range.x).max(0.0);
    let tau_view = tau_vertical / thickness * path;
    let transmittance = (-tau_view).exp();
    // The sun reaches the middle through half the layer, along its own slant.
    let sun_mu = l.sun_direction.y.max(0.02);
    let tau_sun = 0.5 * tau_vertical / sun_mu;
    let cos_theta = direction.dot(l.sun_direction);
    let sun_up = select(0.0, 1.0, l.sun_direction.y > 0.0);
    let mut light = l.sun_irradiance * (multiple_scattering(tau_sun, cos_theta, key) * sun_up);
    if gate(key, GROUND_BOUNCE) {
        // The ground's light, through the lower half of the layer, as the march adds it.
        let ground_irradiance = l.sky_irradiance
            + l.sun_irradiance * ((1.0 - u.media.coverage) * l.sun_direction.y.max(0.0));
        let bounce = l.ground_albedo
            * INV_PI
            * (-0.5 * tau_vertical).exp()
            * INV_FOUR_PI
            * l.ground_bounce_scale;
        light += ground_irradiance * bounce;
    }
    // The sky's light, as the march gives it at a layer's middle.
    light += l.sky_irradiance * (INV_FOUR_PI * 0.75 * l.sky_light_scale);
    if gate(key, POWDER) {
        // The march's powder term at the layer's mean extinction: it darkens a thin layer
        // throughout, not only at its edges.
        light *= 1.0 - l.powder_scale * (-(tau_vertical / thickness) * l.powder_exponent).exp();
    }
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
const INV_PI: f32 = core::f32::consts::FRAC_1_PI;
