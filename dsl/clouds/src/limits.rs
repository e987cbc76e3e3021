//! The accepted range of every scene and frame value, declared once and checked the same way
//! whether the value came from a scene file, a command-line flag or a Rust caller: the error
//! names that origin ([`Origin`]), the value, the range and what to do. `render`, `explain`,
//! `emit`, `export-density`, `tradeoff` and the benches accept and refuse the same scenes
//! because they all check through here.
//!
//! The ranges are what renders correctly, not a guess: `tests/value_edges.rs` renders each
//! edge and checks the image (finite, the sky above the ground, a dark night where the sun is
//! down).

use std::fmt;
use std::path::PathBuf;

use crate::error::DataError;

/// Where a value came from.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// A field of a data file (`scenes/x.toml: fov_deg`).
    File { file: PathBuf, field: String },
    /// A command-line flag (`--fov`).
    Flag(&'static str),
    /// A field of a value a Rust caller built (`Frame::fov_deg`).
    Api(String),
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Origin::File { file, field } => write!(f, "{}: {field}", file.display()),
            Origin::Flag(flag) => f.write_str(flag),
            Origin::Api(field) => f.write_str(field),
        }
    }
}

/// One value's accepted range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limit {
    /// The scene file's field (and the `Frame` member's name).
    pub field: &'static str,
    /// The command-line flag that sets it.
    pub flag: &'static str,
    pub min: f64,
    pub max: f64,
    /// Unit, printed after the numbers ("°", " m").
    pub unit: &'static str,
    /// Why the range ends where it does, or what to do instead.
    pub hint: &'static str,
}

impl Limit {
    /// Checks `value` (any number type) from `origin`.
    pub fn check(&self, value: f64, origin: Origin) -> Result<(), DataError> {
        if value.is_finite() && (self.min..=self.max).contains(&value) {
            return Ok(());
        }
        Err(DataError::OutOfRange {
            origin,
            value: format_value(value),
            allowed: format!(
                "{}{unit} to {}{unit}",
                format_value(self.min),
                format_value(self.max),
                unit = self.unit
            ),
            hint: self.hint,
        })
    }

    /// Checks a value read from field `self.field` of `file`.
    pub fn check_in_file(&self, value: f64, file: &std::path::Path) -> Result<(), DataError> {
        self.check(
            value,
            Origin::File {
                file: file.to_path_buf(),
                field: self.field.to_string(),
            },
        )
    }
}

/// A value as the user wrote it: through f32 when that is what it was (so `1e30` reads
/// `1e30`, not its f64 widening), in exponent form when large.
pub(crate) fn format_value(v: f64) -> String {
    let f = v as f32;
    let large = v.is_finite() && v.abs() >= 1e7;
    match (f64::from(f) == v || !v.is_finite(), large) {
        (true, true) => format!("{f:e}"),
        (true, false) => format!("{f}"),
        (false, true) => format!("{v:e}"),
        (false, false) => format!("{v}"),
    }
}

/// Sun elevation: every sun position, night included (below about −18° the sky is black; a
/// black image is a result, not an error).
pub const SUN_ELEVATION: Limit = Limit {
    field: "sun_elevation_deg",
    flag: "--sun-elevation",
    min: -90.0,
    max: 90.0,
    unit: "°",
    hint: "degrees above the horizon; negative below it",
};

/// Sun azimuth: any direction (it wraps; beyond a million degrees f32 has no fractional
/// degrees left).
pub const SUN_AZIMUTH: Limit = Limit {
    field: "sun_azimuth_deg",
    flag: "--sun-azimuth",
    min: -1e6,
    max: 1e6,
    unit: "°",
    hint: "degrees clockwise from north; any angle, it wraps",
};

/// Camera altitude: from the ground to orbit (the sky is drawn from outside the atmosphere
/// too: `views/limb-from-orbit.toml` is 400 km up).
pub const CAMERA_ALTITUDE: Limit = Limit {
    field: "camera_altitude",
    flag: "--camera-altitude",
    min: 0.0,
    max: 1_000_000.0,
    unit: " m",
    hint: "metres above the ground, up to 1,000 km",
};

/// Camera pitch: straight down to straight up.
pub const CAMERA_PITCH: Limit = Limit {
    field: "camera_pitch_deg",
    flag: "--pitch",
    min: -90.0,
    max: 90.0,
    unit: "°",
    hint: "degrees above the horizon",
};

/// Camera heading: any direction (it wraps, as the sun's azimuth).
pub const CAMERA_YAW: Limit = Limit {
    field: "camera_yaw_deg",
    flag: "--yaw",
    min: -1e6,
    max: 1e6,
    unit: "°",
    hint: "degrees clockwise from north; any angle, it wraps",
};

/// Vertical field of view: a pinhole camera's, up to a degree short of the 180° it cannot
/// reach (`tests/value_edges.rs` checks the edge rows of a 179° view against narrow cameras
/// looking the same way, camera pitched so the top rows look past the zenith).
pub const FOV: Limit = Limit {
    field: "fov_deg",
    flag: "--fov",
    min: 1.0,
    max: 179.0,
    unit: "°",
    hint: "vertical, in degrees; a pinhole camera cannot reach 180° (a fisheye projection \
           would be needed)",
};

/// Coverage of the sky.
pub const COVERAGE: Limit = Limit {
    field: "coverage",
    flag: "--coverage",
    min: 0.0,
    max: 1.0,
    unit: "",
    hint: "the fraction of the sky that is cloudy",
};

/// Haze density at sea level.
pub const HAZE_DENSITY: Limit = Limit {
    field: "haze_density",
    flag: "--haze-density",
    min: 0.0,
    max: 0.01,
    unit: " /m",
    hint: "extinction per metre at sea level; 0 for clear air, 1e-4 for thick haze",
};

