//! The paths other than the volume draw the same clouds as the volume, at the scale each is
//! meant for, and their bakers draw what their CPU twins compute.
//!
//! The `slices` path ([`nimbus_clouds::Path::Slices`]) bakes the density and the optical depths
//! its light needs into a stack of altitude slices around the camera; the view march reads the
//! stack in place of the noise. Its picture is the volume seen at the stack's resolution (a
//! texel subtends about 2° beside the camera's vertical), so the comparison is made on both
//! pictures box-filtered to that scale: every genus, at `low`, against the volume's picture of
//! the same frame. The `blob2d` path ([`nimbus_clouds::Path::Blob2d`]) bakes a 2D map of the
//! clouds' columns (two altitude bands) and lights each view sample from its column; it is
//! held to the same bound at the same scale. The `impostor` path
//! ([`nimbus_clouds::Path::Impostor`]) bakes the volume's own march per direction into an
//! octahedral map; resampled at the map's resolution it is held to half that bound. The `mesh`
//! path ([`nimbus_clouds::Path::Mesh`]) fits instanced clusters of soft puffs to the density
//! and draws them in closed form; it is held to the slices' bound at the same scale. Controls:
//! each path's picture against the volume
//! with the sun 6° lower, and against the volume with its weather 2 km away, must fail the
//! bound every genus meets wherever the picture has broken cloud to tell them apart.

mod common;

use std::path::Path;

use glam::Vec4;
use nimbus_clouds::model::bake::bake_size;
use nimbus_clouds::model::blob2d::{BLOB_TEXELS, blob2d_fragment};
use nimbus_clouds::model::impostor::impostor_fragment;
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::mesh::{CLUSTER_TEXELS, mesh_fragment};
use nimbus_clouds::model::slices::{SLICE_TEXELS, slices_fragment};
use nimbus_clouds::{CloudKey, CloudLibrary, Path as DrawPath, Quality};
use nimbus_runtime::density_export::generate_cpu_textures;
use nimbus_runtime::render::{Frame, Image, Renderer, TextureSizes};

fn library() -> CloudLibrary {
    CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data")
}

/// Mean absolute difference of the display-referred (exposure 1, ACES, sRGB) pictures, each
/// box-filtered over `block`² pixels, in units of 1/255.
fn block_difference(a: &Image, b: &Image, block: u32) -> f64 {
    let (a8, b8) = (a.to_rgba8(1.0), b.to_rgba8(1.0));
    let (w, h) = (a.width / block, a.height / block);
    let mean = |img: &image::RgbaImage, bx: u32, by: u32, c: usize| {
        let mut s = 0.0f64;
        for y in 0..block {
            for x in 0..block {
                s += f64::from(img.get_pixel(bx * block + x, by * block + y)[c]);
            }
        }
        s / f64::from(block * block)
    };
    let mut sum = 0.0f64;
    for by in 0..h {
        for bx in 0..w {
            for c in 0..3 {
                sum += (mean(&a8, bx, by, c) - mean(&b8, bx, by, c)).abs();
            }
        }
    }
    sum / f64::from(3 * w * h)
}

/// The frame every genus is compared in: `low`, 160 × 90, a camera 500 m up looking 12° above
/// the horizon, the sun 30° up to the side.
fn frame(genus: &nimbus_clouds::Genus, path: DrawPath) -> Frame {
    let mut f = Frame::new(genus.clone(), Quality::Low, 160, 90);
    f.frames = 4;
    f.camera_altitude = 500.0;
    f.camera_pitch_deg = 12.0;
    f.sun_elevation_deg = 30.0;
    f.sun_azimuth_deg = 120.0;
    f.features.path = path;
    f
}

/// The baked paths compared with the volume.
const BAKED: [DrawPath; 4] = [
    DrawPath::Slices,
    DrawPath::Impostor,
    DrawPath::Blob2d,
    DrawPath::Mesh,
];

