//! Multiple scattering in thick cloud: the Eddington two-stream (diffusion) solution of the
//! layer around each sample, in place of the octaves.
//!
//! The octaves (`Σ aᵏ e^(−τbᵏ) p(μ; cᵏg)`) dim every order of scattering by the optical depth
//! to the sun, so deep in a deck, where that depth is in the hundreds, all of them vanish: a
//! stratocumulus deck read 3 times too dark from above, 6 times from below and 15 times from
//! inside against Mitsuba's path tracer, while thin cirrostratus read 1.8 times too bright. In
//! cloud the light that has scattered many times is diffuse, and its fluence falls off
//! linearly with depth, not exponentially.
//!
//! Each sample is taken to lie in a horizontally uniform slab: its depth below the sunlit top
//! is the optical depth towards the sun times the sun's cosine, and the slab ends where the
//! march down to the base ends. The phase function is split the δ-Eddington way (Joseph,
//! Wiscombe & Weinman 1976): its forward peak, of weight `f` = its second Legendre moment,
//! travels on with the sunbeam, which then dims as `e^(−(1 − f)τ)`; what the peak carried is
//! scattered once more by the rest of the phase function ([`forward_peak`]). Everything else
//! diffuses through the slab with the phase function's mean cosine `g`, in transport depths
//! `(1 − g)τ`, Marshak boundaries top and bottom, with the beam's forward momentum as a source
//! ([`slab_diffuse_fluence`]). Against a random walk through the slab (`tests/diffusion.rs`):
//! within 2–7 % from 10 optical depths on, about 20 % low at 2.
//!
//! Written with no fitted constant: against Mitsuba 3 over the agreement suite the octaves'
//! 0.07–1.77 of the path tracer's light became 0.86–1.15 (README, "The agreement suite").

use glam::Vec2;

use crate::key::CloudKey;
use nimbus_dsl::prelude::*;

use super::bindings::CLOUDS;
use super::choices::{APPROXIMATE_MIE, DUAL_LOBE, HENYEY_GREENSTEIN, ICE_CRYSTAL, phase_is};
use super::phase::{
    HALO_MEAN_COSINE, HALO_SECOND_MOMENT, approximate_mie_asymmetry, approximate_mie_second_moment,
    henyey_greenstein,
};

/// 1 / (4π).
const INV_FOUR_PI: f32 = 0.079_577_47;

/// The largest forward-peak weight: a phase function all peak (g → 1) would leave nothing to
/// diffuse and divide by zero.
const MAX_PEAK: f32 = 0.99;

/// How far the real-time presets' sun depth may fall short of the slab's before a sample is
/// taken to be lit through a side. Their two sun steps and the shadow map (whose mean extinction
/// is that of the first optical depths below the top, where a rounded layer is thin) read a
/// deck's sun depth low, and their one vertical step (a midpoint, where the layer is densest)
/// its vertical depth high: `tau_up / (tau_sun·μ0)`, 1.00 in the reference for any uniform
/// deck, read 1.75 for the stratus deck and 2.1 for the nimbostratus (3.5 km). Taken at its
/// word, every sample of such a deck was lit through a face straight across the beam, and its
/// base was bright towards the sun and dark away from it (0.30 against 0.85 of the zenith's
/// luminance 15° up, where the reference is even in azimuth). A side that faces the sun reads
/// tens (a tower's side under a 35° sun, 2 optical depths in from it and 30 below its top: 26),
/// so 3 keeps the sides and leaves decks lit through their tops.
const REAL_TIME_TOLERANCE: f32 = 3.0;

/// Mean cosine `g` of the key's phase function (its first Legendre moment).
#[shader_fn]
pub fn phase_asymmetry(#[spec] key: CloudKey) -> f32 {
    let light = CLOUDS.get().light;
    if phase_is(key, HENYEY_GREENSTEIN) {
        return light.g1;
    }
    if phase_is(key, DUAL_LOBE) {
        return light.g1 * (1.0 - light.lobe_weight) + light.g2 * light.lobe_weight;
    }
    if phase_is(key, APPROXIMATE_MIE) {
        return approximate_mie_asymmetry(light.droplet_diameter);
    }
    if phase_is(key, ICE_CRYSTAL) {
        return light.g1 * (1.0 - light.lobe_weight) + HALO_MEAN_COSINE * light.lobe_weight;
    }
    0.0
}