/// Turbulent displacement of cloud bases.
pub const TURBULENCE_DISPLACEMENT: Limit = Limit {
    field: "turbulence_displacement",
    flag: "--turbulence-displacement",
    min: 0.0,
    max: 5000.0,
    unit: " m",
    hint: "metres; 0 for none",
};

/// Offset of the weather texture, per component.
pub const WEATHER_OFFSET: Limit = Limit {
    field: "weather_offset",
    flag: "--weather-offset",
    min: -1e6,
    max: 1e6,
    unit: " tiles",
    hint: "tiles of 100 km (the texture repeats, so small offsets suffice)",
};

/// Image width or height.
pub const IMAGE_SIDE: Limit = Limit {
    field: "resolution",
    flag: "--resolution",
    min: 1.0,
    max: 16384.0,
    unit: " px",
    hint: "WIDTHxHEIGHT in pixels, each side at least 1",
};

/// Frames of temporal accumulation.
pub const FRAMES: Limit = Limit {
    field: "frames",
    flag: "--frames",
    min: 1.0,
    max: 4096.0,
    unit: "",
    hint: "at least one frame is rendered",
};

/// Timed repetitions of a measurement (the median is reported).
pub const REPEATS: Limit = Limit {
    field: "repeats",
    flag: "--repeats",
    min: 1.0,
    max: 1000.0,
    unit: "",
    hint: "timed renders per row; the median is reported",
};

/// Exposure of the display transform.
pub const EXPOSURE: Limit = Limit {
    field: "exposure",
    flag: "--exposure",
    min: 1e-3,
    max: 1e4,
    unit: "",
    hint: "a positive multiplier of the radiance before the tone curve (8 is daylight); 0 \
           would write a black image",
};

/// Multiple-scattering octaves.
pub const OCTAVES: Limit = Limit {
    field: "features.octaves",
    flag: "--octaves",
    min: 1.0,
    max: 12.0,
    unit: "",
    hint: "1 is single scattering; 12 is the reference",
};

pub const LATITUDE: Limit = Limit {
    field: "clock.latitude_deg",
    flag: "--latitude",
    min: -90.0,
    max: 90.0,
    unit: "°",
    hint: "degrees north of the equator (south negative)",
};

pub const LONGITUDE: Limit = Limit {
    field: "clock.longitude_deg",
    flag: "--longitude",
    min: -180.0,
    max: 180.0,
    unit: "°",
    hint: "degrees east of Greenwich (west negative)",
};

pub const UTC_OFFSET: Limit = Limit {
    field: "clock.utc_offset_hours",
    flag: "--utc-offset",
    min: -14.0,
    max: 14.0,
    unit: " h",
    hint: "local time minus UTC; time zones span −12 to +14 hours",
};

/// The clouds' share of a frame (`[budget]`).
pub const BUDGET_FRAME_MS: Limit = Limit {
    field: "budget.frame_ms",
    flag: "(scene files only)",
    min: 0.01,
    max: 1e5,
    unit: " ms",
    hint: "milliseconds of a frame the clouds may take on the target device",
};

/// The volume's frame on the target device (`[budget]`).
pub const BUDGET_VOLUME_MS: Limit = Limit {
    field: "budget.volume_ms",
    flag: "(scene files only)",
    ..BUDGET_FRAME_MS
};

pub const WIND_SPEED: Limit = Limit {
    field: "wind.speed",
    flag: "--wind-speed",
    min: 0.0,
    max: 100.0,
    unit: " m/s",
    hint: "jet streams reach about 100 m/s",
};

pub const WIND_TOP_SPEED: Limit = Limit {
    field: "wind.top_speed",
    ..WIND_SPEED
};

pub const WIND_DIRECTION: Limit = Limit {
    field: "wind.direction_deg",
    flag: "--wind-direction",
    min: -1e6,
    max: 1e6,
    unit: "°",
    hint: "where the wind blows from, degrees clockwise from north; any angle, it wraps",
};

pub const WIND_TOP_DIRECTION: Limit = Limit {
    field: "wind.top_direction_deg",
    ..WIND_DIRECTION
};

pub const WEATHER_AT: Limit = Limit {
    field: "weather[].at",
    flag: "--time",
    min: 0.0,
    max: 100_000.0,
    unit: " s",
    hint: "seconds from the start of the timeline, up to about a day: the clouds' drift is an \
           f32 on the GPU, and 100 m/s for longer would step the 5 m detail noise by metres",
};

pub const WEATHER_OVER: Limit = Limit {
    field: "weather[].over",
    flag: "(scene files only)",
    hint: "seconds before the state's time its transition starts; the whole interval from the \
           state before when left out",
    ..WEATHER_AT
};

pub const TIME: Limit = Limit {
    field: "time",
    flag: "--time",
    ..WEATHER_AT
};

pub const FORMATION_PROBABILITY: Limit = Limit {
    field: "formation.humidity, activation, extinction",
    flag: "(scene files only)",
    min: 0.0,
    max: 1.0,
    unit: "",
    hint: "a probability per step of the formation automaton",
};

pub const FORMATION_STEP: Limit = Limit {
    field: "formation.step_seconds",
    flag: "(scene files only)",
    min: 1.0,
    max: 3600.0,
    unit: " s",
    hint: "seconds per step of the formation automaton: with the time limit, at most 100,000 \
           steps to compute",
};

pub const FORMATION_CELLS: Limit = Limit {
    field: "formation.cells",
    flag: "(scene files only)",
    min: 8.0,
    max: 1024.0,
    unit: "",
    hint: "cells per side of the formation grid over one 100 km weather tile, a multiple of 8",
};