/// Pixels per side of a block of [`block_difference`]: at 160 × 90 and a 60° field of view a
/// block of 4 subtends 1.5°, about a slice stack's texel beside the camera's vertical (the 2D
/// map's texels are half as wide; its columns' one bell per band is what softens it; the mesh's
/// puffs are 2.8° across, 128 around the camera, and softened by their kernels).
const BLOCK: u32 = 4;

/// Bound on [`block_difference`] between a baked path's picture and the volume's, /255: the
/// slices, the 2D map and the mesh approximate the volume's light (3.1/255); the impostor is
/// the volume's own march, resampled at its map's resolution, and is held to 1.5/255. The
/// approximations' bound was 3.0 until the haze without light shafts took the air's sunlit
/// share, four stratified atlas reads up to the front each path finds: altocumulus' slices
/// went from 2.99 to 3.01. Every control of the structured genera still fails 3.1 (the
/// closest: cumulus' slices against the sun 6° lower, 3.22).
fn bound(path: DrawPath) -> f64 {
    if path == DrawPath::Impostor { 1.5 } else { 3.1 }
}

/// Genera whose picture has structure at the block scale (broken cloud): in these a bake
/// misplaced by a few texels or lit by another sun must fail the bound. An overcast's picture
/// (nimbostratus, stratus) is the same under both; that says nothing against the path.
const STRUCTURED: [&str; 5] = [
    "altocumulus",
    "cirrocumulus",
    "cumulus",
    "stratocumulus",
    "takram-default",
];

/// Renders `f` (one frame of a baked path), reads its bake back, binds the CPU twins to the
/// frame's block and noise, and hands `count` random texels (seeded by `seed`) to `compare`
/// as (x, y, the twin's texel, the GPU's).
fn compare_bake(
    f: &Frame,
    seed: u64,
    count: usize,
    twin: impl Fn(Vec4, CloudKey) -> Vec4,
    mut compare: impl FnMut(u32, u32, Vec4, Vec4),
) -> Option<()> {
    let gpu = common::gpu()?;
    println!("adapter: {}", gpu.info());
    let sizes = TextureSizes::default();
    let mut renderer = Renderer::new(gpu, sizes);
    renderer.render(f).expect("render");
    let bake = renderer
        .baked()
        .expect("read back")
        .expect("a baked path's frame keeps its bake");
    let (w, h) = bake_size(f.features.path).expect("a baked path");
    assert_eq!((bake.width, bake.height), (w, h));
    let key = nimbus_clouds::catalog::assign(&f.genus, f.quality, f.features).clouds;
    assert!(key.bakes());
    let u: CloudUniforms = Renderer::uniforms(f);
    let mut textures = generate_cpu_textures(sizes);
    // A bake whose marches read the shadow map (the impostor's) reads the atlas the frame
    // drew.
    if let Some(atlas) = renderer.shadow_atlas().expect("read back") {
        textures.shadow = std::sync::Arc::new(nimbus_dsl::cpu::Texture2d {
            size: [atlas.width, atlas.height],
            texels: atlas.pixels.iter().map(|&p| Vec4::from(p)).collect(),
        });
    }
    let _bound = textures.bind(u);
    let mut rng = common::Rng::new(seed);
    for _ in 0..count {
        let x = (rng.range(0.0, w as f32) as u32).min(w - 1);
        let y = (rng.range(0.0, h as f32) as u32).min(h - 1);
        let cpu = twin(Vec4::new(x as f32 + 0.5, y as f32 + 0.5, 0.0, 1.0), key);
        compare(x, y, cpu, Vec4::from(bake.pixels[(y * w + x) as usize]));
    }
    Some(())
}

