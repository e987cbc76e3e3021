//! The uniform layout Nimbus computes from the Rust struct definitions matches naga's layout of
//! the generated WGSL (its front end's offsets and `naga::proc::Layouter`'s sizes and
//! alignments), member by member, and the bytes written for a CPU value land there.

use std::collections::BTreeSet;
use std::path::Path;

use naga::proc::{Alignment, Layouter};

use nimbus_clouds::CloudKey;
use nimbus_clouds::catalog::catalog;
use nimbus_clouds::model::clouds::{CloudVariant, cloud_module};
use nimbus_clouds::model::formation::{formation_step_module, formation_weather_module};
use nimbus_clouds::model::preview::PreviewParams;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_codegen::{generate_variant, print_and_validate};
use nimbus_dsl::layout::{UniformBytes, align_size, struct_layout};

/// What the comparison covered, for the test's output.
#[derive(Default)]
struct Checked {
    structs: BTreeSet<&'static str>,
    members: usize,
}

/// Compares Nimbus's layout of every struct of `module` with naga's: member offsets as naga's
/// WGSL front end placed them in the printed shader, and each struct's and member's size and
/// alignment as `naga::proc::Layouter` computes them. Nothing here reuses Nimbus's arithmetic,
/// so a drift of `struct_layout` or `align_size` from WGSL's rules fails.
fn check_module(module: nimbus_dsl::ir::Module, checked: &mut Checked) {
    let (ir, _, _, validated) = print_and_validate(module, "layout").expect("valid");
    let naga_module = &validated.module;
    let mut layouter = Layouter::default();
    layouter
        .update(naga_module.to_ctx())
        .expect("naga lays out the generated module");
    let alignment = |a: u32| Alignment::new(a).expect("a power of two");
    for def in &ir.structs {
        let (align, size, offsets) = struct_layout(def);
        let (handle, naga_ty) = naga_module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(def.name))
            .unwrap_or_else(|| panic!("naga has no struct {}", def.name));
        let naga::TypeInner::Struct { members, span } = &naga_ty.inner else {
            panic!("{} is not a struct in naga", def.name);
        };
        let layout = layouter[handle];
        assert_eq!(*span, size, "size of {} (naga's span)", def.name);
        assert_eq!(layout.size, size, "size of {} (Layouter)", def.name);
        assert_eq!(
            layout.alignment,
            alignment(align),
            "alignment of {}: naga {}, Nimbus {align}",
            def.name,
            layout.alignment
        );
        assert_eq!(members.len(), def.fields.len(), "members of {}", def.name);
        for ((m, field), off) in members.iter().zip(def.fields).zip(&offsets) {
            let what = format!("{}.{}", def.name, field.name);
            assert_eq!(m.offset, *off, "offset of {what}");
            let (field_align, field_size) = align_size(field.ty);
            assert_eq!(layouter[m.ty].size, field_size, "size of {what}");
            assert_eq!(
                layouter[m.ty].alignment,
                alignment(field_align),
                "alignment of {what}"
            );
            checked.members += 1;
        }
        checked.structs.insert(def.name);
    }
}

#[test]
fn every_struct_layout_matches_naga() {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let g = lib.genus("takram-default").expect("genus");
    let mut checked = Checked::default();
    for q in Quality::ALL {
        check_module(
            cloud_module(&CloudVariant::new(g, q, q.features()).key).expect("records"),
            &mut checked,
        );
    }
    for v in catalog() {
        check_module(
            nimbus_dsl::ShaderVariant::record(&v).expect("records"),
            &mut checked,
        );
    }
    // Modules outside the catalogue: the uber-shader (its key uniforms) and the formation
    // automaton's kernels.
    for module in [
        cloud_module(&CloudKey::uber()),
        formation_step_module(64),
        formation_weather_module(64, 128, 128),
    ] {
        check_module(module.expect("records"), &mut checked);
    }
    // The uniform blocks a host fills: each must have been compared.
    for name in [
        "CloudUniforms",
        "ResolveParams",
        "DisplayParams",
        "SceneDepthParams",
        "KeyUniforms",
        "FormationParams",
        "PreviewParams",
    ] {
        assert!(
            checked.structs.contains(name),
            "{name} is in no module compared"
        );
    }
    assert!(
        checked.members > 60,
        "only {} members checked",
        checked.members
    );
    println!(
        "{} structs ({}) and {} members checked against naga's layout",
        checked.structs.len(),
        checked
            .structs
            .iter()
            .copied()
            .collect::<Vec<_>>()
            .join(", "),
        checked.members
    );
}

#[test]
fn uniform_bytes_land_at_naga_offsets() {
    let p = PreviewParams {
        resolution: glam::vec2(640.0, 360.0),
        g1: 0.7,
        g2: -0.2,
        lobe_mix: 0.5,
        profile: glam::vec4(1.0, 2.0, 3.0, 4.0),
    };
    let bytes = p.to_uniform_bytes().expect("sized by its layout");
    let g = generate_variant(&catalog()[0], &[nimbus_codegen::Target::Glsl450]).expect("generate");
    let manifest = g
        .files
        .iter()
        .filter_map(|f| f.manifest.clone())
        .find(|m| m.entry_points.values().any(|e| e == "fs_main"))
        .expect("fragment manifest");
    let layout = &manifest.structs[0];
    assert_eq!(bytes.len() as u32, layout.size);
    let read = |field: &str| {
        let off = layout
            .fields
            .iter()
            .find(|f| f.name == field)
            .expect("field")
            .offset as usize;
        f32::from_le_bytes(bytes[off..off + 4].try_into().expect("4 bytes"))
    };
    assert_eq!(read("g1"), 0.7);
    assert_eq!(read("lobe_mix"), 0.5);
    assert_eq!(read("profile"), 1.0);
}
