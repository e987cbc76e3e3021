//! The air table against the integral it stands in for: the sky's and the aerial perspective's
//! light read from the table (`model::air_table`, the CPU twin of the pass drawing it) and
//! integrated along the ray (`sky::air_light`), over every direction, distances from metres to
//! the end of the ray, suns from below the horizon to the zenith and cameras from the ground to
//! orbit. A control reads the table drawn for a sun 2° higher: it must fail the same bounds.

mod common;

use std::path::Path;

use glam::Vec3;
use nimbus_clouds::model::air_table::{air_from_table, air_table_texture};
use nimbus_clouds::model::bindings::{AIR_TABLE, CLOUDS, LINEAR_REPEAT};
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::shell::ground_hit;
use nimbus_clouds::model::sky::{air_light, sky_distance};
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_dsl::CpuBindings;
use nimbus_dsl::cpu::Sampler;

/// How far the table strays from the integral over one sun and camera.
#[derive(Debug, Default)]
struct Departure {
    /// Largest and mean in-scattering error, over the brightest in-scattering of the view.
    worst: f32,
    mean: f32,
    /// Largest transmittance error (absolute, per channel).
    transmittance: f32,
    /// The 95th percentile of the in-scattering's relative error, where it is at least a
    /// twentieth of the brightest.
    relative: f32,
}

fn uniforms(sun_elevation_deg: f32, camera_altitude: f32) -> CloudUniforms {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let e = sun_elevation_deg.to_radians();
    let sun = Vec3::new(e.cos() * 0.6, e.sin(), e.cos() * 0.8);
    CloudUniforms::for_genus(
        lib.genus("cumulus").expect("cumulus"),
        Quality::High,
        sun,
        camera_altitude,
    )
}

/// The table of `table_from` read under the uniforms `u`, against `u`'s integrals.
fn departure(u: &CloudUniforms, table_from: &CloudUniforms) -> Departure {
    let table = air_table_texture(table_from);
    let _bound = CpuBindings::new()
        .set(&CLOUDS, *u)
        .set(&AIR_TABLE, table)
        .set(&LINEAR_REPEAT, Sampler::default())
        .bind();
    let radius = u.march.radius;
    let mut errors = Vec::new();
    let mut pairs = Vec::new();
    let mut brightest = 0.0f32;
    let mut transmittance = 0.0f32;
    // Elevations crowd at the horizon, as the light does; azimuths all round (the table holds
    // one side of the sun's plane).
    let elevations: Vec<f32> = common::linspace(-1.0, 1.0, 41)
        .into_iter()
        .map(|x| x * x * x.signum() * 89.5)
        .chain([-0.3, -0.05, 0.05, 0.3])
        .collect();
    for &el in &elevations {
        for az in common::linspace(0.0, 350.0, 15) {
            let (e, a) = (el.to_radians(), az.to_radians());
            let d = Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin());
            let meets_ground = ground_hit(u.camera_altitude, d.y, radius) >= 0.0;
            let end = sky_distance(u.camera_altitude, d.y, u.sky.top_height, radius).abs();
            // Along the ray only: past its end (under the ground) nothing reads the table.
            for distance in
                [2.0f32, 500.0, 0.01 * end, 0.2 * end, 0.55 * end, end].map(|d| d.min(end))
            {
                let exact = air_light(
                    u.camera_altitude,
                    d,
                    u.light.sun_direction,
                    distance,
                    u.sky,
                    radius,
                );
                let read = air_from_table(d, distance, meets_ground);
                assert!(
                    read.inscatter.is_finite() && read.transmittance.is_finite(),
                    "not finite at elevation {el}°, azimuth {az}°, {distance} m"
                );
                brightest = brightest.max(exact.inscatter.max_element());
                let e = (read.inscatter - exact.inscatter).abs().max_element();
                errors.push(e);
                pairs.push((exact.inscatter.max_element(), e));
                transmittance = transmittance.max(
                    (read.transmittance - exact.transmittance)
                        .abs()
                        .max_element(),
                );
            }
        }
    }
    let scale = brightest.max(1e-12);
    let mut relative: Vec<f32> = pairs
        .iter()
        .filter(|(v, _)| *v >= 0.05 * brightest)
        .map(|(v, e)| e / v)
        .collect();
    relative.sort_by(f32::total_cmp);
    Departure {
        relative: relative[(relative.len() as f32 * 0.95) as usize],
        worst: errors.iter().fold(0.0f32, |m, e| m.max(*e)) / scale,
        mean: errors.iter().sum::<f32>() / errors.len() as f32 / scale,
        transmittance,
    }
}

/// Bounds the table holds everywhere. The worst case is twilight (the sun 2° below the
/// horizon), within 0.3° of the horizon towards the sun, where the glow changes faster than
/// the rows crowding there follow: 15 % of the brightest light of that dim sky; elsewhere 2 %.
fn holds(d: &Departure) -> bool {
    d.worst <= WORST && d.mean <= MEAN && d.relative <= RELATIVE && d.transmittance <= TRANSMITTANCE
}
const WORST: f32 = 0.2;
const MEAN: f32 = 0.001;
const RELATIVE: f32 = 0.06;
const TRANSMITTANCE: f32 = 0.01;

#[test]
fn the_air_table_reads_what_the_integral_gives_for_every_sun_and_camera() {
    let mut failed = Vec::new();
    for sun in [-2.0, 4.0, 35.0, 90.0] {
        for camera in [0.0, 1500.0, 30_000.0, 150_000.0] {
            let u = uniforms(sun, camera);
            let d = departure(&u, &u);
            println!(
                "sun {sun:>5}°, camera {camera:>8} m: worst {:.4}, mean {:.5} of the brightest \
                 in-scattering, 95 % within {:.4} of their own; transmittance within {:.4}",
                d.worst, d.mean, d.relative, d.transmittance
            );
            if !holds(&d) {
                failed.push(format!("sun {sun}°, camera {camera} m: {d:?}"));
            }
        }
    }
    assert!(
        failed.is_empty(),
        "the table departs from the integral:\n{}",
        failed.join("\n")
    );
}

#[test]
fn a_table_drawn_for_another_sun_fails_the_same_bounds() {
    for (sun, camera) in [(35.0, 1500.0), (4.0, 0.0)] {
        let u = uniforms(sun, camera);
        let stale = uniforms(sun + 2.0, camera);
        let d = departure(&u, &stale);
        println!(
            "control, sun {sun}° read from {}°'s table: {d:?}",
            sun + 2.0
        );
        assert!(!holds(&d), "a table 2° off passes: {d:?}");
    }
}
