//! Rust names reach the WGSL as written unless WGSL forbids them (naga's keyword lists): a
//! reserved word is renamed, a built-in's name stays for a local that does not call it, and is
//! renamed where the same function calls the built-in it would shadow. naga validates each.

use nimbus_codegen::{Target, generate};
use nimbus_dsl::prelude::*;
use nimbus_dsl::{ModuleBuilder, loc};

/// `step` and `distance` as locals, neither built-in called: both names stay.
#[shader_fn]
fn keeps_builtin_names(x: f32) -> f32 {
    let step = x * 0.5;
    let distance = step + 1.0;
    distance * step
}

/// A local `length` in a function that calls the built-in `length`: the local is renamed.
#[shader_fn]
fn shadows_a_called_builtin(v: Vec3) -> f32 {
    let length = v.x * 0.5;
    length + v.length()
}

/// `active` and `target` are WGSL reserved words.
#[shader_fn]
fn reserved_words(active: f32) -> f32 {
    let target = active + 1.0;
    target * 2.0
}

/// Calls all three.
#[shader_fn]
fn names_fragment(p: Vec4) -> Vec4 {
    let a = keeps_builtin_names(p.x);
    let b = shadows_a_called_builtin(p.xyz());
    let c = reserved_words(p.z);
    vec4(a, b, c, 1.0)
}

fn wgsl() -> String {
    let module = ModuleBuilder::build("names", "WGSL naming rules.", loc!(), |m| {
        m.fragment("fs_main", "Uses all three.", loc!(), |p| {
            names_fragment::shader(p)
        });
    })
    .expect("records");
    generate(module, "default", &Target::ALL)
        .expect("naga validates every target")
        .wgsl
}

#[test]
fn only_what_wgsl_forbids_is_renamed() {
    let w = wgsl();
    assert!(w.contains("let step = x * 0.5;"), "{w}");
    assert!(w.contains("let distance = step + 1.0;"), "{w}");
    assert!(w.contains("let length_ = v.x * 0.5;"), "{w}");
    assert!(w.contains("return length_ + length(v);"), "{w}");
    assert!(w.contains("fn reserved_words(active_: f32)"), "{w}");
    assert!(w.contains("let target_ = active_ + 1.0;"), "{w}");
    // The CPU twins are the functions as written.
    assert_eq!(keeps_builtin_names(2.0), 2.0 * 1.0);
    assert_eq!(
        shadows_a_called_builtin(Vec3::new(2.0, 0.0, 0.0)),
        1.0 + 2.0
    );
    assert_eq!(reserved_words(1.0), 4.0);
    let px = names_fragment(Vec4::new(2.0, 0.0, 1.0, 0.0));
    assert_eq!((px.x, px.z), (2.0, 4.0));
}

/// Gain of [`with_constants`], a named constant in the shader.
const GAIN: f32 = 2.5;
/// Decided while the shader is generated: a `bool` constant stays a Rust value.
const DOUBLE: bool = false;
/// Loop count, a named `u32` constant.
const TAPS: u32 = 3;

/// Reads three constants.
#[shader_fn]
fn with_constants(x: f32) -> f32 {
    let mut acc = 0.0f32;
    for _i in 0u32..TAPS {
        acc += x * GAIN;
    }
    if DOUBLE { acc * 2.0 } else { acc }
}

mod other {
    /// Same name, another value.
    pub const GAIN: f32 = 4.0;

    /// Reads its own `GAIN`.
    #[nimbus_dsl::shader_fn]
    pub fn other_gain(x: f32) -> f32 {
        x * GAIN
    }
}

#[test]
fn constants_print_by_name_and_two_values_under_one_name_are_an_error() {
    assert_eq!(with_constants(2.0), 15.0);
    let module = ModuleBuilder::build("constants", "Named constants.", loc!(), |m| {
        m.fragment("fs_main", "One constant-reading function.", loc!(), |p| {
            nimbus_dsl::shader::vec4(with_constants::shader(p.x), 0.0, 0.0, 1.0)
        });
    })
    .expect("records");
    let w = generate(module, "default", &Target::ALL)
        .expect("valid everywhere")
        .wgsl;
    assert!(w.contains("const GAIN: f32 = 2.5;"), "{w}");
    assert!(w.contains("const TAPS: u32 = 3u;"), "{w}");
    assert!(w.contains("x * GAIN"), "{w}");
    assert!(w.contains("< TAPS;"), "{w}");
    assert!(
        !w.contains("DOUBLE") && !w.contains("if "),
        "decided at generation time:\n{w}"
    );

    assert_eq!(other::other_gain(1.0), 4.0);
    let err = ModuleBuilder::build("clash", "Two GAINs.", loc!(), |m| {
        m.fragment("fs_main", "Both.", loc!(), |p| {
            let a = with_constants::shader(p.x);
            let b = other::other_gain::shader(p.y);
            nimbus_dsl::shader::vec4(a, b, 0.0, 1.0)
        });
    })
    .expect_err("two values named GAIN");
    assert!(err.to_string().contains("constant `GAIN`"), "{err}");
}
