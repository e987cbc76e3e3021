//! The weather without its tile's repetition (`untiled-weather`, `model::untiled_weather`).
//!
//! From orbit the 100 km weather tile came back ten times and more across the view, and the
//! same cloud fields stood in rows and columns along the tile's axes. Here the coverage-stage
//! density of a genus is sampled on a ground grid 1,200 km across, without the planet-scale
//! field (which hides the repetition only in part), and compared with itself one tile over:
//! with the key's plain weather (the control) the field repeats exactly; untiled it is no more
//! alike one tile over than at any other distance. The blend between the lattice's regions
//! stays narrow and keeps most of the weather's spread there (an average of two unrelated
//! fields has less: paler lanes in a hexagonal net), and the sky as a whole keeps its cloud
//! fraction.

use std::path::Path;

use glam::{Vec2, Vec3};
use nimbus_clouds::model::density::weather_density;
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::untiled_weather::hex_corners;
use nimbus_clouds::{CloudKey, CloudLibrary, Quality};
use nimbus_runtime::density_export::generate_cpu_textures;
use nimbus_runtime::render::TextureSizes;

/// Grid spacing (m) and points per side: 1,200 km, twelve tiles.
const STEP: f32 = 2_000.0;
const N: usize = 600;
/// One weather tile, in grid steps.
const TILE: usize = 50;

struct Field {
    /// Coverage-stage density of the genus' first layer at each grid point.
    density: Vec<f32>,
    /// Whether the point lies in a blend band (no lattice vertex has all the weight).
    in_band: Vec<bool>,
}

fn field(genus: &str, untiled: bool) -> Field {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let g = lib.genus(genus).expect("genus");
    let mut u = CloudUniforms::for_genus(g, Quality::High, Vec3::Y, 2.0);
    u.media.planet_weather = 0.0;
    let mut features = Quality::High.features();
    features.untiled_weather = untiled;
    let key =
        CloudKey::new(features, &g.phase, g.layer_groups() as u32).with_functions(g.functions);
    let textures = generate_cpu_textures(TextureSizes {
        weather: 128,
        shape: 16,
        detail: 8,
        turbulence: 16,
    });
    let _bound = textures.bind(u);
    let layer = g.layers.iter().find(|l| l.is_enabled()).expect("a layer");
    let altitude = layer.altitude + 0.3 * layer.height;
    let mut density = Vec::with_capacity(N * N);
    let mut in_band = Vec::with_capacity(N * N);
    for j in 0..N {
        for i in 0..N {
            let xz = Vec2::new(i as f32, j as f32) * STEP + Vec2::splat(-600_000.0);
            let p = Vec3::new(xz.x, altitude, xz.y) + u.camera_offset;
            density.push(weather_density(p, altitude, 0, key).x);
            let uv = Vec2::new(p.x, p.z) * u.media.weather_repeat + u.media.weather_offset;
            in_band.push(hex_corners(uv).weights.max_element() < 0.999);
        }
    }
    Field { density, in_band }
}

/// Correlation of the field with itself shifted `(dx, dz)` grid steps.
fn correlation(v: &[f32], dx: usize, dz: usize) -> f64 {
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for j in 0..N - dz {
        for i in 0..N - dx {
            a.push(f64::from(v[j * N + i]));
            b.push(f64::from(v[(j + dz) * N + i + dx]));
        }
    }
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - ma) * (y - mb))
        .sum::<f64>()
        / n;
    let va = a.iter().map(|x| (x - ma).powi(2)).sum::<f64>() / n;
    let vb = b.iter().map(|y| (y - mb).powi(2)).sum::<f64>() / n;
    cov / (va * vb).sqrt().max(1e-12)
}

fn cloud_fraction<'a>(d: impl Iterator<Item = &'a f32>) -> f64 {
    let (mut cloudy, mut all) = (0usize, 0usize);
    for x in d {
        all += 1;
        cloudy += usize::from(*x > 0.0);
    }
    cloudy as f64 / all.max(1) as f64
}

