//! CPU/GPU parity of the cloud model's functions (issue 3): shell intersection, phase
//! functions and the density stages, each over ≥ 10,000 inputs including extremes.

mod common;

use common::{MIN_INPUTS, Rng, Tolerance, compare};
use glam::Vec4;
use nimbus_clouds::model::density::{
    coverage_remap, detail_erosion, height_fraction, shape_altering, shape_erosion,
};
use nimbus_clouds::model::genus_fns::exponential_profile;
use nimbus_clouds::model::layers::{LayerGroup, LayerGroupShader};
use nimbus_clouds::model::phase::{approximate_mie, draine_phase, isotropic_phase, rayleigh_phase};
use nimbus_clouds::model::shell::{EARTH_RADIUS, ray_shell};
use nimbus_dsl::Value;
use nimbus_dsl::ir::{ExprId, Scalar, Type};

fn f(v: f32) -> u32 {
    v.to_bits()
}
fn a(w: &[u32], i: usize) -> f32 {
    f32::from_bits(w[i])
}
fn v4(w: &[u32], i: usize) -> Vec4 {
    Vec4::new(a(w, i), a(w, i + 1), a(w, i + 2), a(w, i + 3))
}
fn out4(v: Vec4) -> Vec<u32> {
    v.to_array().map(f32::to_bits).to_vec()
}
const VEC4: Type = Type::Vector(4, Scalar::F32);

#[test]
fn ray_shell_matches_cpu() {
    let mut rng = Rng::new(21);
    let mut inputs = Vec::new();
    // Extremes: ground level, exactly horizontal and vertical rays, in orbit, shells below.
    for hc in [0.0, 2.0, 1000.0, 10_000.0, 400_000.0] {
        for mu in [-1.0, -0.01, 0.0, 1e-4, 0.5, 1.0] {
            for hs in [0.0, 750.0, 8000.0] {
                inputs.push(vec![f(hc), f(mu), f(hs), f(EARTH_RADIUS)]);
            }
        }
    }
    while inputs.len() < MIN_INPUTS {
        inputs.push(vec![
            f(rng.range(0.0, 20_000.0)),
            f(rng.range(-1.0, 1.0)),
            f(rng.range(0.0, 20_000.0)),
            f(EARTH_RADIUS),
        ]);
    }
    compare(
        "ray_shell",
        ray_shell::PARAMS.iter().map(|p| p.1).collect(),
        ray_shell::RESULT,
        &ray_shell::call_ids,
        &inputs,
        |w| {
            let r = ray_shell(a(w, 0), a(w, 1), a(w, 2), a(w, 3));
            vec![r.x.to_bits(), r.y.to_bits()]
        },
        // Distances up to ~1000 km; a few ulp of sqrt differ between CPU and GPU.
        Tolerance {
            abs: 1e-3,
            rel: 2e-6,
        },
    );
}

fn phase_inputs(seed: u64, second: (f32, f32)) -> Vec<Vec<u32>> {
    let mut rng = Rng::new(seed);
    let mut inputs = vec![vec![f(1.0), f(second.0)], vec![f(-1.0), f(second.1)]];
    while inputs.len() < MIN_INPUTS {
        inputs.push(vec![
            f(rng.range(-1.0, 1.0)),
            f(rng.range(second.0, second.1)),
        ]);
    }
    inputs
}

#[test]
fn phase_functions_match_cpu() {
    let mut rng = Rng::new(22);
    let single: Vec<Vec<u32>> = (0..MIN_INPUTS)
        .map(|i| {
            vec![f(if i < 2 {
                [1.0, -1.0][i]
            } else {
                rng.range(-1.0, 1.0)
            })]
        })
        .collect();
    let tol = Tolerance {
        abs: 1e-7,
        rel: 4e-6,
    };
    compare(
        "isotropic_phase",
        vec![Type::F32],
        Type::F32,
        &isotropic_phase::call_ids,
        &single,
        |w| vec![isotropic_phase(a(w, 0)).to_bits()],
        tol,
    );
    compare(
        "rayleigh_phase",
        vec![Type::F32],
        Type::F32,
        &rayleigh_phase::call_ids,
        &single,
        |w| vec![rayleigh_phase(a(w, 0)).to_bits()],
        tol,
    );
    let mie = phase_inputs(23, (5.0, 50.0));
    compare(
        "approximate_mie",
        vec![Type::F32, Type::F32],
        Type::F32,
        &approximate_mie::call_ids,
        &mie,
        |w| vec![approximate_mie(a(w, 0), a(w, 1)).to_bits()],
        // exp() of the fitted parameters, then a peaked lobe: relative error dominates.
        Tolerance {
            abs: 1e-6,
            rel: 3e-5,
        },
    );
    let mut rng = Rng::new(24);
    let draine: Vec<Vec<u32>> = (0..MIN_INPUTS)
        .map(|_| {
            vec![
                f(rng.range(-1.0, 1.0)),
                f(rng.range(-0.95, 0.95)),
                f(rng.range(0.0, 25.0)),
            ]
        })
        .collect();
    compare(
        "draine_phase",
        vec![Type::F32, Type::F32, Type::F32],
        Type::F32,
        &draine_phase::call_ids,
        &draine,
        |w| vec![draine_phase(a(w, 0), a(w, 1), a(w, 2)).to_bits()],
        Tolerance {
            abs: 1e-7,
            rel: 8e-6,
        },
    );
}

