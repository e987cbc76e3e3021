//! The stability invariants over random valid genera, cameras, suns and rays (proptest): every
//! parameter ranges over what validation accepts, edges included.

use glam::Vec3;
use nimbus_clouds::{DensityProfileParams, PhaseSpec};
use nimbus_testkit::stability::{base_genus, check_case, run_case_cpu, single_ray_case};
use proptest::prelude::*;

/// 10^x, for parameters that span decades.
fn decades(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    (lo..=hi).prop_map(|x: f32| 10f32.powf(x))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_rays_keep_every_invariant(
        camera in prop_oneof![Just(0.0f32), decades(-3.0, 5.7)],
        sun_elevation in -90.0f32..=90.0,
        mu in -1.0f32..=1.0,
        azimuth in 0.0f32..std::f32::consts::TAU,
        coverage in prop_oneof![Just(0.0f32), Just(1.0), 0.0f32..=1.0],
        density in prop_oneof![Just(0.0f32), decades(-40.0, 3.0)],
        altitude in 0.0f32..=12_000.0,
        height in prop_oneof![Just(0.0f32), Just(1e-3), decades(-3.0, 3.9)],
        filter in decades(-3.0, 0.0),
        g in -0.999f32..=0.999,
        b in -80.0f32..=80.0,
        a in -2.0f32..=2.0,
    ) {
        let mut genus = base_genus();
        genus.coverage = coverage;
        genus.phase = PhaseSpec::HenyeyGreenstein { g };
        let layer = &mut genus.layers[0];
        layer.density_scale = density;
        layer.altitude = altitude;
        layer.height = height;
        layer.coverage_filter_width = filter.clamp(1e-3, 1.0);
        layer.density_profile = DensityProfileParams { a, b, c: 0.5, d: 0.25 };
        let s = ((1.0 - mu) * (1.0 + mu)).max(0.0).sqrt();
        let direction = Vec3::new(s * azimuth.cos(), mu, s * azimuth.sin());
        let case = single_ray_case(&genus, sun_elevation, camera, direction);
        let violations = check_case(&case, &run_case_cpu(&case));
        prop_assert!(
            violations.is_empty(),
            "{}",
            violations.iter().map(ToString::to_string).collect::<Vec<_>>().join("\n")
        );
    }
}
