//! The DSL's control flow and types end to end: bounded loops with `break`, `let mut`, compound
//! assignment, `if` as a value with `else if`, early `return`, casts, vectors and matrices. Each
//! function is printed, validated by naga, and run on the GPU against its CPU twin.

mod common;

use common::{MIN_INPUTS, Rng, Tolerance, compare};
use glam::{Mat3, Vec3, Vec4};
use nimbus_codegen::{Target, generate};
use nimbus_dsl::ir::{Scalar, Type};
use nimbus_dsl::prelude::*;
use nimbus_dsl::{ModuleBuilder, loc};

/// Weighted sum along a ray, stopping early once it saturates.
#[shader_fn]
fn march_sum(start: f32, step_len: f32, steps: u32) -> f32 {
    let mut t = start;
    let mut acc = 0.0f32;
    for i in 0u32..steps {
        if acc > 10.0 {
            break;
        }
        let w = if i % 2u32 == 0u32 {
            1.0
        } else if t > 3.0 {
            0.5
        } else {
            0.25
        };
        acc += w * t;
        t += step_len;
    }
    acc
}

/// Lambert-ish shading through a matrix, with an early exit for back faces.
#[shader_fn]
fn shade(n: Vec3, l: Vec3, m: Mat3, k: i32) -> Vec4 {
    let nl = n.normalize().dot(l.normalize());
    if nl < 0.0 {
        return vec4(0.0, 0.0, 0.0, 1.0);
    }
    let r = m * n;
    let c = smoothstep(0.0, 1.0, nl) * (k as f32);
    (r * c).extend(1.0)
}

#[test]
fn loops_branches_and_returns_print_as_structured_wgsl() {
    let m = ModuleBuilder::build("language", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), |frag| {
            let s = march_sum::shader(frag.x, frag.y, 8u32);
            let c = shade::shader(frag.xyz(), frag.xyz(), Mat3::IDENTITY, 2i32);
            c * s
        });
    })
    .expect("records");
    let g = generate(m, "default", &Target::ALL).expect("every target validates");
    for want in [
        "for (var i: u32 = 0u; i < steps; i += 1u) {",
        "break;",
        "if t > 3.0 {",
        "acc = acc + w * t;",
        "return vec4<f32>(0.0, 0.0, 0.0, 1.0);",
        "f32(k)",
        "mat3x3<f32>(",
    ] {
        assert!(g.wgsl.contains(want), "missing `{want}` in:\n{}", g.wgsl);
    }
    assert_eq!(g.stats.loops, 1);
}

#[test]
fn march_sum_matches_cpu() {
    let mut rng = Rng::new(11);
    let mut inputs = vec![
        vec![0.0f32.to_bits(), 0.0f32.to_bits(), 0],
        vec![1.0f32.to_bits(), 5.0f32.to_bits(), 64],
    ];
    while inputs.len() < MIN_INPUTS {
        inputs.push(vec![
            rng.range(-2.0, 4.0).to_bits(),
            rng.range(0.0, 1.0).to_bits(),
            (rng.next_u64() % 40) as u32,
        ]);
    }
    compare(
        "march_sum",
        march_sum::PARAMS.iter().map(|p| p.1).collect(),
        march_sum::RESULT,
        &march_sum::call_ids,
        &inputs,
        |w| vec![march_sum(f32::from_bits(w[0]), f32::from_bits(w[1]), w[2]).to_bits()],
        Tolerance {
            abs: 1e-5,
            rel: 1e-6,
        },
    );
}

#[test]
fn shade_matches_cpu() {
    let mut rng = Rng::new(12);
    let mut inputs = Vec::new();
    while inputs.len() < MIN_INPUTS {
        let mut w = Vec::new();
        // Directions away from zero length, where normalize is defined on both sides.
        for _ in 0..2 {
            let v = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let v = if v.length() < 0.1 { Vec3::X } else { v };
            w.extend(v.to_array().map(f32::to_bits));
        }
        for _ in 0..9 {
            w.push(rng.range(-2.0, 2.0).to_bits());
        }
        w.push(((rng.next_u64() % 7) as i32 - 3) as u32);
        inputs.push(w);
    }
    compare(
        "shade",
        vec![
            Type::Vector(3, Scalar::F32),
            Type::Vector(3, Scalar::F32),
            Type::Matrix(3),
            Type::I32,
        ],
        shade::RESULT,
        &shade::call_ids,
        &inputs,
        |w| {
            let f = |i: usize| f32::from_bits(w[i]);
            let n = Vec3::new(f(0), f(1), f(2));
            let l = Vec3::new(f(3), f(4), f(5));
            let m = Mat3::from_cols_array(&std::array::from_fn(|i| f(6 + i)));
            let out = shade(n, l, m, w[15] as i32);
            out.to_array().iter().map(|c| c.to_bits()).collect()
        },
        Tolerance {
            abs: 1e-5,
            rel: 1e-5,
        },
    );
}

/// Taps of [`blurred`] either side of the centre.
const TAPS: i32 = 2;

