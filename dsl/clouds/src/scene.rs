//! Scene presets: a genus seen under a given sky (coverage, sun, camera) at a quality preset.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::DataError;
use crate::limits::{self, Limit, Origin};

use super::budget::Budget;
use super::clock::Clock;
use super::features::FeatureOverrides;
use super::formation::Formation;
use super::quality::Quality;
use super::timeline::WeatherState;
use super::view_defaults::VIEW_DEFAULTS;
use super::wind::Wind;

/// A scene preset file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenePreset {
    /// Identifier; must equal the file's stem.
    pub name: String,
    pub description: String,
    /// Name of the genus file to use.
    pub genus: String,
    /// Overrides the genus' coverage.
    pub coverage: Option<f32>,
    /// Sun elevation above the horizon, degrees.
    #[serde(default = "default_sun_elevation")]
    pub sun_elevation_deg: f32,
    /// Sun azimuth, degrees clockwise from north.
    #[serde(default = "default_sun_azimuth")]
    pub sun_azimuth_deg: f32,
    /// Camera altitude above the ground, metres.
    #[serde(default = "default_camera_altitude")]
    pub camera_altitude: f32,
    /// Camera pitch above the horizon, degrees.
    #[serde(default = "default_camera_pitch")]
    pub camera_pitch_deg: f32,
    /// Camera heading, degrees clockwise from north.
    #[serde(default = "default_camera_yaw")]
    pub camera_yaw_deg: f32,
    /// Vertical field of view, degrees.
    #[serde(default = "default_fov")]
    pub fov_deg: f32,
    /// Density of the haze at sea level (1/m); 0 for air without haze.
    #[serde(default = "default_haze_density")]
    pub haze_density: f32,
    /// Turbulent displacement of cloud bases (m); 0 for none.
    #[serde(default = "default_turbulence_displacement")]
    pub turbulence_displacement: f32,
    /// Offset of the weather texture in tiles (one tile is 100 km): moves the clouds.
    #[serde(default, deserialize_with = "exactly_two")]
    pub weather_offset: [f32; 2],
    #[serde(default)]
    pub quality: Quality,
    #[serde(default)]
    pub features: FeatureOverrides,
    /// Place and local time at the timeline's start: the sun follows them (and
    /// `sun_elevation_deg`, `sun_azimuth_deg` are then unused).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clock: Option<Clock>,
    /// The wind the clouds drift with.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind: Option<Wind>,
    /// Weather states over time, in time order (`[[weather]]` tables).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub weather: Vec<WeatherState>,
    /// Clouds forming and dissolving over the timeline (`[formation]`): where the automaton
    /// has cloud, the weather lets the genus' clouds through.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub formation: Option<Formation>,
    /// The clouds' share of a frame on the target device (`[budget]`): with no path named, the
    /// analysis picks the most accurate one that fits ([`crate::budget::choose`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub budget: Option<Budget>,
}

/// A pair of numbers, refusing a list of any other length (serde's fixed arrays accept and drop
/// extra elements from TOML).
fn exactly_two<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f32; 2], D::Error> {
    let v: Vec<f32> = Vec::deserialize(d)?;
    <[f32; 2]>::try_from(v.as_slice()).map_err(|_| {
        serde::de::Error::custom(format!(
            "expected 2 numbers (x and z, in tiles), got {}: {v:?}",
            v.len()
        ))
    })
}

// What a scene file leaves out: the one set of defaults (`VIEW_DEFAULTS`).
fn default_sun_elevation() -> f32 {
    VIEW_DEFAULTS.sun_elevation_deg
}

fn default_sun_azimuth() -> f32 {
    VIEW_DEFAULTS.sun_azimuth_deg
}

fn default_camera_altitude() -> f32 {
    VIEW_DEFAULTS.camera_altitude
}

fn default_haze_density() -> f32 {
    VIEW_DEFAULTS.haze_density
}

fn default_turbulence_displacement() -> f32 {
    VIEW_DEFAULTS.turbulence_displacement
}

fn default_camera_pitch() -> f32 {
    VIEW_DEFAULTS.camera_pitch_deg
}

fn default_camera_yaw() -> f32 {
    VIEW_DEFAULTS.camera_yaw_deg
}

fn default_fov() -> f32 {
    VIEW_DEFAULTS.fov_deg
}