fn random_group(rng: &mut Rng) -> LayerGroup {
    let mut v = |lo: f32, hi: f32| {
        Vec4::new(
            rng.range(lo, hi),
            rng.range(lo, hi),
            rng.range(lo, hi),
            rng.range(lo, hi),
        )
    };
    let min = v(0.0, 8000.0);
    let mut g = LayerGroup::empty();
    g.min_height = min;
    g.max_height = min + v(0.0, 3000.0);
    g.density_scale = v(0.0, 0.3);
    g.shape_amount = v(0.0, 1.0);
    g.shape_detail_amount = v(0.0, 1.0);
    g.weather_exponent = v(0.2, 3.0);
    g.shape_altering_bias = v(0.1, 1.5);
    g.coverage_filter_width = v(0.001, 1.0);
    g.profile_a = v(0.0, 1.0);
    g.profile_b = v(-10.0, 10.0);
    g.profile_c = v(-1.0, 1.0);
    g.profile_d = v(0.0, 1.0);
    g
}

fn group_words(g: &LayerGroup) -> Vec<u32> {
    let mut w = Vec::new();
    for v in [
        g.min_height,
        g.max_height,
        g.density_scale,
        g.shape_amount,
        g.shape_detail_amount,
        g.weather_exponent,
        g.shape_altering_bias,
        g.coverage_filter_width,
        g.profile_a,
        g.profile_b,
        g.profile_c,
        g.profile_d,
        g.shadow_mask,
    ] {
        w.extend(v.to_array().map(f32::to_bits));
    }
    w.extend(g.channel_matrix.to_cols_array().map(f32::to_bits));
    w
}

fn group_from(w: &[u32]) -> LayerGroup {
    let mut g = LayerGroup::empty();
    let fields = [
        &mut g.min_height,
        &mut g.max_height,
        &mut g.density_scale,
        &mut g.shape_amount,
        &mut g.shape_detail_amount,
        &mut g.weather_exponent,
        &mut g.shape_altering_bias,
        &mut g.coverage_filter_width,
        &mut g.profile_a,
        &mut g.profile_b,
        &mut g.profile_c,
        &mut g.profile_d,
        &mut g.shadow_mask,
    ];
    for (i, field) in fields.into_iter().enumerate() {
        *field = v4(w, i * 4);
    }
    g.channel_matrix = glam::Mat4::from_cols_array(&std::array::from_fn(|i| a(w, 52 + i)));
    g
}

const GROUP: Type = <LayerGroupShader as Value>::TYPE;

