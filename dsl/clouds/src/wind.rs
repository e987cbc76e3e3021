//! Wind: the clouds drift with the air they are in, faster and turned with height (shear).
//!
//! A scene gives the wind near the ground and at [`TOP_ALTITUDE`]; between them it changes
//! linearly with altitude, so each layer moves with the wind at its own height and a tall
//! cloud leans downwind. The clouds' noise positions are displaced by the wind's drift, the
//! same in the weather, shape and detail textures, so a cloud moves as a whole.
//!
//! The wind's velocity is a `#[shader_fn]` ([`wind_velocity`], [`wind_velocity_at`]): the
//! timeline computes the drift with its CPU twin, and a JavaScript host (`nimbus-wind.js` in a
//! three.js package, printed by [`nimbus_codegen::print_js`] from
//! [`crate::timeline::host_module`]) with its JavaScript twin, so the formula exists once.

use glam::{Vec2, Vec4};
use nimbus_dsl::prelude::*;
use serde::{Deserialize, Serialize};

/// Altitude (m) of a scene's `top_speed` and `top_direction_deg`.
pub const TOP_ALTITUDE: f32 = 10_000.0;

/// A scene's wind.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Wind {
    /// Speed near the ground, m/s.
    pub speed: f32,
    /// Where the wind blows from, degrees clockwise from north (270: a westerly, blowing east).
    pub direction_deg: f32,
    /// Speed at 10 km (m/s); the ground's when absent (no shear).
    pub top_speed: Option<f32>,
    /// Direction at 10 km; the ground's when absent (no veer).
    pub top_direction_deg: Option<f32>,
}

/// Velocity (m/s, local x east, z south) of a wind of `speed` (m/s) from `direction_deg`
/// (degrees clockwise from north, where it blows from).
#[shader_fn]
pub fn wind_velocity(speed: f32, direction_deg: f32) -> Vec2 {
    let from = direction_deg.to_radians();
    // It blows towards the opposite azimuth: −(sin, −cos) of where it comes from.
    Vec2::new(-from.sin(), from.cos()) * speed
}

/// The velocity at `altitude` (m) of a wind whose velocity is `ground` near the ground and
/// `top` at [`TOP_ALTITUDE`]: linear in altitude, continued above.
#[shader_fn]
pub fn wind_velocity_at(ground: Vec2, top: Vec2, altitude: f32) -> Vec2 {
    ground + (top - ground) * (altitude / TOP_ALTITUDE)
}

/// How far the clouds have drifted after `seconds`: the displacement at the ground (m) and its
/// growth per metre of altitude (shear), as the shader's `media.wind_drift` and
/// `media.wind_shear_drift` take them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Drift {
    pub ground: Vec2,
    pub per_metre: Vec2,
}

/// How far the clouds have drifted `seconds` after the start of a wind whose velocity is
/// `ground` near the ground and `top` at [`TOP_ALTITUDE`]: x, y the displacement at the ground
/// (m, local x and z; `media.wind_drift`), z, w how much farther per metre of altitude
/// (`media.wind_shear_drift`) — the packing `frame_sequence::drift_at` reads.
#[shader_fn]
pub fn wind_drift(ground: Vec2, top: Vec2, seconds: f32) -> Vec4 {
    let at_ground = ground * seconds;
    let per_metre = (top - ground) * (seconds / TOP_ALTITUDE);
    vec4(at_ground.x, at_ground.y, per_metre.x, per_metre.y)
}

impl Wind {
    /// The velocity at `altitude` (m): linear in altitude through the ground's and
    /// [`TOP_ALTITUDE`]'s, continued above (the shader's drift is the same line).
    pub fn velocity_at(&self, altitude: f32) -> Vec2 {
        let low = wind_velocity(self.speed, self.direction_deg);
        let high = wind_velocity(
            self.top_speed.unwrap_or(self.speed),
            self.top_direction_deg.unwrap_or(self.direction_deg),
        );
        wind_velocity_at(low, high, altitude)
    }

    /// The drift after `seconds`, by [`wind_drift`]: the function a JavaScript host's timeline
    /// calls too (`NimbusTimeline`, through `nimbus-wind.js`). Timelines stop at about a day
    /// (`limits::WEATHER_AT`), where an f32 time still steps by 8 ms.
    pub fn drift(&self, seconds: f64) -> Drift {
        let d = wind_drift(
            self.velocity_at(0.0),
            self.velocity_at(TOP_ALTITUDE),
            seconds as f32,
        );
        Drift {
            ground: Vec2::new(d.x, d.y),
            per_metre: Vec2::new(d.z, d.w),
        }
    }
}
