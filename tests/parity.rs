//! CPU/GPU parity: every `#[shader_fn]` of the sample module runs on the CPU (its Rust twin)
//! and on the GPU (the generated WGSL, in a wgpu compute pass; lavapipe where there is no GPU)
//! over at least 10,000 inputs including extremes. The largest difference is printed and
//! asserted within the stated tolerance.

mod common;

use common::{MIN_INPUTS, Rng, Tolerance, compare, linspace};
use nimbus_clouds::model::phase::{dual_lobe_hg, henyey_greenstein};
use nimbus_clouds::model::preview::{
    PhaseModel, PreviewParams, PreviewParamsShader, fullscreen_position, preview_color,
    preview_fragment, preview_phase,
};
use nimbus_clouds::model::profile::density_profile;
use nimbus_dsl::Value;
use nimbus_dsl::ir::{ExprId, Type};
use nimbus_dsl::shader;

fn f(v: f32) -> u32 {
    v.to_bits()
}

fn out_f(v: f32) -> Vec<u32> {
    vec![v.to_bits()]
}

fn out_v4(v: glam::Vec4) -> Vec<u32> {
    v.to_array().iter().map(|c| c.to_bits()).collect()
}

fn arg(w: &[u32], i: usize) -> f32 {
    f32::from_bits(w[i])
}

/// Cosines including both ends, zero and the values next to ±1, and random ones.
fn cosines(rng: &mut Rng, n: usize) -> Vec<f32> {
    let mut v = vec![-1.0, -0.999_999_9, 0.0, 0.999_999_9, 1.0];
    v.extend(linspace(-1.0, 1.0, n.saturating_sub(5 + n / 2)));
    while v.len() < n {
        v.push(rng.range(-1.0, 1.0));
    }
    v
}

#[test]
fn henyey_greenstein_matches_cpu() {
    let mut rng = Rng::new(1);
    let mus = cosines(&mut rng, 101);
    let mut gs = linspace(-0.99, 0.99, 99);
    gs.extend([-0.999, 0.999]);
    let inputs: Vec<Vec<u32>> = mus
        .iter()
        .flat_map(|mu| gs.iter().map(move |g| vec![f(*mu), f(*g)]))
        .collect();
    compare(
        "henyey_greenstein",
        henyey_greenstein::PARAMS.iter().map(|p| p.1).collect(),
        henyey_greenstein::RESULT,
        &henyey_greenstein::call_ids,
        &inputs,
        |w| out_f(henyey_greenstein(arg(w, 0), arg(w, 1))),
        Tolerance {
            abs: 1e-7,
            rel: 2e-6,
        },
    );
}

#[test]
fn dual_lobe_hg_matches_cpu() {
    let mut rng = Rng::new(2);
    let mut inputs = Vec::new();
    for mu in [-1.0, 0.0, 1.0] {
        for w in [0.0, 0.5, 1.0] {
            inputs.push(vec![f(mu), f(0.99), f(-0.99), f(w)]);
        }
    }
    while inputs.len() < MIN_INPUTS {
        inputs.push(vec![
            f(rng.range(-1.0, 1.0)),
            f(rng.range(-0.99, 0.99)),
            f(rng.range(-0.99, 0.99)),
            f(rng.range(0.0, 1.0)),
        ]);
    }
    compare(
        "dual_lobe_hg",
        dual_lobe_hg::PARAMS.iter().map(|p| p.1).collect(),
        dual_lobe_hg::RESULT,
        &dual_lobe_hg::call_ids,
        &inputs,
        |w| out_f(dual_lobe_hg(arg(w, 0), arg(w, 1), arg(w, 2), arg(w, 3))),
        Tolerance {
            abs: 1e-7,
            rel: 4e-6,
        },
    );
}

#[test]
fn density_profile_matches_cpu() {
    let mut rng = Rng::new(3);
    let mut inputs = Vec::new();
    // Extremes: a = 0 with a huge b (the 0·∞ case), b near exp's overflow, η at both ends.
    for a in [0.0, 1e-30, 1.0, 1e30] {
        for b in [-1e3, -100.0, 0.0, 10.0, 80.0] {
            for eta in [0.0, 0.5, 1.0] {
                inputs.push(vec![f(eta), f(a), f(b), f(0.75), f(0.25)]);
            }
        }
    }
    while inputs.len() < MIN_INPUTS {
        inputs.push(vec![
            f(rng.range(0.0, 1.0)),
            f(rng.range(-2.0, 2.0)),
            f(rng.range(-10.0, 10.0)),
            f(rng.range(-1.0, 1.0)),
            f(rng.range(-1.0, 1.0)),
        ]);
    }
    compare(
        "density_profile",
        density_profile::PARAMS.iter().map(|p| p.1).collect(),
        density_profile::RESULT,
        &density_profile::call_ids,
        &inputs,
        |w| {
            out_f(density_profile(
                arg(w, 0),
                arg(w, 1),
                arg(w, 2),
                arg(w, 3),
                arg(w, 4),
            ))
        },
        // exp() on GPUs is allowed a few ulp more than libm's.
        Tolerance {
            abs: 1e-6,
            rel: 1e-5,
        },
    );
}

#[test]
fn fullscreen_position_matches_cpu_exactly() {
    let inputs: Vec<Vec<u32>> = (0..MIN_INPUTS as u32)
        .chain([u32::MAX - 1, u32::MAX])
        .map(|i| vec![i])
        .collect();
    compare(
        "fullscreen_position",
        fullscreen_position::PARAMS.iter().map(|p| p.1).collect(),
        fullscreen_position::RESULT,
        &fullscreen_position::call_ids,
        &inputs,
        |w| out_v4(fullscreen_position(w[0])),
        Tolerance { abs: 0.0, rel: 0.0 },
    );
}

