//! Scene presets: a genus seen under a given sky (coverage, sun, camera) at a quality preset.

use serde::{Deserialize, Serialize};

use super::features::Features;
use super::quality::Quality;

/// Per-effect overrides on top of the quality preset's defaults.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeatureOverrides {
    pub shape_detail: Option<bool>,
    pub turbulence: Option<bool>,
    pub light_shafts: Option<bool>,
    pub haze: Option<bool>,
    pub shadows: Option<bool>,
    pub ground_bounce: Option<bool>,
    pub powder: Option<bool>,
    pub accurate_sun_sky_light: Option<bool>,
    pub accurate_phase_function: Option<bool>,
    pub octaves: Option<u32>,
}

impl FeatureOverrides {
    pub fn apply(&self, mut f: Features) -> Features {
        let pairs = [
            (self.shape_detail, &mut f.shape_detail),
            (self.turbulence, &mut f.turbulence),
            (self.light_shafts, &mut f.light_shafts),
            (self.haze, &mut f.haze),
            (self.shadows, &mut f.shadows),
            (self.ground_bounce, &mut f.ground_bounce),
            (self.powder, &mut f.powder),
            (self.accurate_sun_sky_light, &mut f.accurate_sun_sky_light),
            (self.accurate_phase_function, &mut f.accurate_phase_function),
        ];
        for (o, slot) in pairs {
            if let Some(v) = o {
                *slot = v;
            }
        }
        if let Some(o) = self.octaves {
            f.octaves = o;
        }
        f
    }
}

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
