//! Phase functions: the angular distribution of light scattered by cloud droplets.
//!
//! All are normalised so that their integral over the sphere is 1 (units: 1/sr), and take
//! `cos_theta`, the cosine of the angle between the light's travel direction and the view ray's
//! reversed direction (1 = forward scattering).

use crate::prelude::*;

/// 1 / (4π).
const INV_FOUR_PI: f32 = 0.079_577_47;

/// Henyey–Greenstein (1941): `(1 − g²) / (4π (1 + g² − 2gμ)^{3/2})`.
///
/// The denominator is evaluated as `(1 − g)² + 2g(1 − μ)`, which is the same quantity without
/// the cancellation that makes the textbook form 10 % wrong near μ = 1 at g = 0.999 in f32.
#[shader_fn]
pub fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let one_minus_g = 1.0 - g;
    let denom = one_minus_g * one_minus_g + 2.0 * g * (1.0 - cos_theta);
    let numerator = one_minus_g * (1.0 + g);
    INV_FOUR_PI * numerator / (denom * denom.sqrt())
}

/// Two Henyey–Greenstein lobes mixed by `weight`: `(1 − w)·HG(μ, g1) + w·HG(μ, g2)`.
///
/// A forward lobe (g1 ≈ 0.7) gives the silver lining, a backward one (g2 ≈ −0.2) the glow seen
/// with the sun behind the viewer. Normalised for any weight in [0, 1].
#[shader_fn]
pub fn dual_lobe_hg(cos_theta: f32, g1: f32, g2: f32, weight: f32) -> f32 {
    let forward = henyey_greenstein(cos_theta, g1);
    let backward = henyey_greenstein(cos_theta, g2);
    mix(forward, backward, weight)
}
