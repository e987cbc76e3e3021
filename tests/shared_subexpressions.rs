//! The printer binds a value a statement computes more than once to a `let`, and only that:
//! cheap reads stay inline, and values read by two statements are left alone.

mod common;

use common::{MIN_INPUTS, Rng, Tolerance, compare};
use glam::Vec4;
use nimbus_codegen::{Target, generate};
use nimbus_dsl::ir::Type;
use nimbus_dsl::prelude::*;
use nimbus_dsl::{ModuleBuilder, loc};

/// `exp(a) + b` written three times in one statement (twice inside a splat); `b * 2.0` in two
/// statements; `a` (a name) read many times.
#[shader_fn]
fn repeats(a: f32, b: f32) -> Vec4 {
    let v = (Vec4::splat(a.exp() + b) + Vec4::splat(a.exp() + b)) * (a.exp() + b);
    let w = v.x + b * 2.0;
    v * w + b * 2.0
}

fn wgsl() -> String {
    let m = ModuleBuilder::build("share", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), |frag| {
            repeats::shader(frag.x, frag.y)
        });
    })
    .expect("records");
    generate(m, "default", &Target::ALL)
        .expect("every target validates")
        .wgsl
}

fn function<'a>(wgsl: &'a str, name: &str) -> &'a str {
    let start = wgsl.find(&format!("fn {name}(")).expect("function printed");
    let end = wgsl[start..].find("\n}").map_or(wgsl.len(), |e| start + e);
    &wgsl[start..end]
}

#[test]
fn a_value_computed_twice_in_a_statement_is_bound_once() {
    let wgsl = wgsl();
    let body = function(&wgsl, "repeats");
    assert_eq!(body.matches("exp(a)").count(), 1, "exp(a) once:\n{body}");
    assert_eq!(
        body.matches("vec4<f32>(").count(),
        1,
        "the splat once:\n{body}"
    );
    // The value used inside the splat is named once, the splat once: the inner sum is not given
    // a second name of its own.
    assert_eq!(body.matches("let v_part").count(), 2, "{body}");
}

#[test]
fn values_of_two_statements_and_cheap_reads_stay_inline() {
    let wgsl = wgsl();
    let body = function(&wgsl, "repeats");
    assert_eq!(body.matches("b * 2.0").count(), 2, "{body}");
    assert!(
        !body.contains("let w_part") && !body.contains("result_part"),
        "{body}"
    );
}

#[test]
fn the_shared_shader_matches_its_cpu_twin_on_the_gpu() {
    // The rewrite changes where a value is computed, never what: the CPU twin is the reference.
    let mut rng = Rng::new(21);
    let mut inputs = Vec::new();
    while inputs.len() < MIN_INPUTS {
        inputs.push(vec![
            rng.range(-3.0, 3.0).to_bits(),
            rng.range(-3.0, 3.0).to_bits(),
        ]);
    }
    compare(
        "repeats",
        vec![Type::F32, Type::F32],
        repeats::RESULT,
        &repeats::call_ids,
        &inputs,
        |w| {
            let out = repeats(f32::from_bits(w[0]), f32::from_bits(w[1]));
            out.to_array().iter().map(|c| c.to_bits()).collect()
        },
        Tolerance {
            abs: 1e-4,
            rel: 1e-5,
        },
    );
}
