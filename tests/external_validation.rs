//! Every emitted GLSL file passes glslangValidator, every HLSL file two HLSL front ends
//! (glslang's, compiled to SPIR-V for each stage and entry point, and Slang's, the file as one
//! program), and every SPIR-V file passes spirv-val
//! (naga lets a few GLSL ES 3.00 built-ins through that WebGL2 rejects, so naga alone is not
//! enough). When a tool is not installed the check is skipped with the reason printed; with
//! `NIMBUS_REQUIRE_TOOLS=1` (set by .ci/run) a missing tool fails instead.

mod common;

use nimbus_clouds::catalog::catalog;
use nimbus_codegen::external::{ExternalCheck, check_file, check_files};
use nimbus_codegen::{Target, generate_variant};

fn check(targets: &[Target], tool: &str) {
    let available = if tool == "Slang" {
        common::tool_available("glslangValidator") && common::slang_available()
    } else {
        common::tool_available(tool)
    };
    if !available {
        if std::env::var("NIMBUS_REQUIRE_TOOLS").is_ok_and(|v| v == "1") {
            panic!("NIMBUS_REQUIRE_TOOLS=1 but {tool} is not installed");
        }
        eprintln!(
            "SKIPPED: {tool} is not installed (apt-get install glslang-tools spirv-tools; \
             python3 -m pip install slangpy)"
        );
        return;
    }
    let generated: Vec<_> = catalog()
        .iter()
        .map(|source| generate_variant(source, targets).expect("generate"))
        .collect();
    let files: Vec<_> = generated.iter().flat_map(|g| &g.files).collect();
    let mut checked = 0;
    for (f, outcome) in files.iter().zip(check_files(&files)) {
        match outcome {
            ExternalCheck::Passed { .. } => checked += 1,
            other => panic!("{}: {other:?}", f.file_name),
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
fn hlsl_passes_glslang_and_slang() {
    check(&[Target::Hlsl], "Slang");
}

#[test]
fn the_hlsl_check_rejects_hlsl_that_does_not_compile() {
    // The check must be able to fail, in each front end: an undeclared identifier, an entry
    // point the file does not have (glslang only warns of it), and an entry point without the
    // attribute Slang finds entry points by (glslang takes that file).
    let require = std::env::var("NIMBUS_REQUIRE_TOOLS").is_ok_and(|v| v == "1");
    if !common::tool_available("glslangValidator") || !common::slang_available() {
        assert!(
            !require,
            "NIMBUS_REQUIRE_TOOLS=1 but glslangValidator or Slang is missing"
        );
        eprintln!("SKIPPED: glslangValidator or Slang (slangpy) is not installed");
        return;
    }
    let file = |text: &str, entry: &str| nimbus_codegen::OutputFile {
        file_name: "bad.hlsl".into(),
        target: Target::Hlsl,
        entry_point: None,
        contents: nimbus_codegen::Contents::Text(text.into()),
        manifest: Some(nimbus_codegen::manifest::BindingManifest {
            module: "bad".into(),
            variant: "x".into(),
            target: "hlsl".into(),
            entry_points: [("fragment".to_string(), entry.to_string())].into(),
            bindings: Vec::new(),
            combined_samplers: Vec::new(),
            buffer_sizes: None,
            structs: Vec::new(),
            overrides: Vec::new(),
        }),
    };
    let attribute = "#ifdef __SLANG__\n[shader(\"fragment\")]\n#endif\n";
    let good = format!(
        "{attribute}float4 fs_main() : SV_Target0 {{ return float4(1.0, 0.0, 0.0, 1.0); }}\n"
    );
    let outcome = |text: &str, entry: &str| check_file(&file(text, entry));
    assert!(matches!(
        outcome(&good, "fs_main"),
        ExternalCheck::Passed { .. }
    ));
    let undeclared = good.replace("float4(1.0,", "float4(missing,");
    assert!(matches!(
        outcome(&undeclared, "fs_main"),
        ExternalCheck::Failed { .. }
    ));
    assert!(matches!(
        outcome(&good, "fs_other"),
        ExternalCheck::Failed { .. }
    ));
    let unmarked = good.replace(attribute, "");
    match outcome(&unmarked, "fs_main") {
        ExternalCheck::Failed { tool, .. } => assert!(tool.starts_with("Slang"), "{tool}"),
        other => panic!("Slang took an entry point without its attribute: {other:?}"),
    }
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