fn params_words(p: &PreviewParams) -> Vec<u32> {
    let mut w = vec![
        f(p.resolution.x),
        f(p.resolution.y),
        f(p.g1),
        f(p.g2),
        f(p.lobe_mix),
    ];
    w.extend(p.profile.to_array().map(f));
    w
}

fn params_from(w: &[u32]) -> PreviewParams {
    PreviewParams {
        resolution: glam::vec2(arg(w, 0), arg(w, 1)),
        g1: arg(w, 2),
        g2: arg(w, 3),
        lobe_mix: arg(w, 4),
        profile: glam::vec4(arg(w, 5), arg(w, 6), arg(w, 7), arg(w, 8)),
    }
}

fn random_params(rng: &mut Rng) -> PreviewParams {
    PreviewParams {
        resolution: glam::vec2(rng.range(1.0, 4096.0), rng.range(1.0, 4096.0)),
        g1: rng.range(-0.95, 0.95),
        g2: rng.range(-0.95, 0.95),
        lobe_mix: rng.range(0.0, 1.0),
        profile: glam::vec4(
            rng.range(0.0, 1.0),
            rng.range(-4.0, 4.0),
            rng.range(-1.0, 1.0),
            rng.range(0.0, 1.0),
        ),
    }
}

const PARAMS_TYPE: Type = <PreviewParamsShader as Value>::TYPE;

#[test]
fn preview_phase_matches_cpu_for_every_model() {
    for model in PhaseModel::ALL {
        let mut rng = Rng::new(4);
        let mut inputs = Vec::new();
        while inputs.len() < MIN_INPUTS {
            let mut w = vec![f(rng.range(-1.0, 1.0))];
            w.extend(params_words(&random_params(&mut rng)));
            inputs.push(w);
        }
        inputs[0][0] = f(1.0);
        inputs[1][0] = f(-1.0);
        let call = move |a: &[ExprId]| {
            preview_phase::shader(
                shader::F32::from_id(a[0]),
                PreviewParamsShader::from_id(a[1]),
                model,
            )
            .id()
        };
        compare(
            &format!("preview_phase[{model:?}]"),
            vec![Type::F32, PARAMS_TYPE],
            Type::F32,
            &call,
            &inputs,
            |w| out_f(preview_phase(arg(w, 0), params_from(&w[1..]), model)),
            Tolerance {
                abs: 1e-7,
                rel: 4e-6,
            },
        );
    }
}

#[test]
fn preview_color_and_fragment_match_cpu_for_every_model() {
    for model in PhaseModel::ALL {
        let mut rng = Rng::new(5);
        let mut inputs = Vec::new();
        for (x, y) in [(0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0), (0.5, 0.5)] {
            let mut w = vec![f(x), f(y)];
            w.extend(params_words(&PreviewParams::default()));
            inputs.push(w);
        }
        while inputs.len() < MIN_INPUTS {
            let mut w = vec![f(rng.range(0.0, 1.0)), f(rng.range(0.0, 1.0))];
            w.extend(params_words(&random_params(&mut rng)));
            inputs.push(w);
        }
        let call = move |a: &[ExprId]| {
            preview_color::shader(
                shader::Vec2::from_id(a[0]),
                PreviewParamsShader::from_id(a[1]),
                model,
            )
            .id()
        };
        // cos and log2 are approximations on GPUs; colours are in [0, 1].
        compare(
            &format!("preview_color[{model:?}]"),
            vec![Type::Vector(2, nimbus_dsl::ir::Scalar::F32), PARAMS_TYPE],
            Type::Vector(4, nimbus_dsl::ir::Scalar::F32),
            &call,
            &inputs,
            |w| {
                out_v4(preview_color(
                    glam::vec2(arg(w, 0), arg(w, 1)),
                    params_from(&w[2..]),
                    model,
                ))
            },
            Tolerance {
                abs: 2e-5,
                rel: 0.0,
            },
        );

        let frag_inputs: Vec<Vec<u32>> = inputs
            .iter()
            .map(|w| {
                let p = params_from(&w[2..]);
                let mut v = vec![
                    f(arg(w, 0) * p.resolution.x),
                    f(arg(w, 1) * p.resolution.y),
                    f(0.5),
                    f(1.0),
                ];
                v.extend(&w[2..]);
                v.push(f(1.25));
                v
            })
            .collect();
        let call = move |a: &[ExprId]| {
            preview_fragment::shader(
                shader::Vec4::from_id(a[0]),
                PreviewParamsShader::from_id(a[1]),
                shader::F32::from_id(a[2]),
                model,
            )
            .id()
        };
        compare(
            &format!("preview_fragment[{model:?}]"),
            vec![
                Type::Vector(4, nimbus_dsl::ir::Scalar::F32),
                PARAMS_TYPE,
                Type::F32,
            ],
            Type::Vector(4, nimbus_dsl::ir::Scalar::F32),
            &call,
            &frag_inputs,
            |w| {
                let frag = glam::vec4(arg(w, 0), arg(w, 1), arg(w, 2), arg(w, 3));
                out_v4(preview_fragment(
                    frag,
                    params_from(&w[4..13]),
                    arg(w, 13),
                    model,
                ))
            },
            Tolerance {
                abs: 3e-5,
                rel: 0.0,
            },
        );
    }
}