impl ScenePreset {
    /// Checks every value against its [`crate::limits`], naming `file` and the field in an
    /// error.
    pub fn validate(&self, file: &Path) -> Result<(), DataError> {
        self.validate_from(&|limit: &Limit| Origin::File {
            file: file.to_path_buf(),
            field: limit.field.to_string(),
        })?;
        Ok(())
    }

    /// Checks every value against its [`crate::limits`]; `origin` says where the value of each
    /// limit's field came from (a flag for what the command line overrode, the file for the
    /// rest), and the error names it.
    pub fn validate_from(&self, origin: &dyn Fn(&Limit) -> Origin) -> Result<(), DataError> {
        let check = |limit: &Limit, v: f32| limit.check(f64::from(v), origin(limit));
        if let Some(c) = self.coverage {
            check(&limits::COVERAGE, c)?;
        }
        check(&limits::SUN_ELEVATION, self.sun_elevation_deg)?;
        check(&limits::SUN_AZIMUTH, self.sun_azimuth_deg)?;
        check(&limits::CAMERA_ALTITUDE, self.camera_altitude)?;
        check(&limits::CAMERA_PITCH, self.camera_pitch_deg)?;
        check(&limits::CAMERA_YAW, self.camera_yaw_deg)?;
        check(&limits::FOV, self.fov_deg)?;
        check(&limits::HAZE_DENSITY, self.haze_density)?;
        check(
            &limits::TURBULENCE_DISPLACEMENT,
            self.turbulence_displacement,
        )?;
        for v in self.weather_offset {
            check(&limits::WEATHER_OFFSET, v)?;
        }
        if let Some(o) = self.features.octaves {
            limits::OCTAVES.check(f64::from(o), origin(&limits::OCTAVES))?;
        }
        if let Some(c) = &self.clock {
            limits::LATITUDE.check(c.latitude_deg, origin(&limits::LATITUDE))?;
            limits::LONGITUDE.check(c.longitude_deg, origin(&limits::LONGITUDE))?;
            limits::UTC_OFFSET.check(c.utc_offset_hours, origin(&limits::UTC_OFFSET))?;
        }
        if let Some(w) = &self.wind {
            check(&limits::WIND_SPEED, w.speed)?;
            check(&limits::WIND_DIRECTION, w.direction_deg)?;
            if let Some(v) = w.top_speed {
                check(&limits::WIND_TOP_SPEED, v)?;
            }
            if let Some(v) = w.top_direction_deg {
                check(&limits::WIND_TOP_DIRECTION, v)?;
            }
        }
        if let Some(b) = &self.budget {
            check(&limits::BUDGET_FRAME_MS, b.frame_ms)?;
            check(&limits::BUDGET_VOLUME_MS, b.volume_ms)?;
        }
        if let Some(f) = &self.formation {
            let p = &limits::FORMATION_PROBABILITY;
            for (field, v) in [
                ("formation.humidity", f.humidity),
                ("formation.activation", f.activation),
                ("formation.extinction", f.extinction),
            ] {
                Limit { field, ..*p }.check(f64::from(v), origin(&Limit { field, ..*p }))?;
            }
            check(&limits::FORMATION_STEP, f.step_seconds)?;
            let cells = &limits::FORMATION_CELLS;
            cells.check(f64::from(f.cells), origin(cells))?;
            if !f.cells.is_multiple_of(8) {
                return Err(DataError::OutOfRange {
                    origin: origin(cells),
                    value: f.cells.to_string(),
                    allowed: "a multiple of 8".into(),
                    hint: cells.hint,
                });
            }
        }
        let mut previous = 0.0f64;
        for state in &self.weather {
            limits::WEATHER_AT.check(state.at, origin(&limits::WEATHER_AT))?;
            if state.at < previous {
                return Err(DataError::OutOfRange {
                    origin: origin(&limits::WEATHER_AT),
                    value: format!("{} s", state.at),
                    allowed: format!("≥ {previous} s, the time of the state before it"),
                    hint: "weather states are listed in time order",
                });
            }
            previous = state.at;
            if let Some(c) = state.coverage {
                check(&limits::COVERAGE, c)?;
            }
            if let Some(over) = state.over {
                limits::WEATHER_OVER.check(over, origin(&limits::WEATHER_OVER))?;
            }
        }
        Ok(())
    }
}