/// Mean and standard deviation.
fn spread(v: &[f32]) -> (f64, f64) {
    let n = v.len().max(1) as f64;
    let m = v.iter().map(|x| f64::from(*x)).sum::<f64>() / n;
    let var = v.iter().map(|x| (f64::from(*x) - m).powi(2)).sum::<f64>() / n;
    (m, var.sqrt())
}

/// The largest correlation one tile over (along x, along z, diagonally), and the largest at
/// shifts that are no multiple of the tile (the field's own correlation at that distance).
fn repetition(f: &Field) -> (f64, f64) {
    let at_tile = [(TILE, 0), (0, TILE), (TILE, TILE), (2 * TILE, 0)]
        .map(|(dx, dz)| correlation(&f.density, dx, dz))
        .into_iter()
        .fold(f64::MIN, f64::max);
    let elsewhere = [(37, 0), (0, 37), (63, 21), (81, 0)]
        .map(|(dx, dz)| correlation(&f.density, dx, dz).abs())
        .into_iter()
        .fold(0.0, f64::max);
    (at_tile, elsewhere)
}

#[test]
fn the_weather_does_not_repeat_on_the_tile_and_keeps_its_clouds() {
    for genus in ["cumulus", "stratocumulus"] {
        let plain = field(genus, false);
        let untiled = field(genus, true);
        let (plain_tile, plain_else) = repetition(&plain);
        let (tile, elsewhere) = repetition(&untiled);
        println!(
            "{genus}: correlation one tile over {plain_tile:.3} plain (elsewhere {plain_else:.3}), \
             {tile:.3} untiled (elsewhere {elsewhere:.3})"
        );
        assert!(
            plain_tile > 0.95,
            "control: the plain weather should repeat on the tile ({plain_tile})"
        );
        assert!(
            tile < elsewhere + 0.1,
            "{genus}: the untiled weather still repeats one tile over ({tile} against {elsewhere})"
        );

        let band: Vec<f32> = untiled
            .density
            .iter()
            .zip(&untiled.in_band)
            .filter(|(_, b)| **b)
            .map(|(d, _)| *d)
            .collect();
        let inside: Vec<f32> = untiled
            .density
            .iter()
            .zip(&untiled.in_band)
            .filter(|(_, b)| !**b)
            .map(|(d, _)| *d)
            .collect();
        let share = band.len() as f64 / untiled.density.len() as f64;
        let (s_band, s_inside) = (spread(&band), spread(&inside));
        println!("{genus}: spread (mean, sd) in bands {s_band:.3?}, elsewhere {s_inside:.3?}");
        let (f_band, f_inside) = (cloud_fraction(band.iter()), cloud_fraction(inside.iter()));
        let (f_plain, f_untiled) = (
            cloud_fraction(plain.density.iter()),
            cloud_fraction(untiled.density.iter()),
        );
        println!(
            "{genus}: {:.1} % of the plane in blend bands; cloud fraction there {f_band:.3}, \
             elsewhere {f_inside:.3}; whole sky {f_untiled:.3} untiled, {f_plain:.3} plain",
            100.0 * share
        );
        assert!(
            share > 0.02 && share < 0.3,
            "{genus}: blend bands cover {share} of the plane"
        );
        // Linear blending of two unrelated fields loses some spread (a fifth, measured); the
        // band is narrow so that little of the sky has it. More would show as paler lanes.
        assert!(
            s_band.1 > 0.7 * s_inside.1 && (s_band.0 / s_inside.0 - 1.0).abs() < 0.2,
            "{genus}: the weather along the region borders differs ({s_band:?} against {s_inside:?})"
        );
        assert!(
            (f_band / f_inside - 1.0).abs() < 0.15,
            "{genus}: cloud fraction along the region borders {f_band} against {f_inside}"
        );
        assert!(
            (f_untiled / f_plain - 1.0).abs() < 0.1,
            "{genus}: the sky's cloud fraction moved ({f_untiled} against {f_plain})"
        );
    }
}
