//! The ice crystals' phase function (`model::phase::ice_crystal_phase`): its 22° halo ring
//! integrates to 1 over the sphere with the mean cosine and second moment the diffusion takes
//! from it, peaks at the halo's angle with the sky inside it darker, and mixed into a
//! Henyey–Greenstein lobe makes the radial bump a person sees as a halo around the sun.

use nimbus_clouds::model::phase::{
    HALO_ANGLE, HALO_MEAN_COSINE, HALO_SECOND_MOMENT, halo_ring, henyey_greenstein,
    ice_crystal_phase,
};

/// `2π ∫ p(θ) w(θ) sin θ dθ` by the midpoint rule in θ, fine enough for the halo's 0.5° edge.
fn integral(p: impl Fn(f32) -> f32, w: impl Fn(f64) -> f64) -> f64 {
    let n = 400_000;
    let d = std::f64::consts::PI / n as f64;
    (0..n)
        .map(|i| {
            let theta = (i as f64 + 0.5) * d;
            let mu = theta.cos();
            f64::from(p(mu as f32)) * w(mu) * theta.sin() * d * std::f64::consts::TAU
        })
        .sum()
}

#[test]
fn the_halo_ring_is_normalised_with_the_moments_the_diffusion_uses() {
    let norm = integral(halo_ring, |_| 1.0);
    let m1 = integral(halo_ring, |mu| mu);
    let m2 = integral(halo_ring, |mu| 0.5 * (3.0 * mu * mu - 1.0));
    println!("ring: integral {norm:.6}, mean cosine {m1:.6}, second moment {m2:.6}");
    assert!((norm - 1.0).abs() < 2e-4, "the ring integrates to {norm}");
    assert!(
        (m1 - f64::from(HALO_MEAN_COSINE)).abs() < 2e-4,
        "mean cosine {m1}"
    );
    assert!(
        (m2 - f64::from(HALO_SECOND_MOMENT)).abs() < 2e-4,
        "second moment {m2}"
    );
    // The whole phase function too, for any halo fraction.
    for halo in [0.0f32, 0.1, 0.5, 1.0] {
        let total = integral(|mu| ice_crystal_phase(mu, 0.8, halo), |_| 1.0);
        assert!((total - 1.0).abs() < 1e-3, "halo {halo}: integral {total}");
    }
}

#[test]
fn the_halo_peaks_at_22_degrees_with_a_darker_sky_inside() {
    let at = |deg: f32| ice_crystal_phase(deg.to_radians().cos(), 0.8, 0.1);
    // The radial profile's largest value between 15° and 35° lies within 0.5° of the angle.
    let (mut best, mut best_deg) = (0.0f32, 0.0f32);
    for i in 0..=400 {
        let deg = 15.0 + 20.0 * i as f32 / 400.0;
        if at(deg) > best {
            (best, best_deg) = (at(deg), deg);
        }
    }
    println!(
        "peak {best:.4} at {best_deg:.2}° (halo angle {:.2}°)",
        HALO_ANGLE.to_degrees()
    );
    assert!(
        (best_deg - HALO_ANGLE.to_degrees()).abs() < 0.5,
        "peak at {best_deg}°"
    );
    // Brighter than the sky 3° inside and 5° outside it: a ring, not a shoulder.
    assert!(
        best > 1.3 * at(19.0) && best > 1.3 * at(27.0),
        "{best} against {} and {}",
        at(19.0),
        at(27.0)
    );
    // Control: the same lobe without the halo falls off monotonically through 22°.
    let plain = |deg: f32| henyey_greenstein(deg.to_radians().cos(), 0.8);
    assert!(plain(19.0) > plain(22.0) && plain(22.0) > plain(27.0));
}