#[test]
fn density_stages_match_cpu() {
    let mut rng = Rng::new(25);
    let mut inputs = Vec::new();
    while inputs.len() < MIN_INPUTS {
        let g = random_group(&mut rng);
        let mut w = vec![f(rng.range(-100.0, 12_000.0))];
        w.extend(group_words(&g));
        inputs.push(w);
    }
    let tol = Tolerance {
        abs: 2e-5,
        rel: 2e-5,
    };
    let call = |x: &[ExprId]| {
        height_fraction::shader(
            nimbus_dsl::shader::F32::from_id(x[0]),
            LayerGroupShader::from_id(x[1]),
        )
        .id()
    };
    compare(
        "height_fraction",
        vec![Type::F32, GROUP],
        VEC4,
        &call,
        &inputs,
        |w| out4(height_fraction(a(w, 0), group_from(&w[1..]))),
        tol,
    );

    // The profile over η ∈ [0, 1], with the group's coefficients.
    let eta_inputs: Vec<Vec<u32>> = inputs
        .iter()
        .enumerate()
        .map(|(i, w)| {
            let mut v: Vec<u32> = (0..4)
                .map(|k| f(((i * 4 + k) % 101) as f32 / 100.0))
                .collect();
            v.extend(&w[1..]);
            v
        })
        .collect();
    let call = |x: &[ExprId]| {
        exponential_profile::shader(
            nimbus_dsl::shader::Vec4::from_id(x[0]),
            LayerGroupShader::from_id(x[1]),
        )
        .id()
    };
    compare(
        "exponential_profile",
        vec![VEC4, GROUP],
        VEC4,
        &call,
        &eta_inputs,
        |w| out4(exponential_profile(v4(w, 0), group_from(&w[4..]))),
        tol,
    );
}

/// Every height function a genus can name, built-in or a user's (the supercell example
/// crate's), on the GPU against its CPU twin, over η ∈ [0, 1.1] (the march asks [0, 1]) with
/// random layer groups; every output finite.
#[test]
fn every_genus_height_function_matches_cpu() {
    use nimbus_clouds::HeightFn;
    use nimbus_clouds::functions::known;
    supercell::register_functions().expect("register");
    let functions = known::<HeightFn>();
    assert!(
        functions.contains(&supercell::SHAPE) && functions.contains(&supercell::PROFILE),
        "the user's functions are known once registered"
    );
    let mut rng = Rng::new(27);
    let mut inputs = Vec::new();
    while inputs.len() < MIN_INPUTS {
        let i = inputs.len();
        let mut w: Vec<u32> = (0..4)
            .map(|k| f(((i * 4 + k) % 111) as f32 / 100.0))
            .collect();
        w.extend(group_words(&random_group(&mut rng)));
        inputs.push(w);
    }
    for hf in functions {
        let call = |x: &[ExprId]| {
            (hf.shader)(
                nimbus_dsl::shader::Vec4::from_id(x[0]),
                LayerGroupShader::from_id(x[1]),
            )
            .id()
        };
        compare(
            hf.name,
            vec![VEC4, GROUP],
            VEC4,
            &call,
            &inputs,
            |w| {
                let v = (hf.cpu)(v4(w, 0), group_from(&w[4..]));
                assert!(v.is_finite(), "{}: {v} at η {}", hf.name, v4(w, 0));
                out4(v)
            },
            Tolerance {
                abs: 3e-5,
                rel: 3e-5,
            },
        );
    }
}