/// Second Legendre moment of the key's phase function: δ-Eddington's forward-peak weight `f`
/// (`g²` for Henyey–Greenstein, the weighted `gᵢ²` for two lobes).
#[shader_fn]
pub fn phase_second_moment(#[spec] key: CloudKey) -> f32 {
    let light = CLOUDS.get().light;
    if phase_is(key, HENYEY_GREENSTEIN) {
        return light.g1 * light.g1;
    }
    if phase_is(key, DUAL_LOBE) {
        return light.g1 * light.g1 * (1.0 - light.lobe_weight)
            + light.g2 * light.g2 * light.lobe_weight;
    }
    if phase_is(key, APPROXIMATE_MIE) {
        return approximate_mie_second_moment(light.droplet_diameter);
    }
    if phase_is(key, ICE_CRYSTAL) {
        return light.g1 * light.g1 * (1.0 - light.lobe_weight)
            + HALO_SECOND_MOMENT * light.lobe_weight;
    }
    0.0
}

/// δ-Eddington's forward-peak weight `f` for a phase function of mean cosine `g` and second
/// moment `chi2`: the second moment, where the phase function peaks forwards. It is kept
/// within [0, max(g, 0)] so that the rest of the phase function, of mean cosine
/// `g* = (g − f)/(1 − f)`, stays between 0 and `g` (a backward phase function has no forward
/// peak to split off: `g* = g`), and below [`MAX_PEAK`].
#[shader_fn]
pub fn forward_peak_weight(g: f32, chi2: f32) -> f32 {
    chi2.min(g.max(0.0)).clamp(0.0, MAX_PEAK)
}

/// Fluence (x) and downward net flux (y) of the diffuse light at transport depth `z` below
/// the top of a conservatively scattering slab of transport depth `total`, lit by a sunbeam of
/// irradiance 1 at up-cosine `mu0` that dims as `e^(−z/nu)` in transport depth.
///
/// The Eddington equations `F′ = (μ0/ν)e^(−z/ν)` (what the beam loses, the diffuse light
/// gains) and `φ′ = −3F + 3(μ0/ν − 1)μ0·e^(−z/ν)` (the beam's forward momentum), with no
/// diffuse light entering at either face (`φ ± 2F = 0`), solve to
/// `φ = D − 3Cz − 3μ0²e^(−z/ν)`, `F = C − μ0·e^(−z/ν)`.
#[shader_fn]
pub fn slab_diffuse_fluence(z: f32, total: f32, mu0: f32, nu: f32) -> Vec2 {
    let beam = (-z / nu).exp();
    let through = (-total / nu).exp();
    let c = mu0 * (3.0 * mu0 * (1.0 - through) + 2.0 * (1.0 + through)) / (3.0 * total + 4.0);
    let d = 3.0 * mu0 * mu0 - 2.0 * c + 2.0 * mu0;
    let fluence = d - 3.0 * c * z - 3.0 * mu0 * mu0 * beam;
    vec2(fluence.max(0.0), c - mu0 * beam)
}

/// Below this much absorption per scattering (`1 − ω`, δ-scaled) a slab is taken to be
/// conservative ([`slab_diffuse_fluence`]): the absorbing solution's two exponentials then
/// nearly cancel, and in single precision its error outgrows what the absorption changes.
const CONSERVATIVE_BELOW: f32 = 1e-4;

