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

/// The 22° halo's angle: the minimum deviation of light through two faces of a hexagonal ice
/// prism that meet at 60° (refractive index 1.31): `2 asin(1.31 sin 30°) − 60°` = 21.84°, in
/// radians. Rays deviate by at least this much and pile up there, so the sky inside the
/// halo is darker and its inner edge sharp.
pub const HALO_ANGLE: f32 = 0.381_167_7;

/// Width of the halo's inner edge (0.5°, radians): the sun's disc is 0.53° across and the
/// index of ice spreads the edge over the visible spectrum by about as much.
pub const HALO_RISE: f32 = 0.008_726_646;

/// How far beyond the angle the halo's light fades (3°, radians): rays that cross the prism
/// away from minimum deviation spread outwards.
pub const HALO_FALL: f32 = 0.052_359_88;

/// `1 / (2π ∫ ring(θ) sin θ dθ)` for the ring of [`halo_ring`]: with `s`, `c` the sine and
/// cosine of [`HALO_ANGLE`], the inner half-Gaussian gives `R√(π/2)s − R²c` and the outer
/// exponential `F(s + Fc)/(1 + F²)` (`tests/phase.rs` checks it against quadrature).
pub const HALO_NORM: f32 = 6.130_608;

/// Mean cosine of [`halo_ring`] (quadrature; `tests/phase.rs`).
pub const HALO_MEAN_COSINE: f32 = 0.907_771;

/// Second Legendre moment of [`halo_ring`] (quadrature; `tests/phase.rs`).
pub const HALO_SECOND_MOMENT: f32 = 0.737_172;

/// The 22° halo as a phase function on its own: all its light at scattering angles near
/// [`HALO_ANGLE`], a half-Gaussian of width [`HALO_RISE`] inside it and an exponential fade of
/// [`HALO_FALL`] outside, normalised over the sphere.
#[shader_fn]
pub fn halo_ring(cos_theta: f32) -> f32 {
    let x = cos_theta.clamp(-1.0, 1.0).acos() - HALO_ANGLE;
    let inner = (-0.5 * (x / HALO_RISE) * (x / HALO_RISE)).exp();
    let outer = (-x / HALO_FALL).exp();
    HALO_NORM * select(inner, outer, x > 0.0)
}

/// Scattering by the hexagonal ice crystals of cirriform cloud: a Henyey–Greenstein lobe of
/// asymmetry `g` (diffraction and the light through the crystals) and the fraction `halo` of
/// the light in the 22° halo ([`halo_ring`]).
#[shader_fn]
pub fn ice_crystal_phase(cos_theta: f32, g: f32, halo: f32) -> f32 {
    // A weighted sum, as `dual_lobe_hg` and for its reason.
    henyey_greenstein(cos_theta, g) * (1.0 - halo) + halo_ring(cos_theta) * halo
}
