//! Feature toggles. Each is a generation-time choice: a toggle that is off leaves no code,
//! binding or texture in the variant.

use serde::{Deserialize, Serialize};

/// Which effects a variant simulates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Features {
    /// Detail erosion by the 32³ Worley texture.
    pub shape_detail: bool,
    /// Domain distortion of the shape by the curl-noise texture near cloud bases.
    pub turbulence: bool,
    /// Crepuscular rays: the shadow-length march through the beer shadow map.
    pub light_shafts: bool,
    /// Analytic exponential haze.
    pub haze: bool,
    /// Beer shadow map: optical depth towards the sun beyond the secondary march.
    pub shadows: bool,
    /// Light bounced from the ground below the clouds.
    pub ground_bounce: bool,
    /// The "powder" darkening of thin cloud edges facing the sun.
    pub powder: bool,
    /// Sun and sky irradiance evaluated per sample rather than interpolated between the shells.
    pub accurate_sun_sky_light: bool,
    /// Approximate Mie (Jendersie & d'Eon 2023) instead of the dual-lobe Henyey–Greenstein.
    pub accurate_phase_function: bool,
    /// Multiple-scattering octaves (1..=12).
    pub octaves: u32,
}

impl Default for Features {
    fn default() -> Self {
        Self {
            shape_detail: true,
            turbulence: true,
            light_shafts: true,
            haze: true,
            shadows: true,
            ground_bounce: true,
            powder: true,
            accurate_sun_sky_light: true,
            accurate_phase_function: false,
            octaves: 8,
        }
    }
}

/// A named on/off toggle, as spelled on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Toggle {
    ShapeDetail,
    Turbulence,
    LightShafts,
    Haze,
    Shadows,
    GroundBounce,
    Powder,
    AccurateSunSkyLight,
    AccuratePhaseFunction,
}

impl Toggle {
    pub const ALL: [Toggle; 9] = [
        Toggle::ShapeDetail,
        Toggle::Turbulence,
        Toggle::LightShafts,
        Toggle::Haze,
        Toggle::Shadows,
        Toggle::GroundBounce,
        Toggle::Powder,
        Toggle::AccurateSunSkyLight,
        Toggle::AccuratePhaseFunction,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Toggle::ShapeDetail => "shape-detail",
            Toggle::Turbulence => "turbulence",
            Toggle::LightShafts => "light-shafts",
            Toggle::Haze => "haze",
            Toggle::Shadows => "shadows",
            Toggle::GroundBounce => "ground-bounce",
            Toggle::Powder => "powder",
            Toggle::AccurateSunSkyLight => "accurate-sun-sky-light",
            Toggle::AccuratePhaseFunction => "accurate-phase-function",
        }
    }

    pub fn parse(s: &str) -> Option<Toggle> {
        let s = s.trim().to_ascii_lowercase().replace('_', "-");
        Toggle::ALL.into_iter().find(|t| t.name() == s)
    }

    pub fn get(self, f: &Features) -> bool {
        match self {
            Toggle::ShapeDetail => f.shape_detail,
            Toggle::Turbulence => f.turbulence,
            Toggle::LightShafts => f.light_shafts,
            Toggle::Haze => f.haze,
            Toggle::Shadows => f.shadows,
            Toggle::GroundBounce => f.ground_bounce,
            Toggle::Powder => f.powder,
            Toggle::AccurateSunSkyLight => f.accurate_sun_sky_light,
            Toggle::AccuratePhaseFunction => f.accurate_phase_function,
        }
    }

    pub fn set(self, f: &mut Features, on: bool) {
        match self {
            Toggle::ShapeDetail => f.shape_detail = on,
            Toggle::Turbulence => f.turbulence = on,
            Toggle::LightShafts => f.light_shafts = on,
            Toggle::Haze => f.haze = on,
            Toggle::Shadows => f.shadows = on,
            Toggle::GroundBounce => f.ground_bounce = on,
            Toggle::Powder => f.powder = on,
            Toggle::AccurateSunSkyLight => f.accurate_sun_sky_light = on,
            Toggle::AccuratePhaseFunction => f.accurate_phase_function = on,
        }
    }
}

impl Features {
    /// A short stable name for file names and manifests: `octaves8` plus the toggles that are on.
    pub fn key(&self) -> String {
        let mut s = format!("o{}", self.octaves);
        for t in Toggle::ALL {
            if t.get(self) {
                let abbrev: String = t
                    .name()
                    .split('-')
                    .filter_map(|w| w.chars().next())
                    .collect();
                s.push('-');
                s.push_str(&abbrev);
            }
        }
        s
    }
}
