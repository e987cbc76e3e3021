//! Properties of the sample cloud model, checked on the CPU twins.

use nimbus_clouds::model::phase::{dual_lobe_hg, henyey_greenstein};
use nimbus_clouds::model::profile::density_profile;

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

#[test]
fn every_phase_function_integrates_to_one() {
    use nimbus_clouds::model::phase::{
        approximate_mie, draine_phase, isotropic_phase, rayleigh_phase,
    };
    type Phase = Box<dyn Fn(f32) -> f32>;
    let cases: Vec<(&str, Phase)> = vec![
        ("isotropic", Box::new(isotropic_phase)),
        ("rayleigh", Box::new(rayleigh_phase)),
        (
            "draine g=0.5 a=1",
            Box::new(|mu| draine_phase(mu, 0.5, 1.0)),
        ),
        (
            "draine g=-0.3 a=20",
            Box::new(|mu| draine_phase(mu, -0.3, 20.0)),
        ),
        ("mie d=10", Box::new(|mu| approximate_mie(mu, 10.0))),
        ("mie d=20", Box::new(|mu| approximate_mie(mu, 20.0))),
        ("mie d=50", Box::new(|mu| approximate_mie(mu, 50.0))),
    ];
    for (name, p) in cases {
        let total = sphere_integral(p);
        assert!((total - 1.0).abs() < 2e-3, "{name}: ∫p dΩ = {total}");
    }
}

/// The shell intersection in f32 against the same geometry in f64 (plain quadratic is exact
/// enough there): within a metre except at grazing incidence, where only continuity matters.
#[test]
fn ray_shell_is_accurate_at_planet_scale() {
    use nimbus_clouds::model::shell::{EARTH_RADIUS, ray_shell};
    let r = f64::from(EARTH_RADIUS);
    let exact = |hc: f64, mu: f64, hs: f64| -> Option<(f64, f64)> {
        let b = (r + hc) * mu;
        let c = (r + hc) * (r + hc) - (r + hs) * (r + hs);
        let d = b * b - c;
        (d >= 0.0).then(|| (-b - d.sqrt(), -b + d.sqrt()))
    };
    let mut worst = 0.0f64;
    for hc in [2.0, 500.0, 1100.0, 5000.0, 10_000.0] {
        for elev_deg in [-30.0, -2.0, 0.0, 1.0, 5.0, 45.0, 90.0] {
            let mu = f64::to_radians(elev_deg).sin();
            for hs in [750.0, 2200.0, 8000.0] {
                let got = ray_shell(hc as f32, mu as f32, hs as f32, EARTH_RADIUS);
                // Feed the f64 reference the f32-rounded inputs, so only arithmetic error counts.
                let Some((t0, t1)) = exact(
                    f64::from(hc as f32),
                    f64::from(mu as f32),
                    f64::from(hs as f32),
                ) else {
                    assert_eq!(
                        got,
                        glam::Vec2::splat(-1.0),
                        "hc={hc} elev={elev_deg} hs={hs}"
                    );
                    continue;
                };
                for (g, e) in [(got.x, t0), (got.y, t1)] {
                    assert!(g.is_finite(), "hc={hc} elev={elev_deg} hs={hs}");
                    let err = (f64::from(g) - e).abs();
                    worst = worst.max(err);
                    assert!(
                        err < 1.0,
                        "hc={hc} elev={elev_deg} hs={hs}: {g} vs {e} (error {err} m)"
                    );
                }
            }
        }
    }
    println!("ray_shell worst error vs f64: {worst:.3} m");
}

/// The reference's detail erosion doubles density even at amount 0, so a variant without the
/// stage was not the same as one with a zero amount; the gain now follows the amount.
#[test]
fn detail_erosion_at_amount_zero_is_no_detail() {
    use nimbus_clouds::model::density::detail_erosion;
    for rho in [0.0f32, 0.1, 0.37, 0.5, 0.99, 1.0] {
        for d in [0.0f32, 0.3, 1.0] {
            let eta = glam::Vec4::new(0.0, 0.25, 0.6, 1.0);
            let out = detail_erosion(
                glam::Vec4::splat(rho),
                d.powi(6),
                1.0 - d,
                eta,
                glam::Vec4::ZERO,
            );
            assert_eq!(out, glam::Vec4::splat(rho), "rho {rho}, d {d}");
        }
    }
    // At amount 1 it is the reference's (2ρ − m/2)/(1 − m/2).
    let (rho, d) = (0.3f32, 0.5f32);
    let eta = glam::Vec4::splat(1.0);
    let m = 1.0 - d;
    let expect = ((2.0 * rho - 0.5 * m) / (1.0 - 0.5 * m)).clamp(0.0, 1.0);
    let got = detail_erosion(
        glam::Vec4::splat(rho),
        d.powi(6),
        1.0 - d,
        eta,
        glam::Vec4::ONE,
    );
    assert!((got.x - expect).abs() < 1e-6, "{got} vs {expect}");
}

#[test]
fn binding_enums_find_every_slot_they_declare() {
    use nimbus_clouds::model::clouds::{CloudBinding, ResolveBinding};
    for b in CloudBinding::ALL {
        assert_eq!(CloudBinding::at(CloudBinding::GROUP, b.binding()), Some(b));
    }
    assert_eq!(CloudBinding::at(1, 0), None);
    assert_eq!(CloudBinding::at(0, 12), None);
    for (i, b) in ResolveBinding::ALL.into_iter().enumerate() {
        assert_eq!(ResolveBinding::at(ResolveBinding::GROUP, i as u32), Some(b));
        assert_eq!(b as usize, i);
    }
}

#[test]
fn every_resource_id_is_its_serialised_name_and_every_slot_names_one() {
    use nimbus_clouds::model::bindings::{DisplayBinding, SunLightBinding};
    use nimbus_clouds::model::clouds::{CloudBinding, ResolveBinding};
    use nimbus_clouds::model::resource::Resource;
    let mut ids = std::collections::BTreeSet::new();
    for r in Resource::ALL {
        let serialised = serde_json::to_value(r).expect("a resource serialises");
        assert_eq!(
            serialised,
            serde_json::Value::String(r.id().into()),
            "{r:?}"
        );
        assert!(ids.insert(r.id()), "{} named twice", r.id());
    }
    // Each pass's slots are distinct, and every resource but the uber-shader's key is bound by
    // some pass of a package.
    let mut used: std::collections::BTreeSet<Resource> = Default::default();
    let slots: Vec<Vec<((u32, u32), Resource)>> = vec![
        CloudBinding::ALL
            .iter()
            .map(|b| (b.slot(), b.resource()))
            .collect(),
        ResolveBinding::ALL
            .iter()
            .map(|b| (b.slot(), b.resource()))
            .collect(),
        DisplayBinding::ALL
            .iter()
            .map(|b| (b.slot(), b.resource()))
            .collect(),
        SunLightBinding::ALL
            .iter()
            .map(|b| (b.slot(), b.resource()))
            .collect(),
    ];
    for pass in &slots {
        let distinct: std::collections::BTreeSet<_> = pass.iter().map(|(s, _)| *s).collect();
        assert_eq!(distinct.len(), pass.len(), "{pass:?}");
        used.extend(pass.iter().map(|(_, r)| *r));
    }
    assert_eq!(
        used.len(),
        Resource::ALL.len(),
        "unused: {:?}",
        Resource::ALL
            .iter()
            .filter(|r| !used.contains(r))
            .collect::<Vec<_>>()
    );
}
