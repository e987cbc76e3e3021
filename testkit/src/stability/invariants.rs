//! The invariants every probe of the catalogue must keep, and the energy bounds they use.

use glam::{Vec3, Vec4};

use nimbus_clouds::CloudKey;
use nimbus_clouds::model::bindings::CLOUDS;
use nimbus_clouds::model::diffusion::{forward_peak_weight, phase_asymmetry, phase_second_moment};
use nimbus_clouds::model::march::{CloudUniforms, cloud_phase, sun_attenuation};
use nimbus_clouds::model::phase::henyey_greenstein;
use nimbus_clouds::model::sky::sun_disc;
use nimbus_dsl::CpuBindings;

use super::case::Case;
use super::probe::RayOutcome;

const INV_PI: f32 = core::f32::consts::FRAC_1_PI;
const INV_FOUR_PI: f32 = 0.079_577_47;

/// One broken invariant.
#[derive(Clone, Debug, PartialEq)]
pub struct Violation {
    pub case: &'static str,
    /// Probe index (the first of a chain or pair).
    pub probe: usize,
    pub what: String,
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} probe #{}: {}", self.case, self.probe, self.what)
    }
}

/// Largest value of the variant's phase function over all angles (it peaks at cos θ = ±1 for
/// every kind here; a grid with both ends makes sure).
fn phase_peak(u: &CloudUniforms, key: &CloudKey) -> f32 {
    let _bound = CpuBindings::new().set(&CLOUDS, *u).bind();
    (0..=2000)
        .map(|i| cloud_phase(-1.0 + i as f32 / 1000.0, 1.0, *key))
        .fold(INV_FOUR_PI, f32::max)
}

/// Largest light the diffusion adds per unit of sun irradiance and scattering coefficient (0
/// without it): the diffuse fluence is at most `3μ0² + 2μ0 ≤ 5` and its flux at most 2, seen
/// as `(φ + 3|g|·|F|) / 4π`, plus the forward peak's light at the peak of the rest of the
/// phase function.
fn diffusion_peak(u: &CloudUniforms, key: &CloudKey) -> f32 {
    if !key.features.diffusion {
        return 0.0;
    }
    let _bound = CpuBindings::new().set(&CLOUDS, *u).bind();
    let g = phase_asymmetry(*key);
    let f = forward_peak_weight(g, phase_second_moment(*key));
    let g_star = (g - f) / (1.0 - f);
    let rest = henyey_greenstein(1.0, g_star).max(henyey_greenstein(-1.0, g_star));
    (5.0 + 3.0 * 2.0) * INV_FOUR_PI + rest
}

/// Upper bound of the light a unit of scattering coefficient sends towards the camera: the sun
/// through every octave (Σ 2⁻ᵏ ≤ 2 times the phase peak, brightened at most as much as the
/// atmosphere above the camera dims it) and the diffusion, plus sky light (through the
/// diffusion's slab where it is on) and ground bounce at their largest.
pub fn source_bound(u: &CloudUniforms, key: &CloudKey) -> Vec3 {
    let l = u.light;
    let attenuation = if key.features.accurate_sun_sky_light {
        // The ratio grows with the sample's altitude; a sample in space bounds it.
        sun_attenuation(1e7, u.camera_altitude, l.sun_direction.y)
    } else {
        1.0
    };
    let sun =
        l.sun_irradiance * (attenuation * (2.0 * phase_peak(u, key) + diffusion_peak(u, key)));
    // With the diffusion the sky's light in a cloud is the two-stream slab's: fluence at most
    // 4 and flux at most 1, seen as `(φ + 3|g|·F) / 4π`.
    let sky_peak = if key.features.diffusion {
        let _bound = CpuBindings::new().set(&CLOUDS, *u).bind();
        (4.0 + 3.0 * phase_asymmetry(*key).abs()) * INV_FOUR_PI
    } else {
        INV_FOUR_PI
    };
    let sky = l.sky_irradiance * (sky_peak * l.sky_light_scale);
    let ground = if key.features.ground_bounce {
        (l.sky_irradiance + l.sun_irradiance)
            * (l.ground_albedo * INV_PI * INV_FOUR_PI * l.ground_bounce_scale)
    } else {
        Vec3::ZERO
    };
    sun + sky + ground
}

/// Upper bound of a pixel: the sun's disc seen through no air, the clouds' source bound, and
/// everything else that scatters sunlight (air and haze at their phase peaks, plus the sky).
pub fn fragment_bound(u: &CloudUniforms, key: &CloudKey) -> Vec3 {
    let top = u.sky.solar_irradiance;
    let disc = sun_disc(1.0, Vec3::ONE, u.sky);
    let air_peak = henyey_greenstein(1.0, u.sky.mie_g) + 2.0 * INV_FOUR_PI;
    disc + source_bound(u, key)
        + top * (2.0 * phase_peak(u, key) + air_peak + 1.0)
        + u.light.sky_irradiance
}

