//! One probe: a view ray marched and composited exactly as a pixel is, with every output kept.

use glam::Vec3;

use nimbus_clouds::CloudKey;
use nimbus_clouds::model::march::{MarchResult, composite, march_clouds};
use nimbus_dsl::prelude::*;

use super::case::{Case, Probe};

/// Everything a probe yields: the march and the composited pixel.
#[derive(Clone, Copy, Debug, PartialEq, ShaderStruct)]
pub struct RayOutcome {
    pub march: MarchResult,
    pub colour: Vec4,
}

/// The angle a probe's pixel subtends (rad): a 1920-pixel-wide, 90° view. The catalogue's
/// samples then stand for metres to kilometres, so the detail's level-of-detail blend is
/// exercised from all detail to none.
pub const PROBE_PIXEL_ANGLE: f32 = 8.2e-4;

/// Marches `direction` and composites it, as [`nimbus_clouds::model::march::cloud_fragment`] does for
/// the ray of a pixel.
#[shader_fn]
pub fn probe_ray(direction: Vec3, jitter: f32, #[spec] key: CloudKey) -> RayOutcome {
    let march = march_clouds(direction, jitter, PROBE_PIXEL_ANGLE, key);
    let colour = composite(direction, jitter, march, key);
    RayOutcome { march, colour }
}

/// Every probe of `case` through the CPU twins, each under its own uniforms.
pub fn run_case_cpu(case: &Case) -> Vec<RayOutcome> {
    let t = case.textures.build();
    case.probes
        .iter()
        .map(|p: &Probe| {
            let _bound = t.bind(p.uniforms);
            probe_ray(p.direction, p.jitter, case.key)
        })
        .collect()
}
