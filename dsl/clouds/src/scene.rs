//! Scene presets: a genus seen under a given sky (coverage, sun, camera) at a quality preset.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::DataError;
use crate::limits::{self, Limit, Origin};

use super::features::FeatureOverrides;
use super::quality::Quality;

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
    #[serde(default)]
    pub sun_azimuth_deg: f32,
    /// Camera altitude above the ground, metres.
    #[serde(default = "default_camera_altitude")]
    pub camera_altitude: f32,
    /// Camera pitch above the horizon, degrees.
    #[serde(default = "default_camera_pitch")]
    pub camera_pitch_deg: f32,
    /// Camera heading, degrees clockwise from north.
    #[serde(default)]
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

fn default_sun_elevation() -> f32 {
    45.0
}

fn default_camera_altitude() -> f32 {
    2.0
}

fn default_haze_density() -> f32 {
    3e-5
}

fn default_turbulence_displacement() -> f32 {
    350.0
}

fn default_camera_pitch() -> f32 {
    10.0
}

fn default_fov() -> f32 {
    60.0
}

impl ScenePreset {
    /// Checks every value against its [`crate::limits`], naming `file` and the field in an
    /// error.
    pub fn validate(&self, file: &Path) -> Result<(), DataError> {
        self.validate_from(&|limit: &Limit| Origin::File {
            file: file.to_path_buf(),
            field: limit.field.to_string(),
        })
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
        Ok(())
    }
}
