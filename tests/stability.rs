//! The stability catalogue on the CPU twins: one test per named case (the GPU runs the same
//! probes in the root crate's `tests/stability_gpu.rs`).

use nimbus_testkit::stability::{catalogue, check_case, genus_case, run_case_cpu};

fn run(name: &str) {
    let case = catalogue()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no case `{name}` in the catalogue"));
    run_case(&case);
}

fn run_case(case: &nimbus_testkit::stability::Case) {
    let name = case.name;
    let outcomes = run_case_cpu(case);
    let violations = check_case(case, &outcomes);
    let samples: f32 = outcomes.iter().map(|o| o.march.samples).sum();
    println!(
        "{name}: {} probes, {} chains, {} pairs, {samples} density samples, {} violations ({})",
        case.probes.len(),
        case.chains.len(),
        case.pairs.len(),
        violations.len(),
        case.about
    );
    for v in violations.iter().take(20) {
        println!("  {v}");
    }
    assert!(
        violations.is_empty(),
        "{name}: {} violations",
        violations.len()
    );
}

macro_rules! cases {
    ($($test:ident => $name:literal),* $(,)?) => {
        $(
            #[test]
            fn $test() {
                run($name);
            }
        )*

        /// Every case of the catalogue has its test above.
        #[test]
        fn every_case_has_a_test() {
            let tested = [$($name),*];
            for c in catalogue() {
                assert!(tested.contains(&c.name), "case `{}` has no test", c.name);
            }
            assert_eq!(tested.len(), catalogue().len());
        }
    };
}

cases! {
    anvil_shape => "anvil-shape",
    cellular_weather => "cellular-weather",
    streak_weather => "streak-weather",
    grain_weather => "grain-weather",
    cell_rows_weather => "cell-rows-weather",
    tangent_rays => "tangent-rays",
    sun_at_horizon => "sun-at-horizon",
    sun_just_below_horizon => "sun-just-below-horizon",
    sun_far_below_horizon => "sun-far-below-horizon",
    camera_at_ground => "camera-at-ground",
    camera_inside_layer => "camera-inside-layer",
    camera_on_layer_boundary => "camera-on-layer-boundary",
    camera_above_layers => "camera-above-layers",
    camera_in_orbit => "camera-in-orbit",
    zero_height_layer => "zero-height-layer",
    one_millimetre_layer => "one-millimetre-layer",
    density_scale_zero => "density-scale-zero",
    density_scale_1e_8 => "density-scale-1e-8",
    density_scale_1e3 => "density-scale-1e3",
    coverage_zero => "coverage-zero",
    coverage_one => "coverage-one",
    narrow_coverage_filter => "narrow-coverage-filter",
    hg_g_0_999 => "hg-g-0.999",
    hg_g_minus_0_999 => "hg-g-minus-0.999",
    overflowing_profile_exponent => "overflowing-profile-exponent",
    step_limits => "step-limits",
    far_distances => "far-distances",
    denormal_density => "denormal-density",
    reference_low_sun => "reference-low-sun",
    reference_sun_below_horizon => "reference-sun-below-horizon",
    reference_optically_thick => "reference-optically-thick",
    secondary_step_scale_near_one => "secondary-step-scale-near-one",
    secondary_span_overflow => "secondary-span-overflow",
    verification_mode => "verification-mode",
    eight_layers => "eight-layers",
    coincident_layers => "coincident-layers",
    tiny_reach => "tiny-reach",
}

/// A genus of a user's own (the `supercell` example crate: its shape and profile are
/// `#[shader_fn]`s written there) holds the same invariants on the CPU twins.
#[test]
fn user_genus_supercell() {
    let genus = supercell::genus().expect("supercell genus");
    assert!(
        genus.functions.shape == supercell::SHAPE && genus.functions.profile == supercell::PROFILE,
        "the genus file names the crate's functions"
    );
    run_case(&genus_case(
        "user-genus-supercell",
        "the supercell example crate's own shape and profile",
        &genus,
    ));
}

/// Found by the catalogue's thin-density cases under the reference preset (no extinction
/// cut-off): the step integral `S·(1 − e^(−σΔ))/max(σ, 1e-7)` made radiance grow as σ² below
/// σ = 1e-7. Written as `S·Δ·(1 − e^(−x))/x` with a series near 0, it is linear in density.
#[test]
fn thin_medium_radiance_is_linear_in_density() {
    use glam::Vec3;
    use nimbus_clouds::Quality;
    use nimbus_clouds::model::clouds::CloudVariant;
    use nimbus_clouds::model::march::{CloudUniforms, march_clouds, one_minus_exp_over};
    use nimbus_testkit::stability::{CaseTextures, base_genus};

    for x in [
        0.0f64, 1e-12, 1e-9, 1e-6, 1e-3, 0.0999, 0.1001, 0.5, 1.0, 10.0, 100.0, 1e4,
    ] {
        let exact = if x == 0.0 { 1.0 } else { -(-x).exp_m1() / x };
        let got = f64::from(one_minus_exp_over(x as f32));
        assert!(
            (got - exact).abs() <= 2e-6 * exact,
            "(1 - e^-x)/x at {x}: {got} vs {exact}"
        );
    }
    let t = CaseTextures::Constant(1.0).build();
    let radiance = |density: f32| {
        let mut genus = base_genus();
        genus.coverage = 1.0;
        genus.layers[0].density_scale = density;
        let q = Quality::Reference;
        let key = CloudVariant::new(&genus, q, q.features()).key;
        let u = CloudUniforms::for_genus(&genus, q, Vec3::new(0.3, 0.8, 0.2), 2.0);
        let _bound = t.bind(u);
        let r = march_clouds(Vec3::Y, 0.5, 0.0, key);
        r.radiance.x
    };
    let (one, two) = (radiance(1e-9), radiance(2e-9));
    println!(
        "radiance at density 1e-9: {one:e}, at 2e-9: {two:e}, ratio {}",
        two / one
    );
    assert!(one > 0.0, "a thin medium must scatter something");
    assert!(
        (two / one - 2.0).abs() < 0.01,
        "twice the density should scatter twice the light, got ×{}",
        two / one
    );
}
