//! Display transform: exposure, the ACES filmic curve (Narkowicz 2015 fit) and the sRGB
//! transfer function.

use glam::Vec3;

use nimbus_dsl::prelude::*;

/// ACES filmic tone curve fit (Narkowicz 2015), per channel, output in [0, 1].
#[shader_fn]
pub fn aces(x: f32) -> f32 {
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// sRGB encoding of a linear value in [0, 1].
#[shader_fn]
pub fn srgb_encode(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        return linear * 12.92;
    }
    1.055 * linear.powf(1.0 / 2.4) - 0.055
}

/// Linear radiance to display sRGB in [0, 1].
#[shader_fn]
pub fn tonemap(color: Vec3, exposure: f32) -> Vec3 {
    let c = color * exposure;
    vec3(
        srgb_encode(aces(c.x)),
        srgb_encode(aces(c.y)),
        srgb_encode(aces(c.z)),
    )
}
