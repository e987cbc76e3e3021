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

/// Member offsets of every struct glslang lays out in `spirv`'s disassembly, by struct name:
/// `OpName`, `OpMemberName` and `OpMemberDecorate … Offset` joined on the type's id.
fn spirv_offsets(disassembly: &str) -> Vec<(String, String, u32)> {
    use std::collections::BTreeMap;
    let mut names: BTreeMap<&str, &str> = BTreeMap::new();
    let mut members: BTreeMap<(&str, &str), &str> = BTreeMap::new();
    let mut offsets = Vec::new();
    for line in disassembly.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["OpName", id, name] => {
                names.insert(id, name.trim_matches('"'));
            }
            ["OpMemberName", id, index, name] => {
                members.insert((id, index), name.trim_matches('"'));
            }
            ["OpMemberDecorate", id, index, "Offset", offset] => {
                offsets.push((*id, *index, offset.parse::<u32>().unwrap_or(u32::MAX)));
            }
            _ => {}
        }
    }
    offsets
        .into_iter()
        .filter_map(|(id, index, offset)| {
            let s = names.get(id)?;
            let m = members.get(&(id, index))?;
            Some((s.to_string(), m.to_string(), offset))
        })
        .collect()
}

/// Compiles every entry point of an HLSL file with glslang, HLSL packing rules, and compares
/// each struct member's offset with the one its manifest gives (the WGSL layout the host
/// writes): how many members agreed, or the first that did not.
fn packing_agrees(file: &nimbus_codegen::OutputFile, text: &str) -> Result<usize, String> {
    let manifest = file.manifest.as_ref().ok_or("no manifest")?;
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let hlsl = dir.path().join(&file.file_name);
    std::fs::write(&hlsl, text).map_err(|e| e.to_string())?;
    let mut agreed = 0;
    for (stage, entry) in &manifest.entry_points {
        let stage = match stage.as_str() {
            "vertex" => "vert",
            "fragment" => "frag",
            _ => "comp",
        };
        let spv = dir.path().join(format!("{entry}.spv"));
        let out = std::process::Command::new("glslangValidator")
            .args(["-D", "-V", "--hlsl-offsets", "-S", stage, "-e", entry, "-o"])
            .arg(&spv)
            .arg(&hlsl)
            .output()
            .map_err(|e| e.to_string())?;
        if !out.status.success() {
            return Err(String::from_utf8_lossy(&out.stdout).into_owned());
        }
        let dis = std::process::Command::new("spirv-dis")
            .arg(&spv)
            .output()
            .map_err(|e| e.to_string())?;
        for (s, member, offset) in spirv_offsets(&String::from_utf8_lossy(&dis.stdout)) {
            let Some(want) = manifest
                .structs
                .iter()
                .filter(|m| m.name == s)
                .flat_map(|m| &m.fields)
                .find(|f| f.target_name == member)
            else {
                continue;
            };
            if want.offset != offset {
                return Err(format!(
                    "{}: {s}.{member} at byte {offset} in HLSL, {} in the WGSL layout",
                    file.file_name, want.offset
                ));
            }
            agreed += 1;
        }
    }
    Ok(agreed)
}

#[test]
fn hlsl_cbuffer_packing_puts_every_member_at_its_wgsl_offset() {
    // Every uniform struct of the catalogue (the cloud block with its nested groups, media,
    // march and light blocks; resolve, display, scene depth, previews), laid out by glslang
    // with HLSL's packing rules, against the offsets the uniform files write. The control: the
    // sun-light file without its padding members puts members elsewhere.
    if !common::tool_available("glslangValidator") || !common::tool_available("spirv-dis") {
        assert!(
            !std::env::var("NIMBUS_REQUIRE_TOOLS").is_ok_and(|v| v == "1"),
            "NIMBUS_REQUIRE_TOOLS=1 but glslangValidator or spirv-dis is missing"
        );
        eprintln!("SKIPPED: glslangValidator or spirv-dis is not installed");
        return;
    }
    let mut agreed = 0;
    let mut control = None;
    for source in catalog() {
        let g = generate_variant(&source, &[Target::Hlsl]).expect("generate");
        for f in &g.files {
            let nimbus_codegen::Contents::Text(text) = &f.contents else {
                continue;
            };
            agreed += packing_agrees(f, text).unwrap_or_else(|e| panic!("{e}"));
            if text.contains("float _pad") && control.is_none() {
                let unpadded: String = text
                    .lines()
                    .filter(|l| !l.trim_start().starts_with("float _pad"))
                    .map(|l| format!("{l}\n"))
                    .collect();
                control = Some(packing_agrees(f, &unpadded));
            }
        }
    }
    assert!(agreed > 100, "only {agreed} members compared");
    match control {
        Some(Err(why)) => println!("control: {why}"),
        other => panic!("the comparison cannot fail: {other:?}"),
    }
    println!("{agreed} struct members at their WGSL offsets under HLSL packing");
}
