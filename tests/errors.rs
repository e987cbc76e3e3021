//! Bad input gets a typed error naming what is wrong and where, with no panic and no partial
//! output folder left looking complete.

use nimbus_clouds::catalog::catalog;
use nimbus_codegen::{
    CodegenError, EmitExtras, MARKER_FILE, Target, emit, generate, generate_variant,
};
use nimbus_dsl::cpu::{Sampler, Texture3d};
use nimbus_dsl::prelude::*;
use nimbus_dsl::shader;
use nimbus_dsl::{ModuleBuilder, loc};
use nimbus_output::{OutputError, Overwrite};

#[test]
fn unknown_target_is_named_with_the_known_ones() {
    let err = Target::parse_list("wgsl,dx9").expect_err("dx9 is not a target");
    assert!(matches!(&err, CodegenError::UnknownTarget { given, .. } if given == "dx9"));
    let msg = err.to_string();
    assert!(
        msg.contains("`dx9`") && msg.contains("glsl-es300") && msg.contains("spirv"),
        "{msg}"
    );
}

/// Valid Rust, invalid WGSL: shader functions cannot recurse.
#[shader_fn]
fn countdown(x: f32) -> f32 {
    if x > 1.0 {
        return countdown(x - 1.0);
    }
    x
}

#[test]
fn a_dsl_function_naga_rejects_is_reported_at_its_rust_line() {
    assert_eq!(countdown(3.5), 0.5, "the CPU twin still works");
    let module = ModuleBuilder::build("recursion", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), |frag| {
            let v = countdown::shader(frag.x);
            shader::vec4(v, v, v, 1.0)
        });
    })
    .expect("records");
    let err = generate(module, "default", &[Target::Wgsl]).expect_err("naga must reject recursion");
    let CodegenError::Parse {
        module,
        origin: Some(origin),
        ..
    } = &err
    else {
        panic!("expected a parse error with an origin, got {err:?}");
    };
    assert_eq!(module, "recursion");
    assert_eq!(origin.function, "countdown");
    assert!(
        origin.loc.file.ends_with("tests/errors.rs"),
        "{}",
        origin.loc
    );
    // The `return countdown(x - 1.0);` line of this file.
    let line = include_str!("errors.rs")
        .lines()
        .position(|l| l.contains("return countdown(x - 1.0);"))
        .expect("line present") as u32
        + 1;
    assert_eq!(origin.loc.line, line, "{err}");
    let msg = err.to_string();
    assert!(
        msg.contains("countdown") && msg.contains("tests/errors.rs"),
        "{msg}"
    );
    println!("{msg}");
    assert!(
        !msg.contains("Expression ["),
        "IR terms leaked into the message: {msg}"
    );
}

/// `textureSample` needs derivatives, which only fragment shaders have.
#[shader_fn]
fn implicit_sample(tex: &Texture3d, smp: &Sampler, p: Vec3) -> f32 {
    tex.sample(smp, p).x
}

#[test]
fn a_stage_violation_without_a_naga_span_still_names_the_function() {
    let cpu_tex = Texture3d {
        size: [1, 1, 1],
        texels: vec![glam::Vec4::splat(0.25)],
    };
    assert_eq!(
        implicit_sample(&cpu_tex, &Sampler::default(), Vec3::splat(0.5)),
        0.25
    );
    let module = ModuleBuilder::build("bad_stage", "", loc!(), |m| {
        let tex = m.handle::<Texture3d>("shape", 0, 0, "");
        let smp = m.handle::<Sampler>("shape_sampler", 0, 1, "");
        let out = m.storage::<shader::F32>("out", 0, 2, true, "");
        m.compute("main_cs", "", loc!(), [1, 1, 1], |gid| {
            let v = implicit_sample::shader(tex.get(), smp.get(), shader::Vec3::splat(0.5));
            out.array().set(gid.x, v);
        });
    })
    .expect("records");
    // Every target at once takes the parallel path (the lowering beside the print): the
    // refusal is located the same way.
    let every = generate(module.clone(), "default", &Target::ALL).expect_err("naga must reject it");
    let err = generate(module, "default", &[Target::Wgsl]).expect_err("naga must reject it");
    assert_eq!(every.to_string(), err.to_string());
    let CodegenError::Validation {
        origin: Some(origin),
        message,
        ..
    } = &err
    else {
        panic!("expected a validation error with an origin, got {err:?}");
    };
    assert_eq!(origin.function, "main_cs", "{err}");
    assert!(
        message.to_lowercase().contains("stage") || message.contains("forbidden"),
        "{message}"
    );
}

