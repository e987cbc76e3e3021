//! The density export: a Mitsuba VOL file whose header is the documented layout and whose
//! values are the model's extinction at the voxel centres; bad regions are refused with the
//! field named and nothing written.

use std::path::Path;

use glam::Vec3;
use nimbus_clouds::model::bindings::CloudTextures;
use nimbus_clouds::model::march::total_density;
use nimbus_clouds::model::shadow::altitude_at;
use nimbus_clouds::{CloudLibrary, load_scene};
use nimbus_runtime::RuntimeError;
use nimbus_runtime::density_export::{Region, density_grid, generate_cpu_textures};
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

fn frame() -> Frame {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let lib = CloudLibrary::load(&root).expect("data");
    let scene = load_scene(&root.join("scenes/default.toml")).expect("scene");
    Frame::from_scene(&scene, lib.genus(&scene.genus).expect("genus"), 1, 1)
}

fn textures() -> CloudTextures {
    generate_cpu_textures(TextureSizes {
        weather: 64,
        shape: 16,
        detail: 8,
        turbulence: 16,
    })
}

fn i32_at(b: &[u8], at: usize) -> i32 {
    i32::from_le_bytes(b[at..at + 4].try_into().expect("4 bytes"))
}

fn f32_at(b: &[u8], at: usize) -> f32 {
    f32::from_le_bytes(b[at..at + 4].try_into().expect("4 bytes"))
}

#[test]
fn vol_file_holds_the_models_extinction_at_voxel_centres() {
    let f = frame();
    let t = textures();
    let region = Region {
        min: Vec3::new(-40_000.0, 800.0, -40_000.0),
        max: Vec3::new(40_000.0, 2200.0, 40_000.0),
    };
    let size = [12u32, 6, 10];
    let grid = density_grid(&f, region, size, 1, &t, &|| {}).expect("grid");
    let dir = tempfile::tempdir().expect("tmp");
    let path = dir.path().join("clouds.vol");
    grid.save_mitsuba_vol(&path, nimbus_output::Overwrite::OwnOnly)
        .expect("write");
    let b = std::fs::read(&path).expect("read back");
    assert_eq!(&b[..4], b"VOL\x03");
    assert_eq!(i32_at(&b, 4), 1, "encoding: f32");
    assert_eq!([i32_at(&b, 8), i32_at(&b, 12), i32_at(&b, 16)], [12, 6, 10]);
    assert_eq!(i32_at(&b, 20), 1, "one channel");
    let bbox: Vec<f32> = (0..6).map(|i| f32_at(&b, 24 + 4 * i)).collect();
    assert_eq!(
        bbox,
        [-40_000.0, 800.0, -40_000.0, 40_000.0, 2200.0, 40_000.0]
    );
    assert_eq!(b.len(), 48 + 4 * 12 * 6 * 10);
    // Voxel (x, y, z) is value ((z·ny + y)·nx + x): recompute a few from the model directly.
    let u = Renderer::uniforms(&f);
    let key = f.variant().key;
    let sigma = u.light.scattering_coefficient + u.light.absorption_coefficient;
    let mut cloudy = 0;
    for (x, y, z) in [
        (0u32, 0u32, 0u32),
        (5, 2, 7),
        (11, 5, 9),
        (3, 1, 4),
        (8, 3, 2),
    ] {
        // The voxel's centre as the export places it: its corner plus half a voxel.
        let corner = region.min + grid.voxel() * Vec3::new(x as f32, y as f32, z as f32);
        let c = corner + grid.voxel() * 0.5;
        let p = Vec3::new(c.x, c.y - f.camera_altitude, c.z);
        let h = altitude_at(p, f.camera_altitude, u.march.radius);
        let want = {
            let _bound = t.bind(u);
            total_density(p, h, 0.0, key) * sigma
        };
        let got = f32_at(&b, 48 + 4 * (((z * 6 + y) * 12 + x) as usize));
        assert_eq!(got, want, "voxel ({x}, {y}, {z})");
    }
    for v in &grid.values {
        assert!(v.is_finite() && *v >= 0.0);
        cloudy += usize::from(*v > 0.0);
    }
    println!("{cloudy} of {} voxels cloudy", grid.values.len());
    assert!(
        cloudy > 0 && cloudy < grid.values.len(),
        "the box must cut through clouds"
    );
}

