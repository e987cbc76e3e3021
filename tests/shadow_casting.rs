//! A layer whose genus says it casts no shadow (`shadow = false`) is left out of the shadow
//! map, and only it: the nimbostratus' scud (0–900 m, under the deck that casts) drawn into the
//! atlas by the CPU twin of the shadow pass must give the atlas of the same sky with the scud's
//! density at zero, texel for texel. The control flags the scud as casting: the atlas must then
//! differ, or the texels checked never see the scud and the comparison proves nothing (the
//! deck is thinned so that the sun's rays reach the scud).

use std::path::Path;

use glam::{Vec3, Vec4};
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::shadow::{atlas_columns, atlas_rows, shadow_fragment};
use nimbus_clouds::{CloudLibrary, Genus, Quality};
use nimbus_runtime::density_export::generate_cpu_textures;
use nimbus_runtime::render::TextureSizes;

/// A texel grid over the whole atlas of `genus` at `quality`, the sun 30° high, drawn by the
/// CPU twin; `min_height` replaces the slab's bottom when given (so that two genera differing
/// in a layer's density march their sun rays over the same span, with the same steps).
fn atlas(genus: &Genus, quality: Quality, min_height: Option<f32>) -> (Vec<Vec4>, f32) {
    let key = CloudVariant::new(genus, quality, quality.features()).key;
    let (s, c) = 30f32.to_radians().sin_cos();
    let sun = Vec3::new(c, s, 0.0);
    let mut u = CloudUniforms::for_genus(genus, quality, sun, 1_000.0);
    if let Some(h) = min_height {
        // The cascades are placed from the slab too: placed again.
        u.march.min_height = h;
        u = u.with_sun(sun);
    }
    let textures = generate_cpu_textures(TextureSizes {
        weather: 128,
        shape: 32,
        detail: 16,
        turbulence: 32,
    });
    let _bound = textures.bind(u);
    let side = u.shadow.map_size;
    let width = side * atlas_columns(u.shadow.cascade_count) as f32;
    let height = side * atlas_rows(u.shadow.cascade_count) as f32;
    let n = 24;
    let texels = (0..n * n)
        .map(|i| {
            let x = ((i % n) as f32 + 0.5) / n as f32 * width;
            let y = ((i / n) as f32 + 0.5) / n as f32 * height;
            shadow_fragment(Vec4::new(x.floor() + 0.5, y.floor() + 0.5, 0.0, 1.0), key)
        })
        .collect();
    (texels, u.march.min_height)
}

#[test]
fn a_layer_that_casts_no_shadow_is_not_in_the_shadow_map() {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let mut genus = lib.genus("nimbostratus").expect("nimbostratus").clone();
    // The deck thinned a thousandfold: at its 75 optical depths every sun ray ends in it, and
    // no texel would reach the scud below whether it cast or not.
    for layer in genus.layers.iter_mut().filter(|l| l.shadow) {
        layer.density_scale *= 1e-3;
    }
    let scud = genus
        .layers
        .iter()
        .position(|l| !l.shadow && l.is_enabled())
        .expect("the nimbostratus has a layer that casts no shadow");
    for quality in [Quality::Low, Quality::High] {
        let (drawn, bottom) = atlas(&genus, quality, None);
        let mut without = genus.clone();
        without.layers[scud].density_scale = 0.0;
        let (expected, _) = atlas(&without, quality, Some(bottom));
        let mut casting = genus.clone();
        casting.layers[scud].shadow = true;
        let (control, _) = atlas(&casting, quality, None);

        let differing = drawn.iter().zip(&expected).filter(|(a, b)| a != b).count();
        assert_eq!(
            differing,
            0,
            "{quality:?}: {differing} of {} texels differ from the atlas without the scud",
            drawn.len()
        );
        let shadowed = drawn
            .iter()
            .zip(&control)
            .filter(|(a, b)| (a.z - b.z).abs() > 1e-4)
            .count();
        assert!(
            shadowed * 10 >= drawn.len(),
            "{quality:?}: the scud flagged as casting changed only {shadowed} of {} texels' \
             optical depth: the grid does not see it",
            drawn.len()
        );
        println!(
            "{quality:?}: {} texels equal to the atlas without the scud; {shadowed} darker with it casting",
            drawn.len()
        );
    }
}
