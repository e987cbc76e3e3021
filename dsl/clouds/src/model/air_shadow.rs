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
//!
//! Without light shafts the haze takes the same share ([`super::march::haze_light`]): lit
//! everywhere, it drew the sunset under a broken deck 44 % too bright in the accuracy study.

use glam::Vec3;

use crate::key::CloudKey;
use nimbus_dsl::prelude::*;

use super::bindings::CLOUDS;
use super::choices::{HAZE, LIGHT_SHAFTS, SHADOWS, gate};
use super::scene_shadow::cloud_depth_to_sun;
use super::shell::ray_shell;

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

/// How much of an open ray [`air_sunlit`] reads: `distance` (the march's reach, 100–200 km)
/// ends far above every cloud, and the sun reaches all of the way above the top of the
/// shadow-casting layers (there the atlas reads no optical depth), so the shadow map is read
/// only below it, where a ray from a camera under the layers spends its first kilometres (all
/// of its way, near the horizon), and the rest counts as sunlit. Spread over the whole reach,
/// the four reads had mostly landed above the layers.
#[shader_fn]
pub fn open_air_reach(direction: Vec3, distance: f32) -> f32 {
    let u = CLOUDS.get();
    let m = u.march;
    let exit = ray_shell(
        u.camera_altitude,
        direction.y,
        m.shadow_top_height,
        m.radius,
    )
    .y;
    select(
        distance,
        exit.clamp(0.0, distance),
        u.camera_altitude < m.shadow_top_height && direction.y > 0.0,
    )
}

/// The sun's share of the air in front of what a view ray shows, its first `near` metres:
/// the clouds' front, else the ground or an engine's surface (`ends`: something ends the ray
/// there), else the march's reach. Read once for the air's light and for the haze's, which
/// takes it when there are no light shafts; an open sky's air, whose light is all sky light,
/// needs it for that haze alone.
#[shader_fn]
pub fn near_air_sunlit(
    direction: Vec3,
    near: f32,
    ends: bool,
    jitter: f32,
    #[spec] key: CloudKey,
) -> f32 {
    let mut sunlit = 1.0f32;
    if gate(key, HAZE) {
        if gate(key, LIGHT_SHAFTS) {
            // The light-shaft march reads the open air's shadows itself.
            if ends {
                sunlit = air_sunlit(direction, near, jitter, key);
            }
        } else {
            // One read serves an ended ray (all of its way) and an open one (its way below
            // the layers, the rest sunlit): as two, SwiftShader, which runs both sides of a
            // branch, paid for both at every pixel.
            let below = select(open_air_reach(direction, near), near, ends);
            let read = air_sunlit(direction, below, jitter, key);
            let shaded = below / near.max(1.0);
            sunlit = select(1.0 - shaded * (1.0 - read), read, ends);
        }
    } else if ends {
        sunlit = air_sunlit(direction, near, jitter, key);
    }
    sunlit
}
