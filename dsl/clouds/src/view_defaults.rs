//! The one set of defaults for what a view of the clouds leaves out: a scene file's missing
//! fields, a `Frame` made in code (the runtime's `Frame::new`) and the values an engine
//! package's uniform files are written for all come from here.

/// Where the sun stands, where the camera looks from and what the air holds, unless told.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewDefaults {
    /// Sun elevation above the horizon and azimuth clockwise from north (degrees).
    pub sun_elevation_deg: f32,
    pub sun_azimuth_deg: f32,
    /// Camera altitude above the ground (m), pitch above the horizon, heading clockwise from
    /// north and vertical field of view (degrees).
    pub camera_altitude: f32,
    pub camera_pitch_deg: f32,
    pub camera_yaw_deg: f32,
    pub fov_deg: f32,
    /// Haze density at sea level (1/m) and turbulent displacement of cloud bases (m).
    pub haze_density: f32,
    pub turbulence_displacement: f32,
    /// Image size (pixels) where nothing else gives one.
    pub width: u32,
    pub height: u32,
}

/// A fair afternoon from the ground: the sun 35° high in the south-east, the camera 2 m up
/// looking 12° above the horizon with a 60° field of view, 640 × 360.
pub const VIEW_DEFAULTS: ViewDefaults = ViewDefaults {
    sun_elevation_deg: 35.0,
    sun_azimuth_deg: 150.0,
    camera_altitude: 2.0,
    camera_pitch_deg: 12.0,
    camera_yaw_deg: 0.0,
    fov_deg: 60.0,
    haze_density: 3e-5,
    turbulence_displacement: 350.0,
    width: 640,
    height: 360,
};

impl ViewDefaults {
    /// The view in words, for what is written with these values.
    pub fn describe(&self) -> String {
        format!(
            "sun {}° high at azimuth {}°, camera {} m above the ground looking {}° up, {} × {}",
            self.sun_elevation_deg,
            self.sun_azimuth_deg,
            self.camera_altitude,
            self.camera_pitch_deg,
            self.width,
            self.height
        )
    }
}
