//! What the marches skip in clear air is exactly nothing: `total_density` leaves out the
//! erosion (its shape, detail and turbulence reads) of a layer group whose weather allows no
//! cloud, and along sun rays, secondary marches and the shadow map's columns it gives, to the
//! bit, the sum of every group's full `layer_density` — for every genus, at every preset,
//! in cloud and in clear air alike.

use std::path::Path;

use glam::Vec3;
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::model::density::layer_density;
use nimbus_clouds::model::march::{CloudUniforms, total_density};
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::density_export::generate_cpu_textures;
use nimbus_runtime::render::TextureSizes;

#[test]
fn skipping_the_erosion_of_clear_air_changes_no_density() {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let textures = generate_cpu_textures(TextureSizes {
        weather: 64,
        shape: 16,
        detail: 8,
        turbulence: 16,
    });
    let (mut clear, mut cloudy) = (0, 0);
    for (_, genus) in lib.genera.values() {
        for quality in [Quality::Low, Quality::Ultra] {
            let key = CloudVariant::new(genus, quality, quality.features()).key;
            let u =
                CloudUniforms::for_genus(genus, quality, Vec3::new(0.3, 0.8, 0.2).normalize(), 2.0);
            let _bound = textures.bind(u);
            let (bottom, top) = (
                u.march.min_height,
                u.march.max_height.max(u.march.min_height + 1.0),
            );
            for i in 0..300 {
                let x = (i % 20) as f32 * 913.0 - 9_000.0;
                let z = (i / 20) as f32 * 787.0 - 6_000.0;
                let h = bottom + (top - bottom) * ((i * 37 % 101) as f32 / 100.0);
                let p = Vec3::new(x, h - u.camera_altitude, z);
                let footprint = (i % 3) as f32 * 20.0;
                let got = total_density(p, h, footprint, key);
                let q = p + u.camera_offset;
                let mut want = 0.0f32;
                for group in 0..key.groups {
                    want += layer_density(q, h, group, footprint, key).dot(glam::Vec4::ONE);
                }
                assert_eq!(
                    got.to_bits(),
                    want.to_bits(),
                    "{} {}: at {p} ({h} m) {got} against {want}",
                    genus.name,
                    quality.name()
                );
                if want > 0.0 {
                    cloudy += 1;
                } else {
                    clear += 1;
                }
            }
        }
    }
    println!("{cloudy} samples in cloud, {clear} in clear air: every one equal to the bit");
    // Both kinds, or the comparison proves nothing about the skip.
    assert!(
        cloudy > 100 && clear > 100,
        "{cloudy} in cloud, {clear} clear"
    );
}
