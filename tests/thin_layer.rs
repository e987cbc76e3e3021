//! Thin layers against their analytic optical depth: a layer thinner than a march step must
//! still be integrated over its whole path (it used to be hit by one jittered sample in a
//! hundred and render as scattered dots), and a 1 mm layer of density scale 1000 has optical
//! depth ~1, not 1e-3 (the density was clamped to 1 per metre).

use glam::Vec3;
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::model::march::{CloudUniforms, march_clouds};
use nimbus_clouds::{CloudLayer, DensityProfileParams, Genus, Quality};
use nimbus_testkit::stability::{CaseTextures, base_genus};

/// One flat layer at 2 km: full coverage, no erosion, constant profile.
fn layer(height: f32, density_scale: f32) -> Genus {
    Genus {
        coverage: 1.0,
        layers: vec![CloudLayer {
            altitude: 2000.0,
            height,
            density_scale,
            shape_amount: 0.0,
            shape_detail_amount: 0.0,
            weather_exponent: 1.0,
            coverage_filter_width: 1.0,
            shape_altering_bias: 1.0,
            density_profile: DensityProfileParams {
                a: 0.0,
                b: 0.0,
                c: 0.0,
                d: 1.0,
            },
            ..CloudLayer::default()
        }],
        ..base_genus()
    }
}

/// Optical depth along `direction` in closed form: with weather 1, coverage 1 and a filter
/// width of 1 the coverage remap returns the shape `1 − (2η − 1)²` (bias 1), whose mean over
/// the layer is 2/3; no erosion and a constant profile leave it as it is. The thickness is the
/// one the uniforms hold in f32 (a 1 mm layer at 2 km is 0.977 mm there).
fn analytic(u: &CloudUniforms, scale: f32, direction: Vec3) -> f32 {
    let g = u.groups[0];
    let thickness = g.max_height.x - g.min_height.x;
    let sigma = u.light.scattering_coefficient + u.light.absorption_coefficient;
    sigma * scale * thickness * (2.0 / 3.0) / direction.y
}

#[test]
fn thin_layers_have_their_analytic_optical_depth() {
    let textures = CaseTextures::Constant(1.0).build();
    // (name, thickness, density scale, relative tolerance, view cosines). At 1 mm the path is
    // a few millimetres between two ray–shell roots kilometres away, each good to ~0.3 mm in
    // f32: single rays are off by up to a quarter, their mean by a few per cent; at μ 0.2 the
    // layer is 10 km away, where f32 distances step by 1 mm, the layer's own thickness, and
    // the march cannot resolve it (a limit of f32, not tested).
    let cases: [(&str, f32, f32, f32, &[f32]); 4] = [
        (
            "1000 m, scale 1e-3 (control: many samples)",
            1000.0,
            1e-3,
            0.02,
            &[1.0, 0.5, 0.2],
        ),
        ("10 m, scale 0.05", 10.0, 0.05, 0.02, &[1.0, 0.5, 0.2]),
        ("1 m, scale 0.5", 1.0, 0.5, 0.02, &[1.0, 0.5, 0.2]),
        ("1 mm, scale 1000", 1e-3, 1000.0, 0.05, &[1.0, 0.5]),
    ];
    for (name, height, scale, tolerance, cosines) in cases {
        let genus = layer(height, scale);
        let key = CloudVariant::new(&genus, Quality::High, Quality::High.features()).key;
        let mut u = CloudUniforms::for_genus(&genus, Quality::High, Vec3::new(0.3, 0.8, 0.2), 2.0);
        // The optical depth is read back from the transmittance, so no ray may end early (the
        // control's 3.3 optical depths at μ 0.2 fall below `high`'s threshold of 0.1).
        u.march.min_transmittance = 0.0;
        let _bound = textures.bind(u);
        for &mu in cosines {
            let direction = Vec3::new((1.0 - mu * mu).sqrt(), mu, 0.0);
            let want = analytic(&u, scale, direction);
            // Mean optical depth over 32 stratified jitters: one sample per thin layer lands at
            // a jittered height, so single rays vary with the rounded shape; their mean is the
            // integral.
            let n = 32;
            let got: f32 = (0..n)
                .map(|j| {
                    let r = march_clouds(direction, (j as f32 + 0.5) / n as f32, 0.0, key);
                    -r.transmittance.max(1e-30).ln()
                })
                .sum::<f32>()
                / n as f32;
            println!("{name}, μ {mu}: march τ {got:.5}, analytic τ {want:.5}");
            assert!(want > 0.01, "{name}: the case must be visible (τ {want})");
            assert!(
                (got - want).abs() <= tolerance * want,
                "{name}, μ {mu}: the march's mean optical depth {got} against {want}"
            );
        }
    }
}