/// Fluence (x) and downward net flux (y) of the diffuse light at optical depth `t` below the
/// top of a slab of optical depth `total` that absorbs: single-scattering albedo `omega` < 1
/// and mean cosine `g`, both δ-scaled like the depths, lit by a sunbeam of irradiance `beam`
/// at up-cosine `mu0` that dims as `e^(−t/mu0)` and by diffuse light of flux `sky` entering
/// its top (none its base).
///
/// The Eddington equations `F′ = ω·beam·e^(−t/μ0) − (1 − ω)φ` (the beam's scattered light
/// gained, the diffuse light's absorbed lost) and `φ′ = −3(1 − ωg)F + 3ωgμ0·beam·e^(−t/μ0)`
/// solve to `φ = A e^(−k(T−t)) + B e^(−kt) + α e^(−t/μ0)`, with `k² = 3(1 − ω)(1 − ωg)`:
/// in a thick absorbing cloud the diffuse light dies out over `1/k` optical depths instead of
/// falling linearly through the whole slab. `A` and `B` follow from Marshak's conditions
/// `φ + 2F = 4·sky` at the top and `φ − 2F = 0` at the base, written with `e^(−kT)` so no
/// exponential overflows however thick the slab.
#[shader_fn]
pub fn absorbing_slab(
    t: f32,
    total: f32,
    mu0: f32,
    omega: f32,
    g: f32,
    beam: f32,
    sky: f32,
) -> Vec2 {
    let a = 1.0 - omega * g;
    let k = (3.0 * (1.0 - omega) * a).max(0.0).sqrt();
    let p = k / (3.0 * a);
    // The beam's particular solution φ = αe^(−t/μ0), F = βe^(−t/μ0); at kμ0 = 1 the beam
    // and a homogeneous solution coincide, and a cosine 0.1 % off stands in for it.
    let m = select(mu0, mu0 * 1.001, (k * mu0 - 1.0).abs() < 1e-3);
    let alpha = beam * 3.0 * omega * m * m * (1.0 + g * (1.0 - omega)) / (k * k * m * m - 1.0);
    let beta = m * ((1.0 - omega) * alpha - omega * beam);
    let x = (-k * total).exp();
    // The 2×2 system [[x(1 − 2P), 1 + 2P], [1 + 2P, x(1 − 2P)]]·(A, B) = (r1, r2).
    let outer = x * (1.0 - 2.0 * p);
    let inner = 1.0 + 2.0 * p;
    let r1 = 4.0 * sky - alpha - 2.0 * beta;
    let r2 = -(alpha - 2.0 * beta) * (-total / m).exp();
    let det = (outer * outer - inner * inner).min(-1e-12);
    let from_base = (r1 * outer - inner * r2) / det;
    let from_top = (outer * r2 - inner * r1) / det;
    let up = (-k * (total - t)).exp();
    let down = (-k * t).exp();
    let s = (-t / m).exp();
    vec2(
        (from_base * up + from_top * down + alpha * s).max(0.0),
        -p * (from_base * up - from_top * down) + beta * s,
    )
}

/// The sunlight that reached a sample `tau_sun` deep by scattering within the forward peak
/// (weight `f`), scattered once more towards the camera by the rest of the phase function
/// (Henyey–Greenstein of `g_star`): what the δ-scaled beam `e^(−(1 − f)τ)` carries beyond the
/// unscattered `e^(−τ)`.
///
/// `omega` is the single-scattering albedo: the peak scatters `ω·f` of what the beam loses.
#[shader_fn]
pub fn forward_peak(tau_sun: f32, cos_theta: f32, f: f32, g_star: f32, omega: f32) -> f32 {
    let carried = (-(1.0 - omega * f) * tau_sun).exp() - (-tau_sun).exp();
    (1.0 - f) * henyey_greenstein(cos_theta, g_star) * carried
}

/// Single-scattering albedo of the clouds' medium, `σs / (σs + σa)`.
#[shader_fn]
pub fn cloud_albedo() -> f32 {
    let l = CLOUDS.get().light;
    l.scattering_coefficient / (l.scattering_coefficient + l.absorption_coefficient).max(1e-12)
}

/// Up-cosine of the sunlit face a sample lies under, and its cosine to the sun: a horizontally
/// uniform deck is lit through its top (the face's cosine to the sun is the sun's elevation
/// sine `mu0`), an isolated cloud under a low sun through its sunlit side, which faces the sun.
/// Which one is told by the optical depths: under a top the sun's slant path is the vertical
/// one over `mu0`; where the slant path is shorter than that, it came in through a side, and
/// the face's cosine to the sun is `tau_up / tau_sun`, up to 1 (the face straight across the
/// beam). Returns (cosine to the sun, the view ray's cosine to the face's normal), the normal
/// taken in the vertical plane of the sun.
///
/// `tolerance` is how far short of the slab's the sun's depth may fall from the estimates
/// alone: 1 where both are marched the whole way (the reference), [`REAL_TIME_TOLERANCE`]
/// where the sun's comes from two steps and the shadow map and the vertical from one step.
#[shader_fn]
pub fn sunlit_face(
    tau_sun: f32,
    tau_up: f32,
    cos_theta: f32,
    view_up: f32,
    mu0: f32,
    tolerance: f32,
) -> Vec2 {
    let mu_face = (tau_up / (tau_sun * tolerance).max(1e-6)).clamp(mu0, 1.0);
    // The normal is the vertical tilted towards the sun by `alpha`.
    let alpha = (mu0.acos() - mu_face.acos()).max(0.0);
    let sun_across = (1.0 - mu0 * mu0).max(0.0).sqrt().max(1e-4);
    let view_towards_sun = (cos_theta - view_up * mu0) / sun_across;
    vec2(
        mu_face,
        alpha.sin() * view_towards_sun + alpha.cos() * view_up,
    )
}