/// A small weighted blur of a function of two integers, its loops unrolled.
#[shader_fn]
fn blurred(x: f32, y: f32) -> f32 {
    let mut sum = 0.0f32;
    for dy in unroll(-TAPS..TAPS + 1) {
        for dx in unroll(0u32..3u32) {
            let w = 1.0 / (1.0 + (dy * dy) as f32 + dx as f32);
            sum += w * (x * dx as f32 + y * dy as f32).sin();
        }
    }
    sum
}

/// Unrollable only in name: its bound is a run-time value.
#[shader_fn]
fn unroll_unknown_bound(x: f32, n: u32) -> f32 {
    let mut sum = 0.0f32;
    for i in unroll(0u32..n) {
        sum += x * i as f32;
    }
    sum
}

/// Unrollable only in name: more copies than `unroll` makes.
#[shader_fn]
fn unroll_too_long(x: f32) -> f32 {
    let mut sum = 0.0f32;
    for i in unroll(0u32..17u32) {
        sum += x * i as f32;
    }
    sum
}

/// Unrollable only in name: its body leaves early.
#[shader_fn]
fn unroll_with_break(x: f32) -> f32 {
    let mut sum = 0.0f32;
    for i in unroll(0u32..4u32) {
        if sum > 1.0 {
            break;
        }
        sum += x * i as f32;
    }
    sum
}

#[test]
fn unrolled_loops_print_without_a_loop_and_match_cpu() {
    let m = ModuleBuilder::build("unrolled", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), |frag| {
            frag * blurred::shader(frag.x, frag.y)
        });
    })
    .expect("records");
    let g = generate(m, "default", &Target::ALL).expect("every target validates");
    // Fifteen copies of the body, each with its counters folded in, and no loop left.
    assert_eq!(g.stats.loops, 0, "a loop is left in:\n{}", g.wgsl);
    assert!(!g.wgsl.contains("for ("), "a loop is left in:\n{}", g.wgsl);
    assert_eq!(g.wgsl.matches("sin(").count(), 15, "{}", g.wgsl);
    // The counters are literals in each copy: the last copy reads dy = 2, dx = 2.
    assert!(
        g.wgsl.contains("0.14285715 * sin(x * 2.0 + y * 2.0)"),
        "{}",
        g.wgsl
    );
    let mut rng = Rng::new(14);
    let mut inputs = Vec::new();
    while inputs.len() < MIN_INPUTS {
        inputs.push((0..2).map(|_| rng.range(-3.0, 3.0).to_bits()).collect());
    }
    compare(
        "blurred",
        blurred::PARAMS.iter().map(|p| p.1).collect(),
        blurred::RESULT,
        &blurred::call_ids,
        &inputs,
        |w| vec![blurred(f32::from_bits(w[0]), f32::from_bits(w[1])).to_bits()],
        Tolerance {
            abs: 1e-5,
            rel: 1e-5,
        },
    );
}

#[test]
fn unroll_refuses_a_loop_it_cannot_copy() {
    // On the CPU `unroll` is the range itself: both run as the loops they are.
    assert_eq!(unroll_unknown_bound(1.0, 3), 3.0);
    assert_eq!(unroll_with_break(1.0), 3.0);
    let unknown = ModuleBuilder::build("unroll_unknown", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), |frag| {
            frag * unroll_unknown_bound::shader(frag.x, 3u32)
        });
    });
    let message = format!(
        "{}",
        unknown.expect_err("a run-time bound cannot be unrolled")
    );
    assert!(
        message.contains("unroll") && message.contains("known when the shader is generated"),
        "{message}"
    );
    let leaves = ModuleBuilder::build("unroll_break", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), |frag| {
            frag * unroll_with_break::shader(frag.x)
        });
    });
    let message = format!("{}", leaves.expect_err("an early exit cannot be unrolled"));
    assert!(message.contains("cannot leave early"), "{message}");
    assert_eq!(unroll_too_long(1.0), 136.0);
    let long = ModuleBuilder::build("unroll_long", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), |frag| {
            frag * unroll_too_long::shader(frag.x)
        });
    });
    let message = format!(
        "{}",
        long.expect_err("17 copies are more than unroll makes")
    );
    assert!(
        message.contains("17 iterations") && message.contains("at most 16"),
        "{message}"
    );
}

/// Copies of the first loop in [`unroll_where_known`].
const COPIES: u32 = 3;

/// One loop whose count is known when the shader is generated and one whose count is not: the
/// first unrolled, the second left a loop, neither an error (the key's counts in a specialised
/// shader and in the uber-shader).
#[shader_fn]
fn unroll_where_known(x: f32, n: u32) -> f32 {
    let mut sum = 0.0f32;
    for i in unroll_known(0u32..COPIES) {
        sum += (x * (i + 1u32) as f32).cos();
    }
    for i in unroll_known(0u32..n) {
        sum += (x * i as f32).sin();
    }
    sum
}

