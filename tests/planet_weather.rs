//! Planet-scale weather: beyond the viewer's surroundings the coverage follows a field of
//! fronts and clear regions, so a long horizon or a view from orbit no longer shows the 100 km
//! weather tile repeated (every cell below a pixel: white noise); near the camera the coverage
//! is the one asked for.

use std::path::Path;

use glam::{Vec2, Vec3};
use nimbus_clouds::model::density::planet_coverage;
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::density_export::generate_cpu_textures;
use nimbus_runtime::render::TextureSizes;

fn uniforms(planet_weather: f32) -> CloudUniforms {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let genus = lib.genus("cumulus").expect("cumulus");
    let mut u = CloudUniforms::for_genus(genus, Quality::High, Vec3::Y, 2.0);
    u.media.coverage = 0.5;
    u.media.planet_weather = planet_weather;
    u
}

/// The coverage at ground points `step` metres apart on a `n`×`n` grid centred `centre`
/// metres from the camera.
fn grid(u: CloudUniforms, centre: Vec2, step: f32, n: i32) -> Vec<f32> {
    let textures = generate_cpu_textures(TextureSizes {
        weather: 128,
        shape: 16,
        detail: 8,
        turbulence: 16,
    });
    let _bound = textures.bind(u);
    let mut out = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let xz = centre + Vec2::new(i as f32, j as f32) * step;
            let p = Vec3::new(xz.x, 1500.0, xz.y) + u.camera_offset;
            out.push(planet_coverage(p, p, u.media.coverage));
        }
    }
    out
}

fn mean(v: &[f32]) -> f32 {
    v.iter().sum::<f32>() / v.len() as f32
}

#[test]
fn far_tiles_differ_and_near_coverage_is_the_one_asked_for() {
    let (on, off) = (uniforms(1.0), uniforms(0.0));
    // Near the camera (within 20 km): exactly the coverage asked for.
    let near = grid(on, Vec2::splat(-20_000.0), 2_000.0, 20);
    assert!(near.iter().all(|c| (c - 0.5).abs() < 1e-6), "{near:?}");
    // Far away, one weather tile (100 km) apart: the same coverage without the planet-scale
    // field (the repetition), different with it.
    let a = grid(on, Vec2::new(400_000.0, 0.0), 10_000.0, 10);
    let b = grid(on, Vec2::new(500_000.0, 0.0), 10_000.0, 10);
    let (a0, b0) = (
        grid(off, Vec2::new(400_000.0, 0.0), 10_000.0, 10),
        grid(off, Vec2::new(500_000.0, 0.0), 10_000.0, 10),
    );
    assert_eq!(a0, b0, "control: without the field every tile is alike");
    let differ = a
        .iter()
        .zip(&b)
        .filter(|(x, y)| (*x - *y).abs() > 0.05)
        .count();
    println!(
        "{differ} of {} points one tile apart differ by > 0.05",
        a.len()
    );
    assert!(
        differ * 2 > a.len(),
        "tiles still repeat: {differ} of {}",
        a.len()
    );
    // Over 2,000 km the field has clear and overcast regions and keeps the mean coverage.
    let wide = grid(on, Vec2::splat(300_000.0), 50_000.0, 40);
    let (lo, hi) = wide
        .iter()
        .fold((1.0f32, 0.0f32), |(l, h), c| (l.min(*c), h.max(*c)));
    println!(
        "over 2,000 km: coverage {lo:.2} to {hi:.2}, mean {:.3} (asked 0.5)",
        mean(&wide)
    );
    assert!(
        lo < 0.25 && hi > 0.75,
        "no clear or overcast regions: {lo}..{hi}"
    );
    assert!(
        (mean(&wide) - 0.5).abs() < 0.1,
        "mean coverage moved: {}",
        mean(&wide)
    );
}
