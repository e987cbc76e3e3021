//! Snapshot tests: the generated code of the sample module, pinned per target and variant, plus
//! the variant manifest. A change to the model or to codegen shows up here as a reviewable diff
//! (`cargo insta review`); CI runs with `INSTA_UPDATE=no` and fails on any unreviewed change.

mod common;

use nimbus_clouds::catalog::catalog;
use nimbus_codegen::{Contents, Target, generate_variant};

#[test]
fn every_target_of_every_sample_variant_is_pinned() {
    for source in catalog() {
        let g = generate_variant(&source, &Target::ALL).expect("generate");
        insta::assert_snapshot!(format!("{}.wgsl", g.id()), g.wgsl);
        for file in &g.files {
            if file.target == Target::Wgsl {
                continue;
            }
            let text = match &file.contents {
                Contents::Text(t) => t.clone(),
                Contents::SpirV(words) => common::spirv_text(words),
            };
            insta::assert_snapshot!(file.file_name.clone(), text);
            if let Some(m) = &file.manifest {
                insta::assert_snapshot!(format!("{}.json", file.file_name), m.to_json());
            }
        }
    }
}

#[test]
fn variant_manifest_is_pinned() {
    let lines: Vec<String> = catalog()
        .iter()
        .map(|s| {
            let g = generate_variant(s, &Target::ALL).expect("generate");
            g.stats.manifest_line(&g.id())
        })
        .collect();
    insta::assert_snapshot!("variant_manifest", lines.join("\n"));
}

#[test]
fn generation_is_deterministic() {
    for source in catalog() {
        let a = generate_variant(&source, &Target::ALL).expect("first");
        let b = generate_variant(&source, &Target::ALL).expect("second");
        assert_eq!(a.wgsl, b.wgsl, "{}: WGSL differs between runs", a.id());
        assert_eq!(
            a.files,
            b.files,
            "{}: target outputs differ between runs",
            a.id()
        );
    }
}
