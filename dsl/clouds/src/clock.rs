//! Time of day: where the sun stands at a scene's place and time, so that it moves as the
//! timeline runs.
//!
//! The solar position is NOAA's (the General Solar Position equations of its solar calculator,
//! after Meeus, "Astronomical Algorithms"): geometric, without refraction, good to about 0.01°
//! between 1800 and 2100, far finer than a sun disc (0.53°).

use chrono::{Datelike, NaiveDateTime, Timelike};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A scene's place and the local time at the start of its timeline.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Clock {
    /// Local date and time at timeline second 0: `"2026-06-21T17:30"` (seconds optional).
    #[serde(serialize_with = "write_time", deserialize_with = "read_time")]
    pub start: NaiveDateTime,
    /// Local time minus UTC, hours (`2` for central European summer time).
    #[serde(default)]
    pub utc_offset_hours: f64,
    /// Degrees north.
    pub latitude_deg: f64,
    /// Degrees east.
    pub longitude_deg: f64,
}

const TIME_FORMATS: [&str; 2] = ["%Y-%m-%dT%H:%M:%S", "%Y-%m-%dT%H:%M"];

fn read_time<'de, D: Deserializer<'de>>(d: D) -> Result<NaiveDateTime, D::Error> {
    let text = String::deserialize(d)?;
    TIME_FORMATS
        .iter()
        .find_map(|f| NaiveDateTime::parse_from_str(&text, f).ok())
        .ok_or_else(|| {
            serde::de::Error::custom(format!(
                "`{text}` is not a local date and time like \"2026-06-21T17:30\" \
                 (YYYY-MM-DDTHH:MM, seconds optional)"
            ))
        })
}

fn write_time<S: Serializer>(t: &NaiveDateTime, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&t.format(TIME_FORMATS[0]).to_string())
}

/// Where the sun stands: degrees above the horizon (negative below it) and clockwise from north.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunPosition {
    pub elevation_deg: f64,
    pub azimuth_deg: f64,
}

impl Clock {
    /// The sun `seconds` after the start.
    pub fn sun_at(&self, seconds: f64) -> SunPosition {
        let local = self.start.and_utc().timestamp() as f64 + seconds;
        let utc = local - self.utc_offset_hours * 3600.0;
        solar_position(utc, self.latitude_deg, self.longitude_deg)
    }

    /// Day of the year of the start (1 = 1 January), for reports.
    pub fn start_day(&self) -> u32 {
        self.start.ordinal()
    }

    /// Local hour of the start, for reports.
    pub fn start_hour(&self) -> f64 {
        f64::from(self.start.hour()) + f64::from(self.start.minute()) / 60.0
    }
}

/// The sun at `utc_seconds` (seconds since 1970-01-01T00:00 UTC) seen from `latitude_deg` north,
/// `longitude_deg` east.
pub fn solar_position(utc_seconds: f64, latitude_deg: f64, longitude_deg: f64) -> SunPosition {
    let julian_day = utc_seconds / 86_400.0 + 2_440_587.5;
    let t = (julian_day - 2_451_545.0) / 36_525.0;
    let mean_longitude = (280.466_46 + t * (36_000.769_83 + t * 0.000_303_2)).rem_euclid(360.0);
    let mean_anomaly = 357.529_11 + t * (35_999.050_29 - 0.000_153_7 * t);
    let eccentricity = 0.016_708_634 - t * (0.000_042_037 + 0.000_000_126_7 * t);
    let m = mean_anomaly.to_radians();
    let centre = m.sin() * (1.914_602 - t * (0.004_817 + 0.000_014 * t))
        + (2.0 * m).sin() * (0.019_993 - 0.000_101 * t)
        + (3.0 * m).sin() * 0.000_289;
    let omega = (125.04 - 1934.136 * t).to_radians();
    let apparent_longitude =
        (mean_longitude + centre - 0.005_69 - 0.004_78 * omega.sin()).to_radians();
    let mean_obliquity =
        23.0 + (26.0 + (21.448 - t * (46.815 + t * (0.000_59 - t * 0.001_813))) / 60.0) / 60.0;
    let obliquity = (mean_obliquity + 0.002_56 * omega.cos()).to_radians();
    let declination = (obliquity.sin() * apparent_longitude.sin()).asin();
    let y = (obliquity / 2.0).tan().powi(2);
    let l0 = mean_longitude.to_radians();
    let e = eccentricity;
    // Equation of time, minutes.
    let equation_of_time = 4.0
        * (y * (2.0 * l0).sin() - 2.0 * e * m.sin() + 4.0 * e * y * m.sin() * (2.0 * l0).cos()
            - 0.5 * y * y * (4.0 * l0).sin()
            - 1.25 * e * e * (2.0 * m).sin())
        .to_degrees();
    let utc_minutes = (utc_seconds / 60.0).rem_euclid(1440.0);
    let true_solar_minutes =
        (utc_minutes + equation_of_time + 4.0 * longitude_deg).rem_euclid(1440.0);
    let hour_angle = (true_solar_minutes / 4.0 - 180.0).to_radians();
    let phi = latitude_deg.to_radians();
    let cos_zenith = (phi.sin() * declination.sin()
        + phi.cos() * declination.cos() * hour_angle.cos())
    .clamp(-1.0, 1.0);
    let zenith = cos_zenith.acos();
    let elevation_deg = 90.0 - zenith.to_degrees();
    // Azimuth from the zenith angle; at a pole or with the sun overhead it is undefined: south.
    let denominator = phi.cos() * zenith.sin();
    let azimuth_deg = if denominator.abs() < 1e-12 {
        180.0
    } else {
        let a = ((phi.sin() * cos_zenith - declination.sin()) / denominator)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        if hour_angle > 0.0 {
            (a + 180.0).rem_euclid(360.0)
        } else {
            (540.0 - a).rem_euclid(360.0)
        }
    };
    SunPosition {
        elevation_deg,
        azimuth_deg,
    }
}