#[test]
fn bad_regions_are_refused_naming_the_field() {
    let f = frame();
    let t = textures();
    let ok = Region {
        min: Vec3::new(-1.0, 1000.0, -1.0),
        max: Vec3::new(1.0, 2000.0, 1.0),
    };
    let cases = [
        (ok, [0u32, 4, 4], "resolution"),
        (ok, [4, 4, 2000], "resolution"),
        (
            Region {
                min: ok.max,
                max: ok.min,
            },
            [4, 4, 4],
            "region",
        ),
        (
            Region {
                min: Vec3::new(-1.0, -5.0, -1.0),
                max: ok.max,
            },
            [4, 4, 4],
            "region",
        ),
        (
            Region {
                min: Vec3::new(f32::NAN, 0.0, 0.0),
                max: ok.max,
            },
            [4, 4, 4],
            "region",
        ),
    ];
    for filter in [0, 9] {
        match density_grid(&f, ok, [4, 4, 4], filter, &t, &|| {}) {
            Err(RuntimeError::Region {
                field: "filter", ..
            }) => {}
            other => panic!("filter {filter}: expected a `filter` error, got {other:?}"),
        }
    }
    for (region, size, field) in cases {
        match density_grid(&f, region, size, 1, &t, &|| {}) {
            Err(e @ RuntimeError::Region { field: f, .. }) => {
                assert_eq!(f, field, "{e}");
                println!("refused: {e}");
            }
            other => panic!("{region:?} {size:?}: expected a `{field}` error, got {other:?}"),
        }
    }
}

#[test]
fn box_filtered_voxels_average_the_density_over_the_voxel() {
    // Each voxel of a filtered grid is the mean of filter³ samples spread evenly over it, not
    // the value at its centre: recompute a few by hand, and check that the filtered grid
    // differs from the point-sampled one where the density varies within a voxel.
    let f = frame();
    let t = textures();
    let region = Region {
        min: Vec3::new(-3_000.0, 900.0, -3_000.0),
        max: Vec3::new(3_000.0, 2100.0, 3_000.0),
    };
    let size = [10u32, 4, 8];
    let filtered = density_grid(&f, region, size, 3, &t, &|| {}).expect("grid");
    let point = density_grid(&f, region, size, 1, &t, &|| {}).expect("grid");
    let u = Renderer::uniforms(&f);
    let key = f.variant().key;
    let sigma = u.light.scattering_coefficient + u.light.absorption_coefficient;
    let voxel = filtered.voxel();
    let _bound = t.bind(u);
    for (x, y, z) in [(0u32, 0u32, 0u32), (4, 1, 3), (9, 3, 7), (6, 2, 1)] {
        let corner = region.min + voxel * Vec3::new(x as f32, y as f32, z as f32);
        let mut sum = 0.0f32;
        for k in 0..27u32 {
            let sub = Vec3::new((k % 3) as f32, ((k / 3) % 3) as f32, (k / 9) as f32);
            let c = corner + voxel * (sub + 0.5) / 3.0;
            let p = Vec3::new(c.x, c.y - f.camera_altitude, c.z);
            let h = altitude_at(p, f.camera_altitude, u.march.radius);
            sum += total_density(p, h, 0.0, key);
        }
        let want = sum / 27.0 * sigma;
        let got = filtered.values[((z * 4 + y) * 10 + x) as usize];
        assert!(
            (got - want).abs() <= 1e-6 * want.max(1e-6),
            "voxel ({x}, {y}, {z}): {got} vs {want}"
        );
    }
    // Where there is cloud, the average over the voxel is not the sample at its centre.
    let cloudy: Vec<(f32, f32)> = filtered
        .values
        .iter()
        .zip(&point.values)
        .filter(|(a, b)| a.max(**b) > 0.0)
        .map(|(a, b)| (*a, *b))
        .collect();
    let differ = cloudy
        .iter()
        .filter(|(a, b)| (a - b).abs() > 1e-4 * a.max(*b).max(1e-6))
        .count();
    println!(
        "{differ} of {} cloudy voxels differ from their centre samples",
        cloudy.len()
    );
    assert!(
        cloudy.len() >= 20,
        "the region must hold clouds: {}",
        cloudy.len()
    );
    assert!(
        differ > cloudy.len() / 4,
        "only {differ} of {} cloudy voxels differ from the centre samples",
        cloudy.len()
    );
}

