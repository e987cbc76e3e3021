//! No stall when a scene's effects change (`Renderer::set_no_stall`): the frame a toggle
//! flips draws with the key drawn before while the new key's pipelines build off the frame
//! path, and a change of the shadow pass's key redraws the atlas a band per frame. Each is
//! held to what a renderer that stalls draws: the same atlas in the end, to the bit, and the
//! same image once the new key draws; and each check has its control (the atlas half-way is
//! not that atlas; the renderer that stalls never draws a stand-in).

mod common;

use std::path::Path;
use std::time::Duration;

use nimbus_clouds::{CloudLibrary, Quality, Toggle};
use nimbus_runtime::render::{Frame, Image, Renderer, TextureSizes};

const SIZES: TextureSizes = common::SMALL_TEXTURES;

/// Cumulus at `high` (three cascades of 512 texels: 4 bands of 128 rows each), seen from
/// the ground, one frame per call and each call afresh (no history to blend stand-ins in).
fn frame(detail: bool) -> Frame {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let mut f = Frame::new(
        lib.genus("cumulus").expect("cumulus").clone(),
        Quality::High,
        48,
        27,
    );
    f.camera_pitch_deg = 20.0;
    f.frames = 1;
    f.continue_history = false;
    Toggle::ShapeDetail.set(&mut f.features, detail);
    f
}

fn largest_difference(a: &Image, b: &Image) -> f32 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..4).map(move |c| (p[c] - q[c]).abs()))
        .fold(0.0, f32::max)
}

fn atlas(r: &mut Renderer<'_>) -> Image {
    r.shadow_atlas().expect("readback").expect("an atlas")
}

#[test]
fn a_toggle_draws_a_stand_in_then_the_new_key_and_the_atlas_refreshes_band_by_band() {
    let Some(gpu) = common::gpu() else { return };
    let (before, after) = (frame(true), frame(false));
    assert_ne!(
        before.variant().key.shadow_key(),
        after.variant().key.shadow_key(),
        "the toggle must change the shadow pass's key for this test to mean anything"
    );

    // What a renderer that stalls draws: the new key at once, its atlas whole.
    let mut stalls = Renderer::new(gpu, SIZES);
    stalls.render(&before).expect("render");
    let want_image = stalls.render(&after).expect("render");
    assert!(
        !stalls.drew_stand_in(),
        "a renderer that stalls never stands in"
    );
    let want_atlas = atlas(&mut stalls);

    let mut smooth = Renderer::new(gpu, SIZES);
    smooth.set_no_stall(true);
    let old_image = smooth.render(&before).expect("render");
    // The frame the toggle flips requests the new key and draws with the one before.
    let first = smooth.render(&after).expect("render");
    assert!(
        smooth.drew_stand_in(),
        "the first frame after a switch stands in"
    );
    let d = largest_difference(&first, &old_image);
    assert!(
        d < 1e-3,
        "the stand-in draws the previous key's picture (differs by {d})"
    );

    // Frames until the new key draws and the atlas has every band of the new shadow key.
    let mut shadow_frames = 0;
    let mut half_way = None;
    let mut last = first;
    for _ in 0..2000 {
        if smooth.drew_stand_in() || smooth.stats().passes.contains(&"shadow") {
            std::thread::sleep(Duration::from_millis(5));
        } else if shadow_frames > 0 {
            break;
        }
        last = smooth.render(&after).expect("render");
        if smooth.stats().passes.contains(&"shadow") {
            shadow_frames += 1;
            if shadow_frames == 1 {
                half_way = Some(atlas(&mut smooth));
            }
        }
    }
    assert!(!smooth.drew_stand_in(), "the new key never drew");
    assert_eq!(
        shadow_frames, 12,
        "three cascade tiles of 512 rows, redrawn 128 rows per frame"
    );
    let got_atlas = atlas(&mut smooth);
    let d = largest_difference(&got_atlas, &want_atlas);
    assert!(d == 0.0, "the atlas redrawn band by band differs by {d}");
    let control = largest_difference(&half_way.expect("a band was drawn"), &want_atlas);
    assert!(
        control > 1e-3,
        "after one band the rest of the atlas is the previous key's (differs by {control})"
    );
    let d = largest_difference(&last, &want_image);
    assert!(
        d < 1e-5,
        "the new key's frame differs from the stalling renderer's by {d}"
    );
    println!(
        "stand-in, then the new key; atlas refreshed over {shadow_frames} frames, equal to a \
         whole redraw (half-way it differed by {control:.3})"
    );
}

/// A genus of other genus functions has no stand-in (every pipeline that draws its shapes,
/// the uber-shader's too, holds its code): its first frame waits for its own key and is its
/// own picture, where a toggle's first frame is the previous key's (the test above).
#[test]
fn a_genus_of_other_functions_waits_for_its_own_key() {
    let Some(gpu) = common::gpu() else { return };
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let before = frame(true);
    let functions = before.variant().key.functions;
    let other = lib
        .genera
        .values()
        .map(|(_, g)| g)
        .find(|g| {
            let mut f = before.clone();
            f.genus = (*g).clone();
            f.variant().key.functions != functions
        })
        .expect("a genus with functions of its own");
    let mut after = before.clone();
    after.genus = other.clone();

    let mut stalls = Renderer::new(gpu, SIZES);
    let want = stalls.render(&after).expect("render");

    let mut smooth = Renderer::new(gpu, SIZES);
    smooth.set_no_stall(true);
    let old = smooth.render(&before).expect("render");
    let first = smooth.render(&after).expect("render");
    assert!(
        !smooth.drew_stand_in(),
        "nothing built can draw {}",
        other.name
    );
    let d = largest_difference(&first, &want);
    assert!(
        d < 1e-5,
        "{}'s first frame differs from its own by {d}",
        other.name
    );
    let control = largest_difference(&first, &old);
    assert!(
        control > 1e-3,
        "the two genera look alike ({control}): no control"
    );
}
