//! Random valid genera seen under random valid scenes (proptest): every value within what
//! validation accepts, layer counts from one to the maximum, every phase model and quality.
//! Each accepted pair must validate, generate shaders that naga validates for every target,
//! and march finite rays through the CPU twins.

use glam::Vec3;
use nimbus_clouds::{
    Channel, CloudLayer, DensityProfileParams, FeatureOverrides, Genus, MAX_LAYERS, PhaseSpec,
    Quality, ScenePreset,
};
use nimbus_codegen::Target;
use nimbus_testkit::fuzz::check_scene_keys;
use nimbus_testkit::stability::{base_genus, check_case, run_case_cpu, single_ray_case};
use proptest::prelude::*;

fn layer() -> impl Strategy<Value = CloudLayer> {
    (
        (0usize..4, 0.0f32..12_000.0, 0.0f32..6_000.0, 0.0f32..2.0),
        (0.0f32..=1.0, 0.0f32..=1.0, 0.1f32..4.0, 0.05f32..2.0),
        (1e-3f32..=1.0, any::<bool>(), -2.0f32..2.0, -80.0f32..=80.0),
    )
        .prop_map(
            |((ch, altitude, height, density), (shape, detail, wexp, bias), (fw, shadow, a, b))| {
                CloudLayer {
                    channel: [Channel::R, Channel::G, Channel::B, Channel::A][ch],
                    altitude,
                    height,
                    density_scale: density,
                    shape_amount: shape,
                    shape_detail_amount: detail,
                    weather_exponent: wexp,
                    shape_altering_bias: bias,
                    coverage_filter_width: fw,
                    shadow,
                    density_profile: DensityProfileParams {
                        a,
                        b,
                        c: 0.75,
                        d: 0.25,
                    },
                }
            },
        )
}

fn phase() -> impl Strategy<Value = PhaseSpec> {
    prop_oneof![
        (-0.999f32..=0.999).prop_map(|g| PhaseSpec::HenyeyGreenstein { g }),
        (-0.999f32..=0.999, -0.999f32..=0.999, 0.0f32..=1.0)
            .prop_map(|(g1, g2, weight)| PhaseSpec::DualLobe { g1, g2, weight }),
        (5.0f32..=50.0).prop_map(|d| PhaseSpec::ApproximateMie {
            droplet_diameter_um: d
        }),
        Just(PhaseSpec::Isotropic),
    ]
}

fn genus() -> impl Strategy<Value = Genus> {
    (
        prop::collection::vec(layer(), 1..=MAX_LAYERS),
        phase(),
        0.0f32..=1.0,
    )
        .prop_map(|(mut layers, phase, coverage)| {
            // At least one layer renders something (validation requires it).
            layers[0].height = layers[0].height.max(100.0);
            layers[0].density_scale = layers[0].density_scale.max(0.01);
            Genus {
                name: "fuzzed".into(),
                description: "random".into(),
                coverage,
                phase,
                layers,
                ..base_genus()
            }
        })
}

fn scene() -> impl Strategy<Value = ScenePreset> {
    (
        (
            -90.0f32..=90.0,
            -360.0f32..=720.0,
            0.0f32..=100_000.0,
            -90.0f32..=90.0,
        ),
        (1.0f32..=170.0, 0.0f32..=0.01, 0.0f32..=5000.0, 0usize..5),
        (prop::option::of(0.0f32..=1.0), prop::option::of(1u32..=12)),
    )
        .prop_map(
            |((sun, az, alt, pitch), (fov, haze, turb, q), (coverage, octaves))| ScenePreset {
                name: "fuzzed".into(),
                description: "random".into(),
                genus: "fuzzed".into(),
                coverage,
                sun_elevation_deg: sun,
                sun_azimuth_deg: az,
                camera_altitude: alt,
                camera_pitch_deg: pitch,
                camera_yaw_deg: az * 0.5,
                fov_deg: fov,
                haze_density: haze,
                turbulence_displacement: turb,
                weather_offset: [az / 100.0, sun / 100.0],
                quality: Quality::ALL.get(q).copied().unwrap_or(Quality::Reference),
                features: FeatureOverrides {
                    octaves,
                    ..FeatureOverrides::default()
                },
                clock: None,
                wind: None,
                weather: Vec::new(),
                formation: None,
                budget: None,
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn random_valid_genera_and_scenes_generate_valid_shaders_and_finite_rays(
        genus in genus(),
        scene in scene(),
        mu in -1.0f32..=1.0,
    ) {
        prop_assert!(genus.validate().is_ok(), "{:?}", genus.validate());
        prop_assert!(scene.validate(std::path::Path::new("scenes/fuzzed.toml")).is_ok());
        let keys = check_scene_keys(&genus, &scene, &Target::ALL);
        prop_assert!(keys >= 1);
        let s = ((1.0 - mu) * (1.0 + mu)).max(0.0).sqrt();
        let direction = Vec3::new(s, mu, 0.0);
        let case = single_ray_case(&genus, scene.sun_elevation_deg, scene.camera_altitude, direction);
        let violations = check_case(&case, &run_case_cpu(&case));
        prop_assert!(
            violations.is_empty(),
            "{}",
            violations.iter().map(ToString::to_string).collect::<Vec<_>>().join("\n")
        );
    }
}
