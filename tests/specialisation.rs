//! Generation-time choices leave no trace: a branch decided while generating leaves no code,
//! binding or helper behind in WGSL or in any other target.

use nimbus_clouds::catalog::catalog;
use nimbus_codegen::{Contents, Target, generate};
use nimbus_dsl::cpu::{Sampler, Texture3d};
use nimbus_dsl::prelude::*;
use nimbus_dsl::shader;
use nimbus_dsl::{ModuleBuilder, loc};

fn texts(g: &nimbus_codegen::Generated) -> Vec<(String, String)> {
    g.files
        .iter()
        .filter_map(|f| match &f.contents {
            Contents::Text(t) => Some((f.file_name.clone(), t.clone())),
            Contents::SpirV(_) => None,
        })
        .collect()
}

#[test]
fn the_single_lobe_preview_has_no_dual_lobe_code_in_any_target() {
    for source in catalog() {
        let g = nimbus_codegen::generate_variant(&source, &Target::ALL).expect("generate");
        let dual = nimbus_dsl::ShaderVariant::variant(&source) == "dual_lobe";
        for (name, text) in texts(&g) {
            // The vertex stage never evaluates a phase function, in either variant.
            // WGSL and HLSL files hold both stages.
            let fragment =
                name.ends_with(".wgsl") || name.ends_with(".hlsl") || name.contains(".fs_main.");
            assert_eq!(text.contains("dual_lobe_hg"), dual && fragment, "{name}");
        }
    }
}

/// Shadowed density: samples a shadow texture only when `shadows` is on.
#[shader_fn]
fn lit_density(
    density: f32,
    tex: &Texture3d,
    smp: &Sampler,
    p: Vec3,
    #[spec] shadows: bool,
) -> f32 {
    if shadows {
        let t = tex.sample_level(smp, p, 0.0).x;
        return density * t;
    }
    density
}

fn module(shadows: bool) -> nimbus_dsl::ir::Module {
    ModuleBuilder::build("toggle", "", loc!(), |m| {
        let tex = m.handle::<Texture3d>("shadow_map", 0, 1, "");
        let smp = m.handle::<Sampler>("shadow_sampler", 0, 2, "");
        m.fragment("fs_main", "", loc!(), |frag| {
            let p = frag.xyz();
            let d = lit_density::shader(frag.w, tex.get(), smp.get(), p, shadows);
            shader::vec4(d, d, d, 1.0)
        });
    })
    .expect("records")
}

#[test]
fn a_toggle_that_is_off_removes_its_code_bindings_and_textures_everywhere() {
    let on = generate(module(true), "on", &Target::ALL).expect("on");
    let off = generate(module(false), "off", &Target::ALL).expect("off");
    assert_eq!(on.stats.bindings, 2);
    assert_eq!(on.stats.texture_samples, 1);
    assert_eq!(off.stats.bindings, 0, "no binding left:\n{}", off.wgsl);
    assert_eq!(off.stats.texture_samples, 0);
    for (name, text) in texts(&on) {
        if name.contains(".fs_main.") || name.ends_with(".wgsl") || name.ends_with(".hlsl") {
            assert!(
                text.contains("shadow_map") || text.contains("_group_0_binding_1"),
                "{name} lost the texture"
            );
        }
    }
    for (name, text) in texts(&off) {
        for gone in [
            "shadow_map",
            "shadow_sampler",
            "texture_3d",
            "textureSample",
            "sampler3D",
            "Texture3D",
            "SamplerState",
            "texture3d",
            "binding",
        ] {
            assert!(
                !text.contains(gone),
                "{name} still mentions `{gone}`:\n{text}"
            );
        }
    }
    for f in off.files.iter().filter_map(|f| f.manifest.as_ref()) {
        assert!(
            f.bindings.is_empty(),
            "{:?}: {:?}",
            f.entry_points,
            f.bindings
        );
    }
    // The CPU twin agrees with both specialisations.
    let tex = Texture3d {
        size: [1, 1, 1],
        texels: vec![glam::Vec4::splat(0.5)],
    };
    let smp = Sampler::default();
    assert_eq!(lit_density(0.8, &tex, &smp, Vec3::ZERO, true), 0.4);
    assert_eq!(lit_density(0.8, &tex, &smp, Vec3::ZERO, false), 0.8);
}

/// Literal arithmetic that a variant fixes is folded, and a branch on it disappears.
#[shader_fn]
fn folded(x: f32, #[spec] octaves: u32) -> f32 {
    let scale = octaves as f32 * 0.5;
    if scale > 1.0 {
        return x * scale;
    }
    x
}

#[test]
fn literal_conditions_are_folded_away() {
    let m = ModuleBuilder::build("fold", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), |frag| {
            let v = folded::shader(frag.x, 4u32);
            shader::vec4(v, v, v, 1.0)
        });
    })
    .expect("records");
    let g = generate(m, "fold", &[Target::Wgsl]).expect("generate");
    let body = g
        .wgsl
        .split("fn folded_4")
        .nth(1)
        .expect("specialised copy")
        .to_string();
    assert!(!body.contains("if "), "branch should be folded:\n{body}");
    assert!(body.contains("x * 2.0"), "{body}");
    assert_eq!(folded(1.0, 4), 2.0);
    assert_eq!(folded(1.0, 1), 1.0);
}
