//! Cascades in rotation, the host's bookkeeping (`shadow::redrawn_tiles`,
//! `shadow::anchored_tiles`): a tile drawn frames ago, around another place and for another
//! sun, is read through the transform it was drawn with, moved to where its clouds are now;
//! a tile redrawn takes the sun's transform as it is, the others keep theirs to the bit; the
//! JavaScript twins the engine packages run give the same transforms; and the wgpu runtime in
//! rotation ends, a band of a tile a frame (and the air table in bands), at the atlas, the
//! table and the frame a whole redraw draws, never showing a tile half drawn.

mod common;

use std::path::Path;

use glam::{Vec2, Vec3, Vec4};
use nimbus_clouds::model::march::CloudUniforms;
use nimbus_clouds::model::shadow::{
    CascadeLookup, anchored_tiles, redrawn_tiles, shadow_anchor, shifted_lookup,
};
use nimbus_clouds::model::sun::{host_module, sun_direction, sun_light};
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_codegen::print_js;
use serde_json::{Value, json};

fn block(quality: Quality, altitude: f32) -> CloudUniforms {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    CloudUniforms::for_genus(
        lib.genus("cumulus").expect("cumulus"),
        quality,
        sun_direction(35.0, 150.0),
        altitude,
    )
}

/// Every tile's texture coordinates of camera-relative `p` (u in x..w of the first vector).
fn coordinates(l: &CascadeLookup, p: Vec3) -> (Vec4, Vec4) {
    (l.u * p.extend(1.0), l.v * p.extend(1.0))
}

/// Points around the camera out to the coarsest cascade's reach, on and off the ground.
fn points() -> Vec<Vec3> {
    let mut out = Vec::new();
    for i in 0..9 {
        for j in 0..9 {
            for y in [-1.5, 0.0, 800.0, 2_500.0] {
                out.push(Vec3::new(
                    (i as f32 - 4.0) * 6_000.0,
                    y,
                    (j as f32 - 4.0) * 6_000.0,
                ));
            }
        }
    }
    out
}

/// Where a camera-relative point lies in the clouds' own frame (noise space, less the wind's
/// drift at the ground, and altitude): what a shadow tile's column holds.
fn cloud_point(p: Vec3, camera_offset: Vec3, camera_altitude: f32, drift: Vec2) -> Vec3 {
    Vec3::new(
        p.x + camera_offset.x - drift.x,
        p.y + camera_altitude,
        p.z + camera_offset.z - drift.y,
    )
}

/// A `high` frame of cumulus at 64 × 36, the sun at `elevation` and `azimuth`, one frame
/// drawn on its own: what the runtime tests below render.
fn high_frame(lib: &CloudLibrary, elevation: f32, azimuth: f32) -> nimbus_runtime::render::Frame {
    let mut f = nimbus_runtime::render::Frame::new(
        lib.genus("cumulus").expect("cumulus").clone(),
        Quality::High,
        64,
        36,
    );
    f.camera_pitch_deg = 20.0;
    f.sun_elevation_deg = elevation;
    f.sun_azimuth_deg = azimuth;
    f.frames = 1;
    f.continue_history = false;
    f
}

/// The largest difference between two images, every channel.
fn largest(a: &nimbus_runtime::render::Image, b: &nimbus_runtime::render::Image) -> f32 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..4).map(move |c| (p[c] - q[c]).abs()))
        .fold(0.0f32, f32::max)
}

/// The largest difference between two atlases over their first tile (the top-left square of
/// `side` texels).
fn tile0(a: &nimbus_runtime::render::Image, b: &nimbus_runtime::render::Image, side: usize) -> f32 {
    let mut d = 0.0f32;
    for y in 0..side {
        for x in 0..side {
            let (p, q) = (
                a.pixels[y * a.width as usize + x],
                b.pixels[y * b.width as usize + x],
            );
            d = (0..4).map(|c| (p[c] - q[c]).abs()).fold(d, f32::max);
        }
    }
    d
}

