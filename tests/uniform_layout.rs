//! The uniform layout Nimbus computes from the Rust struct definitions matches naga's layout of
//! the generated WGSL, member by member, and the bytes written for a CPU value land there.

use std::path::Path;

use nimbus_clouds::catalog::catalog;
use nimbus_clouds::model::clouds::{CloudVariant, cloud_module};
use nimbus_clouds::model::preview::PreviewParams;
use nimbus_clouds::{CloudLibrary, Quality};
use nimbus_codegen::{generate_variant, print_and_validate};
use nimbus_dsl::layout::{UniformBytes, struct_layout};

fn check_module(module: nimbus_dsl::ir::Module) -> usize {
    let (ir, _, _, validated) = print_and_validate(module, "layout").expect("valid");
    let mut checked = 0;
    for def in &ir.structs {
        let (_, size, offsets) = struct_layout(def);
        let naga_ty = validated
            .module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(def.name))
            .unwrap_or_else(|| panic!("naga has no struct {}", def.name));
        let naga::TypeInner::Struct { members, span } = &naga_ty.1.inner else {
            panic!("{} is not a struct in naga", def.name);
        };
        assert_eq!(*span, size, "size of {}", def.name);
        for ((m, field), off) in members.iter().zip(def.fields).zip(&offsets) {
            assert_eq!(m.offset, *off, "offset of {}.{}", def.name, field.name);
            checked += 1;
        }
    }
    checked
}

#[test]
fn every_struct_offset_matches_naga() {
    let lib =
        CloudLibrary::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")).expect("data");
    let g = lib.genus("takram-default").expect("genus");
    let mut fields = 0;
    for q in Quality::ALL {
        fields += check_module(
            cloud_module(&CloudVariant::new(g, q, q.features()).key).expect("records"),
        );
    }
    for v in catalog() {
        fields += check_module(nimbus_dsl::ShaderVariant::record(&v).expect("records"));
    }
    assert!(fields > 60, "only {fields} members checked");
    println!("{fields} struct members checked against naga's layout");
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
        .find(|m| m.entry_point == "fs_main")
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
