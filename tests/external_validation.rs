//! Every emitted GLSL file passes glslangValidator, every HLSL file its HLSL front end
//! (compiled to SPIR-V for its stage and entry point), and every SPIR-V file passes spirv-val
//! (naga lets a few GLSL ES 3.00 built-ins through that WebGL2 rejects, so naga alone is not
//! enough). When a tool is not installed the check is skipped with the reason printed; with
//! `NIMBUS_REQUIRE_TOOLS=1` (set by .ci/run) a missing tool fails instead.

mod common;

use nimbus_clouds::catalog::catalog;
use nimbus_codegen::external::{ExternalCheck, check_file};
use nimbus_codegen::{Target, generate_variant};

fn check(targets: &[Target], tool: &str) {
    if !common::tool_available(tool) {
        if std::env::var("NIMBUS_REQUIRE_TOOLS").is_ok_and(|v| v == "1") {
            panic!("NIMBUS_REQUIRE_TOOLS=1 but {tool} is not installed");
        }
        eprintln!("SKIPPED: {tool} is not installed (apt-get install glslang-tools spirv-tools)");
        return;
    }
    let mut checked = 0;
    for source in catalog() {
        let g = generate_variant(&source, targets).expect("generate");
        for f in &g.files {
            match check_file(f) {
                ExternalCheck::Passed { .. } => checked += 1,
                other => panic!("{}: {other:?}", f.file_name),
            }
        }
    }
    assert!(checked > 0, "no {tool} checks ran");
    println!("{tool}: {checked} files passed");
}

#[test]
fn glsl_passes_glslang_validator() {
    check(&[Target::GlslEs300, Target::Glsl450], "glslangValidator");
}

#[test]
fn hlsl_passes_glslang_validators_hlsl_front_end() {
    check(&[Target::Hlsl], "glslangValidator");
}

#[test]
fn the_hlsl_check_rejects_hlsl_that_does_not_compile() {
    // The check must be able to fail: an undeclared identifier, and an entry point the file
    // does not have.
    if !common::tool_available("glslangValidator") {
        eprintln!("SKIPPED: glslangValidator is not installed");
        return;
    }
    let file = |text: &str, entry: &str| nimbus_codegen::OutputFile {
        file_name: "bad.hlsl".into(),
        target: Target::Hlsl,
        entry_point: Some((entry.into(), nimbus_dsl::ir::Stage::Fragment)),
        contents: nimbus_codegen::Contents::Text(text.into()),
        manifest: None,
    };
    let good = "float4 fs_main() : SV_Target0 { return float4(1.0, 0.0, 0.0, 1.0); }\n";
    assert!(matches!(
        check_file(&file(good, "fs_main")),
        ExternalCheck::Passed { .. }
    ));
    let undeclared = "float4 fs_main() : SV_Target0 { return float4(missing, 0.0, 0.0, 1.0); }\n";
    assert!(matches!(
        check_file(&file(undeclared, "fs_main")),
        ExternalCheck::Failed { .. }
    ));
    assert!(matches!(
        check_file(&file(good, "fs_other")),
        ExternalCheck::Failed { .. }
    ));
}

#[test]
fn spirv_passes_spirv_val() {
    check(&[Target::SpirV], "spirv-val");
}

#[test]
fn glslang_validator_rejects_what_webgl2_rejects() {
    // The check must be able to fail: a GLSL ES 3.00 shader using an ES 3.10 built-in.
    if !common::tool_available("glslangValidator") {
        eprintln!("SKIPPED: glslangValidator is not installed");
        return;
    }
    let bad = nimbus_codegen::OutputFile {
        file_name: "bad.es300.frag".into(),
        target: Target::GlslEs300,
        entry_point: None,
        contents: nimbus_codegen::Contents::Text(
            "#version 300 es\nprecision highp float;\nout vec4 c;\nvoid main() { c = vec4(float(bitCount(3u))); }\n".into(),
        ),
        manifest: None,
    };
    assert!(matches!(check_file(&bad), ExternalCheck::Failed { .. }));
}