#[test]
fn unroll_known_unrolls_known_counts_and_keeps_other_loops() {
    let expected: f32 = (1..=3).map(|i| (0.5 * i as f32).cos()).sum::<f32>()
        + (0..4).map(|i| (0.5 * i as f32).sin()).sum::<f32>();
    assert_eq!(unroll_where_known(0.5, 4), expected);
    let m = ModuleBuilder::build("unroll_known", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), |frag| {
            frag * unroll_where_known::shader(frag.x, 4u32)
        });
    })
    .expect("an unknown count is a loop, not an error");
    let g = generate(m, "default", &Target::ALL).expect("every target validates");
    assert_eq!(g.stats.loops, 1, "{}", g.wgsl);
    assert_eq!(g.wgsl.matches("cos(").count(), 3, "{}", g.wgsl);
    assert_eq!(g.wgsl.matches("sin(").count(), 1, "{}", g.wgsl);
}

/// Shader functions reached through a module path, as a crate organises them.
mod helpers {
    use nimbus_dsl::prelude::*;

    /// Pulls a value towards one.
    #[shader_fn]
    pub fn bias(x: f32, b: f32) -> f32 {
        x / ((1.0 / b - 2.0) * (1.0 - x) + 1.0)
    }
}

/// Calls through every form the macro resolves by declaration, not by spelling: a
/// `#[shader_fn]` by module path, associated functions of glam types and of `f32`, a glam
/// constant, a `std` constant, and a matrix constructor.
#[shader_fn]
fn resolved_calls(v: Vec3, s: f32) -> Vec4 {
    let b = helpers::bias(s.clamp(0.05, 0.95), 0.3);
    let m = Mat3::from_cols(Vec3::X, Vec3::new(0.0, b, 0.0), Vec3::splat(0.5));
    let w = f32::max(v.x, std::f32::consts::PI * s) + f32::min(b, 0.25);
    (m * v + Vec3::ZERO).extend(w)
}

#[test]
fn calls_resolve_by_declaration_and_match_cpu() {
    let m = ModuleBuilder::build("resolved", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), |frag| {
            resolved_calls::shader(frag.xyz(), frag.w)
        });
    })
    .expect("records");
    let g = generate(m, "default", &Target::ALL).expect("every target validates");
    for want in [
        "fn bias(",
        "const PI: f32 = 3.1415927;",
        "PI * s",
        "mat3x3<f32>(",
    ] {
        assert!(g.wgsl.contains(want), "missing `{want}` in:\n{}", g.wgsl);
    }
    let mut rng = Rng::new(13);
    let mut inputs = Vec::new();
    while inputs.len() < MIN_INPUTS {
        inputs.push((0..4).map(|_| rng.range(-2.0, 2.0).to_bits()).collect());
    }
    compare(
        "resolved_calls",
        vec![Type::Vector(3, Scalar::F32), Type::F32],
        resolved_calls::RESULT,
        &resolved_calls::call_ids,
        &inputs,
        |w| {
            let f = |i: usize| f32::from_bits(w[i]);
            let out = resolved_calls(Vec3::new(f(0), f(1), f(2)), f(3));
            out.to_array().iter().map(|c| c.to_bits()).collect()
        },
        Tolerance {
            abs: 1e-5,
            rel: 1e-5,
        },
    );
}

/// Two comparisons as a call's arguments, a `<` before a `>`: what WGSL's template-list rule
/// would read as `x<…, x>`.
#[shader_fn]
fn between(p: Vec4) -> Vec4 {
    let x = p.x;
    let low = p.y;
    let high = p.z;
    let below = p.w > 0.5;
    let outside = select(x < low - 1.0, x > high + 1.0, below);
    Vec4::splat(select(0.0, 1.0, outside))
}

/// The printed WGSL parses: an argument with a `<` of its own before the last is
/// parenthesised, so a later `>` cannot close a template list (the impostor's bake printed
/// `select(elevation < horizon - reach, elevation > horizon + reach, below)`, which naga's
/// parser refused). The last argument and lone comparisons keep their plain spelling.
#[test]
fn comparisons_in_arguments_are_not_template_lists() {
    let m = ModuleBuilder::build("between", "", loc!(), |m| {
        m.fragment("fs_main", "", loc!(), between::shader);
    })
    .expect("records");
    let g = generate(m, "default", &Target::ALL).expect("every target validates");
    assert!(
        g.wgsl
            .contains("select((x < low - 1.0), x > high + 1.0, below)"),
        "{}",
        g.wgsl
    );
    assert!(g.wgsl.contains("select(0.0, 1.0, outside)"), "{}", g.wgsl);
    naga::front::wgsl::parse_str(&g.wgsl).expect("the printed WGSL parses");
    // The CPU twin reads the same: below the band against its lower edge, above it the upper.
    let at = |x: f32, below: f32| between(Vec4::new(x, 2.0, 5.0, below)).x;
    assert_eq!((at(0.5, 0.0), at(1.5, 0.0)), (1.0, 0.0));
    assert_eq!((at(6.5, 1.0), at(5.5, 1.0)), (1.0, 0.0));
}