#[test]
fn conflicting_bindings_are_refused_by_the_builder() {
    let err = ModuleBuilder::build("clash", "", loc!(), |m| {
        let _ = m.handle::<Texture3d>("a", 0, 0, "");
        let _ = m.handle::<Sampler>("b", 0, 0, "");
    })
    .expect_err("same binding twice");
    assert!(err.to_string().contains("@group(0) @binding(0)"), "{err}");
}

#[test]
fn an_unwritable_output_folder_is_named_and_leaves_nothing_behind() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let blocker = tmp.path().join("a-file");
    std::fs::write(&blocker, "not a folder").expect("write");
    let target = blocker.join("out");
    let g = generate_variant(&catalog()[0], &[Target::Wgsl]).expect("generate");
    let err = emit(&[g], &EmitExtras::default(), &target, Overwrite::OwnOnly)
        .expect_err("cannot write under a file");
    assert!(
        matches!(
            err,
            CodegenError::Destination(OutputError::NotAFolder { .. })
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("a-file"), "{err}");
    let left: Vec<_> = std::fs::read_dir(tmp.path()).expect("read").collect();
    assert_eq!(left.len(), 1, "only the blocking file remains");
}

#[test]
fn a_foreign_folder_is_not_replaced() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let precious = tmp.path().join("notes.txt");
    std::fs::write(&precious, "mine").expect("write");
    let g = generate_variant(&catalog()[0], &[Target::Wgsl]).expect("generate");
    let err =
        emit(&[g], &EmitExtras::default(), tmp.path(), Overwrite::OwnOnly).expect_err("refuses");
    assert!(
        matches!(err, CodegenError::Destination(OutputError::NotOurs { .. })),
        "{err:?}"
    );
    assert_eq!(
        std::fs::read_to_string(&precious).expect("still there"),
        "mine"
    );
}

#[test]
fn a_previous_output_is_replaced_whole() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("shaders");
    let all = generate_variant(&catalog()[0], &Target::ALL).expect("generate");
    let first = emit(&[all], &EmitExtras::default(), &out, Overwrite::OwnOnly).expect("first emit");
    assert!(first.files.len() > 2);
    let wgsl_only = generate_variant(&catalog()[0], &[Target::Wgsl]).expect("generate");
    emit(
        &[wgsl_only],
        &EmitExtras::default(),
        &out,
        Overwrite::OwnOnly,
    )
    .expect("second emit");
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .expect("read")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        vec![
            MARKER_FILE.to_string(),
            nimbus_output::OWNERSHIP_FILE.to_string(),
            "preview-hg.wgsl".to_string()
        ]
    );
    let leftovers = std::fs::read_dir(tmp.path()).expect("read").count();
    assert_eq!(leftovers, 1, "no temporary folder left beside the output");
}

/// A generation-time value whose suffix cannot tell two values apart.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Gain(u32);

impl nimbus_dsl::SpecValue for Gain {
    fn suffix(&self) -> String {
        String::new()
    }

    fn label(&self) -> String {
        format!("gain {}", self.0)
    }
}

/// Scales by a generation-time gain.
#[nimbus_dsl::shader_fn]
fn scaled(x: f32, #[spec] gain: Gain) -> f32 {
    x * gain.0 as f32
}

#[test]
fn a_specialisation_key_clash_is_a_typed_error() {
    assert_eq!(scaled(2.0, Gain(3)), 6.0);
    let err = nimbus_dsl::ModuleBuilder::build(
        "clash",
        "Two gains, one name.",
        nimbus_dsl::loc!(),
        |m| {
            m.fragment("fs_main", "Both gains.", nimbus_dsl::loc!(), |p| {
                let a = scaled::shader(p.x, Gain(1));
                let b = scaled::shader(p.y, Gain(2));
                nimbus_dsl::shader::vec4(a, b, 0.0, 1.0)
            });
        },
    )
    .expect_err("two values under one name");
    match &err {
        nimbus_dsl::DslError::SpecialisationClash {
            function,
            first,
            second,
            ..
        } => {
            assert_eq!(function, "scaled");
            assert!(
                first.contains("gain 1") && second.contains("gain 2"),
                "{err}"
            );
        }
        other => panic!("expected a clash, got {other:?}"),
    }
}
