//! After the first frame, frames create nothing: each pass keeps its uniform buffer, bind group
//! and target, the history and readback buffers are reused, and bind groups are remade only
//! when a resource they reference was replaced. One test in its own binary, so that no other
//! test allocates on the same device while it counts.

mod common;

use std::path::Path;

use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

const SIZES: TextureSizes = common::SMALL_TEXTURES;

#[test]
fn frames_after_the_first_create_no_buffer_texture_or_bind_group() {
    let Some(gpu) = common::gpu() else { return };
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let mut f = Frame::new(
        lib.genus("cumulus").expect("cumulus").clone(),
        Quality::High,
        40,
        24,
    );
    f.camera_pitch_deg = 20.0;
    f.upscale = true;
    f.frames = 2;
    f.continue_history = true;
    let mut r = Renderer::new(gpu, SIZES);
    let before = gpu.resource_counts();
    r.render(&f).expect("first");
    let first = gpu.resource_counts();
    // The first frame made the passes' resources: the counter sees the renderer's allocations.
    assert!(
        first.buffers > before.buffers
            && first.textures > before.textures
            && first.bind_groups > before.bind_groups,
        "{before:?} → {first:?}"
    );
    // A game loop: the camera turns, the sun and the wind move (the shadow atlas is redrawn),
    // each call renders several frames; a fresh start on the same targets too.
    for i in 0..6 {
        f.camera_yaw_deg += 3.0;
        f.sun_elevation_deg += 0.5;
        f.weather_offset.x += 0.001;
        f.continue_history = i % 3 != 2;
        r.render(&f).expect("frame");
        assert_eq!(gpu.resource_counts(), first, "call {i} allocated");
    }
    // Control: a new image size needs new targets and bind groups, and the counter sees them.
    f.width = 48;
    r.render(&f).expect("resized");
    let resized = gpu.resource_counts();
    assert!(
        resized.textures > first.textures && resized.bind_groups > first.bind_groups,
        "{first:?} → {resized:?}"
    );
    println!("first frame: {first:?}; after 6 more calls: unchanged; resized: {resized:?}");
}