#[test]
fn the_baked_paths_draw_every_genus_as_the_volume_does_at_their_scale() {
    let Some(gpu) = common::gpu() else { return };
    println!("adapter: {}", gpu.info());
    let lib = library();
    let mut renderer = Renderer::new(gpu, TextureSizes::default());
    let mut failures = Vec::new();
    for (name, (_, genus)) in &lib.genera {
        let volume = renderer
            .render(&frame(genus, DrawPath::Volume))
            .expect("volume");
        // Controls, as a broken path would draw them: the volume lit by a sun 6° lower, and
        // the volume with its weather 2 km away (a bake misplaced by a few texels).
        let mut lower = frame(genus, DrawPath::Volume);
        lower.sun_elevation_deg -= 6.0;
        let lower = renderer.render(&lower).expect("lower sun");
        let mut moved = frame(genus, DrawPath::Volume);
        moved.weather_offset.x += 0.02;
        let moved = renderer.render(&moved).expect("moved");
        for path in BAKED {
            let picture = renderer.render(&frame(genus, path)).expect("path");
            assert!(
                renderer
                    .stats()
                    .textures
                    .iter()
                    .any(|t| t.starts_with("cloud_bake")),
                "{name}: the {path} frame drew no bake"
            );
            let d = block_difference(&picture, &volume, BLOCK);
            let low = block_difference(&picture, &lower, BLOCK);
            let away = block_difference(&picture, &moved, BLOCK);
            println!(
                "{name:<18} {path:<7} vs volume {d:.2}/255; controls: sun 6° lower {low:.2}, \
                 weather 2 km away {away:.2}"
            );
            let bound = bound(path);
            if d > bound {
                failures.push(format!(
                    "{name}: {path} {d:.2}/255 from the volume (bound {bound})"
                ));
            }
            if STRUCTURED.contains(&name.as_str()) && low.max(away) <= bound {
                failures.push(format!(
                    "{name}: the controls ({low:.2}, {away:.2}) pass against {path}: the bound \
                     cannot tell these clouds apart"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The sun's disc is narrower than an impostor texel, so the impostor draws it per pixel over
/// its baked picture: in a narrow view towards the sun, the pixels of the disc (brighter than a
/// tenth of the brightest) are the volume's, as many and in the same place.
#[test]
fn the_impostor_draws_the_suns_disc_where_the_volume_does() {
    let Some(gpu) = common::gpu() else { return };
    println!("adapter: {}", gpu.info());
    let lib = library();
    let genus = lib.genus("cirrus").expect("cirrus");
    let mut renderer = Renderer::new(gpu, TextureSizes::default());
    let disc = |path: DrawPath, renderer: &mut Renderer| {
        let mut f = Frame::new(genus.clone(), Quality::Low, 320, 180);
        f.frames = 2;
        f.camera_altitude = 500.0;
        f.features.path = path;
        (f.sun_elevation_deg, f.sun_azimuth_deg) = (8.0, 40.0);
        (f.camera_pitch_deg, f.camera_yaw_deg, f.fov_deg) = (6.0, 40.0, 12.0);
        let picture = renderer.render(&f).expect("render");
        let brightness: Vec<f32> = picture.pixels.iter().map(|p| p[0] + p[1] + p[2]).collect();
        let brightest = brightness.iter().copied().fold(0.0f32, f32::max);
        let lit: Vec<bool> = brightness.iter().map(|&b| b > 0.1 * brightest).collect();
        (lit, brightest)
    };
    let (volume, volume_peak) = disc(DrawPath::Volume, &mut renderer);
    let (impostor, impostor_peak) = disc(DrawPath::Impostor, &mut renderer);
    let count = |lit: &[bool]| lit.iter().filter(|&&l| l).count();
    let both = volume
        .iter()
        .zip(&impostor)
        .filter(|(a, b)| **a && **b)
        .count();
    println!(
        "disc pixels: volume {}, impostor {}, in both {both}; peaks {volume_peak:.0} / \
         {impostor_peak:.0}",
        count(&volume),
        count(&impostor)
    );
    assert!(
        count(&volume) >= 8,
        "the view misses the sun: {}",
        count(&volume)
    );
    assert!(
        both * 10 >= count(&volume).max(count(&impostor)) * 9,
        "the impostor's disc is not the volume's: {} and {} pixels, {both} in both",
        count(&volume),
        count(&impostor)
    );
    assert!(
        (impostor_peak / volume_peak - 1.0).abs() < 0.1,
        "the disc's radiance: impostor {impostor_peak}, volume {volume_peak}"
    );
}

#[test]
fn the_slice_pass_draws_what_its_cpu_twin_computes() {
    let lib = library();
    let genus = lib.genus("cumulus").expect("cumulus");
    let mut f = frame(genus, DrawPath::Slices);
    // The medium preset: shape detail and ground bounce, so the stack's density erodes and
    // its third channel (the optical depth down to the base) is baked.
    f.quality = Quality::Medium;
    f.features = Quality::Medium.features();
    f.features.ground_bounce = true;
    f.features.path = DrawPath::Slices;
    f.frames = 1;
    let (mut compared, mut cloudy, mut worst) = (0, 0, 0.0f32);
    let ran = compare_bake(&f, 33, 400, slices_fragment, |_, _, cpu, gpu| {
        // Half floats hold the GPU's texels: 1/1024 relative, and the noise's texel
        // interpolation differs between a GPU sampler and the CPU's in the last bits.
        for c in 0..3 {
            let scale = cpu[c].abs().max(if c == 0 { 1e-3 } else { 0.05 });
            worst = worst.max((gpu[c] - cpu[c]).abs() / scale);
        }
        compared += 1;
        if cpu.x > 1e-3 {
            cloudy += 1;
        }
    });
    if ran.is_none() {
        return;
    }
    println!(
        "{compared} texels of the {SLICE_TEXELS}-texel slices ({cloudy} in cloud): worst \
         relative difference {worst:.4}"
    );
    assert!(cloudy >= 20, "too few texels in cloud to compare: {cloudy}");
    assert!(
        worst < 0.02,
        "the slice pass departs from its CPU twin by {worst}"
    );
}

#[test]
fn the_map_pass_draws_what_its_cpu_twin_computes() {
    let lib = library();
    // Two decks (the takram layers: low cumulus and a thin high layer), so both bands hold a
    // column.
    let genus = lib.genus("takram-default").expect("takram-default");
    let mut f = frame(genus, DrawPath::Blob2d);
    f.frames = 1;
    let (mut compared, mut cloudy, mut worst) = (0, [0; 2], 0.0f32);
    let ran = compare_bake(&f, 34, 400, blob2d_fragment, |x, _, cpu, gpu| {
        let tile = x / BLOB_TEXELS;
        let column_tile = tile.is_multiple_of(2);
        // Column tiles: optical depth, mean altitude, spread (the last two only where there
        // is cloud to have them); sun tiles: four optical depths.
        let channels = if column_tile { 3 } else { 4 };
        for c in 0..channels {
            if column_tile && c > 0 && cpu.x < 1e-3 {
                continue;
            }
            let scale = cpu[c].abs().max(0.05);
            worst = worst.max((gpu[c] - cpu[c]).abs() / scale);
        }
        compared += 1;
        if column_tile && cpu.x > 1e-3 {
            cloudy[(tile / 2) as usize] += 1;
        }
    });
    if ran.is_none() {
        return;
    }
    println!(
        "{compared} texels of the map ({} and {} columns in cloud, lower and upper band): \
         worst relative difference {worst:.4}",
        cloudy[0], cloudy[1]
    );
    assert!(
        cloudy.iter().all(|&n| n >= 10),
        "too few columns in cloud to compare: {cloudy:?}"
    );
    assert!(
        worst < 0.02,
        "the map pass departs from its CPU twin by {worst}"
    );
}

/// The impostor's texels are the volume's pixel per direction, marched and composited by the
/// same `impostor_fragment` on the CPU (with the shadow atlas the frame drew, which its marches
/// to the sun and the ground's shadows read): (light, opacity) in every tile of both rows, the
/// views above and below the horizon, and nothing where a row is never read.
#[test]
fn the_impostor_pass_draws_what_its_cpu_twin_computes() {
    let lib = library();
    let genus = lib.genus("cumulus").expect("cumulus");
    let mut f = frame(genus, DrawPath::Impostor);
    f.frames = 1;
    let (mut compared, mut cloudy, mut empty, mut worst) = (0, 0, 0, 0.0f32);
    let ran = compare_bake(&f, 35, 300, impostor_fragment, |_, _, cpu, gpu| {
        for c in 0..4 {
            let scale = cpu[c].abs().max(0.05);
            worst = worst.max((gpu[c] - cpu[c]).abs() / scale);
        }
        compared += 1;
        if cpu.w > 0.1 {
            cloudy += 1;
        }
        if cpu == glam::Vec4::ZERO {
            empty += 1;
        }
    });
    if ran.is_none() {
        return;
    }
    println!(
        "{compared} texels of the impostor ({cloudy} in cloud, {empty} never read): worst \
         relative difference {worst:.4}"
    );
    assert!(cloudy >= 20, "too few texels in cloud to compare: {cloudy}");
    assert!(
        empty >= 20 && compared - empty >= 20,
        "too few texels on either side of the horizon: {empty} of {compared} empty"
    );
    assert!(
        worst < 0.02,
        "the impostor pass departs from its CPU twin by {worst}"
    );
}

/// The cluster table's texels are the puffs `mesh_fragment` fits on the CPU from the same
/// block and noise: each cluster's flag (the heights and azimuths its puffs reach), and each
/// puff's centre and reach, spreads and peak, and optical depths to the sun, the ground and up
/// beyond its kernel. Two decks (the takram
/// layers), so both bands hold puffs; compared where the CPU's cluster holds cloud.
#[test]
fn the_mesh_pass_draws_what_its_cpu_twin_computes() {
    let lib = library();
    let genus = lib.genus("takram-default").expect("takram-default");
    let mut f = frame(genus, DrawPath::Mesh);
    f.frames = 1;
    let (mut compared, mut cloudy, mut worst) = (0, 0, 0.0f32);
    let ran = compare_bake(&f, 36, 3000, mesh_fragment, |x, _, cpu, gpu| {
        let part = x % CLUSTER_TEXELS;
        let centre_texel = part != 0 && (part - 1).is_multiple_of(3);
        // The flag's four channels; a puff's centre texel only where it holds cloud (an empty
        // puff's centre is its cell's, and its reach 0).
        if centre_texel && cpu.w == 0.0 {
            return;
        }
        for c in 0..4 {
            // Half floats: 1/1024 relative; positions in km near the camera are small.
            let scale = cpu[c].abs().max(0.05);
            worst = worst.max((gpu[c] - cpu[c]).abs() / scale);
        }
        compared += 1;
        if centre_texel {
            cloudy += 1;
        }
    });
    if ran.is_none() {
        return;
    }
    println!(
        "{compared} texels of the cluster table ({cloudy} puffs in cloud): worst relative \
         difference {worst:.4}"
    );
    assert!(cloudy >= 20, "too few puffs in cloud to compare: {cloudy}");
    assert!(
        worst < 0.02,
        "the mesh pass departs from its CPU twin by {worst}"
    );
}

/// The stack is redrawn when what it is baked from moves (the sun, the camera's place and
/// height, the weather, a redrawn shadow cascade) and kept when only the view does (turning the
/// camera, another frame's jitter, the image's size): the members engine hosts are told to
/// ignore (`cloud_bake.ignores`) are members of the block, and nothing the bake reads.
#[test]
fn the_stack_follows_the_sun_and_the_place_not_the_view() {
    use nimbus_clouds::model::bake::{BAKE_IGNORES, MAP_READS, bake_inputs};
    use nimbus_dsl::layout::{UniformBytes, read_members};
    let lib = library();
    let genus = lib.genus("cumulus").expect("cumulus");
    let u: CloudUniforms = Renderer::uniforms(&frame(genus, DrawPath::Slices));
    let key_of = |path: DrawPath| {
        let f = frame(genus, path);
        nimbus_clouds::catalog::assign(&f.genus, f.quality, f.features).clouds
    };
    let (slices, impostor_key) = (key_of(DrawPath::Slices), key_of(DrawPath::Impostor));
    let bytes = u.to_uniform_bytes().expect("bytes");
    let members = read_members(CloudUniforms::shader_type(), &bytes);
    for m in BAKE_IGNORES {
        assert!(
            members
                .iter()
                .any(|(p, _)| p == m || p.starts_with(&format!("{m}."))),
            "`{m}` names no member of the cloud block"
        );
    }
    let base = bake_inputs(&u, &slices).expect("inputs");
    let mut view = u;
    view.inverse_view_projection = glam::Mat4::from_rotation_y(0.4) * u.inverse_view_projection;
    view.jitter = 0.73;
    view.frame = 11;
    view.resolution = glam::Vec2::new(320.0, 180.0);
    assert_eq!(
        bake_inputs(&view, &slices).expect("inputs"),
        base,
        "the view moved the stack"
    );
    let impostor = bake_inputs(&u, &impostor_key).expect("inputs");
    assert_eq!(
        bake_inputs(&view, &impostor_key).expect("inputs"),
        impostor,
        "the view moved the impostor"
    );
    // Every bake lights as the volume does at its key, through the shadow map: a redrawn
    // cascade tile (its transform moved) redraws it; a key without the map ignores it.
    assert!(MAP_READS.starts_with("shadow.lookup"));
    let mut tile = u;
    tile.shadow.lookup.u = glam::Mat4::IDENTITY;
    assert!(slices.uses_shadow_map() && impostor_key.uses_shadow_map());
    for (name, key) in [("stack", slices), ("impostor", impostor_key)] {
        assert_ne!(
            bake_inputs(&tile, &key).expect("inputs"),
            bake_inputs(&u, &key).expect("inputs"),
            "a redrawn cascade tile left the {name} as it was"
        );
    }
    let mut unshadowed = slices;
    unshadowed.features.shadows = false;
    unshadowed.features.light_shafts = false;
    assert!(!unshadowed.uses_shadow_map());
    assert_eq!(
        bake_inputs(&tile, &unshadowed).expect("inputs"),
        bake_inputs(&u, &unshadowed).expect("inputs"),
        "a stack that reads no map followed its tiles"
    );
    type Change = fn(&mut CloudUniforms);
    let moved: [(&str, Change); 4] = [
        ("the sun", |u| {
            u.light.sun_direction = glam::Vec3::new(0.0, 1.0, 0.0)
        }),
        ("the camera's place", |u| u.camera_offset.x += 30.0),
        ("the camera's height", |u| u.camera_altitude += 10.0),
        ("the coverage", |u| u.media.coverage += 0.01),
    ];
    for (what, change) in moved {
        let mut v = u;
        change(&mut v);
        assert_ne!(
            bake_inputs(&v, &slices).expect("inputs"),
            base,
            "{what} left the stack as it was"
        );
    }
    // An impostor that bakes the whole view runs the composite in its bake: the haze and the
    // composite's switches redraw it. Over the engine's depth it composites per pixel, and
    // they do not.
    assert!(impostor_key.bakes_view());
    let mut depth_key = impostor_key;
    depth_key.features.scene_depth = true;
    assert!(!depth_key.bakes_view());
    let composite_inputs: [(&str, Change); 2] = [
        ("the haze", |u: &mut CloudUniforms| u.haze.density += 1e-5),
        ("the ground switch", |u: &mut CloudUniforms| {
            u.composite.ground = 0.0
        }),
    ];
    for (what, change) in composite_inputs {
        let mut v = u;
        change(&mut v);
        assert_ne!(
            bake_inputs(&v, &impostor_key).expect("inputs"),
            bake_inputs(&u, &impostor_key).expect("inputs"),
            "{what} left the impostor's view as it was"
        );
        assert_eq!(
            bake_inputs(&v, &depth_key).expect("inputs"),
            bake_inputs(&u, &depth_key).expect("inputs"),
            "{what} moved the impostor that composites per pixel"
        );
    }
}
