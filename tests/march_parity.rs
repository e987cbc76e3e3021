//! One full ray march, CPU twin against the generated shader on the GPU, over a set of rays
//! from three camera altitudes (below, inside and above the layer), with every texture bound.

mod common;

use std::path::Path;
use std::sync::Arc;

use common::{Rng, Tolerance, compare_with};
use glam::{Vec3, Vec4};
use nimbus_clouds::model::bindings::{CLOUDS, CloudTextures};
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::model::march::{CloudUniforms, CloudUniformsShader, march_clouds};
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_dsl::Value;
use nimbus_dsl::cpu::{Texture2d, Texture3d};
use nimbus_dsl::ir::{ExprId, Scalar, Type};
use nimbus_dsl::layout::Flatten;
use nimbus_dsl::shader;
use nimbus_testkit::parity::cloud_resources;

/// The pixel angle the rays are marched with (a 1920-pixel, 90° view): the detail's level of
/// detail runs from all detail near the camera to none far away, on both sides alike.
const PIXEL_ANGLE: f32 = 8.2e-4;

/// Values on a 1/256 grid, which f16 textures hold exactly.
fn texels(rng: &mut Rng, n: usize, scale: [f32; 4]) -> Vec<Vec4> {
    (0..n)
        .map(|_| {
            Vec4::from_array(std::array::from_fn(|c| {
                (rng.next_u64() % 257) as f32 / 256.0 * scale[c]
            }))
        })
        .collect()
}

#[test]
fn march_clouds_matches_cpu_over_a_set_of_rays() {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    // Half the sky covered, so that enough rays meet clouds.
    let mut cumulus = lib.genus("cumulus").expect("cumulus").clone();
    cumulus.coverage = 0.5;
    march_parity(&cumulus, 400, 10, MARCH_TOLERANCE);
}

/// A genus of a user's own: the supercell example crate's shape and profile `#[shader_fn]`s,
/// recorded into the shader, against their CPU twins.
#[test]
fn user_genus_march_matches_cpu() {
    let genus = supercell::genus().expect("supercell genus");
    // At the cumulus tolerance with soft coverage edges: the functions' own arithmetic.
    let mut soft = genus.clone();
    soft.layers[0].coverage_filter_width = 1.0;
    soft.layers[0].weather_exponent = 1.0;
    march_parity(&soft, 150, 5, MARCH_TOLERANCE);
    // As shipped, its coverage edge is 2.9x steeper (filter width 0.35) and squared (weather
    // exponent 2): the texture filter's rounding (8-bit weights on lavapipe) moves a pixel up
    // to ~6x more than in cumulus (1.3 % measured on one ray in 450), so the relative margin
    // grows with it.
    march_parity(
        &genus,
        150,
        5,
        Tolerance {
            abs: 5e-4,
            rel: 2e-2,
        },
    );
}

/// The built-in weather functions other than the texture's (cellular decks, streaks).
#[test]
fn genus_weather_functions_march_matches_cpu() {
    use nimbus_clouds::model::genus_fns::{CELLULAR_WEATHER, STREAK_WEATHER};
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    for weather in [CELLULAR_WEATHER, STREAK_WEATHER] {
        let mut genus = lib.genus("cumulus").expect("cumulus").clone();
        genus.functions.weather = weather;
        // Cells within patches leave most of the sky clear at cumulus' coverage: more cloud,
        // so that enough rays meet some.
        genus.coverage = 0.8;
        march_parity(&genus, 100, 3, MARCH_TOLERANCE);
    }
}

/// Hundreds of steps of exp/pow and texture filtering; hardware GPUs filter with fewer weight
/// bits than lavapipe, hence the margin. Beyond 30 km every density sample also reads the
/// planet-scale coverage field (two more filtered samples), which took the worst of 1,200
/// cumulus rays from 3.2e-3 to 4.4e-3 relative.
const MARCH_TOLERANCE: Tolerance = Tolerance {
    abs: 5e-4,
    rel: 7e-3,
};