fn finite(v: Vec4) -> bool {
    v.is_finite()
}

/// Checks every invariant of `case` on `outcomes` (one per probe, from the CPU twins or the
/// GPU). Returns all violations, not only the first.
pub fn check_case(case: &Case, outcomes: &[RayOutcome]) -> Vec<Violation> {
    let mut out = Vec::new();
    let mut fail = |probe: usize, what: String| {
        out.push(Violation {
            case: case.name,
            probe,
            what,
        })
    };
    if outcomes.len() != case.probes.len() {
        fail(
            0,
            format!(
                "{} outcomes for {} probes",
                outcomes.len(),
                case.probes.len()
            ),
        );
        return out;
    }
    for (i, (p, o)) in case.probes.iter().zip(outcomes).enumerate() {
        let m = o.march;
        let u = &p.uniforms;
        let values = [
            m.radiance.extend(m.transmittance),
            Vec4::new(m.front_depth, m.samples, 0.0, 0.0),
            o.colour,
        ];
        if !values.iter().all(|v| finite(*v)) {
            fail(
                i,
                format!("non-finite output: march {m:?}, colour {}", o.colour),
            );
            continue;
        }
        if !(0.0..=1.0).contains(&m.transmittance) {
            fail(
                i,
                format!("transmittance {} outside [0, 1]", m.transmittance),
            );
        }
        let l = u.light;
        let albedo = l.scattering_coefficient
            / (l.scattering_coefficient + l.absorption_coefficient).max(1e-30);
        let limit = source_bound(u, &case.key) * (albedo * (1.0 - m.transmittance));
        // f32 rounding over thousands of steps: a thousandth of the bound, and a sliver of the
        // source for rays whose transmittance rounds to 1.
        let slack = source_bound(u, &case.key) * 1e-5;
        if m.radiance.min_element() < 0.0
            || (m.radiance - (limit * 1.001 + slack)).max_element() > 0.0
        {
            fail(
                i,
                format!(
                    "radiance {} outside [0, S_max·albedo·(1 − T)] = [0, {limit}] (T = {})",
                    m.radiance, m.transmittance
                ),
            );
        }
        let bound = fragment_bound(u, &case.key);
        let rgb = o.colour.truncate();
        if rgb.min_element() < 0.0 || (rgb - bound).max_element() > 0.0 {
            fail(i, format!("pixel {rgb} outside [0, {bound}]"));
        }
        let mk = u.march;
        let per_sample = 1.0
            + mk.sun_steps as f32
            + if case.key.features.ground_bounce {
                mk.ground_steps as f32
            } else {
                0.0
            };
        let max_samples = mk.max_iterations as f32 * per_sample;
        if m.samples > max_samples {
            fail(
                i,
                format!(
                    "{} density samples, more than the limit {max_samples}",
                    m.samples
                ),
            );
        }
    }
    for chain in &case.chains {
        for w in chain.windows(2) {
            let (near, far) = (outcomes[w[0]].march, outcomes[w[1]].march);
            if far.transmittance > near.transmittance + 1e-6 {
                fail(
                    w[0],
                    format!(
                        "transmittance rises along the ray: {} at probe #{}, then {} at #{}",
                        near.transmittance, w[0], far.transmittance, w[1]
                    ),
                );
            }
        }
    }
    for pair in &case.pairs {
        let (a, b) = (outcomes[pair.a], outcomes[pair.b]);
        // Absolute slack in units of the clouds' light (the pixel bound is the sun's disc).
        let scale = source_bound(&case.probes[pair.a].uniforms, &case.key).max_element();
        let (ca, cb) = (a.colour.truncate(), b.colour.truncate());
        let allowed = pair.rel * ca.abs().max(cb.abs()).max_element() + pair.abs * scale;
        let diff = (ca - cb).abs().max_element();
        let dt = (a.march.transmittance - b.march.transmittance).abs();
        if diff > allowed || dt > pair.rel + pair.abs {
            fail(
                pair.a,
                format!(
                    "not continuous: pixel {ca} (T {}) vs {cb} (T {}) at probe #{}; |Δ| {diff:e} > {allowed:e} or |ΔT| {dt} > {}",
                    a.march.transmittance,
                    b.march.transmittance,
                    pair.b,
                    pair.rel + pair.abs
                ),
            );
        }
    }
    out
}
