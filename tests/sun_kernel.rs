//! The `sun_light` kernel that engine packages without a JavaScript host run when the sun
//! moves: on the GPU it turns a cloud block filled for one sun, with only the direction changed,
//! into the block `CloudUniforms::for_genus` makes for the new sun. Every word the sun does not
//! decide is copied bit for bit; the irradiances and cascade transforms match the CPU within
//! float precision of the GPU's transcendentals.

mod common;

use std::path::Path;

use nimbus_clouds::catalog::ShaderKey;
use nimbus_clouds::model::bindings::SunLightBinding;
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::sun::sun_direction;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_codegen::{Target, generate};
use nimbus_dsl::ShaderVariant;
use nimbus_dsl::layout::{UniformBytes, member_layout};

/// Members the kernel writes: the sun's direction (normalised) and what it decides.
const SUN_MEMBERS: [&str; 6] = [
    "light.sun_direction",
    "light.sun_irradiance",
    "light.sky_irradiance",
    "shadow.lookup.u",
    "shadow.lookup.v",
    "shadow.inverse_matrix",
];

/// Relative tolerance of the sun members, against each member's largest component: the sky
/// irradiance sums 1,536 in-scattering samples of `exp`, whose GPU error is a few ulp.
const TOLERANCE: f64 = 1e-5;

#[test]
fn sun_light_kernel_completes_the_block_for_a_moved_sun() {
    let Some(gpu) = common::gpu() else { return };
    let lib = CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"))
        .expect("example data");
    let key = ShaderKey::SunLight;
    let generated = generate(
        key.record().expect("module"),
        &key.variant(),
        &[Target::Wgsl],
    )
    .expect("wgsl");
    let ty = CloudUniforms::shader_type();
    let mut checked = 0;
    for (genus, quality, from, to, altitude) in [
        (
            "cumulus",
            Quality::Medium,
            (35.0, 150.0),
            (12.0, 240.0),
            2.0,
        ),
        (
            "stratocumulus",
            Quality::High,
            (60.0, 10.0),
            (5.0, 95.0),
            800.0,
        ),
        (
            "takram-default",
            Quality::Low,
            (8.0, 230.0),
            (70.0, 300.0),
            2.0,
        ),
    ] {
        let g = lib.genus(genus).expect("genus");
        let old = CloudUniforms::for_genus(g, quality, sun_direction(from.0, from.1), altitude);
        let new_sun = sun_direction(to.0, to.1);
        let expected = CloudUniforms::for_genus(g, quality, new_sun, altitude);
        // What a host writes: the old block with only the new direction, at any length.
        let mut inputs = old;
        inputs.light.sun_direction = new_sun * 3.0;
        let bytes = inputs.to_uniform_bytes().expect("sized by its layout");
        let out = gpu
            .run_uniform_kernel(
                &generated,
                "cs_sun_light",
                (SunLightBinding::Inputs.slot().1, &bytes),
                (SunLightBinding::Block.slot().1, bytes.len()),
            )
            .expect("dispatch");
        assert_eq!(out.len(), bytes.len());

        let got = member_layout(ty, &out);
        let want = member_layout(
            ty,
            &expected.to_uniform_bytes().expect("sized by its layout"),
        );
        let before = member_layout(ty, &old.to_uniform_bytes().expect("sized by its layout"));
        for ((g, w), b) in got.iter().zip(&want).zip(&before) {
            assert_eq!(g.path, w.path);
            if SUN_MEMBERS.contains(&g.path.as_str()) {
                let scale = w.value.iter().fold(1e-6f64, |m, v| m.max(v.abs()));
                let err = g
                    .value
                    .iter()
                    .zip(&w.value)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                let moved = b
                    .value
                    .iter()
                    .zip(&w.value)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                println!(
                    "{genus}.{}: {} relative error {:.2e} (the old sun's value is {:.2e} off)",
                    quality.name(),
                    g.path,
                    err / scale,
                    moved / scale
                );
                assert!(
                    err <= TOLERANCE * scale,
                    "{genus}: {} = {:?}, expected {:?}",
                    g.path,
                    g.value,
                    w.value
                );
                // Control: the old sun's value would fail the same check, so a kernel that
                // only copied its input could not pass.
                assert!(
                    moved > 100.0 * TOLERANCE * scale,
                    "{genus}: {} does not depend on the sun in this case",
                    g.path
                );
            } else {
                assert_eq!(
                    g.value, w.value,
                    "{genus}: {} must be copied unchanged",
                    g.path
                );
            }
            checked += 1;
        }
    }
    println!(
        "sun_light kernel on {}: {checked} members checked",
        gpu.info().name
    );
}