/// The march of `genus` at `high`, `rays` rays from each of three camera altitudes, on the GPU
/// against the CPU twin within `tol`; at least `min_opaque` rays must be mostly opaque.
fn march_parity(genus: &nimbus_clouds::Genus, rays: usize, min_opaque: usize, tol: Tolerance) {
    let quality = Quality::High;
    let key = CloudVariant::new(genus, quality, quality.features()).key;
    let mut rng = Rng::new(31);
    let textures = CloudTextures {
        weather: Arc::new(Texture2d {
            size: [16, 16],
            texels: texels(&mut rng, 256, [1.0; 4]),
        }),
        shape: Arc::new(Texture3d {
            size: [16, 16, 16],
            texels: texels(&mut rng, 4096, [1.0; 4]),
        }),
        detail: Arc::new(Texture3d {
            size: [8, 8, 8],
            texels: texels(&mut rng, 512, [1.0; 4]),
        }),
        turbulence: Arc::new(Texture2d {
            size: [8, 8],
            texels: texels(&mut rng, 64, [1.0; 4]),
        }),
        // Front depth in metres (integers), mean extinction, max and tail optical depth.
        shadow: Arc::new(Texture2d {
            size: [8, 8],
            texels: texels(&mut rng, 64, [1024.0, 0.0625, 4.0, 0.5]),
        }),
    };

    let mut inputs = Vec::new();
    for altitude in [200.0, 2200.0, 6000.0] {
        let u = test_uniforms(genus, quality, altitude);
        let mut words = Vec::new();
        u.flatten(&mut words);
        for i in 0..rays {
            let elevation: f32 = match i {
                0 => 0.0,
                1 => 90.0,
                2 => -90.0,
                _ => rng.range(-20.0, 89.0),
            };
            let azimuth = rng.range(0.0, std::f32::consts::TAU);
            let (se, ce) = elevation.to_radians().sin_cos();
            let dir = Vec3::new(ce * azimuth.cos(), se, ce * azimuth.sin()).normalize();
            let mut w: Vec<u32> = dir.to_array().map(f32::to_bits).to_vec();
            w.extend(&words);
            inputs.push(w);
        }
    }
    let resources = cloud_resources(&textures);
    let call = move |a: &[ExprId]| {
        // Each record carries the uniforms of its camera altitude.
        let u = CloudUniformsShader::from_id(a[1]);
        CLOUDS.feed(u);
        let r = march_clouds::shader(
            shader::Vec3::from_id(a[0]),
            u.jitter,
            shader::F32::from(PIXEL_ANGLE),
            key,
        );
        r.radiance.extend(r.transmittance).id()
    };
    let uniforms_of = |w: &[u32]| -> CloudUniforms {
        // The uniforms of a record are those of its camera altitude.
        let altitude = f32::from_bits(w[3 + uniforms_altitude_word()]);
        test_uniforms(genus, quality, altitude)
    };
    // The CPU twin on one input record (direction, then the uniforms' words), its early
    // termination's threshold scaled by `threshold`.
    let cpu_march_at = |w: &[u32], threshold: f32| {
        let dir = Vec3::new(
            f32::from_bits(w[0]),
            f32::from_bits(w[1]),
            f32::from_bits(w[2]),
        );
        let mut u = uniforms_of(w);
        u.march.min_transmittance *= threshold;
        let _bound = textures.bind(u);
        march_clouds(dir, u.jitter, PIXEL_ANGLE, key)
    };
    let cpu_march = |w: &[u32]| cpu_march_at(w, 1.0);
    let label = format!("march_clouds[{}]", key.name());
    compare_with(
        &label,
        vec![
            Type::Vector(3, Scalar::F32),
            <CloudUniformsShader as Value>::TYPE,
        ],
        Type::Vector(4, Scalar::F32),
        &call,
        &resources,
        &inputs,
        rays * 3,
        |w| {
            // A ray whose transmittance falls within the two sides' difference (the
            // tolerance) of the early termination's threshold may end a step sooner or later
            // on one side than on the other, and the light the termination extrapolates (a
            // tenth of the ray's at a threshold of 0.1) differs by what that step adds: either
            // end is the CPU twin's answer.
            [1.0, 1.0 - tol.rel, 1.0 + tol.rel]
                .map(|threshold| {
                    let r = cpu_march_at(w, threshold);
                    r.radiance
                        .extend(r.transmittance)
                        .to_array()
                        .map(f32::to_bits)
                        .to_vec()
                })
                .to_vec()
        },
        tol,
    );
    // The alternatives excuse a few rays at the threshold, not a march that no longer agrees.
    let tipped = inputs
        .iter()
        .filter(|w| {
            let r = cpu_march_at(w, 1.0 - tol.rel);
            let s = cpu_march_at(w, 1.0 + tol.rel);
            r.radiance != s.radiance || r.transmittance != s.transmittance
        })
        .count();
    println!(
        "{tipped} rays end within {:.1} % of the termination threshold",
        tol.rel * 100.0
    );
    assert!(
        tipped * 20 <= inputs.len(),
        "{tipped} of {} rays end within the tolerance of the termination threshold",
        inputs.len()
    );
    // The rays must actually meet clouds for the comparison to mean anything.
    let transmittances: Vec<f32> = inputs.iter().map(|w| cpu_march(w).transmittance).collect();
    let cloudy = transmittances.iter().filter(|t| **t < 0.99).count();
    let opaque = transmittances.iter().filter(|t| **t < 0.5).count();
    println!(
        "{cloudy} of {} rays meet clouds, {opaque} are mostly opaque",
        transmittances.len()
    );
    assert!(
        cloudy * 4 > transmittances.len(),
        "only {cloudy} rays meet clouds"
    );
    assert!(opaque > min_opaque, "only {opaque} rays are mostly opaque");
    assert!(transmittances.iter().all(|t| (0.0..=1.0).contains(t)));
}

/// The uniforms of the test scene seen from `altitude`: a weather tile of 4 km and shape tiles
/// of ~1 km keep the small test textures busy.
fn test_uniforms(genus: &nimbus_clouds::Genus, quality: Quality, altitude: f32) -> CloudUniforms {
    let mut u = CloudUniforms::for_genus(genus, quality, Vec3::new(0.4, 0.5, 0.3), altitude);
    u.media.weather_repeat = glam::Vec2::splat(1.0 / 4000.0);
    u.media.shape_repeat = Vec3::splat(1.0 / 1000.0);
    u.media.detail_repeat = Vec3::splat(1.0 / 200.0);
    u.jitter = 0.5;
    u
}

/// Index of `camera_altitude` in the flattened uniforms.
fn uniforms_altitude_word() -> usize {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let genus = lib.genus("cumulus").expect("cumulus");
    let a = CloudUniforms::for_genus(genus, Quality::High, Vec3::Y, 1.0);
    let mut b = a;
    b.camera_altitude = 2.0;
    let (mut wa, mut wb) = (Vec::new(), Vec::new());
    a.flatten(&mut wa);
    b.flatten(&mut wb);
    wa.iter()
        .zip(&wb)
        .position(|(x, y)| x != y)
        .expect("altitude word")
}