#[test]
fn a_kept_tile_is_read_where_its_clouds_are_now() {
    for quality in [Quality::Low, Quality::High] {
        // Drawn with the camera here, the wind's drift there.
        let (offset0, altitude0, drift0) = (Vec3::new(120.0, 0.0, -40.0), 2.0, Vec2::new(0.0, 0.0));
        let u0 = block(quality, altitude0);
        let drawn = sun_light(u0, u0.light.sun_direction).shadow_lookup;
        let anchor0 = shadow_anchor(offset0, altitude0, drift0);
        let kept = redrawn_tiles(drawn, drawn, anchor0, Vec4::ONE);
        // Read frames later: the camera flew 900 m and climbed 300 m, the wind carried the
        // clouds 250 m east and 60 m south.
        let (offset1, altitude1, drift1) = (
            Vec3::new(1_020.0, 0.0, -40.0),
            302.0,
            Vec2::new(250.0, 60.0),
        );
        let anchor1 = shadow_anchor(offset1, altitude1, drift1);
        let read = anchored_tiles(kept, anchor1);
        let mut worst = 0.0f32;
        let mut control = 0.0f32;
        for p in points() {
            // The point of the clouds `p` now shows, and where the camera stood relative to
            // it when the tile was drawn.
            let c = cloud_point(p, offset1, altitude1, drift1);
            let then = Vec3::new(
                c.x - offset0.x + drift0.x,
                c.y - altitude0,
                c.z - offset0.z + drift0.y,
            );
            let (want_u, want_v) = coordinates(&drawn, then);
            let (got_u, got_v) = coordinates(&read, p);
            worst = worst.max(
                (got_u - want_u)
                    .abs()
                    .max((got_v - want_v).abs())
                    .max_element(),
            );
            // The control: the tile read as if drawn around the camera now.
            let (stale_u, stale_v) = coordinates(&drawn, p);
            control = control.max(
                (stale_u - want_u)
                    .abs()
                    .max((stale_v - want_v).abs())
                    .max_element(),
            );
        }
        // Tile coordinates: 1e-5 is a 40th of a texel of a 2,048-texel tile.
        println!(
            "{}: kept tiles read {worst:.2e} off (tile widths); unmoved, {control:.2e}",
            quality.name()
        );
        assert!(worst < 1e-5, "{}: {worst}", quality.name());
        assert!(
            control > 1e-3,
            "{}: the control moved nothing ({control})",
            quality.name()
        );
    }
}

#[test]
fn a_redrawn_tile_takes_the_sun_as_it_is_and_the_others_keep_theirs() {
    let u = block(Quality::High, 2.0);
    let before = sun_light(u, sun_direction(35.0, 150.0)).shadow_lookup;
    let after = sun_light(u, sun_direction(37.0, 153.0)).shadow_lookup;
    let anchor = shadow_anchor(Vec3::new(310.0, 0.0, 75.0), 2.0, Vec2::new(40.0, -12.0));
    let kept = redrawn_tiles(before, before, anchor, Vec4::ONE);
    // Tile 1 redrawn for the new sun: its row is the new sun's, the others' are untouched.
    let mixed = redrawn_tiles(kept, after, anchor, Vec4::new(0.0, 1.0, 0.0, 0.0));
    let fresh = shifted_lookup(after, -anchor);
    for c in 0..4 {
        for (m, k, f) in [(mixed.u, kept.u, fresh.u), (mixed.v, kept.v, fresh.v)] {
            let (m, k, f) = (m.col(c), k.col(c), f.col(c));
            assert_eq!(m.x.to_bits(), k.x.to_bits(), "tile 0, column {c}");
            assert_eq!(m.y.to_bits(), f.y.to_bits(), "tile 1, column {c}");
            assert_eq!(m.z.to_bits(), k.z.to_bits(), "tile 2, column {c}");
            assert_eq!(m.w.to_bits(), k.w.to_bits(), "tile 3, column {c}");
        }
    }
    // Every tile redrawn around the camera: the sun's own lookup, to rounding.
    let all = anchored_tiles(redrawn_tiles(mixed, after, anchor, Vec4::ONE), anchor);
    for p in points() {
        let (gu, gv) = coordinates(&all, p);
        let (wu, wv) = coordinates(&after, p);
        let d = (gu - wu).abs().max((gv - wv).abs()).max_element();
        assert!(d < 1e-5, "{p}: {d}");
    }
    // The control: the mixed lookup still reads tiles 0, 2 and 3 for the old sun.
    let read = anchored_tiles(mixed, anchor);
    let p = Vec3::new(2_000.0, 0.0, 1_000.0);
    let (gu, _) = coordinates(&read, p);
    let (wu, _) = coordinates(&after, p);
    assert!((gu.x - wu.x).abs() > 1e-4, "tile 0 took the new sun");
}