#[test]
fn erosion_and_coverage_match_cpu() {
    let mut rng = Rng::new(26);
    let mut r4 = |lo: f32, hi: f32| {
        Vec4::new(
            rng.range(lo, hi),
            rng.range(lo, hi),
            rng.range(lo, hi),
            rng.range(lo, hi),
        )
    };
    let mut inputs = Vec::new();
    for _ in 0..MIN_INPUTS {
        let mut w = Vec::new();
        for v in [r4(0.0, 1.0), r4(0.1, 2.0), r4(0.001, 1.0), r4(0.0, 1.0)] {
            w.extend(v.to_array().map(f32::to_bits));
        }
        w.push(f(r4(0.0, 1.0).x));
        inputs.push(w);
    }
    // Extremes: η at 0 and 1, full-amount erosion with zero noise, the narrowest filter.
    inputs[0][..4].copy_from_slice(&[f(0.0), f(1.0), f(0.0), f(1.0)]);
    inputs[1][12..16].copy_from_slice(&[f(1.0); 4]);
    inputs[1][16] = f(0.0);
    let tol = Tolerance {
        abs: 3e-5,
        rel: 3e-5,
    };
    let (vec4_, f32_) = (
        nimbus_dsl::shader::Vec4::from_id,
        nimbus_dsl::shader::F32::from_id,
    );
    let call = |x: &[ExprId]| shape_altering::shader(vec4_(x[0]), vec4_(x[1])).id();
    compare(
        "shape_altering",
        vec![VEC4, VEC4],
        VEC4,
        &call,
        &inputs.iter().map(|w| w[..8].to_vec()).collect::<Vec<_>>(),
        |w| out4(shape_altering(v4(w, 0), v4(w, 4))),
        tol,
    );
    let call = |x: &[ExprId]| {
        coverage_remap::shader(vec4_(x[0]), f32_(x[1]), vec4_(x[2]), vec4_(x[3])).id()
    };
    let cov_inputs: Vec<Vec<u32>> = inputs
        .iter()
        .map(|w| {
            let mut v = w[..4].to_vec();
            v.push(w[16]);
            v.extend(&w[12..16]);
            v.extend(&w[8..12]);
            v
        })
        .collect();
    compare(
        "coverage_remap",
        vec![VEC4, Type::F32, VEC4, VEC4],
        VEC4,
        &call,
        &cov_inputs,
        |w| out4(coverage_remap(v4(w, 0), a(w, 4), v4(w, 5), v4(w, 9))),
        tol,
    );
    let call = |x: &[ExprId]| shape_erosion::shader(vec4_(x[0]), f32_(x[1]), vec4_(x[2])).id();
    let ero_inputs: Vec<Vec<u32>> = inputs
        .iter()
        .map(|w| {
            let mut v = w[..4].to_vec();
            v.push(w[16]);
            v.extend(&w[12..16]);
            v
        })
        .collect();
    compare(
        "shape_erosion",
        vec![VEC4, Type::F32, VEC4],
        VEC4,
        &call,
        &ero_inputs,
        |w| out4(shape_erosion(v4(w, 0), a(w, 4), v4(w, 5))),
        tol,
    );
    let call = |x: &[ExprId]| {
        detail_erosion::shader(
            vec4_(x[0]),
            f32_(x[1]),
            f32_(x[2]),
            vec4_(x[3]),
            vec4_(x[4]),
        )
        .id()
    };
    let det_inputs: Vec<Vec<u32>> = inputs
        .iter()
        .map(|w| {
            let mut v = w[12..16].to_vec();
            // The two erosion signals: any d⁶-like value and any billowy value.
            v.push(w[16]);
            v.push(f(1.0 - f32::from_bits(w[16]).clamp(0.0, 1.0)));
            v.extend(&w[..4]);
            v.extend(
                &w[4..8]
                    .iter()
                    .map(|x| f(f32::from_bits(*x).min(1.0)))
                    .collect::<Vec<_>>(),
            );
            v
        })
        .collect();
    compare(
        "detail_erosion",
        vec![VEC4, Type::F32, Type::F32, VEC4, VEC4],
        VEC4,
        &call,
        &det_inputs,
        |w| {
            out4(detail_erosion(
                v4(w, 0),
                a(w, 4),
                a(w, 5),
                v4(w, 6),
                v4(w, 10),
            ))
        },
        tol,
    );
}

/// `lane_of` (the shadow atlas's tile picked by a mask, not an index) is the lane itself on
/// both sides (as a value: a lane of −0 reads +0), each of the four lanes whatever the others
/// hold (huge, tiny, negative), so the mask leaks nothing of the lanes it does not pick.
#[test]
fn lane_of_is_the_lane_on_both_sides() {
    use nimbus_clouds::model::shadow::lane_of;
    let mut rng = Rng::new(47);
    let mut inputs = Vec::new();
    let extremes = [0.0, -0.0, 1.0, -1.0, 1e30, -1e30, 1e-30, 65_504.0];
    for k in 0..4 {
        for (i, &x) in extremes.iter().enumerate() {
            let mut v = [extremes[(i + 3) % 8]; 4];
            v[k] = x;
            inputs.push(vec![f(v[0]), f(v[1]), f(v[2]), f(v[3]), f(k as f32)]);
        }
    }
    while inputs.len() < MIN_INPUTS {
        let k = (rng.range(0.0, 4.0) as u32).min(3) as f32;
        let v: Vec<u32> = (0..4).map(|_| f(rng.range(-2e4, 2e4))).collect();
        inputs.push([v, vec![f(k)]].concat());
    }
    for w in &inputs {
        let k = a(w, 4) as usize;
        assert_eq!(
            lane_of(v4(w, 0), a(w, 4)),
            v4(w, 0)[k],
            "lane {k} of {:?}",
            v4(w, 0)
        );
    }
    compare(
        "lane_of",
        lane_of::PARAMS.iter().map(|p| p.1).collect(),
        lane_of::RESULT,
        &lane_of::call_ids,
        &inputs,
        |w| vec![lane_of(v4(w, 0), a(w, 4)).to_bits()],
        Tolerance { abs: 0.0, rel: 0.0 },
    );
}
