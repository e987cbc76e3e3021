//! Properties of the sample cloud model, checked on the CPU twins.

use nimbus_dsl::model::phase::{dual_lobe_hg, henyey_greenstein};
use nimbus_dsl::model::profile::density_profile;

/// ∫ p dΩ = 2π ∫_{-1}^{1} p(μ) dμ, by the midpoint rule on a grid fine enough for the peak at
/// g = 0.99 (width ≈ (1 − g)² ≈ 1e-4 in μ), accumulated in f64.
fn sphere_integral(p: impl Fn(f32) -> f32) -> f64 {
    let n = 2_000_000;
    let h = 2.0 / n as f64;
    let sum: f64 = (0..n)
        .map(|i| f64::from(p((-1.0 + (i as f64 + 0.5) * h) as f32)))
        .sum();
    2.0 * std::f64::consts::PI * sum * h
}

#[test]
fn henyey_greenstein_integrates_to_one() {
    for g in [-0.9, -0.5, 0.0, 0.3, 0.7, 0.9, 0.99] {
        let total = sphere_integral(|mu| henyey_greenstein(mu, g));
        assert!((total - 1.0).abs() < 1e-3, "g = {g}: ∫p dΩ = {total}");
    }
}

#[test]
fn dual_lobe_integrates_to_one_for_any_weight() {
    for w in [0.0, 0.25, 0.5, 1.0] {
        let total = sphere_integral(|mu| dual_lobe_hg(mu, 0.7, -0.2, w));
        assert!((total - 1.0).abs() < 1e-3, "w = {w}: ∫p dΩ = {total}");
    }
}

#[test]
fn henyey_greenstein_keeps_its_symmetry_and_peak() {
    for g in [0.2, 0.7, 0.9] {
        for mu in [-1.0, -0.3, 0.0, 0.5, 1.0] {
            let a = henyey_greenstein(mu, -g);
            let b = henyey_greenstein(-mu, g);
            assert!(
                (a - b).abs() <= 1e-6 * a.abs().max(1.0),
                "p(μ;−g) ≠ p(−μ;g) at g={g} μ={mu}"
            );
        }
    }
    // The stable denominator keeps the f32 peak at g = 0.999 within 1e-4 of (1+g)/(4π(1−g)²).
    let g = 0.999f32;
    let exact = (1.0 + f64::from(g)) / (4.0 * std::f64::consts::PI * (1.0 - f64::from(g)).powi(2));
    let got = f64::from(henyey_greenstein(1.0, g));
    assert!(
        ((got - exact) / exact).abs() < 1e-4,
        "peak {got} vs {exact}"
    );
}

#[test]
fn density_profile_default_and_overflow_cases() {
    assert_eq!(density_profile(0.0, 0.0, 0.0, 0.75, 0.25), 0.25);
    assert_eq!(density_profile(1.0, 0.0, 0.0, 0.75, 0.25), 1.0);
    // a = 0 with e^(b·η) overflowing must not give 0·∞ = NaN.
    assert_eq!(density_profile(1.0, 0.0, 1000.0, 0.75, 0.25), 1.0);
}