/// The frame of the default scene with its genus' phase replaced by `phase`.
fn frame_with_phase(phase: nimbus_clouds::PhaseSpec) -> Frame {
    let mut f = frame();
    f.genus.phase = phase;
    f
}

#[test]
fn the_phase_table_integrates_to_one_as_mitsuba_reads_it_or_is_refused() {
    use nimbus_clouds::PhaseSpec;
    use nimbus_runtime::mitsuba_scene::{
        MAX_PHASE_ENTRIES, PHASE_ENTRIES, PHASE_TABLE_TOLERANCE, phase_table, table_integral,
    };
    let t = textures();
    // An even table integrates as the trapezoid rule: isotropic is exactly 1.
    let iso = vec![(1.0 / (4.0 * std::f64::consts::PI)) as f32; 9];
    assert!((table_integral(&iso) - 1.0).abs() < 1e-6);
    // A broad phase keeps the coarse table.
    let dual = phase_table(&frame_with_phase(PhaseSpec::default()), &t).expect("dual lobe");
    assert_eq!(dual.len(), PHASE_ENTRIES);
    for diameter in [5.0f32, 20.0, 50.0] {
        let f = frame_with_phase(PhaseSpec::ApproximateMie {
            droplet_diameter_um: diameter,
        });
        // The control: the coarse table the export used to write misses 1 by far.
        let coarse: Vec<f32> = {
            let key = f.variant().key;
            let _bound = t.bind(Renderer::uniforms(&f));
            (0..PHASE_ENTRIES)
                .map(|i| {
                    let c = -1.0 + 2.0 * i as f32 / (PHASE_ENTRIES - 1) as f32;
                    nimbus_clouds::model::march::cloud_phase(c, 1.0, key)
                })
                .collect()
        };
        let coarse_error = (table_integral(&coarse) - 1.0).abs();
        match phase_table(&f, &t) {
            Ok(table) => {
                let error = (table_integral(&table) - 1.0).abs();
                println!(
                    "{diameter} µm: {} entries, integral off by {error:.2e} (1,025 entries: \
                     {coarse_error:.3})",
                    table.len()
                );
                assert!(error <= PHASE_TABLE_TOLERANCE, "{diameter} µm: {error}");
                assert!(table.len() > PHASE_ENTRIES && table.len() <= MAX_PHASE_ENTRIES);
                assert!(
                    coarse_error > 0.1,
                    "{diameter} µm: the control {coarse_error}"
                );
            }
            Err(e) => {
                println!("{diameter} µm: refused: {e}");
                assert!(matches!(e, RuntimeError::PhaseTable { .. }), "{e}");
                let text = e.to_string();
                assert!(
                    text.contains(&f.genus.name) && text.contains("ApproximateMie"),
                    "{text}"
                );
            }
        }
    }
}

#[test]
fn a_camera_inside_the_grid_starts_its_rays_in_the_medium() {
    use nimbus_runtime::density_export::DensityGrid;
    use nimbus_runtime::mitsuba_scene::mitsuba_scene_xml;
    let f = frame();
    let grid_around = |min: Vec3, max: Vec3| DensityGrid {
        region: Region { min, max },
        size: [1, 1, 1],
        values: vec![0.01],
        albedo: 1.0,
        filter: 1,
        shape_texel: 52.0,
    };
    let eye_y = f.camera_altitude;
    let inside = grid_around(
        Vec3::new(-100.0, eye_y - 10.0, -100.0),
        Vec3::new(100.0, eye_y + 10.0, 100.0),
    );
    let outside = grid_around(
        Vec3::new(-100.0, eye_y + 500.0, -100.0),
        Vec3::new(100.0, eye_y + 900.0, 100.0),
    );
    let reference = r#"<ref name="medium" id="clouds"/>"#;
    let xml = mitsuba_scene_xml(&f, &inside, "d.vol", &[0.08; 3]);
    assert!(xml.contains(reference), "{xml}");
    // A reference follows what it names.
    let declared = xml.find(r#"id="clouds""#).expect("medium");
    assert!(declared < xml.find(reference).expect("ref"), "{xml}");
    let xml = mitsuba_scene_xml(&f, &outside, "d.vol", &[0.08; 3]);
    assert!(!xml.contains(reference), "{xml}");
}
