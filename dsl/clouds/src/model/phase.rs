//! Phase functions: the angular distribution of light scattered by cloud droplets.
//!
//! All are normalised so that their integral over the sphere is 1 (units: 1/sr), and take
//! `cos_theta`, the cosine of the angle between the light's travel direction and the view ray's
//! reversed direction (1 = forward scattering).

use glam::Vec4;

use nimbus_dsl::prelude::*;

/// 1 / (4π).
const INV_FOUR_PI: f32 = 0.079_577_47;

/// Henyey–Greenstein (1941): `(1 − g²) / (4π (1 + g² − 2gμ)^{3/2})`.
///
/// The denominator is evaluated as `(1 − |g|)² + 2|g|(1 − μ')` with μ' = sign(g)·μ (the
/// symmetry p(μ; g) = p(−μ; −g)): both terms are non-negative, so nothing cancels. The
/// textbook `1 + g² − 2gμ` is 10 % wrong at the peak for g = 0.999 in f32.
#[shader_fn]
pub fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let k = g.abs();
    let mu = select(cos_theta, -cos_theta, g < 0.0);
    let one_minus_k = 1.0 - k;
    let denom = one_minus_k * one_minus_k + 2.0 * k * (1.0 - mu);
    let numerator = one_minus_k * (1.0 + k);
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
    // Weighted sum rather than `mix`: drivers evaluate `mix(x, y, a)` as `x + (y - x) * a`
    // (llvmpipe's GL does), and with the lobes up to seven orders of magnitude apart a weight
    // of 1 then returned the forward lobe's rounding error (2.4e-4 for 2.0e-4 at g = ±0.99).
    forward * (1.0 - weight) + backward * weight
}

/// Isotropic scattering, 1 / (4π).
#[shader_fn]
pub fn isotropic_phase(cos_theta: f32) -> f32 {
    // Reads the cosine so every phase function keeps the same signature in the WGSL (codegen
    // drops parameters a function never reads).
    INV_FOUR_PI + 0.0 * cos_theta
}

/// Rayleigh scattering by molecules: `3 (1 + μ²) / (16π)`, for haze and sky.
#[shader_fn]
pub fn rayleigh_phase(cos_theta: f32) -> f32 {
    0.059_683_1 * (1.0 + cos_theta * cos_theta)
}

/// Draine (2003): Henyey–Greenstein reshaped by `(1 + αμ²) / (1 + α(1 + 2g²)/3)`; α = 0 is HG,
/// α = 1 Cornette–Shanks.
#[shader_fn]
pub fn draine_phase(cos_theta: f32, g: f32, alpha: f32) -> f32 {
    let shape = (1.0 + alpha * cos_theta * cos_theta) / (1.0 + alpha * (1.0 + 2.0 * g * g) / 3.0);
    henyey_greenstein(cos_theta, g) * shape
}

/// The fitted parameters of the approximate Mie phase function for water droplets of
/// diameter `d` µm (valid 5..50; Jendersie & d'Eon 2023, "An Approximate Mie Scattering
/// Function for Fog and Cloud Rendering"): the Henyey–Greenstein lobe's `g` (x), the Draine
/// lobe's `g` (y) and `α` (z), and the Draine lobe's weight (w).
#[shader_fn]
pub fn approximate_mie_fit(d: f32) -> Vec4 {
    vec4(
        (-0.099_056_7 / (d - 1.671_54)).exp(),
        (-2.206_79 / (d + 3.910_29) - 0.428_934).exp(),
        (3.624_89 - 8.292_88 / (d + 5.528_25)).exp(),
        (-0.599_085 / (d - 0.641_583) - 0.665_888).exp(),
    )
}

/// Approximate Mie phase function for water droplets of diameter `d` µm (valid 5..50): a
/// blend of Henyey–Greenstein and Draine with the fitted parameters of
/// [`approximate_mie_fit`].
#[shader_fn]
pub fn approximate_mie(cos_theta: f32, d: f32) -> f32 {
    let fit = approximate_mie_fit(d);
    mix(
        henyey_greenstein(cos_theta, fit.x),
        draine_phase(cos_theta, fit.y, fit.z),
        fit.w,
    )
}

/// Mean cosine of [`approximate_mie`] at droplet diameter `d` µm: the blend of its lobes' mean
/// cosines, Draine's being `g (1 + α(3 + 2g²)/5) / (1 + α(1 + 2g²)/3)`.
#[shader_fn]
pub fn approximate_mie_asymmetry(d: f32) -> f32 {
    let fit = approximate_mie_fit(d);
    let g = fit.y;
    let alpha = fit.z;
    let draine =
        g * (1.0 + alpha * (3.0 + 2.0 * g * g) / 5.0) / (1.0 + alpha * (1.0 + 2.0 * g * g) / 3.0);
    mix(fit.x, draine, fit.w)
}

/// Second Legendre moment of [`approximate_mie`] at droplet diameter `d` µm: the blend of its
/// lobes' moments, Draine's being `(g² + α(36g⁴ + 55g² + 14)/105) / (1 + α(1 + 2g²)/3)`.
#[shader_fn]
pub fn approximate_mie_second_moment(d: f32) -> f32 {
    let fit = approximate_mie_fit(d);
    let g2 = fit.y * fit.y;
    let alpha = fit.z;
    let draine = (g2 + alpha * (36.0 * g2 * g2 + 55.0 * g2 + 14.0) / 105.0)
        / (1.0 + alpha * (1.0 + 2.0 * g2) / 3.0);
    mix(fit.x * fit.x, draine, fit.w)
}