/// Sunlight scattered more than once towards the camera, per unit of sun irradiance and of
/// σs, at a sample `tau_sun` deep towards the sun, `tau_up` below the top and `tau_down` above
/// the slab's base, on a view ray of up-cosine `view_up`: the forward peak's light and the
/// diffuse light's in-scattering `(φ + 3gF·ω) / 4π` (the Eddington radiance `(φ + 3F·ω) / 4π`
/// seen through the phase function), in the slab under the sample's sunlit face
/// ([`sunlit_face`]).
#[shader_fn]
pub fn diffuse_scattering(
    tau_sun: f32,
    tau_up: f32,
    tau_down: f32,
    cos_theta: f32,
    view_up: f32,
    #[spec] key: CloudKey,
) -> f32 {
    let u = CLOUDS.get();
    let mu0 = u.light.sun_direction.y.max(0.01);
    let tolerance = select(REAL_TIME_TOLERANCE, 1.0, u.march.secondary_full_path > 0u32);
    let face = sunlit_face(tau_sun, tau_up, cos_theta, view_up, mu0, tolerance);
    let g = phase_asymmetry(key);
    let f = forward_peak_weight(g, phase_second_moment(key));
    let g_star = (g - f) / (1.0 - f);
    let omega = cloud_albedo();
    // δ-scaled: the peak's scattering is no event, so depths shrink by 1 − ωf and the albedo
    // of what is left is (1 − f)ω / (1 − ωf).
    let scale = 1.0 - omega * f;
    let omega_star = (1.0 - f) * omega / scale;
    let z = (1.0 - g) * tau_sun * face.x;
    let mut diffuse =
        slab_diffuse_fluence(z, z + (1.0 - g) * tau_down, face.x, (1.0 - g_star) * face.x);
    // A branch on a uniform: the genera that absorb nothing never take it.
    if 1.0 - omega_star >= CONSERVATIVE_BELOW {
        let depth = scale * tau_sun * face.x;
        diffuse = absorbing_slab(
            depth,
            depth + scale * tau_down,
            face.x,
            omega_star,
            g_star,
            1.0,
            0.0,
        );
    }
    let seen = (diffuse.x + 3.0 * g * diffuse.y * face.y).max(0.0) * INV_FOUR_PI;
    seen + forward_peak(tau_sun, cos_theta, f, g_star, omega)
}

/// The sky's diffuse light scattered towards the camera, per unit of the sky's horizontal
/// irradiance and of σs, at a sample `tau_up` below the top of the cloud and `tau_down` above
/// its base, on a view ray of up-cosine `view_up`.
///
/// Diffuse light entering a conservative slab's top with flux 1 (and none its base) solves
/// the Eddington equations with a constant downward flux `F = 4/(3T + 4)` and the fluence
/// `φ = 4 − 2F − 3Fz` at transport depth `z` of `T`: the top of a thick cloud sees the sky's
/// radiance `1/π` from everywhere (what the sky sends down, the cloud sends back up), its base
/// only what diffuses through. Without it a thick layer's base was lit by half the sky's blue
/// light however deep it lay, and a nimbostratus read navy blue from below.
#[shader_fn]
pub fn sky_diffuse_scattering(
    tau_up: f32,
    tau_down: f32,
    view_up: f32,
    #[spec] key: CloudKey,
) -> f32 {
    let g = phase_asymmetry(key);
    let z = (1.0 - g) * tau_up;
    let total = z + (1.0 - g) * tau_down;
    let flux = 4.0 / (3.0 * total + 4.0);
    let mut diffuse = vec2(4.0 - 2.0 * flux - 3.0 * flux * z, flux);
    // With absorption, the same light in δ-scaled depths (see `diffuse_scattering`).
    let f = forward_peak_weight(g, phase_second_moment(key));
    let omega = cloud_albedo();
    let scale = 1.0 - omega * f;
    let omega_star = (1.0 - f) * omega / scale;
    if 1.0 - omega_star >= CONSERVATIVE_BELOW {
        let depth = scale * tau_up;
        let g_star = (g - f) / (1.0 - f);
        diffuse = absorbing_slab(
            depth,
            depth + scale * tau_down,
            1.0,
            omega_star,
            g_star,
            0.0,
            1.0,
        );
    }
    (diffuse.x + 3.0 * g * diffuse.y * view_up).max(0.0) * INV_FOUR_PI
}