#[test]
fn the_javascript_twins_keep_and_read_the_tiles_as_the_cpu_twins() {
    if !nimbus_testkit::skip::browser_tools_present(
        "the JavaScript twin test of the cascade rotation",
        nimbus_testkit::skip::node_missing(),
    ) {
        return;
    }
    let module = host_module().expect("records");
    let js = print_js(
        &module,
        &["shadow_anchor", "redrawn_tiles", "anchored_tiles"],
    )
    .expect("prints");
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("sun.mjs"), &js).expect("write module");
    let u = block(Quality::Ultra, 2.0);
    let a = sun_light(u, sun_direction(35.0, 150.0)).shadow_lookup;
    let b = sun_light(u, sun_direction(8.0, 230.0)).shadow_lookup;
    let lookup = |l: &CascadeLookup| {
        let cols = |m: glam::Mat4| (0..4).map(|c| m.col(c).to_array()).collect::<Vec<_>>();
        json!({ "u": cols(l.u), "v": cols(l.v) })
    };
    let cases = [
        (Vec3::new(0.0, 0.0, 0.0), 2.0, Vec2::ZERO, Vec4::ONE),
        (
            Vec3::new(1_500.0, 0.0, -800.0),
            450.0,
            Vec2::new(30.0, 5.0),
            Vec4::new(0.0, 0.0, 1.0, 0.0),
        ),
        (
            Vec3::new(-40_000.0, 0.0, 9_000.0),
            3_000.0,
            Vec2::new(-7_000.0, 2_000.0),
            Vec4::new(1.0, 0.0, 0.0, 0.0),
        ),
    ];
    let inputs: Vec<Value> = cases
        .iter()
        .map(|(o, alt, d, m)| {
            json!({
                "offset": o.to_array(), "altitude": alt, "drift": d.to_array(), "mask": m.to_array()
            })
        })
        .collect();
    std::fs::write(
        dir.path().join("run.mjs"),
        format!(
            "import {{ shadow_anchor, redrawn_tiles, anchored_tiles }} from './sun.mjs';\n\
             const a = {a}; const b = {b}; const cases = {cases};\n\
             console.log(JSON.stringify(cases.map((c) => {{\n\
               const anchor = shadow_anchor(c.offset, c.altitude, c.drift);\n\
               const kept = redrawn_tiles(a, b, anchor, c.mask);\n\
               return {{ anchor, kept, read: anchored_tiles(kept, anchor) }};\n\
             }})));\n",
            a = lookup(&a),
            b = lookup(&b),
            cases = Value::Array(inputs),
        ),
    )
    .expect("write runner");
    let results = common::run_node_json(&dir.path().join("run.mjs"), &js);
    let mut worst = 0.0f64;
    for ((o, alt, d, m), got) in cases.iter().zip(results.as_array().expect("results")) {
        let anchor = shadow_anchor(*o, *alt, *d);
        let kept = redrawn_tiles(a, b, anchor, *m);
        let read = anchored_tiles(kept, anchor);
        for (field, cpu) in [("kept", kept), ("read", read)] {
            let want: Vec<f64> = [cpu.u, cpu.v]
                .iter()
                .flat_map(|m| m.to_cols_array())
                .map(f64::from)
                .collect();
            let js = common::json_floats(&got[field]);
            assert_eq!(js.len(), want.len(), "{field}");
            for (j, c) in js.iter().zip(&want) {
                // f64 against f32: relative to the member's size, absolute near zero.
                let diff = (j - c).abs() / (1.0 + c.abs());
                worst = worst.max(diff);
                assert!(diff < 1e-5, "{field}: JavaScript {j} against CPU {c}");
            }
        }
    }
    println!("JavaScript (f64) against the CPU twins (f32): largest difference {worst:.2e}");
}

