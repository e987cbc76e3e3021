//! The stability catalogue on the GPU: every probe of every case through the generated shader
//! (lavapipe where there is no GPU), judged by the same invariants as the CPU twins in
//! `dsl/tests/stability.rs`. The largest GPU–CPU difference per case is printed.

mod common;

use glam::{Vec3, Vec4};
use nimbus_clouds::model::bindings::CLOUDS;
use nimbus_clouds::model::march::{CloudUniformsShader, MarchResult};
use nimbus_dsl::Value;
use nimbus_dsl::ir::{ExprId, Scalar, Type};
use nimbus_dsl::layout::Flatten;
use nimbus_dsl::shader;
use nimbus_testkit::parity::{KernelFn, cloud_resources, run_on_gpu};
use nimbus_testkit::stability::{
    Case, RayOutcome, RayOutcomeShader, catalogue, check_case, genus_case, probe_ray, run_case_cpu,
};

/// Runs every probe of `cases` (which share a variant key and textures: one kernel) on the GPU.
fn run_cases_gpu(gpu: &nimbus_runtime::Gpu, cases: &[&Case]) -> Vec<Vec<RayOutcome>> {
    let case = cases[0];
    let t = case.textures.build();
    let resources = cloud_resources(&t);
    let key = case.key;
    let call = move |a: &[ExprId]| {
        // Each probe has its own uniforms: they travel with its record.
        CLOUDS.feed(CloudUniformsShader::from_id(a[2]));
        probe_ray::shader(shader::Vec3::from_id(a[0]), shader::F32::from_id(a[1]), key).id()
    };
    let mut words = Vec::new();
    for p in cases.iter().flat_map(|c| &c.probes) {
        words.extend(p.direction.to_array().map(f32::to_bits));
        words.push(p.jitter.to_bits());
        p.uniforms.flatten(&mut words);
    }
    let f = KernelFn {
        name: case.name,
        params: vec![
            Type::Vector(3, Scalar::F32),
            Type::F32,
            <CloudUniformsShader as Value>::TYPE,
        ],
        result: <RayOutcomeShader as Value>::TYPE,
        call: &call,
        resources: &resources,
    };
    let out = run_on_gpu(gpu, &f, &words).expect("GPU run");
    let mut all: Vec<RayOutcome> = out
        .chunks_exact(10)
        .map(|w| {
            let v: Vec<f32> = w.iter().map(|x| f32::from_bits(*x)).collect();
            RayOutcome {
                march: MarchResult {
                    radiance: Vec3::new(v[0], v[1], v[2]),
                    transmittance: v[3],
                    front_depth: v[4],
                    samples: v[5],
                },
                colour: Vec4::new(v[6], v[7], v[8], v[9]),
            }
        })
        .collect();
    cases
        .iter()
        .map(|c| all.drain(..c.probes.len()).collect())
        .collect()
}

#[test]
fn stability_catalogue_holds_on_the_gpu() {
    let Some(gpu) = common::gpu() else { return };
    println!("adapter: {}", gpu.info());
    let mut cases = catalogue();
    // A genus of a user's own: the supercell example crate's shape and profile functions.
    let supercell = supercell::genus().expect("supercell genus");
    cases.push(genus_case(
        "user-genus-supercell",
        "the supercell example crate's own shape and profile",
        &supercell,
    ));
    // One kernel per variant key and texture set: compiling is what takes the time.
    let mut groups: Vec<Vec<&Case>> = Vec::new();
    for c in &cases {
        match groups
            .iter_mut()
            .find(|g| g[0].key == c.key && g[0].textures == c.textures)
        {
            Some(g) => g.push(c),
            None => groups.push(vec![c]),
        }
    }
    println!("{} cases in {} kernels", cases.len(), groups.len());
    let mut failures = Vec::new();
    for (case, gpu_out) in groups
        .iter()
        .flat_map(|g| g.iter().copied().zip(run_cases_gpu(gpu, g)))
    {
        assert_eq!(
            gpu_out.len(),
            case.probes.len(),
            "{}: outcome count",
            case.name
        );
        let cpu_out = run_case_cpu(case);
        let transmittance = gpu_out
            .iter()
            .zip(&cpu_out)
            .map(|(g, c)| (g.march.transmittance - c.march.transmittance).abs())
            .fold(0.0f32, f32::max);
        let samples = gpu_out
            .iter()
            .zip(&cpu_out)
            .filter(|(g, c)| g.march.samples != c.march.samples)
            .count();
        let violations = check_case(case, &gpu_out);
        println!(
            "{:<30} {:>4} probes: {} violations on the GPU; largest |T_gpu - T_cpu| {:.2e}; {} probes with another sample count",
            case.name,
            case.probes.len(),
            violations.len(),
            transmittance,
            samples
        );
        for v in violations.iter().take(10) {
            println!("  {v}");
        }
        failures.extend(violations);
    }
    assert!(
        failures.is_empty(),
        "{} violations on the GPU",
        failures.len()
    );
}
