//! The clouds' shadow on the air in front of them.
//!
//! The air between the camera and what it sees scatters sunlight towards it (the aerial
//! perspective of `sky::air_light`), but only where the sun reaches it: under an overcast the
//! air is in the deck's shadow. Lit as if no cloud shaded it, the air under a nimbostratus
//! tinted its grey base navy blue and drew a bright patch round the hidden sun. With the cloud
//! shadows on, the air's sunlight is scaled by the mean of the sun's direct beam through the
//! clouds (`e^(−τ)`, [`cloud_depth_to_sun`]) at a few stratified points along the way. The
//! light a deck lets through diffusely is left out: it no longer comes from the sun's
//! direction, so the air's forward peak must not see it (with it, as `sun_through_clouds`
//! counts it for the ground, the air under a nimbostratus still drew a patch round the sun).

use glam::Vec3;

use crate::key::CloudKey;
use nimbus_dsl::prelude::*;

use super::choices::{SHADOWS, gate};
use super::scene_shadow::cloud_depth_to_sun;

/// Looks into the shadow map along the way (stratified by the pixel's jitter).
const AIR_SHADOW_SAMPLES: u32 = 4;

/// The fraction of the sun's direct light that reaches the air along `direction` over its
/// first `distance` metres (1 without cloud shadows).
#[shader_fn]
pub fn air_sunlit(direction: Vec3, distance: f32, jitter: f32, #[spec] key: CloudKey) -> f32 {
    let mut sunlit = 1.0f32;
    if gate(key, SHADOWS) {
        let mut sum = 0.0f32;
        for i in 0u32..AIR_SHADOW_SAMPLES {
            let t = (i as f32 + jitter) / AIR_SHADOW_SAMPLES as f32 * distance;
            sum += (-cloud_depth_to_sun(direction * t)).exp();
        }
        sunlit = sum / AIR_SHADOW_SAMPLES as f32;
    }
    sunlit
}