/// The wgpu runtime in rotation (`Renderer::set_cascade_rotation`): after the sun moves, each
/// frame draws one band of a tile (`tile_bands`: `high`'s 512-texel tiles in eight) into the
/// back atlas, and a tile reaches the atlas the clouds read only with its last band: until
/// then the atlas is the old sun's to the bit (no frame reads a tile half drawn), after it
/// that tile is the whole redraw's. Once all three tiles are drawn the atlas is a whole
/// redraw's to the bit and the frame its to rounding, while the frame right after the move
/// is not (the control). The air table, drawn in bands likewise, stays the old sun's until
/// its last band and ends at the whole redraw's table.
#[test]
fn the_runtime_redraws_a_band_a_frame_and_ends_at_the_whole_atlas() {
    use nimbus_clouds::model::air_table::air_table_size;
    use nimbus_clouds::model::tile_bands::{bands_of, tile_bands};
    use nimbus_runtime::render::Renderer;
    let Some(gpu) = common::gpu() else { return };
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let frame = |elevation: f32| high_frame(&lib, elevation, 150.0);
    // The atlas's first tile (its top-left square of `side` texels) against another's.
    let settings = Quality::High.settings();
    let (count, side) = (settings.shadow_cascade_count, settings.shadow_map_size);
    let bands = tile_bands(side);
    assert!(bands > 1, "high's tiles are drawn in bands");
    let (air_w, air_h) = air_table_size();
    let air_bands = bands_of(air_w, air_h);
    let (before, after) = (frame(35.0), frame(20.0));
    let mut whole = Renderer::new(gpu, common::SMALL_TEXTURES);
    let want = whole.render(&after).expect("render");
    let want_atlas = whole.shadow_atlas().expect("readback").expect("atlas");

    let mut rotating = Renderer::new(gpu, common::SMALL_TEXTURES);
    rotating.set_cascade_rotation(true);
    rotating.render(&before).expect("render");
    let old_atlas = rotating.shadow_atlas().expect("readback").expect("atlas");
    let old_air = rotating.air_table().expect("readback").expect("air table");
    let mut passes = Vec::new();
    let mut air_passes = Vec::new();
    let mut air_while_drawing = 0.0f32;
    let mut first = None;
    let mut last = None;
    // While the first tile's bands are drawn, and right after its last.
    let (mut while_drawing, mut tile_done) = (0.0f32, f32::MAX);
    for i in 0..count * bands + 1 {
        let image = rotating.render(&after).expect("render");
        passes.push(
            rotating
                .stats()
                .passes
                .iter()
                .filter(|p| **p == "shadow")
                .count(),
        );
        air_passes.push(
            rotating
                .stats()
                .passes
                .iter()
                .filter(|p| **p == "air")
                .count(),
        );
        let air = rotating.air_table().expect("readback").expect("air table");
        if i + 1 < air_bands {
            air_while_drawing = air_while_drawing.max(largest(&air, &old_air));
        }
        let atlas = rotating.shadow_atlas().expect("readback").expect("atlas");
        if i + 1 < bands {
            while_drawing = while_drawing.max(largest(&atlas, &old_atlas));
        } else if i + 1 == bands {
            tile_done = tile0(&atlas, &want_atlas, side as usize);
        }
        if i == 0 {
            first = Some(image);
        } else {
            last = Some(image);
        }
    }
    let want_passes: Vec<usize> = (0..count * bands + 1)
        .map(|i| usize::from(i < count * bands))
        .collect();
    assert_eq!(
        passes, want_passes,
        "a band per frame, {count} tiles of {bands}, then none"
    );
    // The air table in bands likewise, one tile: the old sun's until its last band.
    let want_air: Vec<usize> = (0..count * bands + 1)
        .map(|i| usize::from(i < air_bands))
        .collect();
    assert_eq!(air_passes, want_air, "the air table's {air_bands} bands");
    let want_table = whole.air_table().expect("readback").expect("air table");
    let table_d = largest(
        &rotating.air_table().expect("readback").expect("air table"),
        &want_table,
    );
    let table_moved = largest(&old_air, &want_table);
    println!(
        "air table in {air_bands} bands: {air_while_drawing} from the old one while drawn, {table_d} \
         from a whole redraw's at the end (the sun's move changed it by {table_moved})"
    );
    assert!(air_while_drawing == 0.0 && table_d == 0.0 && table_moved > 1e-3);
    let got_atlas = rotating.shadow_atlas().expect("readback").expect("atlas");
    let atlas_d = largest(&got_atlas, &want_atlas);
    let settled = largest(last.as_ref().expect("frames"), &want);
    let first = largest(first.as_ref().expect("frames"), &want);
    println!(
        "rotation in bands ({count} tiles of {bands}): the atlas {while_drawing} from the old one \
         while the first tile is drawn, its tile {tile_done} from a whole redraw's after its last \
         band; the atlas at the end {atlas_d} from a whole redraw, the frame {settled:.2e} (the \
         frame after the move: {first:.3})"
    );
    // The control: the new sun's first tile is not the old one's, so a band of it in the
    // atlas would show.
    let moved = tile0(&old_atlas, &want_atlas, side as usize);
    assert!(
        moved > 1e-2,
        "the control: the sun's move left the first tile alone ({moved})"
    );
    assert!(
        while_drawing == 0.0,
        "a tile half drawn reached the atlas: {while_drawing}"
    );
    assert!(
        tile_done == 0.0,
        "the first tile, done, differs by {tile_done}"
    );
    assert!(atlas_d == 0.0, "the rotated atlas differs by {atlas_d}");
    assert!(settled < 1e-3, "the settled frame differs by {settled}");
    assert!(
        first > 1e-2,
        "the control: the frame after the move already looked whole ({first})"
    );
}

