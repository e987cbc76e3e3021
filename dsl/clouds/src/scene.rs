//! Scene presets: a genus seen under a given sky (coverage, sun, camera) at a quality preset.

use serde::{Deserialize, Serialize};

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
    #[serde(default)]
    pub weather_offset: [f32; 2],
    #[serde(default)]
    pub quality: Quality,
    #[serde(default)]
    pub features: FeatureOverrides,
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
    pub fn validate(&self) -> Result<(), (String, String)> {
        if let Some(c) = self.coverage
            && !(c.is_finite() && (0.0..=1.0).contains(&c))
        {
            return Err(("coverage".into(), format!("must be in [0, 1], got {c}")));
        }
        if !(self.sun_elevation_deg.is_finite() && (-90.0..=90.0).contains(&self.sun_elevation_deg))
        {
            return Err((
                "sun_elevation_deg".into(),
                format!("must be in [-90, 90], got {}", self.sun_elevation_deg),
            ));
        }
        if !self.sun_azimuth_deg.is_finite() {
            return Err((
                "sun_azimuth_deg".into(),
                format!("must be finite, got {}", self.sun_azimuth_deg),
            ));
        }
        if !(self.camera_altitude.is_finite() && self.camera_altitude >= 0.0) {
            return Err((
                "camera_altitude".into(),
                format!("must be ≥ 0 m, got {}", self.camera_altitude),
            ));
        }
        if !(self.camera_pitch_deg.is_finite() && (-90.0..=90.0).contains(&self.camera_pitch_deg)) {
            return Err((
                "camera_pitch_deg".into(),
                format!("must be in [-90, 90], got {}", self.camera_pitch_deg),
            ));
        }
        if !(self.haze_density.is_finite() && (0.0..=1e-2).contains(&self.haze_density)) {
            return Err((
                "haze_density".into(),
                format!("must be in [0, 0.01] per metre, got {}", self.haze_density),
            ));
        }
        if !(self.turbulence_displacement.is_finite()
            && (0.0..=5000.0).contains(&self.turbulence_displacement))
        {
            return Err((
                "turbulence_displacement".into(),
                format!(
                    "must be in [0, 5000] m, got {}",
                    self.turbulence_displacement
                ),
            ));
        }
        if !self.weather_offset.iter().all(|v| v.is_finite()) {
            return Err((
                "weather_offset".into(),
                format!("must be finite, got {:?}", self.weather_offset),
            ));
        }
        if !self.camera_yaw_deg.is_finite() {
            return Err((
                "camera_yaw_deg".into(),
                format!("must be finite, got {}", self.camera_yaw_deg),
            ));
        }
        if !(self.fov_deg.is_finite() && self.fov_deg > 0.0 && self.fov_deg < 180.0) {
            return Err((
                "fov_deg".into(),
                format!("must be in (0, 180), got {}", self.fov_deg),
            ));
        }
        if let Some(o) = self.features.octaves
            && !(1..=12).contains(&o)
        {
            return Err((
                "features.octaves".into(),
                format!("must be in 1..=12, got {o}"),
            ));
        }
        Ok(())
    }
}
