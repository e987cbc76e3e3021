//! One probe: a view ray marched and composited exactly as a pixel is, with every output kept.

use glam::Vec3;

use nimbus_clouds::CloudKey;
use nimbus_clouds::model::march::{CloudUniforms, MarchResult, composite, march_clouds};
use nimbus_dsl::cpu::{Sampler, Texture2d, Texture3d};
use nimbus_dsl::prelude::*;

use super::case::{Case, Probe};

/// Everything a probe yields: the march and the composited pixel.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct RayOutcome {
    pub march: MarchResult,
    pub colour: Vec4,
}

/// Marches `direction` and composites it, as [`nimbus_clouds::model::march::cloud_fragment`] does for
/// the ray of a pixel.
#[shader_fn]
#[expect(clippy::too_many_arguments, reason = "one parameter per texture")]
pub fn probe_ray(
    direction: Vec3,
    jitter: f32,
    u: CloudUniforms,
    weather_tex: &Texture2d,
    shape_tex: &Texture3d,
    detail_tex: &Texture3d,
    turbulence_tex: &Texture2d,
    shadow_tex: &Texture2d,
    smp: &Sampler,
    #[spec] key: CloudKey,
) -> RayOutcome {
    let march = march_clouds(
        direction,
        jitter,
        u,
        weather_tex,
        shape_tex,
        detail_tex,
        turbulence_tex,
        shadow_tex,
        smp,
        key,
    );
    let colour = composite(direction, jitter, march, u, shadow_tex, smp, key);
    RayOutcome { march, colour }
}

/// Every probe of `case` through the CPU twins.
pub fn run_case_cpu(case: &Case) -> Vec<RayOutcome> {
    let t = case.textures.build();
    let smp = Sampler::default();
    case.probes
        .iter()
        .map(|p: &Probe| {
            probe_ray(
                p.direction,
                p.jitter,
                p.uniforms,
                &t.weather,
                &t.shape,
                &t.detail,
                &t.turbulence,
                &t.shadow,
                &smp,
                case.key,
            )
        })
        .collect()
}
