//! A genus of a user's own (the `supercell` example crate): its shape and profile are
//! `#[shader_fn]`s written there. Its shaders carry its functions on every target, validated;
//! it renders; and the functions, not the numbers, make its picture.

mod common;

use nimbus_clouds::catalog::ShaderKey;
use nimbus_clouds::model::clouds::CloudVariant;
use nimbus_clouds::{GenusFunctions, Quality};
use nimbus_codegen::{Target, generate_variant};
use nimbus_dsl::ShaderVariant;
use nimbus_runtime::render::{Frame, Renderer, TextureSizes};

#[test]
fn the_user_genus_shaders_hold_its_functions_on_every_target() {
    let genus = supercell::genus().expect("supercell genus");
    let key = CloudVariant::new(&genus, Quality::High, Quality::High.features()).key;
    // Its functions in the key's name (then the weather exponent's power: its layer's is 2).
    assert!(
        key.name().contains("-supercell_shape-supercell_profile"),
        "{}",
        key.name()
    );
    let shadow = key.shadow_key().expect("shadow pass");
    for shader in [ShaderKey::Clouds(key), ShaderKey::Shadow(shadow)] {
        // Every target, each validated by naga (an invalid one is an error here).
        let g = generate_variant(&shader, &Target::ALL).expect("generates and validates");
        let wgsl = g
            .files
            .iter()
            .find(|f| f.file_name.ends_with(".wgsl"))
            .map(|f| String::from_utf8_lossy(&f.contents.to_bytes()).into_owned())
            .expect("WGSL");
        for own in ["fn supercell_shape(", "fn supercell_profile("] {
            assert!(wgsl.contains(own), "{}: no `{own}`", shader.id());
        }
        // The defaults it replaces are gone, the one it calls is there.
        assert!(!wgsl.contains("fn rounded_shape("), "{}", shader.id());
        assert!(wgsl.contains("fn exponential_profile("), "{}", shader.id());
        assert!(
            wgsl.contains("// nimbus: `supercell_shape` from examples/supercell/src/lib.rs"),
            "the generated code says where the user's function came from"
        );
        let targets: Vec<Target> = g.files.iter().map(|f| f.target).collect();
        for t in Target::ALL {
            assert!(targets.contains(&t), "{}: no {t:?} file", shader.id());
        }
    }
}

#[test]
fn the_user_genus_renders_and_its_functions_make_the_picture() {
    let Some(gpu) = common::gpu() else { return };
    println!("adapter: {}", gpu.info());
    let genus = supercell::genus().expect("supercell genus");
    let frame_of = |g: nimbus_clouds::Genus| {
        let mut f = Frame::new(g, Quality::Medium, 160, 90);
        f.camera_altitude = 300.0;
        f.camera_pitch_deg = 14.0;
        f.sun_elevation_deg = 28.0;
        f
    };
    let mut renderer = Renderer::new(gpu, TextureSizes::default());
    let own = renderer.render(&frame_of(genus.clone())).expect("render");
    // Control: the same numbers with the built-in functions.
    let mut plain = genus;
    plain.functions = GenusFunctions::default();
    let std = renderer.render(&frame_of(plain)).expect("render");
    let cover = |im: &nimbus_runtime::render::Image| {
        im.pixels.iter().map(|p| p[3]).sum::<f32>() / im.pixels.len() as f32
    };
    let diff = own
        .pixels
        .iter()
        .zip(&std.pixels)
        .filter(|(a, b)| (a[3] - b[3]).abs() > 0.05)
        .count() as f32
        / own.pixels.len() as f32;
    println!(
        "cloud cover: supercell {:.3}, same numbers with the built-in functions {:.3}; {:.1} % of pixels differ in opacity by > 0.05",
        cover(&own),
        cover(&std),
        diff * 100.0
    );
    assert!(cover(&own) > 0.01, "the supercell renders clouds");
    assert!(diff > 0.01, "its functions change the picture");
    assert!(
        renderer
            .stats()
            .pipelines
            .iter()
            .any(|p| p.contains("supercell_shape")),
        "a pipeline of its own key: {:?}",
        renderer.stats().pipelines
    );
}