/// A tile is drawn, band by band, from the block of its first band: with the sun moving every
/// frame while `high`'s first tile is drawn in its bands, the tile copied in is a whole
/// redraw's for the sun of that first band, to the bit. The control: a whole redraw for the sun
/// of its last band differs (bands drawn from the block of their own frame would mix the two).
#[test]
fn a_tile_drawn_in_bands_shows_the_sun_of_its_first_band() {
    use nimbus_clouds::model::tile_bands::tile_bands;
    use nimbus_runtime::render::Renderer;
    let Some(gpu) = common::gpu() else { return };
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let frame = |azimuth: f32| high_frame(&lib, 30.0, azimuth);
    let side = Quality::High.settings().shadow_map_size as usize;
    let bands = tile_bands(side as u32);
    let whole = |azimuth: f32| {
        let mut r = Renderer::new(gpu, common::SMALL_TEXTURES);
        r.render(&frame(azimuth)).expect("render");
        r.shadow_atlas().expect("readback").expect("atlas")
    };
    let mut rotating = Renderer::new(gpu, common::SMALL_TEXTURES);
    rotating.set_cascade_rotation(true);
    rotating.render(&frame(150.0)).expect("render");
    // The sun moves 3° of azimuth every frame while tile 0's bands are drawn.
    let azimuth = |i: u32| 153.0 + 3.0 * i as f32;
    for i in 0..bands {
        rotating.render(&frame(azimuth(i))).expect("render");
    }
    let atlas = rotating.shadow_atlas().expect("readback").expect("atlas");
    let first = tile0(&atlas, &whole(azimuth(0)), side);
    let last = tile0(&atlas, &whole(azimuth(bands - 1)), side);
    println!(
        "tile 0 drawn in {bands} bands with the sun moving 3° a frame: {first} from a whole \
         redraw for its first band's sun, {last} from one for its last band's"
    );
    assert!(first == 0.0, "tile 0 is not its first band's sun: {first}");
    assert!(
        last > 1e-3,
        "the control: the sun's move changed nothing ({last})"
    );
}

/// Switching the rotation off while a tile is half drawn redraws the whole atlas on the next
/// frame (a half-drawn tile, or tiles read through the sun as it is, would put shadows out of
/// place): the atlas is then a whole redraw's to the bit. The control: the atlas a frame into
/// the rotation is still the old sun's.
#[test]
fn switching_the_rotation_off_mid_tile_redraws_the_atlas_whole() {
    use nimbus_runtime::render::Renderer;
    let Some(gpu) = common::gpu() else { return };
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let frame = |elevation: f32| high_frame(&lib, elevation, 150.0);
    let mut whole = Renderer::new(gpu, common::SMALL_TEXTURES);
    whole.render(&frame(20.0)).expect("render");
    let want = whole.shadow_atlas().expect("readback").expect("atlas");
    let mut r = Renderer::new(gpu, common::SMALL_TEXTURES);
    r.set_cascade_rotation(true);
    r.render(&frame(35.0)).expect("render");
    let old = r.shadow_atlas().expect("readback").expect("atlas");
    // One band drawn into the back atlas, then the rotation switched off.
    r.render(&frame(20.0)).expect("render");
    let mid = r.shadow_atlas().expect("readback").expect("atlas");
    r.set_cascade_rotation(false);
    r.render(&frame(20.0)).expect("render");
    let after = r.shadow_atlas().expect("readback").expect("atlas");
    let (d, control) = (largest(&after, &want), largest(&mid, &old));
    println!(
        "rotation off mid-tile: the next atlas {d} from a whole redraw (a frame into the \
         rotation it was the old one's: {control} from it; the old against the new: {})",
        largest(&old, &want)
    );
    assert!(
        d == 0.0,
        "the atlas after switching the rotation off differs by {d}"
    );
    assert!(control == 0.0 && largest(&old, &want) > 1e-2);
}
